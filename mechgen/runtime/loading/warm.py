"""Calling a compiled module's entry points once each, through a Mechanism, so that numba
compiles them (and writes its on-disk cache) with exactly the argument types the runtime
passes later. Used by the background worker (mechgen.runtime.loading.warmup) and by a large call
that cannot wait for it (mechgen.runtime.loading.tiers).

A stage whose solve fails (a model that does not assemble at the times tried, a singular
configuration) has still compiled what it called.
"""
from __future__ import annotations

import sys
import traceback
import warnings

import numpy as np

from ...errors import MechgenError
from ...protocol import LEVEL, LEVELS

# in the order users need them: a position, its derivatives, a sweep (the quick path,
# then the careful continuation), what pictures and diagnostics call, a design table (its
# quick path, then its careful one), and for a model with mass or loads its solves and
# sweeps at the force levels
STAGES = ("position", "derivatives", "sweep", "careful", "diagnostics", "design",
          "design_careful", "forces")
# what a large call of each kind compiles in its own process before the worker's cache is
# ready (loading.tiers): a force sweep its own quick path, not the kinematic one's
STAGES_FOR = {"sweep": ("sweep",), "design": ("design",), "simulate": ("simulate",),
              "dynamic": ("dynamic_sweep",), "static": ("static_sweep",)}


def _top(mech):
    return LEVELS[int(mech.built_level)]


def _position(mech, t):
    mech.solve(t)


def _derivatives(mech, t):
    if mech.built_level >= LEVEL["velocity"]:
        mech.solve(t, level=_top(mech))


def _sweep(mech, t):
    mech.sweep(t, t + 0.01, 3, level=_top(mech))
    mech.sweep(t, t + 0.01, 3, level="position")


def _careful(mech, t):
    mech.sweep(t, t + 0.01, 3, level=_top(mech), method="full")
    mech.sweep(t, t + 0.01, 3, level="position", method="full")


def _diagnostics(mech, t):
    q = mech.guess.copy()
    try:
        q = mech.solve(t).q
    except MechgenError:
        pass
    mech.residual(q, t)
    mech.jacobian(q, t)
    mech.pivot_ratio(q, t)
    mech.points_at(q, t)
    z = np.zeros(mech.n)
    for order in range(3):
        mech.output_values(q, z, z, t, order)
    mech.module.solve_position(q.copy(), float(t), mech.p, mech.tol, mech.xtol, mech.maxit, 0,
                               np.zeros(4))
    mech.module.nu(q, float(t), mech.p, np.empty(mech.m))
    mech.solve_derivatives(np.array([t]), q[None, :].copy(), level=int(mech.built_level))


def _design(mech, t):
    if mech.parameter_names:
        value = float(mech.p[0])
        designs = {mech.parameter_names[0]: [value, value]}
        mech.design_sweep(t, t + 0.01, 3, designs, level=_top(mech), on_fail="ignore")


def _design_careful(mech, t):
    # what a table of easy designs starting at the guess's time never calls: the careful
    # sweep to a first time that is not the guess's (walk_designs) and after a quick path
    # (sweep_designs_rest)
    if mech.parameter_names:
        value = float(mech.p[0])
        mech.design_sweep(t + 0.01, t + 0.02, 3, {mech.parameter_names[0]: [value, value]},
                          level=_top(mech), method="full", on_fail="ignore")


def _forces(mech, t):
    if getattr(mech.module, "FORCES", False):
        mech.solve(t, level="static")
        mech.sweep(t, t + 0.01, 3, level="static")
        if mech.built_level >= LEVEL["acceleration"]:
            mech.solve(t, level="dynamic")
            mech.sweep(t, t + 0.01, 3, level="dynamic")


def _dynamic_sweep(mech, t):
    if getattr(mech.module, "FORCES", False) and mech.built_level >= LEVEL["acceleration"]:
        mech.sweep(t, t + 0.01, 3, level="dynamic")


def _static_sweep(mech, t):
    if getattr(mech.module, "FORCES", False):
        mech.sweep(t, t + 0.01, 3, level="static")


def _simulate(mech, t):
    if getattr(mech.module, "FORCES", False):
        mech.simulate(t, t + 1e-3, 2)


_RUN = {"position": _position, "derivatives": _derivatives, "sweep": _sweep,
        "careful": _careful, "diagnostics": _diagnostics, "design": _design,
        "design_careful": _design_careful,
        "forces": _forces, "simulate": _simulate, "dynamic_sweep": _dynamic_sweep,
        "static_sweep": _static_sweep}


def warm(mech, stages=STAGES, t=0.0) -> list:
    """Run ``stages`` (names from STAGES) on ``mech`` (a Mechanism on a compiled module);
    the names of those that ran through (a solve failing on the way counts: what it
    called is compiled). Any other error is written to stderr and the stage skipped."""
    done = []
    for stage in stages:
        try:
            with warnings.catch_warnings():
                warnings.simplefilter("ignore")
                _RUN[stage](mech, t)
        except MechgenError:
            pass
        except Exception:       # noqa: BLE001 - reported, the other stages still run
            traceback.print_exc(file=sys.stderr)
            continue
        done.append(stage)
    return done
