"""`mechgen check`: Mech's CheckSystem and more (degrees of freedom, rank, assembly modes,
contradictory constraints, structure).

The numbers come from one lambdify of Φ and Φ_q; everything after it is numpy: damped
Gauss-Newton (least squares, so that non-square systems work too), the SVD for ranks and
null spaces, quasi-random starts for the assembly modes.
"""
from __future__ import annotations

import math

import numpy as np
import sympy as sp

from ..model.forces.holds import held
from ..model.geometry import T
from ..model.symbolic import rank_analysis
from ..turns import meshed_alike, turn_coefficients
from .cycle_check import whole_cycle
from .functions.equations_code import mesh_counts
from .loop_lengths import loop_dimensions
from .solver.blocks import CLOSED_FORM_QUADRATIC, CLOSED_FORM_TRIG, DYAD_RRR, EXPLICIT, NEWTON
from .solver.dyads import signed
from .solver.plan import make_plan

TOL = 1e-9          # max |Φ| below which a configuration counts as assembled
STARTS = 128        # quasi-random starts of the assembly-mode search


class System:
    """Φ and Φ_q of a model at fixed parameters and time as numpy functions of q, for one
    configuration (q of shape (n,)) or a stack of them ((k, n)): one lambdify of Φ and
    of the nonzero entries of Φ_q."""

    def __init__(self, eq, params, t):
        self.m, self.n = eq.phi_q.shape
        # numpy floats: 1/T at T = 0 gives inf (the configuration fails), never a
        # ZeroDivisionError out of the lambdified code
        self.t = np.float64(t)
        self.params = [np.float64(v) for v in params]
        nonzero = [(i, j) for i in range(self.m) for j in range(self.n) if eq.phi_q[i, j] != 0]
        self._rows = np.array([i for i, _ in nonzero], dtype=int)
        self._cols = np.array([j for _, j in nonzero], dtype=int)
        exprs = list(eq.phi) + [eq.phi_q[i, j] for i, j in nonzero]
        self._f = sp.lambdify((list(eq.q), list(eq.params), T), exprs, modules="numpy",
                              cse=True)

    def __call__(self, q):
        """(Φ, Φ_q) at q as float arrays: (m,) and (m, n), or (k, m) and (k, m, n)."""
        q = np.asarray(q, dtype=float)
        stack = q.reshape(-1, self.n)
        vals = np.empty((self.m + self._rows.size, stack.shape[0]))
        with np.errstate(all="ignore"):
            for k, v in enumerate(self._f(list(stack.T), self.params, self.t)):
                vals[k] = v                 # a constant entry comes back as a scalar
        r = vals[:self.m].T
        J = np.zeros((stack.shape[0], self.m, self.n))
        J[:, self._rows, self._cols] = vals[self.m:].T
        if q.ndim == 1:
            return r[0], J[0]
        return r, J

    def solve(self, q0, rows=None, maxit=60):
        """Damped Gauss-Newton from q0 on the rows given (all by default): it ends at a
        solution or at a least-squares point of the rows. Returns (q, max |Φ|, steps,
        converged)."""
        rows = slice(None) if rows is None else list(rows)
        q = np.array(q0, dtype=float)

        def at(x):
            r, J = self(x)
            return r[rows], J[rows]

        r, J = at(q)
        it = 0
        for it in range(1, maxit + 1):
            if not (np.all(np.isfinite(r)) and np.all(np.isfinite(J))):
                return q, math.inf, it, False
            if np.max(np.abs(r), initial=0.0) < 1e-3 * TOL:
                break
            dq = np.linalg.lstsq(J, -r, rcond=None)[0]
            base, lam = float(r @ r), 1.0
            while True:                 # halve the step until |Φ|² decreases
                qn = q + lam * dq
                rn, Jn = at(qn)
                if np.all(np.isfinite(rn)) and float(rn @ rn) < base or lam < 1e-3:
                    break
                lam *= 0.5
            q, r, J = qn, rn, Jn
            if np.max(np.abs(lam * dq), initial=0.0) < 1e-14 * (1 + np.max(np.abs(q))):
                break
        norm = float(np.max(np.abs(r), initial=0.0)) if np.all(np.isfinite(r)) else math.inf
        return q, norm, it, norm < TOL

    def solve_many(self, Q, step, maxit=40):
        """Gauss-Newton from every row of Q at once (steps capped at ``step``); returns
        the rows that converge."""
        Q = np.array(Q, dtype=float)
        for _ in range(maxit):
            r, J = self(Q)
            alive = np.all(np.isfinite(r), axis=1) & np.all(np.isfinite(J), axis=(1, 2))
            Q, r, J = Q[alive], r[alive], J[alive]
            if not len(Q):
                break
            dq = -np.einsum("knm,km->kn", np.linalg.pinv(J), r)
            big = np.max(np.abs(dq), axis=1, keepdims=True)
            Q = Q + dq * np.minimum(1.0, step / np.maximum(big, 1e-300))
        r = self(Q)[0] if len(Q) else np.zeros((0, self.m))
        good = np.all(np.isfinite(r), axis=1) & (np.max(np.abs(r), axis=1, initial=0.0) < TOL)
        return Q[good]


