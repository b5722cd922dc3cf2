"""Statics and inverse dynamics on a solved configuration (levels "static" and "dynamic").

The generated module of a model with mass or loads holds ``force_terms`` (Q_a, Q_c, I),
``energies`` and ``driver_factors`` (mechgen.compiler.forces_code); at every solved point
the multipliers solve Φ_qᵀ λ = Q_a + Q_c − I (q̇ = q̈ = 0 at level "static"). A model
without mass or loads has no such functions: its right side is zero, so are its λ.

A sorted square build solves the multipliers in the module, block by block in the
reverse solving order (multipliers_sorted, through force_rows); where a block's scaled
pivot is below SING_RTOL, or the module has no blocks (a batched numpy solve where its
pivot ratio allows), or Φ_q has more rows than columns, numpy's SVD of Φ_q decides: its
rank on the row-equilibrated Φ_q at SING_RTOL, as the kinematic solves read it. Below
full row rank (redundant constraints) λ is the minimum-norm solution and
``indeterminate`` names the constraints whose multipliers are not unique; where
Φ_qᵀ λ = Q has no solution (a lock or toggle position with a load that would move it)
the solve raises SingularError (a sweep: NaN and ``force_singular`` at those points).

What a constraint applies to the bodies is −Φ_q[rows]ᵀ λ[rows]: its entries on a body's
X, Y, Th are the force and the moment about the body's origin. numpy only, never sympy.
"""
from __future__ import annotations

import warnings

import numpy as np

from ..errors import SingularError
from ..protocol import SING_RTOL
from .results import Solution, Sweep

FORCE_LEVELS = ("static", "dynamic")
CONSISTENT_RTOL = 1e-8     # a residual of Φ_qᵀλ = Q above this share of its size: no solution


def is_force_level(level) -> bool:
    return level.__class__ is str and level in FORCE_LEVELS


# -- the model's tables -------------------------------------------------------------------
class _Tables:
    """What the force results look up, read once per module: constraint rows and names,
    the bodies' coordinates, the driver rows."""

    def __init__(self, mech):
        mod = mech.module
        self.forces = bool(getattr(mod, "FORCES", False))
        self.driver_rows = tuple(getattr(mod, "DRIVER_ROWS", ()))
        self.constraints = {}        # name, label or number -> (label, rows, is driver)
        row = 0
        for number, kind, label, count, driver in mod.CONSTRAINTS:
            entry = (label, tuple(range(row, row + count)), bool(driver))
            row += count
            for key in (number, str(number), label, _name_of(label, kind),
                        *_stage_names(label, kind)):
                if key is not None:
                    self.constraints.setdefault(key, entry)
        index = {c: k for k, c in enumerate(mech.coordinates)}
        self.bodies = {}             # name -> (X, Y, Th) indices, or None for the ground
        self.ground = None
        for name, number, is_ground in mod.BODIES:
            if is_ground:
                self.ground = name
                self.bodies[name] = None
            else:
                self.bodies[name] = (index[f"X{number}"], index[f"Y{number}"],
                                     index[f"Th{number}"])

    def constraint(self, name, mech):
        entry = self.constraints.get(name)
        if entry is None:
            names = sorted({str(v[0]) for v in self.constraints.values()})
            raise ValueError(f"model '{mech.name}' has no constraint {name!r} (constraints: "
                             f"{'; '.join(names)})")
        return entry

    def body(self, name, mech):
        name = getattr(name, "name", name)
        if name not in self.bodies:
            raise ValueError(f"model '{mech.name}' has no body {name!r} (bodies: "
                             f"{', '.join(self.bodies)})")
        return self.bodies[name]


def _name_of(label, kind):
    """The ``name=`` of a constraint from its label ``name: kind(args)``, or None."""
    marker = f": {kind}("
    return label.split(marker, 1)[0] if marker in label else None


def _stage_names(label, kind):
    """The names of a stage group's constraints, ``[stage] name: kind(args) | ...``."""
    if kind != "stages":
        return ()
    out = []
    for part in label.split(" | "):
        part = part.split("] ", 1)[-1]
        if ": " in part:
            out.append(part.split(": ", 1)[0])
    return tuple(out)


