"""How the command line fails, end to end: `check` must not pass a model whose redundant
equations agree only at the instant checked (a driver fighting a constraint or another
driver, a lock on a driven body, an extra link that makes the linkage rigid); a division by
zero in the model's equations (a driver 1/T at T = 0, the rate of sqrt(T) there) and an
undefined sympy function are one clear message, not a traceback."""
from __future__ import annotations

from cli_runs import run, write

import numpy as np
import pytest


FOURBAR = """
from mechgen import Model, T, pi, distance
m = Model("{name}")
base = m.ground("base", points=[(0, 0), (4, 0)])
crank = m.body("crank", points=[(0, 0), (1, 0)], guess=(0, 0, 1.0))
coupler = m.body("coupler", points=[(0, 0), (4, 0)], guess=(0.5, 0.8, 0.3))
rocker = m.body("rocker", points=[(0, 0), (3, 0)], guess=(4, 0, 1.6))
m.revolute(base[1], crank[0])
m.revolute(crank[2], coupler[0])
m.revolute(coupler[2], rocker[2])
m.revolute(base[2], rocker[0])
m.rotation_lock(crank, 2 * pi * T + 1.0, name="drive")
{extra}
"""


@pytest.fixture(autouse=True)
def _plain(monkeypatch):
    monkeypatch.setenv("MECHGEN_TIER", "python")


def one_line(err):
    lines = [ln for ln in err.splitlines() if ln.strip()]
    assert len(lines) == 1 and "Traceback" not in err, err
    return lines[0]


# -- check: redundant equations that agree only at t --------------------------------------
@pytest.mark.parametrize("name, extra, culprits", [
    # a second driver of the crank at twice the speed: both hold at t = 0 only
    ("fight", 'm.constraint(crank.th - 4 * pi * T - 1.0, name="drive2")', ["drive2"]),
    # the driven crank also locked at its angle at t = 0
    ("lock", 'm.constraint(crank.th - 1.0, name="lock")', ["lock"]),
    # an extra link from the coupler's pin to the frame: the four-bar made rigid
    ("rigid", 'm.constraint(distance(coupler[0], base[2]) - 3.560559162976355, '
              'name="extra")', ["extra"]),
    # the rate agrees (0 at t = 0), the acceleration does not
    ("accel", 'm.constraint(crank.th - 2 * pi * T - 1.0 - T**2, name="drive2")', ["drive2"]),
])
def test_check_fails_redundant_equations_that_agree_only_at_t(capsys, tmp_path, name, extra,
                                                              culprits):
    path = write(tmp_path, FOURBAR.format(name=name, extra=extra))
    code, out, _ = run(capsys, "check", path)
    # before: "check: True" (exit 0), yet solve(0.3) failed: "the redundant constraints
    # are inconsistent here"
    assert code == 1 and "check: False" in out, out
    assert "CANNOT MOVE from t = 0" in out
    block = out[out.index("CANNOT MOVE"):]
    assert all(c in block for c in culprits) and "drive:" in block


def test_check_passes_a_consistent_redundant_driver(capsys, tmp_path):
    extra = 'm.rotation_lock(crank, 2 * pi * T + 1.0, name="drive2")'
    path = write(tmp_path, FOURBAR.format(name="red", extra=extra))
    code, out, _ = run(capsys, "check", path)
    assert code == 0 and "check: True" in out and "redundant: 1" in out
    assert "CANNOT" not in out


def test_check_fails_a_slider_driver_fighting_its_guide(capsys, tmp_path):
    """The quick-return's slider turned by a driver while its translate holds it level."""
    from conftest import EXAMPLES
    text = open(f"{EXAMPLES}/quick_return.py").read() + \
        '\nm.rotation_lock(deslizadera, 0.5 * T, name="slider spin")\n'
    code, out, _ = run(capsys, "check", write(tmp_path, text))
    assert code == 1 and "CANNOT MOVE" in out and "slider spin" in out, out


# -- division by zero and undefined functions: one message -----------------------------------
ONE_BODY = """
from mechgen import Model, T, sqrt
import sympy
m = Model("{name}")
b = m.ground("b", points=[(0, 0)])
c = m.body("c", points=[(0, 0), (1, 0)], guess=(0, 0, 0))
m.revolute(b[1], c[0])
m.rotation_lock(c, {angle})
"""


