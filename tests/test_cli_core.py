"""`mechgen equations` and `mechgen check`, and how the command line fails on a bad model."""
import os
import re
import subprocess
import sys
from cli_runs import run, write

import sympy as sp
from sympy.parsing.mathematica import parse_mathematica

from conftest import EXAMPLES, example_model
from test_robustness import DEAD_CENTRE

QR = os.path.join(EXAMPLES, "quick_return.py")


def sections(text):
    """{title: [lines]} of an `equations` printout (titles are unindented lines)."""
    out, title = {}, None
    for line in text.splitlines():
        if line and not line.startswith(" "):
            title = line.split(",")[0].split(":")[0].strip()
            out[title] = []
        elif title and line.strip():
            out[title].append(line)
    return out


def rows(lines):
    """{row number: expression text} from `[i]  expr    # label` or `[i]  # label` + expr."""
    found, pending = {}, None
    for line in lines:
        m = re.match(r"^\s+\[\s*(\d+)\]\s+(.*)$", line)
        if m:
            i, rest = int(m.group(1)), m.group(2)
            if rest.startswith("# "):
                pending = i
            else:
                found[i] = re.split(r"\s{4}# ", rest)[0].strip()
        elif pending is not None:
            found[pending] = line.strip()
            pending = None
    return found


# -- mechgen equations --------------------------------------------------------------------
def test_equations_prints_phi_jacobian_nu_gamma_in_the_model_symbols(capsys):
    code, out, err = run(capsys, "equations", QR)
    assert code == 0 and err == ""
    eq = example_model("quick_return").equations()
    assert "q   = (X2, Y2, Th2, X3, Y3, Th3, X4, Y4, Th4)" in out
    assert "qd  = (X2d, Y2d, Th2d" in out and "qdd = (X2dd, Y2dd" in out
    part = sections(out)
    assert set(part) >= {"Phi(q", "Phi_q", "nu = -Phi_t", "gamma"}
    names = {str(s): s for s in (*eq.q, *eq.qd, *eq.params, eq.T)}
    phi = rows(part["Phi(q"])
    assert len(phi) == 9
    for i, text in phi.items():
        assert text.endswith(" = 0")
        assert sp.expand(sp.sympify(text[:-4], locals=names) - eq.phi[i - 1]) == 0, text
    for key, vec in (("nu = -Phi_t", eq.nu), ("gamma", eq.gamma)):
        got = rows(part[key])
        assert len(got) == 9
        for i, text in got.items():
            assert sp.expand(sp.sympify(text, locals=names) - vec[i - 1]) == 0, (key, text)
    # every row carries its constraint's label
    assert "# 1 revolute(base[2], manivela[1]) x" in out
    assert "# 2 crank driver: rotation_lock(manivela, base, T*velocidad + anguloI)" in out
    assert "# 4 point_on_line(manivela[2], colisa.line(1, 2))" in out
    assert "# 6 translate(base.line(3, 4), deslizadera.line(1, 2)) offset" in out
    # the Jacobian: a pattern with its numbers, and each symbolic entry by (row, coordinate)
    jac = "\n".join(part["Phi_q"])
    assert re.search(r"\[1\]\s+-1\s+\.\s+\.", jac)
    entries = dict(re.findall(r"^\s+\[(\d+, \w+)\]\s+(.+)$", jac, re.M))
    assert sp.expand(sp.sympify(entries["6, Th2"], locals=names) - eq.phi_q[5, 2]) == 0
    assert sp.sympify(entries["8, Th4"], locals=names) == eq.phi_q[7, 8]
    assert len(entries) == sum(1 for e in eq.phi_q if e != 0 and not e.is_number)


def test_equations_numeric_substitutes_the_defaults_as_mech_prints_them(capsys):
    code, out, _ = run(capsys, "equations", QR, "--numeric")
    assert code == 0
    phi = rows(sections(out)["Phi(q"])
    assert phi[3] == "-6.28319*T + Th2 = 0"         # Mech: 0. - 6.28319 T + Th2 = 0
    assert phi[1] == "-X2 = 0" and phi[2] == "5 - Y2 = 0"
    assert "longitud" not in "".join(phi.values())
    assert rows(sections(out)["nu = -Phi_t"])[3] == "6.28319"


