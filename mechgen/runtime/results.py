"""Solutions and sweeps: arrays indexed by coordinate name (``"X4"``, ``"X4d"``, ``"X4dd"``)
and by declared output name; CSV and pandas export. A sweep's interpolation, extremes and
roots are computed by mechgen.runtime.analysis.interpolate and mechgen.runtime.analysis.events."""
from __future__ import annotations

import csv

import numpy as np

from ..errors import MechgenError
from ..protocol import (INFO_COLUMNS, INFO_ITERATIONS, INFO_JUMP, INFO_STATUS, JUMP, LEVEL,
                        LEVELS, REPORT_JUMP, STATUS_CODE, STATUS_COLUMNS, STATUS_ITERATIONS,
                        STATUS_SUBSTEPS, INFO_SUBSTEPS)
from .quantity import lookup, column_names, level_needed, level_of

__all__ = ["Solution", "Sweep", "write_csv", "lookup"]

_NONE = np.empty(0)             # the jumps and crossings of a sweep that has none
_NONE.flags.writeable = False
_INT16 = np.dtype(np.int16)


def _status_rows(status, N):
    """A sweep's STATUS rows (int16, protocol.STATUS_*) from what was given: those rows,
    None (all OK, iterations unknown) or the wide float INFO rows of format 2."""
    if status is None:
        return np.zeros((N, 1), dtype=np.int16)
    status = np.asarray(status)
    if status.ndim == 2 and status.dtype.kind == "f" and status.shape[1] > INFO_STATUS:
        rows = np.empty((status.shape[0], STATUS_COLUMNS), dtype=np.int16)
        rows[:, STATUS_CODE] = status[:, INFO_STATUS]
        rows[:, STATUS_ITERATIONS] = status[:, INFO_ITERATIONS]
        rows[:, STATUS_SUBSTEPS] = status[:, INFO_SUBSTEPS] if status.shape[1] > INFO_SUBSTEPS \
            else 0
        return rows
    if status.ndim == 1:            # the codes alone
        return status.astype(np.int16).reshape(-1, 1)
    return status


def write_csv(path, header, data):
    """A table as CSV: full-precision numbers, NaN (not solved) as an empty cell."""
    with open(path, "w", newline="") as fh:
        w = csv.writer(fh)
        w.writerow(header)
        for row in data:
            w.writerow(["" if x != x else repr(float(x)) for x in row])
    return path


# what a solution or a sweep at a force level has (mechgen.runtime.forces), asked of one at a
# kinematic level: an AttributeError that says which level they need
_FORCE_NAMES = frozenset(("driver", "reaction", "reactions", "multipliers", "contact",
                          "contacts", "indeterminate", "power", "energy", "shaking",
                          "flywheel", "contact_lost"))


def _no_forces(obj, name, call):
    plain = f"{type(obj).__name__!r} object has no attribute {name!r}"
    if name not in _FORCE_NAMES:
        return AttributeError(plain)
    if hasattr(type(obj), "force_level"):       # at a force level: the other kind has it
        other = "sweep" if call == "solve" else "solve"
        return AttributeError(f"{plain} (it is a {other}'s: mech.{other}(..., "
                              f"level={obj.force_level!r}))")
    try:
        level = f"; this one is at level {obj.level!r}"
    except Exception:
        level = ""
    return AttributeError(f"{name}: forces need a {call} at level \"dynamic\" or \"static\" "
                          f"(mech.{call}(..., level=\"dynamic\")){level}")


def pandas():
    """The pandas module, or an ImportError that says what needs it (pandas is optional)."""
    try:
        import pandas as pd     # optional: only to_dataframe() needs it
    except ImportError:
        raise ImportError("to_dataframe() needs pandas (pip install pandas); "
                          "to_csv() works without it") from None
    return pd


class Derivatives:
    """What a Solution or Sweep solved with ``sensitivities=`` answers
    (docs/reference/sensitivities.md): the Sensitivities object mechgen.runtime.sensitivity
    attaches does the work."""

    def _carried(self):
        sens = self.__dict__.get("sensitivities")
        if sens is None:
            call = "solve" if isinstance(self, Solution) else "sweep"
            raise MechgenError(f"this result carries no sensitivities: {call}(..., "
                               "sensitivities=True) or a list of parameter names")
        return sens

    def sensitivity(self, name, param):
        """∂name/∂param: a coordinate or its rate (``"X4"``, ``"X4dd"``), a declared output,
        a symbolic quantity (Mech's output functions) or, solved at a force level, a
        driver's effort; a float on a Solution, an array over a Sweep's points."""
        return self._carried().value(self, name, param)

    @property
    def sensitivity_params(self) -> list:
        """The parameters whose derivatives this result carries (dq_dp's columns)."""
        return list(self._carried().params)

    @property
    def dq_dp(self) -> np.ndarray:
        """dq/dp: (coordinates, parameters) on a Solution, (points, coordinates,
        parameters) on a Sweep; dqd_dp and dqdd_dp the same for the rates (None above
        the result's level)."""
        return self._carried().of_order(0)

    @property
    def dqd_dp(self):
        return self._carried().of_order(1)

    @property
    def dqdd_dp(self):
        return self._carried().of_order(2)