def halton(count, dim):
    """Points 1..count of the Halton sequence in [0, 1)^dim: deterministic and even."""
    primes, p = [], 2
    while len(primes) < dim:
        if all(p % d for d in primes if d * d <= p):
            primes.append(p)
        p += 1
    out = np.empty((count, dim))
    for d, base in enumerate(primes):
        for k in range(count):
            f, x, i = 1.0, 0.0, k + 1
            while i > 0:
                f /= base
                x += f * (i % base)
                i //= base
            out[k, d] = x
    return out


def angle_coordinates(system, q, names, body_angles) -> tuple[set, set]:
    """(periodic, shown wrapped): the coordinates in which Φ is 2π-periodic (angles equal
    modulo 2π are one configuration), and those printed in (−π, π] (these and every
    body's rotation: a driven Th2 − ωT is not periodic, yet it is an orientation)."""
    x = np.asarray(q, dtype=float) + np.random.default_rng(7).uniform(-0.5, 0.5, (2, system.n))
    r0 = system(x)[0]
    periodic = set()
    for j in range(system.n):
        y = x.copy()
        y[:, j] += 2 * math.pi
        r1 = system(y)[0]
        if np.all(np.isfinite(r0)) and np.all(np.isfinite(r1)) and \
                np.max(np.abs(r1 - r0)) <= 1e-9 * (1 + np.max(np.abs(r0))):
            periodic.add(j)
    return periodic, periodic | {j for j, s in enumerate(names) if s in body_angles}


def wrap(q, angles):
    """q with the given angles in (−π, π]."""
    q = np.array(q, dtype=float)
    for j in angles:
        w = math.remainder(q[j], 2 * math.pi)
        q[j] = math.pi if w == -math.pi else w
    return q


def _differ(a, b, periodic):
    d = np.array(b, dtype=float) - a
    for j in periodic:
        d[j] = math.remainder(d[j], 2 * math.pi)
    return d


def _is_flip(a, b, periodic, same, placed=None):
    """b is a turned half a turn in some angles and equal elsewhere, every point a
    constraint places (``placed``: their positions as a function of q) where it was: the
    mirror root of a parallel or point-on-line condition (a slider reversed on its guide),
    not another assembly of the mechanism (as the runtime's mech.assemblies counts)."""
    d = _differ(a, b, periodic)
    flipped = [j for j in periodic if abs(abs(d[j]) - math.pi) <= same]
    rest = np.delete(d, flipped)
    return bool(flipped) and np.max(np.abs(rest), initial=0.0) <= same and \
        _stays(a, b, same, placed)


