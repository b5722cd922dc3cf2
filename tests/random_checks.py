"""The judge of tests/test_random_mechanisms.py and benchmarks/random_mechanisms.py: runs a
random mechanism of tests/random_families.py through mechgen (a sweep at a level and
method, single solves with and without a guess, a design table on a backend) and sorts
every answer against the closed form as right, refused or wrong.

The contract judged (issue 20): the mode is fixed by the start; a point with status OK
equals the closed form of that mode at its time (angles modulo 2 pi; positions to 1e-8,
velocities 1e-7, accelerations 1e-6, each relative to the size of the quantity over the
run); a flagged point (JUMP, THROUGH_SINGULAR) or a failed solve is a refusal, and the
point after a flag may start a new branch; a lock window (a time where the mode cannot
assemble) ends the branch, so an OK point past one is wrong. A sweep that raises is
refused (the points it returned before raising are still judged); a run that raises
anything else "crashed" (guarded). Refusing is not free: answered() counts the points a
run's mode reaches from its start without a lock window (the closed form assembles all
the way), and how many of them were answered right; a code that refuses everything
answers none of them."""
from __future__ import annotations

from collections import Counter
from dataclasses import dataclass, field

import numpy as np

import mechgen
from mechgen.protocol import OK

TOL = (1e-8, 1e-7, 1e-6)          # positions, velocities, accelerations (relative)
LEVELS = ("position", "velocity", "acceleration")
METHODS = ("auto", "sorted", "full")
REFUSALS = (mechgen.ConvergenceError, mechgen.SingularError)


@dataclass
class Verdict:
    """One run (a sweep, a design, a single solve): its outcome and the first wrong point."""
    outcome: str = "right"            # right, refused, wrong, crashed
    points: Counter = field(default_factory=Counter)
    detail: str = ""

    def wrong(self, msg):
        if self.outcome != "wrong":
            self.detail = msg
        self.outcome = "wrong"
        self.points["wrong"] += 1


def wrap(dq, mask):
    dq = np.array(dq, dtype=float)
    dq[..., mask] = np.remainder(dq[..., mask] + np.pi, 2 * np.pi) - np.pi
    return dq


def _scales(refs, upto):
    """Per level: 1 + the largest |value| of any mode over the run (NaN-free)."""
    out = []
    for lev in range(upto + 1):
        vals = [np.nanmax(np.abs(r[lev])) if np.isfinite(r[lev]).any() else 0.0
                for r in refs.values()]
        out.append(1.0 + max(vals))
    return out


def _errors(fam, refs, arrs, upto, scales):
    """mode -> per point, the largest error relative to its tolerance (> 1: off)."""
    errs = {}
    for s, ref in refs.items():
        e = np.zeros(len(arrs[0]))
        for lev in range(upto + 1):
            d = arrs[lev] - ref[lev]
            if lev == 0:
                d = wrap(d, fam.angle_mask)
            with np.errstate(invalid="ignore"):
                r = np.max(np.abs(d), axis=-1) / (TOL[lev] * scales[lev])
            e = np.maximum(e, np.where(np.isnan(r), np.inf, r))
        errs[s] = e
    return errs