def tables(mech) -> _Tables:
    mod = mech.module
    cached = getattr(mech, "_force_tables", None)
    if cached is None or cached[0] is not mod:
        cached = (mod, _Tables(mech))
        mech._force_tables = cached
    return cached[1]


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
    """multipliers() by the SVD of Φ_q = J: its rank on the row-equilibrated J at
    SING_RTOL, the minimum-norm λ, and a residual check."""
    scale = np.max(np.abs(J), axis=1, initial=0.0)
    scale[scale == 0] = 1.0
    s_scaled = np.linalg.svd(J / scale[:, None], compute_uv=False)
    top = s_scaled[0] if s_scaled.size and s_scaled[0] > 0 else 1.0
    rank = int(np.sum(s_scaled > SING_RTOL * top))
    u, s, vt = np.linalg.svd(J)
    k = min(rank, s.size)
    lam = u[:, :k] @ ((vt[:k] @ rhs) / s[:k])
    residual = rhs - J.T @ lam
    size = np.linalg.norm(rhs) + np.linalg.norm(np.abs(J).T @ np.abs(lam))
    dependent = ()
    if k < J.shape[0]:
        w = np.linalg.norm(u[:, k:], axis=1)
        labels = mech.constraint_labels
        dependent = tuple(labels[i] for i in range(J.shape[0]) if w[i] > 1e-6 * w.max())
    if not np.all(np.isfinite(lam)) or np.linalg.norm(residual) > CONSISTENT_RTOL * size:
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
                         "equation (only g(q) − f(T) and relative_distance drivers)")
    return np.sum(lam_rows[..., list(rows)] * f, axis=-1)


def _reaction(tab, mech, name, on, about, J, lam, q, point_xy):
    """(fx, fy, moment) that constraint ``name`` applies to body ``on`` at one point;
    the moment about the body's origin, or about ``about``."""
    label, rows, _ = tab.constraint(name, mech)
    rows = list(rows)
    gen = -J[rows].T @ lam[rows]         # the constraint's generalized force on the system
    body = tab.body(on, mech)
    if body is None:                     # the ground: Newton's third law, about the origin
        f = np.zeros(2)
        moment = 0.0
        for idx in tab.bodies.values():
            if idx is None:
                continue
            fb = gen[list(idx[:2])]
            f -= fb
            moment -= gen[idx[2]] + q[idx[0]] * fb[1] - q[idx[1]] * fb[0]
        origin = np.zeros(2)
    else:
        f = gen[list(body[:2])].copy()
        moment = gen[body[2]]
        origin = q[list(body[:2])]
    if about is not None:
        d = origin - point_xy(about)
        moment += d[0] * f[1] - d[1] * f[0]
    return np.array([f[0], f[1], moment])


def _point_xy(mech, q, t):
    """A function giving the global (x, y) of ``about``: a point of the model (the object
    or its label) or a pair of global coordinates."""
    def at(about):
        label = getattr(about, "label", about)
        if isinstance(label, str):
            if label not in mech.point_names:
                raise ValueError(f"about={label!r} is not a point of model '{mech.name}' "
                                 f"(points: {', '.join(mech.point_names)})")
            return mech.points_at(q, t)[mech.point_names.index(label)]
        xy = np.asarray(about, dtype=float)
        if xy.shape != (2,):
            raise ValueError(f"about= must be a point or (x, y), got {about!r}")
        return xy
    return at


class ForceSolution(Solution):
    """A Solution with its multipliers: ``s.multipliers`` ({row label: λ}),
    ``s.driver(name)``, ``s.reaction(name, on=body, about=point)``, ``s.indeterminate``
    (the constraints whose reactions are not unique: redundant ones) and ``s.terms``
    (Q_a, Q_c, I over the coordinates)."""

    force_level = "dynamic"
    lam = None
    terms = None
    indeterminate = ()

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
        return float(_effort(tables(mech), mech, name, self.lam, self._factors()))

    def reaction(self, name, on, about=None) -> np.ndarray:
        """(fx, fy, moment): what constraint ``name`` applies to body ``on`` (the ground
        too), global axes, the moment about the body's origin or about ``about`` (a point
        of the model or global (x, y))."""
        mech = self.mechanism
        return _reaction(tables(mech), mech, name, on, about, mech.jacobian(self.q, self.t),
                         self.lam, self.q, _point_xy(mech, self.q, self.t))


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


