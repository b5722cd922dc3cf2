"""Motion under forces (docs/reference/simulation.md): ``mech.simulate(t0, t1, n,
free=[driver names])``.

The drivers named in ``free`` stop prescribing their motion at t0 (and the ``hold`` rows
that the build gives a model without a driver for every degree of freedom always do); the
others keep theirs. The equations of motion are the index-1 form of M q̈ + Φ_Cᵀ λ = Q,
Φ_C(q, t) = 0 (C: every constraint row but the freed ones): at a state (q, q̇) the
module's ``free_accelerations`` gives q̈ and λ (by the sorted blocks and a reduced system
as small as the freedoms released, else by M's Cholesky factor, else the whole saddle
point; see DESIGN.md). The module's ``integrate_span`` (the default, "dopri5": the
Dormand–Prince 5(4) pair and error control of scipy's RK45, compiled with the right side)
or scipy's ``solve_ivp`` (any other method) integrates (q, q̇) from one output time to
the next. At every output time the state is put back on the constraints (Gauss-Newton on
Φ_C = 0, minimum-norm steps, then q̇ onto Φ_C q̇ = ν_C), so the positions satisfy Φ = 0 to
the solver's tolerance at every output and nothing drifts from one interval into the next.

Why this method: it needs nothing the module does not already have (Φ_q, γ, the force
terms) and no choice of independent coordinates, so it cannot be caught by a choice
going singular (a crank's toggle, a dead centre only for a driver, is passed); a
configuration where the constraints still acting lose rank (a lock) stops the
integration with a SingularError naming the time and the constraints. Rows that are
redundant (dependent at every configuration: a planetary set with two planets) leave the
motion determined: q̈ then comes from the least-squares form (_System.redundant), λ the
minimum-norm multipliers, integrated by scipy's RK45. The result is a
ForceSweep at level "dynamic": positions, velocities, accelerations, the multipliers of
the constraints still acting (0 on the freed rows), the efforts of the drivers still
prescribed, power() and energy() to show what the integration conserved, and
``simulation`` (how it was integrated: extrema() and roots() refine on it).
"""
from __future__ import annotations

import warnings

import numpy as np

from ...errors import ConvergenceError, SingularError
from ..guards import positive_tol, sweep_times
from ..kinematics.guesses import start_vector
from ..kinematics.solving import solve
from ...protocol import SING_RTOL
from .lookup import _constraints_of, division_error, loads_guarded, tables
from .points import CONSISTENT_RTOL, svd_solve
from .sweep import ForceSweep

PROJECT_TOL = 1e-12     # |Φ_C| (relative to the mechanism's size) after the projection
PROJECT_MAXIT = 25
REDUNDANT_RTOL = 1e-10  # rows dependent to this share of the largest singular value (the
                        # row-equilibrated Φ_C's) are redundant, not a lock approached
INTERVAL_EVALUATIONS = 200_000   # evaluations between two output times before giving up
SIMULATE_POINTS = 100_000        # what an integration counts as, for the tiers' choice
COMPILED = "dopri5"              # the module's own integrator (integrate_span)


class _Stalled(Exception):
    """The integrator spent its evaluations before the next output (a load switching on
    and off, or a motion running away); ``y`` the state it had reached."""

    def __init__(self, t, y=None):
        super().__init__(t)
        self.t = float(t)
        self.y = y


