"""`mechgen solve` and `mechgen sweep`: readable tables, CSV files, one clear message on
bad input. Every command builds into a tmp dir (--outdir), never into generated/."""
from __future__ import annotations

import csv
import glob
import os
import re
import shutil
import subprocess
import sys

import pytest

from conftest import EXAMPLES, GENERATED

QR = os.path.join(EXAMPLES, "quick_return.py")
SLIDER = os.path.join(EXAMPLES, "quick_return_slider.py")


@pytest.fixture(scope="module")
def outdir(tmp_path_factory):
    """A tmp module folder seeded with copies of generated/ and numba's cache of them: the
    CLI renders each model, finds the same text and keeps the file, so numba's cache holds
    (were generated/ stale, the CLI would rewrite the module and numba recompile it)."""
    path = tmp_path_factory.mktemp("cli_generated")
    for f in glob.glob(os.path.join(GENERATED, "*.py")):
        shutil.copy2(f, path / os.path.basename(f))
    cache = glob.glob(os.path.join(GENERATED, "__pycache__", "*.nb[ic]"))
    if cache:
        (path / "__pycache__").mkdir()
        for f in cache:
            shutil.copy2(f, path / "__pycache__" / os.path.basename(f))
    return str(path)


@pytest.fixture(autouse=True)
def _plain_python_tier(monkeypatch):
    """The commands' output and messages are the point here, not numba: they run the
    modules on the plain-Python tier (the same numbers; with numba's cache cold, the
    seeded copies were compiled again, ~60 s of CPU for this file and test_cli_options.py)."""
    monkeypatch.setenv("MECHGEN_TIER", "python")


@pytest.fixture
def run(outdir, capsys):
    """mechgen's main() in this process: (exit code, stdout, stderr)."""
    from mechgen.cli import main

    def call(*argv, out=True):
        argv = list(argv)
        if out:
            argv += ["--outdir", outdir]
        try:
            code = main(argv)
        except SystemExit as exc:       # argparse's own errors
            code = exc.code
        captured = capsys.readouterr()
        return code, captured.out, captured.err
    return call


def table(text):
    """{name: value} from `mechgen solve`'s "  name -> value" lines."""
    return {m.group(1): float(m.group(2))
            for m in re.finditer(r"^\s+(\w+)\s+->\s+(\S+)$", text, re.M)}


def close(a, b, digits=6):
    import math
    return abs(a - b) <= 0.6 * 10 ** (math.floor(math.log10(abs(b))) - digits + 1)


def one_message(err):
    """A failure prints one message, no traceback, naming itself as mechgen's: a headline
    line, and under it, indented, the details where it has some (a lock's)."""
    lines = [ln for ln in err.splitlines() if ln.strip()]
    assert len(lines) >= 1 and all(ln.startswith("  ") for ln in lines[1:]), err
    assert "Traceback" not in err
    return lines[0]


# -- solve -----------------------------------------------------------------------------------
def test_solve_acceleration_table(run, outdir):
    code, out, err = run("solve", QR, "-t", "0.15", "--level", "acceleration")
    assert code == 0, err
    first = out.splitlines()[0]
    assert first.startswith("quick_return at T = 0.15") and "acceleration" in first
    values = table(out)
    assert values["T"] == 0.15
    for name, seed in dict(Th2=0.942478, Th3=-0.233107, X4=6.92194, Th2d=6.28319,
                           Th3d=2.27897, X4d=-18.7395, Th3dd=1.64018, X4dd=-40.9024).items():
        assert close(values[name], seed), (name, values[name])
    assert close(values["stroke_x"], 6.92194) and close(values["stroke_xdd"], -40.9024)
    # one row per coordinate and level: 1 + 27 + 3 outputs
    assert len(values) == 31
    # aligned: every "->" in the same column
    arrows = {line.index("->") for line in out.splitlines()[1:]}
    assert len(arrows) == 1


def test_solve_position_default_level_and_guess(run):
    code, out, err = run("solve", QR, "-t", "0.85", "--guess", "X4=1.0")
    assert code == 0, err
    values = table(out)
    assert close(values["X4"], 0.802632)
    assert "X4d" not in values and "position" in out.splitlines()[0]


def test_solve_builds_into_an_empty_folder(run, tmp_path):
    """--outdir names where the module goes; it is built there when missing."""
    target = tmp_path / "fresh"
    code, out, err = run("solve", os.path.join(EXAMPLES, "fourbar_loop.py"), "-t", "0",
                         "--guess", "theta3=-0.9", "--guess", "theta4=-2.4", "--outdir", str(target),
                         out=False)
    assert code == 0, err
    assert os.path.isfile(target / "fourbar_loop.py")
    values = table(out)
    assert abs(values["theta3"] - -1.048246730) < 1e-9
    assert abs(values["theta4"] - -2.313301945) < 1e-9


