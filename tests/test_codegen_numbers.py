"""Numbers first: every function of a generated module against sympy.

For the four example models, each emitted function (phi, phi_q, nu, gamma, points, outputs,
outputs_d, outputs_dd) is compared with ``sympy.lambdify`` of quantities derived here
independently of the code generator (Φ_q as ``Φ.jacobian(q)``, ν as ``−∂Φ/∂T``, γ and the
output derivatives by differentiating along q(T) as sympy functions), at random points with
random parameter values; the linear solves (sorted and full) against ``numpy.linalg.solve``
of the lambdified system; the sorted position solve against the full Newton and the
lambdified residual. Each model is built three ways into tmp dirs — CSE on, CSE off, and
the ``--no-sort`` build — and checked compiled by numba (every model with CSE, the
quick-return in all three) and, in a subprocess, with ``NUMBA_DISABLE_JIT=1`` (all twelve).
Velocities and accelerations are checked against finite differences of solved positions.
"""
from __future__ import annotations

import json
import os
import re
import subprocess
import sys
import zlib

import numpy as np
import pytest

HERE = os.path.dirname(os.path.abspath(__file__))
if HERE not in sys.path:
    sys.path.insert(0, HERE)

from conftest import example_model  # noqa: E402

MODELS = ("quick_return", "quick_return_slider", "fourbar", "fourbar_loop")
VARIANTS = {"cse": {}, "nocse": {"cse": False}, "nosort": {"sort": False}}

# Where each model assembles, with the parameters it is solved at (None: the defaults).
# The slider-driven quick-return locks near T = ±0.246; fourbar_loop's crank turns only
# when omega is set.
SOLVE_AT = {
    "quick_return": dict(t=(0.0, 1.0), params=None),
    "quick_return_slider": dict(t=(-0.2, 0.2), params=None),
    "fourbar": dict(t=(0.0, 1.0), params=None),
    "fourbar_loop": dict(t=(0.0, 1.0), params={"omega": 2 * np.pi}),
}


# -- the sympy reference ------------------------------------------------------------------
class Reference:
    """Lambdified quantities of a model, derived without the code generator."""

    def __init__(self, model):
        import sympy as sp
        from mechgen.model.geometry import T
        self.model = model
        eq = model.equations()
        q, qd, qdd = list(eq.q), list(eq.qd), list(eq.qdd)
        params = [sym for sym, _ in model.params.values()]
        self.args = [*q, *qd, *qdd, T, *params]
        self.n = len(q)
        phi = eq.phi
        # q(T) as functions: total time derivatives by sympy's own chain rule
        funcs = [sp.Function(f"f_{s.name}")(T) for s in q]
        to_f = {**dict(zip(q, funcs)),
                **{a: f.diff(T) for a, f in zip(qd, funcs)},
                **{a: f.diff(T, 2) for a, f in zip(qdd, funcs)}}

        def back(expr):
            reps = {}
            for f, a, b, c in zip(funcs, q, qd, qdd):
                reps[f.diff(T, 3)] = sp.nan   # a third derivative: not available
                reps[f.diff(T, 2)] = c
                reps[f.diff(T)] = b
            expr = expr.subs(reps)
            return expr.subs(dict(zip(funcs, q)))

        def d_dt(expr, order):
            return back(sp.diff(sp.sympify(expr).subs(to_f), T, order))

        acc = [d_dt(phi[i], 2) for i in range(phi.rows)]
        gamma = sp.Matrix([-a.subs({s: 0 for s in qdd}) for a in acc])
        # Φ̈ = Φ_q q̈ − γ must hold identically: checks the split itself
        # (simplify where expand leaves sin/cos of sums, as a gear's rolling row does)
        rest = [sp.expand(acc[i] - (phi.jacobian(q).row(i) * sp.Matrix(qdd))[0] + gamma[i])
                for i in range(phi.rows)]
        assert all(r == 0 or sp.simplify(r) == 0 for r in rest)
        self.expr = {
            "phi": phi,
            "phi_q": phi.jacobian(sp.Matrix(q)),
            "nu": -phi.diff(T),
            "gamma": gamma,
        }
        outs = list(model.outputs.values())
        if outs:
            self.expr["outputs"] = sp.Matrix(outs)
            self.expr["outputs_d"] = sp.Matrix([d_dt(e, 1) for e in outs])
            self.expr["outputs_dd"] = sp.Matrix([d_dt(e, 2) for e in outs])
        self._fn = {k: sp.lambdify(self.args, v, modules="numpy") for k, v in self.expr.items()}

    def point_exprs(self, labels):
        """Global positions of points given by their labels, ``body[k]`` or ``body.at(x, y)``."""
        import sympy as sp
        out = []
        for label in labels:
            m = re.fullmatch(r"(\w+)\[(\d+)\]", label)
            if m:
                pt = self.model.bodies[m.group(1)][int(m.group(2))]
            else:
                m = re.fullmatch(r"(\w+)\.at\((.+), (.+)\)", label)
                assert m, f"cannot read point label {label!r}"
                pt = self.model.bodies[m.group(1)].at(sp.sympify(m.group(2)), sp.sympify(m.group(3)))
            out.append([pt.r[0], pt.r[1]])
        return sp.lambdify(self.args, sp.Matrix(out), modules="numpy")

    def __call__(self, name, q, qd, qdd, t, p):
        value = self._fn[name](*q, *qd, *qdd, t, *p)
        return np.array(value, dtype=np.float64)


