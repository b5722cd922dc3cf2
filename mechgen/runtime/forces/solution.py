"""One solved configuration's forces: ``mech.solve(t, level="static"|"dynamic")``, its
multipliers, driver efforts and reactions (mechgen.runtime.forces)."""
from __future__ import annotations

import warnings
from operator import mul as _mul

import numpy as np

from ...errors import RedundancyWarning, SingularError
from ...protocol import SING_RTOL
from ..kinematics.entry import module_attr
from ..guards import all_finite
from ..kinematics.solving import solve
from ..results import Solution
from .contact import contact_labels, contact_values
from .directions import singular_error
from .lookup import _constraints_of, loads_guarded, tables
from .points import MISSING, by_blocks, svd_solve, written_out

# -- one point ----------------------------------------------------------------------------
def force_terms(mech, q, qd, qdd, t) -> np.ndarray:
    """(3, n): Q_a, Q_c, I at one point (zeros for a model without mass or loads)."""
    out = np.zeros((3, mech.n))
    if tables(mech).forces:
        mech.module.force_terms(q, qd, qdd, float(t), mech.p, out)
    return out


def multipliers(mech, q, t, rhs, level="dynamic"):
    """(λ, labels of the rows whose λ is not unique) solving Φ_qᵀ λ = rhs at (q, t), the
    minimum-norm λ where Φ_q has dependent rows; SingularError where there is none. A
    square Φ_q whose pivot ratio (the kinematic solves' measure) is at least SING_RTOL
    is solved directly; any other by the SVD."""
    J = mech.jacobian(q, t)
    if mech.m == mech.n and mech.pivot_ratio(q, t) >= SING_RTOL:
        lam = np.linalg.solve(J.T, rhs)
        if np.all(np.isfinite(lam)):
            return lam, ()
    return svd_multipliers(mech, J, q, t, rhs, level)


def svd_multipliers(mech, J, q, t, rhs, level):
    """multipliers() by the SVD of Φ_q = J (points.svd_solve): the minimum-norm λ and the
    labels of the rows whose λ is not unique; SingularError where Φ_qᵀλ = rhs has no
    solution."""
    lam, rank, dependent, consistent = svd_solve(J, rhs)
    labels = mech.constraint_labels
    dependent = tuple(labels[i] for i in dependent)
    if not consistent:
        where = "; ".join(dependent) or "(could not tell which)"
        raise SingularError(
            f"model '{mech.name}': no {level} force balance Φ_qᵀλ = Q at t={t:.6g}: Φ_q has "
            f"rank {rank} for {mech.n} coordinates (a lock or toggle position: the loads "
            f"would move it); the constraints involved: {where}", t=t, constraints=dependent,
            level=level, q=np.array(q))
    return lam, dependent


def _effort(tab, mech, name, lam_rows, factors):
    """The driver's effort from its rows' λ and factors (a row of DRIVER_ROWS each)."""
    label, rows, driver = tab.constraint(name, mech)
    if not driver:
        raise ValueError(f"constraint {label!r} of model '{mech.name}' is not a driver "
                         "(its equations do not hold T)")
    if not tab.forces:           # no mass, no loads: every λ is zero
        return np.zeros(lam_rows.shape[:-1])
    if any(r not in tab.driver_rows for r in rows):
        raise ValueError(f"driver {label!r}: its effort is not defined (no driver row)")
    cols = [tab.driver_rows.index(r) for r in rows]
    f = factors[..., cols]
    if np.any(np.isnan(f)):
        raise ValueError(f"driver {label!r}: its effort is not defined for this form of "
                         "equation (only g(q) − f(T) and relative_distance drivers, of one "
                         "row in T: a driver of several, such as a point moved along a "
                         "path, has no single driven quantity; its force on a body is "
                         f"reaction({label!r}, on=body))")
    return np.sum(lam_rows[..., list(rows)] * f, axis=-1)


def effort(mech, name, lam_rows, factors):
    """A driver's effort (its rows' λ times their factors, summed; as Solution.driver
    signs it) from λ and DRIVER_ROWS' factors (a leading axis of points allowed): linear
    in each, so that its derivative is effort(dλ, factors) + effort(λ, dfactors)."""
    return _effort(tables(mech), mech, name, lam_rows, factors)


