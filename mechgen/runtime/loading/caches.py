"""The on-disk caches of a generated module: where mechgen keeps its own (state_dir),
and numba's, checked before the module is imported: a damaged cache is deleted (numba
then compiles again), never loaded.

numba keeps, per jitted function, an index ``<module>.<function>-<line>.<tag>.nbi`` and
data files ``....<k>.nbc`` (pickles) beside the module in ``__pycache__`` (or under
``$NUMBA_CACHE_DIR``). It checks an index against the module file's time stamp and size,
not against the bytes it holds: a truncated file makes the first call raise EOFError or
UnpicklingError, an edited one may load. Here every index and the data files it names
are read back (the index unpickled, the data parsed as pickles without running them), and
each file's sha256 is compared with the one recorded when it was last seen whole
(``<state>/<name>.<digest>.numba-sums``, keyed by the module's content digest) where its
time stamp and size are those recorded (other bytes under them are damage; a file with
a new time stamp was written again, by numba in this or another process): a file that
fails either is deleted with its function's other files, with a warning. Files numba
writes while this process runs are recorded at exit.

numpy-free; numba is imported only to locate its cache folder.
"""
from __future__ import annotations

import atexit
import glob
import hashlib
import json
import os
import pickle
import pickletools
import time
import warnings


_WATCHED: dict = {}          # module path -> (digest, start time) to record at exit


def state_dir(path: str) -> str:
    """Where mechgen keeps what it knows of the module at ``path`` (its bytecode, the marks
    and lock of mechgen.runtime.loading.tiers): beside numba's cache of it."""
    cache = os.environ.get("NUMBA_CACHE_DIR")
    if cache:
        return os.path.join(cache, "mechgen-tiers")
    here = os.path.join(os.path.dirname(path), "__pycache__")
    try:
        os.makedirs(here, exist_ok=True)
        if os.access(here, os.W_OK):
            return here
    except OSError:
        pass
    return os.path.join(os.path.expanduser("~"), ".cache", "mechgen", "tiers")


def cache_folder(path: str) -> str:
    """The folder where numba caches the functions of the module file at ``path``."""
    path = os.path.abspath(path)
    root = os.environ.get("NUMBA_CACHE_DIR")
    if root:
        try:
            from numba.core.caching import _CacheLocator
            return os.path.join(root, _CacheLocator.get_suitable_cache_subpath(path))
        except (ImportError, AttributeError):
            pass
    return os.path.join(os.path.dirname(path), "__pycache__")


def _files(folder: str, stem: str) -> list:
    try:
        names = os.listdir(folder)
    except OSError:
        return []
    return sorted(n for n in names if n.startswith(stem + ".") and n.endswith((".nbi", ".nbc")))


def _group(name: str) -> str:
    """The function a cache file belongs to: its index name without ``.nbi``."""
    if name.endswith(".nbi"):
        return name[:-4]
    return name[:-4].rsplit(".", 1)[0]       # "<base>.<k>.nbc" -> "<base>"


def _sha(path: str) -> str:
    """The file's sha256 with its time stamp and size: ``sha:mtime_ns:size``."""
    st = os.stat(path)
    with open(path, "rb") as fh:
        return f"{hashlib.sha256(fh.read()).hexdigest()}:{st.st_mtime_ns}:{st.st_size}"


def _damaged(recorded: str, now: str) -> bool:
    """Whether a file changed without being written: other bytes under the same time stamp
    and size (a disk's damage). A file written again since (another process compiling
    more functions, a background worker) has a new time stamp: it is read back whole or
    not by _whole, and recorded anew."""
    if recorded == now:
        return False
    old, new = recorded.split(":"), now.split(":")
    if len(old) != 3:
        return old[0] != new[0]
    return old[1:] == new[1:]


def _sums_path(path: str, digest: str) -> str:
    stem = os.path.splitext(os.path.basename(path))[0]
    return os.path.join(state_dir(path), f"{stem}.{digest[:20]}.numba-sums")


