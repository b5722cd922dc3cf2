"""Malformed input: runtime calls, generated modules edited or from another version, and
model files through the command line. Each gets one clear message naming the culprit;
a failed build leaves no module (and no temporary file) behind."""
import os
import subprocess
import sys

import numpy as np
import pytest

import mechgen
from mechgen.protocol import FORMAT_VERSION, _STAMP as _CHECK, content_digest

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
GENERATED = os.path.join(ROOT, "generated")
EXAMPLES = os.path.join(ROOT, "examples")
NAN, INF = float("nan"), float("inf")


# -- runtime calls ------------------------------------------------------------------------
RUNTIME_CASES = [
    # (what, call, exception, words the message must hold)
    ("unknown coordinate", lambda m: m.solve(0.1)["X9"], KeyError, ["'X9'", "X4"]),
    ("unknown derivative", lambda m: m.solve(0.1)["X9dd"], KeyError, ["'X9dd'"]),
    ("derivative not solved", lambda m: m.solve(0.1)["X4d"], KeyError, ["velocity"]),
    ("unknown sweep column", lambda m: m.sweep(0, 1, 3)["Th7"], KeyError, ["'Th7'"]),
    ("unknown parameter", lambda m: m.with_params(longitude=2.0), ValueError,
     ["'longitude'", "longitud"]),
    ("NaN parameter", lambda m: m.with_params(longitud=NAN), ValueError, ["'longitud'", "finite"]),
    ("infinite parameter", lambda m: m.with_params(velocidad=INF), ValueError, ["'velocidad'"]),
    ("text parameter", lambda m: m.with_params(longitud="3 m"), ValueError, ["'longitud'", "number"]),
    ("None parameter", lambda m: m.with_params(anguloI=None), ValueError, ["'anguloI'"]),
    ("NaN time", lambda m: m.solve(NAN), ValueError, ["t", "finite"]),
    ("infinite time", lambda m: m.solve(-INF), ValueError, ["t", "finite"]),
    ("text time", lambda m: m.solve("0.1"[::-1] + "x"), ValueError, ["t must be a number"]),
    ("None time", lambda m: m.solve(None), ValueError, ["t must be a number"]),
    ("unknown guess name", lambda m: m.solve(0.1, guess={"X9": 1.0}), ValueError, ["'X9'", "Th4"]),
    ("NaN guess", lambda m: m.solve(0.1, guess={"X4": NAN}), ValueError, ["X4", "finite"]),
    ("text guess", lambda m: m.solve(0.1, guess={"X4": "far"}), ValueError, ["X4", "number"]),
    ("short guess", lambda m: m.solve(0.1, guess=np.zeros(3)), ValueError, ["(9,)", "(3,)"]),
    ("2-D guess", lambda m: m.solve(0.1, guess=np.zeros((9, 1))), ValueError, ["(9,)", "(9, 1)"]),
    ("inf in guess", lambda m: m.solve(0.1, guess=np.full(9, INF)), ValueError, ["NaN or infinite"]),
    ("unknown level", lambda m: m.solve(0.1, level="speed"), ValueError, ["'speed'", "velocity"]),
    ("unknown method", lambda m: m.solve(0.1, method="fast"), ValueError, ["'fast'", "sorted"]),
    ("negative tol", lambda m: m.solve(0.1, tol=-1e-9), ValueError, ["tol", "positive"]),
    ("NaN tol", lambda m: m.solve(0.1, tol=NAN), ValueError, ["tol"]),
    ("zero maxit", lambda m: m.solve(0.1, maxit=0), ValueError, ["maxit"]),
    ("float maxit", lambda m: m.solve(0.1, maxit=2.5), ValueError, ["maxit"]),
    ("zero points", lambda m: m.sweep(0, 1, 0), ValueError, ["n must be a positive integer"]),
    ("float points", lambda m: m.sweep(0, 1, 2.5), ValueError, ["n must be"]),
    ("bool points", lambda m: m.sweep(0, 1, True), ValueError, ["n must be"]),
    ("NaN sweep end", lambda m: m.sweep(0, NAN, 5), ValueError, ["t1", "finite"]),
    ("NaN in times", lambda m: m.sweep(0, 1, 5, times=[0, NAN, 1]), ValueError, ["times"]),
    ("2-D times", lambda m: m.sweep(0, 1, 5, times=[[0, 1]]), ValueError, ["times"]),
    ("n beside times", lambda m: m.sweep(0, 1, 101, times=np.linspace(0, 1, 50)), ValueError,
     ["n=101", "50 points"]),
    ("t1 beside times", lambda m: m.sweep(0, 1, 5, times=np.linspace(0, 0.8, 5)), ValueError,
     ["t1=1", "0.8"]),
    ("t0 beside times", lambda m: m.sweep(0.1, 1, 3, times=[0, 0.5, 1]), ValueError, ["t0=0.1"]),
    ("table n beside times", lambda m: m.sweep(0, 1, 7, times=[0, 0.5, 1],
                                               params={"longitud": [2.0, 3.0]}),
     ValueError, ["n=7", "3 points"]),
    ("sweep guess", lambda m: m.sweep(0, 1, 5, guess={"Y9": 0}), ValueError, ["'Y9'"]),
    ("singularities n", lambda m: m.singularities(0, 1, n=1), ValueError, ["n must be"]),
    ("singularities NaN", lambda m: m.singularities(NAN, 1), ValueError, ["t0", "finite"]),
    ("not a name", lambda m: m.solve(0.1)[3], TypeError, ["name"]),
]