class _System:
    """The rows kept, and the module's functions at one parameter vector."""

    def __init__(self, mech, free):
        self.mech, self.mod, self.p = mech, mech.module, mech.p
        self.n, self.m = mech.n, mech.m
        self.keep = np.ones(self.m, dtype=np.bool_)
        tab = tables(mech)
        if not tab.forces:
            raise ValueError(f"simulate: model '{mech.name}' has no masses and no loads: "
                             "nothing moves it (give its bodies mass=, inertia=)")
        if isinstance(free, str):
            free = [free]
        # the rows the build added to hold a model's undriven coordinates at the guess
        # (mechgen.model.forces.holds) always let go: they are no drivers of the user's
        for k, (_, kind, *_rest) in enumerate(mech.module.CONSTRAINTS):
            if kind == "hold":
                self.keep[list(tab.constraint(_rest[0], mech)[1])] = False
        for name in free or ():
            label, rows, driver = tab.constraint(name, mech)
            if not driver:
                raise ValueError(f"simulate: free={name!r}: constraint {label!r} is not a "
                                 "driver (its equations do not hold T)")
            self.keep[list(rows)] = False
        self.c = int(self.keep.sum())
        self.calls = 0
        self.dependent = set()      # rows whose λ is not unique (redundant), once met
        self.J = np.empty((self.m, self.n))
        self.r = np.empty(self.m)

    def accelerations(self, q, qd, t):
        qdd, lam = np.empty(self.n), np.empty(self.m)
        rank = self.mod.free_accelerations(q, qd, float(t), self.p, self.keep, qdd, lam)
        if rank < self.n + self.c:
            found = self.redundant(q, qd, t)
            if found is None:
                raise self.singular(q, t, f" ({rank} of {self.n + self.c})")
            return found
        return qdd, lam

    def redundant(self, q, qd, t):
        """(q̈, λ) where the rows kept are redundant (dependent at every configuration, as
        the meshes of a planetary set with two planets) and the motion still determined:
        q̈ = q̈_p + Z y, q̈_p the least-squares solution of Φ_C q̈ = γ_C, Z the motions
        Φ_C allows and Zᵀ M Z y = Zᵀ (Q − h − M q̈_p); λ the minimum-norm solution of
        Φ_Cᵀ λ = Q − h − M q̈ (as a force solve gives). None where Φ_C q̈ = γ_C has no
        solution (a lock) or M is singular on Z (a motion without mass)."""
        n, t = self.n, float(t)
        q, qd = np.asarray(q, dtype=np.float64), np.asarray(qd, dtype=np.float64)
        J = self.jacobian(q, t).copy()
        g = np.empty(self.m)
        self.mod.gamma(q, qd, t, self.p, g)
        g = g[self.keep]
        M = np.empty((n, n))
        self.mod.mass_matrix(q, t, self.p, M)
        terms = np.empty((3, n))
        self.mod.force_terms(q, qd, np.zeros(n), t, self.p, terms)
        f = terms[0] + terms[1] - terms[2]
        scale = np.max(np.abs(J), axis=1, initial=0.0)
        scale[scale == 0] = 1.0
        sv = np.linalg.svd(J / scale[:, None], compute_uv=False)
        top = sv[0] if sv.size and sv[0] > 0 else 1.0
        rank = int(np.sum(sv > REDUNDANT_RTOL * top))
        if rank == J.shape[0]:
            return None         # rows near dependence, not dependent: a lock, approached
        u, s, vt = np.linalg.svd(J)
        k = min(rank, s.size)
        qdd = vt[:k].T @ ((u[:, :k].T @ g) / s[:k])
        if not np.linalg.norm(J @ qdd - g) <= CONSISTENT_RTOL * (
                np.linalg.norm(g) + np.linalg.norm(np.abs(J) @ np.abs(qdd)) + 1e-300):
            return None                         # the rows lock: no acceleration fits them
        Z = vt[k:].T
        if Z.shape[1]:
            W = Z.T @ M @ Z
            w = np.linalg.eigvalsh(W)
            size = max(float(np.abs(np.diag(M)).max(initial=0.0)), 1e-300)
            if not w.min() > SING_RTOL * size:
                return None                     # a motion without mass or inertia
            qdd = qdd + Z @ np.linalg.solve(W, Z.T @ (f - M @ qdd))
        lam_c, _, dependent, consistent = svd_solve(J, f - M @ qdd)
        if not consistent:
            return None
        rows = np.flatnonzero(self.keep)
        self.dependent.update(int(rows[i]) for i in dependent)
        lam = np.zeros(self.m)
        lam[self.keep] = lam_c
        return qdd, lam

    def singular(self, q, t, rank=""):
        """The SingularError of a rank loss at (q, t), its cause named (why)."""
        constraints, why = self.why(q, t)
        return SingularError(f"simulate: model '{self.mech.name}' at t={t:.9g}: the "
                             f"equations of motion lose rank{rank}: {why}", t=float(t),
                             constraints=constraints, level="dynamic", q=np.array(q))

    def why(self, q, t):
        """(constraints, text) of a rank loss of the equations of motion at (q, t): the
        constraints still acting whose equations become dependent (a lock or toggle, or
        redundant constraints), else the coordinates free to move without mass."""
        from ..analysis.singular import support, unique, constraint_of_rows, scaled_jacobian
        J = scaled_jacobian(self.mech, q, t)[self.keep]
        rows = np.flatnonzero(self.keep)
        u, sv, vt = np.linalg.svd(J)
        k = J.shape[0]                           # the weakest direction of the rows kept
        ratio = float(sv[k - 1] / sv[0]) if k and sv[0] > 0 else 0.0
        M = np.empty((self.n, self.n))
        self.mod.mass_matrix(np.asarray(q, dtype=float), float(t), self.p, M)
        free = vt[k:].T                                      # motions the constraints allow
        w, v = np.linalg.eigh(free.T @ M @ free) if free.shape[1] else (np.ones(1), None)
        scale = max(float(np.abs(np.diag(M)).max(initial=0.0)), 1e-300)
        if v is None or ratio <= float(w.min()) / scale:
            owner = constraint_of_rows(self.mech)
            names = unique(owner[rows[i]] for i in support(u[:, k - 1:k], axis=1))
            return names, ("the constraints still acting lock there (or are redundant): "
                           + "; ".join(names))
        still = free @ v[:, :1]
        coords = [self.mech.coordinates[j] for j in support(still, axis=1)]
        return (), ("a motion the constraints allow carries no mass or inertia (of "
                    f"{', '.join(coords)}): give those bodies mass=, inertia=")

    def rhs(self, t, y):
        n = self.n
        self.calls += 1
        if self.calls > INTERVAL_EVALUATIONS:
            raise _Stalled(t, np.array(y, dtype=np.float64))
        qdd, _ = self.accelerations(y[:n], y[n:], t)
        return np.concatenate([y[n:], qdd])

    def _settle(self, q, t, size, cols):
        """Newton on Φ_C(q) = 0 in place, correcting the columns ``cols`` of q (minimum
        norm): whether it converged."""
        for _ in range(PROJECT_MAXIT):
            r = self.residual(q, t)
            if not np.all(np.isfinite(r)):
                raise ConvergenceError(f"simulate: model '{self.mech.name}' at t={t:.9g}: "
                                       "the constraints are not finite at the state reached",
                                       t=float(t))
            if np.max(np.abs(r), initial=0.0) <= PROJECT_TOL * size:
                return True
            q[cols] -= np.linalg.lstsq(self.jacobian(q, t)[:, cols], r, rcond=None)[0]
        return False

    def switches(self) -> np.ndarray:
        """The switch times of the stages whose rows still act (none where every stage
        row is freed)."""
        times = np.asarray(getattr(self.mod, "SWITCH_TIMES", ()), dtype=np.float64)
        row = 0
        for _, kind, _, count, _ in self.mod.CONSTRAINTS:
            if kind == "stages" and self.keep[row:row + count].any():
                return times
            row += count
        return times[:0]

    def switch(self, q, qd, t, size):
        """(q, q̇) just after a stage switch at t: q on the later stage's rows (they agree
        in position) and q̇ changed by an impulse through the rows still acting, the least
        change in kinetic energy, ½ Δq̇ᵀ M Δq̇, that meets Φ_C q̇ = ν_C of the later stage:
        [M Φ_Cᵀ; Φ_C 0] (q̇⁺, −μ) = (M q̇⁻, ν_C) (a free pendulum keeps its momentum about
        the cart whose prescribed speed jumps)."""
        q, _, _ = self.project(q, qd, t, size)
        n = self.n
        M = np.empty((n, n))
        self.mod.mass_matrix(q, t, self.p, M)
        J = self.jacobian(q, t)
        nu = np.empty(self.m)
        self.mod.nu(q, t, self.p, nu)
        c = J.shape[0]
        A = np.block([[M, J.T], [J, np.zeros((c, c))]])
        x = np.linalg.lstsq(A, np.concatenate([M @ qd, nu[self.keep]]), rcond=None)[0]
        return q, x[:n]

    def residual(self, q, t):
        self.mod.phi(q, float(t), self.p, self.r)
        return self.r[self.keep]

    def jacobian(self, q, t):
        self.mod.phi_q(q, float(t), self.p, self.J)
        return self.J[self.keep]

    def project(self, q, qd, t, size, held=(), held_rates=()):
        """(q, q̇) put back on Φ_C = 0 and Φ_C q̇ = ν_C (minimum-norm corrections); the
        size of the position correction. ``held``: indices of coordinates the corrections
        leave as they are where the others alone can satisfy Φ_C (those a user named in
        q0); else every coordinate moves. ``held_rates``: the same for the velocities (those
        a user named in qd0)."""
        q, qd = q.copy(), qd.copy()
        start = q.copy()
        loose = [j for j in range(self.n) if j not in held]
        if not (held and loose and self._settle(q, t, size, loose)):
            q[:] = start
            if not self._settle(q, t, size, slice(None)):
                raise ConvergenceError(f"simulate: model '{self.mech.name}' at t={t:.9g}: "
                                       "the state could not be put back on the constraints",
                                       t=float(t))
        J = self.jacobian(q, t)
        nu = np.empty(self.m)
        self.mod.nu(q, float(t), self.p, nu)
        nu = nu[self.keep]
        loose = [j for j in range(self.n) if j not in held_rates]
        if held_rates and loose:                # the named rates kept where the rest can
            trial = qd.copy()
            trial[loose] -= np.linalg.lstsq(J[:, loose], J @ qd - nu, rcond=None)[0]
            scale = 1.0 + float(np.max(np.abs(nu), initial=0.0)) \
                + float(np.max(np.abs(J), initial=0.0)) * float(np.max(np.abs(qd)))
            if np.max(np.abs(J @ trial - nu), initial=0.0) <= 1e-10 * scale:
                return q, trial, float(np.max(np.abs(q - start), initial=0.0))
        qd -= np.linalg.lstsq(J, J @ qd - nu, rcond=None)[0]
        return q, qd, float(np.max(np.abs(q - start), initial=0.0))


