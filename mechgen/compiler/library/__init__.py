"""The numeric library of every generated module, kept as real Python files.

linalg.py (elimination, rank-revealing solve, determinant), solve.py (Newton, velocity and
acceleration solves, the solve entry points), continuation.py (the sweep, evaluation
along a sweep), designs.py (each design's start: the guess carried to its parameters; a
sweep per design) and, for a model with mass or loads, forces.py (the
multipliers block by block, forward dynamics and its integrator, the loops over points
and designs) and force_designs.py (the tables that solve the multipliers in their own
sweeps) each have a head that imports what the code needs to
run on its own, the marker line MARKER, and the body below it: the renderer copies the
bodies verbatim into every generated module (library_text), after the module's own
constants and model functions, so that a generated module runs where mechgen is not
installed. toy.py is a small hand-written model that stands for those when the library is
imported by itself (tests, lint).

A body imports nothing and names nothing of mechgen: it uses math, np and njit, which a
generated module's header imports, and the names toy.__all__ lists, which a generated
module defines.
"""
from __future__ import annotations

import os

MARKER = "# -- module body: below this line, the text as a generated module holds it --"
# their order in a generated module
FILES = ("linalg.py", "solve.py", "continuation.py", "designs.py")
FORCE_FILES = ("forces.py", "force_designs.py")    # after those, with mass or loads

_HERE = os.path.dirname(os.path.abspath(__file__))


def source(name: str) -> str:
    """The text of the library file ``name`` (one of FILES, or toy.py)."""
    with open(os.path.join(_HERE, name), encoding="utf-8") as fh:
        return fh.read()


def body(name: str) -> str:
    """The part of library file ``name`` below its marker line, without the blank lines
    around it."""
    text = source(name)
    head, sep, rest = text.partition(MARKER + "\n")
    if not sep:
        raise ValueError(f"{name} has no marker line {MARKER!r}")
    return rest.strip("\n") + "\n"


def library_text(forces=False) -> str:
    """The library as every generated module holds it: the bodies of FILES in order,
    two blank lines between them; with ``forces`` (a model with mass or loads) then those
    of FORCE_FILES."""
    return "\n\n".join(body(name) for name in FILES + (FORCE_FILES if forces else ()))