class Solution(Derivatives):
    """One solved configuration: ``s.t``, ``s.q``, ``s.qd``, ``s.qdd`` and ``s["X4"]``."""

    sensitivities = None        # the derivatives with respect to the parameters, if asked

    def __init__(self, mech, t, q, qd=None, qdd=None, iterations=0, residual=0.0,
                 singular=False, method="sorted"):
        self.mechanism = mech
        self.t = float(t)
        self.q = q
        self.qd = qd
        self.qdd = qdd
        self.iterations = iterations
        self.residual = residual
        self.singular = singular
        self.method = method

    @property
    def level(self) -> str:
        return LEVELS[level_of(self.qd, self.qdd)]

    def __getattr__(self, name):
        # only for names the instance lacks: a kinematic solution asked for its forces
        raise _no_forces(self, name, "solve")

    def __getitem__(self, name):
        kind, k, order = lookup(self.mechanism, name)
        if kind == "q":
            vec = (self.q, self.qd, self.qdd)[order]
            if vec is None:
                raise KeyError(f"{name!r} needs a solve at level {LEVELS[order]} "
                               f"(this solution is at level {self.level})")
            return float(vec[k])
        need = self.mechanism.output_orders[k] + order
        if need > level_of(self.qd, self.qdd):
            raise KeyError("output " + level_needed(name, need, level_of(self.qd, self.qdd),
                                                    "solve"))
        return float(self.mechanism.output_values(self.q, self.qd, self.qdd, self.t, order)[k])

    def keys(self):
        """The names this solution answers, in the order of a sweep's columns: the
        coordinates, their derivatives up to its level, then the declared outputs (OUTPUTS
        of the generated module) and those of their derivatives the level allows."""
        return column_names(self.mechanism, level_of(self.qd, self.qdd))

    def as_dict(self) -> dict:
        """Mech's rule list: {"T": t, "X2": ..., ..., "stroke_x": ...}, outputs included."""
        out = {"T": self.t}
        out.update({k: self[k] for k in self.keys()})
        return out

    def points(self) -> np.ndarray:
        """Global positions of the module's points (mech.point_names)."""
        return self.mechanism.points_at(self.q, self.t)

    def __repr__(self):
        # the outputs too, as a sweep's repr and table show them
        items = ", ".join(f"{k} -> {v + 0.0:.6g}" for k, v in self.as_dict().items())  # no -0
        flag = ", singular" if self.singular else ""
        return f"<Solution {{{items}}}{flag}>"

    def _repr_html_(self):
        cells = "".join(f"<tr><td>{k}</td><td>{v + 0.0:.10g}</td></tr>"
                        for k, v in self.as_dict().items())
        flag = " (singular)" if self.singular else ""
        return (f"<p>Solution of <b>{self.mechanism.name}</b>{flag}</p>"
                f"<table><tbody>{cells}</tbody></table>")


