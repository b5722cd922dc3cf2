"""Design tables: a sweep over time for every combination of parameter values (Mech's
Table[SetGuess[]; SolveMech[{t0, t1}, n], {param, ...}]), the loop over designs run
inside the compiled module (its sweep_designs()).

Mechanism.design_sweep checks the arguments and calls the functions here in order:
split_params (which parameters vary), design_grid (one parameter vector per design),
run_designs (the compiled loop, in chunks when progress is reported), then builds the
DesignTable and report_failures says which designs did not solve.
"""
from __future__ import annotations

import sys
import warnings

import numpy as np

from ..errors import MechgenError
from ..protocol import LEVEL, LEVELS, STATUS_CODE
from .guards import finite
from .quantity import _lookup, column_names
from .results import Sweep, pandas, write_csv

# A design table's per-point record: the first column of a sweep's STATUS rows (int16: the
# status code, protocol.STATUS_*), 2 bytes a point. INFO is its name in a DesignTable.
DESIGN_INFO_COLUMNS = STATUS_CODE + 1
ON_FAIL = ("warn", "raise", "ignore")


def _axis(name, values):
    arr = np.atleast_1d(np.asarray(values, dtype=np.float64))
    if arr.ndim != 1 or arr.size == 0:
        raise ValueError(f"parameter {name!r}: give a number or a 1-D sequence of numbers")
    if not np.all(np.isfinite(arr)):
        raise ValueError(f"parameter {name!r}: values must be finite")
    return arr


class DesignTable:
    """Sweeps of one mechanism over a grid of parameter values (a design table).

    ``tab["X4"]`` has shape ``tab.shape + (len(tab.t),)`` (one axis per varied parameter,
    in the order given, then time); points a design could not solve are NaN and
    ``tab.ok`` / ``tab.failures`` say which. ``tab.sweep(i, ...)`` or
    ``tab.sweep(longitud=1.5)`` is one design as a :class:`~mechgen.Sweep`.
    """

    def __init__(self, mech, names, axes, t, P, Q, QD, QDD, INFO, done, level):
        self.mechanism = mech
        self.names = tuple(names)
        self.axes = tuple(axes)
        self.params = dict(zip(self.names, self.axes))
        self._column = {n: mech.parameter_names.index(n) for n in self.names}   # in P
        self.shape = tuple(len(a) for a in axes)
        self.t = t
        self.P = P
        self.Q, self.QD, self.QDD, self.INFO = Q, QD, QDD, INFO
        self.done = done
        self.level = level
        self._have = LEVEL[level]

    @property
    def ok(self) -> np.ndarray:
        """True for the designs solved at every time."""
        return (self.done == len(self.t)).reshape(self.shape)

    @property
    def failures(self) -> list:
        """(parameter values, time of failure, status) of each design that failed."""
        out = []
        for d in np.nonzero(self.done < len(self.t))[0]:
            k = int(self.done[d])
            values = {n: float(self.P[d, self._column[n]]) for n in self.names}
            out.append((values, float(self.t[k]), int(self.INFO[d, k, STATUS_CODE])))
        return out

    def __len__(self):
        return int(np.prod(self.shape))

    def _flat(self, index=None, **values):
        if values:
            if index is not None:
                raise TypeError("give grid indices or parameter values, not both")
            idx = []
            for name, axis in zip(self.names, self.axes):
                if name not in values:
                    raise KeyError(f"give a value for each varied parameter ({', '.join(self.names)})")
                hit = np.nonzero(np.isclose(axis, values.pop(name), rtol=1e-12, atol=1e-12))[0]
                if not hit.size:
                    raise KeyError(f"{name} = {values} is not on the grid {axis.tolist()}")
                idx.append(int(hit[0]))
            if values:
                raise KeyError(f"{', '.join(values)} is not a varied parameter "
                               f"({', '.join(self.names)})")
            index = tuple(idx)
        if not isinstance(index, tuple):
            index = (index,)
        return int(np.ravel_multi_index(index, self.shape))

    def sweep(self, *index, **values):
        """One design as a Sweep (only the points it solved)."""
        d = self._flat(index if index else None, **values)
        mech = self.mechanism.with_params(**{n: float(self.P[d, self._column[n]])
                                             for n in self.names})
        k = int(self.done[d])
        QD = self.QD[d, :k].copy() if self._have >= LEVEL["velocity"] else None
        QDD = self.QDD[d, :k].copy() if self._have >= LEVEL["acceleration"] else None
        return Sweep(mech, self.t[:k].copy(), self.Q[d, :k].copy(), QD, QDD,
                     self.INFO[d, :k].copy())

    @property
    def sweeps(self) -> list:
        """Every design as a Sweep, in grid order (Mech's Table)."""
        return [self.sweep(*np.unravel_index(d, self.shape)) for d in range(len(self))]

    def __getitem__(self, name) -> np.ndarray:
        if not isinstance(name, str):
            raise TypeError("index a design table by quantity name (tab['X4']); "
                            "use tab.sweep(i) for one design")
        mech = self.mechanism
        kind, k, order = _lookup(mech, name)
        N = len(self.t)
        D = len(self)
        if kind == "q":
            if order > self._have:
                raise KeyError(f"{name!r} needs a table at level {LEVELS[order]}")
            arr = (self.Q, self.QD, self.QDD)[order][:, :, k].copy()
        else:
            need = mech.output_orders[k] + order
            if need > self._have:
                raise KeyError(f"output {name!r} needs a table at level {LEVELS[min(need, LEVEL['acceleration'])]}")
            arr = np.empty((D, N))
            out = np.empty((N, len(mech.outputs)))
            for d in range(D):
                mech.module.eval_outputs(self.Q[d], self.QD[d], self.QDD[d], self.t,
                                         self.P[d], order, out)
                arr[d] = out[:, k]
        for d in range(D):
            arr[d, int(self.done[d]):] = np.nan
        return arr.reshape(self.shape + (N,))

    def table(self) -> tuple[list, np.ndarray]:
        """A long table: one row per design and time; the varied parameters, T, then the
        coordinates (and derivatives) and outputs the table's level provides."""
        grid = np.stack(np.meshgrid(*self.axes, indexing="ij"), axis=-1).reshape(-1, len(self.axes))
        N = len(self.t)
        header = list(self.names) + ["T"]
        cols = [np.repeat(grid[:, j], N) for j in range(len(self.names))]
        cols.append(np.tile(self.t, len(self)))
        mech = self.mechanism
        for name in column_names(mech, self._have, coordinates=mech.coordinates):
            header.append(name)
            cols.append(self[name].reshape(-1))
        return header, np.column_stack(cols)

    def to_csv(self, path):
        """Write the long table (see table()) to a CSV file; unsolved points are empty."""
        return write_csv(path, *self.table())

    def to_dataframe(self):
        """The long table (see table()) as a pandas DataFrame (needs pandas)."""
        header, data = self.table()
        return pandas().DataFrame(data, columns=header)

    def __repr__(self):
        axes = ", ".join(f"{n} in [{', '.join(f'{v:g}' for v in a[:6])}{', ...' if len(a) > 6 else ''}]"
                         for n, a in zip(self.names, self.axes))
        bad = len(self) - int(np.sum(self.done == len(self.t)))
        return (f"<DesignTable of '{self.mechanism.name}': {len(self)} designs ({axes}) × "
                f"{len(self.t)} times, level {self.level}"
                f"{f', {bad} failed' if bad else ''}>")