def assert_close(got, want, what, rtol=1e-10):
    """Agreement to rounding: relative to the size of the largest entry of the result."""
    got, want = np.asarray(got, dtype=np.float64), np.asarray(want, dtype=np.float64)
    assert got.shape == want.reshape(got.shape).shape, (what, got.shape, want.shape)
    want = want.reshape(got.shape)
    scale = max(1.0, float(np.max(np.abs(want))) if want.size else 1.0)
    err = float(np.max(np.abs(got - want))) if got.size else 0.0
    assert err <= rtol * scale, f"{what}: max error {err:.3g} (scale {scale:.3g})\n{got}\n{want}"
    return err


def random_state(mech, rng, scale=1.0):
    """A random point (q, qd, qdd, t, p) around the guess, parameters perturbed too."""
    n = mech.n
    q = mech.guess + scale * rng.uniform(-1, 1, n)
    qd = 5 * rng.uniform(-1, 1, n)
    qdd = 20 * rng.uniform(-1, 1, n)
    t = rng.uniform(-1, 1)
    p = mech.p * (1 + 0.2 * rng.uniform(-1, 1, mech.p.size)) + 0.3 * rng.uniform(-1, 1, mech.p.size)
    return q, qd, qdd, t, p


def check_functions(ref, mech, rng, npoints=4):
    """phi, phi_q, nu, gamma, points, outputs* against the reference at random points."""
    mod = mech.module
    assert list(mod.PARAMETERS) == list(ref.model.params), "parameter order"
    assert list(mod.COORDINATES) == [str(s) for s in ref.model.equations().q], "coordinate order"
    npts = len(mod.POINTS)
    points_ref = ref.point_exprs([label for label, _ in mod.POINTS])
    errors = {}
    for _ in range(npoints):
        q, qd, qdd, t, p = random_state(mech, rng)
        m, n = mech.m, mech.n
        got = {}
        out = np.full(m, np.nan)
        mod.phi(q, t, p, out)
        got["phi"] = out.copy()
        J = np.full((m, n), np.nan)
        mod.phi_q(q, t, p, J)
        got["phi_q"] = J
        out = np.full(m, np.nan)
        mod.nu(q, t, p, out)
        got["nu"] = out.copy()
        out = np.full(m, np.nan)
        mod.gamma(q, qd, t, p, out)
        got["gamma"] = out.copy()
        for name in ("outputs", "outputs_d", "outputs_dd"):
            if name in ref.expr:
                out = np.full(len(mech.outputs), np.nan)
                getattr(mod, name)(q, qd, qdd, t, p, out)
                got[name] = out
        for name, value in got.items():
            err = assert_close(value, ref(name, q, qd, qdd, t, p), f"{mod.MODEL_NAME}.{name}")
            errors[name] = max(errors.get(name, 0.0), err)
        P = np.full((npts, 2), np.nan)
        mod.points(q, t, p, P)
        want = np.array(points_ref(*q, *qd, *qdd, t, *p), dtype=np.float64)
        errors["points"] = max(errors.get("points", 0.0),
                               assert_close(P, want, f"{mod.MODEL_NAME}.points"))
    return errors


def solved_states(mech, rng, count=4):
    """Solved configurations (q, qd, t) at random rows of a fine sweep over the model's
    valid range (starting at T = 0 on the model's own branch)."""
    lo, hi = SOLVE_AT[mech.name]["t"]
    sw = mech.sweep(0.0, hi, 41, level="velocity")
    rows = rng.choice(np.arange(1, len(sw)), size=count, replace=False)
    return [(sw.Q[k], sw.QD[k], sw.t[k]) for k in sorted(rows)]


