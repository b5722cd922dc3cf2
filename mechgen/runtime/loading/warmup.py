"""``python -m mechgen.runtime.loading.warmup PATH [STAGE ...]``: the background worker of the
``auto`` tier (mechgen.runtime.loading.tiers). Imports the generated module at PATH with numba,
calls its entry points once each (mechgen.runtime.loading.warm, all stages unless named), so
that numba's on-disk cache holds them, then leaves the mark that says the cache is
ready (a stage not in it is compiled where it is first called, as without the worker). Runs at a lowered priority; exits at once when another process holds the
module's lock (it is doing the same) or the mark is already there.
"""
from __future__ import annotations

import os
import sys

from .loader import check_version, import_path
from ..mechanism import Mechanism
from .tiers import Lock, cache_ready, dump_mark, state_paths
from .warm import STAGES, warm


def main(argv=None) -> int:
    """Warm the cache of one module; 0 when the mark is there at the end."""
    args = list(sys.argv[1:] if argv is None else argv)
    if not args:
        print(__doc__, file=sys.stderr)
        return 2
    path, stages = os.path.abspath(args[0]), tuple(args[1:]) or STAGES
    try:
        os.nice(10)
    except (AttributeError, OSError):
        pass
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
