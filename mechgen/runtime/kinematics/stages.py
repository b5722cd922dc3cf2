"""Sweeps across stage switches (Mech's TimeSwitch / StageSwitch), numpy only.

A module built from a model with stages states ``SWITCH_TIMES`` and ``STAGES``; its Φ
switches rows at those times (the later stage holds at a switch time). A sweep whose
times cross a switch is solved stage by stage: each stage's piece is an ordinary sweep
of its own times, ending at the switch time's left limit (solved at the float just below
it, where the earlier stage still holds) and the next starting at the switch time itself
from that configuration. Before the next stage starts, the configuration reached is
checked against the next stage's equations: stages that disagree in position there are a
ModelError naming both, the time and the rows that disagree.

The result, a :class:`StagedSweep`, holds the switch time twice (the left and the right
limit: the same position, the velocities and accelerations of each side), lists the
switches in ``sw.switches``, and interpolates, finds extremes and roots stage by stage,
never across a switch. A quantity whose derivative changes sign at a switch (a slider
that reverses there) has an extreme at the switch time.
"""
from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from ...errors import MechgenError, ModelError
from ...protocol import LEVEL
from ..analysis.events import Event, Events
from ..analysis.locks import singularities as find_singularities
from ..quantity import Quantity
from ..results import Sweep
from .sweeping import from_start

_POSITION = LEVEL["position"]
POSITION_AGREEMENT = 1e-8   # largest |Φ| of the next stage at the reached configuration


@dataclass(frozen=True)
class Switch:
    """A stage switch inside a sweep: its time, the stages before and after it in the
    sweep's order, and the rows of the sweep holding the switch time as each of them
    reaches it (``row_before``, then ``row_after``: the left and right limits of a forward
    sweep; the same position, each stage's own velocities and accelerations)."""
    t: float
    before: str
    after: str
    row_before: int
    row_after: int


def switch_times(mech) -> np.ndarray:
    """The module's switch times (empty for a module without stages)."""
    return np.asarray(getattr(mech.module, "SWITCH_TIMES", ()), dtype=np.float64)


def stage_names(mech) -> tuple:
    return tuple(s[0] for s in getattr(mech.module, "STAGES", ()))


def stage_index(mech, t) -> np.ndarray:
    """The stage (0, 1, ...) holding at each time t (the later one at a switch time)."""
    return np.searchsorted(switch_times(mech), np.asarray(t, dtype=np.float64), side="right")


def pieces(ts, switches):
    """Split monotonic sweep times at the switch times they cross: [(stage, times, shown)]
    in sweep order, ``times`` the times solved (a left limit just below its switch time)
    and ``shown`` the times reported (the switch time itself). None when nothing is
    crossed."""
    ts = np.asarray(ts, dtype=np.float64)
    if ts.size < 2 or not switches.size:
        return None
    lo, hi = float(ts.min()), float(ts.max())
    crossed = switches[(switches > lo) & (switches <= hi)]
    if not crossed.size:
        return None
    d = np.diff(ts)
    twice = (d == 0) & np.isin(ts[1:], crossed)     # a switch time given twice (the times
    if twice.any():                                 # of a staged sweep): held twice anyway
        ts = np.delete(ts, np.flatnonzero(twice) + 1)
        d = np.diff(ts)
    if not (np.all(d > 0) or np.all(d < 0)):
        raise ValueError("a sweep across a stage switch needs strictly monotonic times")
    forward = d[0] > 0
    grid = ts if forward else ts[::-1]
    stage = np.searchsorted(switches, grid, side="right")
    out = []
    for k in range(int(stage[0]), int(stage[-1]) + 1):
        solved = grid[stage == k]
        head, tail = [], []
        if k > stage[0] and (not solved.size or solved[0] != switches[k - 1]):
            head = [float(switches[k - 1])]                  # the right limit
        if k < stage[-1]:
            tail = [float(np.nextafter(switches[k], -np.inf))]  # the left limit
        shown = np.concatenate([head, solved, [float(switches[k])] if tail else []])
        solved = np.concatenate([head, solved, tail])
        if not forward:
            solved, shown = solved[::-1].copy(), shown[::-1].copy()
        out.append((k, solved, shown))
    return out if forward else out[::-1]


