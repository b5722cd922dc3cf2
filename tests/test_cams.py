"""Cams (Mech's CamToPoint1, CamToLine1, CamToCam1): their equations against the chain
rule, the emitted Φ, Φ_q, ν, γ against lambdify of the explicit profile expressions and
finite differences, the worked examples against their designed motion (cycloidal law,
eccentric circle), the periodic spline through a table, and the refusal of a profile on
which a follower loses contact geometry."""
from __future__ import annotations

import json
import os
import subprocess
import sys

import numpy as np
import pytest
import sympy as sp

import mechgen
from conftest import GENERATED, ROOT
from mechgen import Model, T, cos, pi, sin
from mechgen.model.library2d.profiles import ProfileFunction, periodic_spline


# -- small models, one per follower ------------------------------------------------------
def _cam_and_slider(name):
    m = Model(name)
    w = m.param("w", 1.3)
    g = m.ground("g", points=[(0, 0), (0.3, 0), (0.3, 1)])
    cam = m.body("cam", guess=(0, 0, 0.2))
    f = m.body("f", points=[(0, 0), (0, 1), (-1, 0), (1, 0)], guess=(0.3, 2.4, 0))
    m.revolute(g[1], cam[0])
    m.rotation_lock(cam, 0.2 + w * T)
    m.translate(g.line(2, 3), f.line(1, 2))
    return m, cam, f


def knife_model():
    m, cam, f = _cam_and_slider("knife")
    r0 = m.param("r0", 2.0)
    prof = m.profile("bump", polar=lambda th: r0 + 0.3 * cos(th))
    m.cam_to_point(cam, prof, f[1], contact="s", guess=1.4)
    return m


def roller_model():
    m, cam, f = _cam_and_slider("roller")
    R, e = m.param("R", 1.8), m.param("e", 0.4)
    prof = m.profile("disc", xy=lambda s: (e + R * cos(s), 0.9 * R * sin(s)))
    m.cam_to_point(cam, prof, f[1], contact="s", guess=1.4, radius=0.5)
    return m


def flat_model():
    m, cam, f = _cam_and_slider("flat")
    prof = m.profile("oval", xy=lambda s: (0.5 + 2 * cos(s), 1.5 * sin(s)))
    m.cam_to_line(cam, prof, f.line(3, 4), contact="s", guess=1.4)
    return m


def table_model():
    m, cam, f = _cam_and_slider("tabled")
    th = np.linspace(0, 2 * np.pi, 16, endpoint=False)
    r = 2 + 0.2 * np.cos(th) + 0.1 * np.sin(2 * th)
    prof = m.profile("table", points=np.column_stack([r * np.cos(th), r * np.sin(th)]))
    m.cam_to_point(cam, prof, f[1], contact="s", guess=1.4, radius=0.3)
    return m


def two_cams_model():
    m = Model("twocams")
    g = m.ground("g", points=[(0, 0), (4.0, 0)])
    c1 = m.body("c1", guess=(0, 0, 0.3))
    c2 = m.body("c2", guess=(4, 0, 0.1))
    m.revolute(g[1], c1[0])
    m.revolute(g[2], c2[0])
    m.rotation_lock(c1, 0.3 + 0.7 * T)
    p1 = m.profile("lobe1", xy=lambda s: (0.4 + 2 * cos(s), 1.6 * sin(s)))
    p2 = m.profile("lobe2", polar=lambda s: 1.6 + 0.1 * cos(2 * s))
    m.cam_to_cam(c1, p1, c2, p2, contact=("s1", "s2"), guess=(0.0, 3.1))
    return m


MODELS = {"knife": knife_model, "roller": roller_model, "flat": flat_model,
          "table": table_model, "twocams": two_cams_model}


def explicit(expr):
    """``expr`` with every profile function replaced by its explicit expression."""
    def sub(e):
        return e.func.diffed().subs(dict(zip((e.func.var,) + e.func.params, e.args)))
    return sp.sympify(expr).replace(lambda e: isinstance(e, ProfileFunction), sub)


