"""The module a large call answers with before numba's cache is ready: its loops compiled,
everything else run as plain Python.

A sweep of 10^5 points needs numba for its loop (sweep_fast: microseconds a point instead
of a millisecond) but not for the handful of one-point calls around it (the start's
solve, its turns, its pivot ratio), which Python answers in milliseconds and numba
would compile for seconds: on the quick-return they are 4 of the 7 seconds of compiling
that the first compiled sweep cost. The mixed module holds the plain module's names
with the compiled module's loops put over them; a loop is a function whose arguments
take many points (LOOP_ARGS: a grid of times, of configurations, of designs, or a span to
integrate over). Both tiers give the same numbers bit for bit (the generated text is one;
tests/test_tiers.py), so a loop started from a point the plain tier solved gives what the
compiled module would. The tiers (mechgen.runtime.loading.tiers) answer with it until the
background worker has filled numba's cache, then load the compiled module whole.
"""
from __future__ import annotations

import types

# a function with one of these arguments works on many points: compiled in a mixed module
LOOP_ARGS = frozenset({"ts", "Q", "Q0", "P", "t1"})


def is_loop(fn) -> bool:
    """Whether ``fn`` (a numba dispatcher or a plain function) takes many points."""
    py = getattr(fn, "py_func", None) or getattr(fn, "__wrapped__", None) or fn
    code = getattr(py, "__code__", None)
    if code is None:
        return False
    return not LOOP_ARGS.isdisjoint(code.co_varnames[:code.co_argcount])


def mixed_module(plain: types.ModuleType, compiled: types.ModuleType) -> types.ModuleType:
    """A module object with ``plain``'s names (the runtime's marks on it included) and
    ``compiled``'s loops in place of the plain ones."""
    module = types.ModuleType(compiled.__name__, compiled.__doc__)
    module.__dict__.update(vars(plain))
    for name, value in vars(compiled).items():
        if callable(value) and hasattr(value, "py_func") and is_loop(value):
            setattr(module, name, value)
    module.__mechgen_tier__ = "compiled"        # its large calls are: no switch from it
    module.__mechgen_mixed__ = True
    return module

