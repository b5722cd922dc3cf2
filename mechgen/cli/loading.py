"""From the command line's arguments to models and loaded mechanisms.

The model, compiler and runtime layers are imported when a command first needs them, not
with the parser: ``mechgen --help`` and usage errors then answer without loading sympy,
jinja2 or numba (the same reason plot_commands imports matplotlib late).
"""
from __future__ import annotations

from .options import model_file, module_folder


def models(args):
    """The models the arguments name: every model of the file (build, unless --model
    names one), or the one --model picks."""
    from ..model.loader import load_models, pick_model
    found = load_models(model_file(args.model_file))
    if getattr(args, "all_models", False) and not args.model:
        return found
    return [pick_model(found, args.model, args.model_file)]


def build_if_needed(model, outdir, **kwargs) -> str:
    """Write the module unless the file already holds exactly this text (as
    mechgen.compile does)."""
    from ..bridge import build_if_changed
    return build_if_changed(model, module_folder(outdir), **kwargs)


def mechanism(args):
    """Build (when out of date) and load the model the arguments name: a model file whose
    module is up to date loads without sympy (mechgen.bridge.compile_file)."""
    from ..bridge import compile_file
    return compile_file(model_file(args.model_file), module_folder(args.outdir),
                        name=args.model)