@pytest.mark.parametrize("name", sorted(MODELS))
def test_phi_q_nu_gamma_follow_from_phi(name):
    """Φ_q = ∂Φ/∂q, ν = −Φ_t and Φ̈ = Φ_q q̈ − γ along q(T), by sympy's chain rule (the
    profile functions differentiate as their derivative functions, checked below)."""
    eq = MODELS[name]().equations()
    assert (eq.phi_q - eq.phi.jacobian(eq.q)).applyfunc(sp.expand) == sp.zeros(*eq.phi_q.shape)
    assert eq.nu == -eq.phi.diff(eq.T)
    funcs = [sp.Function(f"f_{s}")(eq.T) for s in eq.q]
    d2 = eq.phi.xreplace(dict(zip(eq.q, funcs))).diff(eq.T, 2)
    d2 = d2.subs({f.diff(eq.T, 2): qdd for f, qdd in zip(funcs, eq.qdd)})
    d2 = d2.subs({f.diff(eq.T): qd for f, qd in zip(funcs, eq.qd)}).subs(dict(zip(funcs, eq.q)))
    args = list(eq.q) + list(eq.qd) + list(eq.qdd) + [eq.T] + list(eq.params)
    rest = sp.lambdify(args, d2 - (eq.phi_q * eq.qdd - eq.gamma), "numpy")
    rng = np.random.default_rng(3)
    for _ in range(3):     # zero, numerically (1/sqrt powers need not cancel by expand)
        assert np.max(np.abs(np.asarray(rest(*rng.uniform(0.2, 1.5, len(args))),
                                        dtype=float))) < 1e-9


@pytest.mark.parametrize("name", sorted(MODELS))
def test_profile_derivatives_against_finite_differences(name):
    """Each profile function's derivative functions are the derivatives of its numbers."""
    eq = MODELS[name]().equations()
    funcs = {f.func for e in list(eq.gamma) for f in sp.sympify(e).atoms(ProfileFunction)}
    assert funcs
    s = np.linspace(0.05, 6.2, 41)
    h = 1e-5
    for f in funcs:
        if f.order == 0:
            continue
        lower = next(g for g in funcs | {f} if g.base == f.base and g.order == f.order - 1) \
            if any(g.base == f.base and g.order == f.order - 1 for g in funcs) else None
        if lower is None:
            continue
        p = [1.3] * len(f.params)
        fd = (lower._imp_(s + h, *p) - lower._imp_(s - h, *p)) / (2 * h)
        if name == "table" and f.order == 3:
            continue     # a cubic spline's third derivative jumps at the knots
        assert np.allclose(fd, f._imp_(s, *p), atol=1e-5 * (1 + np.max(np.abs(fd))))


def _emitted(model, tmp_path):
    """The module built from ``model``, its helpers and model functions as plain Python
    (no numba compile: the code as emitted)."""
    from mechgen.compiler.build import build
    from mechgen.runtime.loading.loader import import_path
    mod = import_path(build(model, str(tmp_path)))
    for name in dir(mod):
        fn = getattr(mod, name)
        if hasattr(fn, "py_func"):
            setattr(mod, name, fn.py_func)
    return mod


@pytest.mark.parametrize("name", sorted(MODELS))
def test_emitted_functions_against_lambdify_and_finite_differences(name, tmp_path):
    model = MODELS[name]()
    eq = model.equations()
    mod = _emitted(model, tmp_path)
    p = np.array(list(model.param_defaults.values()), dtype=float)
    subs = dict(zip(eq.params, p))
    args = list(eq.q) + list(eq.qd) + [eq.T]
    # the reference: sympy's lambdify of the equations, each profile function evaluated
    # by numpy from its explicit expression (ProfileFunction._imp_), not by the module
    ref = {k: sp.lambdify(args, eq[k].subs(subs), "numpy")
           for k in ("phi", "phi_q", "nu", "gamma")}
    n, m_ = len(eq.q), eq.phi.rows
    rng = np.random.default_rng(7)
    for _ in range(3):
        q, qd, t = rng.uniform(0.1, 2.0, n), rng.uniform(-1, 1, n), float(rng.uniform(0, 1))
        x = list(q) + list(qd) + [t]
        out = np.zeros(m_)
        mod.phi(q, t, p, out)
        assert np.allclose(out, np.ravel(ref["phi"](*x)), rtol=1e-12, atol=1e-12)
        J = np.zeros((m_, n))
        mod.phi_q(q, t, p, J)
        assert np.allclose(J, np.asarray(ref["phi_q"](*x), dtype=float), rtol=1e-12, atol=1e-12)
        h = 1e-6
        for j in range(n):
            up, dn = np.zeros(m_), np.zeros(m_)
            e = np.zeros(n)
            e[j] = h
            mod.phi(q + e, t, p, up)
            mod.phi(q - e, t, p, dn)
            assert np.allclose((up - dn) / (2 * h), J[:, j], atol=1e-7)
        nu = np.zeros(m_)
        mod.nu(q, t, p, nu)
        assert np.allclose(nu, np.ravel(ref["nu"](*x)), atol=1e-12)
        g = np.zeros(m_)
        mod.gamma(q, qd, t, p, g)
        assert np.allclose(g, np.ravel(ref["gamma"](*x)), rtol=1e-11, atol=1e-11)


