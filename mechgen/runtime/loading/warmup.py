"""``python -m mechgen.runtime.loading.warmup PATH [STAGE ...]``: the background worker of the
``auto`` tier (mechgen.runtime.loading.tiers). Imports the generated module at PATH with numba,
calls its entry points once each (mechgen.runtime.loading.warm, all stages unless named), so
that numba's on-disk cache holds them, then leaves the mark that says the cache is
ready (a stage not in it is compiled where it is first called, as without the worker).
Runs at the lowest priority on one core (yield_machine); exits at once when another
process holds the module's lock (it is doing the same) or the mark is already there. A
process that needs some functions now never waits for it (tiers.Tiers._compile_here).
"""
from __future__ import annotations

import os
import sys

from .loader import check_version, import_path
from ..mechanism import Mechanism
from .tiers import Lock, cache_ready, dump_mark, state_paths
from .warm import STAGES, warm


def yield_machine() -> None:
    """Leave the machine to the user's work: the lowest priority (nice 19) and one core at
    most (the last this process may run on), where the system allows."""
    try:
        os.nice(19 - os.nice(0))
    except (AttributeError, OSError):
        pass
    try:
        cores = sorted(os.sched_getaffinity(0))
        if len(cores) > 1:
            os.sched_setaffinity(0, {cores[-1]})
    except (AttributeError, OSError):
        pass


def main(argv=None) -> int:
    """Warm the cache of one module; 0 when the mark is there at the end."""
    args = list(sys.argv[1:] if argv is None else argv)
    if not args:
        print(__doc__, file=sys.stderr)
        return 2
    path, stages = os.path.abspath(args[0]), tuple(args[1:]) or STAGES
    yield_machine()
    lock = Lock(state_paths(path)[1])
    if not lock.acquire(wait=False):
        return 0
    try:
        if cache_ready(path):
            return 0
        module = import_path(path)
        check_version(module)
        done = warm(Mechanism(module), stages)
        if tuple(done) == stages:
            dump_mark(path, stages)
    finally:
        lock.release()
    return 0


if __name__ == "__main__":
    sys.exit(main())