def _check_accuracy(rtol, atol, max_step):
    """ValueError unless rtol and atol are finite and positive and max_step positive: the
    compiled integrator would take a negative tolerance (and return a motion that is not
    as accurate as asked) and a zero atol (0/0 on a coordinate that stays 0, then an
    error about something else)."""
    positive_tol(rtol, "simulate: rtol")
    positive_tol(atol, "simulate: atol")
    try:
        ok = float(max_step) > 0.0
    except (TypeError, ValueError):
        ok = False
    if not ok:
        raise ValueError(f"simulate: max_step must be above 0 (inf: no limit), got "
                         f"{max_step!r}")


def _named_rates(mech, rates, qd):
    """(q̇, indices named) from qd0 given as a dict: velocity names ("Th2d") or the
    coordinates' own ("Th2"); the rates not named keep qd's."""
    qd = qd.copy()
    named = []
    for key, value in rates.items():
        name = key[:-1] if isinstance(key, str) and key not in mech.state.index \
            and key.endswith("d") else key
        if name not in mech.state.index:
            raise ValueError(f"simulate: qd0: {key!r} is not a velocity of '{mech.name}' "
                             f"(velocities: {', '.join(c + 'd' for c in mech.coordinates)})")
        try:
            v = float(value)
        except (TypeError, ValueError):
            v = float("nan")
        if not np.isfinite(v):
            raise ValueError(f"simulate: qd0: {key!r} must be a finite number, got {value!r}")
        qd[mech.state.index[name]] = v
        named.append(mech.state.index[name])
    return qd, named