def locks_between(fam, p, ts, sigma, sub=24, fine=20000):
    """For each step k -> k + 1 of times ts (and the point itself): whether the mechanism
    cannot assemble somewhere in [t_k, t_k+1] (a fine grid of the closed form's
    discriminant of mode sigma). Returns (at, between)."""
    at = fam.disc(p, ts, sigma) < 0
    if len(ts) < 2:
        return at, np.zeros(0, dtype=bool)
    m = max(sub, fine // len(ts))
    u = np.linspace(0.0, 1.0, m)
    grid = ts[:-1, None] + (ts[1:] - ts[:-1])[:, None] * u[None, :]
    between = (fam.disc(p, grid.ravel(), sigma).reshape(grid.shape) < 0).any(axis=1)
    return at, between


def reachable_count(fam, p, t0, ts, sigma):
    """How many of the times ts mode sigma reaches from t0 without a lock window between
    (its discriminant on a fine grid from t0 out to the farthest time, each way)."""
    ts = np.asarray(ts, dtype=float)
    count = 0
    for side in (ts >= t0, ts < t0):
        if not side.any():
            continue
        far = ts[side].max() if ts[side][0] >= t0 else ts[side].min()
        m = max(64, int(4000 * abs(far - t0) / fam.period(p)) + 2)
        grid = np.linspace(t0, far, m)
        bad = np.flatnonzero(fam.disc(p, grid, sigma) < 0)
        stop = grid[bad[0]] if bad.size else None
        if stop is None:
            count += int(side.sum())
        elif far >= t0:
            count += int(np.sum(side & (ts < stop)))
        else:
            count += int(np.sum(side & (ts > stop)))
    return count


def answered(verdicts):
    """(points answered right, points their mode reaches from the start) over verdicts
    judged against a given mode (points["reachable"]): the share a judge bounds."""
    right = sum(min(v.points["right"], v.points["reachable"]) for v in verdicts)
    return right, sum(v.points["reachable"] for v in verdicts)


def judge(fam, p, ts, Q, QD=None, QDD=None, status=None, sigma=None, raised=False,
          what="", planned=None, t0=None):
    """Sort the points of a (possibly partial) sweep; ``sigma``: the mode the start
    fixes (None: the mode its first point is on). With sigma, points["reachable"] counts
    the times asked for (``planned``, else ts) that sigma reaches from ``t0`` (else the
    first time) without a lock window: those a right answer gives."""
    v = Verdict()
    ts = np.asarray(ts, dtype=float)
    N = len(ts)
    times = ts if planned is None else np.asarray(planned, dtype=float)
    if sigma is not None and len(times):
        v.points["reachable"] = reachable_count(fam, p, times[0] if t0 is None else t0,
                                                times, fam.judged(sigma))
    if raised:
        v.outcome = "refused"
        v.points["raised"] += 1
    if N == 0:
        return v
    arrs = [np.asarray(Q)]
    for a in (QD, QDD):
        if a is None:
            break
        arrs.append(np.asarray(a))
    upto = len(arrs) - 1
    refs = {s: fam.exact(p, s, ts, upto) for s in fam.judged_modes()}
    scales = _scales(refs, upto)
    errs = _errors(fam, refs, arrs, upto, scales)
    match = {s: errs[s] <= 1.0 for s in refs}
    locks = {}
    status = np.zeros(N, dtype=int) if status is None else np.asarray(status, dtype=int)
    anchor, blocked = (None if sigma is None else fam.judged(sigma)), False

    def which(k):
        hits = [s for s in refs if match[s][k]]
        return hits[0] if hits else None

    def near(k):
        best = min(refs, key=lambda s: errs[s][k])
        return best, errs[best][k]

    for k in range(N):
        if k > 0 and anchor is not None:
            if anchor not in locks:
                locks[anchor] = locks_between(fam, p, ts, anchor)[1]
            blocked = blocked or bool(locks[anchor][k - 1])
        if status[k] != OK:
            v.points["flagged"] += 1
            if v.outcome == "right":
                v.outcome = "refused"
            anchor, blocked = which(k), False
            continue
        if anchor is None:
            anchor = which(k)
            if anchor is None:
                s, e = near(k)
                v.wrong(f"{what} t={ts[k]:.9g} (point {k}): status OK but on no mode "
                        f"(nearest {s}, error {e:.3g} x tol)")
            else:
                v.points["right"] += 1
            continue
        if blocked:
            v.wrong(f"{what} t={ts[k]:.9g} (point {k}): status OK past a lock window "
                    f"(mode {anchor} cannot pass; lands on {which(k)}); got "
                    f"{_show(fam, arrs[0][k])}")
            continue
        if match[anchor][k]:
            v.points["right"] += 1
            continue
        other = which(k)
        v.wrong(f"{what} t={ts[k]:.9g} (point {k}): status OK, "
                + (f"on the other mode {other}" if other is not None else
                   f"off mode {anchor} by {errs[anchor][k]:.3g} x tol")
                + f"; got {_show(fam, arrs[0][k])} want {_show(fam, refs[anchor][0][k])}")
    return v


def _show(fam, q):
    return "{" + ", ".join(f"{c}={x:.6g}" for c, x in zip(fam.coords, q) if c[:2] in ("Th",)
                           or c == "s") + "}"


# -- runs ---------------------------------------------------------------------------------
@dataclass
class Spec:
    """One random sweep of one random mechanism."""
    family: str
    variant: str
    params: dict
    sigma: tuple
    t0: float
    t1: float
    n: int
    level: str
    method: str

    def __str__(self):
        ps = ", ".join(f"{k}={v!r}" for k, v in self.params.items())
        return (f"{self.family}/{self.variant} sigma={self.sigma} sweep({self.t0}, {self.t1!r}, "
                f"{self.n}, level={self.level!r}, method={self.method!r}) params=dict({ps})")


def draw_spec(fam, rng, variant=None, level=None, method=None):
    """A random mechanism of family fam that assembles at t = 0, a mode, a span and a
    point count (coarse: 7 to 40 points a period, up to fine: 721)."""
    variant = variant or fam.variants[int(rng.integers(len(fam.variants)))]
    modes = fam.modes()
    for _ in range(500):
        p = fam.draw(rng, variant)
        sigma = modes[int(rng.integers(len(modes)))]
        if fam.disc(p, np.array([0.0]), sigma)[0] > 1e-6:
            break
    else:
        raise RuntimeError(f"{fam.name}/{variant}: no assemblable draw")
    per = fam.period(p)
    n_turn = int(rng.choice([rng.integers(7, 41), rng.integers(41, 200), 361, 721],
                            p=[0.5, 0.3, 0.1, 0.1]))
    span = per * float(rng.uniform(0.3, 1.6))
    n = max(3, int(round(n_turn * span / per)))
    return Spec(fam.name, variant, p, sigma, 0.0, span, n,
                level or LEVELS[int(rng.integers(3))], method or METHODS[int(rng.integers(3))])


def run_sweep(fam, spec, mech=None):
    """The spec's sweep from the exact start of its mode, judged."""
    mech = (mech or fam.mech()).with_params(**spec.params)
    q0 = fam.exact(spec.params, spec.sigma, np.array([spec.t0]), 0)[0][0]
    planned = np.linspace(spec.t0, spec.t1, spec.n)
    raised = False
    try:
        sw = mech.sweep(spec.t0, spec.t1, spec.n, level=spec.level, method=spec.method, guess=q0)
    except REFUSALS as err:
        sw, raised = getattr(err, "sweep", None), True
        if sw is None:
            return judge(fam, spec.params, [], [], raised=True, sigma=spec.sigma,
                         planned=planned, t0=spec.t0)
    return judge(fam, spec.params, sw.t, sw.Q, sw.QD, sw.QDD, sw.status, sigma=spec.sigma,
                 raised=raised, what=str(spec), planned=planned, t0=spec.t0)


def reachable(fam, p, t0, ts, sigma):
    """Whether each t of ts is reached from t0 on mode sigma without crossing a lock
    window."""
    out = []
    for t in ts:
        grid = np.linspace(t0, t, max(64, int(4000 * abs(t - t0) / fam.period(p)) + 2))
        out.append(bool((fam.disc(p, grid, sigma) >= 0).all()))
    return np.array(out)


SOLVES = ("guess", "wrapped", "none")


def single_solves(fam, spec, rng, count=4, mech=None, kinds=SOLVES):
    """Single solves at random times t of the spec's mechanism, as (kind, Verdict):
    "guess": the guess is its mode's exact configuration at t moved 2 % of the way to
    the nearest other mode, and the answer must be that mode; "wrapped": the same with
    its angles taken to (-pi, pi] (the same configuration: angles count modulo 2 pi);
    "none": set_guess(the exact start) and solve(t0) (so that both the guess and
    mech.last are the start), then solve(t) without a guess, which must give the mode
    connected to the start (only times that no lock window separates from it)."""
    p = spec.params
    m = (mech or fam.mech()).with_params(**p)
    per = fam.period(p)
    lev = LEVELS.index(spec.level)
    q0 = fam.exact(p, spec.sigma, np.array([spec.t0]), 0)[0][0]
    ts = spec.t0 + per * rng.uniform(-1.0, 2.0, count)
    ok = reachable(fam, p, spec.t0, ts, spec.sigma)
    out = []
    for t, connected in zip(ts, ok):
        here = fam.exact(p, spec.sigma, np.array([t]), 0)[0][0]
        if not np.isfinite(here).all():
            continue
        others = [fam.exact(p, s, np.array([t]), 0)[0][0] for s in fam.judged_modes()]
        gap = min([d for d in (np.max(np.abs(wrap(o - here, fam.angle_mask))) for o in others
                               if np.isfinite(o).all()) if d > 1e-9] + [1.0])
        nudge = 0.02 * min(gap, 0.5) * rng.uniform(-1, 1, here.shape)
        for kind in kinds:
            if kind == "none" and not connected:
                continue
            what = f"{spec} solve({float(t)!r}, guess={kind})"
            try:
                if kind == "none":
                    m.set_guess(q0)
                    m.solve(spec.t0, level=spec.level, method=spec.method)   # mech.last
                    s = m.solve(float(t), level=spec.level, method=spec.method)
                else:
                    g = here + nudge
                    if kind == "wrapped":
                        g = wrap(g, fam.angle_mask)
                    s = m.solve(float(t), guess=g, level=spec.level, method=spec.method)
            except REFUSALS:
                reach = int(fam.disc(p, np.array([t]), fam.judged(spec.sigma))[0] >= 0)
                out.append((kind, Verdict("refused", Counter(raised=1, reachable=reach))))
                continue
            arrs = [s.q[None], None if s.qd is None else s.qd[None],
                    None if s.qdd is None else s.qdd[None]]
            out.append((kind, judge(fam, p, [t], *arrs[:lev + 1],
                                    status=[1 if s.singular else OK], sigma=spec.sigma,
                                    what=what)))
    return out


def run_table(fam, spec, rng, designs=4, backend="cpu", client=None, mech=None):
    """A design table around the spec's mechanism: its speed and one dimension varied
    (grid=False), every design from the spec's exact start; each design judged from the
    mode its first point is on. Returns verdicts."""
    p = spec.params
    m = (mech or fam.mech()).with_params(**p)
    speed = "f" if "f" in p else "w"
    dims = [k for k in fam.params if k not in (speed, "th0", "ph", "cph", "g", "be", "ax",
                                                 "ay", "gx", "gy", "ox", "oy", "xc")]
    dim = dims[int(rng.integers(len(dims)))]
    vals = {speed: [p[speed] * float(x) for x in rng.uniform(0.5, 1.5, designs)],
            dim: [p[dim] * (1 + float(x)) for x in rng.uniform(-0.01, 0.01, designs)]}
    vals[speed][0], vals[dim][0] = p[speed], p[dim]
    q0 = fam.exact(p, spec.sigma, np.array([spec.t0]), 0)[0][0]
    extra = {} if backend == "cpu" else {"backend": backend}
    if client is not None:
        extra["client"] = client
    try:
        tab = m.sweep(spec.t0, spec.t1, spec.n, params=vals, grid=False, guess=q0,
                      level=spec.level, method=spec.method, on_fail="ignore", **extra)
    except REFUSALS:
        return [Verdict("refused", Counter(raised=1))]
    out = []
    for d in range(designs):
        pd = dict(p, **{k: vals[k][d] for k in vals})
        sw = tab.sweep(d)
        what = f"{spec} design {d} ({speed}={pd[speed]!r}, {dim}={pd[dim]!r}, backend={backend})"
        out.append(judge(fam, pd, sw.t, sw.Q, sw.QD, sw.QDD, sw.status,
                         raised=int(tab.done[d]) < len(tab.t), what=what))
    return out


def mode_of(fam, p, t, q):
    """The mode whose exact configuration at t is q (angles modulo 2 pi), or None."""
    ts = np.array([t])
    refs = {s: fam.exact(p, s, ts, 0) for s in fam.judged_modes()}
    errs = _errors(fam, refs, [np.asarray(q)[None]], 0, _scales(refs, 0))
    hits = [s for s in refs if errs[s][0] <= 1.0]
    return hits[0] if hits else None


def run_carried_table(fam, spec, rng, designs=4, mech=None):
    """A design table without a guess whose designs' dimensions move far from the spec's
    (one dimension, by up to 30 %). The guess is a rough one, set at the spec's
    parameters: the spec's exact start moved up to 40 % of the way to the nearest other
    mode; its mode is the one a solve at t0 reaches from it. Each design must start on
    that mode where the way from the spec's dimensions to its own keeps clear of
    toggles at t0 (that mode's discriminant stays above 2 % along it: the mode is carried
    there, never left to a Newton from the guess at the design's dimensions); a design
    whose way is not clear is judged from the mode its first point is on. Returns
    verdicts."""
    p = spec.params
    m = (mech or fam.mech()).with_params(**p)
    dims = [k for k in fam.params if k not in ("f", "w", "th0", "ph", "cph", "g", "be", "ax",
                                                 "ay", "gx", "gy", "ox", "oy", "xc")]
    dim = dims[int(rng.integers(len(dims)))]
    values = [p[dim] * float(x) for x in rng.uniform(0.7, 1.3, designs)]
    values[0] = p[dim]
    t0 = np.array([spec.t0])
    q0 = fam.exact(p, spec.sigma, t0, 0)[0][0]
    others = [fam.exact(p, s, t0, 0)[0][0] for s in fam.judged_modes()]
    gap = min([d for d in (np.max(np.abs(wrap(o - q0, fam.angle_mask))) for o in others
                           if np.isfinite(o).all()) if d > 1e-9] + [1.0])
    try:
        m.set_guess(q0 + 0.4 * min(gap, 1.0) * rng.uniform(-1, 1, q0.shape), t=spec.t0)
        sigma = mode_of(fam, p, spec.t0, m.solve(spec.t0, method=spec.method).q)
        tab = m.sweep(spec.t0, spec.t1, spec.n, params={dim: values}, level=spec.level,
                      method=spec.method, on_fail="ignore")
    except REFUSALS:
        return [Verdict("refused", Counter(raised=1))]
    out = []
    for d, value in enumerate(values):
        pd = dict(p, **{dim: value})
        way = [dict(p, **{dim: p[dim] + s * (value - p[dim])}) for s in np.linspace(0, 1, 41)]
        clear = sigma is not None and \
            min(float(np.min(fam.disc(w, t0, sigma))) for w in way) > 0.02
        sw = tab.sweep(d)
        what = f"{spec} carried design {d} ({dim}={value!r}, mode {sigma}, clear={clear})"
        out.append(judge(fam, pd, sw.t, sw.Q, sw.QD, sw.QDD, sw.status,
                         sigma=sigma if clear else None,
                         raised=int(tab.done[d]) < len(tab.t), what=what, planned=tab.t,
                         t0=spec.t0))
    return out


CRASHES = []


def guarded(spec, run, pairs=False):
    """run(), or a "crashed" verdict where mechgen raised something other than its
    refusals (a traceback is a defect of its own, issue 20, but not a wrong number)."""
    try:
        return run()
    except Exception as exc:            # noqa: BLE001 - counted and shown, not hidden
        v = Verdict("crashed", detail=f"{spec}: {type(exc).__name__}: {exc}")
        return [("crash", v)] if pairs else [v]


def tally(counts, kind, verdicts, wrongs, keep=20):
    """Count verdicts under kind; keep the first wrong ones' details (crashes in
    CRASHES)."""
    right, reach = answered(verdicts)
    counts[(kind, "answered")] += right
    counts[(kind, "reachable")] += reach
    for v in verdicts:
        counts[(kind, v.outcome)] += 1
        if v.outcome == "wrong" and len(wrongs) < keep:
            wrongs.append(v.detail)
        if v.outcome == "crashed":
            CRASHES.append(v.detail)


def summary(counts, wrongs=()):
    """Lines of per-family counts: right / refused / wrong (and crashed: mechgen raised
    something other than ConvergenceError or SingularError), and the share of the points
    their mode reaches that were answered right (answered())."""
    rows = {}
    for (kind, outcome), n in counts.items():
        rows.setdefault(kind, Counter())[outcome] += n
    lines = [f"{'family/run':38s} {'right':>7s} {'refused':>8s} {'wrong':>6s} {'crashed':>8s}"
             f" {'answered':>9s}"]
    for kind in sorted(rows):
        c = rows[kind]
        share = f"{c['answered'] / c['reachable']:9.3f}" if c["reachable"] else f"{'-':>9s}"
        lines.append(f"{kind:38s} {c['right']:7d} {c['refused']:8d} {c['wrong']:6d} "
                     f"{c['crashed']:8d} {share}")
    return lines