def check_linear_solves(ref, mech, states, rng):
    """velocity_/acceleration_ sorted and full against numpy.linalg.solve of the reference."""
    mod, p, n = mech.module, mech.p, mech.n
    z = np.zeros(n)
    errors = {}
    for q, qd, t in states:
        J = ref("phi_q", q, z, z, t, p).reshape(mech.m, n)
        v_ref = np.linalg.solve(J, ref("nu", q, z, z, t, p).ravel())
        qd_rand = qd + rng.uniform(-1, 1, n)       # γ at any velocity, not only the solved one
        a_ref = np.linalg.solve(J, ref("gamma", q, qd_rand, z, t, p).ravel())
        kinds = ("sorted", "full") if mod.SORTED else ("full",)
        for kind in kinds:
            v = np.full(n, np.nan)
            assert getattr(mod, f"velocity_{kind}")(q, t, p, v) == 0
            a = np.full(n, np.nan)
            assert getattr(mod, f"acceleration_{kind}")(q, qd_rand, t, p, a) == 0
            errors[f"velocity_{kind}"] = max(errors.get(f"velocity_{kind}", 0.0),
                                             assert_close(v, v_ref, f"velocity_{kind}", 1e-9))
            errors[f"acceleration_{kind}"] = max(errors.get(f"acceleration_{kind}", 0.0),
                                                 assert_close(a, a_ref, f"acceleration_{kind}", 1e-9))
    return errors


def check_position(ref, mech, states, rng, other=None):
    """position_sorted (when built) and newton_full, from a perturbed solution, converge to
    the same configuration, which zeroes the reference Φ; ``other`` (a second module of the
    same model) must agree too."""
    mod, p, n = mech.module, mech.p, mech.n
    z = np.zeros(n)
    errors = {"position": 0.0}
    for q, _, t in states:
        start = q + 0.02 * rng.uniform(-1, 1, n)
        results = []
        solvers = [mod] + ([other] if other is not None else [])
        for m_ in solvers:
            names = ("position_sorted", "newton_full") if m_.SORTED else ("newton_full",)
            for fn in names:
                x = start.copy()
                info = np.zeros(4)
                status = getattr(m_, fn)(x, t, p, 1e-12, 1e-12, 50, info)
                assert status == 0, (m_.MODEL_NAME, fn, t, status)
                res = float(np.max(np.abs(ref("phi", x, z, z, t, p))))
                assert res < 1e-11, (fn, t, res)
                results.append(x)
        for x in results[1:]:
            errors["position"] = max(errors["position"], assert_close(x, results[0], "position", 1e-9))
        assert_close(results[0], q, "position vs sweep", 1e-9)
    return errors


def check_module(ref, mech, seed, states_from=None, other=None):
    """Every check on one loaded module; returns the largest error per function.
    Solved states come from ``states_from`` (a Mechanism of the same model; default
    ``mech``) so that a variant need not compile its sweep."""
    rng = np.random.default_rng(seed)
    params = SOLVE_AT[mech.name]["params"] or {}
    solving = mech.with_params(**params)
    errors = check_functions(ref, mech, rng)
    states = solved_states((states_from or mech).with_params(**params), rng)
    errors.update(check_linear_solves(ref, solving, states, rng))
    errors.update(check_position(ref, solving, states, rng, other))
    return errors


# -- fixtures -------------------------------------------------------------------------------
@pytest.fixture(scope="session")
def references():
    cache = {}

    def get(name):
        if name not in cache:
            cache[name] = Reference(example_model(name))
        return cache[name]
    return get


FIXTURE = {"quick_return": "qr", "quick_return_slider": "qr_slider", "fourbar": "fourbar",
           "fourbar_loop": "fourbar_loop"}


@pytest.fixture
def committed(request):
    """name -> the Mechanism of generated/<name>.py (conftest's session fixtures, whose numba
    cache the other tests share). test_generated_golden proves those files are what the
    generator emits today."""
    return lambda name: request.getfixturevalue(FIXTURE[name])


