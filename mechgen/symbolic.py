"""Symbolic expansion: Φ, Φ_q, Φ_t, ν = −Φ_t and γ = −(Φ_q q̇)_q q̇ − 2 Φ_qt q̇ − Φ_tt."""
from __future__ import annotations

from dataclasses import dataclass, field

import sympy as sp

from .errors import ModelError
from .geometry import T


def derivative_symbols(coords):
    """The velocity (``X2d``) and acceleration (``X2dd``) symbols of the coordinates."""
    qd = [sp.Symbol(f"{c.name}d", real=True) for c in coords]
    qdd = [sp.Symbol(f"{c.name}dd", real=True) for c in coords]
    return qd, qdd


@dataclass(frozen=True)
class Equations:
    """The expanded constraint system of a model, parameters kept as symbols.

    Fields are sympy Matrices (column vectors except ``phi_q``); ``labels[i]`` names
    the constraint that row i of Φ comes from.
    """
    q: sp.Matrix
    qd: sp.Matrix
    qdd: sp.Matrix
    phi: sp.Matrix
    phi_q: sp.Matrix
    phi_t: sp.Matrix
    nu: sp.Matrix
    gamma: sp.Matrix
    labels: tuple
    rows: tuple = field(repr=False)     # (constraint number, component) per row
    params: tuple = ()
    T: sp.Symbol = T

    def __getitem__(self, key):
        return getattr(self, key)

    def keys(self):
        return ("q", "qd", "qdd", "phi", "phi_q", "phi_t", "nu", "gamma")

    @property
    def shape(self):
        return self.phi_q.shape


def expand(model) -> Equations:
    if not model.coords:
        raise ModelError(f"model '{model.name}' has no coordinates: declare a body or a coordinate")
    if not model.constraints:
        raise ModelError(f"model '{model.name}' has no constraints")
    exprs, labels, rows = [], [], []
    for con in model.constraints:
        for k, (expr, label) in enumerate(con.rows()):
            exprs.append(sp.sympify(expr))
            labels.append(label)
            rows.append((con.number, k))
    q = sp.Matrix(model.coords)
    qd_syms, qdd_syms = derivative_symbols(model.coords)
    qd, qdd = sp.Matrix(qd_syms), sp.Matrix(qdd_syms)
    phi = sp.Matrix(exprs)
    phi_q = phi.jacobian(q)
    phi_t = phi.diff(T)
    # γ = −(Φ_q q̇)_q q̇ − 2 Φ_qt q̇ − Φ_tt, built row by row to keep it short
    gamma = []
    for i in range(phi.rows):
        row = phi_q.row(i)
        v = (row * qd)[0]
        g = -(sp.Matrix([v]).jacobian(q) * qd)[0]
        g -= 2 * (sp.Matrix([phi_t[i]]).jacobian(q) * qd)[0]
        g -= sp.diff(phi_t[i], T)
        gamma.append(g)
    return Equations(q=q, qd=qd, qdd=qdd, phi=phi, phi_q=phi_q, phi_t=phi_t, nu=-phi_t,
                     gamma=sp.Matrix(gamma), labels=tuple(labels), rows=tuple(rows),
                     params=tuple(model.param_symbols))


def total_derivative(expr, coords, order: int = 1):
    """d^order/dT^order of an expression in q, q̇, (q̈) and T."""
    qd, qdd = derivative_symbols(coords)
    chain = list(zip(coords, qd)) + list(zip(qd, qdd))
    third = {s for s in qdd}

    def once(e):
        if any(s in third for s in e.free_symbols):
            raise ModelError("dt: the expression already holds accelerations; "
                             "a third derivative is not available")
        out = sp.diff(e, T)
        for x, xd in chain:
            if x in e.free_symbols:
                out += sp.diff(e, x) * xd
        return out

    if isinstance(expr, sp.MatrixBase):
        result = expr
        for _ in range(order):
            result = result.applyfunc(once)
        return result
    result = sp.sympify(expr)
    for _ in range(order):
        result = once(result)
    return result