# -- the worked examples, run from their committed modules ------------------------------
SCRIPT = r"""
import json, sys
import numpy as np
import mechgen
out = {}
mech = mechgen.load(sys.argv[1] + "/cam_cycloidal.py")
sw = mech.sweep(0.0, 1.0, 97, level="acceleration")
out["cyc"] = dict(t=sw.t.tolist(), y=sw["Y3"].tolist(), yd=sw["Y3d"].tolist(),
                  ydd=sw["Y3dd"].tolist(), phi=sw["phi"].tolist(), x=sw["X3"].tolist())
mech = mechgen.load(sys.argv[1] + "/cam_roller_arm.py")
sw = mech.sweep(0.0, 1.0, 97, level="acceleration")
out["arm"] = dict(t=sw.t.tolist(), th=sw["Th3"].tolist(), thd=sw["Th3d"].tolist(),
                  thdd=sw["Th3dd"].tolist(), phi=sw["phi"].tolist())
mech = mechgen.load(sys.argv[1] + "/cam_eccentric.py")
sw = mech.sweep(0.0, 1.0, 41, level="acceleration")
out["ecc"] = dict(t=sw.t.tolist(), y=sw["Y3"].tolist(), yd=sw["Y3d"].tolist(),
                  ydd=sw["Y3dd"].tolist())
print(json.dumps(out))
"""


@pytest.fixture(scope="module")
def example_sweeps():
    """Sweeps of the two cam examples from the committed modules, run with numba's JIT
    off (the emitted Python itself; the golden test keeps the modules current)."""
    env = dict(os.environ, NUMBA_DISABLE_JIT="1", PYTHONPATH=ROOT)
    run = subprocess.run([sys.executable, "-c", SCRIPT, GENERATED], env=env,
                         capture_output=True, text=True, timeout=300)
    assert run.returncode == 0, run.stderr[-3000:]
    return {k: {n: np.array(v) for n, v in d.items()}
            for k, d in json.loads(run.stdout.splitlines()[-1]).items()}


def cycloidal_law(phi, h=2.0, beta=2 * np.pi / 3):
    """s, s', s'' of the rise–dwell–return–dwell law of examples/cam_cycloidal.py."""
    phi = np.mod(phi, 2 * np.pi)
    s, v, a = np.zeros_like(phi), np.zeros_like(phi), np.zeros_like(phi)
    for lo, sign, base in ((0.0, 1, 0.0), (np.pi, -1, h)):
        r = (phi >= lo) & (phi < lo + beta)
        x = (phi[r] - lo) / beta
        s[r] = base + sign * h * (x - np.sin(2 * np.pi * x) / (2 * np.pi))
        v[r] = sign * h / beta * (1 - np.cos(2 * np.pi * x))
        a[r] = sign * 2 * np.pi * h / beta ** 2 * np.sin(2 * np.pi * x)
    s[(phi >= beta) & (phi < np.pi)] = h
    return s, v, a


def test_cycloidal_cam_gives_back_its_motion_law(example_sweeps):
    """The roller follower of a cam designed from a cycloidal rise–dwell–return–dwell
    reproduces s(φ), ω s'(φ), ω² s''(φ) over a whole turn."""
    sw = example_sweeps["cyc"]
    omega, d0 = 2 * np.pi, np.sqrt(5.0 ** 2 - 1.0 ** 2)
    s, v, a = cycloidal_law(omega * sw["t"])
    assert np.max(np.abs(sw["y"] - d0 - s)) < 1e-9
    assert np.max(np.abs(sw["yd"] - omega * v)) < 1e-9
    assert np.max(np.abs(sw["ydd"] - omega ** 2 * a)) < 1e-9
    assert np.max(np.abs(sw["x"] - 1.0)) < 1e-12
    # the contact parameter is the cam angle: the designed pitch point is the roller's centre
    assert np.max(np.abs(sw["phi"] - omega * sw["t"])) < 1e-9


