"""The plain-Python tier of a generated module: the same text run by the interpreter,
without numba, so that a model answers before numba has compiled anything.

A generated module's header reads ``njit, math = __mechgen_python__`` when that name is
defined (see templates/module.py.j2): :func:`python_module` defines it as an ``njit``
that returns the function unchanged and a ``math`` with numba's answers where Python's
would raise (NaN for a domain error, ±inf for an overflow), then wraps every function of
the module so that numpy's floating-point warnings stay quiet, as compiled code is.
Nothing here imports numba or sympy.
"""
from __future__ import annotations

import hashlib
import marshal
import math as _math
import os
import sys
import types
import warnings
from time import perf_counter

import numpy as np

from ...errors import MechgenError
from .caches import state_dir  # noqa: F401 - where the tiers keep their files
from .loader import checked_text
from .plain_linalg import REPLACEMENTS

_NAN = float("nan")
_INF = float("inf")


def njit(*args, **options):
    """numba's decorator, doing nothing: ``@njit`` and ``@njit(cache=True, ...)`` alike."""
    if args and callable(args[0]) and not options:
        return args[0]
    return lambda fn: fn


def _safe(fn, overflow=_INF):
    """fn, returning NaN where Python raises ValueError (a domain error: sqrt(-1),
    sin(inf), floor(nan)) and ±``overflow`` where it raises OverflowError, as numba does."""
    def call(*args):
        try:
            return fn(*args)
        except ValueError:
            return _NAN
        except OverflowError:
            return overflow
    call.__name__ = fn.__name__
    return call


def _floor(x):
    try:
        return _math.floor(x)
    except (ValueError, OverflowError):
        return x       # nan or ±inf, as a float (numba's floor of them is no number either)


def _log(fn):
    """A logarithm as numba's: -inf at 0, NaN below."""
    def call(*args):
        try:
            return fn(*args)
        except ValueError:
            return -_INF if args[0] == 0 else _NAN
    call.__name__ = fn.__name__
    return call


def _sinh(x):
    try:
        return _math.sinh(x)
    except OverflowError:
        return _math.copysign(_INF, x)


def _pow(x, y):
    try:
        return _math.pow(x, y)
    except ValueError:
        return _NAN
    except OverflowError:
        return _INF


def _make_math():
    ns = {name: getattr(_math, name) for name in dir(_math) if not name.startswith("_")}
    for name in ("sqrt", "acos", "asin", "acosh", "atanh",
                 "sin", "cos", "tan", "fmod", "remainder", "gamma", "lgamma"):
        if name in ns:
            ns[name] = _safe(getattr(_math, name))
    for name in ("exp", "expm1", "cosh"):
        ns[name] = _safe(getattr(_math, name), overflow=_INF)
    ns.update({name: _log(getattr(_math, name)) for name in ("log", "log2", "log10")})
    ns.update(floor=_floor, ceil=_safe(_math.ceil), sinh=_sinh, pow=_pow)
    return types.SimpleNamespace(**ns)


MATH = _make_math()


class Clock:
    """Seconds spent in plain-Python calls, and what to do after each (the tiers' switch)."""

    def __init__(self):
        self.spent = 0.0
        self.after = None      # called with no arguments after each call, when set

    def wrap(self, fn):
        """fn with numpy's warnings off and its time added to ``spent``."""
        def call(*args):
            start = perf_counter()
            try:
                with np.errstate(all="ignore"):
                    return fn(*args)
            finally:
                self.spent += perf_counter() - start
                if self.after is not None:
                    self.after()
        call.__name__ = fn.__name__
        call.__doc__ = fn.__doc__
        call.__wrapped__ = fn
        return call


class NoPlainTier(MechgenError):
    """A module generated before the plain-Python tier existed."""


_MAGIC = b"mechgen-plain-bytecode 1\n"


def _pack(code, digest: str) -> bytes:
    """The bytes kept for a module's bytecode: a header naming the module's content
    digest and the sha256 of the marshalled code, then the code."""
    body = marshal.dumps(code)
    return (_MAGIC + digest.encode("ascii") + b"\n" +
            hashlib.sha256(body).hexdigest().encode("ascii") + b"\n" + body)


