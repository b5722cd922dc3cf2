"""Reading model files: run the file, collect the Models it defines at module level."""
from __future__ import annotations

import importlib.util
import os
import runpy
import sys
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


# the files a model file reads while it runs (a table of dimensions, a cam profile): its
# module depends on them as on its text (bridge.compile_file's manifest lists them)
_READING: set | None = None
_HOOKED = False


def _on_open(event, args):
    if event == "open" and _READING is not None and args and \
            isinstance(args[0], (str, bytes, os.PathLike)):
        mode = args[1] if len(args) > 1 and isinstance(args[1], str) else "r"
        if not any(c in mode for c in "wax"):
            _READING.add(os.fsdecode(args[0]))


def _data_files(opened, path) -> list[str]:
    """The files of ``opened`` that are the model's data, not Python's nor mechgen's
    (compiled bytecode, the standard library, site-packages, mechgen itself)."""
    import site
    import sysconfig
    skip = {os.path.abspath(p) + os.sep for p in
            (sys.prefix, sys.base_prefix, sys.exec_prefix, sysconfig.get_paths()["stdlib"],
             os.path.dirname(os.path.dirname(os.path.abspath(__file__))),
             *getattr(site, "getsitepackages", lambda: [])(),
             getattr(site, "getusersitepackages", lambda: "")() or os.devnull)}
    found = set()
    for f in opened:
        f = os.path.abspath(f)
        if f == path or f.endswith(".pyc") or "__pycache__" in f or not os.path.isfile(f):
            continue
        if not any(f.startswith(s) for s in skip):
            found.add(f)
    return sorted(found)


def _run(path: str) -> tuple[dict, list]:
    """Run the model file: its namespace, and every Model it created (in order); each
    created Model's ``read_files`` lists the data files the run opened."""
    global _READING, _HOOKED
    created, opened = [], set()
    if not _HOOKED:
        sys.addaudithook(_on_open)      # an audit hook stays: it acts while _READING is set
        _HOOKED = True
    collect_models(created)
    outer, _READING = _READING, opened
    try:
        namespace = runpy.run_path(path, run_name="__mechgen_model__")
    finally:
        _READING = outer
        if outer is not None:
            outer |= opened
        collect_models(None)
    files = _data_files(opened, path)
    for mdl in created:
        mdl.read_files = files
    return namespace, created


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
    """The Model defined in a model file.

    Parameters
    ----------
    path : str
        The model file (plain Python defining ``mechgen.Model`` objects at module level).
    name : str, optional
        Which model, when the file defines several.

    Returns
    -------
    Model
        The model, not yet built (``mechgen.compile(model)`` builds and loads it).

    Raises
    ------
    ModelError
        The file is missing, fails, defines no model, or several without ``name``.
    """
    return pick_model(load_models(path), name, path)