def _stays(a, b, same, placed):
    """Whether every point a constraint places is where it was (no ``placed``: yes)."""
    return placed is None or np.max(np.abs(placed(a) - placed(b)), initial=0.0) <= same


def placed_points(model, eq, t):
    """The positions of the points the model's constraints place (a point a constraint
    takes as such, not an axis' end), as a numpy function of q at time t and the
    parameters' defaults; None where there are none."""
    pts = {(pt.body.name, pt.local): pt for c in model.constraints
           for pt in getattr(c, "placed", ())}
    if not pts:
        return None
    exprs = [e for pt in pts.values() for e in pt.r]
    f = sp.lambdify((list(eq.q), list(eq.params), T), exprs, modules="numpy")
    params = [float(v) for v in model.param_defaults.values()]
    return lambda q: np.array(f(list(q), params, float(t)), dtype=float).reshape(-1)


class Meshing:
    """Whether two assemblies mesh their gears alike (mechgen.turns): the mesh counts of
    the model's gear rows as a numpy function of q, the driver rows (those holding T)."""

    def __init__(self, eq, params, t, system):
        counts = mesh_counts(eq)
        self.t, self.system = np.float64(t), system
        self.params = [np.float64(v) for v in params]
        self._f = sp.lambdify((list(eq.q), list(eq.params), T), [e for _, e in counts],
                              modules="numpy")
        self.drivers = [i for i in range(eq.phi.rows) if T in eq.phi[i].free_symbols]

    def counts(self, q):
        return np.array(self._f(list(q), self.params, self.t), dtype=float)

    def alike(self, q, ref, turns):
        turns = sorted(turns)
        C = turn_coefficients(self.counts, np.asarray(ref, dtype=float), turns)
        J = self.system(ref)[1]
        D = J[np.ix_(self.drivers, turns)] if self.drivers else np.zeros((0, len(turns)))
        return meshed_alike(self.counts(ref), self.counts(q), C, D)


def assembly_modes(system, guess, periodic, starts=STARTS, first=None, turns=(),
                   meshing=None, placed=None):
    """Every distinct assembly found at the system's time from the guess and from
    ``starts`` quasi-random starts (angles over [−π, π), positions within the model's size
    of the guess; ``first`` is the solution Newton reaches from the guess, when known), as
    the runtime's mech.assemblies counts them: poses equal modulo 2π in the periodic
    angles and in ``turns`` (every body's rotation: a gear's, which Φ reads through its
    rolling relation, is a pose modulo 2π too) and a body turned half a turn with all else
    equal and every point a constraint places where it was (``placed``, placed_points: a
    slider reversed on its guide) count once. Returns (modes, index of the mode
    the guess reaches or None); the periodic angles come in (−π, π], the guess's mode
    first."""
    turns = sorted(set(periodic) | set(turns))
    guess = np.asarray(guess, dtype=float)
    others = [j for j in range(system.n) if j not in periodic]
    size = max([1.0] + [abs(guess[j]) for j in others])
    same = 1e-7 * (1 + size)
    found = []

    def add(q):
        w = wrap(q, periodic)
        for k, other in enumerate(found):
            if np.max(np.abs(_differ(other, w, turns)), initial=0.0) <= same:
                return k
        found.append(w)
        return len(found) - 1

    if first is None:                       # where Newton goes from the guess, if known
        q, _, _, ok = system.solve(guess)
        first = q if ok else None
    reached = None if first is None else add(first)
    if starts:
        u = halton(starts, system.n + 1)
        Q = np.repeat(guess[None, :], starts, axis=0)
        for j in periodic:
            Q[:, j] = -math.pi + 2 * math.pi * u[:, j]
        # half the starts move the positions too, picked by a dimension of their own (the
        # parity of k would pick the same half of the first coordinate's range each time)
        moved = u[:, system.n] < 0.5
        for j in others:
            Q[moved, j] = guess[j] + size * (2 * u[moved, j] - 1)
        for q in system.solve_many(Q, step=size):
            add(q)
    target = wrap(guess, periodic)

    def turned(w):
        """w with each angle turned half a turn where that still assembles and lies
        nearer the guess: the representative of a mode that the runtime keeps."""
        for j in periodic:
            v = w.copy()
            v[j] = wrap([w[j] + math.pi], [0])[0]
            if abs(math.remainder(v[j] - target[j], 2 * math.pi)) < \
                    abs(math.remainder(w[j] - target[j], 2 * math.pi)) - same and \
                    np.max(np.abs(system(v)[0]), initial=0.0) < TOL and \
                    _stays(w, v, same, placed):
                w = v
        return w

    if meshing is not None and reached is not None:     # one meshing of the gears
        keep = [k for k, w in enumerate(found) if k == reached or
                meshing.alike(w, found[reached], turns)]
        reached = keep.index(reached)
        found = [found[k] for k in keep]
    modes, mode = [], None
    for k, w in enumerate(found):
        w = w if k == reached else turned(w)
        for g, kept in enumerate(modes):
            if np.max(np.abs(_differ(kept, w, turns)), initial=0.0) <= same or \
                    _is_flip(kept, w, periodic, same, placed):
                break
        else:
            g = len(modes)
            modes.append(w)
        if k == reached:
            mode = g
    return modes, mode


