"""The compiler: a model to the text of a generated module (equations, checks, block
structure, solver plan, statement IR, printer, render). Imports the model language; never
the runtime. (``mechgen.compiler.build`` is the module of that name: build(), render().)"""
from .build import render, write_module
from .context import module_context

__all__ = ["render", "write_module", "module_context"]
