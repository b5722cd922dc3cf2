"""What a generated module and the runtime agree on, stated once.

The compiler writes these values into every generated module (its header constants); the
runtime reads them from here to interpret what the module returns. Neither side imports
the other: both import this file, which imports nothing of mechgen and nothing heavy.
"""
from __future__ import annotations

import hashlib
import re

MECHGEN_VERSION = "0.1.0"
# the file of a module's sensitivity companion: <name>_sensitivities.py beside <name>.py
SENSITIVITY_SUFFIX = "_sensitivities"
SENSITIVITY_FORMAT = 2      # its layout, which the runtime reads (a stale one is rebuilt)
FORMAT_VERSION = 4          # the layout of a generated module that this runtime reads (4:
                            # a design table's sweeps start per design, start_designs)

# Derivative levels, in order; a module is built up to one of them.
LEVELS = ("position", "velocity", "acceleration")
LEVEL = {name: k for k, name in enumerate(LEVELS)}

# The force levels (a solve or sweep with the multipliers: level="static" or "dynamic") and
# each one's fused quick path, the sweep that solves the multipliers on its way
# (compiler/functions/dynamics_code.py): the module's flag that says it is written (else a
# stub), the kinematic level (LEVEL) its sweep runs at, its name.
FORCE_LEVELS = ("static", "dynamic")
FUSED_PATHS = {"static": ("STATIC_FUSED", 0, "sweep_fast_statics"),
               "dynamic": ("FORCE_FUSED", 2, "sweep_fast_forces")}


def fused_path(module, level, lev):
    """The quick path of ``module`` that solves force level ``level``'s multipliers on its
    way in a sweep at kinematic level ``lev`` (FUSED_PATHS), or None."""
    flag, need, name = FUSED_PATHS[level]
    return getattr(module, name) if lev == need and getattr(module, flag, False) else None


# Solving methods (the ``method`` argument of the generated solvers).
METHODS = ("auto", "sorted", "full")
METHOD = {name: k for k, name in enumerate(METHODS)}
METHOD_AUTO, METHOD_SORTED, METHOD_FULL = 0, 1, 2

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

# The solvers' info vector (solve_position: the first four; solve_point: all seven).
INFO_ITERATIONS = 0         # Newton iterations of the point
INFO_RESIDUAL = 1           # max |Φ| reached
INFO_RANK = 2               # numeric rank of Φ_q
INFO_METHOD = 3             # 0 sorted, 1 full Newton
POSITION_INFO_SIZE = 4
POINT_RESIDUAL = 4          # solve_point: max |Φ| of the solution
POINT_PIVOT = 5             # solve_point: its pivot ratio
INFO_REACH = 6              # position_sorted, where info is this long: the smallest reach
                            # margin of its blocks solved whatever the guess (reach())
POINT_INFO_SIZE = 7

# A sweep's per-point record: STATUS[k, column], a small integer array (int16) of one to
# three columns, written for every point the sweep accepts (and the one where it stops);
# a sweep writes the columns its STATUS has.
STATUS_CODE = 0             # one of the status codes above (OK, JUMP, THROUGH_SINGULAR)
STATUS_ITERATIONS = 1       # Newton iterations of the point (capped at STATUS_MAX)
STATUS_SUBSTEPS = 2         # substeps taken on the way to it (capped at STATUS_MAX)
STATUS_COLUMNS = 3
STATUS_MAX = 32767
# A sweep's report (one float vector a sweep): the info vector of the point where it
# stopped (the first four entries, as INFO_* above), then
REPORT_STATUS = 4           # the status it stopped with (OK when it did not)
REPORT_REACHED = 5          # the time of the last configuration reached on the way
REPORT_FAILED = 6           # the time whose solve failed
REPORT_JUMP = 7             # the size of the first branch jump (0.0: none)
REPORT_SIZE = 8
# The wide INFO rows of format 2 (seven floats a point), kept for readers of old results:
# Sweep.info builds them from STATUS and the report.
INFO_STATUS = 4
INFO_SUBSTEPS = 5
INFO_JUMP = 6
INFO_COLUMNS = 7

# Numerical thresholds shared by the generated solvers and the runtime's diagnostics.
PIVOT_RTOL = 1e-10          # a pivot below this fraction of its row's size counts as zero
SING_RTOL = 1e-6            # velocity/acceleration: a pivot below this fraction of its
                            # row's size marks a singular configuration (SingularError)
TINY = 1e-300

# Step control of the continuation sweep (the generated sweep() and sweep_fast()).
BRANCH_RATIO = 0.5          # a correction larger than this times the step taken ...
BRANCH_ATOL = 1e-6          # ... plus this (relative to the size of q) halves the step
BRANCH_HMIN = 2.0 ** -20    # smallest substep, as a fraction of the sweep's own step
BRANCH_TURN = 0.5           # largest turn of an angle (radians) in one step of a sweep
BRANCH_NEAR = 1e-4          # a pivot ratio below this: near a singular configuration
CARRY_HMIN = 2.0 ** -16     # smallest step of carry_params (a design's start carried in
                            # its parameters), as a fraction of the way, and the most
CARRY_MAXIT = 12            # Newton iterations of a step (its prediction is close)
BRANCH_DET_EVERY = 16       # a position sweep's quick path evaluates det Φ_q at least
                            # every this many points (sweep_fast; its CUDA twin: 1)

# The constants above that every generated module states in its header, in groups
# (a comment line, then the names): its solvers use them by name.
HEADER_CONSTANTS = (
    ("Methods: sorted blocks with the full Newton as fallback, sorted only, full only",
     ("METHOD_AUTO", "METHOD_SORTED", "METHOD_FULL")),
    ("Status codes of the solvers; VELOCITY or ACCELERATION + a status: that solve failed",
     ("OK", "NO_CONVERGENCE", "SINGULAR", "NOT_FINITE", "GAVE_UP", "JUMP", "THROUGH_SINGULAR",
      "VELOCITY", "ACCELERATION")),
    ("The solvers' info vectors; a sweep's STATUS columns and report entries",
     ("INFO_ITERATIONS", "INFO_RESIDUAL", "INFO_RANK", "INFO_METHOD", "POSITION_INFO_SIZE",
      "POINT_RESIDUAL", "POINT_PIVOT", "INFO_REACH", "POINT_INFO_SIZE", "STATUS_CODE", "STATUS_ITERATIONS",
      "STATUS_SUBSTEPS", "STATUS_COLUMNS", "STATUS_MAX", "REPORT_STATUS", "REPORT_REACHED", "REPORT_FAILED",
      "REPORT_JUMP", "REPORT_SIZE")),
    ("Pivot thresholds (rows of Φ_q scaled to 1) and the smallest size counted as non-zero",
     ("PIVOT_RTOL", "SING_RTOL", "TINY")),
    ("Step control of sweep(), sweep_fast() and carry_params()",
     ("BRANCH_RATIO", "BRANCH_ATOL", "BRANCH_HMIN", "BRANCH_TURN", "BRANCH_NEAR",
      "BRANCH_DET_EVERY", "CARRY_HMIN", "CARRY_MAXIT")),
)


def header_constants():
    """HEADER_CONSTANTS with their values written as Python: [(comment, [(name, text)])].
    repr() of a float reads back as the same float, so the module computes with exactly
    the values stated here."""
    values = globals()
    return [(comment, [(name, repr(values[name])) for name in names])
            for comment, names in HEADER_CONSTANTS]


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
