"""From a model to a module file: render it (render.py), write it atomically."""
from __future__ import annotations

import os
import tempfile

from .fingerprint import fingerprint, record, up_to_date

_RENDER_NAMES = ("PREAMBLE", "STAMP", "environment", "render")


def __getattr__(name):
    """The renderer's names (mechgen.compiler.render), imported when first used: finding
    an up-to-date module needs neither jinja2 nor the emitters."""
    if name in _RENDER_NAMES:
        from .render import PREAMBLE, STAMP, environment, render
        return {"PREAMBLE": PREAMBLE, "STAMP": STAMP, "environment": environment,
                "render": render}[name]
    raise AttributeError(f"module {__name__!r} has no attribute {name!r}")


__all__ = ["PREAMBLE", "STAMP", "build", "build_if_changed", "environment", "render",
           "write_module"]


def write_module(text: str, path: str) -> str:
    """Write atomically: a failed build leaves no half-written module behind."""
    directory = os.path.dirname(os.path.abspath(path)) or "."
    os.makedirs(directory, exist_ok=True)
    fd, tmp = tempfile.mkstemp(prefix=".mechgen-", suffix=".py.tmp", dir=directory)
    try:
        with os.fdopen(fd, "w", encoding="utf-8", newline="\n") as fh:
            fh.write(text)
        # mkstemp makes the file private (0600); a module is as readable as any new file
        umask = os.umask(0)
        os.umask(umask)
        os.chmod(tmp, 0o666 & ~umask)
        os.replace(tmp, path)
    except BaseException:
        if os.path.exists(tmp):
            os.unlink(tmp)
        raise
    return path


def build(model, outdir="generated", **kwargs) -> str:
    """Render ``model`` and write ``outdir/<name>.py``; returns the path."""
    from .render import render
    text = render(model, **kwargs)
    return write_module(text, os.path.join(outdir, f"{model.name}.py"))


def build_if_changed(model, outdir, **kwargs) -> str:
    """Write ``outdir/<name>.py`` unless it already holds this model's module: a rewrite
    would change the file's time stamp and throw away numba's compiled cache beside it.
    A model unchanged since the module was written (the same build fingerprint,
    mechgen.compiler.fingerprint) is not even rendered again; otherwise the module is
    rendered and written only where its text differs."""
    return update_module(model, outdir, **kwargs)[0]


def update_module(model, outdir, **kwargs) -> tuple[str, bool]:
    """build_if_changed, and whether it wrote the file: (path, written)."""
    return commit_module(*prepare_module(model, outdir, **kwargs))


def prepare_module(model, outdir, **kwargs) -> tuple:
    """update_module's work before it writes anything: (path, text, digest), text None
    where the module is up to date. A build of several models prepares every one before
    it writes any (commit_module): one that fails leaves every file as it was."""
    path = os.path.join(outdir, f"{model.name}.py")
    try:
        digest = fingerprint(model, **kwargs)
    except Exception:  # noqa: BLE001 - a model the digest cannot read: render it
        digest = None
    if digest is not None and up_to_date(path, digest):
        return path, None, digest
    from .render import render
    return path, render(model, **kwargs), digest


def commit_module(path, text, digest) -> tuple[str, bool]:
    """Write what prepare_module rendered where the file holds other text: (path,
    written)."""
    if text is None:
        return path, False
    try:
        with open(path, encoding="utf-8") as fh:
            same = fh.read() == text
    except OSError:
        same = False
    if not same:
        write_module(text, path)
    if digest is not None:
        record(path, digest, text)
    return path, not same