def warn_shared(mech, name, indeterminate, stacklevel):
    """A RedundancyWarning where driver ``name`` is among the constraints whose
    multipliers are not unique (two drivers that prescribe one motion, say): its effort
    is then the minimum-norm share of what the drivers together apply, not the effort."""
    label = tables(mech).constraint(name, mech)[0]
    if label in indeterminate:
        others = "; ".join(c for c in indeterminate if c != label)
        warnings.warn(f"model '{mech.name}': driver {label!r} is redundant with other "
                      f"constraints ({others}): its effort is not unique, and the value "
                      "given is the minimum-norm share (what the drivers apply together, "
                      "their power, is exact)", RedundancyWarning, stacklevel=stacklevel)


def _reaction(tab, mech, name, on, about, J, lam, q, point_xy):
    """(fx, fy, moment) that constraint ``name`` applies to body ``on`` at one point;
    the moment about the body's origin, or about ``about``."""
    rows = list(tab.constraint(name, mech)[1])
    gen = -J[rows].T @ lam[rows]         # the constraint's generalized force on the system
    xy = None if about is None else point_xy(about)[None]
    return on_body(tab, mech, on, gen[None], q[None], xy)[0]


def on_body(tab, mech, on, gen, Q, about_xy=None):
    """(N, 3): (fx, fy, moment) on body ``on`` at N points from a constraint's generalized
    forces ``gen`` (N, coordinates) at the configurations Q; the moment about the body's
    origin, or about the points ``about_xy`` (N, 2)."""
    body = tab.body(on, mech)
    N = gen.shape[0]
    if body is None:                     # the ground: Newton's third law, about the origin
        f = np.zeros((N, 2))
        moment = np.zeros(N)
        for idx in tab.bodies.values():
            if idx is None:
                continue
            fb = gen[:, list(idx[:2])]
            f -= fb
            moment -= gen[:, idx[2]] + Q[:, idx[0]] * fb[:, 1] - Q[:, idx[1]] * fb[:, 0]
        origin = np.zeros((N, 2))
    else:
        f = gen[:, list(body[:2])].copy()
        moment = gen[:, body[2]].copy()
        origin = Q[:, list(body[:2])]
    if about_xy is not None:
        d = origin - about_xy
        moment += d[:, 0] * f[:, 1] - d[:, 1] * f[:, 0]
    return np.column_stack([f[:, 0], f[:, 1], moment])


def _point_xy(mech, q, t):
    """A function giving the global (x, y) of ``about``: a point of the model (the object
    or its label: ``crank[2]``, also ``crank[1]`` where the module keeps it as the origin
    ``crank[0]``, or ``crank.at(x, y)`` at numeric local coordinates) or a pair of global
    coordinates."""
    def at(about):
        label = getattr(about, "label", about)
        if isinstance(label, str):
            k = _point_index(mech, label)
            if k is not None:
                return mech.points_at(q, t)[k]
            local = _numeric_local(about)
            if local is None:
                raise ValueError(f"about={label!r} is not a point of model '{mech.name}' "
                                 f"(points: {', '.join(mech.point_names)}; or give global "
                                 "(x, y))")
            return _to_global(mech, q, local)
        xy = np.asarray(about, dtype=float)
        if xy.shape != (2,):
            raise ValueError(f"about= must be a point or (x, y), got {about!r}")
        return xy
    return at


def _point_index(mech, label):
    """The index in mech.point_names of point ``label``: its own, or, for ``body[k]`` that
    the module merged with another point of its body (a point at the body's origin is kept
    as ``body[0]``), the one BODY_POINTS gives (k = 0: the origin, k ≥ 1: the k-th point);
    None where there is none."""
    if label in mech.point_names:
        return mech.point_names.index(label)
    name, bracket, rest = label.partition("[")
    if not bracket or not rest.endswith("]") or not rest[:-1].isdigit():
        return None
    k = int(rest[:-1])
    for body, origin, points in getattr(mech.module, "BODY_POINTS", ()):
        if body == name:
            index = origin if k == 0 else points[k - 1] if k <= len(points) else -1
            return index if index >= 0 else None
    return None


def _numeric_local(point):
    """(x, y) of a model point object at local coordinates that are numbers, else None."""
    try:
        return float(point.local[0]), float(point.local[1]), point.body
    except (AttributeError, TypeError, ValueError, IndexError):
        return None


def _to_global(mech, q, local):
    """Global (x, y) of ``local`` = (x, y, body): local coordinates in the body (the
    ground's are global)."""
    x, y, body = local
    idx = tables(mech).body(getattr(body, "name", body), mech)
    if idx is None:
        return np.array([x, y])
    c, s = np.cos(q[idx[2]]), np.sin(q[idx[2]])
    return np.array([q[idx[0]] + c * x - s * y, q[idx[1]] + s * x + c * y])


