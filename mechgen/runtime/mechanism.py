"""The Mechanism: a loaded generated module, solved at one time or over many (numpy + numba,
never sympy). It checks what users pass (guards), calls the module's compiled functions
and hands the rest to the modules below it (results, analysis, tables, forces,
sensitivity, fitting), none of which imports it. A symbolic quantity is evaluated by the
symbolic side ``mechgen.compile`` attaches (``mech.symbolic``)."""
from __future__ import annotations

import numpy as np

from ..protocol import FORCE_LEVELS, SING_RTOL
from .kinematics.entry import module_attr
from .kinematics.follow import start_at
from .guards import finite, method_index
from .kinematics.guesses import guess_at, start_vector
from .kinematics.solving import solve, solve_derivatives
from .kinematics.solving import sweep as sweep_once
from .loading.tiers import Tiers
from .quantity import symbolic_side
from .results import Solution, Sweep
from .state import RuntimeState

# imported where used, so that a fresh process's first answer does not wait for them:
# assembly, design (and its backends), forces' solvers, stages, singular and locks (the
# errors of a failed solve, singularities)

def load(path_or_module, tier=None, **kwargs) -> "Mechanism":
    """A :class:`Mechanism` from a generated module: a path or an imported module
    (checked by mechgen.runtime.loading.loader: content stamp, format, mechgen version).

    tier: "auto" (default, or $MECHGEN_TIER): plain Python at once, numba's compiled
    code once a background process has compiled it; "python"; "compiled" (numba at once;
    an imported module is always compiled). See mechgen.runtime.loading.tiers; ``mech.tier``
    says which answers now. The numbers are the same."""
    return Mechanism(Tiers.open(path_or_module, tier), **kwargs)


def _on_state(name, doc):
    """A Mechanism attribute that is the state's ``name`` (runtime.state)."""
    def get(self):
        return getattr(self.state, name)

    def put(self, value):
        setattr(self.state, name, value)
    return property(get, put, doc=doc)