RUNAWAY_TURNS = 100     # a body turned this often between two outputs, faster at the end


def _runaway(mech, t, t_a, y_a, y):
    """The sentence of a motion that runs away, or None: between the output at t_a (state
    y_a) and the stall at t (state y) a body turned RUNAWAY_TURNS times or more and turns
    faster at t than at t_a (the integrator spent its steps on ever faster turns, not on
    a load switching at one time); the fastest such body is named."""
    if y_a is None or y is None or not np.all(np.isfinite(y)):
        return None
    n, best = mech.n, None
    for name, idx in tables(mech).bodies.items():
        if idx is None:
            continue
        th = idx[2]
        turns = abs(float(y[th] - y_a[th])) / (2.0 * np.pi)
        w, w_a = float(y[n + th]), float(y_a[n + th])
        if turns >= RUNAWAY_TURNS and abs(w) > abs(w_a) and \
                (best is None or abs(w) > abs(best[1])):
            best = (name, w, w_a, turns)
    if best is None:
        return None
    name, w, w_a, turns = best
    return (f"simulate: model '{mech.name}': the motion runs away near t={t:.9g}: body "
            f"'{name}' turns at {w:.4g} rad/s there ({w_a:.4g} rad/s at t={t_a:.6g}, "
            f"{turns:,.0f} turns since), its speed growing without bound: a load feeds "
            "energy in as the mechanism speeds up (a motor whose torque grows with its "
            "speed: T = Tm (1 − ω/wm) with Tm < 0, say); check the loads' signs")