def _read_sums(path, digest) -> dict:
    try:
        with open(_sums_path(path, digest), encoding="utf-8") as fh:
            sums = json.load(fh)
        return sums if isinstance(sums, dict) else {}
    except (OSError, ValueError):
        return {}


def _write_sums(path, digest, sums) -> None:
    target = _sums_path(path, digest)
    try:
        os.makedirs(os.path.dirname(target), exist_ok=True)
        tmp = f"{target}.{os.getpid()}.tmp"
        with open(tmp, "w", encoding="utf-8") as fh:
            json.dump(sums, fh, sort_keys=True)
        os.replace(tmp, target)
    except OSError:
        pass


def _parsed(data: bytes) -> None:
    """Parse a pickle without running it (unpickling numba's data rebuilds its
    environment, which imports the module): raise unless it is one whole pickle."""
    end = None
    for op, _arg, pos in pickletools.genops(data):
        end = pos
        if op.name == "STOP":
            break
    if end is None or end + 1 != len(data):
        raise ValueError("not one whole pickle")


def _whole(folder: str, index: str) -> bool:
    """Whether an index (unpickled, as numba reads it) and the data files it names
    (parsed) are whole."""
    try:
        with open(os.path.join(folder, index), "rb") as fh:
            pickle.load(fh)                         # numba's version
            stamp, overloads = pickle.loads(fh.read())
        for data in overloads.values():
            file = os.path.join(folder, data)
            if os.path.exists(file):
                with open(file, "rb") as fh:
                    _parsed(fh.read())
        return True
    except Exception:       # noqa: BLE001 - any failure to read it back is damage
        return False


def check(path: str, digest: str) -> list:
    """Delete the damaged parts of numba's cache of the module at ``path`` (content
    digest ``digest``); record the sums of the rest. Returns the files deleted."""
    folder = cache_folder(path)
    stem = os.path.splitext(os.path.basename(path))[0]
    names = _files(folder, stem)
    sums = _read_sums(path, digest)
    bad = set()
    current = {}
    for name in names:
        try:
            current[name] = _sha(os.path.join(folder, name))
        except OSError:
            continue
        if name in sums and _damaged(sums[name], current[name]):
            bad.add(_group(name))
    for name in names:
        if name.endswith(".nbi") and _group(name) not in bad and not _whole(folder, name):
            bad.add(_group(name))
    removed = []
    for name in names:
        if _group(name) in bad:
            try:
                os.remove(os.path.join(folder, name))
                removed.append(name)
            except OSError:
                pass
            current.pop(name, None)
    if removed:
        # the tiers' mark (runtime.loading.tiers) says the cache is complete: no longer
        marks = os.path.join(glob.escape(state_dir(path)), f"{glob.escape(stem)}-*.compiled")
        for mark in glob.glob(marks):
            try:
                os.remove(mark)
            except OSError:
                pass
        warnings.warn(f"numba's cache of {path} was damaged ({', '.join(sorted(removed))}): "
                      "deleted; those functions compile again", RuntimeWarning, stacklevel=3)
    if current != sums:
        _write_sums(path, digest, current)
    _WATCHED[os.path.abspath(path)] = (digest, time.time())
    return removed


def record_written() -> None:
    """At exit: record the sums of the cache files numba wrote while this process ran
    (its own writes: new functions compiled, an index extended)."""
    for path, (digest, since) in list(_WATCHED.items()):
        folder = cache_folder(path)
        stem = os.path.splitext(os.path.basename(path))[0]
        sums = _read_sums(path, digest)
        changed = False
        for name in _files(folder, stem):
            file = os.path.join(folder, name)
            try:
                if os.stat(file).st_mtime < since - 1.0 and name in sums:
                    continue
                if name.endswith(".nbi") and not _whole(folder, name):
                    continue
                sha = _sha(file)
            except OSError:
                continue
            if sums.get(name) != sha:
                sums[name] = sha
                changed = True
        if changed:
            _write_sums(path, digest, sums)


atexit.register(record_written)