@pytest.mark.parametrize("what,call,exc,words", RUNTIME_CASES, ids=[c[0] for c in RUNTIME_CASES])
def test_runtime_refuses_bad_input(qr, what, call, exc, words):
    before = (qr.p.copy(), qr.last, qr.guess.copy())
    with pytest.raises(exc) as info:
        call(qr)
    text = str(info.value)
    for word in words:
        assert word in text, (what, text)
    assert "\n" not in text.strip("'\"")                          # one message, one line
    assert np.array_equal(qr.p, before[0]) and np.array_equal(qr.guess, before[2])


def test_a_failed_solve_leaves_last_alone(qr_slider):
    good = qr_slider.solve(0.1)
    with pytest.raises(mechgen.ConvergenceError):
        qr_slider.solve(0.25)
    assert qr_slider.last is good


def test_failed_sweep_carries_only_converged_points(qr_slider):
    with pytest.raises(mechgen.ConvergenceError) as info:
        qr_slider.sweep(0.0, 0.5, 51, level="acceleration")
    sw = info.value.sweep
    assert 0 < len(sw) < 51 and np.all(np.isfinite(sw.Q)) and np.all(np.isfinite(sw.QDD))
    assert max(qr_slider.residual(q, t) for q, t in zip(sw.Q, sw.t)) <= 1e-10


# -- generated modules ------------------------------------------------------------------------
def _copy(tmp_path, edit=None, restamp=False, name="quick_return_slider"):
    text = open(os.path.join(GENERATED, name + ".py"), encoding="utf-8").read()
    if edit:
        text = edit(text)
    if restamp:
        body = _CHECK.sub("", text, count=1)
        text = f"# content-sha256: {content_digest(body)}\n" + body
    sub = tmp_path / f"copy{len(list(tmp_path.iterdir()))}"
    sub.mkdir()
    path = sub / (name + ".py")
    path.write_text(text, encoding="utf-8")
    return str(path)


def test_module_edited_by_hand_is_refused(tmp_path):
    path = _copy(tmp_path, lambda s: s.replace("out[8] = X4 - amplitud", "out[8] = X4 + amplitud"))
    with pytest.raises(mechgen.MechgenError, match="edited after mechgen generated it"):
        mechgen.load(path)
    path = _copy(tmp_path, lambda s: s + "\n# a harmless comment\n")
    with pytest.raises(mechgen.MechgenError, match="rebuild it"):
        mechgen.load(path)


