"""Symbolic expansion: Φ, Φ_q, Φ_t, ν = −Φ_t and γ = −(Φ_q q̇)_q q̇ − 2 Φ_qt q̇ − Φ_tt."""
from __future__ import annotations

from dataclasses import dataclass, field
from functools import cached_property

import sympy as sp

from ..errors import ModelError
from .geometry import T
from .stages import staged_rows


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

    @cached_property
    def nonzeros(self) -> dict:
        """Φ_q's nonzero entries, {(i, j): entry} row by row (computed once: reading a
        large sympy Matrix cell by cell is slow)."""
        zero = sp.S.Zero
        return {(i, j): x for i, row in enumerate(self.phi_q.tolist())
                for j, x in enumerate(row) if x is not zero and x != 0}

    @cached_property
    def row_columns(self) -> tuple:
        """Per row of Φ_q, the columns of its nonzero entries (ascending)."""
        cols = [[] for _ in range(self.phi_q.rows)]
        for i, j in self.nonzeros:
            cols[i].append(j)
        return tuple(tuple(c) for c in cols)


def expand(model) -> Equations:
    where = getattr(model, "_where", None)
    if not model.coords:
        raise ModelError(f"model '{model.name}' has no coordinates: declare a body or a "
                         "coordinate", where=where)
    if not model.constraints:
        raise ModelError(f"model '{model.name}' has no constraints", where=where)
    exprs, labels, rows = [], [], []
    for number, k, expr, label in _rows(model):
        exprs.append(sp.sympify(expr))
        labels.append(label)
        rows.append((number, k))
    q = sp.Matrix(model.coords)
    qd_syms, qdd_syms = derivative_symbols(model.coords)
    qd, qdd = sp.Matrix(qd_syms), sp.Matrix(qdd_syms)
    phi = sp.Matrix(exprs)
    n = len(model.coords)
    index = {c: j for j, c in enumerate(model.coords)}
    # Differentiate each row only by the coordinates it holds: the work grows with the
    # number of nonzeros, not with rows × columns.
    phi_q = sp.zeros(len(exprs), n)
    phi_t = sp.zeros(len(exprs), 1)
    gamma = sp.zeros(len(exprs), 1)
    for i, e in enumerate(exprs):
        cols = sorted(index[s] for s in e.free_symbols if s in index)
        for j in cols:
            phi_q[i, j] = sp.diff(e, q[j])
        et = sp.diff(e, T)
        phi_t[i] = et
        # γ = −(Φ_q q̇)_q q̇ − 2 Φ_qt q̇ − Φ_tt
        v = sum((phi_q[i, j] * qd[j] for j in cols), sp.Integer(0))
        g = -sum((sp.diff(v, q[k]) * qd[k] for k in cols), sp.Integer(0))
        if et != 0:
            g -= 2 * sum((sp.diff(et, q[k]) * qd[k] for k in cols), sp.Integer(0))
            g -= sp.diff(et, T)
        gamma[i] = g
    return Equations(q=q, qd=qd, qdd=qdd, phi=phi, phi_q=phi_q, phi_t=phi_t, nu=-phi_t,
                     gamma=gamma, labels=tuple(labels), rows=tuple(rows),
                     params=tuple(model.param_symbols))


def _rows(model):
    """(constraint number, component, expression, label) per row of Φ; a model with stages
    joins its stage rows as Piecewise in T (mechgen.model.stages)."""
    if getattr(model, "stages", None):
        return staged_rows(model)
    return [(con.number, k, expr, label) for con in model.constraints
            for k, (expr, label) in enumerate(con.rows())]


def total_derivative(expr, coords, order: int = 1):
    """d^order/dT^order of an expression in q, q̇, (q̈) and T."""
    qd, qdd = derivative_symbols(coords)
    # each symbol once: where the coordinates come from several models (dt without a
    # model), one model's coordinate X2d may be another's velocity of X2, and both say
    # that X2d's rate is X2dd (counted twice, dt(X2d) read 2*X2dd)
    chain = {}
    for x, xd in list(zip(coords, qd)) + list(zip(qd, qdd)):
        chain.setdefault(x, xd)
    third = {s for s in qdd if s not in chain}

    def once(e):
        if any(s in third for s in e.free_symbols):
            raise ModelError("dt: the expression already holds accelerations; "
                             "a third derivative is not available")
        out = sp.diff(e, T)
        for x, xd in chain.items():
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


# -- numeric structure checks (compile side: numpy is fine here, the runtime never calls them)
def numeric_jacobian(eq, q_values, param_values, t=0.0):
    """Φ_q as a float array at the coordinates ``q_values`` (coordinate order), the
    parameter values ``param_values`` (parameter order) and time ``t``."""
    import numpy as np
    f = sp.lambdify((list(eq.q), list(eq.params), T), eq.phi_q, modules="numpy")
    return np.array(f(list(q_values), list(param_values), t), dtype=float).reshape(eq.phi_q.shape)


def rank_analysis(J, rtol=1e-9, share=1e-6):
    """(rank, dependent rows, free columns) of a Jacobian.

    Dependent rows are the equations that take part in a dependency (a left null vector
    of J); free columns the coordinates that move in a null vector of J, i.e. that the
    equations leave undetermined. ``share`` is the smallest participation (relative to the
    largest) that counts.
    """
    import numpy as np
    J = np.asarray(J, dtype=float)
    m, n = J.shape
    if not np.all(np.isfinite(J)):
        raise ModelError("the Jacobian is not finite at this configuration")
    u, s, vt = np.linalg.svd(J)
    tol = rtol * (s[0] if s.size and s[0] > 0 else 1.0)
    rank = int(np.sum(s > tol))
    rows, cols = [], []
    if rank < m:
        w = np.linalg.norm(u[:, rank:], axis=1)
        rows = [i for i in range(m) if w[i] > share * w.max()]
    if rank < n:
        w = np.linalg.norm(vt[rank:, :], axis=0)
        cols = [j for j in range(n) if w[j] > share * w.max()]
    return rank, rows, cols


def check_square(model, eq=None):
    """Raise ModelError when the model has fewer equations than coordinates.

    ``mechgen check`` reports such a model; a build refuses it, naming the coordinates
    the equations leave free at the guess. More equations than coordinates are allowed
    (redundant but consistent constraints, handled by the solver).
    """
    eq = model.equations() if eq is None else eq
    m, n = eq.phi.rows, len(eq.q)
    if m >= n:
        return
    free = []
    try:
        J = numeric_jacobian(eq, model.guess_vector(), list(model.param_defaults.values()))
        free = [str(eq.q[j]) for j in rank_analysis(J)[2]]
    except (ModelError, TypeError, ValueError, ZeroDivisionError):
        pass
    missing = n - m
    hint = "" if model.drivers else " The model has no driver (a constraint in T)."
    if getattr(model, "ground_body", 1) is None and getattr(model, "moving_bodies", None):
        hint += (" The model has no ground (m.ground(name, points=[...]), the fixed body): "
                 "nothing holds its bodies in place.")
    text = (f"model '{model.name}' is not square: {m} equations for {n} coordinates "
            f"({', '.join(map(str, eq.q))}); {missing} equation{'s' if missing > 1 else ''} "
            f"missing: add {'a driver or a constraint' if missing == 1 else 'drivers or constraints'}."
            + hint)
    if free:
        text += f" Left free at the guess: {', '.join(free)}."
    raise ModelError(text, where=getattr(model, "_where", None))