def test_roller_arm_cam_gives_back_its_swing(example_sweeps):
    """examples/cam_roller_arm.py: the oscillating arm follows ψ0 − s(φ) of the cycloidal
    rise–dwell–return–dwell law it was designed from (swing 0.3), with ω s', ω² s''."""
    sw = example_sweeps["arm"]
    omega, psi0 = 2 * np.pi, 2.7
    s, v, a = cycloidal_law(omega * sw["t"], h=0.3)
    assert np.max(np.abs(sw["th"] - (psi0 - s))) < 1e-9
    assert np.max(np.abs(sw["thd"] + omega * v)) < 1e-9
    assert np.max(np.abs(sw["thdd"] + omega ** 2 * a)) < 1e-8
    assert np.max(np.abs(sw["phi"] - omega * sw["t"])) < 1e-9


def test_flat_follower_on_eccentric_circle_against_closed_form(example_sweeps):
    """Y3 = e sin θ + R, with θ = ω T, and its derivatives."""
    sw = example_sweeps["ecc"]
    e, R, w = 0.5, 2.0, 2 * np.pi
    th = w * sw["t"]
    assert np.max(np.abs(sw["y"] - (e * np.sin(th) + R))) < 1e-12
    assert np.max(np.abs(sw["yd"] - e * w * np.cos(th))) < 1e-12
    assert np.max(np.abs(sw["ydd"] + e * w * w * np.sin(th))) < 1e-10


# -- the spline through a table -----------------------------------------------------------
def test_periodic_spline_through_a_table():
    rng = np.random.default_rng(1)
    y = rng.uniform(-1, 1, 9)
    c = np.array(periodic_spline(y))
    h = 2 * np.pi / 9
    ends = [sum(c[i, k] * h ** k for k in range(4)) for i in range(9)]
    d1 = [c[i, 1] + 2 * c[i, 2] * h + 3 * c[i, 3] * h * h for i in range(9)]
    d2 = [2 * c[i, 2] + 6 * c[i, 3] * h for i in range(9)]
    assert np.allclose(c[:, 0], y)                              # through the points
    assert np.allclose(ends, np.roll(y, -1))                    # continuous, closing
    assert np.allclose(d1, np.roll(c[:, 1], -1))                # C1
    assert np.allclose(d2, np.roll(2 * c[:, 2], -1))            # C2


def test_table_profile_evaluates_like_its_emitted_code():
    m = table_model()
    prof = [c for c in m.constraints if c.kind == "cam_to_point"][0]
    fx = [f for f in sp.sympify(prof.exprs[0]).atoms(ProfileFunction)
          if f.func.__name__ == "table_x"][0].func
    from mechgen.compiler.codegen.printer import pycode
    s = sp.Symbol("s", real=True)
    code = pycode(fx.diffed().subs(fx.var, s))
    import math  # noqa: F401  (the code uses it)
    for v in (-7.0, 0.0, 0.3, 2.0, 6.2, 13.1):
        assert abs(eval(code, {"math": math, "s": v}) - float(fx._imp_(v))) < 1e-12
    th = np.linspace(0, 2 * np.pi, 16, endpoint=False)
    r = 2 + 0.2 * np.cos(th) + 0.1 * np.sin(2 * th)
    assert np.allclose(fx._imp_(th), r * np.cos(th))           # through the table


# -- loss of contact geometry ---------------------------------------------------------------
def test_a_cusp_is_refused_naming_cam_and_parameter():
    m, cam, f = _cam_and_slider("cusp")
    astroid = m.profile("astroid", xy=lambda s: (2 * cos(s) ** 3, 2 * sin(s) ** 3))
    n = len(m.coords)
    with pytest.raises(mechgen.ModelError, match=r"cam 'cam'.*cusp at s = "):
        m.cam_to_point(cam, astroid, f[1], contact="s", guess=1.4)
    assert len(m.coords) == n and "s" not in m._names      # the model as it was


