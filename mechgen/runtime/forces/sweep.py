"""A sweep's forces: ``mech.sweep(t0, t1, n, level="static"|"dynamic")``, λ at every point
(points.solve_points), the drivers' efforts, reactions, the power balance, energies, the
shaking of the frame and the flywheel."""
from __future__ import annotations

import warnings

import numpy as np

from ...protocol import SING_RTOL, STATUS_COLUMNS
from ..kinematics.solving import sweep as sweep_once
from ..results import Sweep
from .contact import CAM_KINDS, contact_labels, contact_values
from .contact_loss import contact_loss, pulling
from .directions import load_ends, mark
from .lookup import _constraints_of, column_name, effort_column, loads_guarded, tables
from .points import PointForces, solve_points
from .solution import ForceSolution, _effort, _point_xy, on_body, warn_shared

def _largest(r) -> float:
    """The largest size in a reaction array, NaN (unsolved points) left out; 0 if none."""
    r = np.abs(r)
    return float(np.max(r[np.isfinite(r)], initial=0.0))


# -- a sweep -------------------------------------------------------------------------------
class ForceSweep(Sweep):
    """A Sweep with λ at every point (``sw.LAM``, NaN where the force balance has no
    solution: ``sw.force_singular``): ``driver``, ``reaction``, ``contact`` and
    ``contact_lost``, ``power``, ``energy``, ``shaking``."""

    force_level = "dynamic"
    _extras = None          # (TERMS, NU, ENERGY), made when first asked for

    @classmethod
    def of(cls, sw, level) -> "ForceSweep":
        """The kinematic sweep ``sw`` as a ForceSweep at ``level``, its multipliers still to
        be set: its arrays and marks shared, not copied (a staged sweep's pieces and
        switches too: whatever kind of sweep the kinematics returned)."""
        out = cls.__new__(cls)          # (copy.copy's way, at a fifth of its cost)
        fields = vars(out)
        fields.update(vars(sw))
        fields.pop("_contact_cache", None)      # contact forces of other multipliers
        out.force_level = level
        return out

    def _made(self, k):
        if self._extras is None:
            mech = self.mechanism
            pts = solve_points(mech.module, self.solved_t, self.Q, self.QD, self.QDD, mech.p,
                               self.force_level, extras=True)
            self._extras = (pts.TERMS, pts.NU, pts.ENERGY)
        return self._extras[k]

    @property
    def TERMS(self) -> np.ndarray:
        """(n, 3, coordinates): Q_a, Q_c and I at every point."""
        return self._made(0)

    @property
    def NU(self) -> np.ndarray:
        """(n, equations): ν = Φ_q q̇ at every point."""
        return self._made(1)

    @property
    def ENERGY(self) -> np.ndarray:
        """(n, 3): kinetic energy, potential energy and ∂V/∂t at every point."""
        return self._made(2)

    def _velocities(self):
        return np.zeros_like(self.Q) if self.force_level == "static" else self.QD

    def driver(self, name) -> np.ndarray:
        """The driver's effort at every point, (n,)."""
        mech = self.mechanism
        value = _effort(tables(mech), mech, name, self.LAM, self.FACTORS)
        warn_shared(mech, name, getattr(self, "indeterminate", ()), 3)
        return value

    def reaction(self, name, on, about=None) -> np.ndarray:
        """(n, 3): (fx, fy, moment) that constraint ``name`` applies to body ``on``."""
        mech = self.mechanism
        tab = tables(mech)
        rows = list(tab.constraint(name, mech)[1])
        mod, p, Q, LAM, ts = mech.module, mech.p, self.Q, self.LAM, self.solved_t
        N = len(self)
        J, gen = np.empty((mech.m, mech.n)), np.empty((N, mech.n))
        for k in range(N):          # Φ_q point by point (compiled), the rest on whole arrays
            mod.phi_q(Q[k], float(ts[k]), p, J)
            gen[k] = -J[rows].T @ LAM[k][rows]
        xy = None if about is None else \
            np.array([_point_xy(mech, Q[k], float(ts[k]))(about) for k in range(N)]).reshape(N, 2)
        return on_body(tab, mech, on, gen, Q, xy)

    def contact(self, name) -> np.ndarray:
        """(n,): the scalar force constraint ``name`` transmits at every point
        (ForceSolution.contact: a cam's contact force, positive pushing; gears' tooth
        force; a rack's force along its axis; a joint's force magnitude), NaN where the
        force balance has no solution."""
        mech = self.mechanism
        label = tables(mech).constraint(name, mech)[0]
        return self._contacts([label])[label].copy()

    def _contacts(self, labels) -> dict:
        """{label: contact force array} for these constraints, computed once together."""
        cache = self.__dict__.setdefault("_contact_cache", {})
        missing = [label for label in labels if label not in cache]
        if missing:
            cache.update(contact_values(self.mechanism, missing, self.solved_t, self.Q,
                                              self.LAM))
        return {label: cache[label] for label in labels}

    def contact_lost(self, name):
        """Where cam constraint ``name``'s follower loses contact (its contact force
        would have to pull): a ContactLoss, true when it is lost somewhere, with ``mask``,
        ``times``, ``intervals`` and ``first`` (the first time the force reaches zero,
        refined by solving between the sweep's points)."""
        return contact_loss(self, name)

    def power(self) -> dict:
        """Power balance at every point: "drivers" (their power input, λ·Φ_t), "loads"
        (the applied loads', Q_a·q̇, and ∂V/∂t: what changes a spring's length, stiffness
        or gravity with T puts in), "kinetic" and "potential" (the energies' rates) and
        "residual" = drivers + loads − kinetic − potential."""
        qd = self._velocities()
        drivers = -np.sum(self.LAM * self.NU, axis=1)
        loads = np.sum(self.TERMS[:, 0] * qd, axis=1) + self.ENERGY[:, 2]
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
        name), then the reaction of every constraint on every body it acts on,
        "<constraint> on <body> fx", "... fy", "... m" (the moment about the body's
        origin): the moving bodies as the first point's reactions() names them, the
        ground where the constraint loads it at any point of the sweep (a driver whose
        force is zero at the first point still loads the frame later)."""
        mech = self.mechanism
        names, arrays = [], []
        short = {}
        taken = {"T", *self.columns()}
        free = set(getattr(self, "free", ()))     # a simulation's released drivers: no effort
        for number, kind, label, _, driver in mech.module.CONSTRAINTS:
            short[label] = column_name(tables(mech), label, kind, number)
            rows = tables(mech).constraint(label, mech)[1]
            if driver and not all(mech.constraint_labels[r] in free for r in rows):
                try:
                    arrays.append(self.driver(label))
                except ValueError:      # an effort this slice does not define: no column
                    continue
                names.append(effort_column(short[label], taken))
        if not len(self):
            return names, arrays
        tab = tables(mech)
        first = ForceSolution(mech, self.solved_t[0], self.Q[0])
        first.lam = np.nan_to_num(self.LAM[0])
        acts = {}                       # label -> the bodies it acts on
        for label, body in first.reactions():
            acts.setdefault(label, set()).add(body)
        for _, _, label, _, _ in mech.module.CONSTRAINTS:
            if free and all(mech.constraint_labels[r] in free
                            for r in tab.constraint(label, mech)[1]):
                continue
            bodies = acts.get(label, set())
            values = {b: self.reaction(label, on=b) for b in bodies}
            ground = tab.ground
            if ground is not None and ground not in bodies and bodies:
                r = self.reaction(label, on=ground)
                size = max(_largest(v) for v in values.values())
                if _largest(r) > 1e-9 * max(size, 1e-300):
                    values[ground] = r
            for body in tab.bodies:     # in the model's order
                if body in values:
                    for k, part in enumerate(("fx", "fy", "m")):
                        names.append(f"{short[label]} on {body} {part}")
                        arrays.append(values[body][:, k])
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
        if not abs(omega) > 1e-9 * float(np.max(np.abs(rate), initial=0.0)):
            raise ValueError(f"flywheel: driver {label!r} has a mean rate of {omega:.3g} over "
                             "the sweep (it goes back and forth): a flywheel needs a driver "
                             "turning one way at constant speed")
        _one_period(mech, label, omega * (t[-1] - t[0]), omega)
        return {"energy": energy, "inertia": energy / (cs * omega ** 2), "mean_power": mean}

    def shaking(self) -> np.ndarray:
        """(n, 3): the force and the moment about the ground origin that the moving parts
        apply to the frame: through the constraints (drivers included), Σ over the bodies
        of Φ_qᵀλ (= Q_a + Q_c − I) on X, Y and Th, moved to the origin; and through the
        loads anchored on it (a motor's moment(rotor, base, M), a spring or a damper to a
        ground point), the opposite of what they apply to the moving parts (the module's
        frame_loads, Q_f). Together Σ (Q_a + Q_c − Q_f − I): the inertia forces and the
        loads from outside (gravity, forces at points, moments on one body), whatever
        way the model drives the mechanism."""
        tab = tables(self.mechanism)
        gen = self.TERMS[:, 0] + self.TERMS[:, 1] - self.TERMS[:, 2] - self._frame_loads()
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


    def _frame_loads(self) -> np.ndarray:
        """(n, N_COORDS): Q_f at every point (zeros where no load is anchored on the
        frame, or the module predates frame_loads)."""
        mod, mech = self.mechanism.module, self.mechanism
        out = np.zeros_like(self.Q)
        if getattr(mod, "FRAME_LOADS", False):
            qd = self._velocities()
            for k in range(len(self)):
                mod.frame_loads(self.Q[k], qd[k], float(self.solved_t[k]), mech.p, out[k])
        return out


def _one_period(mech, label, travel, omega):
    """A ValueError where an angle driver (rotation_lock) turns less than a whole turn
    over the sweep, a warning where it turns other than a whole number of turns: the
    flywheel's ΔE is the fluctuation over one period of the cycle, a turn of the crank."""
    kind = next((c[1] for c in mech.module.CONSTRAINTS if c[2] == label), None)
    if kind != "rotation_lock":
        return
    turns = abs(travel) / (2 * np.pi)
    period = 2 * np.pi / abs(omega)
    said = (f"flywheel: driver {label!r} turns {turns:.4g} of a turn over the sweep "
            f"({abs(travel):.4g} rad), but the flywheel's energy is the fluctuation over one "
            f"period of the cycle, a whole turn (2π rad, {period:.6g} in T at its mean rate)")
    if turns < 1 - 1e-6:
        raise ValueError(f"{said}: sweep over a whole period")
    if abs(turns - round(turns)) > 1e-6:
        warnings.warn(f"{said}: the sweep is not a whole number of periods", stacklevel=3)