def test_equations_mathematica_style_reads_like_seed_001(capsys):
    code, out, _ = run(capsys, "equations", QR, "--numeric", "--mathematica")
    assert code == 0
    phi = rows(sections(out)["Phi(q"])
    assert phi[8] == "34 Sin[Th4] = 0"
    assert phi[6].startswith("9 (-X2 + X3 - 3 Cos[Th2]) Cos[Th3]")
    printed = "9 (-X2 + X3 - 3 Cos[Th2]) Cos[Th3] - 9 (Y2 - Y3 + 3 Sin[Th2]) Sin[Th3]"
    assert sp.expand(parse_mathematica(phi[6][:-4]) - parse_mathematica(printed)) == 0
    assert sp.expand(parse_mathematica(phi[7][:-4]) - parse_mathematica(
        "-25 + (Y3 - Y4 + 9 Cos[Th3])^2 + (X3 - X4 - 9 Sin[Th3])^2")) == 0


def test_equations_latex(capsys):
    code, out, _ = run(capsys, "equations", QR, "--latex")
    assert code == 0
    assert out.count(r"\begin{align*}") == out.count(r"\end{align*}") == 4
    assert r"\Phi_{1} &= - X_{2} = 0" in out
    assert r"\theta_{3}" in out and r"\dot{\theta}_{4}" in out
    assert r"\text{4 point\_on\_line(manivela[2], colisa.line(1, 2))}" in out
    assert r"\mathit{velocidad}" in out
    assert "point_on_line" not in out.replace(r"point\_on\_line", "")    # all escaped


def test_equations_of_the_loop_model_and_model_selection(capsys, tmp_path):
    code, out, _ = run(capsys, "equations", os.path.join(EXAMPLES, "fourbar_loop.py"))
    assert code == 0
    assert "q   = (theta3, theta4)" in out and "# 1 loop 1 re" in out and "# 1 loop 1 im" in out
    path = write(tmp_path, """
        from mechgen import Model, T, cos
        a = Model("first")
        x = a.coordinate("x")
        a.constraint(x - cos(T))
        b = Model("second")
        y = b.coordinate("y")
        b.constraint(y - 2 * T)
    """)
    code, out, err = run(capsys, "equations", path)
    assert code == 1 and "several models (first, second); choose one with --model" in err
    code, out, _ = run(capsys, "equations", path, "--model", "second")
    assert code == 0 and "Model second" in out and "[1]  -2*T + y = 0" in out


def test_a_build_of_several_models_writes_none_when_one_fails(capsys, tmp_path):
    """Every model of the file is rendered before any module is written: the second one
    (not square) fails the build, and the first's module is not written either."""
    path = write(tmp_path, """
        from mechgen import Model, T, cos
        a = Model("first_ok")
        x = a.coordinate("x")
        a.constraint(x - cos(T))
        b = Model("second_bad")
        y = b.coordinate("y")
        z = b.coordinate("z")
        b.constraint(y - 2 * T)
    """)
    out_dir = tmp_path / "out"
    for extra in ((), ("--force",)):
        code, out, err = run(capsys, "build", path, "--outdir", str(out_dir), *extra)
        assert code == 1 and "second_bad" in err and "not square" in err
        assert not out_dir.exists() or not list(out_dir.glob("*.py")), extra
    fixed = path.replace("model.py", "fixed.py")
    with open(fixed, "w") as fh:
        fh.write(open(path).read() + "b.constraint(z - T)\n")
    code, out, _ = run(capsys, "build", fixed, "--outdir", str(out_dir))
    assert code == 0 and sorted(p.name for p in out_dir.glob("*.py")) == \
        ["first_ok.py", "second_bad.py"]


# -- mechgen check ----------------------------------------------------------------------------
def test_check_quick_return(capsys):
    code, out, _ = run(capsys, "check", QR)
    assert code == 0
    assert "bodies:       4: base = 1 (ground), manivela = 2, colisa = 3, deslizadera = 4" in out
    assert "coordinates:  9: X2, Y2, Th2, X3, Y3, Th3, X4, Y4, Th4" in out
    assert "equations:    9 from 6 constraints" in out
    assert "drivers:      1\n    2 crank driver: rotation_lock(" in out
    assert "degrees of freedom: 1 (9 coordinates - 8 kinematic equations), 1 driven" in out
    assert "Jacobian rank at the guess (t = 0): 9 of 9" in out
    assert re.search(r"Jacobian rank assembled at t = 0 .*: 9 of 9", out)
    assert "redundant:" not in out and "left free" not in out and "MISSING" not in out
    assert out.rstrip().endswith("check: True")


