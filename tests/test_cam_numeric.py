"""How a cam builds fast without changing what it builds: the memoised profile derivatives
(mechgen.model.dag) are the very expressions of sympy's ``diff``, the contact check's
numpy evaluation on the expression graph (mechgen.model.numpy_eval) gives lambdify's
numbers, and the check still refuses what it refused, with the same message, on a profile
defined piecewise (a motion law), the values checked against closed forms."""
from __future__ import annotations

import re

import numpy as np
import pytest
import sympy as sp

import mechgen
from mechgen import Model, Piecewise, cos, pi, sin
from mechgen.model.dag import Differentiator, replace
from mechgen.model.numpy_eval import evaluate
from mechgen.model.library2d.profiles import Profile, derivative, wrap

S = sp.Symbol("_prof_s", real=True)
A, B = sp.symbols("a b", real=True)


def sympy_diff(expr, var):
    """The reference: sympy's own diff, a Piecewise branch by branch (as profiles fold it)."""
    if isinstance(expr, sp.Piecewise):
        return sp.Piecewise(*[(sympy_diff(e, var), c) for e, c in expr.args], evaluate=False)
    return sp.diff(expr, var)


def _dented(th):
    """2 + 0.4 cos 3θ, written in two ways on the two halves of the turn (cos 3θ by the
    triple-angle formula on the second), as a profile defined piecewise would be."""
    return Piecewise((2 + 0.4 * cos(3 * th), th < pi),
                     (2 + 0.4 * (4 * cos(th) ** 3 - 3 * cos(th)), True))


def _profiles():
    """Profile coordinates of every kind the language makes: parametric, polar, a
    periodic Piecewise, the spline through a table, parameters in them."""
    m = Model("shapes")
    R, e = m.param("R", 1.8), m.param("e", 0.4)
    out = [m.profile("ellipse", xy=lambda s: (e + R * cos(s), 0.9 * R * sin(s))),
           m.profile("bump", polar=lambda th: R + 0.3 * cos(th)),
           m.profile("dented", polar=_dented, periodic=True),
           m.profile("table", points=[(2 * np.cos(t) + 0.1 * np.sin(2 * t), 1.5 * np.sin(t))
                                      for t in np.linspace(0, 2 * np.pi, 9, endpoint=False)])]
    exprs = [(p.x, p.var) for p in out] + [(p.y, p.var) for p in out]
    # functions of two arguments, powers, exp and log, the wrapped parameter
    exprs.append((sp.atan2(sp.sin(S), B + 2) + sp.exp(A * S) * sp.log(2 + sp.cos(S))
                  + sp.sqrt(3 + sp.sin(S)) ** 3 + S ** S + wrap(S, 2 * sp.pi) ** 2
                  + sp.tan(S / 7) - sp.asin(sp.sin(S) / 2), S))
    return exprs


PROFILES = _profiles()
# node kinds that the memoised rules leave to sp.diff (their derivatives hold Heaviside
# and DiracDelta: no numbers for them)
NONSMOOTH = [(sp.Abs(A * sp.cos(S)) + sp.Max(S, A * S ** 2) + sp.sign(S - B) * S, S)]


@pytest.mark.parametrize("k", range(len(PROFILES) + len(NONSMOOTH)))
def test_memoised_derivatives_are_sympys_own(k):
    """Orders 1..3: the same expression as sympy's diff, node for node (so the generated
    module's text and numbers do not change)."""
    expr, var = (PROFILES + NONSMOOTH)[k]
    d = Differentiator(var)

    def memoised(e):
        if isinstance(e, sp.Piecewise):
            return sp.Piecewise(*[(memoised(a), c) for a, c in e.args], evaluate=False)
        return d(e)

    ours = ref = expr
    for order in (1, 2, 3):
        ours, ref = memoised(ours), sympy_diff(ref, var)
        assert sp.srepr(ours) == sp.srepr(ref), order
    assert derivative(expr, var, 2) == sympy_diff(sympy_diff(expr, var), var)


def test_memoised_replace_is_xreplace():
    expr, var = PROFILES[2]
    e3 = derivative(expr, var, 3)
    x = sp.Symbol("x", real=True)
    rule = {var: x}
    assert sp.srepr(replace(e3, rule)) == sp.srepr(e3.xreplace(rule))


@pytest.mark.parametrize("k", range(len(PROFILES)))
def test_graph_evaluation_matches_lambdify(k):
    """The contact check's numpy evaluation against lambdify of the same expressions,
    orders 0..2, at random parameter values (and a node kind it hands to lambdify)."""
    expr, var = PROFILES[k]
    params = sorted(sp.sympify(expr).free_symbols - {var}, key=str)
    rng = np.random.default_rng(3 + k)
    s = rng.uniform(0.01, 10, 400)     # s**s: real for s > 0; tan(s/7): no pole
    values = {p: float(v) for p, v in zip(params, rng.uniform(0.5, 2.0, len(params)))}
    exprs = [derivative(expr, var, order) for order in range(3)]
    exprs.append(sp.Heaviside(var - 1.0) * expr)        # no numpy rule: lambdify's
    got = evaluate(exprs, {var: s, **values}, s.shape)
    for e, g in zip(exprs, got):
        ref = sp.lambdify([var] + params, e, modules="numpy")(s, *values.values())
        ref = np.broadcast_to(np.asarray(ref, dtype=float), s.shape)
        assert np.allclose(g, ref, rtol=1e-12, atol=1e-12 * (1 + np.max(np.abs(ref))))


