"""Issue 14, the command line a new user meets: honest verdicts from `check`, one meaning per
option (-o the file written, --outdir the generated modules), chosen columns, times as
expressions and as asked for, no -0, quiet broken pipes, `singularities`, and the points a
failed sweep reached."""
from __future__ import annotations

import argparse
import csv
import glob
import math
import os
import re
import shutil
import subprocess
import sys
import textwrap
from cli_runs import run

import numpy as np
import pytest

from conftest import EXAMPLES, GENERATED
from mechgen.cli import parser
from mechgen.cli.options import number
from mechgen.cli.tables import cell, format_table, times, write_csv

QR = os.path.join(EXAMPLES, "quick_return.py")
SLIDER = os.path.join(EXAMPLES, "quick_return_slider.py")
FOURBAR = os.path.join(EXAMPLES, "fourbar.py")
LOCKS = ["0.2464863829", "0.2535136171", "0.7415457788", "0.7584542212"]   # seed 001, 3B


@pytest.fixture(scope="module")
def outdir(build_dir):
    """The session's build folder, seeded with generated/ and numba's cache of it (the CLI
    renders each model, finds the same text and keeps the file: no recompilation)."""
    for f in glob.glob(os.path.join(GENERATED, "*.py")):
        target = os.path.join(build_dir, os.path.basename(f))
        if not os.path.exists(target):
            shutil.copy2(f, target)
    cache = os.path.join(build_dir, "__pycache__")
    os.makedirs(cache, exist_ok=True)
    for f in glob.glob(os.path.join(GENERATED, "__pycache__", "*.nb[ic]")):
        if not os.path.exists(os.path.join(cache, os.path.basename(f))):
            shutil.copy2(f, cache)
    return build_dir


@pytest.fixture(autouse=True)
def _plain_python_tier(monkeypatch):
    """The commands' output and messages are the point here, not numba: they run the
    modules on the plain-Python tier (the same numbers; with numba's cache cold, the
    seeded copies were compiled again, ~60 s of CPU for this file and test_cli_solve.py)."""
    monkeypatch.setenv("MECHGEN_TIER", "python")


def model_file(tmp_path, source, extra="", name="model.py", replace=()):
    text = open(source).read()
    for old, new in replace:
        assert old in text
        text = text.replace(old, new)
    path = tmp_path / name
    path.write_text(text + textwrap.dedent(extra))
    return str(path)


def culprits(out):
    """The constraint lines listed after "contradict each other" (numbered; not the line
    that names a loop's lengths)."""
    part = out.split("contradict each other")[1].split("  structure")[0]
    return [ln.strip() for ln in part.splitlines()[1:] if ln.strip()[:1].isdigit()]


# -- check: wrong or misleading verdicts -----------------------------------------------------
def test_check_fails_a_contradictory_extra_distance(capsys, tmp_path):
    """|B - D| >= d - a = 2.2 for any crank angle: a distance of 1 contradicts the crank's
    pivot, whatever the coupler and rocker do."""
    path = model_file(tmp_path, FOURBAR,
                      'm.relative_distance(crank[2], ground[2], 1.0, name="extra")\n')
    code, out, _ = run(capsys, "check", path)
    assert code == 1 and out.rstrip().endswith("check: False")
    assert "CANNOT ASSEMBLE at t = 0" in out
    assert culprits(out) == ["1 revolute(ground[1], crank[1])",
                             "6 extra: relative_distance(crank[2], ground[2], 1.00000000000000)"]
    assert "redundant:" not in out                  # not all ten equations as "redundant"


def test_check_fails_two_conflicting_rotation_locks(capsys, tmp_path):
    path = model_file(tmp_path, FOURBAR, 'm.rotation_lock(crank, 0.3, name="second lock")\n')
    code, out, _ = run(capsys, "check", path)
    assert code == 1 and out.rstrip().endswith("check: False")
    assert culprits(out) == ["5 crank angle: rotation_lock(crank, T*omega + theta2)",
                             "6 second lock: rotation_lock(crank, 0.300000000000000)"]