def test_check_counts_the_blocks_as_the_module_solves_them(capsys):
    """check's structure line and the generated module's solving order agree: the
    quick-return's eight blocks, five explicit, three closed forms (two of them a sign kept
    from the guess), read here off the committed module's docstring."""
    code, out, _ = run(capsys, "check", QR)
    assert code == 0
    with open(os.path.join(os.path.dirname(EXAMPLES), "generated", "quick_return.py"),
              encoding="utf-8") as fh:
        doc = fh.read().split('"""')[1]
    order = re.findall(r"^  \d+\. [^(]* \((.*)\)$", doc, re.M)
    explicit = sum(o == "explicit" for o in order)
    closed = sum(o.startswith("closed form") for o in order)
    signs = sum("sign" in o for o in order)
    assert (len(order), explicit, closed, signs) == (8, 5, 3, 2)
    assert (f"structure: {len(order)} blocks as the module solves them ({explicit} explicit, "
            f"{closed} closed form); {signs} with an assembly mode the guess picks") in out


MISSING_DRIVER = """
    from mechgen import Model
    m = Model("free4")
    g = m.ground("ground", points=[(0, 0), (3, 0)])
    crank = m.body("crank", points=[(0, 0), (0.8, 0)], guess=(0, 0, 1.0))
    coupler = m.body("coupler", points=[(0, 0), (2.5, 0)], guess=(0.4, 0.7, 0.5))
    rocker = m.body("rocker", points=[(0, 0), (2, 0)], guess=(3, 0, 1.8))
    m.revolute(g[1], crank[1])
    m.revolute(crank[2], coupler[1])
    m.revolute(g[2], rocker[1])
    m.revolute(coupler[2], rocker[2])
"""


def test_check_names_the_free_coordinates_of_a_model_missing_its_driver(capsys, tmp_path):
    path = write(tmp_path, MISSING_DRIVER)
    code, out, _ = run(capsys, "check", path)
    assert code == 1
    assert "equations:    8 from 4 constraints" in out
    assert "drivers:      0" in out
    assert "MISSING: 1 equation(s) fewer than coordinates: add a driver" in out
    assert "coordinates left free: Th2, X3, Y3, Th3, Th4" in out
    assert out.rstrip().endswith("check: False")
    # and the build refuses it, in one line naming the same coordinates
    code, out, err = run(capsys, "build", path, "-o", str(tmp_path / "out"))
    assert code == 1 and out == ""
    assert "Traceback" not in err and len(err.strip().splitlines()) == 1
    assert "is not square: 8 equations for 9 coordinates" in err
    assert "Left free at the guess: Th2, X3, Y3, Th3, Th4." in err
    assert not os.path.exists(tmp_path / "out" / "free4.py")


def test_check_names_the_dependent_equations_of_a_redundant_model(capsys, tmp_path):
    """The quick-return with the slider's height held twice (translate and relative_y)."""
    text = open(QR).read() + '\nm.relative_y(deslizadera[1], 10, name="height again")\n'
    path = write(tmp_path, text)
    code, out, _ = run(capsys, "check", path)
    assert code == 0                              # consistent: reported, not refused
    assert "over-determined: 1 equation(s) more than coordinates" in out
    dependent = out.split("the dependency involves:")[1].split("  structure")[0]
    assert "7 height again: relative_y(deslizadera[1], 10)" in dependent
    assert "6 translate(base.line(3, 4), deslizadera.line(1, 2)) offset" in dependent
    assert "revolute" not in dependent and "point_on_line" not in dependent


def test_check_parallelogram_with_an_extra_parallel_link(capsys, tmp_path):
    path = write(tmp_path, """
        from mechgen import Model, T, pi
        m = Model("parallelogram")
        ground = m.ground("ground", points=[(0, 0), (4, 0), (2, 0)])
        crank = m.body("crank", points=[(0, 0), (1, 0)], guess=(0, 0, 1.0))
        coupler = m.body("coupler", points=[(0, 0), (4, 0), (2, 0)], guess=(0.5, 0.8, 0.0))
        rocker = m.body("rocker", points=[(0, 0), (1, 0)], guess=(4, 0, 1.0))
        extra = m.body("extra", points=[(0, 0), (1, 0)], guess=(2, 0, 1.0))
        m.revolute(ground[1], crank[1])
        m.revolute(crank[2], coupler[1])
        m.revolute(ground[2], rocker[1])
        m.revolute(coupler[2], rocker[2])
        m.revolute(ground[3], extra[1])
        m.revolute(coupler[3], extra[2], name="extra link")
        m.rotation_lock(crank, 1.0 + 2 * pi * T, name="crank")
    """)
    code, out, _ = run(capsys, "check", path)
    assert code == 0
    assert "degrees of freedom: 0 (12 coordinates - 12 kinematic equations), 1 driven" in out
    assert re.search(r"assembled .*: 12 of 12", out)
    assert "redundant: 1 dependent equation(s)" in out
    dependent = out.split("the dependency involves:")[1].split("  structure")[0]
    assert "6 extra link: revolute(coupler[3], extra[2])" in dependent
    assert "crank: rotation_lock" not in dependent          # the driver is independent