def _stalled(mech, t, t_a, t_b, y_a=None, y=None):
    """The ConvergenceError of an integration that spent INTERVAL_EVALUATIONS between two
    outputs: a motion running away (_runaway, from the states at t_a and at t), else a
    load that chatters."""
    away = _runaway(mech, t, t_a, y_a, y)
    if away:
        return ConvergenceError(away, t=t)
    return ConvergenceError(
        f"simulate: model '{mech.name}': the integration stalled near t={t:.9g} "
        f"({INTERVAL_EVALUATIONS:,} evaluations between the outputs at {t_a:.6g} and "
        f"{t_b:.6g}): a load that switches on and off there (a press stalling on its work, "
        "say) chatters; smooth it, or change the loads", t=t)


SCIPY_METHODS = ("RK45", "RK23", "DOP853", "Radau", "BDF", "LSODA")   # solve_ivp's by name


def _scipy_span(system, y, t_a, t_b, method, rtol, atol, max_step):
    """(y at t_b, steps, evaluations) by scipy's solve_ivp."""
    from scipy.integrate import solve_ivp
    system.calls = 0
    try:
        sol = solve_ivp(system.rhs, (t_a, t_b), y, method=method, rtol=rtol, atol=atol,
                        max_step=max_step)
    except _Stalled as stall:
        raise _stalled(system.mech, stall.t, t_a, t_b, y, stall.y) from None
    if sol.status != 0:
        raise ConvergenceError(f"simulate: model '{system.mech.name}': the integration "
                               f"stopped at t={sol.t[-1]:.9g}: {sol.message}",
                               t=float(sol.t[-1]))
    return sol.y[:, -1], max(len(sol.t) - 1, 0), sol.nfev