class Sweep(Derivatives):
    """Solutions at many times: ``sw.t`` and ``sw["X4"]`` are numpy arrays.

    ``sw.Q`` (and ``sw.QD``, ``sw.QDD`` at the levels solved, else None) are the solved
    rows; ``sw.status`` is each point's status code (protocol: OK, JUMP,
    THROUGH_SINGULAR) and ``sw.iterations`` its Newton iterations. ``sw.jumps`` and
    ``sw.crossings`` are the times a sweep reached by a branch jump or at or through a
    singular configuration (Mechanism.sweep fills them in). ``sw.simulation`` is how a
    sweep of mech.simulate was integrated (its free drivers and tolerances), else None:
    the exact values that extrema() and roots() refine come from integrating again
    between its outputs, never from the kinematics."""

    simulation = None
    sensitivities = None        # the derivatives with respect to the parameters, if asked

    def __init__(self, mech, t, Q, QD=None, QDD=None, status=None, report=None):
        self.mechanism = mech
        self.t = t
        self.Q = Q
        self.QD = QD
        self.QDD = QDD
        self._status = status if status.__class__ is np.ndarray and status.dtype is _INT16 \
            and status.ndim == 2 else _status_rows(status, Q.shape[0])
        self._report = report
        self.jumps = self.crossings = _NONE

    @property
    def status(self) -> np.ndarray:
        """Each point's status code (int16): OK (0), JUMP or THROUGH_SINGULAR."""
        return self._status[:, STATUS_CODE]

    @property
    def iterations(self):
        """Each point's Newton iterations (int16), or None where not recorded."""
        if self._status.shape[1] <= STATUS_ITERATIONS:
            return None
        return self._status[:, STATUS_ITERATIONS]

    @property
    def substeps(self):
        """The substeps each point took on the way to it (int16), or None where not
        recorded."""
        if self._status.shape[1] <= STATUS_SUBSTEPS:
            return None
        return self._status[:, STATUS_SUBSTEPS]

    @property
    def info(self) -> np.ndarray:
        """The wide per-point rows of earlier versions (float, protocol.INFO_COLUMNS):
        iterations, status and substeps filled, the size of the first jump at its point,
        NaN in the columns a sweep no longer records (residual, rank, method)."""
        N = len(self)
        info = np.full((N, INFO_COLUMNS), np.nan)
        info[:, INFO_STATUS] = self.status
        its = self.iterations
        info[:, INFO_ITERATIONS] = np.nan if its is None else its
        sub = self.substeps
        info[:, INFO_SUBSTEPS] = np.nan if sub is None else sub
        info[:, INFO_JUMP] = 0.0
        jumped = self.status == JUMP
        if self._report is not None and np.any(jumped):
            info[int(np.argmax(jumped)), INFO_JUMP] = self._report[REPORT_JUMP]
        return info

    @property
    def level(self) -> str:
        return LEVELS[self._have()]

    def __len__(self):
        return self.t.shape[0]

    def __getattr__(self, name):
        # only for names the instance lacks: a kinematic sweep asked for its forces
        raise _no_forces(self, name, "sweep")

    def _have(self) -> int:
        """The level held, as an index into LEVELS."""
        return level_of(self.QD, self.QDD)

    @property
    def solved_t(self) -> np.ndarray:
        """The times the equations were solved at: ``t``, but for a sweep across a stage
        switch, whose left limit of a switch was solved just below the switch time (what
        the equations read there: the earlier stage's rows)."""
        return self.__dict__.get("_solved_t", self.t)

    def __getitem__(self, key):
        if isinstance(key, (int, np.integer)):
            k = int(key)
            if k < 0:
                k += len(self)
            if not 0 <= k < len(self):
                raise IndexError(f"sweep index {key} out of range ({len(self)} points)")
            return Solution(self.mechanism, self.t[k], self.Q[k].copy(),
                            None if self.QD is None else self.QD[k].copy(),
                            None if self.QDD is None else self.QDD[k].copy())
        kind, k, order = lookup(self.mechanism, key)
        if kind == "q":
            arr = (self.Q, self.QD, self.QDD)[order]
            if arr is None:
                raise KeyError(f"{key!r} needs a sweep at level {LEVELS[order]} "
                               f"(this sweep is at level {self.level})")
            return arr[:, k].copy()
        need = self.mechanism.output_orders[k] + order
        if need > self._have():
            raise KeyError("output " + level_needed(key, need, self._have(), "sweep"))
        return self.outputs(order)[:, k].copy()

    def outputs(self, order=0) -> np.ndarray:
        """All declared outputs (or their derivatives) at every point, compiled loop."""
        mech = self.mechanism
        out = np.empty((len(self), len(mech.outputs)))
        z = np.zeros_like(self.Q)
        mech.module.eval_outputs(self.Q, z if self.QD is None else self.QD,
                                 z if self.QDD is None else self.QDD, self.solved_t, mech.p,
                                 order, out)
        return out

    def points(self) -> np.ndarray:
        """Point positions at every time: shape (len, n_points, 2)."""
        mech = self.mechanism
        out = np.empty((len(self), len(mech.point_names), 2))
        mech.module.eval_points(self.Q, self.solved_t, mech.p, out)
        return out

    def columns(self) -> list:
        """The names of the table's columns after T: coordinates, their derivatives, outputs."""
        return column_names(self.mechanism, self._have())

    def table(self) -> tuple[list, np.ndarray]:
        cols = self.columns()
        data = np.column_stack([self.t] + [self[c] for c in cols]) if len(self) else \
            np.zeros((0, len(cols) + 1))
        return ["T"] + cols, data

    def to_csv(self, path):
        """Write T and every column to a CSV file; where the model declares its units,
        each name carries its unit ("T [s]", "X4 [mm]", "crank [N·mm]": unit_columns)."""
        from .unit_columns import labelled
        return write_csv(path, *labelled(self.mechanism, *self.table()))

    def to_dataframe(self):
        """A pandas DataFrame of T and every column (needs pandas)."""
        header, data = self.table()
        return pandas().DataFrame(data, columns=header)

    def at_level(self, level) -> "Sweep":
        """This sweep with the velocity (and, for "acceleration", the acceleration) level
        solved at its own positions: linear solves, no Newton iteration. Levels it holds
        already are kept; raises SingularError at a point where they are not determined."""
        lev = LEVEL[level] if isinstance(level, str) else int(level)
        QD, QDD = self.mechanism.solve_derivatives(self.t, self.Q, self.QD, self.QDD, lev)
        out = Sweep(self.mechanism, self.t, self.Q, QD, QDD, self._status, self._report)
        out.jumps, out.crossings = self.jumps, self.crossings
        out.simulation = self.simulation
        return out

    # -- analysis (mechgen.runtime.analysis.interpolate, mechgen.runtime.analysis.events: imported when first
    # used, not by a process that only solves) ----------------------------------------------
    def interpolate(self, name, method="auto", degree=3, extrapolate=False):
        """A callable of t (Mech's TimeInterpolate) using the derivatives the sweep holds:
        quintic Hermite with accelerations, cubic Hermite with velocities, a cubic spline
        on positions; method="lagrange" is Mathematica's default InterpolatingFunction."""
        from .analysis.interpolate import interpolate
        return interpolate(self, name, method=method, degree=degree, extrapolate=extrapolate)

    def extrema(self, name, method="auto", xtol=1e-12):
        """Maxima and minima of a quantity, bracketed by the sweep and refined on exact
        solves of its time derivative; each also says what the interpolant gives. The
        sweep's ends are extremes too (``e.at`` "start"/"end"); a sweep over exactly one
        period is a closed cycle (``.periodic``), whose extremes through its ends are
        found once, as interior ones."""
        from .analysis.events import extrema
        return extrema(self, name, method=method, xtol=xtol)

    def roots(self, name, method="auto", xtol=1e-12):
        """Times where a quantity crosses zero, refined on exact solves; a zero at an end
        of the sweep counts (``e.at``), except through the ends of a closed cycle."""
        from .analysis.events import roots
        return roots(self, name, method=method, xtol=xtol)

    def singularities(self):
        """Where Φ_q loses rank between the first and last time of this sweep, along its
        assembly mode (mech.singularities on the same times and start)."""
        if len(self) < 2:
            return []
        return self.mechanism.singularities(self.t[0], self.t[-1], n=max(len(self), 201),
                                            guess=self.Q[0])

    @property
    def sensitivity_singular(self) -> np.ndarray:
        """The times of this sweep where Φ_q had lost rank: no sensitivities (NaN) there."""
        return self.t[np.asarray(self._carried().singular, dtype=bool)]

    def _repr_html_(self):
        header, data = self.table()
        rows = range(len(self)) if len(self) <= 20 else [*range(8), None, *range(len(self) - 8, len(self))]
        head = "".join(f"<th>{h}</th>" for h in header)
        body = []
        for k in rows:
            if k is None:
                body.append(f"<tr><td colspan='{len(header)}'>... {len(self) - 16} rows ...</td></tr>")
            else:
                body.append("<tr>" + "".join(f"<td>{v:.6g}</td>" for v in data[k]) + "</tr>")
        return (f"<p>Sweep of <b>{self.mechanism.name}</b>: {len(self)} points, level "
                f"{self.level}</p><table><thead><tr>{head}</tr></thead><tbody>"
                f"{''.join(body)}</tbody></table>")

    def __repr__(self):
        if not len(self):
            return f"<Sweep of '{self.mechanism.name}': no points>"
        cols = self.columns()
        shown = ", ".join(cols[:12]) + (f", ... ({len(cols)} columns)" if len(cols) > 12 else "")
        return (f"<Sweep of '{self.mechanism.name}': {len(self)} points, T from {self.t[0]:.6g} "
                f"to {self.t[-1]:.6g}, level {getattr(self, 'force_level', self.level)}; "
                f"columns {shown}>")
