"""From the command line's arguments to models and loaded mechanisms.

The model, compiler and runtime layers are imported when a command first needs them, not
with the parser: ``mechgen --help`` and usage errors then answer without loading sympy,
jinja2 or numba (the same reason plot_commands imports matplotlib late).
"""
from __future__ import annotations

import os

from .options import model_file, module_folder


def models(args):
    """The models the arguments name: every model of the file (build), or the one
    --model picks."""
    from ..model.loader import load_models, pick_model
    found = load_models(model_file(args.model_file))
    if getattr(args, "all_models", False):
        return found
    return [pick_model(found, args.model, args.model_file)]


def build_if_needed(model, outdir, **kwargs) -> str:
    """Write the module unless the file already holds exactly this text."""
    from ..compiler.build import render, write_module
    path = os.path.join(module_folder(outdir), f"{model.name}.py")
    text = render(model, **kwargs)
    try:
        with open(path, encoding="utf-8") as fh:
            if fh.read() == text:
                return path
    except OSError:
        pass
    return write_module(text, path)


def mechanism(args):
    """Build (when out of date) and load the model the arguments name."""
    from ..runtime import load
    return load(build_if_needed(models(args)[0], args.outdir))