def disagreeing(system, groups, starts):
    """A smallest set of constraints that cannot hold together (a deletion filter: drop
    each constraint in turn while the rest still cannot be assembled from any start).
    ``groups`` maps constraint number to its rows of Φ. Returns the constraint numbers."""
    def consistent(numbers):
        rows = [i for c in numbers for i in groups[c]]
        return any(system.solve(q, rows)[3] for q in starts)

    keep = list(groups)
    for c in list(groups):
        rest = [k for k in keep if k != c]
        if rest and not consistent(rest):
            keep = rest
    return keep


def _num(v) -> str:
    v = float(v)
    return "0" if abs(v) < 5e-13 else f"{v:.6g}"


def _mode_table(modes, reached, nearest, names, periodic):
    """The modes side by side, on the coordinates in which they differ."""
    cols = [j for j in range(len(names))
            if any(abs(_differ(modes[0], w, periodic)[j]) > 1e-7 * (1 + abs(w[j])) for w in modes)]
    if len(modes) == 1 or reached is None:     # no mode to tell apart: show all of it
        cols = list(range(len(names)))
    cells = [[str(k + 1)] + [_num(w[j]) for j in cols] for k, w in enumerate(modes)]
    header = ["mode"] + [names[j] for j in cols]
    widths = [max(len(h), *(len(r[c]) for r in cells)) for c, h in enumerate(header)]
    out = ["    " + "  ".join(h.rjust(w) for h, w in zip(header, widths))]
    for k, row in enumerate(cells):
        note = "   <- the guess reaches this one" if k == reached else \
            "   <- nearest the guess" if k == nearest else ""
        out.append("    " + "  ".join(c.rjust(w) for c, w in zip(row, widths)) + note)
    return out


def _missing(drivers, driver_rows, missing, free, owner):
    """What a model with fewer equations than coordinates lacks, in words."""
    left = f"; left free: {', '.join(f'{c} ({owner[c]})' if c in owner else c for c in free)}" \
        if free else ""
    if not drivers:
        more = f" and {missing - 1} more constraint(s) or driver(s)" if missing > 1 else ""
        return (f"  MISSING: {missing} equation(s) fewer than coordinates: add a driver "
                f"(a constraint in T){more}{left}")
    return (f"  MISSING: {missing} equation(s) fewer than coordinates: the model has "
            f"{len(drivers)} driver(s) ({driver_rows} equation(s)), so a constraint is "
            f"missing (a joint left out?), or a driver if the mechanism has more degrees of "
            f"freedom{left}")