# -- sweep -----------------------------------------------------------------------------------
def test_sweep_prints_a_table(run):
    code, out, err = run("sweep", QR, "--t0", "0", "--t1", "1", "-n", "21")
    assert code == 0, err
    lines = out.rstrip("\n").splitlines()
    header = lines[0].split()
    assert header[:4] == ["T", "X2", "Y2", "Th2"] and "X4" in header and "stroke_x" in header
    assert len(lines) == 22                       # header and 21 rows, both ends included
    rows = [ln.split() for ln in lines[1:]]
    assert all(len(r) == len(header) for r in rows)
    # right-aligned columns: every line has the same length
    assert len({len(ln) for ln in lines}) == 1
    col = header.index("X4")
    assert float(rows[0][0]) == 0.0 and float(rows[-1][0]) == 1.0
    assert close(float(rows[0][col]), 9.07905) and close(float(rows[10][col]), -0.181877)


def test_sweep_to_csv(run, tmp_path):
    target = tmp_path / "sweep.csv"
    code, out, err = run("sweep", QR, "--t0", "0", "--t1", "1", "-n", "11",
                         "--level", "velocity", "--csv", str(target))
    assert code == 0, err
    assert "wrote 11 rows" in out and str(target) in out
    with open(target, newline="") as fh:
        rows = list(csv.reader(fh))
    assert rows[0][0] == "T" and "X4d" in rows[0] and "X4dd" not in rows[0]
    assert len(rows) == 12
    x4 = [float(r[rows[0].index("X4")]) for r in rows[1:]]
    assert close(x4[0], 9.07905) and close(x4[5], -0.181877)


# -- failures: one clear message, non-zero exit ----------------------------------------------------
@pytest.mark.parametrize("argv,pattern", [
    (("solve", QR, "-t", "nan"), r"t must be finite"),
    (("solve", QR, "-t", "0.1", "--guess", "X9=1"), r"'X9' is not a coordinate"),
    (("solve", QR, "-t", "0.1", "--guess", "X4"), r"--guess takes NAME=VALUE"),
    (("solve", QR, "-t", "0.1", "--guess", "X4=far"), r"'far' is not a number"),
    (("sweep", QR, "-n", "0"), r"n must be a positive integer"),
    (("solve", os.path.join(EXAMPLES, "no_such_model.py"), "-t", "0"), r"does not exist"),
    (("solve", SLIDER, "-t", "0.25"), r"ConvergenceError|SingularError"),
])
def test_bad_input_exits_with_one_message(run, argv, pattern):
    code, out, err = run(*argv)
    assert code not in (0, None)
    line = one_message(err)
    assert line.startswith("mechgen: ") and re.search(pattern, line), line
    assert "->" not in out          # no numbers printed as if it had worked


def test_failed_solve_says_when(run):
    code, out, err = run("solve", SLIDER, "-t", "0.25")
    assert code == 1
    assert "t=0.25" in err and ("ConvergenceError" in err or "SingularError" in err)


@pytest.mark.parametrize("argv", [
    ("solve", QR),                                          # -t is required
    ("solve", QR, "-t", "0.1", "--level", "jerk"),
    ("sweep", QR, "-n", "many"),
])
def test_usage_errors(run, argv):
    code, out, err = run(*argv)
    assert code == 2
    assert err.strip().splitlines()[-1].startswith("mechgen ") and "error:" in err


def test_nothing_written_to_generated(run, outdir):
    before = {f: os.stat(os.path.join(GENERATED, f)).st_mtime_ns
              for f in os.listdir(GENERATED) if f.endswith(".py")}
    code, _, err = run("solve", QR, "-t", "0.3")
    assert code == 0, err
    after = {f: os.stat(os.path.join(GENERATED, f)).st_mtime_ns
             for f in os.listdir(GENERATED) if f.endswith(".py")}
    assert before == after


# -- the installed entry point ------------------------------------------------------------------
def _entry():
    exe = shutil.which("mechgen")
    return [exe] if exe else [sys.executable, "-m", "mechgen.cli"]


def test_console_script(outdir, tmp_path):
    proc = subprocess.run(_entry() + ["solve", QR, "-t", "0.5", "--outdir", outdir],
                          capture_output=True, text=True, cwd=str(tmp_path), timeout=600)
    assert proc.returncode == 0, proc.stderr
    assert close(table(proc.stdout)["X4"], -0.181877)
    proc = subprocess.run(_entry() + ["solve", SLIDER, "-t", "0.25", "--outdir", outdir],
                          capture_output=True, text=True, cwd=str(tmp_path), timeout=600)
    assert proc.returncode == 1
    assert one_message(proc.stderr).startswith("mechgen: ")
    assert proc.stdout == ""
    assert not os.path.exists(tmp_path / "generated")
