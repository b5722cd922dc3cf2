"""The sensitivity module of a mechanism's module (``<name>_sensitivities.py`` beside
``<name>.py``, mechgen.compiler.sensitivities): found, checked against the module's
MODEL_HASH and loaded; or built through the symbolic side ``mechgen.compile`` attached
(``mech.symbolic.build_sensitivities``), the runtime never importing the compiler.

Loaded companions are kept per module object, not on the Mechanism.
"""
from __future__ import annotations

import importlib.util
import os
import sys
import threading
import weakref

import numpy as np

from ...errors import MechgenError
from ...protocol import SENSITIVITY_FORMAT, SENSITIVITY_SUFFIX, content_digest, stamp_of

_LOADED = weakref.WeakKeyDictionary()     # module -> (companion, Blocks)
_LAST = {}                                # id(module) -> (weak reference, _LOADED's entry)
_LOCK = threading.Lock()


class Blocks:
    """The main module's solving order as the companion's solve_columns reads it: the
    rows and unknowns of each block (brow, bvar, block b at bstart[b]:bstart[b + 1]); one
    block of everything where the module is not sorted."""

    def __init__(self, module):
        n, m = int(module.N_COORDS), int(module.N_EQS)
        blocks = getattr(module, "BLOCKS", ()) if getattr(module, "SORTED", False) else ()
        index = {c: k for k, c in enumerate(module.COORDINATES)}
        rows, cols, start = [], [], [0]
        for _, names, brows in blocks:
            cols += [index[c] for c in names]
            rows += list(brows)
            start.append(len(rows))
        if not blocks or len(rows) != n or len(cols) != n:
            rows, cols, start = list(range(min(m, n))), list(range(n)), [0, n]
        self.brow = np.asarray(rows, dtype=np.int64)
        self.bvar = np.asarray(cols, dtype=np.int64)
        self.bstart = np.asarray(start, dtype=np.int64)
        self.square = m == n
        # a single solve's: the three arrays in one, its scratch (one call at a time: a
        # Mechanism's lock is held), q̇ = 0 where the level has none
        self.packed = np.concatenate([self.brow, self.bvar, self.bstart])
        npar = len(module.PARAMETERS)
        self.scratch = np.empty(m * (n + npar) + (n + 4) * n)
        self.shape = (3, n, npar)
        self.zero = np.zeros(n)


def path_of(module) -> str:
    """Where the sensitivity module of ``module`` lives."""
    source = getattr(module, "__file__", None)
    if not source:
        raise MechgenError(f"module '{module.MODEL_NAME}' has no file: sensitivities need "
                           "the generated module on disk (mechgen.load(path))")
    root, ext = os.path.splitext(os.path.abspath(source))
    return root + SENSITIVITY_SUFFIX + (ext or ".py")


def _import(path, module_hash, tier):
    """The companion at ``path`` if it belongs to the module of ``module_hash``, else
    None; run as plain Python where the module answering is (``tier``)."""
    try:
        with open(path, encoding="utf-8") as fh:
            text = fh.read()
    except OSError:
        return None
    found = stamp_of(text)
    if found is None or found != content_digest(text) or \
            f'MODULE_HASH = "{module_hash}"' not in text or \
            f"SENSITIVITY_FORMAT = {SENSITIVITY_FORMAT}\n" not in text:
        return None     # another module's, or an older layout: built again
    if tier == "python":
        from ..loading.plain import python_module
        return python_module(path)
    name = os.path.splitext(os.path.basename(path))[0]
    existing = sys.modules.get(name)
    if existing is not None and getattr(existing, "MODULE_HASH", None) == module_hash and \
            os.path.abspath(getattr(existing, "__file__", "")) == path:
        return existing
    spec = importlib.util.spec_from_file_location(name, path)
    mod = importlib.util.module_from_spec(spec)
    sys.modules[name] = mod
    try:
        spec.loader.exec_module(mod)
    except BaseException:
        sys.modules.pop(name, None)
        raise
    return mod


def _import_like(module, path, tier):
    """The companion as ``module`` runs: plain, compiled, or mixed (its loops compiled,
    the rest plain: mechgen.runtime.loading.mixed) where the module is."""
    if not getattr(module, "__mechgen_mixed__", False):
        return _import(path, module.MODEL_HASH, tier)
    plain = _import(path, module.MODEL_HASH, "python")
    compiled = _import(path, module.MODEL_HASH, "compiled")
    if plain is None or compiled is None:
        return None
    from ..loading.mixed import mixed_module
    return mixed_module(plain, compiled)


def companion(mech):
    """(sensitivity module, Blocks) of ``mech``'s module, loading or building it."""
    module = mech.module
    hit = _LAST.get(id(module))         # (a plain look-up: a weak one costs a solve 0.2 µs)
    if hit is not None and hit[0]() is module:
        return hit[1]
    hit = _LOADED.get(module)
    if hit is not None:
        _LAST[id(module)] = (weakref.ref(module), hit)
        return hit
    with _LOCK:
        hit = _LOADED.get(module)
        if hit is not None:
            return hit
        path = path_of(module)
        tier = getattr(module, "__mechgen_tier__", "compiled")
        found = _import_like(module, path, tier)
        if found is None:
            builder = getattr(mech.symbolic, "build_sensitivities", None)
            if builder is None:
                raise MechgenError(
                    f"'{mech.name}' has no sensitivity module ({os.path.basename(path)}): "
                    "build it with `mechgen build MODEL.py --sensitivities`, or load the "
                    "mechanism with mechgen.compile(model), which builds it when first asked")
            builder(os.path.abspath(module.__file__))
            found = _import_like(module, path, tier)
            if found is None:
                raise MechgenError(f"the sensitivity module {path} was built but does not "
                                   f"belong to the module of '{mech.name}' (MODEL_HASH)")
        if not all(getattr(module, "SOLVED", (True,))):
            raise MechgenError(f"'{mech.name}' was built pruned (--outputs): sensitivities "
                               "need every coordinate; rebuild without --outputs")
        hit = (found, Blocks(module))
        _LOADED[module] = hit
        return hit