class _Check:
    """One model checked at one time: the counts, the first assembly from the guess, and
    the lines of the report (``run`` says whether the model passes)."""

    def __init__(self, model, t, starts, cycle=True):
        self.model, self.t, self.starts, self.cycle = model, float(t), starts, cycle
        self.eq = eq = model.equations()
        self.names = [str(c) for c in eq.q]
        self.n, self.m = len(eq.q), eq.phi.rows
        self.system = System(eq, list(model.param_defaults.values()), t)
        self.guess = np.array(model.guess_vector(), dtype=float)
        self.owner = {}
        for b in model.bodies.values():
            if not b.is_ground:
                self.owner.update({str(b.x): b.name, str(b.y): b.name, str(b.th): b.name})
        self.periodic, self.shown = angle_coordinates(
            self.system, self.guess, self.names,
            {str(b.th) for b in model.bodies.values() if not b.is_ground})
        self.lines = []

    def counts(self):
        model, n, m = self.model, self.n, self.m
        drivers = model.drivers
        driver_rows = sum(len(c.exprs) for c in drivers)
        stages = getattr(model, "stages", None)
        if stages:      # each stage drives with its own rows: count those of one stage
            driver_rows = sum(len(c.exprs) for c in model.stage_view(stages[0]).drivers)
        bodies = [f"{b.name} = {b.number}" + (" (ground)" if b.is_ground else "")
                  for b in model.bodies.values()]
        self.lines += [
            f"Model {model.name}" + (f"  [{model.source}]" if getattr(model, "source", None)
                                     else ""),
            f"  bodies:       {len(model.bodies)}" + (f": {', '.join(bodies)}" if bodies else ""),
            f"  coordinates:  {n}: {', '.join(self.names)}",
            f"  equations:    {m} from {len(model.constraints)} constraints",
            f"  drivers:      {len(drivers)}" +
            "".join(f"\n    {c.number} {c.label}" for c in drivers),
            *([f"  stages:       {len(stages)}: " + ", ".join(
                f"{st.name} ({st.range_text()})" for st in stages)] if stages else []),
            f"  degrees of freedom: {n - (m - driver_rows)} ({n} coordinates - "
            f"{m - driver_rows} kinematic equations), {driver_rows} driven"]
        return drivers, driver_rows

    def run(self) -> bool:
        eq, n, m, t, lines = self.eq, self.n, self.m, self.t, self.lines
        drivers, driver_rows = self.counts()
        ok = True
        q, residual, its, converged = self.first = self.system.solve(self.guess)
        rank0, rows, cols = rank_analysis(self.system(self.guess)[1])
        if converged:
            rank, rows, cols = rank_analysis(self.system(q)[1])
        free = [self.names[j] for j in cols] if converged and rank < n else []
        if m < n:
            ok = False
            lines.append(_missing(drivers, driver_rows, n - m, free, self.owner))
        elif m > n:
            lines.append(f"  over-determined: {m - n} equation(s) more than coordinates "
                         "(redundant constraints must be consistent)")
        unused = [self.names[j] for j in range(n) if all(eq.phi_q[i, j] == 0 for i in range(m))]
        if unused:
            ok = False
            lines.append(f"  coordinates in no equation: {', '.join(unused)}")
        lines.append(f"  Jacobian rank at the guess (t = {t:g}): {rank0} of {n}")
        if converged:
            lines.append(f"  Jacobian rank assembled at t = {t:g} ({its} Gauss-Newton steps "
                         f"from the guess, residual {residual:.1e}): {rank} of {n}")
            if rows and m > rank:
                lines.append(f"  redundant: {m - rank} dependent equation(s); the dependency "
                             "involves:")
                lines += [f"    [{i + 1}] {eq.labels[i]}" for i in rows]
            if m > rank and not free:
                ok = self.rates_agree(q) and ok
            if free:
                ok = False
                lines.append(f"  free: {n - rank} coordinate direction(s) not fixed by the "
                             f"equations; coordinates left free: {', '.join(free)}")
            else:
                lines.append("  configuration reached (angles in (-pi, pi]): " + ", ".join(
                    f"{s} = {_num(v)}" for s, v in zip(self.names, wrap(q, self.shown))))
        if not free and m >= n:
            ok = self.modes() and ok
        if ok and converged and self.cycle:     # a driver that cannot turn locks later
            more, ok = whole_cycle(self.system, self.model, eq, q, t, self.shown)
            lines += more
        lines.append(_structure(eq, self.model))
        lines.append("  check: " + ("True" if ok else "False"))
        return ok

    def rates_agree(self, q) -> bool:
        """More equations than the rank: the dependent rows hold at t, but do they keep
        holding? Φ_q q̇ = ν and Φ_q q̈ = γ must be solvable too (ν and γ in the range of
        Φ_q), else the constraints agree only at this instant (a driver fighting a
        constraint or another driver, a lock on a driven body, an extra link that makes
        the linkage rigid) and the motion stops at t. False (with the rows named) then."""
        eq = self.eq
        f = sp.lambdify((list(eq.q), list(eq.qd), list(eq.params), T),
                        [list(eq.nu), list(eq.gamma)], modules="numpy", cse=True)
        params = [np.float64(v) for v in self.model.param_defaults.values()]
        J = self.system(q)[1]
        zero = np.zeros(self.n)
        with np.errstate(all="ignore"):
            nu = np.array(f(list(q), list(zero), params, np.float64(self.t))[0], dtype=float)
            qd = np.linalg.lstsq(J, nu, rcond=None)[0]
            gamma = np.array(f(list(q), list(qd), params, np.float64(self.t))[1], dtype=float)
            qdd = np.linalg.lstsq(J, gamma, rcond=None)[0]
        for what, rhs, x in (("velocities", nu, qd), ("accelerations", gamma, qdd)):
            if not np.all(np.isfinite(rhs)):
                continue
            r = rhs - J @ x
            scale = 1 + np.max(np.abs(rhs)) + np.max(np.abs(J)) * np.max(np.abs(x))
            if np.max(np.abs(r)) <= 1e-8 * scale:
                continue
            rows = np.flatnonzero(np.abs(r) > 1e-3 * np.max(np.abs(r)))
            self.lines.append(
                f"  CANNOT MOVE from t = {self.t:g}: the redundant equations hold here but "
                f"their {what} disagree "
                f"(Phi_q {'qd = nu' if what == 'velocities' else 'qdd = gamma'} "
                f"has no solution, residual {np.max(np.abs(r)):.3g}): a driver fights a "
                "constraint or another driver, or an extra constraint locks the motion; "
                "remove or correct one of:")
            self.lines += [f"    [{i + 1}] {eq.labels[i]}" for i in rows]
            return False
        return True

    def modes(self) -> bool:
        """The assembly modes at t, or why there is none; False when the guess reaches
        none."""
        t, periodic, lines = self.t, self.periodic, self.lines
        q, residual, its, converged = self.first
        meshing = Meshing(self.eq, self.model.param_defaults.values(), t, self.system) \
            if mesh_counts(self.eq) else None
        modes, reached = assembly_modes(self.system, self.guess, periodic, self.starts,
                                        first=q if converged else None, turns=self.shown,
                                        meshing=meshing,
                                        placed=placed_points(self.model, self.eq, t))
        if not modes:
            return self.contradiction()
        target = wrap(self.guess, periodic)
        nearest = min(range(len(modes)), key=lambda k: np.max(np.abs(
            _differ(target, modes[k], periodic))))
        same = "; angles equal modulo 2 pi count once" if periodic else ""
        lines.append(f"  assembly modes at t = {t:g}: {len(modes)} found (from the guess and "
                     f"{self.starts} other starts{same})" +
                     (f"; the guess reaches mode {reached + 1}" if reached is not None else ""))
        if len(modes) > 1 or reached is None:
            lines += _mode_table(modes, reached, nearest if nearest != reached else None,
                                 self.names, periodic)
        if reached is not None and nearest != reached:
            lines.append(f"  note: mode {nearest + 1} lies nearer the guess than mode "
                         f"{reached + 1}, which Newton reaches from it: check the guesses "
                         "(--guess NAME=VALUE picks a mode at run time)")
        if converged:
            return True
        lines.append(f"  CANNOT ASSEMBLE from the guess at t = {t:g} (residual {residual:.2g} "
                     f"after {its} steps): start it near one of the modes above")
        return False

    def contradiction(self) -> bool:
        """No assembly at all: name a smallest set of constraints that cannot hold
        together."""
        groups = {}
        for i, (number, _) in enumerate(self.eq.rows):
            groups.setdefault(number, []).append(i)
        culprits = disagreeing(self.system, groups, [self.guess, self.first[0]])
        self.lines += [
            f"  CANNOT ASSEMBLE at t = {self.t:g}: no configuration from the guess (residual "
            f"{self.first[1]:.2g}) or from {self.starts} other starts.",
            f"  These {len(culprits)} constraints contradict each other (redundant "
            "constraints that disagree, or a loop that cannot close); correct or remove one "
            "of them:"]
        by_number = {c.number: c for c in self.model.constraints}
        self.lines += [f"    {c} {by_number[c].label}" for c in culprits]
        self.lines += loop_dimensions(self.model, [by_number[c] for c in culprits], self.t)
        return False