def attach(sw, level, fused=None) -> "ForceSweep":
    """The kinematic sweep ``sw`` (at acceleration for "dynamic", position for "static")
    with λ at every point, as a ForceSweep; warns where the force balance has no
    solution. ``fused``: what the sweep's quick path solved already (sweeping.compiled):
    only the other points, and those whose pivot fell below SING_RTOL, are solved here."""
    mech = sw.mechanism
    out = ForceSweep.of(sw, level)
    if fused and fused["count"] > 0:
        pts = _completed(mech, sw, level, fused)
    else:
        pts = solve_points(mech.module, sw.solved_t, sw.Q, sw.QD, sw.QDD, mech.p, level,
                           extras=False)
    out.LAM, out.FACTORS = pts.LAM, pts.FACTORS
    if pts.extras:
        out._extras = (pts.TERMS, pts.NU, pts.ENERGY)
    out.force_singular = pts.singular
    labels = mech.constraint_labels
    out.indeterminate = _constraints_of(mech, {labels[i] for i in pts.dependent})
    if out.force_singular.any():
        times = out.t[out.force_singular]
        ends = [f"{kind} '{name}'" for name, kind, _, _ in load_ends(mech.module)]
        why = (f", or a spring or damper whose two ends meet there (no direction: "
               f"{', '.join(ends)})") if ends else ""
        warnings.warn(f"model '{mech.name}': no force balance at {times.size} point(s) "
                      f"(first t={times[0]:.6g}): a lock or toggle position{why}; their "
                      "multipliers are NaN (sw.force_singular)", stacklevel=4)
    if tables(mech).forces:
        _warn_pulling(out)
    return out