def test_check_fails_a_loop_that_cannot_close(capsys, tmp_path):
    """Coupler 0.5: a + b + c = 3.3 > d, but |B - D| - b = 2.6 - 0.5 > c: no assembly."""
    path = model_file(tmp_path, FOURBAR, replace=[('m.param("b", 2.5)', 'm.param("b", 0.5)')])
    code, out, _ = run(capsys, "check", path)
    assert code == 1
    assert [c.split()[0] for c in culprits(out)] == ["1", "2", "3", "4", "5"]
    assert "the loop cannot close: crank[2]–ground[2] = 2.69072 > c (rocker) + b (coupler)" \
        in out


def test_check_says_a_joint_is_missing_not_a_driver(capsys, tmp_path):
    path = model_file(tmp_path, FOURBAR, replace=[("m.revolute(coupler[2], rocker[2])\n", "")])
    code, out, _ = run(capsys, "check", path)
    assert code == 1 and out.rstrip().endswith("check: False")
    missing = next(ln for ln in out.splitlines() if "MISSING" in ln)
    assert "MISSING: 2 equation(s) fewer than coordinates" in missing
    assert "add a driver" not in missing and "a constraint is missing" in missing
    assert "left free: Th3 (coupler), Th4 (rocker)" in missing
    assert "coordinates left free: Th3, Th4" in out


def test_check_counts_the_assembly_modes_and_says_which_the_guess_reaches(capsys):
    from test_robustness import fourbar_closed
    code, out, _ = run(capsys, "check", FOURBAR)
    assert code == 0 and out.rstrip().endswith("check: True")
    assert re.search(r"assembly modes at t = 0: 2 found .*; the guess reaches mode 1", out)
    rows = {int(m.group(1)): (float(m.group(2)), float(m.group(3)))
            for m in re.finditer(r"^\s+(\d)\s+(\S+)\s+(\S+)", out.split("mode       Th3")[1], re.M)}
    for mode, sigma in ((1, 1), (2, -1)):
        th3, th4 = fourbar_closed(0.8, 2.5, 2.0, 3.0, np.array([math.pi / 3]), sigma)
        assert rows[mode] == pytest.approx((th3[0], th4[0]), abs=1e-5)
    assert "<- the guess reaches this one" in out.split("\n       2")[0]


def test_check_shows_angles_wrapped(capsys, tmp_path):
    """A guess four turns away assembles there; check prints the angle in (-pi, pi]."""
    path = model_file(tmp_path, FOURBAR,
                      replace=[("guess=(3, 0, 1.8)", "guess=(3, 0, 1.8 + 4 * pi)")])
    code, out, _ = run(capsys, "check", path)
    assert code == 0
    reached = next(ln for ln in out.splitlines() if "configuration reached" in ln)
    assert "Th4 = 1.79247" in reached and "Th2 = 1.0472" in reached
    values = [float(v) for v in re.findall(r"Th\d = (\S+?)(?:,|$)", reached)]
    assert all(-math.pi < v <= math.pi for v in values)


def test_check_notes_a_guess_that_reaches_the_farther_mode(capsys, tmp_path):
    path = model_file(tmp_path, FOURBAR, replace=[("guess=(0.4, 0.7, 0.5)", "guess=(0.4, 0.7, -1.0)"),
                                                  ("guess=(3, 0, 1.8)", "guess=(3, 0, 0.0)")])
    code, out, _ = run(capsys, "check", path)
    assert code == 0
    assert "note: mode 2 lies nearer the guess than mode 1" in out
    assert re.search(r"1\s+-1.04825\s+-2.3133\s+<- the guess reaches this one", out)
    assert re.search(r"2\s+0.52741\s+1.79247\s+<- nearest the guess", out)


def test_check_fails_a_guess_from_which_no_mode_is_reached(capsys, tmp_path):
    path = tmp_path / "square.py"
    path.write_text("from mechgen import Model\nm = Model('square')\n"
                    "x = m.coordinate('x', guess=0.0)\nm.constraint(x**2 - 2, name='x squared')\n")
    code, out, _ = run(capsys, "check", path)
    assert code == 1
    assert "assembly modes at t = 0: 2 found" in out
    assert "CANNOT ASSEMBLE from the guess at t = 0" in out
    assert re.search(r"1\s+1.41421", out) and re.search(r"2\s+-1.41421", out)


