"""The compiler: a model to the text of a generated module (equations, checks, block
structure, solver plan, statement IR, printer, render). Imports the model language; never
the runtime."""
from .build import build, render, write_module
from .context import module_context

__all__ = ["build", "render", "write_module", "module_context"]