def test_check_rank_deficient_square_model(capsys, tmp_path):
    """Square but singular: a constraint repeated in place of the driver."""
    path = write(tmp_path, """
        from mechgen import Model
        m = Model("twice")
        g = m.ground("g", points=[(0, 0), (1, 0)])
        b = m.body("b", points=[(0, 0), (1, 0)], guess=(0.2, 0.1, 0.3))
        m.revolute(g[1], b[1])
        m.relative_x(b[1], 0, name="again")
    """)
    code, out, _ = run(capsys, "check", path)
    assert code == 1
    assert "Jacobian rank at the guess (t = 0): 2 of 3" in out
    dependent = out.split("the dependency involves:")[1].split("  free")[0]
    assert "1 revolute(g[1], b[1]) x" in dependent and "2 again: relative_x" in dependent
    assert "revolute(g[1], b[1]) y" not in dependent
    assert "coordinates left free: Th2" in out


# -- failures: one clear message, no traceback ----------------------------------------------
def test_bad_model_fails_with_one_clear_message(capsys, tmp_path):
    path = write(tmp_path, """
        from mechgen import Model
        m = Model("bad")
        base = m.ground("base", points=[(0, 0)])
        colisa = m.body("colisa", points=[(0, 0), (0, 9)])
        m.revolute(base[1], colisa[3])
    """)
    for command in ("equations", "check", "build"):
        code, out, err = run(capsys, command, path)
        assert code == 1, command
        assert err.strip() == (f"mechgen: ModelError: {path}:5: body 'colisa' has 2 points; "
                               "point 3 does not exist (points count from 1, 0 is the origin)")


def test_missing_file_and_raising_file(capsys, tmp_path):
    code, _, err = run(capsys, "check", str(tmp_path / "nope.py"))
    assert code == 1 and "does not exist" in err and "Traceback" not in err
    path = write(tmp_path, "import mechgen\nm = mechgen.Model('x')\n1 / 0\n")
    code, _, err = run(capsys, "equations", path)
    assert code == 1
    assert f"{path}:3: the model file raised ZeroDivisionError: division by zero" in err


def test_console_script_prints_no_traceback(tmp_path):
    path = write(tmp_path, MISSING_DRIVER.replace("m.revolute(g[1], crank[1])",
                                                  "m.revolute(g, crank[1])"))
    proc = subprocess.run([sys.executable, "-m", "mechgen.cli", "check", path],
                          capture_output=True, text=True, timeout=120)
    assert proc.returncode == 1
    assert "Traceback" not in proc.stderr
    assert proc.stderr.strip() == (f"mechgen: ModelError: {path}:7: revolute: argument 1 must "
                                   "be a point such as body[1], got body ground")


def test_the_command_prints_a_warning_as_one_line_of_its_own(tmp_path):
    """A sweep leaving a dead centre warns; the command says so in its own words, not with
    the line of mechgen's source that raised it."""
    path = write(tmp_path, DEAD_CENTRE.format(guess=0.01))
    env = dict(os.environ, MECHGEN_CACHE=str(tmp_path / "cache"), MECHGEN_TIER="python")
    proc = subprocess.run([sys.executable, "-m", "mechgen.cli", "sweep", path, "--t0", "0",
                           "--t1", "0.1", "-n", "6", "--columns", "Th2"],
                          capture_output=True, text=True, timeout=300, cwd=str(tmp_path), env=env)
    assert proc.returncode == 0, proc.stderr
    lines = proc.stderr.strip().splitlines()
    assert len(lines) == 1 and lines[0].startswith(
        "mechgen: warning: BranchJumpWarning: sweep of 'from_dead_centre': the way to t=0.02 "
        "reaches or passes a singular configuration"), proc.stderr