def test_check_time_takes_an_expression(capsys):
    code, out, _ = run(capsys, "check", QR, "-t", "1/4")
    assert code == 0 and "Jacobian rank at the guess (t = 0.25)" in out
    assert "Th2 = 1.5708" in out
    code, out, _ = run(capsys, "check", FOURBAR, "--starts", "0")
    assert code == 0 and "assembly modes at t = 0: 1 found (from the guess and 0 other" in out


# -- one meaning per option ------------------------------------------------------------------
def test_sweep_dash_o_writes_the_csv_file(capsys, tmp_path, outdir):
    target = tmp_path / "table.csv"
    code, out, err = run(capsys, "sweep", QR, "--outdir", outdir, "-o", target, "-n", 21)
    assert code == 0, err
    assert os.path.isfile(target) and "wrote 21 rows" in out
    rows = list(csv.reader(open(target, newline="")))
    # the times asked for: 0.15, not 0.15000000000000002
    assert [r[0] for r in rows[1:]] == [repr(k / 20) for k in range(21)]
    assert rows[4][0] == "0.15"
    assert float(rows[1][rows[0].index("X4")]) == pytest.approx(9.07905, abs=1e-5)


def test_solve_dash_o_writes_a_one_row_table(capsys, tmp_path, outdir):
    target = tmp_path / "one.csv"
    code, out, err = run(capsys, "solve", QR, "--outdir", outdir, "-t", "0.15", "-o", target,
                         "--columns", "Th3,X4")
    assert code == 0, err
    rows = list(csv.reader(open(target, newline="")))
    assert rows[0] == ["T", "Th3", "X4"] and rows[1][0] == "0.15"
    assert float(rows[1][1]) == pytest.approx(-0.233107, abs=1e-6)
    assert float(rows[1][2]) == pytest.approx(6.92194, abs=1e-5)


@pytest.mark.parametrize("name", ["table.csv", "picture.png", "movie.gif"])
def test_outdir_never_makes_a_folder_named_like_a_file(capsys, tmp_path, name):
    for command in (["build", QR, "-o"], ["build", QR, "--outdir"],
                    ["sweep", QR, "--outdir"], ["solve", QR, "-t", "0", "--outdir"]):
        code, _, err = run(capsys, *command, tmp_path / name)
        assert code == 1 and "names a file, not a folder" in err, (command, err)
        assert not os.path.exists(tmp_path / name)


def test_dash_o_refuses_a_folder(capsys, tmp_path, outdir):
    code, _, err = run(capsys, "sweep", QR, "--outdir", outdir, "-o", tmp_path)
    assert code == 1 and "that is a folder" in err and "--outdir" in err


def test_build_keeps_dash_o_dir_and_outdir_is_the_same_option():
    for flag in ("-o", "--outdir"):
        assert parser().parse_args(["build", "m.py", flag, "here"]).outdir == "here"
    args = parser().parse_args(["sweep", "m.py", "-o", "t.csv", "--outdir", "gen"])
    assert args.csv == "t.csv" and args.outdir == "gen"
    assert parser().parse_args(["sweep", "m.py", "--csv", "t.csv"]).csv == "t.csv"
    args = parser().parse_args(["draw", "m.py", "-o", "d.png", "--outdir", "gen"])
    assert args.output == "d.png" and args.outdir == "gen"


def test_build_keeps_an_unchanged_models_module(capsys, tmp_path):
    """A second `mechgen build` of an unchanged model leaves the module file as it is (its
    time stamp keys numba's compiled cache); --force writes it again; an edit rebuilds."""
    src = model_file(tmp_path, os.path.join(EXAMPLES, "fourbar.py"))
    out_dir = tmp_path / "gen"
    code, out, err = run(capsys, "build", src, "-o", out_dir)
    target = out_dir / "fourbar.py"
    assert code == 0 and out.strip() == f"wrote {target}", err
    before = os.stat(target).st_mtime_ns
    code, out, _ = run(capsys, "build", src, "-o", out_dir)
    assert code == 0 and "is up to date" in out and str(target) in out
    assert os.stat(target).st_mtime_ns == before
    code, out, _ = run(capsys, "build", src, "-o", out_dir, "--force")
    assert code == 0 and out.strip() == f"wrote {target}"
    with open(src, "a") as fh:
        fh.write("\nm.param('extra', 1.5)\n")
    text = open(target).read()
    code, out, _ = run(capsys, "build", src, "-o", out_dir)
    assert code == 0 and out.strip() == f"wrote {target}" and open(target).read() != text


