"""Finite differences along solved trajectories, checked against ν and γ lambdified from
the symbolic equations (used by tests/test_mech2d.py for the 2D library's constraints)."""
import numpy as np
import sympy as sp


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


