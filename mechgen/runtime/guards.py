"""Checks of the arguments users pass, made in Python before any jitted call (numba does
not check types or bounds): each names the argument and what it should be."""
from __future__ import annotations

import math

import numpy as np

from ..protocol import LEVEL, LEVELS, METHOD


def finite(value, what) -> float:
    """``value`` as a finite float, or a ValueError naming ``what``."""
    try:
        x = float(value)
    except (TypeError, ValueError):
        raise ValueError(f"{what} must be a number, got {value!r}") from None
    if not math.isfinite(x):
        raise ValueError(f"{what} must be finite, got {value!r}")
    return x


def positive_tol(tol) -> float:
    tol = finite(tol, "tol")
    if not tol > 0:
        raise ValueError(f"tol must be positive, got {tol!r}")
    return tol


def positive_count(value, what) -> int:
    """A positive integer (an iteration limit): bools and floats are refused."""
    if isinstance(value, bool) or not isinstance(value, (int, np.integer)) or value < 1:
        raise ValueError(f"{what} must be a positive integer, got {value!r}")
    return int(value)


def level_index(level, built_level, name) -> int:
    """The index in protocol.LEVELS of a level name that module ``name`` (built up to
    ``built_level``) can solve."""
    if level not in LEVEL:
        raise ValueError(f"level must be one of {', '.join(LEVEL)}, got {level!r}")
    if LEVEL[level] > built_level:
        raise ValueError(f"module '{name}' was built for level {LEVELS[built_level]} only; "
                         f"rebuild it with `mechgen build MODEL.py --level {level}` to solve "
                         f"{level}")
    return LEVEL[level]


def method_index(method) -> int:
    """The index in protocol.METHODS of a method name."""
    if method not in METHOD:
        raise ValueError(f"method must be one of {', '.join(METHOD)}, got {method!r}")
    return METHOD[method]


def sweep_times(t0, t1, n, times=None) -> np.ndarray:
    """The times of a sweep: n from t0 to t1 (both ends), or the given ones."""
    if times is None:
        t0, t1 = finite(t0, "t0"), finite(t1, "t1")
        if isinstance(n, bool) or not isinstance(n, (int, np.integer, float)) \
                or int(n) != n or n < 1:
            raise ValueError(f"n must be a positive integer, got {n!r}")
        return np.linspace(t0, t1, int(n))
    ts = np.asarray(times, dtype=np.float64)
    if ts.ndim != 1 or not np.all(np.isfinite(ts)):
        raise ValueError("times must be a 1-D array of finite numbers")
    return ts