# -- columns, expressions, -0 ----------------------------------------------------------------
def test_sweep_columns_pick_the_level_they_need(capsys, outdir):
    code, out, err = run(capsys, "sweep", QR, "--outdir", outdir, "-n", 11,
                         "--columns", "X4,X4d", "--columns", "stroke_xdd")
    assert code == 0, err
    lines = out.splitlines()
    assert lines[0].split() == ["T", "X4", "X4d", "stroke_xdd"] and len(lines) == 12
    assert float(lines[1].split()[1]) == pytest.approx(9.07905, abs=1e-5)
    assert float(lines[1].split()[3]) == pytest.approx(-84.3857, abs=1e-4)


def test_columns_errors(capsys, outdir):
    code, _, err = run(capsys, "sweep", QR, "--outdir", outdir, "--columns", "X4,X9")
    assert code == 1 and "no column 'X9'" in err and "X4dd" in err
    code, _, err = run(capsys, "solve", QR, "--outdir", outdir, "-t", "0", "--level",
                       "position", "--columns", "Th3d")
    assert code == 1 and "need --level velocity" in err


def test_times_as_expressions(capsys, outdir):
    code, out, err = run(capsys, "solve", QR, "--outdir", outdir, "-t", "0.5/pi",
                         "--columns", "Th2")
    assert code == 0, err
    assert "T   -> 0.1591549431" in out and "Th2 -> 1" in out     # velocidad = 2 pi
    code, out, err = run(capsys, "sweep", QR, "--outdir", outdir, "--t1", "2*pi/8",
                         "-n", 3, "--columns", "Th2")
    assert code == 0, err
    assert [ln.split()[0] for ln in out.splitlines()[1:]] == ["0", "0.392699", "0.785398"]


@pytest.mark.parametrize("text,value", [("2*pi", 2 * math.pi), ("sqrt(2)/2", math.sqrt(0.5)),
                                        ("-pi", -math.pi), ("1e-3", 1e-3), ("2**3 - 1", 7.0),
                                        ("(1 + 2) * 0.5", 1.5), ("atan2(1, 1)", math.pi / 4),
                                        ("nan", None)])
def test_number_expressions(text, value):
    if value is None:
        assert math.isnan(number(text))
    else:
        assert number(text) == pytest.approx(value, rel=1e-15)


@pytest.mark.parametrize("text", ["__import__('os')", "().__class__", "x", "2pi", "1/0",
                                  "10**10**10", "open('f')", "pi.real", "[1]", "True"])
def test_number_refuses_what_is_not_arithmetic(text):
    with pytest.raises(ValueError, match="is not a number or an expression"):
        number(text)


def test_bad_time_is_a_usage_error(capsys):
    code, _, err = run(capsys, "solve", QR, "-t", "__import__('os')")
    assert code == 2 and "argument -t" in err and "Traceback" not in err


def test_no_negative_zero(capsys, tmp_path, outdir):
    assert cell(-0.0) == "0" and cell(-1e-20) == "-1e-20"
    assert "-0" not in format_table(["a"], [[-0.0]])
    write_csv(tmp_path / "z.csv", ["a", "b"], np.array([[-0.0, 1.0], [np.nan, -0.5]]))
    assert open(tmp_path / "z.csv").read().splitlines() == ["a,b", "0.0,1.0", ",-0.5"]
    # the quick-return's slider never moves vertically: Y4d is -0.0 on its guide
    code, out, err = run(capsys, "sweep", QR, "--outdir", outdir, "-n", 5, "--columns", "Y4d")
    assert code == 0, err
    assert [ln.split()[1] for ln in out.splitlines()[1:]] == ["0"] * 5
    code, out, err = run(capsys, "solve", QR, "--outdir", outdir, "-t", "0.15", "--level",
                         "velocity", "--columns", "Y4d")
    assert code == 0 and "Y4d -> 0\n" in out