def _warn_pulling(sw):
    """Warn for every cam contact whose force would have to pull somewhere."""
    labels = contact_labels(sw.mechanism, CAM_KINDS)
    if not labels:
        return
    try:
        forces = sw._contacts(labels)
    except ValueError:              # a module without the points it needs: no check
        return
    for label, force in forces.items():
        where = pulling(force)
        if where.any():
            warnings.warn(f"model '{sw.mechanism.name}': cam contact {label!r} would have to "
                          f"pull at {int(where.sum())} of {len(force)} point(s) (first "
                          f"t={sw.t[where][0]:.6g}, least force {np.nanmin(force):.6g}): "
                          f"the follower loses contact there (sw.contact_lost({label!r}))",
                          stacklevel=5)


def _completed(mech, sw, level, fused) -> PointForces:
    """The quick path's multipliers (points before fused["count"] whose pivot held),
    the other points' solved by solve_points."""
    N = len(sw)
    pts = PointForces(N, mech.m, mech.n, fused["FACTORS"].shape[1], extras=False)
    pts.LAM, pts.FACTORS = fused["LAM"][:N], fused["FACTORS"][:N]
    redo = np.ones(N, dtype=bool)
    count = min(fused["count"], N)
    redo[:count] = ~(fused["FPIV"][:count] >= SING_RTOL)    # (0.0 where a λ is not finite)
    if redo.any():
        k = np.flatnonzero(redo)
        still = level == "static"           # (a static sweep has no QD, QDD)
        rest = solve_points(mech.module, sw.solved_t[k], sw.Q[k], None if still else sw.QD[k],
                            None if still else sw.QDD[k], mech.p, level, extras=False)
        pts.LAM[k], pts.FACTORS[k], pts.singular[k] = rest.LAM, rest.FACTORS, rest.singular
        pts.dependent = rest.dependent
    mark(mech.module, sw.solved_t, sw.Q, mech.p, pts.LAM, pts.singular)
    return pts


