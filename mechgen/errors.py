"""The exceptions users see. Each names the culprit; none carries a half-result."""
from __future__ import annotations

import os
import traceback

_PKG_DIR = os.path.dirname(os.path.abspath(__file__))


def user_frame():
    """The innermost stack frame outside the mechgen package: the user's line."""
    for frame in reversed(traceback.extract_stack()[:-2]):
        path = os.path.abspath(frame.filename)
        if not path.startswith(_PKG_DIR + os.sep) and "importlib" not in path \
                and not frame.filename.startswith("<frozen"):
            return frame
    return None


class MechgenError(Exception):
    """Base class of every mechgen error."""


class ModelError(MechgenError, ValueError):
    """A model that cannot be built. The message says what and, where it can, where.

    ``where`` holds ``"file:line"`` of the model-file line that caused it (or None).
    """

    def __init__(self, message: str, where: str | None = None):
        if where is None:
            frame = user_frame()
            if frame is not None and frame.filename and not frame.filename.startswith("<"):
                where = f"{frame.filename}:{frame.lineno}"
        self.where = where
        self.message = message
        super().__init__(f"{where}: {message}" if where else message)


class SolveError(MechgenError, RuntimeError):
    """A solve that did not produce a trustworthy answer."""


class ConvergenceError(SolveError):
    """Newton's method found no configuration: says the time, iterations and residual."""

    def __init__(self, message: str, t: float = float("nan"), iterations: int = 0,
                 residual: float = float("nan"), constraints: tuple = ()):
        self.t = t
        self.iterations = iterations
        self.residual = residual
        self.constraints = tuple(constraints)
        super().__init__(message)


class SingularError(SolveError):
    """A singular (toggle, lock, dead-centre) configuration: says the time and the
    constraints that lose rank."""

    def __init__(self, message: str, t: float = float("nan"), constraints: tuple = (),
                 level: str = "position", q=None):
        self.t = t
        self.constraints = tuple(constraints)
        self.level = level
        self.q = q
        super().__init__(message)


class BranchJumpWarning(UserWarning):
    """A sweep could not avoid leaving the assembly mode it started in."""


class RedundancyWarning(UserWarning):
    """The model holds redundant (but consistent) constraints."""


class ModelWarning(UserWarning):
    """A model that builds but says something other than its author likely meant (gravity
    on bodies without mass: it exerts no force)."""


__all__ = ["MechgenError", "ModelError", "SolveError", "ConvergenceError", "SingularError",
           "BranchJumpWarning", "RedundancyWarning", "ModelWarning"]
