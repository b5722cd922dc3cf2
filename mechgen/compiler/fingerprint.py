"""A model's build fingerprint: a digest of everything its module's text depends on, read
from the Model as declared (no symbolic expansion), so that an unchanged model is not
expanded and rendered again (``build_if_changed``).

It covers the model (name, doc, source file name, parameters and defaults, coordinates and
guesses, bodies and their points, every constraint's rows, labels and points, the
outputs), the build options, sympy's version and the source of the code that writes a
module (mechgen.model, mechgen.compiler with its library, mechgen.protocol, the
templates). It is kept beside numba's cache, ``<folder>/__pycache__/<name>.mechgen-build``,
with the content stamp of the module it describes: a module edited, rebuilt with other
options or written by another mechgen is rendered again.
"""
from __future__ import annotations

import glob
import hashlib
import os

import sympy as sp

from ..protocol import MECHGEN_VERSION, content_digest, stamp_of

_PACKAGE = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
_SOURCES = None


def _source_digest() -> str:
    """A digest of the code that decides a module's text (computed once a process)."""
    global _SOURCES
    if _SOURCES is None:
        from .codegen.names import template_dir
        files = sorted(glob.glob(os.path.join(_PACKAGE, "compiler", "**", "*.py"), recursive=True)
                       + glob.glob(os.path.join(_PACKAGE, "model", "**", "*.py"), recursive=True)
                       + [os.path.join(_PACKAGE, "protocol.py")]
                       + glob.glob(os.path.join(template_dir(), "*.j2")))
        h = hashlib.sha256()
        for path in files:
            with open(path, "rb") as fh:
                h.update(os.path.relpath(path, _PACKAGE).encode() + b"\0" + fh.read() + b"\0")
        _SOURCES = h.hexdigest()
    return _SOURCES


def _point(pt) -> tuple:
    return (pt.body.name, sp.srepr(sp.sympify(pt.local)), pt.label)


def fingerprint(model, **options) -> str:
    """The digest of ``model`` built with ``options`` (those of render)."""
    h = hashlib.sha256()

    def put(*parts):
        h.update(repr(parts).encode() + b"\n")

    put("mechgen", MECHGEN_VERSION, sp.__version__, _source_digest())
    put("options", sorted((k, repr(v)) for k, v in options.items()))
    put("model", model.name, model.doc,
        os.path.basename(getattr(model, "source", "") or "<interactive>"))
    if model.units.declared:        # the module states them (UNITS): none, nothing put
        put("units", sorted(model.units.header().items()))
    for name, (sym, value) in model.params.items():
        put("param", name, sp.srepr(sym), repr(value))
    for c in model.coords:
        put("coordinate", sp.srepr(c), sp.srepr(sp.sympify(model.guess[c])))
    for b in model.bodies.values():
        put("body", b.name, b.number, b.is_ground, [sp.srepr(sp.sympify(p)) for p in b.points])
    for c in model.constraints:
        put("constraint", c.number, c.kind, c.label, c.is_driver,
            [(sp.srepr(sp.sympify(e)), label) for e, label in c.rows()],
            [_point(pt) for pt in getattr(c, "points", ())])
    for name, expr in model.outputs.items():
        put("output", name, sp.srepr(expr))
    # mass properties and loads (mechgen.model.forces.loads): the force functions read them
    for b in model.moving_bodies:
        put("mass", b.name, *(_part(getattr(b, k, 0)) for k in ("mass", "inertia", "centroid")))
    if model.gravity_vector is not None:
        put("gravity", _part(model.gravity_vector))
    for load in model.loads:
        put("load", load.kind, load.name, sorted((k, _part(v)) for k, v in vars(load).items()
                                                 if k not in ("kind", "name", "text")))
    return h.hexdigest()


def _part(value):
    """A load's part as text: a point, a body, a sympy value, or a sequence of them."""
    if hasattr(value, "local") and hasattr(value, "body"):
        return _point(value)
    if hasattr(value, "is_ground"):
        return value.name
    if isinstance(value, (tuple, list)):
        return [_part(v) for v in value]
    if isinstance(value, sp.MatrixBase):
        return [_part(v) for v in value]
    return sp.srepr(sp.sympify(value))


def record_path(path: str) -> str:
    """Where the fingerprint of the module at ``path`` is kept."""
    folder, base = os.path.split(os.path.abspath(path))
    return os.path.join(folder, "__pycache__", os.path.splitext(base)[0] + ".mechgen-build")


def up_to_date(path: str, digest: str) -> bool:
    """Whether the module at ``path`` was written from a model with fingerprint ``digest``
    and is unchanged since (its content stamp is the one recorded, and holds)."""
    try:
        with open(record_path(path), encoding="utf-8") as fh:
            recorded = fh.read().split()
        with open(path, encoding="utf-8") as fh:
            text = fh.read()
    except OSError:
        return False
    stamp = stamp_of(text)
    # the file as mechgen wrote it (an edit would leave the stamp and change the text)
    return stamp is not None and recorded == [digest, stamp] and content_digest(text) == stamp


def record(path: str, digest: str, text: str):
    """Keep ``digest`` as the fingerprint of the module ``text`` just written at ``path``
    (quietly nothing where the folder is read-only)."""
    stamp = stamp_of(text)
    target = record_path(path)
    try:
        os.makedirs(os.path.dirname(target), exist_ok=True)
        tmp = f"{target}.{os.getpid()}.tmp"
        with open(tmp, "w", encoding="utf-8") as fh:
            fh.write(f"{digest} {stamp}\n")
        os.replace(tmp, target)
    except OSError:
        pass