def test_a_roller_larger_than_the_radius_of_curvature_is_refused():
    m, cam, f = _cam_and_slider("dented")
    dented = m.profile("dented", polar=lambda th: 2 + 0.4 * cos(3 * th))
    with pytest.raises(mechgen.ModelError, match=r"roller \(radius 1.5\) is larger than the "
                                                 r"radius of curvature .* at s = "):
        m.cam_to_point(cam, dented, f[1], contact="s", guess=1.4, radius=1.5)
    m.cam_to_point(cam, dented, f[1], contact="s", guess=1.4, radius=0.05)   # small: fine


def test_a_flat_face_on_a_concave_profile_is_refused():
    m, cam, f = _cam_and_slider("flatdent")
    dented = m.profile("dented", polar=lambda th: 2 + 0.4 * cos(3 * th))
    with pytest.raises(mechgen.ModelError, match=r"concave at s = .*flat-faced"):
        m.cam_to_line(cam, dented, f.line(3, 4), contact="s", guess=1.4)


def test_bad_arguments():
    m, cam, f = _cam_and_slider("bad")
    with pytest.raises(mechgen.ModelError, match="exactly one of"):
        m.profile("p", xy=lambda s: (cos(s), sin(s)), polar=lambda s: 1)
    with pytest.raises(mechgen.ModelError, match="must be a profile"):
        m.cam_to_point(cam, lambda s: (cos(s), sin(s)), f[1])
    with pytest.raises(mechgen.ModelError, match="not the profile parameter"):
        m.profile("q", xy=lambda s: (cos(s) * sp.Symbol("zz"), sin(s)))


# -- pictures -----------------------------------------------------------------------------
DRAW = r"""
import json, sys
import numpy as np
import matplotlib
matplotlib.use("Agg")
import mechgen
from matplotlib.patches import Polygon
from mechgen.plot import draw
mech = mechgen.load(sys.argv[1] + "/cam_eccentric.py")
out = []
d = draw(mech, 0.1, frame="pose")
for t in (0.1, 0.35):
    d.update(mech.solve(t))
    polys = [a for a in d.artists["cam"] if isinstance(a, Polygon)]
    big = max(polys, key=lambda a: len(a.get_xy()))
    xy = (big.get_transform() - d.ax.transData).transform(big.get_xy())
    out.append(dict(t=t, xy=xy.tolist()))
d.figure.savefig(sys.argv[2])
print(json.dumps(out))
"""


def test_the_profile_is_drawn_turning_with_its_cam(tmp_path):
    """The eccentric cam's outline, at two times, is the circle of radius R about the
    turned centre (e cos θ, e sin θ); the picture is written."""
    from mechgen.model.library2d.cams import PROFILE_POINTS
    from mechgen.plot.glyphs import cams as plot_cams
    assert plot_cams.PROFILE_POINTS == PROFILE_POINTS
    png = str(tmp_path / "cam.png")
    env = dict(os.environ, NUMBA_DISABLE_JIT="1", PYTHONPATH=ROOT)
    run = subprocess.run([sys.executable, "-c", DRAW, GENERATED, png], env=env,
                         capture_output=True, text=True, timeout=300)
    assert run.returncode == 0, run.stderr[-3000:]
    for frame in json.loads(run.stdout.splitlines()[-1]):
        th = 2 * np.pi * frame["t"]
        xy = np.array(frame["xy"])
        assert len(xy) >= PROFILE_POINTS
        r = np.hypot(xy[:, 0] - 0.5 * np.cos(th), xy[:, 1] - 0.5 * np.sin(th))
        assert np.allclose(r, 2.0, atol=1e-9)
    assert os.path.getsize(png) > 5000


def test_the_reference_documents_every_cam_kind():
    import re
    from mechgen.model.library2d.cams import CAM_KINDS, CamsMixin
    text = open(os.path.join(ROOT, "docs", "constraints.md"), encoding="utf-8").read()
    sections = dict(re.findall(r"^## (\w+)\n(.*?)(?=^## |\Z)", text, re.S | re.M))
    for kind in CAM_KINDS:
        assert f"`m.{kind}(" in sections[kind] and f"# 1 {kind}(" in sections[kind]
    for name in ("profile", "cam_to_point", "cam_to_line", "cam_to_cam"):
        assert getattr(CamsMixin, name).__doc__


