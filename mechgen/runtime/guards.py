"""Checks of the arguments users pass, made in Python before any jitted call (numba does
not check types or bounds): each names the argument and what it should be."""
from __future__ import annotations

import math
import os

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


def all_finite(x) -> bool:
    """``np.all(np.isfinite(x))`` of a 1-D float array, the same answer at a fraction of
    its cost (a numpy reduction costs a microsecond, as much as a compiled solve): the sum
    of its numbers as Python floats is finite only where every number is (Python's
    arithmetic neither warns nor raises); a sum that is not (an overflow) asks numpy."""
    s = sum(x.tolist())
    return s - s == 0.0 or bool(np.isfinite(x).all())


def positive_tol(tol, what="tol") -> float:
    """A finite tolerance above 0, or a ValueError naming ``what``."""
    tol = finite(tol, what)
    if not tol > 0:
        raise ValueError(f"{what} must be positive, got {tol!r}")
    return tol


MAX_COUNT = 10 ** 6     # iterations: more never help Newton's method, and numba's int64


def positive_count(value, what) -> int:
    """A positive integer (an iteration limit) up to MAX_COUNT: bools and floats are
    refused."""
    if isinstance(value, bool) or not isinstance(value, (int, np.integer)) or value < 1:
        raise ValueError(f"{what} must be a positive integer, got {value!r}")
    if value > MAX_COUNT:
        raise ValueError(f"{what} must be at most {MAX_COUNT:,} (an iteration limit), "
                         f"got {value!r}")
    return int(value)


def level_index(level, built_level, name) -> int:
    """The index in protocol.LEVELS of a level name that module ``name`` (built up to
    ``built_level``) can solve."""
    if level not in LEVEL:          # (solve and sweep take the force levels before this)
        raise ValueError(f"level must be one of {', '.join(LEVEL)}, static, dynamic, got "
                         f"{level!r}")
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


def sweep_times(t0, t1, n, times=None, each=8) -> np.ndarray:
    """The times of a sweep: n from t0 to t1 (both ends), or the given ones. n points of
    ``each`` bytes (a sweep's point) must fit in memory."""
    if times is None:
        t0, t1 = finite(t0, "t0"), finite(t1, "t1")
        if isinstance(n, bool) or not isinstance(n, (int, np.integer, float)) \
                or int(n) != n or n < 1:
            raise ValueError(f"n must be a positive integer, got {n!r}")
        fits(int(n), each, "sweep points", "n")
        return np.linspace(t0, t1, int(n))
    ts = np.asarray(times, dtype=np.float64)
    if ts.ndim != 1 or not np.all(np.isfinite(ts)):
        raise ValueError("times must be a 1-D array of finite numbers")
    _agree(ts, t0, t1, n)
    return ts


def _agree(ts, t0, t1, n) -> None:
    """t0, t1 and n given beside ``times`` say the same (None: not given): a sweep of 101
    points asked for with 50 times, or from 0 to 1 with times that end at 0.99, is refused
    rather than one of them silently ignored."""
    if n is not None and (isinstance(n, bool) or not isinstance(n, (int, np.integer, float))
                          or n != ts.shape[0]):
        raise ValueError(f"n={n!r} but times has {ts.shape[0]} points: give n=None or "
                         f"n={ts.shape[0]}")
    if ts.shape[0] == 0:
        return
    span = abs(float(ts[-1]) - float(ts[0])) + abs(float(ts[0])) + abs(float(ts[-1]))
    for name, given, end in (("t0", t0, ts[0]), ("t1", t1, ts[-1])):
        if given is None:
            continue
        try:
            value = float(given)
        except (TypeError, ValueError):
            raise ValueError(f"{name} must be a number or None, got {given!r}") from None
        if not abs(value - float(end)) <= 1e-12 * span:
            raise ValueError(f"{name}={given!r} but times {'starts' if name == 't0' else 'ends'}"
                             f" at {float(end)!r}: give {name}=None or the same time")


# -- sizes: refused before anything is allocated ------------------------------------------
def memory_bytes() -> int:
    """This machine's physical memory in bytes (2**40 where the system does not say)."""
    try:
        return int(os.sysconf("SC_PAGE_SIZE")) * int(os.sysconf("SC_PHYS_PAGES"))
    except (ValueError, OSError, AttributeError):
        return 1 << 40


def _size(nbytes) -> str:
    for unit in ("bytes", "KiB", "MiB", "GiB", "TiB", "PiB", "EiB"):
        if nbytes < 1024 or unit == "EiB":
            return f"{nbytes:.0f} {unit}" if unit == "bytes" else f"{nbytes:.3g} {unit}"
        nbytes /= 1024.0
    return f"{nbytes:.3g} EiB"


def point_bytes(n_coords, level) -> int:
    """The memory one sweep point takes: its time, the coordinates at each level solved,
    its status row."""
    return 8 * (1 + int(n_coords) * (int(level) + 1)) + 16


def fits(count, each, noun, argument, extra="") -> None:
    """Refuse (ValueError naming ``argument``) ``count`` ``noun`` of ``each`` bytes that
    would not fit in this machine's memory, before anything is allocated."""
    limit = memory_bytes()
    need = float(count) * float(each)
    if need > limit:
        most = max(limit // max(int(each), 1), 1)
        raise ValueError(f"{argument}: {int(count):,} {noun}{extra} would need {_size(need)}, "
                         f"more than this machine's memory ({_size(limit)}); the limit here "
                         f"is {most:,} {noun}")


def sweep_count(n, n_coords, level, argument="n") -> None:
    """A sweep of n points at ``level`` (an index) must fit in memory."""
    fits(n, point_bytes(n_coords, level), "sweep points", argument)