def split_params(mech, params):
    """(fixed, names, axes) of a design sweep's ``params``: a number fixes a parameter,
    a sequence varies it (an axis of the grid)."""
    if not isinstance(params, dict) or not params:
        raise ValueError("params must be a dict of parameter names to values or sequences")
    fixed, names, axes = {}, [], []
    for name, values in params.items():
        if name not in mech.parameter_names:
            known = ", ".join(mech.parameter_names) or "none"
            raise ValueError(f"model '{mech.name}' has no parameter {name!r} (parameters: {known})")
        if np.ndim(values) == 0:
            fixed[name] = finite(values, f"parameter {name!r}")
        else:
            names.append(name)
            axes.append(_axis(name, values))
    return fixed, names, axes


def design_grid(base, index, names, axes) -> np.ndarray:
    """One parameter vector per design (rows, in grid order): ``base`` with the varied
    parameters (their positions in ``index``) set to every combination of the axes."""
    grid = np.stack(np.meshgrid(*axes, indexing="ij"), axis=-1).reshape(-1, len(axes))
    P = np.tile(base, (grid.shape[0], 1))
    for j, name in enumerate(names):
        P[:, index[name]] = grid[:, j]
    return np.ascontiguousarray(P)


def run_designs(module, ts, q0, P, lev, tol, xtol, maxit, meth, progress=None):
    """The compiled loop over designs (the module's sweep_designs): (Q, QD, QDD, INFO,
    done), indexed by design, then time. With ``progress`` it runs in chunks and reports
    between them (see _progress_reporter)."""
    D, N, nq = P.shape[0], ts.shape[0], q0.shape[0]
    Q, QD, QDD = np.zeros((D, N, nq)), np.zeros((D, N, nq)), np.zeros((D, N, nq))
    INFO = np.zeros((D, N, DESIGN_INFO_COLUMNS), dtype=np.int16)
    done = np.zeros(D, dtype=np.int64)
    report = _progress_reporter(progress, D)
    # about 50 reports, and no chunk much over 200,000 solved points between two of them
    chunk = D if report is None else max(1, min(D, -(-D // 50), max(1, 200_000 // max(N, 1))))
    for a in range(0, D, chunk):
        b = min(D, a + chunk)
        done[a:b] = module.sweep_designs(ts, q0, P[a:b], lev, tol, xtol, maxit, meth,
                                         Q[a:b], QD[a:b], QDD[a:b], INFO[a:b])
        if report is not None:
            report(b, D)
    if report is not None:
        report(None, D)
    return Q, QD, QDD, INFO, done


def _progress_reporter(progress, total):
    """None (quiet), a callable progress(done, total), or a progress line on stderr."""
    if progress is None or progress is False:
        return None
    if callable(progress):
        def call(done, total_):
            if done is not None:
                progress(done, total_)
        return call

    def line(done, total_):
        if done is None:
            sys.stderr.write("\n")
        else:
            sys.stderr.write(f"\rdesigns solved: {done}/{total_} ({100.0 * done / total_:.0f}%)")
        sys.stderr.flush()
    return line


def report_failures(table, on_fail, stacklevel=2):
    """Warn about (on_fail="warn") or raise for (on_fail="raise") the designs that could
    not be solved at every time; on_fail="ignore" says nothing. ``stacklevel`` as
    warnings.warn counts it from here (3: the caller of report_failures' caller)."""
    bad = table.failures
    if not bad or on_fail == "ignore":
        return
    first = bad[0]
    where = ", ".join(f"{k}={v:g}" for k, v in first[0].items())
    msg = (f"{len(bad)} of {len(table)} designs of '{table.mechanism.name}' could not be "
           f"solved at every time (first: {where} fails at t={first[1]:.10g}, status "
           f"{first[2]}); their unsolved points are NaN")
    if on_fail == "raise":
        err = MechgenError(msg)
        err.table = table
        raise err
    warnings.warn(msg, RuntimeWarning, stacklevel=stacklevel)