def _compiled_span(system, rtol, atol, max_step):
    """A function (y, t_a, t_b) -> (y at t_b, steps, evaluations) by the module's
    integrate_span (Dormand–Prince 5(4), compiled), carrying its step from one span to
    the next."""
    mod = system.mod
    if not hasattr(mod, "integrate_span"):
        raise ValueError(f"simulate: method={COMPILED!r} needs a module built by this "
                         "version of mechgen (build the model again)")
    stats = np.zeros(4)

    def span(y, t_a, t_b):
        y_a = np.array(y, dtype=np.float64)
        y = y_a.copy()
        code = mod.integrate_span(y, t_a, t_b, system.p, system.keep, float(rtol),
                                  float(atol), float(max_step), INTERVAL_EVALUATIONS, stats)
        t = float(stats[3])
        if code == 1 and not (np.isfinite(t) and np.all(np.isfinite(y))):
            # not a rank loss: the state went NaN, the forces were not finite on the way
            raise division_error(system.mech, f"between t={t_a:.10g} and t={t_b:.10g}")
        if code == 1:
            raise system.singular(y[:system.n], t)
        if code == 2:
            raise _stalled(system.mech, t, t_a, t_b, y_a, y)
        if code == 3:
            raise ConvergenceError(f"simulate: model '{system.mech.name}': the step fell "
                                   f"below round-off at t={t:.9g}", t=t)
        return y, int(stats[1]), int(stats[2])
    return span


def simulate(mech, t0, t1, n, free=(), q0=None, qd0=None, rtol=1e-8, atol=1e-10,
             method=COMPILED, max_step=np.inf, progress=None) -> ForceSweep:
    """See Mechanism.simulate: the public call, forward in time (t1 before t0 is a
    ValueError); ``integrate`` does the work, in either direction."""
    ts = sweep_times(t0, t1, n)
    if ts[-1] < ts[0]:
        raise ValueError(f"simulate: t1 = {ts[-1]:g} is before t0 = {ts[0]:g}: the motion "
                         "is integrated forward in time from the state at t0; give t0 < t1")
    return integrate(mech, t0, t1, n, free=free, q0=q0, qd0=qd0, rtol=rtol, atol=atol,
                     method=method, max_step=max_step, progress=progress)


