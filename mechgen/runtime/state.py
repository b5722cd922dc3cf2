"""What a Mechanism holds between calls, in one plain object: the generated module and its
tier, the parameters, the guess and where it was given, the tolerances and method, the
lock that makes one solve at a time, the path solve(t) followed, the last configuration
solved and the scratch arrays its calls reuse.

``Mechanism`` is the façade users call (argument checks, dispatch); the layers below it
(runtime.kinematics, forces, tables, ...) read and write this state, never the
Mechanism's own attributes. The checks of the usual arguments (``level``, ``method``,
``tol``, ``maxit``, None for the mechanism's own) are here, since they need the state's
defaults."""
from __future__ import annotations

import threading
from dataclasses import dataclass, field

import numpy as np

from ..protocol import LEVELS, METHOD, POINT_INFO_SIZE
from .guards import level_index, method_index, positive_count, positive_tol
from .loading.tiers import Tiers


@dataclass(eq=False, slots=True)
class RuntimeState:
    """One Mechanism's state (see the module docstring). ``owner`` is the Mechanism the
    results (Solution, Sweep) and errors made from this state belong to."""
    tiers: Tiers                    # the module answering now (runtime.loading.tiers)
    name: str                       # the model's name, as messages give it
    built_level: int                # the highest level the module computes
    index: dict                     # coordinate name -> column
    param_index: dict               # parameter name -> column
    p: np.ndarray                   # the parameters (replaced, never changed in place)
    guess: np.ndarray               # the start of solves: a configuration at guess_t,
    guess_t: float                  # for the parameters guess_p (its mode is carried
    guess_p: np.ndarray             # from them: runtime.kinematics.follow)
    tol: float
    xtol: float
    maxit: int
    method: str
    owner: object = None
    levels: dict = field(default_factory=dict)      # level name -> index, up to built_level
    path: object = None             # solve(t)'s way from the guess (kinematics.follow)
    last: object = None             # a Solution, or (t, q, qd, qdd) until asked for
    # one solve at a time: the scratch below is shared by a mechanism's calls, so that
    # threads sharing a mechanism each get their own answer (the compiled calls hold the
    # GIL: nothing ran in parallel)
    lock: object = field(default_factory=threading.RLock)
    info: np.ndarray = field(default_factory=lambda: np.zeros(POINT_INFO_SIZE))
    none: np.ndarray = field(default_factory=lambda: np.empty(0))   # qd, qdd not asked for
    spare: object = None            # a sweep's big block of memory (kinematics.sweeping)
    rows_scratch: object = None     # (module, arrays) of force_rows at one point
    force_scratch: object = None    # (pivot, factors) of a fused dynamic solve
    force_tables: object = None     # (module, forces.lookup's tables)
    evaluate_cache: dict = field(default_factory=dict)  # symbolic quantities compiled

    def __post_init__(self):
        if not self.levels:
            self.levels = {name: k for k, name in enumerate(LEVELS) if k <= self.built_level}

    def with_guess(self, q, t) -> "RuntimeState":
        """A copy whose guess is ``q``, a configuration at time ``t`` for these parameters
        (what set_guess makes of a Solution), with its own path, lock and scratch: the
        way from another guess, followed without touching this state's."""
        return RuntimeState(self.tiers, self.name, self.built_level, self.index,
                            self.param_index, self.p, q, t, self.p, self.tol, self.xtol,
                            self.maxit, self.method, owner=self.owner, levels=self.levels)

    @property
    def module(self):
        """The generated module answering now: plain Python or numba's."""
        return self.tiers.module

    # -- the usual arguments, checked (None: this state's own) -------------------------
    def level_of(self, level) -> int:
        lev = self.levels.get(level) if level.__class__ is str else None
        return level_index(level, self.built_level, self.name) if lev is None else lev

    def method_of(self, method) -> int:
        name = self.method if method is None else method
        meth = METHOD.get(name) if name.__class__ is str else None
        return method_index(name) if meth is None else meth

    def tol_of(self, tol) -> float:
        return self.tol if tol is None else positive_tol(tol)

    def maxit_of(self, maxit) -> int:
        return self.maxit if maxit is None else positive_count(maxit, "maxit")
