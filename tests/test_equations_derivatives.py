"""Φ_q, ν and γ against their definitions: Φ_q = ∂Φ/∂q, and along any trajectory q(t)
on which Φ(q(t), t) = 0,  d/dt Φ = Φ_q q̇ − ν = 0  and  d²/dt² Φ = Φ_q q̈ − γ = 0.

Checked twice: symbolically by the chain rule (q_i → q_i(T)), and numerically with finite
differences of a solved position trajectory (the runtime's crank-driven quick-return, and a
small model whose drivers couple T with the coordinates, so that Φ_qt and Φ_tt are not 0).
"""
import numpy as np
import pytest
import sympy as sp

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
    assert (d1 - (eq.phi_q * eq.qd - eq.nu)).applyfunc(sp.expand) == sp.zeros(eq.phi.rows, 1)
    assert (d2 - (eq.phi_q * eq.qdd - eq.gamma)).applyfunc(sp.expand) == sp.zeros(eq.phi.rows, 1)


def test_the_coupled_model_has_mixed_time_terms():
    eq = coupled_model().equations()
    phi_qt = eq.phi_t.jacobian(eq.q)
    assert any(e != 0 for e in phi_qt), "the test model must exercise Φ_qt"
    assert any(sp.diff(e, eq.T) != 0 for e in eq.phi_t), "and Φ_tt"


# -- finite differences along solved trajectories -------------------------------------
def numeric(eq, defaults):
    params = [defaults[str(p)] for p in eq.params]
    args = (list(eq.q), list(eq.qd), list(eq.qdd), eq.T)
    f = {k: sp.lambdify(args, eq[k].subs(dict(zip(eq.params, params))), "numpy")
         for k in ("phi", "phi_q", "nu", "gamma")}

    def call(key, q, t, qd=None, qdd=None):
        n = len(eq.q)
        qd = np.zeros(n) if qd is None else qd
        qdd = np.zeros(n) if qdd is None else qdd
        return np.array(f[key](list(q), list(qd), list(qdd), t), dtype=float).reshape(
            eq[key].shape)
    return call


def newton(call, q, t, tol=1e-13):
    for _ in range(50):
        r = call("phi", q, t).ravel()
        dq = np.linalg.solve(call("phi_q", q, t), -r)
        q = q + dq
        if np.max(np.abs(dq)) < tol:
            return q
    raise AssertionError(f"no convergence at t={t}")


H = 1e-3
STENCIL = (-2, -1, 0, 1, 2)


def derivatives(Q):
    """q̇ and q̈ at the centre of five samples spaced H (fourth-order central differences)."""
    qd = (Q[0] - 8 * Q[1] + 8 * Q[3] - Q[4]) / (12 * H)
    qdd = (-Q[0] + 16 * Q[1] - 30 * Q[2] + 16 * Q[3] - Q[4]) / (12 * H ** 2)
    return qd, qdd


def check_fd(call, t, Q):
    q = Q[2]
    qd, qdd = derivatives(Q)
    J = call("phi_q", q, t)
    nu = call("nu", q, t).ravel()
    gamma = call("gamma", q, t, qd=qd).ravel()
    scale = 1 + np.abs(J) @ (np.abs(qdd) + np.abs(qd) ** 2)
    # truncation error of the stencil ~ H⁴ q⁽⁵⁾, and the solver's tolerance / H²
    assert np.all(np.abs(J @ qd - nu) < 1e-5 * (1 + np.abs(J) @ np.abs(qd))), (t, J @ qd, nu)
    assert np.all(np.abs(J @ qdd - gamma) < 1e-4 * scale), (t, J @ qdd, gamma)
    return qd, qdd


def test_gamma_against_finite_differences_of_the_solved_quick_return(qr):
    """Positions from the compiled quick-return (the seed's model); ν and γ from sympy."""
    model = example_model("quick_return")
    eq = model.equations()
    call = numeric(eq, model.param_defaults)
    for t in (0.1, 0.15, 0.37, 0.62, 0.9):
        Q = [qr.solve(t + k * H).q for k in STENCIL]
        for k, qk in zip(STENCIL, Q):
            assert np.max(np.abs(call("phi", qk, t + k * H))) < 1e-10
        qd, qdd = check_fd(call, t, Q)
        if t == 0.15:   # and the seed's printed SolveMech[0.15, Solution->Acceleration]
            names = [str(s) for s in eq.q]
            assert abs(qd[names.index("Th3")] - 2.27897) < 2e-5
            assert abs(qd[names.index("X4")] + 18.7395) < 2e-4
            assert abs(qdd[names.index("Th3")] - 1.64018) < 1e-3
            assert abs(qdd[names.index("X4")] + 40.9024) < 1e-2


def test_gamma_against_finite_differences_with_time_coupled_drivers():
    model = coupled_model()
    eq = model.equations()
    call = numeric(eq, model.param_defaults)
    q = np.array(model.guess_vector())
    for t in (0.0, 0.4, 1.1):
        Q = []
        for k in STENCIL:
            q = newton(call, q, t + k * H)
            Q.append(q)
        check_fd(call, t, Q)
        q = Q[2]
        # a wrong γ (without the −2 Φ_qt q̇ − Φ_tt terms) would not pass
        qd, qdd = derivatives(Q)
        J = call("phi_q", q, t)
        phi_q_qd = (eq.phi_q * eq.qd).jacobian(eq.q) * eq.qd
        f = sp.lambdify((list(eq.q), list(eq.qd), eq.T),
                        (-phi_q_qd).subs(dict(zip(eq.params, [0.5]))), "numpy")
        partial = np.array(f(list(q), list(qd), t), dtype=float).ravel()
        assert np.max(np.abs(J @ qdd - partial)) > 1e-2