@pytest.fixture(scope="session")
def built(tmp_path_factory, references):
    """(name, variant) -> Mechanism, built into a tmp dir once per session."""
    import mechgen
    from mechgen.compiler.build import build
    cache = {}

    def get(name, variant):
        key = (name, variant)
        if key not in cache:
            outdir = tmp_path_factory.mktemp(f"{name}_{variant}")
            path = build(references(name).model, str(outdir), **VARIANTS[variant])
            cache[key] = mechgen.load(path)
        return cache[key]
    return get


# -- the tests ------------------------------------------------------------------------------
# Compiled by numba: every model with CSE, and the CSE-off and --no-sort builds of the
# quick-return (body coordinates, a torn block). The jit-less run below covers every model
# in every variant (compiling all twelve would cost ~1 min of numba time).
JITTED = [(name, "cse") for name in MODELS] + [("quick_return", "nocse"),
                                                ("quick_return", "nosort")]


@pytest.mark.parametrize("name,variant", JITTED)
def test_module_matches_lambdify(name, variant, references, built, committed):
    mech = built(name, variant)
    assert mech.module.SORTED == (variant != "nosort")
    other = built(name, "cse").module if variant == "nosort" else None
    errors = check_module(references(name), mech, seed=zlib.crc32(f"{name}/{variant}".encode()),
                          states_from=committed(name), other=other)
    expected = {"phi", "phi_q", "nu", "gamma", "points", "position"}
    expected |= {"velocity_full", "acceleration_full"}
    if variant != "nosort":
        expected |= {"velocity_sorted", "acceleration_sorted"}
    if references(name).model.outputs:
        expected |= {"outputs", "outputs_d", "outputs_dd"}
    assert expected <= set(errors)


def test_variants_print_differently(references):
    """The variants really differ in text (else the matrix above would prove little)."""
    from mechgen.compiler.build import render
    model = references("quick_return").model
    texts = {v: render(model, **kw) for v, kw in VARIANTS.items()}
    assert "_t0" in texts["cse"] and "_t0 = " not in texts["nocse"].split("def phi(")[1].split("@njit")[0]
    stub = re.compile(r'^def position_sorted\(.*\):\n    """Not built in this module', re.M)
    assert "def position_sorted" in texts["cse"] and not stub.search(texts["cse"])
    assert stub.search(texts["nosort"])         # not built: a stub in its place


@pytest.mark.parametrize("name", ("quick_return",))
def test_solves_agree_across_variants(name, built):
    """Mechanism.solve on the three builds gives the same answer (tolerance 1e-12)."""
    lo, hi = SOLVE_AT[name]["t"]
    params = SOLVE_AT[name]["params"] or {}
    mechs = {v: built(name, v).with_params(**params) for v in VARIANTS}
    for t in np.linspace(0.0, hi, 4)[1:]:
        ref = mechs["cse"].solve(t, level="acceleration", tol=1e-12)
        start = np.round(ref.q, 2)          # the same start, near the solution, for all
        sols = {v: m.solve(t, guess=start, level="acceleration", tol=1e-12)
                for v, m in mechs.items()}
        for v, s in sols.items():
            for attr in ("q", "qd", "qdd"):
                assert_close(getattr(s, attr), getattr(ref, attr), f"{name} {v} {attr} t={t}", 1e-9)
        assert sols["nosort"].method == "full"


_JITLESS = r"""
import json, os, sys
sys.path.insert(0, {tests!r})
import numba
assert numba.config.DISABLE_JIT, "NUMBA_DISABLE_JIT did not take"
import mechgen
from mechgen.compiler.build import build
import test_codegen_numbers as T
report = {{}}
for name in T.MODELS:
    ref = T.Reference(T.example_model(name))
    mechs = {{}}
    for variant in ("cse", "nocse", "nosort"):
        path = build(ref.model, os.path.join({outdir!r}, variant), **T.VARIANTS[variant])
        mechs[variant] = mech = mechgen.load(path)
        assert not hasattr(mech.module.phi, "py_func"), "phi is still a numba dispatcher"
        report[name + "/" + variant] = T.check_module(
            ref, mech, seed=7, states_from=mechs["cse"],
            other=mechs["cse"].module if variant == "nosort" else None)
print(json.dumps(report))
"""