@loads_guarded(span=True)
def force_sweep(mech, t0, t1, n, level, guess=None, method=None, tol=None, maxit=None,
                times=None) -> ForceSweep:
    """``mech.sweep(t0, t1, n, level="static"|"dynamic")``: the kinematic sweep (at
    acceleration, or position), then λ at every point (points.solve_points); the sweep's
    quick path solves them on its way where the module can (sweep_fast_forces,
    sweep_fast_statics)."""
    kin = "acceleration" if level == "dynamic" else "position"
    fused = {}
    sw = sweep_once(mech.state, t0, t1, n, kin, guess=guess, method=method, tol=tol,
                    maxit=maxit, times=times, forces=fused)
    return attach(sw, level, fused)


def of_solution(s) -> ForceSweep:
    """A ForceSolution as a one-point ForceSweep, whose table has the columns that
    ``mechgen sweep --level static|dynamic`` writes (``mechgen solve --level`` prints it)."""
    mech = s.mechanism
    one = (lambda a: None if a is None else np.asarray(a, dtype=float)[None].copy())
    out = ForceSweep(mech, np.array([s.t]), one(s.q), one(s.qd), one(s.qdd),
                     np.zeros((1, STATUS_COLUMNS), dtype=np.int16))
    out.force_level = s.force_level
    out.LAM = one(s.lam)
    out.FACTORS = s._factors()[None]
    out.force_singular = np.zeros(1, dtype=bool)
    out.indeterminate = s.indeterminate
    return out