def test_module_without_a_stamp_is_refused(tmp_path):
    path = tmp_path / "not_generated.py"
    path.write_text("N_COORDS = 1\n")
    with pytest.raises(mechgen.MechgenError, match="not a module generated by mechgen"):
        mechgen.load(str(path))


def test_module_of_another_format_is_refused(tmp_path):
    path = _copy(tmp_path, lambda s: s.replace(f"FORMAT_VERSION = {FORMAT_VERSION}",
                                               "FORMAT_VERSION = 99"), restamp=True)
    with pytest.raises(mechgen.MechgenError, match=r"format 99.*rebuild it"):
        mechgen.load(path)


def test_module_of_another_mechgen_version_is_refused(tmp_path):
    path = _copy(tmp_path, lambda s: s.replace(f'MECHGEN_VERSION = "{mechgen.__version__}"',
                                               'MECHGEN_VERSION = "0.0.1"'), restamp=True)
    with pytest.raises(mechgen.MechgenError, match=r"generated by mechgen 0\.0\.1.*rebuild"):
        mechgen.load(path)


def test_module_that_raises_on_import_is_refused(tmp_path):
    path = _copy(tmp_path, lambda s: s.replace("import math\n", "import math\nraise ImportError('no numba here')\n", 1),
                 restamp=True, name="fourbar_loop")
    with pytest.raises(mechgen.MechgenError, match=r"raised ImportError: no numba here"):
        mechgen.load(path)


def test_load_of_nothing(tmp_path):
    with pytest.raises(mechgen.MechgenError, match="no generated module"):
        mechgen.load(str(tmp_path / "missing.py"))
    with pytest.raises(TypeError, match="a path or a module"):
        mechgen.load(42)


# -- model files through the command line --------------------------------------------------------
HEAD = '''from mechgen import Model, T, pi, sin, Symbol
m = Model("bad")
L = m.param("L", 3.0)
base = m.ground("base", points=[(0, 0), (0, 5)])
crank = m.body("crank", points=[(0, 0), (L, 0)], guess=(0, 5, 0))
m.revolute(base[2], crank[1])
'''
BAD_MODELS = [
    # (name, source, words the one-line message must hold)
    ("typo", HEAD + "m.rotation_lokc(crank, 2*pi*T)\n", ["bad_typo.py:7", "rotation_lokc"]),
    ("arity", HEAD + "m.revolute(base[2])\nm.rotation_lock(crank, 2*pi*T)\n",
     ["bad_arity.py:7", "revolute", "p2"]),
    ("unknown_point", HEAD + "m.point_on_line(crank[5], base.line(1, 2))\n",
     ["bad_unknown_point.py:7", "crank", "point 5"]),
    ("unknown_body", HEAD + "m.rotation_lock(m['nope'], 2*pi*T)\n",
     ["bad_unknown_body.py:7", "'nope'", "base, crank"]),
    ("undeclared", HEAD + "zz = Symbol('zz')\nm.rotation_lock(crank, zz*T)\n",
     ["bad_undeclared.py:8", "zz"]),
    ("non_numeric", HEAD + "w = m.param('w', 'fast')\nm.rotation_lock(crank, w*T)\n",
     ["bad_non_numeric.py:7", "'w'"]),
    ("raises", HEAD + "raise RuntimeError('boom in the model')\n",
     ["bad_raises.py:7", "RuntimeError", "boom in the model"]),
    ("missing_driver", HEAD, ["bad_missing_driver.py", "not square", "driver"]),
    ("empty", 'from mechgen import Model\nm = Model("empty")\n', ["bad_empty.py:2", "no coordinates"]),
    ("no_model", "x = 1\n", ["bad_no_model.py", "no mechgen.Model"]),
    ("syntax", 'from mechgen import Model\nm = Model("s"\n', ["bad_syntax.py", "syntax error"]),
]


