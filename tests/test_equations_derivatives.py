"""Φ_q, ν and γ against their definitions: Φ_q = ∂Φ/∂q, and along any trajectory q(t)
on which Φ(q(t), t) = 0,  d/dt Φ = Φ_q q̇ − ν = 0  and  d²/dt² Φ = Φ_q q̈ − γ = 0.

Checked twice: symbolically by the chain rule (q_i → q_i(T); the two sides compared at
random points to 30 digits), and numerically on the
generated modules (the committed crank-driven quick-return, and a small model whose drivers
couple T with the coordinates, so that Φ_qt and Φ_tt are not 0): their compiled ν and γ and
their solves against closed forms of the motion, differentiated by mpmath.
"""
import numpy as np
import pytest
import sympy as sp

from closed_forms import motion, quick_return
from conftest import example_model
from mechgen import Line, Model, T, cos, sin


def coupled_model():
    """Φ_qt ≠ 0 and Φ_tt ≠ 0: a driven angle between axes on two bodies, and a constraint
    mixing T with a coordinate."""
    m = Model("coupled")
    amp = m.param("amp", 0.5)
    ground = m.ground("ground", points=[(0, 0), (1, 0)])
    crank = m.body("crank", points=[(0, 0), (2, 0)], guess=(0, 0, 0.3))
    slider = m.body("slider", points=[(0, 0), (1, 0)], guess=(2.4, 0, 0))
    m.revolute(ground[1], crank[1])
    m.relative_angle(ground.line(1, 2), Line(ground[1], crank[2]), 0.3 + amp * sin(2 * T),
                     name="driven angle")
    m.translate(ground.line(1, 2), slider.line(1, 2))
    m.constraint(slider.x - 3 * cos(crank.th) - 0.5 * sin(T) * crank.th, name="coupled")
    return m


MODELS = {
    "quick_return": lambda: example_model("quick_return"),
    "quick_return_slider": lambda: example_model("quick_return_slider"),
    "fourbar": lambda: example_model("fourbar"),
    "fourbar_loop": lambda: example_model("fourbar_loop"),
    "coupled": coupled_model,
}


def chain_rule(eq):
    """d/dT Φ(q(T), T) and d²/dT² Φ(q(T), T), written back in q, q̇, q̈."""
    funcs = [sp.Function(f"f_{s}")(eq.T) for s in eq.q]
    phi_t = eq.phi.xreplace(dict(zip(eq.q, funcs)))
    d1, d2 = phi_t.diff(eq.T), phi_t.diff(eq.T, 2)
    back = {}
    for f, q, qd, qdd in zip(funcs, eq.q, eq.qd, eq.qdd):
        back[f.diff(eq.T, 2)] = qdd
    first = {f.diff(eq.T): qd for f, qd in zip(funcs, eq.qd)}
    plain = dict(zip(funcs, eq.q))
    return (d1.subs(first).subs(plain), d2.subs(back).subs(first).subs(plain))


@pytest.mark.parametrize("name", sorted(MODELS))
def test_phi_q_nu_gamma_follow_from_phi_by_the_chain_rule(name):
    eq = MODELS[name]().equations()
    assert (eq.phi_q - eq.phi.jacobian(eq.q)).applyfunc(sp.expand) == sp.zeros(*eq.phi_q.shape)
    assert eq.nu == -eq.phi.diff(eq.T)
    d1, d2 = chain_rule(eq)
    assert all(_zero(e) for e in d1 - (eq.phi_q * eq.qd - eq.nu))
    assert all(_zero(e) for e in d2 - (eq.phi_q * eq.qdd - eq.gamma))


def _zero(e):
    """Whether e is 0: at five random points of its symbols, to 30 digits (exact algebra
    would need expand, and over one denominator for the rational derivatives of
    relative_angle's atan2 row: seconds a row)."""
    import mpmath
    if e == 0:
        return True
    rng = np.random.default_rng(7)
    symbols = sorted(e.free_symbols, key=str)
    f = sp.lambdify(symbols, e, "mpmath")
    with mpmath.workdps(30):
        return all(abs(f(*[mpmath.mpf(v) for v in rng.uniform(-2.0, 2.0, len(symbols))]))
                   < 1e-20 for _ in range(5))


def test_the_coupled_model_has_mixed_time_terms():
    eq = coupled_model().equations()
    phi_qt = eq.phi_t.jacobian(eq.q)
    assert any(e != 0 for e in phi_qt), "the test model must exercise Φ_qt"
    assert any(sp.diff(e, eq.T) != 0 for e in eq.phi_t), "and Φ_tt"


