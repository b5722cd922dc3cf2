"""The runtime: a generated module to numbers (numpy, numba, scipy). Never imports sympy,
the model language or the compiler."""
from .mechanism import Mechanism, load

__all__ = ["Mechanism", "load"]