class Mechanism:
    """A loaded kinematic solver: positions, velocities, accelerations, sweeps."""

    def __init__(self, module, params=None, tol=1e-10, xtol=1e-10, maxit=50, method="auto"):
        tiers = Tiers.of(module)      # the module answering now (runtime.loading.tiers)
        module = tiers.module
        self.name = module.MODEL_NAME
        self.coordinates = tuple(module.COORDINATES)
        self.outputs = tuple(module.OUTPUTS)
        self.output_orders = tuple(module.OUTPUT_ORDERS)
        self.constraint_labels = tuple(module.CONSTRAINT_LABELS)
        self.point_names = tuple(label for label, _ in module.POINTS)
        self.parameter_names = tuple(module.PARAMETERS)
        self.n = len(self.coordinates)
        self.m = len(self.constraint_labels)
        # what this build computes: its highest level, and the coordinates a pruned build
        # (mechgen build --outputs ...) solves
        self.built_level = int(module.LEVEL)
        self.solved = tuple(bool(x) for x in module.SOLVED)
        method_index(method)
        own = np.array(module.PARAMETER_DEFAULTS, dtype=np.float64)
        self.state = RuntimeState(
            tiers, self.name, self.built_level, {c: k for k, c in enumerate(self.coordinates)},
            {name: k for k, name in enumerate(self.parameter_names)}, own,
            np.array(module.GUESS, dtype=np.float64), 0.0, own, float(tol), float(xtol),
            int(maxit), method, owner=self)
        if params:      # (the guess stays one for the model's own parameters)
            self.state.p = self._params_array(params)
        self.model = None      # the symbolic model, when built by mechgen.compile
        self.symbolic = None   # its evaluator (evaluate, derivative, level), attached there

    p = _on_state("p", "The parameters' values, in parameter_names' order.")
    guess = _on_state("guess", "The start of solves: a configuration at guess_t.")
    guess_t = _on_state("guess_t", "The time the guess is a configuration for (set_guess).")
    guess_p = _on_state("guess_p", "The parameters the guess was given for: its mode is "
                        "carried from them (p itself where they are).")
    tol = _on_state("tol", "The residual tolerance of solves.")
    xtol = _on_state("xtol", "The step tolerance of solves.")
    maxit = _on_state("maxit", "The most Newton iterations a solve takes.")
    method = _on_state("method", '"auto", "sorted" or "full": the solver of solves.')

    @property
    def module(self):
        """The generated module answering now: plain Python or numba's (``tier``)."""
        return self.state.tiers.module

    @module.setter
    def module(self, module):
        self.state.tiers = Tiers.of(module)     # this mechanism alone: no tier switch

    @property
    def tier(self) -> str:
        """"python" or "compiled": which tier answers this mechanism's calls now."""
        return self.state.tiers.tier

    def __repr__(self):
        return (f"<Mechanism {self.name!r}: {self.n} coordinates, {self.m} equations, "
                f"parameters {self.parameters}>")

    @property
    def last(self):
        """The last configuration solved (Mech's LastSolve[]): a Solution, or None. After
        a sweep it is the sweep's last point, made into a Solution when first asked for."""
        last = self.state.last
        if last.__class__ is tuple:
            last = self.state.last = Solution(self, *last)
        return last

    @last.setter
    def last(self, value):
        self.state.last = value

    # -- parameters -------------------------------------------------------------------
    @property
    def parameters(self) -> dict:
        p = self.state.p
        return {name: float(p[k]) for name, k in self.state.param_index.items()}

    def _params_array(self, values) -> np.ndarray:
        p, index = self.p.copy(), self.state.param_index
        for name, value in values.items():
            if name not in index:
                known = ", ".join(index) or "none"
                raise ValueError(f"model '{self.name}' has no parameter {name!r} (parameters: {known})")
            p[index[name]] = finite(value, f"parameter {name!r}")
        if values and module_attr(self.module, "mass_matrix") is not None:
            from .forces.masses import negative_mass
            wrong = negative_mass(self, p)
            if wrong:
                given = ", ".join(f"{k}={v!r}" for k, v in values.items())
                raise ValueError(f"model '{self.name}' with {given}: {wrong}")
        return p

    def with_params(self, /, **values) -> "Mechanism":
        """A copy with some parameters changed (``mech.with_params(longitud=1.5)``).

        It keeps the guess and its assembly mode: solves and sweeps start where that mode goes
        as the parameters move from the guess's to the new ones (kinematics.follow).

        Parameters
        ----------
        **values : float
            New values by parameter name.

        Returns
        -------
        Mechanism
        """
        other = Mechanism(self.state.tiers, tol=self.tol, xtol=self.xtol, maxit=self.maxit,
                          method=self.method)
        other.p = self._params_array(values)
        other.model, other.symbolic = self.model, self.symbolic
        other.guess, other.guess_t = self.guess.copy(), self.guess_t
        other.guess_p = self.guess_p
        if values and hasattr(self.symbolic, "check_contacts"):   # cams, as declared
            self.symbolic.check_contacts(other, values)   # (warns; _with_params does not)
        return other

    # -- guesses ----------------------------------------------------------------------
    def set_guess(self, guess=None, t=None):
        """Mech's SetGuess[]: the start of later solves.

        Its parameters are this mechanism's (the model's own for its own guess): a mechanism
        with others (with_params) carries its assembly mode to them.

        Parameters
        ----------
        guess : dict, array or Solution, optional
            Coordinates by name, all of them, or a Solution; None: the model's own guess.
        t : float, optional
            The time ``guess`` is a configuration for: by default a Solution's own, else 0.
        """
        if guess is not None:
            self.guess = start_vector(self, guess)
            self.guess_p = self.p       # (p is never changed in place: shared, not copied)
        else:
            self.guess = np.array(self.module.GUESS, dtype=np.float64)
            own = np.array(self.module.PARAMETER_DEFAULTS, dtype=np.float64)
            self.guess_p = self.p if own.tobytes() == self.p.tobytes() else own
        self.state.path = None  # (a path is kept per guess, and guess_p is not in its key)
        if t is not None:
            self.guess_t = finite(t, "t")
        else:
            self.guess_t = float(guess.t) if isinstance(guess, Solution) else 0.0

    # -- solving ----------------------------------------------------------------------
    def solve(self, t, guess=None, level="position", method=None, tol=None, maxit=None,
              sensitivities=None) -> Solution:
        """Solve at one time (Mech's SolveMech[t]); the result becomes ``last``.

        Without ``guess``, the configuration reached by moving from the guess to t on its
        assembly mode (a lock on the way raises, naming where); with one, Newton from it at t.
        Never returns a configuration that does not satisfy the constraints.

        Parameters
        ----------
        t : float
            The time.
        guess : dict, array or Solution, optional
            Start of a Newton solve at t (some or all coordinates); picks an assembly mode.
        level : str, default "position"
            "position", "velocity", "acceleration"; "static" or "dynamic" add the
            multipliers, driver efforts and reactions (docs/reference/forces.md).
        method, tol, maxit : optional
            The solver ("auto", "sorted", "full") and its tolerance and iterations.
        sensitivities : bool or list of str, optional
            Derivatives with respect to these parameters (True: all).

        Returns
        -------
        Solution

        Raises
        ------
        ConvergenceError, SingularError
        """
        # the usual arguments pass with a look-up each, anything else through guards' checks
        state = self.state
        lev = state.levels.get(level) if level.__class__ is str else None
        with state.lock:
            if lev is None and level in FORCE_LEVELS:
                result = _force_solve()(self, t, level, guess, method, tol, maxit)
            else:
                result = solve(state, t, guess, level, method, tol, maxit, None, lev)
        return _attach()(self, result, sensitivities) if sensitivities else result

    def solve_derivatives(self, ts, Q, QD=None, QDD=None, level="velocity"):
        """(QD, QDD) at solved positions Q (rows, at times ts) up to ``level`` (a name or
        an index into LEVELS): the levels not given are solved (linear solves, no Newton
        iteration); a level above the one asked for stays as given. Raises SingularError
        where they are not determined."""
        return solve_derivatives(self.state, ts, Q, QD, QDD, level)

    # -- diagnostics ------------------------------------------------------------------
    @property
    def sing_rtol(self) -> float:
        """Below this pivot ratio (see pivot_ratio) a configuration counts as singular."""
        return SING_RTOL

    def pivot_ratio(self, q, t) -> float:
        """How far Φ_q(q, t) is from losing rank: the smallest pivot of a full-pivoting
        elimination of the row-equilibrated Jacobian (1: well conditioned, 0: rank lost)."""
        return float(self.module.pivot_ratio(np.asarray(q, dtype=np.float64), float(t), self.p))

    def residual(self, q, t) -> float:
        """‖Φ(q, t)‖∞ (NaN when an equation is not finite).
        """
        r = np.empty(self.m)
        self.module.phi(np.asarray(q, dtype=np.float64), float(t), self.p, r)
        return float(np.abs(r).max()) if self.m else 0.0

    def jacobian(self, q, t) -> np.ndarray:
        """Φ_q(q, t), an m × n array."""
        J = np.empty((self.m, self.n))
        self.module.phi_q(np.asarray(q, dtype=np.float64), float(t), self.p, J)
        return J

    def rank_loss(self, q, t, rtol=None):
        """(rank, labels of the constraint rows in the left null space) of the
        row-equilibrated Φ_q at (q, t): the equations that become dependent at a singular
        or redundant configuration (mechgen.runtime.analysis.singular.null_space says more)."""
        from .analysis.singular import null_space
        null = null_space(self, q, t, rtol=rtol)
        return null.rank, null.constraints

    def singularities(self, t0, t1, n=201, guess=None):
        """Lock (toggle) positions and dead centres in [t0, t1] on the guess's branch.

        Located to ~1e-12 in t by Newton on Φ = 0, det Φ_q = 0 (runtime.analysis.locks).

        Parameters
        ----------
        t0, t1 : float
            The time range.
        n : int, default 201
            Points of the sweep that brackets them.
        guess : optional
            As for :meth:`solve`.

        Returns
        -------
        list of float
            The times, each carrying ``q``, ``solution``, ``kind``, ``constraints`` and
            ``coordinates``.
        """
        t0, t1 = finite(t0, "t0"), finite(t1, "t1")
        if isinstance(n, bool) or int(n) != n or n < 2:
            raise ValueError(f"n must be an integer >= 2, got {n!r}")
        ts = np.linspace(t0, t1, int(n))
        q = start_at(self.state, guess, float(ts[0]), self.tol, self.maxit,
                     self.state.method_of(None),
                     "singularities()' start")
        if module_attr(self.module, "SWITCH_TIMES", ()):     # stage by stage (kinematics.stages)
            from .kinematics.stages import staged_singularities
            return staged_singularities(self, ts, q)
        from .analysis.locks import singularities
        return singularities(self, ts, q)

    # -- sweeps -----------------------------------------------------------------------
    def sweep(self, t0, t1, n, level="position", guess=None, method=None, tol=None,
              maxit=None, times=None, params=None, out=None, backend="cpu", workers=None,
              client=None, reduce=None, sensitivities=None, **table_options) -> Sweep:
        """Solve at n times from t0 to t1, both ends included (Mech's SolveMech[{t0, t1}, n]).

        Each point starts from the one before, on one assembly mode. Raises on the first
        failure, the points solved before it on the error's ``.sweep``. Only the level's
        arrays are filled (a position sweep has no ``sw["X4d"]``).

        Parameters
        ----------
        t0, t1 : float
            First and last time.
        n : int
            Number of times.
        level : str, default "position"
            As for :meth:`solve`; "static" or "dynamic" solve the multipliers at every point.
        guess, method, tol, maxit : optional
            As for :meth:`solve`.
        times : array, optional
            Times of one's own instead of the even grid.
        params : dict, optional
            {name: values}: a design table over every combination (see :meth:`design_sweep`
            and ``**table_options``).
        out : dict, tuple or Sweep, optional
            Arrays the caller owns to write into (``{"q": Q, "qd": QD, "qdd": QDD, "status":
            S}``, float64 (n, coordinates), int16 (n, 3); C-contiguous).
        backend, workers, client, reduce : optional
            Where a design table runs ("cpu", "dask", "cuda") and the quantities whose
            extremes alone it keeps.
        sensitivities : bool or list of str, optional
            As for :meth:`solve`.

        Returns
        -------
        Sweep or DesignTable
        """
        if sensitivities:               # (at position level, solved in the sweep's loop)
            from .sensitivity.fused import sweep_with
            return sweep_with(self, sensitivities, t0, t1, n, level, guess, method, tol, maxit,
                              times, params, out, backend, workers, client, reduce, table_options)
        if level.__class__ is str and level in FORCE_LEVELS and params is None:
            if out is not None or backend != "cpu" or reduce is not None:
                raise ValueError(f"level={level!r}: out=, backend= and reduce= are for a "
                                 "single kinematic sweep or a design table (params=)")
            from .forces.sweep import force_sweep
            return force_sweep(self, t0, t1, n, level, guess=guess, method=method, tol=tol,
                               maxit=maxit, times=times)
        if params is not None:
            if out is not None:
                raise ValueError("out= is for a single sweep, not a design table (params=)")
            from .tables.design import design_table
            return design_table(self, t0, t1, n, params, level=level, guess=guess,
                                method=method, tol=tol, maxit=maxit, times=times,
                                backend=backend, workers=workers, client=client,
                                reduce=reduce, **table_options)
        if backend != "cpu" or workers is not None or client is not None or \
                reduce is not None or table_options:
            raise ValueError("backend=, workers=, client=, reduce= and "
                             f"{', '.join(table_options) or 'the table options'} are for "
                             "design tables (params={name: [values, ...]})")
        return sweep_once(self.state, t0, t1, n, level, guess, method, tol, maxit, times, out)

    def simulate(self, t0, t1, n, free=(), q0=None, qd0=None, rtol=1e-8, atol=1e-10,
                 method="dopri5", max_step=float("inf"), progress=None):
        """Motion under forces (docs/reference/simulation.md).

        The drivers named in ``free`` stop prescribing their motion at t0; from the state
        there the mechanism moves under its masses and loads, the other drivers prescribing
        theirs. A model's ``hold`` rows (free coordinates held at the guess) always go.

        Parameters
        ----------
        t0, t1 : float
            Start and end of the motion.
        n : int
            Output times from t0 to t1.
        free : list of str
            Driver names to release.
        q0, qd0 : array or dict, optional
            The state at t0 (made consistent with the constraints); by default the kinematic
            solution there.
        rtol, atol, method, max_step : optional
            The integration: "dopri5" (compiled Dormand–Prince 5(4), the default) or any of
            scipy's solve_ivp ("DOP853", "RK45", "Radau", "BDF").
        progress : callable, optional
            Called with each output time reached.

        Returns
        -------
        Sweep
            At level "dynamic"; ``power()`` and ``energy()`` show what was conserved.
        """
        from .forces.simulate import simulate
        return simulate(self, t0, t1, n, free=free, q0=q0, qd0=qd0, rtol=rtol, atol=atol,
                        method=method, max_step=max_step, progress=progress)

    def design_sweep(self, t0, t1, n, params, level="position", guess=None, method=None,
                     tol=None, maxit=None, times=None, progress=None, on_fail="warn",
                     backend="cpu", workers=None, client=None, reduce=None, grid=True):
        """A design table: a sweep over time for every combination of parameter values
        (``params={"longitud": [1.5, 2.25, 3.0]}``; a number fixes a parameter; grid=False
        pairs listed designs up), the loop over designs compiled, arrays indexed by
        parameter(s) and time. Each design starts from the guess's assembly mode carried
        to its own parameters and is swept on its own: the numbers do not depend on the
        backend ("cpu" with ``workers``, "dask" with ``client``, "cuda"). ``reduce``:
        quantity names whose min/max alone are kept; ``progress``: None, True or a
        callable(done, total); ``on_fail``: "warn", "raise" or "ignore". The details:
        mechgen.runtime.tables.design."""
        from .tables.design import design_table
        return design_table(self, t0, t1, n, params, level=level, guess=guess, method=method,
                            tol=tol, maxit=maxit, times=times, progress=progress,
                            on_fail=on_fail, backend=backend, workers=workers, client=client,
                            reduce=reduce, grid=grid)

    def optimize(self, objective, bounds, t0, t1, n, backend="cpu", level="position",
                 **options):
        """Dimensional synthesis: parameters within ``bounds`` minimising ``objective``.

        Differential evolution, each generation one design table, then a polish ("gradient":
        Levenberg-Marquardt on exact sensitivities, the default for a sum of squares; True:
        Nelder-Mead). Designs not solved at every time are rejected (tables.synthesis).

        Parameters
        ----------
        objective : callable or dict
            A function of a design table giving one number per design, or {quantity:
            targets at the n times} (a sum of squares).
        bounds : dict
            {name: (low, high)}.
        t0, t1, n : float, float, int
            Each design's sweep.
        backend, level : str
            As for :meth:`sweep`.

        Returns
        -------
        OptimizeResult
        """
        from .tables.synthesis import optimize
        return optimize(self, objective, bounds, t0, t1, n, backend=backend, level=level,
                        **options)

    def tolerance(self, result, tolerances=None, clearance=None, method="worst", **options):
        """Tolerance and clearance bands (docs/reference/sensitivities.md).

        Parameters
        ----------
        result : Sweep or Solution
            Solved with ``sensitivities=``.
        tolerances : dict
            {parameter: t (±t) or (low, high)}.
        clearance : dict, optional
            {revolute name: radial clearance c}.
        method : str, default "worst"
            "worst", "rss" or "montecarlo" (``samples=``, ``seed=``, ``backend=``).

        Returns
        -------
        Bands
            ``band["X4"]``: "nominal", "low", "high"; ``band.contributions("X4")``.
        """
        from .sensitivity.tolerance import tolerance
        return tolerance(self, result, tolerances, clearance=clearance, method=method,
                         **options)

    def fit(self, point, target, params, timing=None, **options):
        """Path fitting: the parameters that take a point through target points.

        A design-table search, then Levenberg-Marquardt on the exact derivatives.

        Parameters
        ----------
        point : Point name
            The point to fit (``"coupler[3]"``).
        target : (k, 2) array
            The points it should pass.
        params : dict
            {name: (low, high)} of the parameters to choose.
        timing : None or k times
            None: the phase at each target is free; else the times it is reached.

        Returns
        -------
        FitResult
            ``params``, ``error`` (RMS distance), ``times``, ``mechanism``.
        """
        from .fitting import fit
        return fit(self, point, target, params, timing=timing, **options)

    # -- assembly modes ---------------------------------------------------------------
    def assemblies(self, t, starts=256, guess=None, level="position", flips=False):
        """Every distinct real assembly mode at time t, the guess's first.

        Angles equal modulo 2π count once. Follow one with ``sweep(..., guess=mode)``.

        Parameters
        ----------
        t : float
            The time.
        starts : int, default 256
            Quasi-random starts besides the guess.
        guess : optional
            As for :meth:`solve`.
        level : str, default "position"
            Level of the solutions returned.
        flips : bool, default False
            Count a body only turned half a turn (a slider reversed).

        Returns
        -------
        list of Solution
        """
        t = finite(t, "t")
        if isinstance(starts, bool) or int(starts) != starts or starts < 0:
            raise ValueError(f"starts must be a non-negative integer, got {starts!r}")
        from .analysis.assembly import assemblies
        return assemblies(self, t, guess_at(self, guess, t), int(starts), level,
                               self.tol, self.state.method_of(None), flips=flips)

    def explore(self, **options):
        """Show this mechanism live in a Jupyter notebook (Mech's Manipulate).

        The page of ``mechgen view`` (docs/reference/view.md); needs Bokeh.

        Parameters
        ----------
        **options
            As for mechgen.view.explore (ranges, traces, plots).

        Returns
        -------
        The notebook's view
        """
        from ..extensions import explorer      # filled by mechgen/__init__ (no upward import)
        return explorer()(self, **options)

    # -- values at solved configurations ----------------------------------------------
    def evaluate(self, expr, solution_or_sweep):
        """Evaluate a symbolic quantity (needs ``mechgen.compile``'s symbolic side).

        Parameters
        ----------
        expr : sympy expression
            Any output function or expression in the coordinates and their rates.
        solution_or_sweep : Solution or Sweep
            Where to evaluate it.

        Returns
        -------
        float, array or array over the sweep
        """
        return symbolic_side(self, "evaluate()").evaluate(self, expr, solution_or_sweep)

    def points_at(self, q, t) -> np.ndarray:
        """Global positions of the module's points (point_names) at (q, t)."""
        out = np.empty((len(self.point_names), 2))
        self.module.points(np.asarray(q, dtype=np.float64), float(t), self.p, out)
        return out

    def output_values(self, q, qd, qdd, t, order=0) -> np.ndarray:
        """The declared outputs (order 0) or their first or second time derivatives."""
        out = np.empty(len(self.outputs))
        z = np.zeros(self.n)
        fn = (self.module.outputs, self.module.outputs_d, self.module.outputs_dd)[order]
        fn(q, z if qd is None else qd, z if qdd is None else qdd, float(t), self.p, out)
        return out


_FORCE_SOLVE = []
_ATTACH = []


def _force_solve():
    """forces.solution.force_solve, imported once (an import statement costs a µs)."""
    if not _FORCE_SOLVE:
        from .forces.solution import force_solve
        _FORCE_SOLVE.append(force_solve)
    return _FORCE_SOLVE[0]


def _attach():
    """mechgen.runtime.sensitivity.attach, imported at the first solve that asks for it."""
    if not _ATTACH:
        from .sensitivity import attach
        _ATTACH.append(attach)
    return _ATTACH[0]
