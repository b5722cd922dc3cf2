"""Calls the runtime makes into a layer above it, through a slot that layer's owner fills
(a base module: no mechgen imports). The runtime names the slot and never imports upward;
``mechgen/__init__`` (the top, which always runs before any submodule) fills it.

``EXPLORE``: ``(mech, **options) -> the notebook's view`` for ``Mechanism.explore`` (the live
view, mechgen.view, which needs Bokeh).
"""
from __future__ import annotations

EXPLORE = None


def explorer():
    """The filled EXPLORE slot."""
    if EXPLORE is None:     # only where mechgen's package __init__ did not run
        raise RuntimeError("mech.explore() needs mechgen's live view: import mechgen first")
    return EXPLORE
