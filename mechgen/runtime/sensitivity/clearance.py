"""A revolute joint's radial clearance (docs/reference/sensitivities.md): its two pin
centres apart by a vector e, |e| <= c, so that the revolute's two rows of Φ read
Φ_r(q) = e instead of 0; e is r(p1) − r(p2) of ``revolute(p1, p2)`` (the model's own
rows), the same in every frame.

Linear (``offset_derivatives``): Φ(q) − E e = 0 gives Φ_q dq/de = E (E the unit columns of
the revolute's rows); the rates follow as the parameters' do, e constant in time:
Φ_q Dq̇ = (ν − Φ_q q̇)_q Dq and Φ_q Dq̈ = (γ − Φ_q q̈)_q Dq + (γ − Φ_q q̈)_q̇ Dq̇, the right
sides read off the sensitivity module's velocity_rhs_p and acceleration_rhs_p, which are
linear in the Dq (Dq̇) they are given: their value at the direction less their value at
zero is the q-part alone. ``along`` does the same for any name a result's
``sensitivity`` answers (a declared output, a symbolic quantity): the chain rule with a
direction in q in place of dq/dp, the explicit ∂/∂p part taken away.

Nonlinear (``correct``): a Monte Carlo sample's configuration at each time solved again
by Newton on Φ(q) − E e = 0 from the configuration without the offset, its rates from
Φ_q q̇ = ν and Φ_q q̈ = γ (ν and γ do not hold e): one compiled loop taking the module's
phi, phi_q, nu and gamma as arguments.
"""
from __future__ import annotations

import copy

import numpy as np

from ...errors import MechgenError
from ...protocol import SING_RTOL
from ..forces.lookup import tables
from ..quantity import Quantity
from .companion import companion
from .solve import Sensitivities

AXES = ("x", "y")      # the components of a clearance's offset e


def revolutes(mech) -> list:
    """The names of the model's revolute joints (their name=, else their label)."""
    out = []
    for _, kind, label, _, _ in mech.module.CONSTRAINTS:
        if kind == "revolute":
            out.append(label.split(": revolute(", 1)[0] if ": revolute(" in label else label)
    return out


def revolute_rows(mech, name) -> tuple:
    """The two rows of Φ of the revolute joint ``name`` (its name=, label or number);
    a ValueError listing the revolutes where it names no revolute."""
    entry = None
    try:
        entry = tables(mech).find(name, mech)
    except ValueError:
        pass
    kinds = {label: kind for _, kind, label, _, _ in mech.module.CONSTRAINTS}
    if entry is None or kinds.get(entry[0]) != "revolute" or len(entry[1]) != 2:
        what = "no constraint" if entry is None else f"constraint {entry[0]!r}, not a revolute"
        have = ", ".join(map(repr, revolutes(mech))) or "none"
        raise ClearanceError(f"clearance {name!r}: model '{mech.name}' has {what}; a "
                             f"clearance belongs to a revolute joint (its revolutes: {have})")
    return entry[1]


class ClearanceError(MechgenError, ValueError):
    """A clearance that cannot be applied (not a revolute, a redundant build)."""


def _square(mech, what):
    if mech.m != mech.n:
        raise ClearanceError(f"{what}: '{mech.name}' has {mech.m} equations for {mech.n} "
                             "coordinates (a redundant build): a pin offset need not be "
                             "compatible with its other rows; give clearances on a square "
                             "build")


def _solve(J, B):
    """X with J X = B, or NaN where J (rows scaled to 1) has lost rank."""
    scale = np.abs(J).sum(axis=1, keepdims=True)
    scale[scale == 0] = 1.0
    s = np.linalg.svd(J / scale, compute_uv=False)
    if s.size == 0 or not np.all(np.isfinite(s)) or s[-1] <= SING_RTOL * s[0]:
        return np.full((J.shape[1], B.shape[1]), np.nan)
    return np.linalg.solve(J, B)


def offset_derivatives(mech, result, rows) -> tuple:
    """(Dq, Dq̇, Dq̈) with respect to the offsets' components: arrays (points, coordinates,
    2 × clearances) over a Sweep, (coordinates, 2 × clearances) at a Solution, column
    2 i + a for component a (x, y) of clearance i (``rows[i]``, its two rows of Φ); None
    above the result's level. NaN where Φ_q has lost rank."""
    _square(mech, "clearance")
    sweep = hasattr(result, "Q")
    Q = result.Q if sweep else result.q[None]
    QD = (result.QD if sweep else None if result.qd is None else result.qd[None])
    QDD = (result.QDD if sweep else None if result.qdd is None else result.qdd[None])
    ts = result.solved_t if sweep else np.array([result.t])
    level = 0 if QD is None else 1 if QDD is None else 2
    n, m, k2 = mech.n, mech.m, 2 * len(rows)
    E = np.zeros((m, k2))
    for i, (rx, ry) in enumerate(rows):
        E[rx, 2 * i], E[ry, 2 * i + 1] = 1.0, 1.0
    N = Q.shape[0]
    D = [np.full((N, n, k2), np.nan) if o <= level else None for o in range(3)]
    rates = _Rates(mech, level) if level else None
    J = np.empty((m, n))
    p = np.asarray(mech.p, dtype=np.float64)
    for k in range(N):
        q = np.ascontiguousarray(Q[k], dtype=np.float64)
        if not np.all(np.isfinite(q)):
            continue
        mech.module.phi_q(q, float(ts[k]), p, J)
        D[0][k] = _solve(J, E)
        if level >= 1 and np.all(np.isfinite(D[0][k])):
            qd = np.ascontiguousarray(QD[k], dtype=np.float64)
            D[1][k] = _solve(J, rates.velocity(q, qd, float(ts[k]), D[0][k]))
            if level >= 2:
                qdd = np.ascontiguousarray(QDD[k], dtype=np.float64)
                D[2][k] = _solve(J, rates.acceleration(q, qd, qdd, float(ts[k]), D[0][k],
                                                       D[1][k]))
    if not sweep:
        D = [None if d is None else d[0] for d in D]
    return tuple(D)


