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
compiled module would. A one-point function that a caller's own loop calls many times
(sw.reaction's Φ_q at every point of a sweep, a simulation's projection) is compiled once
its plain calls have cost PROMOTE_AFTER seconds, about what compiling it costs. The
tiers (mechgen.runtime.loading.tiers) answer with it until the background worker has
filled numba's cache, then load the compiled module whole.
"""
from __future__ import annotations

import types
from time import perf_counter

# a function with one of these arguments works on many points: compiled in a mixed module
LOOP_ARGS = frozenset({"ts", "Q", "Q0", "P", "t1"})
# seconds of plain-Python calls after which a one-point function is compiled (about what
# numba takes to compile one: a caller's own loop over points, sw.reaction's Φ_q at every
# point, costs at most about twice what compiling it at once would have)
PROMOTE_AFTER = 0.5


def is_loop(fn) -> bool:
    """Whether ``fn`` (a numba dispatcher or a plain function) takes many points."""
    py = getattr(fn, "py_func", None) or getattr(fn, "__wrapped__", None) or fn
    code = getattr(py, "__code__", None)
    if code is None:
        return False
    return not LOOP_ARGS.isdisjoint(code.co_varnames[:code.co_argcount])


def promoting(module, name, plain, compiled, after=None):
    """``plain`` (a one-point function of the plain tier) until the calls made through it
    have cost ``after`` seconds (PROMOTE_AFTER), ``compiled`` from then on, also put in
    ``module`` under ``name`` (a caller holding this function gets it too)."""
    budget = [PROMOTE_AFTER if after is None else after]
    done = []

    def call(*args):
        if done:
            return compiled(*args)
        start = perf_counter()
        try:
            return plain(*args)
        finally:
            budget[0] -= perf_counter() - start
            if budget[0] < 0.0:
                done.append(True)
                setattr(module, name, compiled)
    call.__name__ = name
    call.__doc__ = getattr(plain, "__doc__", None)
    call.__wrapped__ = getattr(plain, "__wrapped__", plain)
    return call


def mixed_module(plain: types.ModuleType, compiled: types.ModuleType) -> types.ModuleType:
    """A module object with ``plain``'s names (the runtime's marks on it included) and
    ``compiled``'s loops in place of the plain ones; its other functions are promoting()
    ones: plain until they have cost PROMOTE_AFTER seconds, then compiled."""
    module = types.ModuleType(compiled.__name__, compiled.__doc__)
    module.__dict__.update(vars(plain))
    for name, value in vars(compiled).items():
        if not (callable(value) and hasattr(value, "py_func")) or name.startswith("__"):
            continue
        if is_loop(value):
            setattr(module, name, value)
        elif callable(getattr(plain, name, None)):
            setattr(module, name, promoting(module, name, getattr(plain, name), value))
    module.__mechgen_tier__ = "compiled"        # its large calls are: no switch from it
    module.__mechgen_mixed__ = True
    return module

