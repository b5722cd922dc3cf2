"""What a generated module and the runtime agree on, stated once.

The compiler writes these values into every generated module (its header constants); the
runtime reads them from here to interpret what the module returns. Neither side imports
the other: both import this file, which imports nothing of mechgen and nothing heavy.
"""
from __future__ import annotations

import hashlib
import re

MECHGEN_VERSION = "0.1.0"
FORMAT_VERSION = 1          # the layout of a generated module that this runtime reads

# Derivative levels, in order; a module is built up to one of them.
LEVELS = ("position", "velocity", "acceleration")
LEVEL = {name: k for k, name in enumerate(LEVELS)}

# Solving methods (the ``method`` argument of the generated solvers).
METHODS = ("auto", "sorted", "full")
METHOD = {name: k for k, name in enumerate(METHODS)}
AUTO, SORTED, FULL = 0, 1, 2

# Status codes returned by the generated solvers (position solve; a velocity failure is
# VELOCITY + its status, an acceleration failure ACCELERATION + its status).
OK = 0
NO_CONVERGENCE = 1          # Newton used up its iterations
SINGULAR = 2                # Φ_q lost rank: velocities/accelerations not determined
NOT_FINITE = 3              # a non-finite value appeared
GAVE_UP = 4                 # the sorted solver gave up (the full Newton takes over)
JUMP = 5                    # sweep: reached by a jump the step control could not avoid
THROUGH_SINGULAR = 6        # sweep: reached at or through a singular configuration
VELOCITY = 10               # status offset of a failed velocity solve
ACCELERATION = 20           # status offset of a failed acceleration solve

STATUS_NAMES = {OK: "ok", NO_CONVERGENCE: "no convergence", SINGULAR: "singular",
                NOT_FINITE: "not finite", GAVE_UP: "sorted solver gave up",
                JUMP: "branch jump", THROUGH_SINGULAR: "through a singular configuration"}

# Columns of a sweep's info array (INFO[k, column]).
INFO_ITERATIONS = 0         # Newton iterations of the point
INFO_RESIDUAL = 1           # max |Φ| reached
INFO_RANK = 2               # numeric rank of Φ_q
INFO_METHOD = 3             # 0 sorted, 1 full Newton
INFO_STATUS = 4             # one of the status codes above
INFO_SUBSTEPS = 5           # substeps taken (on failure: the time last reached)
INFO_JUMP = 6               # size of a jump (on failure: the time that failed)
INFO_COLUMNS = 7
# solve_point's info vector: [iterations, residual, rank, method, max|Φ|, pivot ratio]
POINT_RESIDUAL = 4
POINT_PIVOT = 5
POINT_INFO_SIZE = 6

# Numerical thresholds shared by the generated solvers and the runtime's diagnostics.
PIVOT_RTOL = 1e-10          # a pivot below this fraction of its row's size counts as zero
SING_RTOL = 1e-6            # velocity/acceleration: a pivot below this fraction of its
                            # row's size marks a singular configuration (SingularError)
TINY = 1e-300

_STAMP = re.compile(r"^# content-sha256: ([0-9a-f]{64})\n", re.M)
STAMP = "# content-sha256: {digest}\n"


def content_digest(text: str) -> str:
    """The digest stamped in a module's header: of every line but the stamp itself."""
    body = _STAMP.sub("", text, count=1)
    return hashlib.sha256(body.encode("utf-8")).hexdigest()


def stamp_of(text: str):
    """The digest a module's header states, or None when it has no stamp."""
    found = _STAMP.search(text)
    return found.group(1) if found else None