class ForceSolution(Solution):
    """A Solution with its multipliers: ``s.multipliers`` ({row label: λ}),
    ``s.driver(name)``, ``s.reaction(name, on=body, about=point)``, ``s.contact(name)``
    (a cam's, gear's or rack's contact force; a joint's force), ``s.indeterminate`` (the
    constraints whose reactions are not unique: redundant ones) and ``s.terms`` (Q_a,
    Q_c, I over the coordinates)."""

    force_level = "dynamic"
    lam = None
    _terms = None
    indeterminate = ()

    @property
    def terms(self) -> np.ndarray:
        """(3, coordinates): Q_a, Q_c and I at this point (made when first asked for)."""
        if self._terms is None:
            zero = np.zeros(self.mechanism.n)
            static = self.force_level == "static" or self.qd is None
            self._terms = force_terms(self.mechanism, self.q, zero if static else self.qd,
                                      zero if static or self.qdd is None else self.qdd, self.t)
        return self._terms

    @property
    def multipliers(self) -> dict:
        return {label: float(x) for label, x in zip(self.mechanism.constraint_labels, self.lam)}

    def _factors(self):
        out = np.empty(len(tables(self.mechanism).driver_rows))
        if out.size:
            self.mechanism.module.driver_factors(self.q, self.t, self.mechanism.p, out)
        return out

    def driver(self, name) -> float:
        """The driver's torque (angle driver) or force (distance driver), signed so that
        its power input is this value times the rate of the driven quantity."""
        mech = self.mechanism
        value = float(_effort(tables(mech), mech, name, self.lam, self._factors()))
        warn_shared(mech, name, self.indeterminate, 3)
        return value

    def reaction(self, name, on, about=None) -> np.ndarray:
        """(fx, fy, moment): what constraint ``name`` applies to body ``on`` (the ground
        too), global axes, the moment about the body's origin or about ``about`` (a point
        of the model or global (x, y))."""
        mech = self.mechanism
        return _reaction(tables(mech), mech, name, on, about, mech.jacobian(self.q, self.t),
                         self.lam, self.q, _point_xy(mech, self.q, self.t))

    def contact(self, name) -> float:
        """The scalar force constraint ``name`` transmits (mechgen.runtime.forces.contact):
        a cam's normal contact force, positive pushing (negative: the follower would need
        a pulling contact, it has lost contact); gears' tooth force along the line of
        action (the mesh's torque on either gear / its pitch radius); the force the pinion
        applies to a rack along its axis; a revolute's, translate's or point_on_line's
        force magnitude."""
        return float(contact_values(self.mechanism, name, [self.t], self.q[None],
                                    self.lam[None])[0])

    def contacts(self) -> dict:
        """{constraint label: contact force} for every cam, gear and rack constraint."""
        return {label: self.contact(label) for label in contact_labels(self.mechanism)}

    def reactions(self) -> dict:
        """{(constraint label, body name): (fx, fy, moment about the body's origin)} for
        every body each constraint acts on: those whose points it names or whose
        coordinates its rows hold, and the ground where it takes a share."""
        mech = self.mechanism
        tab = tables(mech)
        J = mech.jacobian(self.q, self.t)
        at = _point_xy(mech, self.q, self.t)
        mod = mech.module
        named = {number: {mod.POINTS[k][1] for k in pts} for number, _, pts in
                 getattr(mod, "JOINTS", ())}
        out = {}
        for number, _, label, count, _ in mod.CONSTRAINTS:
            rows = tab.constraint(label, mech)[1]
            bodies = set(named.get(number, ()))
            for name, idx in tab.bodies.items():
                if idx is not None and np.any(J[np.ix_(rows, idx)] != 0):
                    bodies.add(name)
            ground = _reaction(tab, mech, label, tab.ground, None, J, self.lam, self.q, at) \
                if tab.ground is not None else np.zeros(3)
            size = max((np.abs(_reaction(tab, mech, label, b, None, J, self.lam, self.q,
                                         at)).max() for b in bodies), default=0.0)
            if tab.ground is not None and np.abs(ground).max() > 1e-9 * max(size, 1e-300):
                bodies.add(tab.ground)
            for name in tab.bodies:                 # in the model's order
                if name in bodies:
                    out[(label, name)] = _reaction(tab, mech, label, name, None, J,
                                                   self.lam, self.q, at)
        return out


