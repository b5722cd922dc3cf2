"""The compiler: a model to the text of a generated module (equations, checks, block
structure, solver plan, printer, render). Imports the model language; never the runtime.

``build``, ``render`` and ``write_module`` (mechgen.compiler.build) are imported when first
used: an up-to-date module is found without loading the renderer (jinja2, the emitters)."""

__all__ = ["build", "render", "write_module"]


def __getattr__(name):
    if name in __all__:
        from .build import build, render, write_module
        return {"build": build, "render": render, "write_module": write_module}[name]
    raise AttributeError(f"module 'mechgen.compiler' has no attribute {name!r}")
