"""The runtime: a generated module to numbers (numpy, numba, scipy). Never imports sympy,
the model language, the compiler or the bridge.

A folder per concept (their __init__ says what each module holds):
  guards      checks of user arguments, before any jitted call
  quantity    what a name means (coordinate, derivative, output) and a quantity's level
  results     Solution, Sweep, CSV and pandas export
  analysis/   interpolants, extremes and roots, closed cycles, rank and locks, assembly modes
  loading/    a module file, its caches, the plain-Python and compiled tiers, the warm-up
  sweeping    a sweep's arrays and the module's compiled loops
  stages      models whose constraints change at given times
  entry       the module's solve entry points called from Python
  follow      solve(t) without a guess: the careful continuation kept along the way
  tables/     design tables, their backends (threads, dask), reductions, synthesis
  gpu/        design tables on an NVIDIA GPU (numba.cuda, imported only when asked for)
  forces/     statics and inverse dynamics, force tables, forward dynamics
  mechanism   Mechanism and load(): the one class users hold
"""
from .mechanism import Mechanism, load

__all__ = ["Mechanism", "load"]
