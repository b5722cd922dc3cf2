"""Stages (Mech's TimeSwitch / StageSwitch): constraint sets that take over at given times.

A model declares its common constraints as usual and, inside ``with m.stage(...)``
blocks, the constraints of each stage::

    with m.stage("forward", until=0.5):
        m.rotation_lock(manivela, base, velocidad * T)
    with m.stage("back"):
        m.rotation_lock(manivela, base, velocidad * (1 - T))

Stage k runs from the previous stage's ``until`` (included) to its own (excluded); the
first starts at −∞, the last (the one without ``until``) runs to +∞. Every stage gives the
same number of rows; row j of one stage takes the place of row j of the others, so that
Φ keeps its size and the coordinates stay the same. The expanded system holds such a row
as ``Piecewise((row of stage 1, T < t1), (row of stage 2, T < t2), ..., (row of the last,
True))``: Φ_q, ν and γ follow by differentiating each piece, and the compiler prints it as
a conditional expression. At a switch time the later stage holds (right-continuous);
positions must agree there (a row whose two sides differ by a non-zero constant is a
ModelError here; the general case is checked when a sweep crosses the switch), while
velocities and accelerations may jump.
"""
from __future__ import annotations

import copy
import math

import sympy as sp

from ..errors import ModelError, user_frame
from .geometry import T, label_name


class Stage:
    """One stage of a model: a name, its time range [start, until) and its constraints.

    Use it as a context manager: the constraints declared inside belong to it."""

    def __init__(self, model, name: str, number: int, until, where):
        self.model = model
        self.name = name
        self.number = number       # 1, 2, ... in declaration order
        self.until = until         # float, or None for the last stage
        self.where = where
        self.numbers: list[int] = []     # constraint numbers declared inside the stage
        self._begin = None

    @property
    def start(self) -> float:
        """The time the stage takes over (−inf for the first)."""
        stages = self.model.stages
        k = stages.index(self)
        return -math.inf if k == 0 else float(stages[k - 1].until)

    @property
    def end(self) -> float:
        """The time the next stage takes over (+inf for the last)."""
        return math.inf if self.until is None else float(self.until)

    @property
    def constraints(self):
        """The constraints declared inside this stage, in declaration order."""
        mine = set(self.numbers)
        return [c for c in self.model.constraints if c.number in mine]

    def range_text(self, var="t") -> str:
        """``t < 0.5``, ``0.5 <= t < 1``, ``t >= 1`` or ``all t``."""
        a, b = self.start, self.end
        if math.isinf(a) and math.isinf(b):
            return f"all {var}"
        if math.isinf(a):
            return f"{var} < {b:g}"
        if math.isinf(b):
            return f"{var} >= {a:g}"
        return f"{a:g} <= {var} < {b:g}"

    def __enter__(self):
        active = self.model.__dict__.get("_stage_active")
        if active is not None:
            raise ModelError(f"stage '{self.name}' opened inside stage '{active.name}': "
                             "stages follow one another, they do not nest")
        self.model._stage_active = self
        self._begin = len(self.model.constraints)
        return self

    def __exit__(self, *exc):
        self.model._stage_active = None
        self.numbers += [c.number for c in self.model.constraints[self._begin:]]
        self.model._equations = None
        return False

    def __repr__(self):
        return f"<stage {self.number} {self.name!r}: {self.range_text()}>"