def _unpack(data: bytes, digest: str):
    """The code kept in ``data`` when it is whole and was compiled from the module whose
    content digest is ``digest``; None for anything else (another module, an older
    layout, edited or truncated bytes)."""
    if not data.startswith(_MAGIC):
        return None
    head = data[len(_MAGIC):]
    parts = head.split(b"\n", 2)
    if len(parts) != 3:
        return None
    kept_digest, kept_hash, body = parts
    if kept_digest != digest.encode("ascii") or \
            kept_hash != hashlib.sha256(body).hexdigest().encode("ascii"):
        return None
    try:
        return marshal.loads(body)
    except (ValueError, EOFError, TypeError):
        return None


def _code(text: str, path: str, digest: str):
    """The module's compiled bytecode, kept in state_dir by its digest (compiling 2000
    lines of Python costs 0.1 s, loading them 1 ms). The kept file is used only when its
    header names this module's content digest and the sha256 of its bytes matches: a
    damaged or foreign one is deleted and the text compiled again (a warning says so)."""
    tag = sys.implementation.cache_tag or "py"
    name = os.path.splitext(os.path.basename(path))[0]
    kept = os.path.join(state_dir(path), f"{name}.{digest[:20]}.{tag}.plain")
    data = None
    try:
        with open(kept, "rb") as fh:
            data = fh.read()
    except OSError:
        pass
    if data is not None:
        code = _unpack(data, digest)
        if code is not None:
            return code
        warnings.warn(f"the plain-Python bytecode cache {kept} does not match {path} (damaged "
                      "or from another module): deleted, the module compiled again",
                      RuntimeWarning, stacklevel=3)
        try:
            os.remove(kept)
        except OSError:
            pass
    code = compile(text, path, "exec")
    try:
        os.makedirs(os.path.dirname(kept), exist_ok=True)
        tmp = f"{kept}.{os.getpid()}.tmp"
        with open(tmp, "wb") as fh:
            fh.write(_pack(code, digest))
        os.replace(tmp, kept)
    except OSError:
        pass
    return code


def python_module(path: str, clock: Clock | None = None) -> types.ModuleType:
    """The generated module at ``path`` run as plain Python: a module object (not in
    sys.modules) holding its constants and its functions, each wrapped by ``clock``.
    The file's content stamp is checked as for an import."""
    path = os.path.abspath(path)
    if not os.path.isfile(path):
        raise MechgenError(f"no generated module at {path}; build it with `mechgen build MODEL.py`")
    text, found = checked_text(path)
    if "__mechgen_python__" not in text:
        raise NoPlainTier(f"{path} was generated before the plain-Python tier existed; rebuild "
                           "it with `mechgen build MODEL.py`, or load it with tier='compiled'")
    name = os.path.splitext(os.path.basename(path))[0]
    ns = {"__name__": f"{name}__mechgen_python", "__file__": path,
          "__builtins__": __builtins__, "__mechgen_python__": (njit, MATH)}
    try:
        exec(_code(text, path, found), ns)    # noqa: S102 - our own generated module
    except Exception as exc:
        raise MechgenError(f"running the generated module {path} as Python raised "
                           f"{type(exc).__name__}: {exc}; rebuild it with `mechgen build`") from exc
    for key, fast in REPLACEMENTS.items():      # whole-row forms of the O(n³) loops
        if key in ns:
            ns[key] = fast
    module = types.ModuleType(ns.get("MODEL_NAME", name), ns.get("__doc__"))
    clock = clock or Clock()
    for key, value in ns.items():
        if key in ("__builtins__", "__mechgen_python__"):
            continue
        if isinstance(value, types.FunctionType):
            value = clock.wrap(value)
        setattr(module, key, value)
    module.__file__ = path
    module.__mechgen_digest__ = found
    module.__mechgen_tier__ = "python"
    return module
