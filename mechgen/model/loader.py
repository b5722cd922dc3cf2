"""Reading model files: run the file, collect the Models it defines at module level."""
from __future__ import annotations

import importlib.util
import os
import runpy
import traceback

from ..errors import MechgenError, ModelError
from .language import Model, collect_models


def _check_source(path: str) -> None:
    """Refuse a file that is not Python source (binary, or not in its declared encoding)
    before running it, naming the file."""
    try:
        with open(path, "rb") as fh:
            data = fh.read()
    except OSError as exc:
        raise ModelError(f"the model file cannot be read: {exc.strerror or exc}",
                         where=path) from None
    if b"\0" in data:
        raise ModelError("not a Python model file (it holds binary data: NUL bytes)",
                         where=path)
    try:
        importlib.util.decode_source(data)
    except (SyntaxError, UnicodeDecodeError, LookupError) as exc:
        raise ModelError(f"not a Python model file (its text cannot be decoded: {exc})",
                         where=path) from None


def _line_in(path, exc) -> str:
    """``path:line`` of the innermost frame of exc's traceback in the model file, or path."""
    for frame in reversed(traceback.extract_tb(exc.__traceback__)):
        if os.path.abspath(frame.filename) == path:
            return f"{path}:{frame.lineno}"
    return path


def _run(path: str) -> tuple[dict, list]:
    """Run the model file: its namespace, and every Model it created (in order)."""
    created = []
    collect_models(created)
    try:
        return runpy.run_path(path, run_name="__mechgen_model__"), created
    finally:
        collect_models(None)


def load_models(path: str) -> list[Model]:
    """Every ``Model`` defined at module level of the file, in definition order."""
    path = os.path.abspath(path)
    if not os.path.isfile(path):
        raise ModelError("the model file does not exist", where=path)  # path named once
    _check_source(path)
    try:
        namespace, created = _run(path)
    except MechgenError:
        raise
    except SyntaxError as exc:
        where = f"{exc.filename or path}:{exc.lineno}" if exc.lineno else (exc.filename or path)
        raise ModelError(f"syntax error: {exc.msg}", where=where) from None
    except SystemExit as exc:   # a model file ends by running code, never by exiting
        raise ModelError(f"the model file called sys.exit({exc.code!r}): a model file "
                         "defines models and must not exit", where=_line_in(path, exc)) from None
    except KeyboardInterrupt:
        raise                   # the user's Ctrl-C (the command line says where, in one line)
    except BaseException as exc:  # a model file that raises: name its line
        raise ModelError(f"the model file raised {type(exc).__name__}: {exc}",
                         where=_line_in(path, exc)) from None
    models, seen = [], set()
    for value in namespace.values():
        if isinstance(value, Model) and id(value) not in seen:
            seen.add(id(value))
            models.append(value)
    # those it created (kept or not) and those it holds (an imported one included)
    _refuse_twins(created + [m for m in models if all(m is not c for c in created)])
    if not models:
        raise ModelError("the file defines no mechgen.Model at module level", where=path)
    doc = namespace.get("__doc__")
    for mdl in models:
        if doc and not mdl.doc:
            mdl.doc = doc
        mdl.source = path
    return models


def _refuse_twins(created) -> None:
    """Two Models of one name in a file would write one module over the other: refuse,
    naming both lines."""
    first = {}
    for mdl in created:
        if mdl.name in first:
            other = first[mdl.name]
            raise ModelError(f"a second Model named {mdl.name!r} (the first is at "
                             f"{other._where or '?'}): both would write the module "
                             f"{mdl.name}.py; give each model its own name", where=mdl._where)
        first[mdl.name] = mdl


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