def check_report(model, t=0.0, starts=STARTS, cycle=True) -> tuple[str, bool]:
    """Mech's CheckSystem and more. Returns (text, ok).

    ok is False when equations are missing, the Jacobian is rank-deficient at the
    assembled configuration (a coordinate left free), the model cannot be assembled
    at t (constraints that contradict each other, or a guess from which no mode is
    reached), or redundant equations that hold at t disagree in their velocities or
    accelerations (they cannot keep holding: the motion stops at t); redundant but
    consistent equations are reported, not failed. ``cycle``: the assembly followed from
    t through one period of the drivers that turn at a constant rate (cycle_check); ok is
    False where it locks (a driver that cannot turn), and the report says when a model
    was checked at t only.
    """
    holding = held(model)
    check = _Check(holding, t, starts, cycle)
    ok = check.run()
    check.lines += [f"  note: {doubt}" for doubt in model.load_doubts()]
    if holding is not model:
        held_rows = [c.args_text.split(",")[0] for c in holding.constraints[
            len(model.constraints):]]
        check.lines.insert(1, f"  no driver for {', '.join(held_rows)}: held at the guess "
                              "for the kinematics; mech.simulate releases "
                              f"{'it' if len(held_rows) == 1 else 'them'} (motion under "
                              "the model's forces)")
    return "\n".join(check.lines) + "\n", ok


_METHOD_WORDS = {EXPLICIT: "explicit", DYAD_RRR: "RRR dyad", CLOSED_FORM_TRIG: "closed form",
                 CLOSED_FORM_QUADRATIC: "closed form", NEWTON: "Newton"}


def _structure(eq, model) -> str:
    """The blocks as the module solves them (its plan, made at the model's guess as a
    build makes it: explicit, closed forms, dyads, Newton), the blocks whose assembly mode
    is a sign kept from the guess counted."""
    plan = make_plan(model, eq, level="position")
    if not plan.sorted:
        return ("  structure: no block sorting (not square or structurally singular); "
                "full Newton only")
    blocks = plan.blocks
    kinds = {}
    for b in blocks:
        word = _METHOD_WORDS[b.method]
        kinds[word] = kinds.get(word, 0) + 1
    signs = sum(b.method == DYAD_RRR or signed(b.method, b.form) for b in blocks)
    tail = (f"; {signs} with an assembly mode the guess picks (a sign)" if signs else "")
    count = f"{len(blocks)} block" + ("s" if len(blocks) != 1 else "")
    return (f"  structure: {count} as the module solves them (" +
            ", ".join(f"{v} {k}" for k, v in kinds.items()) + ")" + tail)