def test_functions_without_jit(tmp_path):
    """The same checks with NUMBA_DISABLE_JIT=1: the generated code is correct Python as
    written, not only after numba's compilation."""
    script = tmp_path / "jitless.py"
    script.write_text(_JITLESS.format(tests=HERE, outdir=str(tmp_path / "out")))
    env = dict(os.environ, NUMBA_DISABLE_JIT="1")
    proc = subprocess.run([sys.executable, str(script)], capture_output=True, text=True,
                          env=env, timeout=600)
    assert proc.returncode == 0, proc.stderr[-3000:]
    report = json.loads(proc.stdout.strip().splitlines()[-1])
    assert set(report) == {f"{n}/{v}" for n in MODELS for v in VARIANTS}
    for key, errors in report.items():
        need = {"phi", "phi_q", "nu", "gamma", "points", "velocity_full", "acceleration_full",
                "position"}
        if not key.endswith("nosort"):
            need |= {"velocity_sorted", "acceleration_sorted"}
        assert need <= set(errors), key


# -- finite differences along a sweep ---------------------------------------------------
FD_CASES = [
    ("quick_return", None),
    ("quick_return", {"X4": 1.0}),        # the second assembly mode
    ("quick_return_slider", None),
    ("fourbar", None),
    ("fourbar", {"Th3": -1.1, "Th4": -2.2}),
    ("fourbar_loop", None),
]


@pytest.mark.parametrize("name,guess", FD_CASES)
def test_derivatives_match_finite_differences(name, guess, committed):
    """q̇ and q̈ from the linear solves against 4th-order central differences of solved
    positions (and of solved velocities), h = 1e-3, at 25 times along a sweep.

    Tolerance: the stencils' truncation errors are h⁴/30·|q⁽⁵⁾| and h⁴/90·|q⁽⁶⁾|; for these
    mechanisms (drive frequency 2π, lengths ≤ 12, fast-return amplification ≲ 3) the
    derivatives grow like (3·2π)^k·10, giving ≲ 3e-6 of the velocity scale. Rounding of
    positions solved to ~1e-15 adds ~1e-15·10/h ≈ 1e-11 (first derivative) and ~1e-7
    (second, from positions). So 1e-5 relative to each quantity's scale; an error in ν or
    γ (a sign, a missing term) is O(1) relative."""
    lo, hi = SOLVE_AT[name]["t"]
    params = SOLVE_AT[name]["params"] or {}
    mech = committed(name).with_params(**params)
    h = 1e-3
    base = np.linspace(lo + 3 * h, hi - 3 * h, 25)
    offsets = np.array([-2, -1, 0, 1, 2]) * h
    times = (base[:, None] + offsets[None, :]).ravel()
    start = mech.solve(times[0], guess=guess)
    sw = mech.sweep(None, None, None, times=times, guess=start, level="acceleration")
    assert len(sw) == times.size
    n = mech.n
    Q = sw.Q.reshape(base.size, 5, n)
    QD = sw.QD.reshape(base.size, 5, n)
    QDD = sw.QDD.reshape(base.size, 5, n)
    c1 = np.array([1, -8, 0, 8, -1]) / (12 * h)
    c2 = np.array([-1, 16, -30, 16, -1]) / (12 * h * h)
    fd_v = np.einsum("j,kjn->kn", c1, Q)
    fd_a_from_v = np.einsum("j,kjn->kn", c1, QD)
    fd_a_from_q = np.einsum("j,kjn->kn", c2, Q)
    v, a = QD[:, 2], QDD[:, 2]
    vscale = max(1.0, np.max(np.abs(v)))
    ascale = max(1.0, np.max(np.abs(a)))
    assert np.max(np.abs(fd_v - v)) <= 1e-5 * vscale, np.max(np.abs(fd_v - v))
    assert np.max(np.abs(fd_a_from_v - a)) <= 1e-5 * ascale, np.max(np.abs(fd_a_from_v - a))
    assert np.max(np.abs(fd_a_from_q - a)) <= 1e-5 * ascale, np.max(np.abs(fd_a_from_q - a))
    # the motion is not trivial: the test would notice a zero velocity
    assert vscale > 1.0 and ascale > 1.0
    if mech.outputs:
        outs = sw.outputs(0).reshape(base.size, 5, -1)
        outs_d = sw.outputs(1).reshape(base.size, 5, -1)[:, 2]
        outs_dd = sw.outputs(2).reshape(base.size, 5, -1)[:, 2]
        fd = np.einsum("j,kjn->kn", c1, outs)
        assert np.max(np.abs(fd - outs_d)) <= 1e-5 * max(1.0, np.max(np.abs(outs_d)))
        fd = np.einsum("j,kjn->kn", c2, outs)
        assert np.max(np.abs(fd - outs_dd)) <= 1e-5 * max(1.0, np.max(np.abs(outs_dd)))