def _rhs(terms):
    return terms[0] + terms[1] - terms[2]


def force_solve(mech, t, level, guess=None, method=None, tol=None, maxit=None) -> ForceSolution:
    """``mech.solve(t, level="static"|"dynamic")``: the kinematic solve, then λ."""
    kin = "acceleration" if level == "dynamic" else "position"
    s = mech.solve(t, guess=guess, level=kin, method=method, tol=tol, maxit=maxit)
    if level == "static":
        qd = qdd = np.zeros(mech.n)
    else:
        qd, qdd = s.qd, s.qdd
    mod = mech.module
    if hasattr(mod, "multipliers_sorted"):    # one compiled call: terms and λ by blocks
        terms, lam, piv = np.zeros((1, 3, mech.n)), np.zeros((1, mech.m)), np.zeros(1)
        mod.force_rows(np.array([s.t]), s.q[None], qd[None], qdd[None], mech.p,
                       np.empty((1, mech.m, mech.n)), terms, np.zeros((1, mech.m)),
                       np.zeros((1, 3)), np.zeros((1, len(tables(mech).driver_rows))), piv, lam)
        terms, lam, dependent = terms[0], lam[0], ()
        if not (piv[0] >= SING_RTOL and np.all(np.isfinite(lam))):
            lam, dependent = multipliers(mech, s.q, s.t, _rhs(terms), level)
    else:
        terms = force_terms(mech, s.q, qd, qdd, s.t)
        lam, dependent = multipliers(mech, s.q, s.t, _rhs(terms), level)
    out = ForceSolution(mech, s.t, s.q, s.qd, s.qdd, iterations=s.iterations,
                        residual=s.residual, singular=s.singular, method=s.method)
    out.force_level, out.lam, out.terms = level, lam, terms
    out.indeterminate = _constraints_of(mech, dependent) if dependent else ()
    mech.last = out
    return out


def _constraints_of(mech, row_labels):
    """The constraints (their labels) of some row labels, in order, each once."""
    tab = tables(mech)
    out = []
    for label, rows, _ in {v[0]: v for v in tab.constraints.values()}.values():
        if any(mech.constraint_labels[r] in row_labels for r in rows):
            out.append(label)
    return tuple(out)


