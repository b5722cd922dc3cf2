"""Design tables: a sweep over time for every combination of parameter values (Mech's
Table[SetGuess[]; SolveMech[{t0, t1}, n], {param, ...}]), the loop over designs run
inside the compiled module (its sweep_designs()) on a backend (mechgen.runtime.tables.backends:
every core, a dask cluster or a GPU).

design_table (Mechanism.design_sweep) checks the arguments and calls the functions here in
order: split_params (which parameters vary), design_grid or design_list (one parameter
vector per design), the backend, then builds the DesignTable and report_failures says
which designs did not solve. With ``reduce`` the table keeps per design only the minimum,
maximum and their times of the named quantities (mechgen.runtime.tables.reduce).
"""
from __future__ import annotations

import math

import warnings

import numpy as np

from ...errors import BranchJumpWarning, MechgenError
from ...protocol import JUMP, LEVEL, LEVELS, THROUGH_SINGULAR
from ..forces import attach, is_force_level
from ..forces.lookup import (column_name, division_error, effort_column, loads_guarded,
                             tables)
from ..guards import finite, fits, point_bytes, sweep_times
from ..kinematics.entry import module_attr
from ..quantity import lookup, column_names
from ..results import Sweep, pandas, write_csv
from ..kinematics.sweeping import divides
from .backends import cuda_keeps_points, progress_reporter, run_backend
from .chunks import reduce_threads
from .starts import design_starts, guess_reference, mark_starts, quiet_params
from .reduce import (Reduction, driver_efforts, driver_slot, reduce_chunk,
                     reduce_slots, status_name)

ON_FAIL = ("warn", "raise", "ignore")


def _axis(name, values):
    arr = np.atleast_1d(np.asarray(values, dtype=np.float64))
    if arr.ndim != 1:
        raise ValueError(f"parameter {name!r}: give a number or a 1-D sequence of numbers")
    if arr.size == 0:
        raise ValueError(f"parameter {name!r}: the range of values is empty")
    bad = np.nonzero(~np.isfinite(arr))[0]
    if bad.size:
        raise ValueError(f"parameter {name!r}: values must be finite (value {arr[bad[0]]!r} "
                         f"at position {int(bad[0])})")
    return arr


