"""The state behind a live view: the mechanism, the cycle shown, the parameter values and
ranges, the traced points, the glyphs (view.geometry) and the columns of the cycle
(view.cycle). A parameter change solves the whole cycle again with the compiled module
and draws the glyphs again only when a body's shape changed (a length, not a speed)."""
from __future__ import annotations

import math
import textwrap

import numpy as np

from ..errors import MechgenError
from ..runtime.tables.starts import quiet_params
from ..runtime.loading.tiers import Tiers
from ..plot.scene import Scene
from .cycle import (DRIVER, Failure, assembling_range, columns, empty_columns, quantity_names,
                    solve_cycle)
from .geometry import Picture, blank_axes

FRAMING = 61             # configurations of the cycle the glyphs are sized and framed by


class _Motion:
    """A few configurations of a sweep, for draw()'s framing (a rail's length, a slot's
    travel): a thousand would cost draw() time and change nothing it draws."""

    def __init__(self, sw, k=FRAMING):
        pick = np.unique(np.linspace(0, len(sw) - 1, min(k, len(sw))).round().astype(int))
        self._P, self.Q = sw.points()[pick], sw.Q[pick]

    def points(self):
        return self._P


def default_range(value):
    """A slider's range around a parameter's default: ±50 % (±1 about zero)."""
    if value == 0:
        return (-1.0, 1.0)
    half = 0.5 * abs(value)
    return (value - half, value + half)


def default_traces(scene, P, Q, most=3):
    """The points of moving bodies whose paths are longest (at most ``most``, one per
    body, points that move together counted once)."""
    found = []
    names = scene.point_names()      # a body's own points before its origin
    for name in sorted(names, key=lambda n: (n.endswith("[0]"), names.index(n))):
        body, where = scene.locate(name)
        if body.ground:
            continue
        xy = where(P, Q)
        length = float(np.sum(np.hypot(*np.diff(xy, axis=0).T)))
        if length > 0:
            found.append((length, name, body.name, xy))
    found.sort(key=lambda f: -f[0])
    out, bodies, paths = [], set(), []
    for length, name, body, xy in found:
        if body in bodies or any(np.abs(xy - p).max() < 1e-9 * (1 + length) for p in paths):
            continue
        out.append(name)
        bodies.add(body)
        paths.append(xy)
        if len(out) == most:
            break
    return out


def moves(values) -> bool:
    """Whether a quantity changes over the cycle (beyond round-off of its size)."""
    v = np.asarray(values, dtype=float)
    v = v[np.isfinite(v)]
    return v.size > 1 and float(np.ptp(v)) > 1e-9 * (1.0 + float(np.max(np.abs(v))))


def default_plots(mech, data, quantities) -> list:
    """The two plots a page opens with: the first declared output that moves, else the
    coordinate that moves most (its range against its size: a slider's travel, a lever's
    swing; never one that stays put, as the ram's angle Th4 of the quick-return does);
    then a driver's effort that moves (a model with masses or loads), else the first
    one's rate."""
    outputs = [o for o in mech.outputs if moves(data[o])]
    if outputs:
        first = outputs[0]
    else:
        def swing(c):
            v = np.asarray(data[c], dtype=float)
            v = v[np.isfinite(v)]
            return float(np.ptp(v)) / (1.0 + float(np.max(np.abs(v)))) if v.size else 0.0
        moving = [c for c in mech.coordinates if moves(data[c])]
        first = max(moving, key=swing) if moving else mech.coordinates[-1]
    efforts = [q for q in quantities if q.startswith(DRIVER) and moves(data[q])]
    return [first, efforts[0] if efforts else first + "d"]