@pytest.mark.parametrize("name,source,words", BAD_MODELS, ids=[b[0] for b in BAD_MODELS])
def test_bad_model_files_fail_cleanly(tmp_path, capsys, name, source, words):
    from mechgen.cli import main
    src = tmp_path / f"bad_{name}.py"
    src.write_text(source)
    out = tmp_path / "out"
    out.mkdir()
    commands = [["build", str(src), "-o", str(out)]]
    if name != "missing_driver":                  # the others fail as the file is read
        commands += [["check", str(src)], ["equations", str(src)]]
    for command in commands:
        code = main(command)
        err = capsys.readouterr().err
        assert code == 1, (command, err)
        assert err.startswith("mechgen: ") and err.count("\n") == 1, err
        for word in words:
            assert word in err, (command, word, err)
    assert os.listdir(out) == []                  # nothing written, no temporary file


def test_cli_exit_status_and_message(tmp_path):
    """The real command: a non-zero exit and one line on stderr, no traceback."""
    src = tmp_path / "bad_typo.py"
    src.write_text(BAD_MODELS[0][1])
    proc = subprocess.run([sys.executable, "-m", "mechgen.cli", "build", str(src), "-o",
                           str(tmp_path / "out")], capture_output=True, text=True, timeout=120)
    assert proc.returncode == 1 and "Traceback" not in proc.stderr
    assert proc.stderr.strip().count("\n") == 0 and "rotation_lokc" in proc.stderr
    assert not (tmp_path / "out").exists() or os.listdir(tmp_path / "out") == []