def staged_sweep(mech, ts, guess, piece, tol=None):
    """A sweep over the times ts across stage switches (see the module docstring), or None
    when they cross no switch. ``piece(times, guess)`` sweeps one stage's piece (times that
    cross no switch) from ``guess`` (the caller's for the first piece, then the
    configuration the previous piece reached); ``tol``: the sweep's tolerance (None: the
    mechanism's), which bounds the disagreement of two stages at a switch."""
    split = pieces(ts, switch_times(mech))
    if split is None:
        return None
    names = stage_names(mech)
    parts, q = [], guess
    for j, (k, solved, shown) in enumerate(split):
        try:
            if j:
                _check_agreement(mech, parts[-1][1], split[j - 1][0], k, float(solved[0]),
                                 names, tol)
            sw = piece(solved, q)
        except MechgenError as exc:
            # the error carries what was solved before it, every stage's piece included
            part = getattr(exc, "sweep", None)
            done = parts + ([(k, part, shown[:len(part)])] if part is not None and len(part)
                            else [])
            if done:
                exc.sweep = StagedSweep(mech, done, names)
            raise
        parts.append((k, sw, shown))
        q = sw.Q[-1].copy()
    return StagedSweep(mech, parts, names)


def _check_agreement(mech, sw, before, after, t_next, names, tol):
    """Refuse a switch where the configuration the earlier stage reached does not satisfy
    the later stage's equations (evaluated at ``t_next``, the later stage's first time)."""
    q = sw.Q[-1]
    r = np.empty(mech.m)
    mech.module.phi(q, float(t_next), mech.p, r)
    limit = max(POSITION_AGREEMENT, 100 * (tol or mech.tol))
    bad = ~(np.abs(r) <= limit)
    if not np.any(bad):
        return
    worst = [i for i in np.argsort(-np.nan_to_num(np.abs(r), nan=np.inf)) if bad[i]][:3]
    rows = "; ".join(f"row {i + 1} '{mech.constraint_labels[i]}': {r[i]:.6g}" for i in worst)
    ts = float(switch_times(mech)[min(before, after)])
    raise ModelError(
        f"model '{mech.name}': stages '{names[before]}' and '{names[after]}' disagree in "
        f"position at the switch t={ts:.10g}: the configuration that '{names[before]}' "
        f"reaches there does not satisfy the equations of '{names[after]}' (residual {rows}; "
        f"tolerance {limit:.3g}). Make the later stage start where the earlier one ends.",
        where=None)


def staged_singularities(mech, ts, q):
    """Mechanism.singularities stage by stage: Φ_q changes from one stage to the next, so
    that det Φ_q may change sign at a switch without any loss of rank there. Each stage's
    piece starts from the configuration the previous one reached (a position sweep at the
    mechanism's tolerances)."""
    state = mech.state
    tol, maxit, meth = state.tol, state.maxit, state.method_of(None)
    split = pieces(ts, switch_times(mech))
    if split is None:
        return find_singularities(mech, ts, q)
    found = []
    for j, (_, solved, _) in enumerate(split):
        found += find_singularities(mech, solved, q)
        if j + 1 < len(split):
            try:
                q = from_start(mech, solved, q, _POSITION, tol, maxit, meth).Q[-1]
            except MechgenError:
                break          # the branch ends in this stage (a lock): nothing beyond it
    return found