# -- the check still refuses what it refused ----------------------------------------------
def _dented_cam():
    m = Model("dented_cam")
    g = m.ground("g", points=[(0, 0), (0, 1)])
    cam = m.body("cam", guess=(0, 0, 0))
    f = m.body("f", points=[(0, 0), (-1, 0), (1, 0)], guess=(0, 3.0, 0))
    m.revolute(g[1], cam[0])
    prof = m.profile("dented", polar=_dented, periodic=True)
    assert isinstance(prof, Profile) and prof.x.has(sp.Piecewise)
    return m, cam, f, prof


def _polar_radius_of_curvature(th):
    """Closed form for r = 2 + 0.4 cos 3θ: (r² + r'²)^(3/2) / (r² + 2 r'² − r r''),
    negative where the profile is concave."""
    r, r1, r2 = 2 + 0.4 * np.cos(3 * th), -1.2 * np.sin(3 * th), -3.6 * np.cos(3 * th)
    return (r * r + r1 * r1) ** 1.5 / (r * r + 2 * r1 * r1 - r * r2)


def test_a_roller_too_large_for_a_piecewise_profile_is_refused_as_before():
    """The hollows of r = 2 + 0.4 cos 3θ (θ = π/3, π, 5π/3) have a radius of curvature
    of 1.6³/3.2 = 1.28 (closed form): a roller of 1.3 rolling on the outside is refused
    at the hollow the samples hit exactly (θ = π), one of 1.25 is not."""
    assert abs(-_polar_radius_of_curvature(np.pi) - 1.28) < 1e-12
    m, cam, f, prof = _dented_cam()
    message = ("cam_to_point 2, cam 'cam': the roller (radius 1.3) is larger than the radius "
               "of curvature 1.28 of the profile 'dented' at s = 3.14159: its contact point "
               "jumps (contact geometry is lost); use a smaller roller or a flatter profile")
    with pytest.raises(mechgen.ModelError, match=re.escape(message)):
        m.cam_to_point(cam, prof, f[1], contact="s", guess=1.5, radius=1.3)
    assert "s" not in m.guess              # the refused constraint left nothing behind
    m.cam_to_point(cam, prof, f[1], contact="s", guess=1.5, radius=1.25)


def test_a_flat_face_on_a_piecewise_concave_profile_is_refused_as_before():
    """The flat face is refused at the first sample where the profile is concave; the
    place and the radius it names agree with the closed form."""
    m, cam, f, prof = _dented_cam()
    with pytest.raises(mechgen.ModelError) as err:
        m.cam_to_line(cam, prof, f.line(2, 3), contact="s", guess=1.5)
    text = str(err.value)
    got = re.search(r"cam_to_line 2, cam 'cam': the profile 'dented' is concave at "
                       r"s = (\S+) \(radius of curvature (\S+)\): a flat-faced follower "
                       r"would cut through it; a flat face needs a convex profile$", text)
    assert got, text
    step = 2 * np.pi / 2000                                      # the check's samples
    s = round(float(got.group(1)) / step) * step                  # printed to 6 digits
    assert abs(s - float(got.group(1))) < 1e-5
    rho = _polar_radius_of_curvature(s)
    assert rho < 0                                              # concave there
    assert _polar_radius_of_curvature(s - step) > 0             # and convex a sample before
    assert abs(abs(rho) - float(got.group(2))) <= 1e-5 * abs(rho)


def test_a_cusp_in_a_piecewise_profile_is_refused_as_before():
    """An astroid's first quadrant and the rest of it written apart: the cusp at s = 0 is
    named as before."""
    m, cam, f, _ = _dented_cam()
    astroid = m.profile("astroid", xy=lambda s: (
        Piecewise((2 * cos(s) ** 3, s < pi / 2), (2 * cos(s) * cos(s) ** 2, True)),
        2 * sin(s) ** 3), periodic=True)
    with pytest.raises(mechgen.ModelError, match=re.escape(
            "cam_to_point 2, cam 'cam': the profile 'astroid' has a cusp at s = 0 (its "
            "tangent vanishes or turns back there)")):
        m.cam_to_point(cam, astroid, f[1], contact="s", guess=1.4)


# -- the forward-mode code of a profile's derivatives ---------------------------------------
def _run(statements, values):
    """The value the statements store in _v, each statement evaluated with lambdify."""
    from mechgen.compiler.codegen.ir import Assign, Store
    env = dict(values)
    for st in statements:
        free = sorted(sp.sympify(st.expr).free_symbols, key=str)
        v = sp.lambdify(free, st.expr, modules="numpy")(*[env[f] for f in free])
        if isinstance(st, Assign):
            env[st.target] = v
        else:
            assert isinstance(st, Store) and st.lhs == "_v"
            return v
    raise AssertionError("no Store")


@pytest.mark.parametrize("k", range(len(PROFILES)))
def test_forward_mode_derivatives_against_sympys(k):
    """The statements a module's profile helper is printed from (orders 1..3, one program)
    against lambdify of sympy's own derivative, at random points and parameters."""
    from mechgen.compiler.functions.profile_derivatives import Derivatives
    expr, var = PROFILES[k]
    params = sorted(sp.sympify(expr).free_symbols - {var}, key=str)
    rng = np.random.default_rng(11 + k)
    values = {p: float(v) for p, v in zip(params, rng.uniform(0.5, 2.0, len(params)))}
    prog, ref = Derivatives(expr, var), expr
    for order in (1, 2, 3):
        ref = sympy_diff(ref, var)
        s = rng.uniform(0.01, 10, 50)
        want = sp.lambdify([var] + params, ref, modules="numpy")(s, *values.values())
        got = _run(prog.statements(order), {var: s, **values})
        assert np.all(np.abs(got - want) <= 1e-11 * (1 + np.abs(want))), order