class _Rates:
    """The q-parts of the sensitivity module's right sides of Φ_q Dq̇ and Φ_q Dq̈."""

    def __init__(self, mech, level):
        npar = len(mech.parameter_names)
        if npar == 0:
            raise ClearanceError(f"clearance bands of rates need a parameter in "
                                 f"'{mech.name}' (the sensitivity module's right sides are "
                                 "written per parameter)")
        self.comp, _ = companion(mech)
        self.p = np.asarray(mech.p, dtype=np.float64)
        self.sel = np.zeros(1, dtype=np.int64)
        self.m, self.n, self.npar = mech.m, mech.n, npar

    def _columns(self, call, *dirs):
        """call(D..., out) at each column of the directions less call at zero."""
        k2 = dirs[0].shape[1]
        out = np.empty((self.m, k2))
        B = np.zeros((self.m, self.npar))
        zero = [np.zeros((self.n, self.npar)) for _ in dirs]
        call(*zero, B)
        base = B[:, 0].copy()
        for c in range(k2):
            Ds = []
            for d in dirs:
                Dc = np.zeros((self.n, self.npar))
                Dc[:, 0] = d[:, c]
                Ds.append(Dc)
            call(*Ds, B)
            out[:, c] = B[:, 0] - base
        return out

    def velocity(self, q, qd, t, D0):
        return self._columns(lambda DQ, B: self.comp.velocity_rhs_p(q, qd, t, self.p, DQ,
                                                                    self.sel, B), D0)

    def acceleration(self, q, qd, qdd, t, D0, D1):
        return self._columns(lambda DQ, DQD, B: self.comp.acceleration_rhs_p(
            q, qd, qdd, t, self.p, DQ, DQD, self.sel, B), D0, D1)


def along(result, name, directions, column):
    """∂name/∂(offset component ``column``) on ``result``: the chain rule through the
    result's own ``sensitivity`` machinery with ``directions`` (offset_derivatives'
    answer) in place of dq/dp, the explicit ∂name/∂p part taken away. A float or an
    array as result.sensitivity gives it."""
    mech = result.mechanism
    npar = len(mech.parameter_names)
    forces = result.__dict__.get("force_sensitivity")
    if forces is not None and isinstance(name, str) and forces.knows(name):
        raise ClearanceError(f"{name!r}: a driver's effort has no clearance band (its "
                             "multipliers' derivatives are the parameters' only)")
    quantity = Quantity(mech, name)
    if quantity.kind == "q":
        quantity.needs(len([d for d in directions if d is not None]) - 1)
        D = directions[quantity.order]
        return float(D[quantity.k, column]) if D.ndim == 2 else D[:, quantity.k, column].copy()
    if npar == 0:
        raise ClearanceError(f"the clearance band of {name!r} needs a parameter in "
                             f"'{mech.name}' (its derivatives are written per parameter)")

    def value(scale):
        full = []
        for d in directions:
            if d is None:
                full.append(None)
                continue
            F = np.zeros(d.shape[:-1] + (npar,))
            F[..., 0] = scale * d[..., column]
            full.append(F)
        fake = copy.copy(result)
        fake.__dict__.pop("force_sensitivity", None)
        fake.sensitivities = Sensitivities((mech.parameter_names[0],),
                                           np.zeros(1, dtype=np.int64), tuple(full))
        return fake.sensitivity(name, mech.parameter_names[0])

    hit, base = value(1.0), value(0.0)
    return np.asarray(hit) - np.asarray(base) if np.ndim(hit) else float(hit) - float(base)


# -- the nonlinear truth: Newton on Φ(q) − E e = 0 ------------------------------------------
def offsets_of(mech, rows, E) -> np.ndarray:
    """(designs, equations): each design's offsets E (designs, 2 × clearances) placed on
    the rows of its clearances."""
    OFF = np.zeros((E.shape[0], mech.m))
    for i, (rx, ry) in enumerate(rows):
        OFF[:, rx] = E[:, 2 * i]
        OFF[:, ry] = E[:, 2 * i + 1]
    return OFF


def correct(mech, ts, P, OFF, level, Q, QD, QDD, ok, tol=None, maxit=30):
    """Move the designs' points (Q, QD, QDD: (designs, points, coordinates), overwritten)
    onto Φ = OFF[d] (mechgen.runtime.sensitivity.offsets_kernel); ok[d] is cleared where a
    design's point does not converge. A module in the plain tier runs the same loop as
    Python (slow: a big Monte Carlo switches to the compiled tier in its design table)."""
    _square(mech, "clearance")
    from .offsets_kernel import correct_designs
    mod = mech.module
    zero = np.zeros((1, 1, mech.n))
    kernel = correct_designs if getattr(mod.phi, "py_func", None) is not None \
        else correct_designs.py_func
    kernel(mod.phi, mod.phi_q, mod.nu, mod.gamma, np.ascontiguousarray(ts, dtype=np.float64),
           np.ascontiguousarray(P, dtype=np.float64), OFF, int(level),
           float(mech.tol if tol is None else tol), int(maxit), Q,
           QD if QD is not None else zero, QDD if QDD is not None else zero, ok)
    return ok


__all__ = ["AXES", "ClearanceError", "along", "correct", "offset_derivatives", "offsets_of",
           "revolute_rows", "revolutes"]