def _pure(model, tmp_path):
    """``model`` built and loaded with every jitted function of its module replaced by
    its Python (no numba compile)."""
    return mechgen.load(_emitted(model, tmp_path))


def test_cam_on_cam_is_the_equivalent_four_bar(tmp_path):
    """Two eccentric circles touching (cam_to_cam) move as the four-bar whose coupler
    joins their centres with length r1 + r2."""
    def base(name):
        m = Model(name)
        g = m.ground("g", points=[(0, 0), (4.0, 0)])
        c1 = m.body("c1", points=[(1.0, 0)], guess=(0, 0, 0.3))
        c2 = m.body("c2", points=[(2.5, 0)], guess=(4, 0, 1.8))
        m.revolute(g[1], c1[0])
        m.revolute(g[2], c2[0])
        m.rotation_lock(c1, 0.3 + 2 * pi * T)
        return m, c1, c2
    m, c1, c2 = base("cams2")
    p1 = m.profile("circ1", xy=lambda s: (1.0 + 2.0 * cos(s), 2.0 * sin(s)))
    p2 = m.profile("circ2", xy=lambda s: (2.5 + 1.2 * cos(s), 1.2 * sin(s)))
    m.cam_to_cam(c1, p1, c2, p2, contact=("s1", "s2"), guess=(0.4, 2.0))
    ref, r1, r2 = base("bars2")
    ref.relative_distance(r1[1], r2[1], 3.2)     # a crank-rocker (Grashof)
    a = _pure(m, tmp_path / "a").sweep(0, 1, 21, level="acceleration")
    b = _pure(ref, tmp_path / "b").sweep(0, 1, 21, level="acceleration")
    for k in ("Th3", "Th3d", "Th3dd"):
        assert np.max(np.abs(a[k] - b[k])) < 1e-9, k


@pytest.mark.parametrize("side, turn, centre", [("outside", 1, 3.5), ("inside", 1, 2.5),
                                                 ("outside", -1, 3.5), ("inside", -1, 2.5)])
def test_the_roller_sits_on_the_side_asked_whichever_way_the_profile_runs(side, turn, centre):
    """A circle of radius 3 (run counter-clockwise or clockwise): a roller of radius 0.5
    outside it has its centre 3.5 from the centre, inside it 2.5."""
    m = Model("sides")
    g = m.ground("g", points=[(0, 0)])
    cam = m.body("cam", guess=(0, 0, 0))
    f = m.body("f", guess=(centre, 0, 0))
    m.revolute(g[1], cam[0])
    m.rotation_lock(cam, 0)
    prof = m.profile("ring", xy=lambda s: (3 * cos(turn * s), 3 * sin(turn * s)))
    m.cam_to_point(cam, prof, f[0], contact="s", radius=0.5, side=side)
    eq = m.equations()
    phi = sp.lambdify(list(eq.q), eq.phi[-2:, 0], "numpy")
    assert np.allclose(np.ravel(phi(0, 0, 0, centre, 0, 0, 0.0)), 0, atol=1e-14)
    assert not np.allclose(np.ravel(phi(0, 0, 0, 6 - centre, 0, 0, 0.0)), 0, atol=1e-3)


def test_a_periodic_profile_with_a_period_in_parameters(tmp_path):
    """The wrapped parameter's period is an argument of the profile's functions."""
    m, cam, f = _cam_and_slider("wrapped")
    P = m.param("P", 2 * np.pi)
    prof = m.profile("ring", xy=lambda s: (2 * cos(s), 2 * sin(s)), period=P, periodic=True)
    m.cam_to_point(cam, prof, f[1], contact="s", guess=1.4)
    eq = m.equations()
    assert P in set().union(*(e.free_symbols for e in eq.phi))
    mod = _emitted(m, tmp_path)
    out = np.zeros(eq.phi.rows)
    q = np.array([0, 0, 0.2, 0.3, 2.0, 0, 1.4 + 4 * np.pi])
    mod.phi(q, 0.0, np.array([1.3, 2 * np.pi]), out)
    ref = sp.lambdify(list(eq.q) + [eq.T] + list(eq.params), eq.phi, "numpy")
    assert np.allclose(out, np.ravel(ref(*q, 0.0, 1.3, 2 * np.pi)), atol=1e-12)