# -- a sweep -------------------------------------------------------------------------------
class ForceSweep(Sweep):
    """A Sweep with λ at every point (``sw.LAM``, NaN where the force balance has no
    solution: ``sw.force_singular``): ``driver``, ``reaction``, ``power``, ``energy``,
    ``shaking``."""

    force_level = "dynamic"

    def _velocities(self):
        return np.zeros_like(self.Q) if self.force_level == "static" else self.QD

    def driver(self, name) -> np.ndarray:
        """The driver's effort at every point, (n,)."""
        mech = self.mechanism
        return _effort(tables(mech), mech, name, self.LAM, self.FACTORS)

    def reaction(self, name, on, about=None) -> np.ndarray:
        """(n, 3): (fx, fy, moment) that constraint ``name`` applies to body ``on``."""
        mech = self.mechanism
        tab = tables(mech)
        out = np.empty((len(self), 3))
        for k in range(len(self)):
            q, t = self.Q[k], float(self.t[k])
            out[k] = _reaction(tab, mech, name, on, about, mech.jacobian(q, t), self.LAM[k],
                               q, _point_xy(mech, q, t))
        return out

    def power(self) -> dict:
        """Power balance at every point: "drivers" (their power input, λ·Φ_t), "loads"
        (the applied loads', Q_a·q̇), "kinetic" and "potential" (the energies' rates) and
        "residual" = drivers + loads − kinetic − potential."""
        qd = self._velocities()
        drivers = -np.sum(self.LAM * self.NU, axis=1)
        loads = np.sum(self.TERMS[:, 0] * qd, axis=1)
        kinetic = np.sum(self.TERMS[:, 2] * qd, axis=1)
        potential = -np.sum(self.TERMS[:, 1] * qd, axis=1) + self.ENERGY[:, 2]
        return {"drivers": drivers, "loads": loads, "kinetic": kinetic,
                "potential": potential, "residual": drivers + loads - kinetic - potential}

    def energy(self) -> dict:
        """"kinetic", "potential" and "total" energy at every point."""
        return {"kinetic": self.ENERGY[:, 0].copy(), "potential": self.ENERGY[:, 1].copy(),
                "total": self.ENERGY[:, 0] + self.ENERGY[:, 1]}

    def force_columns(self) -> tuple[list, list]:
        """(names, arrays) of the force columns of the table: each driver's effort (its
        name), then the reaction of every constraint on every body it acts on at the first
        point, "<constraint> on <body> fx", "... fy", "... m" (the moment about the body's
        origin)."""
        mech = self.mechanism
        tab = tables(mech)
        names, arrays = [], []
        short = {}
        for number, kind, label, _, driver in mech.module.CONSTRAINTS:
            short[label] = _name_of(label, kind) or str(number)
            if driver:
                try:
                    arrays.append(self.driver(label))
                except ValueError:      # an effort this slice does not define: no column
                    continue
                names.append(short[label])
        if not len(self):
            return names, arrays
        first = ForceSolution(mech, self.t[0], self.Q[0])
        first.lam = np.nan_to_num(self.LAM[0])
        for label, body in first.reactions():
            r = self.reaction(label, on=body)
            for k, part in enumerate(("fx", "fy", "m")):
                names.append(f"{short[label]} on {body} {part}")
                arrays.append(r[:, k])
        return names, arrays

    def table(self) -> tuple[list, np.ndarray]:
        """The kinematic table's columns, then the force columns (force_columns)."""
        header, data = super().table()
        names, arrays = self.force_columns()
        if names:
            data = np.column_stack([data] + [np.asarray(a, dtype=float) for a in arrays])
        return header + names, data

    def flywheel(self, cs, driver=None) -> dict:
        """The flywheel for a coefficient of speed fluctuation ``cs`` with the driver at
        constant speed, the sweep spanning one period: "energy" ΔE, the largest swing of
        ∫(P − P̄) dt (P the driver's power input, trapezoids on the sweep's points),
        "inertia" ΔE / (cs ω̄²), ω̄ the mean rate of the driven quantity, and "mean_power"."""
        if self.force_level != "dynamic":
            raise ValueError("flywheel: needs a dynamic sweep (level=\"dynamic\")")
        cs = float(cs)
        if not cs > 0 or not np.isfinite(cs):
            raise ValueError(f"flywheel: the coefficient of speed fluctuation must be a "
                             f"positive number, got {cs!r}")
        mech, tab = self.mechanism, tables(self.mechanism)
        names = sorted({v[0] for v in tab.constraints.values() if v[2]})
        if driver is None:
            if len(names) != 1:
                raise ValueError(f"flywheel: name the driver (driver=...): model "
                                 f"'{mech.name}' has {len(names)}: {'; '.join(names)}")
            driver = names[0]
        label, rows, _ = tab.constraint(driver, mech)
        if len(rows) != 1 or len(self) < 3:
            raise ValueError(f"flywheel: needs a one-row driver and a sweep of 3 points or "
                             f"more ({label!r}, {len(self)} points)")
        r = rows[0]
        power = -self.LAM[:, r] * self.NU[:, r]
        factor = self.FACTORS[:, tab.driver_rows.index(r)] if tab.forces else -np.ones(len(self))
        rate = -self.NU[:, r] / factor
        t = self.t
        steps = np.diff(t) * (power[1:] + power[:-1]) / 2
        work = np.concatenate([[0.0], np.cumsum(steps)])
        mean = work[-1] / (t[-1] - t[0])
        swing = work - mean * (t - t[0])
        energy = float(swing.max() - swing.min())
        omega = float(np.sum(np.diff(t) * (rate[1:] + rate[:-1]) / 2) / (t[-1] - t[0]))
        return {"energy": energy, "inertia": energy / (cs * omega ** 2), "mean_power": mean}

    def shaking(self) -> np.ndarray:
        """(n, 3): the force and the moment about the ground origin that the moving parts
        apply to the frame through the constraints (drivers included): Σ over the bodies
        of Φ_qᵀλ (= Q_a + Q_c − I) on X, Y and Th, moved to the origin."""
        tab = tables(self.mechanism)
        gen = self.TERMS[:, 0] + self.TERMS[:, 1] - self.TERMS[:, 2]
        gen[np.isnan(self.LAM).any(axis=1)] = np.nan
        out = np.zeros((len(self), 3))
        for idx in tab.bodies.values():
            if idx is None:
                continue
            fx, fy = gen[:, idx[0]], gen[:, idx[1]]
            out[:, 0] += fx
            out[:, 1] += fy
            out[:, 2] += gen[:, idx[2]] + self.Q[:, idx[0]] * fy - self.Q[:, idx[1]] * fx
        return out


