"""The runtime: a generated module to numbers (numpy, numba, scipy). Never imports sympy,
the model language, the compiler or the bridge.

Modules, lowest first (each imports only those above it):
  guards      checks of user arguments, before any jitted call
  quantity    what a name means (coordinate, derivative, output) and a quantity's level
  interpolate interpolants of a sweep (Hermite, spline, Mathematica's Lagrange)
  cycle       whether a sweep covers exactly one period (a closed cycle)
  events      exact extremes and roots along a sweep (its ends included)
  results     Solution, Sweep, CSV and pandas export
  singular    rank analysis of Φ_q, solving helpers that never raise
  locks       lock positions and crossings along a branch; why a solve failed
  assembly    assembly modes at one time, angle coordinates
  reduce      per-design minimum, maximum and their times; a design's status
  refine      exact per-design extremes of a design table (Newton on solves)
  chunks      a chunk of designs through the compiled loop; gathering chunks
  dask_backend  chunks of designs over a dask.distributed cluster (dask imported lazily)
  backends    where a design table runs: threads, dask, cuda
  design      design tables (sweeps over a grid of parameter values, or listed designs)
  synthesis   mech.optimize: differential evolution over design tables
  caches      where a module's caches live; numba's checked before it loads them
  loader      a module file, its stamp, format and version checked
  plain       the module run as plain Python (no numba): the tier that answers at once
  warm        a compiled module's entry points called once each (numba compiles, caches)
  tiers       which tier answers (auto, python, compiled), the background compile, the switch
  mechanism   Mechanism and load(): the one class users hold
  warmup      ``python -m mechgen.runtime.warmup PATH``: the background worker
"""
from .mechanism import Mechanism, load

__all__ = ["Mechanism", "load"]