class StagedSweep(Sweep):
    """A sweep across stage switches: the arrays of every stage's piece, one after the
    other, each switch time held twice (as the stage before it ends there, then as the
    stage after it starts there: left then right limit in a forward sweep).

    ``sw.switches``: the :class:`Switch` records; ``sw.stage``: the stage index of each
    row; ``sw.parts``: the pieces as ordinary sweeps; ``sw.jump(name)``: the change of a
    quantity at each switch (the velocity jump of ``"X4d"``)."""

    def __init__(self, mech, parts, names):
        t = np.concatenate([shown for _, _, shown in parts])
        Q = np.concatenate([sw.Q for _, sw, _ in parts])
        QD = None if parts[0][1].QD is None else np.concatenate([sw.QD for _, sw, _ in parts])
        QDD = None if parts[0][1].QDD is None else \
            np.concatenate([sw.QDD for _, sw, _ in parts])
        info = np.concatenate([sw.info for _, sw, _ in parts])
        super().__init__(mech, t, Q, QD, QDD, info)
        self._solved_t = np.concatenate([sw.t for _, sw, _ in parts])   # left limits below
        self.parts = [sw for _, sw, _ in parts]
        self.stage_names = names
        self.stage = np.concatenate([np.full(len(sw), k) for k, sw, _ in parts])
        self.jumps = np.concatenate([sw.jumps for sw in self.parts])
        self.crossings = np.concatenate([sw.crossings for sw in self.parts])
        switches, row = [], 0
        for j in range(len(parts) - 1):
            row += len(parts[j][1])
            a, b = parts[j][0], parts[j + 1][0]
            switches.append(Switch(float(t[row]), names[a], names[b], row - 1, row))
        self.switches = tuple(switches)

    def jump(self, name) -> np.ndarray:
        """At each switch, in sweep order: the quantity after it minus before it (the right
        minus the left limit in a forward sweep; ``"X4d"``: the velocity jump)."""
        y = Quantity(self.mechanism, name).on_sweep(self)
        return np.array([y[s.row_after] - y[s.row_before] for s in self.switches])

    def at_level(self, level) -> "StagedSweep":
        """As Sweep.at_level, piece by piece (each on its own stage's equations)."""
        out = object.__new__(StagedSweep)
        out.__dict__.update(self.__dict__)
        out.parts = [sw.at_level(level) for sw in self.parts]
        out.QD = np.concatenate([sw.QD for sw in out.parts])
        out.QDD = None if out.parts[0].QDD is None else \
            np.concatenate([sw.QDD for sw in out.parts])
        return out

    def interpolate(self, name, method="auto", degree=3, extrapolate=False):
        """A callable of t, interpolating each stage's piece on its own (see
        Sweep.interpolate): nothing is smoothed across a switch; at a switch time it gives
        the later stage's value (the right limit), as a solve there does."""
        pieces_ = [sw.interpolate(name, method=method, degree=degree, extrapolate=True)
                   if len(sw) >= 2 else _PointPiece(sw, name) for sw in self.parts]
        return StagedInterpolant(pieces_, self.parts, self.switches, extrapolate)

    def extrema(self, name, method="auto", xtol=1e-12):
        """Extremes within each stage (Sweep.extrema) and, at a switch where the quantity's
        time derivative changes sign, an extreme at the switch time itself (method
        "switch"; the interpolant's columns give the same time and value)."""
        events, own = Events(), {}
        for j, sw in enumerate(self.parts):
            if len(sw) >= 2:
                own[j] = sw.extrema(name, method=method, xtol=xtol)
                events += self._own_ends(sw, own[j])
        qty = Quantity(self.mechanism, name)
        dq = qty.derivative()
        view = self if dq is None or dq.level <= _level(self) else self.at_level(dq.level)
        y = qty.on_sweep(self)
        if dq is not None:
            dy = dq.on_sweep(view)
            forward = self.t[-1] >= self.t[0]
            # the signs of the rate in time order, 0 where it rests (a dwell stage): a
            # rate that is positive into a switch and negative after the rest that follows
            # it turns round there (a crank that turns out, dwells, turns back: its
            # largest angle is the dwell's, reached at the first switch)
            rest = 1e-12 * max(1.0, float(np.nanmax(np.abs(dy))) if len(dy) else 1.0)
            sign = np.where(np.abs(dy) <= rest, 0.0, np.sign(dy))
            order = np.arange(len(self)) if forward else np.arange(len(self))[::-1]
            at = np.empty(len(self), dtype=np.int64)
            at[order] = np.arange(len(self))
            later = sign[order]
            for s in self.switches:
                lo, hi = (s.row_before, s.row_after) if forward else \
                    (s.row_after, s.row_before)
                after = later[at[hi]:]
                moving = after[np.flatnonzero(after)]
                if sign[lo] != 0 and moving.size and sign[lo] * moving[0] < 0:
                    kind = "max" if sign[lo] > 0 else "min"
                    events.append(Event(qty.label, kind, s.t, float(y[s.row_after]), s.t,
                                        float(y[s.row_after]), "switch"))
        events += self._lone_ends(qty, y, own, events)
        events.sort(key=lambda e: e.t)
        return events

    def _lone_ends(self, qty, y, own, found):
        """The sweep's end where it is a switch time held by its stage alone (a sweep that
        ends, or starts, exactly at a switch: the lone row of the later stage): an extreme
        at that end as an ordinary sweep's end is, its value the lone row's. Where the
        quantity jumps there, the jump says its kind (a value above the other limit's is a
        maximum); where it is continuous, the neighbouring stage's end says it."""
        out, last = [], len(self.parts) - 1
        for j, at, row, other in ((0, "start", 0, 1), (last, "end", len(self) - 1,
                                                        len(self) - 2)):
            if last == 0 or len(self.parts[j]) != 1 or (j - 1 if j else 1) not in own:
                continue
            near = own[j - 1 if j else 1]
            a, b = float(y[row]), float(y[other])
            if not (math.isfinite(a) and math.isfinite(b)):
                continue
            if abs(a - b) > 1e-9 * max(1.0, float(np.nanmax(np.abs(y)))):
                kind = "max" if a > b else "min"
            else:
                ends = [e for e in near if e.at == ("end" if j else "start")]
                if not ends:
                    continue
                kind = ends[0].kind
            t = float(self.t[row])
            if any(e.t == t and e.kind == kind for e in found):
                continue        # the switch's own extreme
            out.append(Event(qty.label, kind, t, a, t, a, "switch", 0, at))
        return out

    def _own_ends(self, part, events):
        """A stage's events less its ends at a switch (a stage's end there is no end of
        the sweep; an extreme at a switch is the switch's own event)."""
        first, last = part is self.parts[0], part is self.parts[-1]
        return [e for e in events if e.at == "interior" or
                (e.at == "start" and first) or (e.at == "end" and last)]

    def roots(self, name, method="auto", xtol=1e-12):
        """Zero crossings within each stage (Sweep.roots); a quantity that jumps through
        zero at a switch has no root there (the jump is in sw.jump)."""
        events = Events()
        for sw in self.parts:
            if len(sw) >= 2:
                for e in self._own_ends(sw, sw.roots(name, method=method, xtol=xtol)):
                    if not any(abs(e.t - f.t) <= 1e-12 for f in events):
                        events.append(e)
        events.sort(key=lambda e: e.t)
        return events

    def __repr__(self):
        text = super().__repr__()
        shown = ", ".join(f"{s.before} -> {s.after} at t={s.t:.6g}" for s in self.switches)
        return text[:-1] + f"; stage switches: {shown}>"


