"""Which code answers a Mechanism's calls: the generated module run as plain Python (the
``python`` tier, at once) or compiled by numba (the ``compiled`` tier, microseconds a
point once compiled). Both give the same numbers; only the speed differs.

``tier="auto"`` (the default; or ``$MECHGEN_TIER``) starts in the plain-Python tier and
starts a worker process (mechgen.runtime.loading.warmup) that imports the module with numba and
calls its entry points once, in the order users need them, so that numba's on-disk cache
holds them all; it then leaves a mark beside the cache. Once the mark is there and the
plain-Python calls of this process have cost SWITCH_AFTER seconds, the next call loads
the compiled module (from the cache, no compiling) and the Mechanism uses it from then
on. A call too large for Python (a long sweep, a design table: ``expect``) switches at
once: from the cache when it is ready, else by compiling what the call needs in this
process (the worker, if it is ours, is stopped first; a worker of another process is
never waited for: this process compiles, or loads from the cache, just what the call
needs), then starts a worker again for the rest. What the call needs is its loop: until
the worker's cache is ready the process answers with a mixed module (loading.mixed),
the compiled loops over the plain module, so that the call's few one-point solves run
in Python instead of waiting for numba to compile them; the next calls after the mark
is there load the compiled module whole, as above.

``tier="python"`` never compiles; ``tier="compiled"`` imports with numba at once and
compiles what each call needs on first use (no worker).
"""
from __future__ import annotations

import functools
import hashlib
import json
import os
import sys

from ...errors import MechgenError
from ...protocol import MECHGEN_VERSION
from .loader import import_path, open_module, check_version
from .mixed import mixed_module
from .plain import Clock, NoPlainTier, python_module, state_dir

TIERS = ("auto", "python", "compiled")
_STARTED = []          # the workers this process started (they may outlive it)
SWITCH_AFTER = 0.2     # seconds of plain-Python calls after which a ready cache is loaded
BIG_CALL = 0.5         # a call estimated to take longer than this in Python waits for numba
POINT_COST = 5e-6      # seconds a sweep point costs in Python, per coordinate (a first guess)


def tier_choice(tier=None) -> str:
    """The tier asked for: ``tier``, else ``$MECHGEN_TIER``, else "auto"."""
    chosen = tier if tier is not None else (os.environ.get("MECHGEN_TIER") or "auto")
    if chosen not in TIERS:
        raise ValueError(f"tier must be one of {', '.join(map(repr, TIERS))}, got {chosen!r}")
    return chosen


@functools.lru_cache(maxsize=1)
def numba_version() -> str:
    """The installed numba's version, read from its package metadata (importing numba
    costs what the plain-Python tier is there to avoid); "" when it cannot be read.

    The metadata beside the numba that would be imported (one ``numba-*.dist-info`` or
    ``.egg-info`` in its folder) is read directly: importing importlib.metadata costs a
    fresh process 15 to 30 ms, a tenth of its first answer. Anything else (none there,
    several) asks importlib.metadata."""
    import importlib.util
    try:
        spec = importlib.util.find_spec("numba")
    except (ImportError, ValueError):
        spec = None
    if spec is None:
        return ""
    found = _version_beside(spec.origin)
    if found:
        return found
    try:
        from importlib.metadata import version
        return version("numba")
    except Exception:       # noqa: BLE001 - no metadata: the mark keys on the rest
        return ""


def _version_beside(origin) -> str:
    """The Version of the one numba distribution's metadata in the folder holding the
    package at ``origin`` (its __init__.py), or "" when there is not exactly one."""
    if not origin:
        return ""
    folder = os.path.dirname(os.path.dirname(origin))
    try:
        names = [n for n in os.listdir(folder) if n.startswith("numba-") and
                 n.endswith((".dist-info", ".egg-info"))]
    except OSError:
        return ""
    if len(names) != 1:
        return ""
    meta = "METADATA" if names[0].endswith(".dist-info") else "PKG-INFO"
    try:
        with open(os.path.join(folder, names[0], meta), encoding="utf-8") as fh:
            for line in fh:
                if line.startswith("Version:"):
                    return line.split(":", 1)[1].strip()
                if not line.strip():        # the end of the headers
                    break
    except OSError:
        pass
    return ""


