"""The compiler: a model to the text of a generated module (equations, checks, block
structure, solver plan, printer, render). Imports the model language; never the runtime."""
from .build import build, render, write_module

__all__ = ["build", "render", "write_module"]