class Explorer:
    """A mechanism explored over one cycle [t0, t1] of n times. ``trace``: points whose
    paths are drawn (names as draw(trace=...) takes them; default the longest paths);
    ``plots``: the quantities of the two plots (default the outputs, else the last
    coordinates); ``ranges``: {parameter: (low, high)} of the sliders. ``compiled``:
    solve on the module's compiled tier (the default: a slider's move solves a whole
    cycle), else on the tier ``mech`` answers on now."""

    def __init__(self, mech, t0=0.0, t1=1.0, n=1000, trace=None, plots=None, ranges=None,
                 path=None, compiled=True):
        if compiled and mech.tier != "compiled":
            mech = _compiled(mech)
        self.mech, self.path = mech, path
        self.t0, self.t1, self.n = float(t0), float(t1), int(n)
        if not (self.t1 > self.t0) or self.n < 2:
            raise ValueError(f"the cycle needs t1 > t0 and n >= 2, got [{t0}, {t1}], n={n}")
        self.params = dict(mech.parameters)
        self.ranges = {p: default_range(v) for p, v in self.params.items()}
        for name, rng in (ranges or {}).items():
            if name not in self.params:
                raise ValueError(f"ranges: '{mech.name}' has no parameter {name!r} "
                                 f"(parameters: {', '.join(self.params) or 'none'})")
            lo, hi = (float(v) for v in rng)
            if not hi > lo:
                raise ValueError(f"ranges[{name!r}]: need low < high, got {rng!r}")
            self.ranges[name] = (lo, hi)
        notes = []
        try:
            sw = solve_cycle(mech, self.t0, self.t1, self.n, notes=notes)
        except Failure as exc:
            raise MechgenError(f"'{mech.name}' does not run over [{self.t0:g}, {self.t1:g}] "
                               f"with its default parameters: {exc}") from None
        self.scene = Scene(mech)
        if trace is None:
            trace = default_traces(self.scene, sw.points(), sw.Q)
        self.trace = [trace] if isinstance(trace, str) else list(trace)
        self.traces = [self.scene.locate(name) for name in self.trace]
        self.ax = blank_axes()
        self.picture = Picture(mech, sw.Q[0], self.t0, _Motion(sw), labels=True, ax=self.ax)
        self.shape = self._shape(mech, sw)
        self.data = columns(mech, sw, self.picture.frames, self.traces)
        self.names = list(self.data)
        self.quantities = quantity_names(mech)
        if plots is None:
            plots = default_plots(mech, self.data, self.quantities)
        plots = [plots] if isinstance(plots, str) else list(plots)
        unknown = [p for p in plots if p not in self.quantities]
        if unknown:
            raise ValueError(f"plots: no quantity {', '.join(map(repr, unknown))} (choose from "
                             f"{', '.join(self.quantities)})")
        self.plots = plots
        self.guess = None          # the start of the cycle in the assembly mode chosen,
        self.guess_params = None   # and the parameters of that cycle
        self.message = ""
        self.detail = ""           # the solver's whole account of a failure
        self.warning = "\n".join(notes)   # what the last cycle's solve warned of its mode
        self.extent = self._extent(self.data)

    @staticmethod
    def _shape(mech, sw):
        """Every point in its body's frame at the cycle's start: what the glyphs' shapes
        depend on (compared to decide whether to draw them again)."""
        P = sw.points()[0]
        out = []
        scene = Scene(mech)
        org, ang = scene.poses(P[None], sw.Q[:1])
        for i, b in enumerate(scene.bodies):
            c, s = math.cos(ang[0, i]), math.sin(ang[0, i])
            for k in b.every:
                d = P[k] - org[0, i]
                out.append((c * d[0] + s * d[1], -s * d[0] + c * d[1]))
        return np.array(out)

    def _extent(self, data):
        """The drawing's frame: the glyphs' over the motion, the traced paths of the
        cycle's columns ``data`` taken in."""
        x0, x1, y0, y1 = self.picture.extent
        for j in range(len(self.traces)):
            xs, ys = data[f"tr{j}x"], data[f"tr{j}y"]
            x0, x1 = min(x0, xs.min()), max(x1, xs.max())
            y0, y1 = min(y0, ys.min()), max(y1, ys.max())
        return (float(x0), float(x1), float(y0), float(y1))

    def compute(self, params=None, guess=None):
        """Solve the cycle for ``params`` (changes from the current values); returns
        (columns, whether the glyphs were drawn again, message: "" when it runs)."""
        values = dict(self.params)
        values.update(params or {})
        mech = quiet_params(self.mech, values)
        if guess is None and self.guess is not None:
            # the mode chosen: the last cycle's start, carried from its parameters to
            # these (Mechanism.with_params), not a Newton from it here
            base = self.mech.with_params(**self.guess_params)
            base.set_guess(self.guess, t=self.t0)
            mech = base.with_params(**values)
        notes = []
        try:
            sw = solve_cycle(mech, self.t0, self.t1, self.n, guess=guess, notes=notes)
        except Failure as exc:
            self.params = values
            self.warning = ""
            self.message = self._cannot(mech, values, params or {}, str(exc))
            return empty_columns(self.names), False, self.message
        self.warning = "\n".join(notes)
        self.params = values
        if guess is not None or self.guess is not None:
            self.guess, self.guess_params = sw.Q[0].copy(), values
        shape = self._shape(mech, sw)
        again = shape.shape != self.shape.shape or \
            np.abs(shape - self.shape).max() > 1e-12 * (1.0 + np.abs(shape).max())
        if again:
            self.picture = Picture(mech, sw.Q[0], self.t0, _Motion(sw), labels=False,
                                   ax=self.ax, keep_labels=self.picture.labels)
            self.shape = shape
        self.message = ""
        data = columns(mech, sw, self.picture.frames, self.traces)
        self.extent = self._extent(data)
        return data, again, ""

    def _cannot(self, mech, values, changed, why):
        """The message shown in place of the drawing: where it stops, and the range of
        the parameter just changed over which it runs."""
        # the values as typed (to 6 digits: 3.70001 is not said as 3.7, a value that runs)
        said = ", ".join(f"{k} = {v:.6g}" for k, v in values.items() if k in changed) or \
            ", ".join(f"{k} = {v:.6g}" for k, v in values.items())
        self.detail = why
        text = f"Cannot assemble over the cycle for {said}."
        for name in changed:        # what to do first: the range that runs
            lo, hi = self.ranges[name]
            span = assembling_range(mech, name, min(lo, values[name]), max(hi, values[name]),
                                    self.t0, self.t1)
            if span is None:
                text += f"\nNo value of {name} in [{lo:.4g}, {hi:.4g}] assembles."
            else:
                text += f"\nIt assembles for {name} from {span[0]:.4g} to {span[1]:.4g}."
        return text + "\n\n" + "\n".join(textwrap.wrap(_gist(why), 72))

    def modes(self, t):
        """The assembly modes at time t (mech.assemblies): [(label, q)]."""
        mech = self.mech.with_params(**self.params)
        found = mech.assemblies(float(t))
        out = []
        if not found:
            return out
        Q = np.array([s.q for s in found])
        differ = [k for k in range(Q.shape[1]) if np.ptp(Q[:, k]) > 1e-6][:2]
        for i, s in enumerate(found):
            said = ", ".join(f"{mech.coordinates[k]}={s.q[k]:.3g}" for k in differ)
            out.append((f"mode {i + 1}" + (f": {said}" if said else ""), s.q.copy()))
        return out

    def follow_back(self, q, t):
        """The configuration at t0 of the assembly mode q at time t, followed back along
        the motion: the start of a cycle in that mode."""
        mech = self.mech.with_params(**self.params)
        if float(t) == self.t0:
            return np.asarray(q, dtype=float)
        steps = max(2, int(abs(float(t) - self.t0) / (self.t1 - self.t0) * self.n) + 1)
        sw = mech.sweep(float(t), self.t0, steps, guess=q)
        return sw.Q[-1].copy()


def _gist(why) -> str:
    """The first sentence of a solver's account of a failure, and the one that names a
    lock (a toggle position) if any: what fits in place of the drawing."""
    sentences = [x.strip() for x in why.replace("\n", " ").split(". ") if x.strip()]
    keep = sentences[:1] + [x.split(", where")[0] for x in sentences[1:] if "lock" in x][:1]
    return ". ".join(k.rstrip(".") for k in keep) + "."


def _compiled(mech):
    """The mechanism on its compiled tier (the view recomputes whole cycles per slider
    move; the plain-Python tier is for first answers)."""
    path = mech.state.tiers.path
    if path is None:
        return mech
    other = type(mech)(Tiers.open(path, "compiled"))      # (load(path, tier="compiled"))
    other.p = mech.p.copy()
    other.model, other.symbolic = mech.model, mech.symbolic
    other.guess, other.guess_t, other.guess_p = mech.guess.copy(), mech.guess_t, \
        mech.guess_p.copy()
    return other