def state_paths(path: str) -> tuple[str, str]:
    """(mark, lock) of the module file at ``path``: the mark exists when numba's cache
    holds every entry point of exactly this file (its time stamp included, which numba's
    cache checks) for this Python, numba (whose cache another version does not read),
    mechgen and cache folder; the lock is held while a process writes the cache."""
    path = os.path.abspath(path)
    st = os.stat(path)
    where = f"{path}\0{os.environ.get('NUMBA_CACHE_DIR', '')}"
    key = (f"{where}\0{st.st_mtime_ns}\0{st.st_size}\0{sys.version}\0{MECHGEN_VERSION}"
           f"\0{numba_version()}")
    name = os.path.splitext(os.path.basename(path))[0]
    folder = state_dir(path)
    return (os.path.join(folder, f"{name}-{hashlib.sha1(key.encode()).hexdigest()[:16]}.compiled"),
            os.path.join(folder, f"{name}-{hashlib.sha1(where.encode()).hexdigest()[:16]}.lock"))


def cache_ready(path: str) -> bool:
    """Whether numba's cache holds every entry point of the module at ``path``."""
    return os.path.exists(state_paths(path)[0])


class Lock:
    """An exclusive lock on a file (released when the process ends, however it ends)."""

    def __init__(self, path):
        self.path = path
        self.fh = None

    def acquire(self, wait=True) -> bool:
        try:
            import fcntl
        except ImportError:         # not on this system: no lock (numba's cache as before)
            return True
        os.makedirs(os.path.dirname(self.path), exist_ok=True)
        self.fh = open(self.path, "a+")      # noqa: SIM115 - held until release()
        try:
            fcntl.flock(self.fh, fcntl.LOCK_EX | (0 if wait else fcntl.LOCK_NB))
        except BlockingIOError:
            self.fh.close()
            self.fh = None
            return False
        return True

    def release(self):
        if self.fh is not None:
            self.fh.close()       # closing drops the lock
            self.fh = None


