"""``mechgen synthesize POSES.csv``: the table of four-bars, -o's model file (built by
``mechgen build`` and solved at its times: the coupler frame on every pose), --points,
--png, and bad files refused with a one-line error naming the line, nothing written."""
import math
import os

import numpy as np
import pytest

from mechgen.cli import main

GATE = [(0.845, 0.606, 0.360), (0.689, 0.823, 0.180), (0.368, 0.818, 0.054),
        (0.075, 0.592, 0.021), (-0.027, 0.263, 0.088)]


def write(path, text):
    path.write_text(text)
    return str(path)


@pytest.fixture
def gate_csv(tmp_path):
    rows = "\n".join(f"{x}, {y}, {a}" for x, y, a in GATE)
    return write(tmp_path / "gate.csv", "# a gate's five positions\nx,y,angle\n" + rows + "\n")


def test_the_table_of_five_poses(gate_csv, capsys):
    assert main(["synthesize", gate_csv]) == 0
    out = capsys.readouterr().out
    lines = out.splitlines()
    assert lines[0].startswith("5 poses from") and "12 four-bars" in lines[0]
    head = lines[1].split()
    for word in ("O2", "O4", "a", "b", "c", "d", "Grashof", "defects", "transmission"):
        assert word in head
    rows = [ln for ln in lines[2:] if ln.strip()[:2].strip().isdigit()]
    assert len(rows) == 12
    assert "73.3–107.5°" in rows[0] and "crank-rocker" in rows[0] and " none " in rows[0]
    assert sum("circuit" in r for r in rows) == 8
    assert "best defect-free: #1" in out


def test_the_model_file_builds_and_meets_every_pose(gate_csv, tmp_path, capsys):
    import mechgen
    target = str(tmp_path / "gate_linkage.py")
    assert main(["synthesize", gate_csv, "-o", target]) == 0
    assert f"wrote {target}" in capsys.readouterr().out
    outdir = str(tmp_path / "generated")
    assert main(["build", target, "-o", outdir]) == 0
    assert os.path.isfile(os.path.join(outdir, "gate_linkage.py"))
    mech = mechgen.compile(target, outdir=outdir, tier="python")
    scope = {}
    exec(open(target).read(), scope)
    assert np.allclose(scope["POSES"], GATE, atol=0)
    for t, (x, y, th) in zip(scope["TIMES"], GATE):
        s = mech.solve(t)
        assert abs(s["X3"] - x) < 1e-9 and abs(s["Y3"] - y) < 1e-9
        assert abs(math.remainder(s["Th3"] - th, 2 * math.pi)) < 1e-9


def test_points_takes_the_first_poses_and_png_draws(gate_csv, tmp_path, capsys):
    png = str(tmp_path / "four.png")
    assert main(["synthesize", gate_csv, "--points", "4", "--samples", "4", "--png", png]) == 0
    out = capsys.readouterr().out
    assert out.startswith("4 poses from") and "12 four-bars" in out
    with open(png, "rb") as fh:
        assert fh.read(8) == b"\x89PNG\r\n\x1a\n"
    assert main(["synthesize", gate_csv, "--points", "3", "--samples", "3"]) == 0
    assert capsys.readouterr().out.startswith("3 poses from")


@pytest.mark.parametrize("text, args, message", [
    ("x,y,angle\n0, 0, 0\n1, oops, 0.2\n1, 1, 0.4\n", [], "bad.csv:3: y 'oops' is not a number"),
    ("0, 0, 0\n1, 0\n1, 1, 0.4\n", [], "bad.csv:2: expected three values x, y, angle, got 2"),
    ("0, 0, 0\n1, 0, nan\n1, 1, 0.4\n", [], "bad.csv:2: angle is 'nan', not a finite number"),
    ("# nothing\n\n", [], "bad.csv: no poses in it"),
    ("0,0,0\n1,0,0.2\n0,0,0\n", [], "pose 3 repeats pose 1"),
    ("0,0,0\n1,0,0.2\n1,1,0.4\n", ["--points", "4"], "bad.csv has only 3 poses"),
    ("0,0,0\n1,0,0.2\n1,1,0.4\n", ["--points", "2"], "--points 2: synthesis takes 3, 4 or 5"),
    ("".join(f"{k},{k * k},{0.1 * k}\n" for k in range(6)), [], "6 poses; at most 5"),
])
def test_bad_poses_are_one_line_errors_and_nothing_is_written(tmp_path, capsys, text, args,
                                                              message):
    path = write(tmp_path / "bad.csv", text)
    target = tmp_path / "out.py"
    png = tmp_path / "out.png"
    assert main(["synthesize", path, "-o", str(target), "--png", str(png)] + args) == 1
    err = capsys.readouterr().err.strip()
    assert message in err and len(err.splitlines()) == 1 and err.startswith("mechgen: error:")
    assert not target.exists() and not png.exists()
    assert [p.name for p in tmp_path.iterdir()] == ["bad.csv"]


def test_an_existing_file_is_left_as_it_was_on_an_error(tmp_path, capsys):
    path = write(tmp_path / "bad.csv", "0,0,0\n1,0,0.2\n")
    target = write(tmp_path / "keep.py", "old = 1\n")
    assert main(["synthesize", path, "-o", target]) == 1
    assert "at least 3 needed" in capsys.readouterr().err
    assert open(target).read() == "old = 1\n"


def test_help_and_degrees(gate_csv, tmp_path, capsys):
    with pytest.raises(SystemExit) as stop:
        main(["synthesize", "--help"])
    assert stop.value.code == 0
    assert "POSES.csv" in capsys.readouterr().out
    rows = "\n".join(f"{x}, {y}, {math.degrees(a)}" for x, y, a in GATE)
    deg = write(tmp_path / "deg.csv", rows + "\n")
    assert main(["synthesize", deg, "--degrees"]) == 0
    assert main(["synthesize", gate_csv]) == 0
    a, b = capsys.readouterr().out.split("5 poses from")[1:]
    assert a.split("\n", 1)[1] == b.split("\n", 1)[1]          # the same table
