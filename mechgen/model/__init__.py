"""The model language: bodies, points, constraints, drivers and outputs as sympy objects.

Imports sympy; never the compiler's code generation, the runtime or the pictures."""
from .geometry import T, Body, Line, Point
from .language import Model
from .loader import load_model, load_models, pick_model

__all__ = ["Model", "T", "Body", "Line", "Point", "load_model", "load_models", "pick_model"]