class Tiers:
    """The module a Mechanism calls now (``module``, read on every call) and how it may
    change: shared by a Mechanism and its with_params copies."""

    def __init__(self, module, tier, path=None, clock=None):
        self.module = module
        self.tier = tier              # "python" or "compiled": what answers now
        self.mode = tier              # "auto", "python" or "compiled": what was asked
        self.path = path
        self.python = module if tier == "python" else None
        self.clock = clock
        self.worker = None            # our warmup process, when we started one
        self.mixed = False            # answering with a mixed module (loading.mixed)
        self._next_look = SWITCH_AFTER
        self._rate = POINT_COST * max(1, int(getattr(module, "N_COORDS", 1)))

    # -- opening -------------------------------------------------------------------------
    @classmethod
    def of(cls, module) -> "Tiers":
        """The tiers of a module object: compiled, or plain Python (plain.python_module)."""
        if isinstance(module, Tiers):
            return module
        tier = getattr(module, "__mechgen_tier__", "compiled")
        return cls(module, tier)

    @classmethod
    def open(cls, path_or_module, tier=None) -> "Tiers":
        """The tiers of a generated module (a path, or an imported module: compiled)."""
        tier = tier_choice(tier)
        if not isinstance(path_or_module, (str, os.PathLike)) or tier == "compiled":
            return cls(open_module(path_or_module), "compiled")
        path = os.path.abspath(os.fspath(path_or_module))
        clock = Clock()
        try:
            module = python_module(path, clock)
        except NoPlainTier:
            if tier == "python":
                raise
            return cls(open_module(path), "compiled")     # an older module: numba only
        check_version(module)
        tiers = cls(module, "python", path, clock)
        if tier == "auto":
            tiers.mode = "auto"
            clock.after = tiers._look
            if not cache_ready(path):
                tiers.start_worker()
        return tiers

    # -- the background compile ----------------------------------------------------------
    def start_worker(self):
        """Start ``python -m mechgen.runtime.loading.warmup PATH``, detached (it outlives us)."""
        import subprocess
        here = os.path.abspath(__file__)                 # mechgen/runtime/loading/tiers.py
        root = os.path.dirname(os.path.dirname(os.path.dirname(os.path.dirname(here))))
        env = dict(os.environ)
        env["PYTHONPATH"] = os.pathsep.join(x for x in (root, env.get("PYTHONPATH")) if x)
        log = os.path.splitext(state_paths(self.path)[1])[0] + ".log"
        try:
            os.makedirs(os.path.dirname(log), exist_ok=True)
            with open(log, "ab") as err:
                self.worker = subprocess.Popen(
                    [sys.executable, "-m", "mechgen.runtime.loading.warmup", self.path], env=env,
                    stdin=subprocess.DEVNULL, stdout=subprocess.DEVNULL, stderr=err,
                    start_new_session=True, close_fds=True)
            _STARTED.append(self.worker)    # kept: no "still running" warning when dropped
        except OSError:
            self.worker = None      # no worker: a large call compiles in this process

    def stop_worker(self):
        """Stop our worker (numba writes each cache file whole, by a rename)."""
        if self.worker is not None and self.worker.poll() is None:
            self.worker.terminate()
            try:
                self.worker.wait(5)
            except Exception:       # noqa: BLE001 - it did not stop: make it
                self.worker.kill()
                self.worker.wait()
        self.worker = None

    # -- switching -------------------------------------------------------------------------
    def _look(self):
        """After each plain-Python call: once they have cost SWITCH_AFTER seconds, switch
        to the compiled tier as soon as its cache is ready (checked every 50 ms of calls)."""
        clock = self.clock
        if clock.spent < self._next_look or not (self.tier == "python" or self.mixed):
            return
        self._next_look = clock.spent + 0.05
        if self.worker is not None and self.worker.poll() is not None:
            self.worker = None
        if cache_ready(self.path):
            self._switch_or_stay()

    def _switch_or_stay(self, mix=None):
        """switch(), or with ``mix`` (mech, kind) mix(); where numba cannot load the
        module (not installed, broken), stay in the python tier for good."""
        try:
            if mix is None:
                self.switch()
            else:
                self.mix(*mix)
        except MechgenError:
            self.clock.after = None     # (tried no more: the tier answering stays)
            if self.tier == "python":
                self.mode = "python"

    def switch(self):
        """Load the compiled module and answer with it from now on."""
        module = import_path(self.path)
        check_version(module)
        for key, value in vars(self.module).items():     # the runtime's own marks
            if key.startswith("_mechgen_") and not key.startswith("__"):
                setattr(module, key, value)
        self.clock.after = None
        self.module, self.tier, self.mixed = module, "compiled", False

    def mix(self, mech, kind):
        """Answer with the mixed module (loading.mixed: the compiled loops, the rest in
        Python) from now on, its loops that a ``kind`` call needs compiled here first;
        the whole compiled module once the worker's cache is ready (_look)."""
        module = import_path(self.path)
        check_version(module)
        mixed = mixed_module(self.module, module)
        self._compile_here(mech, kind, mixed)
        self.module, self.tier, self.mixed = mixed, "compiled", True

    def expect(self, mech, points, kind="sweep"):
        """Before ``mech``'s call of about ``points`` solves (a sweep, a design table): in the
        python tier of "auto", switch to the compiled tier first when the call would cost
        more than BIG_CALL seconds in Python, compiling here what it needs if the cache is
        not ready (see the module docstring)."""
        if self.tier != "python" or self.mode != "auto":
            return
        if points * self._rate < BIG_CALL:
            return
        if cache_ready(self.path):
            self._switch_or_stay()
            return
        self.stop_worker()
        self._switch_or_stay(mix=(mech, kind))
        if self.tier == "compiled" and not cache_ready(self.path):
            # the entry points this call did not need, compiled in the background again:
            # numba looks in its cache before compiling, so this process's later first
            # calls load them from there once the worker has written them
            self.start_worker()

    def _compile_here(self, mech, kind, module):
        """Compile in this process what a ``kind`` call needs on ``module`` (a mixed one:
        its loops; numba loads from its cache what is there already). The module's lock
        is taken when it is free, never waited for: a worker of another process may be
        compiling the whole module, and this call needs a few of its functions (numba
        writes each cache file whole, by a rename, so that two processes compiling one
        function at once both leave a good one)."""
        lock = Lock(state_paths(self.path)[1])
        held = lock.acquire(wait=False)
        try:
            if not cache_ready(self.path):
                from .warm import STAGES_FOR, warm
                warm(type(mech)(module), STAGES_FOR[kind])
        finally:
            if held:
                lock.release()


def dump_mark(path: str, stages) -> None:
    """Write the mark that says numba's cache of ``path`` is complete (atomically)."""
    mark = state_paths(path)[0]
    tmp = f"{mark}.{os.getpid()}.tmp"
    with open(tmp, "w", encoding="utf-8") as fh:
        json.dump({"module": os.path.abspath(path), "stages": list(stages),
                   "python": sys.version, "mechgen": MECHGEN_VERSION,
                   "numba": numba_version()}, fh)
    os.replace(tmp, mark)