@pytest.mark.parametrize("angle, argv, words", [
    # solve(0.5) follows the motion from the guess's time 0, where 1/T divides by zero
    ("1/T", ["solve", "-t", "0.5"], "non-finite"),
    ("1/T", ["check"], "CANNOT ASSEMBLE"),
    # the rate of sqrt(T) at T = 0
    ("sqrt(T)", ["solve", "-t", "0", "--level", "velocity"], "not finite"),
    ("sqrt(T)", ["sweep", "-n", "3", "--level", "acceleration"], "divide by zero"),
    ('sympy.Function("f")(T)', ["check"], "undefined function"),
    ('sympy.Function("f")(T)', ["solve", "-t", "0"], "undefined function"),
])
def test_a_singular_driver_is_one_message(capsys, tmp_path, angle, argv, words):
    path = write(tmp_path, ONE_BODY.format(name="div", angle=angle))
    code, out, err = run(capsys, argv[0], path, *argv[1:],
                         *(["--outdir", str(tmp_path / "gen")] if argv[0] != "check" else []))
    # before: ZeroDivisionError / NameError / PrintMethodNotImplementedError tracebacks
    assert code == 1
    text = out + err if argv[0] == "check" else one_line(err)
    assert "Traceback" not in err and words in text, (out, err)


def test_runtime_solve_of_a_driver_dividing_by_zero_raises_mechgen_errors(tmp_path):
    import mechgen
    path = write(tmp_path, ONE_BODY.format(name="div2", angle="sqrt(T)"))
    mech = mechgen.compile(mechgen.load_model(path), outdir=str(tmp_path / "gen"))
    with pytest.raises(mechgen.SingularError, match="not finite"):
        mech.solve(0.0, level="velocity")
    s = mech.solve(0.5, level="acceleration")
    assert s["Th2dd"] == pytest.approx(-0.25 * 0.5 ** -1.5, rel=1e-12)
    with pytest.raises(mechgen.MechgenError, match="divide by zero"):
        mech.sweep(0, 1, 3, level="acceleration")
    assert np.isfinite(mech.sweep(0.25, 1, 3, level="acceleration")["Th2dd"]).all()


def test_a_design_table_through_a_division_by_zero_is_a_singular_error(tmp_path):
    """The same SingularError as a single sweep's, not a bare ZeroDivisionError out of
    the module's sweep_designs (in both tiers)."""
    import mechgen
    text = ONE_BODY.format(name="div3", angle="sqrt(T)").replace(
        '(1, 0)], guess', '(L, 0)], guess').replace('m = Model("div3")',
                                                     'm = Model("div3")\nL = m.param("L", 1.0)')
    mech = mechgen.compile(mechgen.load_model(write(tmp_path, text)),
                           outdir=str(tmp_path / "gen"))
    with pytest.raises(mechgen.SingularError, match="divide by zero at a time of the design"):
        mech.sweep(0, 1, 3, level="velocity", params={"L": [1.0, 2.0]})
    tab = mech.sweep(0.25, 1, 3, level="velocity", params={"L": [1.0, 2.0]})
    assert np.allclose(tab["Th2d"][:, 0], 0.5 / 0.25 ** 0.5, rtol=1e-12)


# -- nothing half-written ---------------------------------------------------------------
def test_a_csv_that_fails_midway_leaves_no_file_and_keeps_the_old_one(tmp_path):
    from mechgen.cli.tables import write_csv
    path = tmp_path / "t.csv"
    with pytest.raises(ValueError):
        write_csv(str(path), ["T"], [[1.0], ["not a number"]])
    # before: t.csv held the header and the first row
    assert list(tmp_path.iterdir()) == []
    path.write_text("T\n0.5\n")
    with pytest.raises(ValueError):
        write_csv(str(path), ["T"], [[1.0], ["not a number"]])
    assert path.read_text() == "T\n0.5\n" and list(tmp_path.iterdir()) == [path]
    write_csv(str(path), ["T"], np.array([[0.25]]))
    assert path.read_text().splitlines() == ["T", "0.25"]


@pytest.mark.parametrize("argv", [["draw", "-t", "0.1", "-o", "{d}/p.png"],
                                  ["plot", "Th2", "-n", "3", "-o", "{d}/p.png"],
                                  ["animate", "-n", "3", "-o", "{d}/p.gif"]])
def test_a_picture_that_fails_midway_leaves_no_file(capsys, tmp_path, monkeypatch, argv):
    import matplotlib.figure
    from PIL import Image

    def half(self, fname, *args, **kwargs):
        with open(fname, "wb") as fh:
            fh.write(b"\x89PNG half")
        raise OSError("No space left on device")
    monkeypatch.setattr(matplotlib.figure.Figure, "savefig", half)
    monkeypatch.setattr(Image.Image, "save", half)
    path = write(tmp_path, ONE_BODY.format(name="pic", angle="2*T"))
    out = tmp_path / "out"
    out.mkdir()
    argv = [a.format(d=out) for a in argv]
    code, _, err = run(capsys, argv[0], path, *argv[1:], "--outdir", str(tmp_path / "gen"))
    assert code == 1 and "No space left" in one_line(err)
    # before: p.png / p.gif of 10 bytes stayed behind
    assert list(out.iterdir()) == []


