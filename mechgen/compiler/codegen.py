"""The former entry point, kept until the render path calls module_context directly."""
from __future__ import annotations

from .context import module_context
from .printer import pycode


class ModuleBuilder:
    """``ModuleBuilder(model, **options).context()`` is ``module_context(model, **options)``."""

    def __init__(self, model, **options):
        self.model, self.options = model, options

    def context(self) -> dict:
        return module_context(self.model, **self.options)


__all__ = ["ModuleBuilder", "module_context", "pycode"]