def test_failed_write_leaves_no_half_module(tmp_path, monkeypatch):
    import importlib
    build_mod = importlib.import_module("mechgen.compiler.build")  # the module, not the function
    from mechgen.model.loader import load_models
    model = load_models(os.path.join(EXAMPLES, "fourbar_loop.py"))[0]
    out = tmp_path / "out"
    path = build_mod.build(model, str(out))
    good = open(path, encoding="utf-8").read()

    def broken_replace(src, dst):
        raise OSError("disk full")
    monkeypatch.setattr(build_mod.os, "replace", broken_replace)
    with pytest.raises(OSError, match="disk full"):
        build_mod.build(model, str(out))
    assert os.listdir(out) == ["fourbar_loop.py"]                 # no temporary file left
    assert open(path, encoding="utf-8").read() == good           # the old module intact

    real_fdopen = os.fdopen

    class HalfFile:                               # writes half the module, then fails
        def __init__(self, fh):
            self.fh = fh

        def __enter__(self):
            return self

        def __exit__(self, *exc):
            self.fh.close()

        def write(self, text):
            self.fh.write(text[: len(text) // 2])
            raise OSError("disk full half way")

    monkeypatch.undo()
    monkeypatch.setattr(build_mod.os, "fdopen", lambda fd, *a, **k: HalfFile(real_fdopen(fd, *a, **k)))
    with pytest.raises(OSError, match="half way"):
        build_mod.build(model, str(out))
    with pytest.raises(OSError, match="half way"):
        build_mod.write_module(good, str(out / "other.py"))
    monkeypatch.undo()
    assert os.listdir(out) == ["fourbar_loop.py"]
    assert open(path, encoding="utf-8").read() == good


def test_cli_runtime_errors(tmp_path, capsys, monkeypatch):
    """Solving through the command line: a time without assembly, a NaN time, an unknown
    guess name: exit 1 and one message saying why (a headline, any details indented
    below it). (On the plain-Python tier: the messages
    come from the runtime, the statuses from the module's text; no compile of a fresh
    build.)"""
    from mechgen.cli import main
    monkeypatch.setenv("MECHGEN_TIER", "python")
    src = os.path.join(EXAMPLES, "quick_return_slider.py")
    out = str(tmp_path / "gen")
    cases = [
        (["solve", src, "--outdir", out, "-t", "0.249"], ["ConvergenceError", "t=0.249", "cannot assemble",
                                                   "0.2464863829"]),
        (["solve", src, "--outdir", out, "-t", "nan"], ["t must be finite"]),
        (["solve", src, "--outdir", out, "-t", "0.1", "--guess", "X9=1"], ["'X9'"]),
        (["solve", src, "--outdir", out, "-t", "0.1", "--guess", "X4=far"], ["X4=far"]),
        (["sweep", src, "--outdir", out, "--t0", "0", "--t1", "1", "-n", "101"],
         ["ConvergenceError", "lock (toggle) position at t≈0.2464863829"]),
    ]
    for argv, words in cases:
        assert main(argv) == 1, argv
        err = capsys.readouterr().err
        first, *details = err.splitlines()      # a headline, the details indented below
        assert first.startswith("mechgen: ") and all(d.startswith("  ") for d in details), err
        for word in words:
            assert word in err, (argv, word, err)


# -- issue 20: absurd sizes, exits, twins, names, binary files, argument names ---------------
FOURBAR = os.path.join(EXAMPLES, "fourbar.py")


def _mechgen(*argv, cwd=None):
    """``python -m mechgen ARGV`` as a user runs it: (returncode, stderr)."""
    env = dict(os.environ, PYTHONPATH=os.path.dirname(GENERATED))
    proc = subprocess.run([sys.executable, "-m", "mechgen", *argv], capture_output=True,
                          text=True, timeout=300, env=env, cwd=cwd)
    return proc.returncode, proc.stderr


def _one_line(rc, err, *words):
    assert rc != 0 and "Traceback" not in err, err
    assert err.startswith("mechgen: ") and err.count("\n") == 1, err
    for word in words:
        assert word in err, (word, err)


@pytest.mark.parametrize("argv,words", [
    (["-n", "100000000000000"], ["-n", "100,000,000,000,000", "memory", "limit"]),
    (["-n", "5", "--param", "a=0.5:1:step=1e-13"],
     ["--param a", "5,000,000,000,001 values", "memory", "limit"]),
    (["-n", "5", "--param", "a=0.5:1:n=99999999999999"], ["--param a", "memory"]),
], ids=["points", "step", "count"])
def test_cli_refuses_absurd_sizes_before_building(tmp_path, argv, words):
    out = tmp_path / "out"
    rc, err = _mechgen("sweep", FOURBAR, "--outdir", str(out), *argv)
    _one_line(rc, err, *words)
    assert not out.exists()                      # refused before the build


def test_runtime_refuses_absurd_sizes(qr):
    with pytest.raises(ValueError, match=r"^n: 100,000,000,000,000 sweep points .* limit"):
        qr.sweep(0.0, 1.0, 10 ** 14)
    with pytest.raises(ValueError, match=r"^n: .*sweep points"):
        qr.sweep(0.0, 1.0, 1e14)
    big = np.linspace(1.0, 2.0, 10 ** 5)
    with pytest.raises(ValueError, match=r"^params: 10,000,000,000 designs of 10 times each"):
        qr.sweep(0.0, 1.0, 10, params={"longitud": big, "velocidad": big})


@pytest.mark.parametrize("source,rc_expected,words", [
    ("from mechgen import Model\nm = Model('k')\nraise KeyboardInterrupt\n", 130,
     ["interrupted", "model.py:3"]),
    ("import sys\nfrom mechgen import Model\nm = Model('x')\nsys.exit(0)\n", 1,
     ["model.py:4", "sys.exit(0)"]),
    ("import sys\nsys.exit('bye')\n", 1, ["model.py:2", "sys.exit('bye')"]),
], ids=["KeyboardInterrupt", "exit0", "exit_text"])
def test_model_files_that_interrupt_or_exit(tmp_path, source, rc_expected, words):
    src = tmp_path / "model.py"
    src.write_text(source)
    out = tmp_path / "out"
    rc, err = _mechgen("build", str(src), "-o", str(out))
    _one_line(rc, err, *words)
    assert rc == rc_expected and not out.exists()


def test_two_models_of_one_name_name_both_lines(tmp_path):
    text = open(FOURBAR, encoding="utf-8").read().replace('Model("fourbar")', 'Model("twin")')
    text += '\nm = Model("twin")\n'            # the same variable: the first one is lost
    src = tmp_path / "twins.py"
    src.write_text(text)
    first = 1 + text.splitlines().index('m = Model("twin")')
    second = len(text.splitlines())
    out = tmp_path / "out"
    rc, err = _mechgen("build", str(src), "-o", str(out))
    _one_line(rc, err, f"twins.py:{second}", f"twins.py:{first}", "'twin'")
    assert not out.exists()
    with pytest.raises(mechgen.ModelError, match=f"twins.py:{first}"):
        mechgen.load_model(str(src))


def test_a_binary_file_is_not_a_model_file(tmp_path):
    src = tmp_path / "picture.py"
    src.write_bytes(b"\x89PNG\r\n\x1a\n\x00\x00\x00\rIHDR" + bytes(range(256)))
    out = tmp_path / "out"
    rc, err = _mechgen("build", str(src), "-o", str(out))
    _one_line(rc, err, "picture.py", "not a Python model file")
    assert "None" not in err and not out.exists()
    latin = tmp_path / "latin.py"
    latin.write_bytes("m = 'ñ'\n".encode("latin-1"))
    rc, err = _mechgen("build", str(latin), "-o", str(out))
    _one_line(rc, err, "latin.py", "not a Python model file")


def test_any_identifier_names_a_model(tmp_path):
    """docs/reference/model.md: any Python identifier may name a model; the module file carries it,
    numba's cache and the plain tier load it (the rocker angle against the closed form)."""
    from test_caches import th4_closed_form
    text = open(FOURBAR, encoding="utf-8").read().replace('Model("fourbar")',
                                                           'Model("biela_ñβ")')
    src = tmp_path / "biela.py"
    src.write_text(text, encoding="utf-8")
    out = tmp_path / "out"
    rc, err = _mechgen("build", str(src), "-o", str(out))
    assert rc == 0 and "Traceback" not in err, err
    path = out / "biela_ñβ.py"
    assert path.exists()
    for tier in ("python", "compiled"):
        value = mechgen.load(str(path), tier=tier).solve(0.1)["Th4"]
        assert min(abs(value - r) for r in th4_closed_form(0.1)) < 1e-12, tier
    with pytest.raises(mechgen.ModelError, match="keyword"):
        mechgen.Model("lambda")
    with pytest.raises(mechgen.ModelError, match="identifier"):
        mechgen.Model("two words")


@pytest.mark.parametrize("call,words", [
    (lambda m: mechgen.compile(42), ["compile(model)", "model must be", "int 42"]),
    (lambda m: m.solve(0.1, maxit=10 ** 30), ["maxit", "at most", "1000000000000000000000000000000"]),
    (lambda m: m.sweep(0, 1, 3, maxit=10 ** 30), ["maxit"]),
    (lambda m: m.solve(0.1, guess=["a"] * 9), ["guess", "9 numbers", "'a'"]),
    (lambda m: m.solve(0.1, guess="far"), ["guess", "'far'"]),
], ids=["compile_int", "maxit_solve", "maxit_sweep", "guess_strings", "guess_text"])
def test_arguments_are_named(qr, call, words):
    with pytest.raises((TypeError, ValueError)) as info:
        call(qr)
    for word in words:
        assert word in str(info.value), (word, str(info.value))


@pytest.mark.parametrize("name", ["cmath", "random", "numpy", "numba"])
def test_a_model_may_not_shadow_a_module(name):
    """A generated module named cmath would shadow the standard library's (numba imports
    it again when it loads its cache, and fails): refused at the Model line."""
    with pytest.raises(mechgen.ModelError, match=f"'{name}' is the name of a Python module"):
        mechgen.Model(name)