# -- the generated module's ν, γ and solves against closed forms (mpmath) --------------------
def coupled_exact(t, amp=0.5):
    """coupled_model() in closed form: the crank about the origin at the driven angle, the
    slider on the x axis where its constraint puts it."""
    import mpmath as mp
    th = mp.mpf("0.3") + amp * mp.sin(2 * t)
    return [0, 0, th, 3 * mp.cos(th) + mp.mpf("0.5") * mp.sin(t) * th, 0, 0]


@pytest.fixture(scope="module")
def coupled_mech(tmp_path_factory):
    """coupled_model()'s generated module, run in the plain-Python tier (the module's own
    text, bit for bit the compiled code's: tests/test_tiers.py) to spare a numba build."""
    import mechgen
    return mechgen.compile(coupled_model(), outdir=str(tmp_path_factory.mktemp("coupled")),
                           tier="python")


CASES = {"quick_return": (quick_return, (0.1, 0.15, 0.37, 0.62, 0.9)),
         "coupled": (coupled_exact, (0.0, 0.4, 1.1, 2.3))}


def same_angles(a, b, angles):
    d = np.asarray(a, dtype=float) - b
    d[angles] = np.remainder(d[angles] + np.pi, 2 * np.pi) - np.pi
    return d


@pytest.mark.parametrize("name", sorted(CASES))
def test_module_nu_gamma_and_solves_against_the_closed_form(name, qr, coupled_mech):
    """The generated module's Φ, ν = −Φ_t and γ at the exact configuration: Φ = 0,
    Φ_q q̇ = ν, Φ_q q̈ = γ with q̇, q̈ differentiated from the closed form; then its solves
    (every method) give the closed form's q, q̇, q̈."""
    mech = qr if name == "quick_return" else coupled_mech
    fn, times = CASES[name]
    mod, p, n = mech.module, mech.p, len(mech.coordinates)
    angles = np.array([c.startswith("Th") for c in mech.coordinates])
    for t in times:
        q, qd, qdd = motion(fn, t)
        phi, J, nu, gamma = np.zeros(n), np.zeros((n, n)), np.zeros(n), np.zeros(n)
        mod.phi(q, t, p, phi)
        mod.phi_q(q, t, p, J)
        mod.nu(q, t, p, nu)
        mod.gamma(q, qd, t, p, gamma)
        scale = 1 + np.abs(q).max()
        assert np.abs(phi).max() < 1e-14 * scale, (t, phi)
        vscale = 1 + np.abs(J) @ np.abs(qd)
        ascale = 1 + np.abs(J) @ np.abs(qdd) + np.abs(qd).max() ** 2 * (1 + np.abs(q).max())
        assert np.all(np.abs(J @ qd - nu) < 1e-13 * vscale), (t, J @ qd, nu)
        assert np.all(np.abs(J @ qdd - gamma) < 1e-13 * ascale), (t, J @ qdd, gamma)
        for method in ("auto", "sorted", "full"):
            s = mech.solve(t, level="acceleration", method=method)
            assert np.abs(same_angles(s.q, q, angles)).max() < 1e-12 * scale, (t, method)
            assert np.abs(s.qd - qd).max() < 1e-11 * (1 + np.abs(qd).max()), (t, method)
            assert np.abs(s.qdd - qdd).max() < 1e-10 * (1 + np.abs(qdd).max()), (t, method)


def test_a_gamma_without_its_time_terms_would_not_pass(coupled_mech):
    """On the coupled model the −2 Φ_qt q̇ − Φ_tt terms of γ are large against the tolerance
    above: a γ without them fails there."""
    eq = coupled_model().equations()
    phi_q_qd = (eq.phi_q * eq.qd).jacobian(eq.q) * eq.qd
    f = sp.lambdify((list(eq.q), list(eq.qd), eq.T),
                    (-phi_q_qd).subs(dict(zip(eq.params, [0.5]))), "numpy")
    n = len(eq.q)
    for t in (0.0, 0.4, 1.1):
        q, qd, qdd = motion(coupled_exact, t)
        J, gamma = np.zeros((n, n)), np.zeros(n)
        coupled_mech.module.phi_q(q, t, coupled_mech.p, J)
        coupled_mech.module.gamma(q, qd, t, coupled_mech.p, gamma)
        partial = np.array(f(list(q), list(qd), t), dtype=float).ravel()
        assert np.max(np.abs(J @ qdd - partial)) > 1e-2
        assert np.max(np.abs(gamma - partial)) > 1e-2