class StageMixin:
    """``Model.stage``: constraint sets that switch at given times (see the module)."""

    @property
    def stages(self) -> list:
        """The stages in declaration order ([] for a model without stages)."""
        return self.__dict__.setdefault("_stages", [])

    @property
    def switch_times(self) -> tuple:
        """The times at which one stage hands over to the next, increasing."""
        return tuple(float(s.until) for s in self.stages if s.until is not None)

    def stage(self, name: str, until=None) -> Stage:
        """A stage: ``with m.stage("forward", until=0.5): ...`` declares the constraints
        that hold from the previous stage's switch time up to ``until`` (excluded); the
        last stage has no ``until`` and runs to the end. Constraints declared outside
        every stage hold in all of them. Each stage must give the same number of
        equations, row j of one taking the place of row j of the others, and the
        positions must agree at each switch time (velocities may jump)."""
        if not isinstance(name, str) or not name.strip():
            raise ModelError(f"stage: the name must be a non-empty string, got {name!r}")
        label_name(name, "stage")
        stages = self.stages
        active = self.__dict__.get("_stage_active")
        if active is not None:
            raise ModelError(f"stage {name!r} declared inside stage '{active.name}': stages "
                             "follow one another, they do not nest")
        if any(s.name == name for s in stages):
            raise ModelError(f"stage {name!r} is declared twice in model '{self.name}'; "
                             "to add constraints to it, use the Stage object it returned")
        if stages and stages[-1].until is None:
            raise ModelError(f"stage {name!r} follows stage '{stages[-1].name}', which has no "
                             "until=: every stage but the last says when the next one takes "
                             f"over (m.stage('{stages[-1].name}', until=...))")
        if until is not None:
            until = self._stage_time(until, name)
            if stages and until <= stages[-1].until:
                raise ModelError(f"stage {name!r}: until={until:g} must come after the "
                                 f"switch of stage '{stages[-1].name}' (until="
                                 f"{stages[-1].until:g})")
        frame = user_frame()
        where = f"{frame.filename}:{frame.lineno}" if frame and frame.filename \
            and not frame.filename.startswith("<") else None
        stage = Stage(self, name, len(stages) + 1, until, where)
        stages.append(stage)
        self._equations = None
        return stage

    def _stage_time(self, value, name) -> float:
        try:
            x = float(sp.sympify(value))
        except (TypeError, ValueError, sp.SympifyError):
            raise ModelError(f"stage {name!r}: until= must be a number (a time), got "
                             f"{value!r}") from None
        if not math.isfinite(x):
            raise ModelError(f"stage {name!r}: until= must be finite, got {value!r}")
        return x

    def stage_view(self, stage):
        """A copy of the model holding only the common constraints and those of
        ``stage`` (a Stage or its name): the system that holds during that stage."""
        if isinstance(stage, str):
            found = [s for s in self.stages if s.name == stage]
            if not found:
                known = ", ".join(s.name for s in self.stages) or "none"
                raise ModelError(f"model '{self.name}' has no stage {stage!r} (stages: {known})")
            stage = found[0]
        staged = {n for s in self.stages for n in s.numbers}
        mine = set(stage.numbers)
        view = copy.copy(self)
        view.constraints = [c for c in self.constraints
                            if c.number not in staged or c.number in mine]
        view._stages = []
        view._equations = None
        return view


def _check_stages(model):
    stages = model.stages
    where = getattr(model, "_where", None)
    if model.__dict__.get("_stage_active") is not None:
        raise ModelError(f"stage '{model._stage_active.name}' is still open", where=where)
    last = stages[-1]
    if last.until is not None:
        raise ModelError(f"stage '{last.name}' ends at until={last.until:g} but no stage "
                         "follows it: declare the stage that takes over (the last stage "
                         "has no until=)", where=last.where)
    counts = [sum(len(c.exprs) for c in s.constraints) for s in stages]
    for s, n in zip(stages, counts):
        if n == 0:
            raise ModelError(f"stage '{s.name}' declares no constraint: declare its "
                             "constraints inside `with m.stage(...):`", where=s.where)
    if len(set(counts)) > 1:
        shown = ", ".join(f"'{s.name}' {n}" for s, n in zip(stages, counts))
        raise ModelError(f"the stages of model '{model.name}' give different numbers of "
                         f"equations ({shown}): each stage must replace the others row for "
                         "row, so that the coordinates stay determined", where=stages[0].where)


def staged_rows(model):
    """[(constraint number, component, expression, label)] of a model with stages: the
    common constraints' rows and, where the first stage's constraints stand, each stage
    row joined with its counterparts as a Piecewise in T. Raises ModelError where the
    stages cannot switch (see the module docstring)."""
    _check_stages(model)
    stages = model.stages
    per_stage = [[(c, k, e, label) for c in s.constraints
                  for k, (e, label) in enumerate(c.rows())] for s in stages]
    staged = {n for s in stages for n in s.numbers}
    first = set(stages[0].numbers)
    out, j = [], 0
    for con in model.constraints:
        if con.number not in staged:
            out += [(con.number, k, sp.sympify(e), label)
                    for k, (e, label) in enumerate(con.rows())]
            continue
        if con.number not in first:
            continue
        for _ in con.exprs:
            pieces = [rows[j] for rows in per_stage]
            _check_continuity(model, stages, pieces)
            conds = [T < sp.Float(s.until) for s in stages[:-1]] + [sp.true]
            expr = sp.Piecewise(*[(sp.sympify(p[2]), c) for p, c in zip(pieces, conds)])
            label = " | ".join(f"[{s.name}] {p[3]}" for s, p in zip(stages, pieces))
            out.append((pieces[0][0].number, pieces[0][1], expr, label))
            j += 1
    return out