def _level(sw) -> int:
    return 0 if sw.QD is None else 1 if sw.QDD is None else 2


class _PointPiece:
    """The interpolant of a stage's lone point (a sweep that ends or starts exactly at a
    switch holds the later stage there alone): its value at that time and the time
    derivatives the solution there gives (its velocities and accelerations, solved on that
    stage's equations where the sweep lacks them)."""

    def __init__(self, sw, name, values=None):
        self.t = np.asarray(sw.t, dtype=np.float64)
        self.name, self.method = str(name), "switch point"
        if values is None:
            qty, values = Quantity(sw.mechanism, name), []
            while qty is not None:
                if qty.level > _level(sw):
                    last = sw.mechanism.last
                    try:
                        sw = sw.at_level(qty.level)
                    finally:
                        sw.mechanism.last = last
                values.append(float(qty.on_sweep(sw)[0]))
                qty = qty.derivative()
        self.values = values

    def __call__(self, t, nu=0):
        if nu >= len(self.values):
            raise ValueError(f"the derivative of order {nu} of {self.name!r} at the switch "
                             f"t={float(self.t[0]):g} needs a third derivative of the "
                             "coordinates, which mechgen does not solve for")
        return np.full(np.shape(t), self.values[nu])

    def derivative(self, n=1) -> "_PointPiece":
        out = object.__new__(_PointPiece)
        out.__dict__.update(self.__dict__)
        out.values = self.values[n:]
        out.name = self.name + "'" * n
        return out

    def roots(self, a=None, b=None) -> np.ndarray:
        return self.t[:1].copy() if self.values and self.values[0] == 0.0 else np.empty(0)


class StagedInterpolant:
    """One interpolant per stage piece, chosen by t (the later stage at a switch time)."""

    def __init__(self, pieces_, parts, switches, extrapolate):
        self.pieces = pieces_
        self.name = pieces_[0].name
        self.method = next((p.method for p in pieces_ if not isinstance(p, _PointPiece)),
                           pieces_[0].method)
        self.extrapolate = extrapolate
        spans = [(float(min(p.t[0], p.t[-1])), float(max(p.t[0], p.t[-1]))) for p in parts]
        order = np.argsort([a for a, _ in spans])
        self._order = order
        self._starts = np.array([spans[k][0] for k in order])
        self.domain = (min(a for a, _ in spans), max(b for _, b in spans))
        self.switches = tuple(s.t for s in switches)

    def __call__(self, t, nu=0):
        t_arr = np.asarray(t, dtype=np.float64)
        flat = np.atleast_1d(t_arr).ravel()
        a, b = self.domain
        if not self.extrapolate and np.any((flat < a - 1e-12) | (flat > b + 1e-12)):
            raise ValueError(f"t outside the sweep [{a:g}, {b:g}] (extrapolate=True allows it)")
        # the piece holding t: the last one starting at or before t (the later at a switch)
        which = np.clip(np.searchsorted(self._starts, flat, side="right") - 1, 0,
                        len(self._starts) - 1)
        out = np.empty(flat.shape)
        for j in np.unique(which):
            sel = which == j
            out[sel] = np.asarray(self.pieces[self._order[j]](flat[sel], nu), dtype=np.float64)
        return out.reshape(t_arr.shape) if t_arr.ndim else float(out[0])

    def derivative(self, n=1) -> "StagedInterpolant":
        out = object.__new__(StagedInterpolant)
        out.__dict__.update(self.__dict__)
        out.pieces = [p.derivative(n) for p in self.pieces]
        return out

    def roots(self, a=None, b=None) -> np.ndarray:
        found = [p.roots(a, b) for p in self.pieces]
        return np.unique(np.concatenate(found)) if found else np.empty(0)

    def __repr__(self):
        a, b = self.domain
        return (f"<StagedInterpolant of {self.name} on [{a:g}, {b:g}], {len(self.pieces)} "
                f"stage pieces ({self.method})>")