def force_sweep(mech, t0, t1, n, level, **options) -> ForceSweep:
    """``mech.sweep(t0, t1, n, level="static"|"dynamic")``: the kinematic sweep (at
    acceleration, or position), then λ at every point: the module's force_rows fills
    Φ_q, the force terms, ν and the energies in one compiled loop, with the multipliers
    block by block in the reverse solving order where the module has the blocks
    (multipliers_sorted), else the pivot ratios and one batched numpy solve; a point whose
    smallest pivot is below SING_RTOL (or a model with more equations than coordinates)
    goes to the SVD (svd_multipliers)."""
    kin = "acceleration" if level == "dynamic" else "position"
    sw = mech.sweep(t0, t1, n, level=kin, **options)
    out = ForceSweep.__new__(ForceSweep)
    out.__dict__.update(sw.__dict__)
    out.force_level = level
    N, m, n_q, tab = len(sw), mech.m, mech.n, tables(mech)
    out.TERMS = np.zeros((N, 3, n_q))
    out.ENERGY = np.zeros((N, 3))
    out.LAM = np.zeros((N, m))
    out.NU = np.zeros((N, m))
    out.FACTORS = np.zeros((N, len(tab.driver_rows)))
    out.force_singular = np.zeros(N, dtype=bool)
    out.indeterminate = ()
    if not tab.forces or N == 0:         # no mass, no loads: every λ is zero
        return out
    if level == "static":
        QD = QDD = np.zeros_like(sw.Q)
    else:
        QD, QDD = sw.QD, sw.QDD
    blocks = hasattr(mech.module, "multipliers_sorted")
    JAC = np.empty((1 if blocks else N, m, n_q))    # one reused where λ comes back solved
    PIV = np.empty(N)
    ts = np.ascontiguousarray(sw.t, dtype=np.float64)
    mech.module.force_rows(ts, np.ascontiguousarray(sw.Q), np.ascontiguousarray(QD),
                           np.ascontiguousarray(QDD), mech.p, JAC, out.TERMS, out.NU,
                           out.ENERGY, out.FACTORS, PIV, out.LAM)
    rhs = out.TERMS[:, 0] + out.TERMS[:, 1] - out.TERMS[:, 2]
    direct = (PIV >= SING_RTOL) if m == n_q else np.zeros(N, dtype=bool)
    if blocks:                                      # solved block by block already
        direct &= np.all(np.isfinite(out.LAM), axis=1)
    elif direct.any():
        try:
            lam = np.linalg.solve(JAC[direct].transpose(0, 2, 1), rhs[direct][..., None])[..., 0]
        except np.linalg.LinAlgError:
            direct[:] = False
        else:
            good = np.all(np.isfinite(lam), axis=1)
            out.LAM[np.flatnonzero(direct)[good]] = lam[good]
            direct[np.flatnonzero(direct)[~good]] = False
    indeterminate = set()
    for k in np.flatnonzero(~direct):
        try:
            J = mech.jacobian(sw.Q[k], float(sw.t[k])) if blocks else JAC[k]
            out.LAM[k], dependent = svd_multipliers(mech, J, sw.Q[k], float(sw.t[k]),
                                                    rhs[k], level)
            indeterminate.update(dependent)
        except SingularError:
            out.LAM[k] = np.nan
            out.force_singular[k] = True
    out.indeterminate = _constraints_of(mech, indeterminate)
    if out.force_singular.any():
        times = out.t[out.force_singular]
        warnings.warn(f"model '{mech.name}': no force balance at {times.size} point(s) "
                      f"(first t={times[0]:.6g}): a lock or toggle position; their "
                      "multipliers are NaN (sw.force_singular)", stacklevel=3)
    return out