def stage_pieces(model) -> dict:
    """{(constraint number, component): [(constraint, component, condition) per stage]}
    for each stage row of ``model`` (the rows staged_rows joins as a Piecewise, in the
    same order), so that what depends on a row's kind (a driver's factor) takes each
    stage's own constraint."""
    stages = model.stages
    per_stage = [[(c, k) for c in s.constraints for k in range(len(c.exprs))]
                 for s in stages]
    conds = [T < sp.Float(s.until) for s in stages[:-1]] + [sp.true]
    first = set(stages[0].numbers)
    out, j = {}, 0
    for con in model.constraints:
        if con.number not in first:
            continue
        for k in range(len(con.exprs)):
            out[(con.number, k)] = [rows[j] + (c,) for rows, c in zip(per_stage, conds)]
            j += 1
    return out


def _check_continuity(model, stages, pieces):
    """Two neighbouring stages whose rows differ at the switch time by a non-zero amount
    free of coordinates (a driver law that jumps) cannot agree in position: refuse."""
    coords = set(model.coords)
    defaults = {sym: val for sym, val in model.params.values()}
    for k in range(len(stages) - 1):
        ts = sp.Float(stages[k].until)
        a, b = sp.sympify(pieces[k][2]), sp.sympify(pieces[k + 1][2])
        gap = sp.expand((a - b).subs(T, ts))
        if gap.free_symbols & coords:
            continue          # depends on the configuration: checked when a sweep crosses
        try:
            value = complex(gap.subs(defaults).evalf())
        except (TypeError, ValueError):
            continue
        scale = max(1.0, abs(complex(a.subs(T, ts).subs(defaults).subs(
            {c: 0 for c in coords}).evalf())))
        if abs(value) > 1e-9 * scale:
            raise ModelError(
                f"stages '{stages[k].name}' and '{stages[k + 1].name}' disagree in position at "
                f"the switch t={float(ts):g}: row '{pieces[k][3]}' minus row "
                f"'{pieces[k + 1][3]}' is {gap} = {value.real:.6g} (parameters at their "
                "defaults) whatever the coordinates; make the later stage's law start where "
                "the earlier one ends", where=stages[k + 1].where)


def constraint_table(model):
    """Per constraint (or group of stage constraints sharing rows), in row order: dict(number,
    kind, label, rows, driver), the generated module's CONSTRAINTS table."""
    if not model.stages:
        return [dict(number=c.number, kind=c.kind, label=c.label, rows=len(c.exprs),
                     driver=c.is_driver) for c in model.constraints]
    staged = {n for s in model.stages for n in s.numbers}
    first = set(model.stages[0].numbers)
    groups = [[c for c in s.constraints] for s in model.stages]
    out = []
    for con in model.constraints:
        if con.number not in staged:
            out.append(dict(number=con.number, kind=con.kind, label=con.label,
                            rows=len(con.exprs), driver=con.is_driver))
        elif con.number in first:
            k = groups[0].index(con)
            # the first stage's constraint stands for the rows it shares with the others
            label = " | ".join(f"[{s.name}] {g[k].label}" if k < len(g) else f"[{s.name}]"
                               for s, g in zip(model.stages, groups))
            out.append(dict(number=con.number, kind="stages", label=label,
                            rows=len(con.exprs), driver=True))
    return out


def stages_context(model):
    """What a generated module states about its stages: [(name, start, end, range text)]."""
    def text(x):
        return repr(x) if math.isfinite(x) else f'float("{x}")'
    return [dict(name=s.name, start=text(s.start), end=text(s.end), range=s.range_text(),
                 constraints=[c.label for c in s.constraints]) for s in model.stages]