def test_pictures_and_tables_are_written_whole(capsys, tmp_path):
    path = write(tmp_path, ONE_BODY.format(name="whole", angle="2*T"))
    gen = str(tmp_path / "gen")
    out = tmp_path / "out"
    out.mkdir()
    assert run(capsys, "draw", path, "-t", "0.1", "-o", str(out / "d.png"), "--outdir",
               gen)[0] == 0
    assert run(capsys, "sweep", path, "-n", "3", "-o", str(out / "s.csv"), "--outdir",
               gen)[0] == 0
    assert sorted(p.name for p in out.iterdir()) == ["d.png", "s.csv"]
    assert (out / "d.png").read_bytes()[:4] == b"\x89PNG"
    assert (out / "s.csv").stat().st_mode & 0o777 == 0o666 & ~_umask()


def _umask():
    import os
    mask = os.umask(0)
    os.umask(mask)
    return mask


def test_an_unexpected_exception_is_one_line(capsys, tmp_path, monkeypatch):
    import mechgen.cli.solve_commands as sc

    def broken(args):
        raise AttributeError("'NoneType' object has no attribute 'q'")
    monkeypatch.setattr(sc, "mechanism", broken)
    path = write(tmp_path, ONE_BODY.format(name="oops", angle="2*T"))
    code, _, err = run(capsys, "solve", path, "-t", "0")
    assert code == 1
    assert one_line(err).startswith("mechgen: internal error: AttributeError")


def test_plot_of_one_point_is_refused_not_an_empty_picture(capsys, tmp_path):
    path = write(tmp_path, ONE_BODY.format(name="one_point", angle="2*T"))
    out = tmp_path / "p.png"
    code, _, err = run(capsys, "plot", path, "Th2", "-n", "1", "-o", str(out), "--outdir",
                       str(tmp_path / "gen"))
    # before: "wrote p.png (Th2 over 1 points)", axes with no curve
    assert code == 1 and "-n must be at least 2" in one_line(err) and not out.exists()


def test_written_goes_through_links_and_devices(tmp_path):
    import os
    from mechgen.cli.tables import write_csv
    target = tmp_path / "target.csv"
    target.write_text("old\n")
    link = tmp_path / "link.csv"
    link.symlink_to(target)
    write_csv(str(link), ["T"], np.array([[1.0]]))
    assert link.is_symlink() and target.read_text().splitlines() == ["T", "1.0"]
    write_csv(os.devnull, ["T"], np.array([[1.0]]))      # not replaced by a regular file
    assert not os.path.isfile(os.devnull)
    assert sorted(p.name for p in tmp_path.iterdir()) == ["link.csv", "target.csv"]


def test_check_starts_must_be_a_count(capsys):
    from conftest import EXAMPLES
    code, _, err = run(capsys, "check", f"{EXAMPLES}/quick_return.py", "--starts", "-5")
    # before: "mechgen: error: negative dimensions are not allowed"
    assert code == 2 and "--starts: '-5' is not a count" in err


@pytest.mark.parametrize("argv", [["draw", "--width", "0"], ["animate", "--fps", "0"],
                                  ["animate", "--fps", "-1"], ["draw", "--dpi", "1e9"]])
def test_picture_sizes_and_rates_are_usage_errors(capsys, tmp_path, argv):
    from conftest import EXAMPLES
    code, _, err = run(capsys, argv[0], f"{EXAMPLES}/quick_return.py", *argv[1:], "-o",
                       str(tmp_path / ("p.gif" if argv[0] == "animate" else "p.png")))
    # before: ZeroDivisionError / OverflowError tracebacks, or a 1e9-dpi attempt
    assert code == 2 and "must be a positive number" in err
    assert list(tmp_path.iterdir()) == []


@pytest.mark.parametrize("steps", ["0", "1", "-1"])
def test_view_html_steps_must_vary_something(capsys, tmp_path, steps):
    from conftest import EXAMPLES
    code, _, err = run(capsys, "view", f"{EXAMPLES}/quick_return.py", "--html",
                       str(tmp_path / "v.html"), "--steps", steps)
    # before: --steps 0 wrote "1 cycles precomputed over )", -1 numpy's "Number of samples"
    assert code == 2 and "give 2 or more values" in err and not list(tmp_path.iterdir())
