"""mechgen: a symbolic code-generation compiler for the kinematics of planar mechanisms.

Describe a mechanism with :class:`Model`; ``mechgen build`` expands Φ, Φ_q, ν and γ
symbolically and writes a numba-compiled solver module; :func:`load` runs it.

The modelling names (``Model``, ``T``, ``sin``, the output functions) import sympy when
first used; ``import mechgen`` and the runtime (``load``, ``Mechanism``) do not.
"""
import os as _os

# sympy's expression cache: its default size (1000 entries) thrashes on a model of a few
# dozen bodies, and a larger one builds a 50-loop chain a quarter faster. Read when sympy
# is imported, so it applies where sympy is not imported yet and the user has not set it.
_os.environ.setdefault("SYMPY_CACHE_SIZE", "100000")

from .errors import (BranchJumpWarning, ConvergenceError, MechgenError, ModelError,
                     ModelWarning, RedundancyWarning, SingularError, SolveError)

from .protocol import MECHGEN_VERSION as __version__
from . import extensions as _extensions


def _explore(mech, **options):
    """Mechanism.explore's way up to the live view (mechgen.extensions): imported on use."""
    from .view import explore
    return explore(mech, **options)


_extensions.EXPLORE = _explore

_SYMPY_NAMES = ("sin", "cos", "tan", "sqrt", "atan2", "atan", "asin", "acos", "exp", "log",
                "pi", "E", "I", "Abs", "sign", "sinh", "cosh", "tanh", "Rational", "Piecewise",
                "Symbol", "Matrix")
_QUANTITIES = ("location", "distance", "point_to_line_distance", "angle", "rotation",
               "intersection", "project_on_line", "direction", "magnitude", "unit", "cross",
               "rotation_matrix", "point_to_local", "polar_to_xy", "xy_to_polar", "velocity",
               "acceleration", "dt")
_LAZY = {"Model": "model.language", "T": "model.geometry", "Line": "model.geometry",
         "load_model": "model.loader", "Mechanism": "runtime.mechanism",
         "Solution": "runtime.results", "Sweep": "runtime.results",
         "DesignTable": "runtime.tables.design", "Reduction": "runtime.tables.reduce",
         "OptimizeResult": "runtime.tables.synthesis", "Equations": "model.symbolic"}
# mechgen.synthesis: dimensional synthesis (docs/reference/synthesis.md)
_SUBPACKAGES = ("synthesis",)


def __getattr__(name):
    import importlib
    if name in _SYMPY_NAMES:
        import sympy
        value = getattr(sympy, name)
    elif name in _QUANTITIES:
        value = getattr(importlib.import_module(".model.quantities", __name__), name)
    elif name in _LAZY:
        value = getattr(importlib.import_module("." + _LAZY[name], __name__), name)
    elif name in _SUBPACKAGES:
        value = importlib.import_module("." + name, __name__)
    else:
        raise AttributeError(f"module 'mechgen' has no attribute {name!r}")
    globals()[name] = value
    return value


def __dir__():
    return sorted(set(globals()) | set(_SYMPY_NAMES) | set(_QUANTITIES) | set(_LAZY)
                  | set(_SUBPACKAGES))


def load(path_or_module, **kwargs):
    """Load a generated module as a :class:`Mechanism`.

    Parameters
    ----------
    path_or_module : str or module
        The module's file (``generated/quick_return.py``) or the module, imported.
    **kwargs
        ``tier="auto"`` (default, or $MECHGEN_TIER) answers at once in plain Python while a
        background process compiles; "python" or "compiled" force one (``mech.tier``).
        ``tol``, ``xtol``, ``maxit`` and ``method`` set the Newton solver's defaults.

    Returns
    -------
    Mechanism
        Ready to solve, sweep and draw.
    """
    from .runtime.mechanism import load as _load
    return _load(path_or_module, **kwargs)


def compile(model, **kwargs):  # noqa: A001 - the API name
    """Build a model into a module and load it, keeping the symbolic side.

    The module, ``<model name>.py``, is written into ``$MECHGEN_CACHE`` when that is set,
    else ``~/.cache/mechgen``; a module whose text has not changed is not rewritten, so
    numba's compiled cache beside it stays valid.

    Parameters
    ----------
    model : Model or str
        A Model, or a model file's path (loaded without sympy when its module is up to
        date).
    **kwargs
        ``outdir=`` another folder for the module; ``name=`` the model of a file holding
        several; ``tier=`` as for :func:`load`; ``sensitivities=True`` builds the
        sensitivity module now; the build's options (``level=``, ...).

    Returns
    -------
    Mechanism
        The loaded mechanism, whose ``evaluate(expr, s)`` evaluates any symbolic quantity
        on a solution or a sweep.
    """
    from .bridge import compile_model
    return compile_model(model, **kwargs)


__all__ = ["ModelError", "ConvergenceError", "SingularError", "MechgenError", "SolveError",
           "BranchJumpWarning", "RedundancyWarning", "ModelWarning", "load", "compile",
           "__version__",
           *_SYMPY_NAMES, *_QUANTITIES, *_LAZY]
