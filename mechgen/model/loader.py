"""Reading model files: run the file, collect the Models it defines at module level."""
from __future__ import annotations

import os
import runpy
import traceback

from ..errors import MechgenError, ModelError
from .language import Model


def load_models(path: str) -> list[Model]:
    """Every ``Model`` defined at module level of the file, in definition order."""
    path = os.path.abspath(path)
    if not os.path.isfile(path):
        raise ModelError("the model file does not exist", where=path)  # path named once
    try:
        namespace = runpy.run_path(path, run_name="__mechgen_model__")
    except MechgenError:
        raise
    except SyntaxError as exc:
        raise ModelError(f"syntax error: {exc.msg}", where=f"{exc.filename}:{exc.lineno}") from None
    except BaseException as exc:  # a model file that raises: name its line
        if isinstance(exc, (KeyboardInterrupt, SystemExit)):
            raise
        where = path
        for frame in reversed(traceback.extract_tb(exc.__traceback__)):
            if os.path.abspath(frame.filename) == path:
                where = f"{path}:{frame.lineno}"
                break
        raise ModelError(f"the model file raised {type(exc).__name__}: {exc}", where=where) from None
    models, seen = [], set()
    for value in namespace.values():
        if isinstance(value, Model) and id(value) not in seen:
            seen.add(id(value))
            models.append(value)
    if not models:
        raise ModelError("the file defines no mechgen.Model at module level", where=path)
    doc = namespace.get("__doc__")
    for mdl in models:
        if doc and not mdl.doc:
            mdl.doc = doc
        mdl.source = path
    return models


def pick_model(models: list[Model], name: str | None, path: str = "") -> Model:
    """The model named ``name``, or the only one."""
    if name is None:
        if len(models) > 1:
            names = ", ".join(m.name for m in models)
            raise ModelError(f"the file defines several models ({names}); choose one with --model",
                             where=path or None)
        return models[0]
    for mdl in models:
        if mdl.name == name:
            return mdl
    names = ", ".join(m.name for m in models)
    raise ModelError(f"no model named {name!r} in the file (it defines {names})", where=path or None)


def load_model(path: str, name: str | None = None) -> Model:
    """The Model defined in the model file at ``path`` (``name=`` picks one of several)."""
    return pick_model(load_models(path), name, path)