class DesignTable:
    """Sweeps of one mechanism over a grid of parameter values (a design table).

    ``tab["X4"]`` has shape ``tab.shape + (len(tab.t),)`` (one axis per varied parameter,
    in the order given, then time); points a design could not solve are NaN and
    ``tab.ok`` / ``tab.failures`` / ``tab.status`` say which. ``tab.sweep(i, ...)`` or
    ``tab.sweep(longitud=1.5)`` is one design as a :class:`~mechgen.Sweep`. A table of
    listed designs (``grid=False``) has one axis, the designs, and ``tab.params`` holds
    each varied parameter's value per design. A table made with ``reduce=[...]`` keeps
    only ``tab.reduced(name)`` (minimum, maximum and their times per design).
    """

    sensitivities = None    # with sensitivities=: each design's (mechgen.runtime.sensitivity)

    def __init__(self, mech, names, axes, t, P, data, level, grid=True, reduced=(),
                 force_level=None, start=None):
        self.mechanism = mech
        self._start = mech if start is None else start      # whose guess the designs left
        self.force_level = force_level      # "static" or "dynamic": λ on demand
        self.names = tuple(names)
        self.axes = tuple(axes)
        self.grid = bool(grid)
        self.params = dict(zip(self.names, self.axes))
        self._column = {n: mech.parameter_names.index(n) for n in self.names}   # in P
        self.shape = tuple(len(a) for a in axes) if grid else (P.shape[0],)
        self.t = t
        self.P = P
        self.Q, self.QD, self.QDD, self.INFO = data.Q, data.QD, data.QDD, data.INFO
        self.done = data.done
        self._status = data.status
        self.level = level
        self._have = LEVEL[level]
        self._reduced = {}
        if data.red is not None:
            ok = self.ok
            status = self.status
            for j, name in enumerate(reduced):
                self._reduced[name] = Reduction(
                    name, *(arr[:, j].reshape(self.shape) for arr in data.red), ok, status)

    @property
    def ok(self) -> np.ndarray:
        """True for the designs solved at every time."""
        return (self.done == len(self.t)).reshape(self.shape)

    @property
    def status(self) -> np.ndarray:
        """Each design's status (mechgen.protocol codes): the status of the point it
        failed at, else JUMP or THROUGH_SINGULAR when a point was reached so, else OK.
        ``tab.status_text`` says them in words. The codes: 0 ok; 1 no convergence (Newton
        used up its iterations: past a lock, or the loop cannot close); 2 singular (Φ_q
        lost rank); 3 not finite (a value divided by zero); 4 sorted solver gave up (the
        full Newton took over); 5 branch jump (a point reached by a jump the step control
        could not avoid); 6 through a singular configuration (reached at or through one);
        10 + a code: the velocity solve failed so, 20 + a code: the acceleration solve."""
        return self._status.reshape(self.shape)

    @property
    def status_text(self) -> np.ndarray:
        """``tab.status`` in words, an array of str of the table's shape: "ok", "no
        convergence", "singular", "not finite", "sorted solver gave up", "branch jump",
        "through a singular configuration", or "velocity solve: ..." / "acceleration
        solve: ..." for 10 + and 20 + a code (see ``status``)."""
        codes = self._status.reshape(-1)
        words = {int(c): status_name(c) for c in np.unique(codes)}
        return np.array([words[int(c)] for c in codes], dtype=str).reshape(self.shape)

    @property
    def kept_points(self) -> bool:
        """Whether the table kept every point (False: a table of reductions only)."""
        return self.Q is not None

    @property
    def reductions(self) -> tuple:
        """The names of the quantities reduced (``reduce=``), in order."""
        return tuple(self._reduced)

    def reduced(self, name) -> Reduction:
        """The reduction of quantity ``name`` (``reduce=[name, ...]``): ``.min``, ``.max``,
        ``.tmin``, ``.tmax``, ``.ok``, ``.status``, arrays of the table's shape. On a table
        that kept every point it is computed from them."""
        if name in self._reduced:
            return self._reduced[name]
        same = self._reduced_as(name)       # another name of a reduced quantity (a
        if same is not None:                # driver by its number, its name or its label)
            return self._reduced[same]
        if not self.kept_points:
            raise KeyError(f"{name!r} was not reduced (this table reduced "
                           f"{', '.join(map(str, self._reduced))}); pass reduce=[..., {name!r}]")
        names, slots = reduce_slots(self.mechanism, [name], self._have, self.force_level)
        red = reduce_chunk(self.mechanism.module, slots, self.t, self.P, self.Q, self.QD,
                           self.QDD, self.done)
        return Reduction(name, *(arr[:, 0].reshape(self.shape) for arr in red), self.ok,
                         self.status)

    def _reduced_as(self, name):
        """The key of the reduction of the quantity ``name`` names, where the table reduced
        it under another name (a driver by number and by name); else None."""
        if not self._reduced:
            return None
        try:
            _, want = reduce_slots(self.mechanism, [name], self._have, self.force_level)
        except (ValueError, TypeError, KeyError):
            return None
        _, have = reduce_slots(self.mechanism, list(self._reduced), self._have, self.force_level)
        for key, slot in zip(self._reduced, have):
            if np.array_equal(slot, want[0]):
                return key
        return None

    def take(self, designs) -> "DesignTable":
        """The designs picked by ``designs`` (flat indices or a boolean mask over the
        table's designs, in grid order) as a table of listed designs."""
        idx = np.arange(len(self))[np.asarray(designs).reshape(-1)] \
            if np.asarray(designs).dtype == bool else np.asarray(designs, dtype=np.int64).reshape(-1)
        from .chunks import TableData
        pick = (lambda a: None if a is None else a[idx])
        data = TableData(pick(self.Q), pick(self.QD), pick(self.QDD), pick(self.INFO),
                         self.done[idx], self._status[idx],
                         None if not self._reduced else tuple(
                             np.stack([getattr(r, w).reshape(-1)[idx] for r in self._reduced.values()], axis=1)
                             for w in ("min", "max", "tmin", "tmax")))
        P = self.P[idx]
        axes = [P[:, self._column[n]] for n in self.names]
        return DesignTable(self.mechanism, self.names, axes, self.t, P, data, self.level,
                           grid=False, reduced=tuple(self._reduced),
                           force_level=self.force_level, start=self._start)

    def extremes(self, name) -> Reduction:
        """The exact minimum and maximum of ``name`` for every design and their times, as
        ``reduced`` gives them but refined off the time grid by Newton's method on the
        compiled solver (mechgen.runtime.tables.refine; needs the table's points)."""
        from .refine import extremes
        return extremes(self, name)

    def _values(self, d) -> dict:
        return {n: float(self.P[d, self._column[n]]) for n in self.names}

    @property
    def failures(self) -> list:
        """(parameter values, time of failure, status) of each design that failed."""
        out = []
        for d in np.nonzero(self.done < len(self.t))[0]:
            k = int(self.done[d])
            out.append((self._values(d), float(self.t[k]), int(self._status[d])))
        return out

    def __len__(self):
        return int(np.prod(self.shape))

    def _flat(self, index=None, /, **values):
        if values and not self.grid:
            if index is not None:
                raise TypeError("give a design index or parameter values, not both")
            hit = np.ones(len(self), dtype=bool)
            for name in self.names:
                if name not in values:
                    raise KeyError(f"give a value for each varied parameter ({', '.join(self.names)})")
                hit &= np.isclose(self.P[:, self._column[name]], values.pop(name),
                                  rtol=1e-12, atol=1e-12)
            if values:
                raise KeyError(f"{', '.join(values)} is not a varied parameter "
                               f"({', '.join(self.names)})")
            if not hit.any():
                raise KeyError("no design of the table has those parameter values")
            return int(np.argmax(hit))
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

    def sweep(self, /, *index, **values):
        """One design as a Sweep (only the points it solved). Its ``mechanism`` has the
        design's parameters and, as its guess, the design's first point: its later solves
        keep the mode the table gave the design (the guess= of the table's, if any)."""
        self._need_points("sweep()")
        d = self._flat(index if index else None, **values)
        mech = self._start.with_params(**{n: float(self.P[d, self._column[n]])
                                          for n in self.names})
        k = int(self.done[d])
        if k:       # its mechanism on the table's mode: its first point is its guess
            mech.set_guess(self.Q[d, 0], t=float(self.t[0]))
        QD = self.QD[d, :k].copy() if self._have >= LEVEL["velocity"] else None
        QDD = self.QDD[d, :k].copy() if self._have >= LEVEL["acceleration"] else None
        sw = Sweep(mech, self.t[:k].copy(), self.Q[d, :k].copy(), QD, QDD,
                   self.INFO[d, :k].copy())
        if self.sensitivities is not None:
            sw.sensitivities = self.sensitivities.design(d, k)
        return sw if self.force_level is None else attach(sw, self.force_level)

    def driver(self, name) -> np.ndarray:
        """A driver's effort (torque or force, as Solution.driver signs it) at every point of
        a table at level "static" or "dynamic": shape ``tab.shape + (len(tab.t),)``, NaN
        where a design did not solve (and where no force balance exists)."""
        self._need_points(f"tab.driver({name!r})")
        mech = self.mechanism
        if self.force_level is None:
            raise ValueError(f"tab.driver({name!r}): a driver's effort needs a table at level "
                             "'static' or 'dynamic'")
        label, _, is_driver = tables(mech).constraint(name, mech)
        if not is_driver:
            raise ValueError(f"constraint {label!r} of model '{mech.name}' is not a driver "
                             "(its equations do not hold T)")
        _, index, _ = driver_slot(mech, label, self.force_level)
        try:
            out = driver_efforts(mech.module, self.t, self.P, self.Q, self.QD, self.QDD,
                                 self.done, index, self.force_level)
        except ZeroDivisionError:
            raise division_error(mech, f"in tab.driver({name!r})") from None
        return out.reshape(self.shape + (len(self.t),))

    def sensitivity(self, name, param) -> np.ndarray:
        """∂name/∂param at every point of a table made with ``sensitivities=``: shape
        ``tab.shape + (len(tab.t),)``, NaN where a design did not solve (or lost rank)."""
        if self.sensitivities is None:
            raise MechgenError("this design table carries no sensitivities: make it with "
                               "sensitivities=True or a list of parameter names")
        out = np.full((len(self), len(self.t)), np.nan)
        for d in range(len(self)):
            k = int(self.done[d])
            if k:
                index = np.unravel_index(d, self.shape) if self.grid else (d,)
                out[d, :k] = self.sweep(*index).sensitivity(name, param)
        return out.reshape(self.shape + (len(self.t),))

    @property
    def sweeps(self) -> list:
        """Every design as a Sweep, in grid order (Mech's Table)."""
        return [self.sweep(*np.unravel_index(d, self.shape)) for d in range(len(self))]

    def __getitem__(self, name) -> np.ndarray:
        if not isinstance(name, str):
            raise TypeError("index a design table by quantity name (tab['X4']); "
                            "use tab.sweep(i) for one design")
        self._need_points(f"tab[{name!r}]")
        mech = self.mechanism
        if self.force_level is not None and name not in mech.coordinates:
            entry = tables(mech).find(name, mech)
            if entry is not None and entry[2]:
                return self.driver(name)
        kind, k, order = lookup(mech, name)
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
            zero = np.zeros((N, mech.n))    # derivatives below the table's level
            for d in range(D):
                mech.module.eval_outputs(self.Q[d], zero if self.QD is None else self.QD[d],
                                         zero if self.QDD is None else self.QDD[d], self.t,
                                         self.P[d], order, out)
                arr[d] = out[:, k]
        for d in range(D):
            arr[d, int(self.done[d]):] = np.nan
        return arr.reshape(self.shape + (N,))

    def _need_points(self, what):
        if not self.kept_points:
            raise MechgenError(f"{what}: this design table kept only the reductions of "
                               f"{', '.join(map(str, self._reduced))} (reduce=...); use "
                               "tab.reduced(name), or make the table without reduce")

    def design_params(self) -> np.ndarray:
        """The varied parameters' values, one row per design (in the table's order)."""
        return np.column_stack([self.P[:, self._column[n]] for n in self.names])

    def table(self) -> tuple[list, np.ndarray]:
        """A long table: one row per design and time; the varied parameters, T, then the
        coordinates (and derivatives) and outputs the table's level provides, and at
        level "static" or "dynamic" every driver's effort (named as in a sweep's table). A table of
        reductions has one row per design: the varied parameters, status, then min, max,
        tmin and tmax of each reduced quantity (``X4_min``, ...)."""
        grid = self.design_params()
        if not self.kept_points:
            status = "status"
            while status in self.names:     # a parameter named status keeps its name
                status += "_"
            header = list(self.names) + [status]
            cols = [grid[:, j] for j in range(len(self.names))] + [self._status.astype(float)]
            for name, red in self._reduced.items():
                for what in ("min", "max", "tmin", "tmax"):
                    header.append(f"{name}_{what}")
                    cols.append(getattr(red, what).reshape(-1))
            return header, np.column_stack(cols)
        N = len(self.t)
        header = list(self.names) + ["T"]
        cols = [np.repeat(grid[:, j], N) for j in range(len(self.names))]
        cols.append(np.tile(self.t, len(self)))
        mech = self.mechanism
        for name in column_names(mech, self._have, coordinates=mech.coordinates):
            header.append(name)
            cols.append(self[name].reshape(-1))
        taken = set(header)
        for name, label in self._driver_columns():
            header.append(effort_column(name, taken))
            cols.append(self.driver(label).reshape(-1))
        return header, np.column_stack(cols)

    def _driver_columns(self) -> list:
        """(column name, label) of every driver whose effort a table at a force level
        gives, named as a force sweep's table names them (its name=, else its number);
        none at a kinematic level."""
        if self.force_level is None:
            return []
        mech = self.mechanism
        out = []
        for number, kind, label, _, driver in mech.module.CONSTRAINTS:
            if not driver:
                continue
            try:
                driver_slot(mech, label, self.force_level)
            except ValueError:          # an effort this slice does not define: no column
                continue
            out.append((column_name(tables(mech), label, kind, number), label))
        return out

    def to_csv(self, path):
        """Write the long table (see table()) to a CSV file; unsolved points are empty;
        where the model declares its units, each name carries its unit ("X4 [mm]",
        "X4_tmin [s]"; mechgen.runtime.unit_columns)."""
        from ..unit_columns import labelled
        return write_csv(path, *labelled(self.mechanism, *self.table()))

    def to_dataframe(self):
        """The long table (see table()) as a pandas DataFrame (needs pandas)."""
        header, data = self.table()
        return pandas().DataFrame(data, columns=header)

    def __repr__(self):
        axes = ", ".join(f"{n} in [{', '.join(f'{v:g}' for v in a[:6])}{', ...' if len(a) > 6 else ''}]"
                         for n, a in zip(self.names, self.axes))
        if not self.grid:
            axes = "listed: " + axes
        if not self.kept_points:
            axes += "; reduced: " + ", ".join(map(str, self._reduced))
        bad = len(self) - int(np.sum(self.done == len(self.t)))
        return (f"<DesignTable of '{self.mechanism.name}': {len(self)} designs ({axes}) × "
                f"{len(self.t)} times, level {self.force_level or self.level}"
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


def design_list(base, index, names, axes) -> np.ndarray:
    """One parameter vector per design for listed designs (``grid=False``): design i takes
    the i-th value of every varied parameter (the sequences must be of one length)."""
    sizes = {len(a) for a in axes}
    if len(sizes) != 1:
        raise ValueError("grid=False pairs the parameters' values up: give sequences of one "
                         "length (" + ", ".join(f"{n}: {len(a)}" for n, a in zip(names, axes)) + ")")
    P = np.tile(base, (len(axes[0]), 1))
    for name, axis in zip(names, axes):
        P[:, index[name]] = axis
    return np.ascontiguousarray(P)


def design_table(mech, t0, t1, n, params, level="position", **options):
    """A design table (_design_table); at a force level a division by zero in the force
    functions is a SingularError naming the springs and dampers (lookup.loads_guarded)."""
    force = is_force_level(level)
    run = loads_guarded(span=True)(_design_table) if force else _design_table
    # the warnings point at the caller's line: this frame and the guard's are more
    options["stacklevel"] = options.get("stacklevel", 4) + (2 if force else 1)
    return run(mech, t0, t1, n, params, level, **options)


def _design_table(mech, t0, t1, n, params, level="position", guess=None, method=None,
                 tol=None, maxit=None, times=None, progress=None, on_fail="warn",
                 backend="cpu", workers=None, client=None, reduce=None, grid=True,
                 stacklevel=4):
    """Mechanism.design_sweep (see there): the table, or a Sweep when nothing varies."""
    fixed, names, axes = split_params(mech, params)
    if on_fail not in ON_FAIL:
        raise ValueError(f"on_fail must be 'warn', 'raise' or 'ignore', got {on_fail!r}")
    base = quiet_params(mech, fixed).p if fixed else mech.p.copy()
    if not names:
        if backend != "cpu" or reduce is not None or client is not None:
            raise ValueError("backend=, client= and reduce= are for design tables: vary a "
                             "parameter (params={name: [values, ...]})")
        return mech.with_params(**fixed).sweep(t0, t1, n, level=level, guess=guess,
                                               method=method, tol=tol, maxit=maxit,
                                               times=times)
    force_level = level if is_force_level(level) else None
    if force_level is not None:     # the kinematics the multipliers need, then λ
        level = "acceleration" if force_level == "dynamic" else "position"
    state = mech.state
    lev = state.level_of(level)
    meth = state.method_of(method)
    ts = sweep_times(t0, t1, n, times)
    tol = state.tol_of(tol)
    maxit = state.maxit_of(maxit)
    reduced, slots = ((), None) if reduce is None else \
        reduce_slots(mech, reduce, lev, force_level)
    # refused before the grid is made: designs x points must fit in memory
    designs = math.prod(len(a) for a in axes) if grid else len(axes[0])
    each = 8 * len(base) + (ts.shape[0] * point_bytes(mech.n, lev) if reduce is None
                            else 64 * (mech.n + 1))
    fits(designs, each, "designs", "params", f" of {ts.shape[0]:,} times each")
    make = design_grid if grid else design_list
    P = make(base, state.param_index, names, axes)
    if force_level is not None and module_attr(mech.module, "mass_matrix") is not None:
        from ..forces.limits import refused_design      # each design's loads and masses
        from ..forces.masses import negative_mass
        wrong = refused_design(P, names, state.param_index, lambda p: negative_mass(mech, p))
        if wrong:
            raise ValueError(f"model '{mech.name}': {wrong}")
    # a big table in the python tier: compiled first (runtime.tiers); elsewhere the
    # designs' starts (a few solves each) are this process's work
    state.tiers.expect(mech, P.shape[0] * (ts.shape[0] if backend == "cpu" else 8), "design")
    # a driver's effort the GPU cannot reduce: the kernel keeps the points (backends)
    on_host = backend == "cuda" and cuda_keeps_points(mech, slots, lev, meth)
    origin = guess_reference(mech, ts[0], guess)     # whose guess the designs leave
    try:
        Q0, S0 = design_starts(origin, ts, P, tol, maxit, meth, workers)
        data = run_backend(backend, mech, ts, Q0, P, lev, tol, mech.xtol, maxit, meth,
                           workers=workers, client=client, slots=None if on_host else slots,
                           progress=progress_reporter(progress, P.shape[0]))
    except ZeroDivisionError:   # (Python's and numba's default error model raise)
        raise _divides(mech, ts, slots) from None
    mark_starts(data, S0, ts.shape[0])
    if on_host:         # the kernel keeps the points; the multipliers are solved here
        data.red = reduce_threads(mech.module, slots, ts, P, data.Q, data.QD, data.QDD,
                                  data.done, workers)
        data.Q = data.QD = data.QDD = data.INFO = None
    table = DesignTable(mech, names, axes, ts, P, data, LEVELS[lev], grid=grid,
                        reduced=reduced, force_level=force_level, start=origin)
    report_failures(table, on_fail, stacklevel=stacklevel)
    return table


def _divides(mech, ts, slots):
    """The SingularError of a table whose equations divide by zero at one of its times (a
    driver 1/T, or the rate of sqrt(T), at T = 0), as a single sweep's says (runtime.
    sweeping); with a driver's effort to reduce, the force terms may be the ones."""
    if slots is not None and len(slots):
        return division_error(mech, f"in the design table from t={ts[0]:.10g} to "
                                    f"t={ts[-1]:.10g} (or its equations of motion do)")
    return divides(mech, ts, "the design table")


def report_failures(table, on_fail, stacklevel=2):
    """Warn about (on_fail="warn") or raise for (on_fail="raise") the designs that could
    not be solved at every time; on_fail="ignore" says nothing. ``stacklevel`` as
    warnings.warn counts it from here (3: the caller of report_failures' caller)."""
    if on_fail == "ignore":
        return
    _report_flagged(table, stacklevel + 1)
    bad = table.failures
    if not bad:
        return
    first = bad[0]
    where = ", ".join(f"{k}={v:g}" for k, v in first[0].items())
    msg = (f"{len(bad)} of {len(table)} designs of '{table.mechanism.name}' could not be "
           f"solved at every time (first: {where} fails at t={first[1]:.10g}, status "
           f"{first[2]}: {status_name(first[2])}); their unsolved points are NaN")
    if on_fail == "raise":
        err = MechgenError(msg)
        err.table = table
        raise err
    warnings.warn(msg, RuntimeWarning, stacklevel=stacklevel)


def _report_flagged(table, stacklevel):
    """A BranchJumpWarning for the designs solved at every time that were reached by a
    branch jump or at or through a singular configuration (status JUMP or
    THROUGH_SINGULAR): their points after it may lie on another assembly mode, as a
    single sweep's warning says."""
    status = table._status.reshape(-1)
    flagged = np.flatnonzero((table.done == len(table.t)) &
                             np.isin(status, (JUMP, THROUGH_SINGULAR)))
    if not flagged.size:
        return
    first = int(flagged[0])
    where = ", ".join(f"{k}={v:g}" for k, v in table._values(first).items())
    warnings.warn(
        f"{flagged.size} of {len(table)} designs of '{table.mechanism.name}' were solved "
        f"through a branch jump or a singular configuration (first: {where}, status "
        f"{int(status[first])}: {status_name(status[first])}): their points after it may "
        "lie on another assembly mode (tab.status says which designs)",
        BranchJumpWarning, stacklevel=stacklevel)
