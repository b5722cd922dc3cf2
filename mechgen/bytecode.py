"""Bytecode of mechgen's own modules where Python keeps none: with PYTHONDONTWRITEBYTECODE
set (``sys.dont_write_bytecode``) and no ``__pycache__`` beside the sources (an editable
checkout, a container), every process compiles each module it imports from its text, a
fifth of a warm first answer (30 to 60 ms) and a quarter of a cold one (0.25 s).

:func:`install` (called by ``import mechgen``) puts a finder before Python's own for
``mechgen.*`` alone: a module with no bytecode of Python's is loaded through
:class:`CachedLoader`, which keeps its code under ``$MECHGEN_CACHE/bytecode`` (or
``~/.cache/mechgen``), checked against the source's hash as Python checks a hash-based
.pyc (PEP 552): an edited source is compiled again, never run stale; a damaged or foreign
file is compiled over. Nothing is installed where Python writes or finds its own
bytecode, nor with MECHGEN_BYTECODE=0. Standard library only; imports nothing of mechgen.
"""
from __future__ import annotations

import marshal
import os
import sys
from importlib.machinery import PathFinder, SourceFileLoader
from importlib.util import cache_from_source, source_hash

_MAGIC = b"mechgen-own-bytecode 1\n"


def folder() -> str:
    """Where the code is kept: beside mechgen's other caches (bridge.cache_folder)."""
    base = os.environ.get("MECHGEN_CACHE") or os.path.join(
        os.path.expanduser("~"), ".cache", "mechgen")
    return os.path.join(base, "bytecode", sys.implementation.cache_tag or "py")


class CachedLoader(SourceFileLoader):
    """A module of mechgen, its code kept in :func:`folder` under its source's hash."""

    def get_code(self, fullname):
        path = self.get_filename(fullname)
        source = self.get_data(path)
        key = source_hash(source)
        where = source_hash(os.fsencode(path)).hex()      # one file per checkout
        kept = os.path.join(folder(), f"{fullname}.{where}.{key.hex()}.code")
        try:
            with open(kept, "rb") as fh:
                data = fh.read()
            head = _MAGIC + key + os.fsencode(path) + b"\n"
            if data.startswith(head):
                return marshal.loads(data[len(head):])
        except (OSError, ValueError, EOFError, TypeError):
            pass                # none kept, or damaged: compiled (and kept) again
        code = self.source_to_code(source, path)
        try:
            os.makedirs(os.path.dirname(kept), exist_ok=True)
            tmp = f"{kept}.{os.getpid()}.tmp"
            with open(tmp, "wb") as fh:
                fh.write(_MAGIC + key + os.fsencode(path) + b"\n" + marshal.dumps(code))
            os.replace(tmp, kept)
            _forget_others(kept, f"{fullname}.{where}.")
        except OSError:
            pass                # a folder we cannot write: compiled each time, as before
        return code


def _forget_others(kept, prefix) -> None:
    """Remove the code kept for earlier texts of the same file (edited since)."""
    where = os.path.dirname(kept)
    for name in os.listdir(where):
        if name.startswith(prefix) and name.endswith(".code") and \
                os.path.join(where, name) != kept:
            try:
                os.remove(os.path.join(where, name))
            except OSError:
                pass


class Finder:
    """The spec Python's path finder gives a ``mechgen.*`` module, with CachedLoader as
    its loader where Python has no bytecode of it."""

    @classmethod
    def find_spec(cls, fullname, path=None, target=None):
        if not fullname.startswith("mechgen.") or not sys.dont_write_bytecode:
            return None
        spec = PathFinder.find_spec(fullname, path, target)
        if spec is None or type(spec.loader) is not SourceFileLoader or not spec.origin:
            return None
        try:
            if os.path.exists(cache_from_source(spec.origin)):
                return None     # Python's own bytecode (an installed mechgen): as usual
        except (NotImplementedError, ValueError):
            return None
        spec.loader = CachedLoader(fullname, spec.origin)
        return spec


def install() -> None:
    """Put :class:`Finder` first in sys.meta_path (once), where it can help."""
    if not sys.dont_write_bytecode or os.environ.get("MECHGEN_BYTECODE") == "0":
        return
    if any(f is Finder for f in sys.meta_path):
        return
    sys.meta_path.insert(0, Finder)