@loads_guarded(span=True)
def integrate(mech, t0, t1, n, free=(), q0=None, qd0=None, rtol=1e-8, atol=1e-10,
              method=COMPILED, max_step=np.inf, progress=None) -> ForceSweep:
    """simulate's integration, forward or backward in time (t1 before t0: the refinement
    of a simulated sweep's extremes integrates back from an output, through the result's
    ``simulation["integrate"]``, runtime.analysis.events)."""
    ts = sweep_times(t0, t1, n)
    _check_accuracy(rtol, atol, max_step)
    if not (method == COMPILED or method in SCIPY_METHODS or isinstance(method, type)):
        raise ValueError(f"simulate: no integration method {method!r}: give {COMPILED!r} "
                         f"(compiled Dormand–Prince) or one of scipy's solve_ivp methods "
                         f"({', '.join(SCIPY_METHODS)})")
    system = _System(mech, free)
    # an integration makes thousands of calls: in the python tier of "auto", compiled first
    mech.state.tiers.expect(mech, SIMULATE_POINTS, "simulate")
    system.mod = mech.module
    t_start = float(ts[0])
    if q0 is None:                  # the drivers' state at t0, all of them still acting
        with mech.state.lock:       # (mech.solve(t_start, level="velocity"))
            kin = solve(mech.state, t_start, None, "velocity", None, None, None)
        q, qd = kin.q.copy(), kin.qd.copy()
    else:
        q, qd = start_vector(mech, q0), np.zeros(mech.n)
    held_rates = ()
    if isinstance(qd0, dict):
        qd, held_rates = _named_rates(mech, qd0, qd)
    elif qd0 is not None:
        try:
            qd = np.asarray(qd0, dtype=float).reshape(-1).copy()
        except (TypeError, ValueError):
            qd = None
        if qd is None or qd.shape != (mech.n,) or not np.all(np.isfinite(qd)):
            raise ValueError(f"simulate: qd0 must be {mech.n} finite velocities (one per "
                             f"coordinate: {', '.join(mech.coordinates)}) or a dict of "
                             "them by name ({'Th2d': 5.0})")
    size = 1.0 + float(np.max(np.abs(mech.points_at(q, t_start))))
    qd_in = qd.copy()
    index = mech.state.index
    held = [index[c] for c in q0 if c in index] if isinstance(q0, dict) else ()
    q, qd, moved = system.project(q, qd, t_start, size, held, held_rates)
    if q0 is not None or qd0 is not None:
        moved_rates = held_rates if held_rates else slice(None)   # a dict: what it named
        dv = float(np.max(np.abs(qd[moved_rates] - qd_in[moved_rates]), initial=0.0))
        if moved > 1e-9 * size or dv > 1e-9 * (1.0 + float(np.max(np.abs(qd_in)))):
            warnings.warn(f"simulate: the initial state was made consistent with the "
                          f"constraints still acting (positions moved by up to {moved:.3g}, "
                          f"velocities by up to {dv:.3g})", stacklevel=5)
    N = ts.shape[0]
    Q, QD, QDD = np.empty((N, mech.n)), np.empty((N, mech.n)), np.empty((N, mech.n))
    LAM = np.empty((N, mech.m))
    Q[0], QD[0] = q, qd
    QDD[0], LAM[0] = system.accelerations(q, qd, t_start)
    steps = evaluations = 0
    span = _compiled_span(system, rtol, atol, max_step) if method == COMPILED else None
    switches = system.switches()

    def advance(y, t_a, t_b):
        nonlocal span, method, steps, evaluations
        if span is not None:
            try:
                y, taken, calls = span(y, t_a, t_b)
            except SingularError:
                # the compiled path refuses rows that are redundant; where the motion is
                # still determined (_System.redundant), scipy's RK45 (the same pair)
                # integrates on the least-squares accelerations
                if system.redundant(y[:mech.n], y[mech.n:], t_a) is None:
                    raise
                span, method = None, "RK45"
        if span is None:
            y, taken, calls = _scipy_span(system, y, t_a, t_b, method, rtol, atol, max_step)
        steps += taken
        evaluations += calls
        return y

    for k in range(1, N):
        t_a, t_b = float(ts[k - 1]), float(ts[k])
        y = np.concatenate([q, qd])
        for t_s in switches[(switches > min(t_a, t_b)) & (switches <= max(t_a, t_b))]:
            if t_b < t_a:
                break               # (backwards: no switch is crossed the other way)
            # a stage of the rows still acting takes over: up to its switch on the earlier
            # stage, then the impulse that its velocities ask for
            y = advance(y, t_a, float(np.nextafter(t_s, -np.inf)))
            y = np.concatenate(system.switch(y[:mech.n], y[mech.n:], float(t_s), size))
            t_a = float(t_s)
        if t_a != t_b:
            y = advance(y, t_a, t_b)
        q, qd, _ = system.project(y[:mech.n], y[mech.n:], ts[k], size)
        Q[k], QD[k] = q, qd
        QDD[k], LAM[k] = system.accelerations(q, qd, ts[k])
        if progress is not None:
            progress(float(ts[k]))
    out = ForceSweep(mech, ts, Q, QD, QDD, np.zeros((N, 1), dtype=np.int16))
    out.force_level = "dynamic"
    out.LAM = LAM
    out.FACTORS = np.zeros((N, len(tables(mech).driver_rows)))
    for k in range(N):
        if out.FACTORS.shape[1]:
            mech.module.driver_factors(Q[k], float(ts[k]), mech.p, out.FACTORS[k])
    out.force_singular = np.zeros(N, dtype=bool)
    labels = mech.constraint_labels
    out.indeterminate = _constraints_of(mech, {labels[i] for i in system.dependent})
    out.free = tuple(mech.constraint_labels[i] for i in np.flatnonzero(~system.keep))
    out.steps, out.evaluations = steps, evaluations
    out.simulation = dict(free=tuple(free) if not isinstance(free, str) else (free,),
                          rtol=rtol, atol=atol, method=method, max_step=max_step,
                          integrate=integrate)
    return out
