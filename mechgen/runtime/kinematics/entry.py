"""Which compiled functions of a generated module a solve calls: each call compiles only
what it needs.

numba compiles a jitted function together with everything it calls (and optimises that
whole tree again for every entry point that calls it), so the library's all-in-one
entries (solve_point_derivatives: the sorted solver, the full Newton, both derivative
passes and their full fallbacks) cost several seconds of compiling on first use. The
functions here make the same decisions in Python, one small compiled call at a time: the
sorted solver first (solve_point_sorted), the full Newton (solve_point_full) only when
the sorted solver gave up or the method asks for it, the sorted velocity and acceleration
passes (both in one call, solve_derivatives_sorted, for an acceleration solve), with
their rank-revealing fallbacks compiled only when needed. The
numbers and statuses are those of the library's entries (mechgen.compiler.library.solve).
"""
from __future__ import annotations

from types import ModuleType

from ...protocol import (ACCELERATION, INFO_RANK, INFO_RESIDUAL, METHOD, NOT_FINITE, OK,
                        POINT_PIVOT, SING_RTOL, SINGULAR, VELOCITY)

FULL, SORTED = METHOD["full"], METHOD["sorted"]


def module_attr(mod, name, default=None):
    """``getattr(mod, name, default)``, the same answer without the cost of a miss: a
    module without the name formats an AttributeError (about a microsecond, as much as a
    compiled solve) before getattr gives the default. A plain module's names are its
    __dict__ (a module-level __getattr__, or another kind of object, asks getattr)."""
    if mod.__class__ is ModuleType:
        names = mod.__dict__
        if "__getattr__" not in names:
            return names.get(name, default)
    return getattr(mod, name, default)


def solve_point(mod, q, t, p, tol, xtol, maxit, meth, info) -> int:
    """The module's solve_point(): the position in place, info as there. A division by
    zero in the model's equations (a driver 1/T at T = 0: Python's float division and
    numba's default error model raise where numpy gives inf) is NOT_FINITE, as a NaN is."""
    try:
        return _solve_point(mod, q, t, p, tol, xtol, maxit, meth, info)
    except ZeroDivisionError:
        info[INFO_RESIDUAL] = float("nan")
        return NOT_FINITE


def _solve_point(mod, q, t, p, tol, xtol, maxit, meth, info) -> int:
    first = getattr(mod, "solve_point_sorted", None)
    if first is None:                         # a module from before these entries
        return mod.solve_point(q, t, p, tol, xtol, maxit, meth, info)
    if mod.SORTED and meth != FULL:
        status = first(q, t, p, tol, xtol, maxit, info)
        if status == OK or meth == SORTED:
            return status
    return mod.solve_point_full(q, t, p, tol, xtol, maxit, info)


def solve_velocity(mod, q, t, p, meth, out) -> int:
    """The module's solve_velocity(): the sorted pass, the full solve only when needed
    (NOT_FINITE where the equations divide by zero)."""
    try:
        return _solve_velocity(mod, q, t, p, meth, out)
    except ZeroDivisionError:
        return NOT_FINITE


def _solve_velocity(mod, q, t, p, meth, out) -> int:
    if mod.SORTED and mod.LEVEL >= 1 and meth != FULL:
        status = mod.velocity_sorted(q, t, p, out)
        if status == OK or meth == SORTED:
            return status
    return mod.velocity_full(q, t, p, out)


def solve_acceleration(mod, q, qd, t, p, meth, out) -> int:
    """The module's solve_acceleration(): the sorted pass, the full solve only when needed
    (NOT_FINITE where the equations divide by zero)."""
    try:
        return _solve_acceleration(mod, q, qd, t, p, meth, out)
    except ZeroDivisionError:
        return NOT_FINITE


def _solve_acceleration(mod, q, qd, t, p, meth, out) -> int:
    if mod.SORTED and mod.LEVEL >= 2 and meth != FULL:
        status = mod.acceleration_sorted(q, qd, t, p, out)
        if status == OK or meth == SORTED:
            return status
    return mod.acceleration_full(q, qd, t, p, out)


def solve_point_derivatives(mod, q, t, p, tol, xtol, maxit, meth, level, qd, qdd, info,
                            fused=None) -> int:
    """The module's solve_point_derivatives(): solve_point, then the velocities (not at a
    singular position) and, with level >= 2, the accelerations. Returns the position
    status, or VELOCITY + the velocity status, or ACCELERATION + the acceleration one.
    ``fused`` (piv, lam, factors), a module with dynamics_sorted: the multipliers too, in
    the derivatives' pass (piv[2] 1.0 where their pivots held; 0.0 where that pass did not
    run: the caller solves them)."""
    status = solve_point(mod, q, t, p, tol, xtol, maxit, meth, info)
    if status != OK:
        return status
    if level >= 1:
        if info[INFO_RANK] < len(q) or not info[POINT_PIVOT] >= SING_RTOL:
            return VELOCITY + SINGULAR
        both = getattr(mod, "solve_derivatives_sorted", None)
        if level >= 2 and both is not None and mod.SORTED and mod.LEVEL >= 2 and meth != FULL:
            if fused is not None:
                try:
                    if mod.dynamics_sorted(q, t, p, qd, qdd, *fused) == OK:
                        return OK
                except ZeroDivisionError:   # the plain tier, where numba's numpy error
                    pass                    # model gives inf
                fused[0][2] = 0.0           # (its multipliers are not to be used)
            try:
                return _derivatives(mod, both, q, t, p, meth, qd, qdd)
            except ZeroDivisionError:
                return VELOCITY + NOT_FINITE
        status = solve_velocity(mod, q, t, p, meth, qd)
        if status != OK:
            return VELOCITY + status
    if level >= 2:
        status = solve_acceleration(mod, q, qd, t, p, meth, qdd)
        if status != OK:
            return ACCELERATION + status
    return OK


def _derivatives(mod, both, q, t, p, meth, qd, qdd) -> int:
    """Both sorted passes in one compiled call; where one gave up and the method allows
    it, the full solve of that level and what follows it, as solve_velocity and
    solve_acceleration would have made them."""
    status = both(q, t, p, qd, qdd)
    if status == OK or meth == SORTED:
        return status
    if status < ACCELERATION:             # the sorted velocity pass gave up
        status = mod.velocity_full(q, t, p, qd)
        if status != OK:
            return VELOCITY + status
        status = solve_acceleration(mod, q, qd, t, p, meth, qdd)
    else:                                 # the velocities stand; the accelerations did not
        status = mod.acceleration_full(q, qd, t, p, qdd)
    return OK if status == OK else ACCELERATION + status