def _multipliers_at(mech, s, level):
    """(λ, the force terms or None, dependent rows) at the kinematic solution s."""
    state = mech.state                  # (its fields: a solve's cost, not properties')
    mod, p = state.tiers.module, state.p
    if level == "static":
        qd = qdd = np.zeros(mech.n)
    else:
        qd, qdd = s.qd, s.qdd
    point = written_out(mod)
    terms, dependent = None, ()
    if point is not None:
        lam = np.empty(mech.m)
        piv = point(s.q, qd, qdd, s.t, p, lam)
        if not (piv >= SING_RTOL and _norm_finite(lam)):
            terms = force_terms(mech, s.q, qd, qdd, s.t)
            lam, dependent = multipliers(mech, s.q, s.t, _rhs(terms), level)
    elif by_blocks(mod):                        # one compiled call: terms and λ by blocks
        terms, lam = np.zeros((1, 3, mech.n)), np.zeros((1, mech.m))
        ts, jac, nu, energy, factors, piv = _rows_scratch(mech, mod)
        ts[0], piv[0] = s.t, 0.0
        mod.force_rows(ts, s.q[None], qd[None], qdd[None], p, jac, terms, nu, energy,
                       factors, piv, lam)
        terms, lam = terms[0], lam[0]
        if not (piv[0] >= SING_RTOL and all_finite(lam)):
            lam, dependent = multipliers(mech, s.q, s.t, _rhs(terms), level)
    else:
        terms = force_terms(mech, s.q, qd, qdd, s.t)
        lam, dependent = multipliers(mech, s.q, s.t, _rhs(terms), level)
    return lam, terms, dependent


def _rows_scratch(mech, mod):
    """The arrays of force_rows at one point that a solution does not keep (its time, Φ_q,
    ν, the energies, the driver factors, the pivot), made once per mechanism and module:
    force_rows writes each before it reads it, and nothing reads them after the pivot."""
    state = mech.state
    cached = state.rows_scratch
    if cached is None or cached[0] is not mod:
        m, n = mech.m, mech.n
        cached = state.rows_scratch = (mod, (
            np.empty(1), np.empty((1, m, n)), np.zeros((1, m)), np.zeros((1, 3)),
            np.zeros((1, len(tables(mech).driver_rows))), np.zeros(1)))
    return cached[1]


def _norm_finite(lam) -> bool:
    """Whether λ·λ (numpy's ``lam @ lam``) is finite: where the sum of the squares as
    Python floats is far below overflow, it is, and numpy's is not computed (its call
    costs a solve most of a microsecond); anywhere else numpy's, with its overflow
    warning where there is one."""
    values = lam.tolist()
    if sum(map(_mul, values, values)) < 1e300:     # (NaN: not below)
        return True
    x = float(lam @ lam)
    return x - x == 0.0                             # (x - x: NaN unless finite)


def _rhs(terms):
    return terms[0] + terms[1] - terms[2]


@loads_guarded(span=False)
def force_solve(mech, t, level, guess=None, method=None, tol=None, maxit=None) -> ForceSolution:
    """``mech.solve(t, level="static"|"dynamic")``: the kinematic solve, then λ: in the
    derivatives' pass where the module has dynamics_sorted, else one compiled call where
    it writes the multipliers out (multipliers_point)."""
    kin = "acceleration" if level == "dynamic" else "position"
    state = mech.state
    mod = state.tiers.module
    fused = None
    if level == "dynamic" and module_attr(mod, "dynamics_sorted", MISSING) is not MISSING:
        # λ in the same pass
        scratch = state.force_scratch       # the pivot and the factors
        if scratch is None:
            scratch = state.force_scratch = (np.zeros(3), np.empty(len(mod.DRIVER_ROWS)))
        fused = (scratch[0], np.empty(mech.m), scratch[1])
    s = solve(state, t, guess, kin, method, tol, maxit, fused)
    pointless = singular_error(mech, s)     # a spring or damper without direction
    if pointless is not None:
        raise pointless
    terms, dependent = None, ()
    if fused is not None and fused[0][2] >= SING_RTOL:   # (0.0 where a λ is not finite)
        lam = fused[1]
    else:
        lam, terms, dependent = _multipliers_at(mech, s, level)
    s.__class__ = ForceSolution         # the kinematic solution, with its multipliers
    s.force_level, s.lam, s._terms = level, lam, terms
    s.indeterminate = _constraints_of(mech, dependent) if dependent else ()
    state.last = s
    return s



