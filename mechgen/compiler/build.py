"""From a model to a module file: render it (render.py), write it atomically."""
from __future__ import annotations

import os
import tempfile

from .render import PREAMBLE, STAMP, environment, render

__all__ = ["PREAMBLE", "STAMP", "build", "environment", "render", "write_module"]


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
    text = render(model, **kwargs)
    return write_module(text, os.path.join(outdir, f"{model.name}.py"))