def test_times_are_the_decimals_asked_for():
    ts = times(0.0, 1.0, 21)
    assert [repr(float(t)) for t in ts] == [repr(k / 20) for k in range(21)]
    ts = times(0.0, 2 * math.pi, 5)
    assert ts[-1] == 2 * math.pi and ts[2] == math.pi         # not cut to 15 digits
    assert list(times(0.3, 0.3, 1)) == [0.3]


# -- help, broken pipe, missing file ---------------------------------------------------------
def _subparsers(ap):
    for action in ap._actions:
        if isinstance(action, argparse._SubParsersAction):
            return action.choices
    return {}


def test_every_option_has_plain_help():
    ap = parser()
    commands = _subparsers(ap)
    assert {"build", "equations", "check", "solve", "sweep", "singularities", "draw",
            "animate", "plot"} <= set(commands)
    for name, sub in [("mechgen", ap)] + list(commands.items()):
        text = sub.format_help()
        assert "``" not in text and ":class:" not in text and ":func:" not in text, name
        for action in sub._actions:
            if isinstance(action, argparse._SubParsersAction):
                continue
            assert action.help, (name, action.option_strings or action.dest)


def test_broken_pipe_is_quiet(outdir):
    proc = subprocess.Popen([sys.executable, "-m", "mechgen.cli", "sweep", QR, "--outdir",
                             outdir, "-n", "4000", "--level", "acceleration"],
                            stdout=subprocess.PIPE, stderr=subprocess.PIPE)
    head = [proc.stdout.readline() for _ in range(3)]
    proc.stdout.close()                        # as `| head -3` does
    err = proc.stderr.read().decode()
    assert proc.wait(timeout=300) == 0
    assert head[0].split()[0] == b"T"
    assert err == "", err


def test_missing_model_file_is_named_once(capsys, tmp_path):
    path = str(tmp_path / "nope.py")
    for command in (["check", path], ["sweep", path], ["build", path]):
        code, _, err = run(capsys, *command)
        assert code == 1 and err.count(path) == 1 and "does not exist" in err, err
        assert err.startswith("mechgen: error: ") and err.count("\n") == 1


# -- singularities; a failed sweep -------------------------------------------------------------
def test_singularities_command(capsys, outdir):
    code, out, err = run(capsys, "singularities", SLIDER, "--outdir", outdir, "--t1", "1")
    assert code == 0, err
    assert "4 singular configuration(s)" in out
    assert re.findall(r"T = (\S+)\s+lock", out) == LOCKS
    assert out.count("cannot fix Th2") == 4
    assert "constraints losing rank: 2 revolute(base[1], colisa[1]); 3 point_on_line" in out
    code, out, err = run(capsys, "singularities", QR, "--outdir", outdir)
    assert code == 0 and "no singular configuration for T from 0 to 1" in out


def test_failed_sweep_prints_the_points_reached(capsys, tmp_path, outdir):
    code, out, err = run(capsys, "sweep", SLIDER, "--outdir", outdir, "-n", 11,
                         "--columns", "X4")
    assert code == 1
    lines = out.splitlines()
    assert lines[0].split() == ["T", "X4"]
    assert [ln.split()[0] for ln in lines[1:]] == ["0", "0.1", "0.2"]
    assert float(lines[1].split()[1]) == pytest.approx(4.13931, abs=1e-5)
    first, *details = err.splitlines()      # a headline with the lock, details below
    assert "ConvergenceError" in first and LOCKS[0] in first
    assert all(d.startswith("  ") for d in details)
    target = tmp_path / "part.csv"
    code, out, err = run(capsys, "sweep", SLIDER, "--outdir", outdir, "-n", 11, "-o", target)
    assert code == 1 and "3 of 11 rows" in out
    assert [r[0] for r in csv.reader(open(target))][1:] == ["0.0", "0.1", "0.2"]
