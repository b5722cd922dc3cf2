"""Exploring a mechanism live (docs/reference/view.md): ``mechgen view MODEL.py`` serves a page
(view.server), ``mechgen view MODEL.py --html FILE`` writes one that needs no server
(view.standalone), ``mech.explore()`` shows that page in a notebook.

A layer above the runtime and the pictures (it draws what plot.draw draws, in Bokeh)
and below the command line: geometry (the drawing's glyphs in the frames they move with),
cycle (a cycle's columns, or why it cannot assemble), explorer (the state: parameters,
assembly mode, when to draw again), layers (the glyphs as Bokeh columns), page (the
Bokeh page), scripts (its JavaScript), server, standalone.
"""
from __future__ import annotations

NOTEBOOK_TIMES = 200     # times in each precomputed cycle of a notebook's view
FRAME_HEIGHT = 900       # pixels of the notebook's frame that holds the page


def need_bokeh():
    """A clear error where Bokeh, which draws the page, is not installed."""
    import importlib.util
    if importlib.util.find_spec("bokeh") is None:
        from ..errors import MechgenError
        raise MechgenError("the live view needs Bokeh, which the main install leaves "
                           "out: from the top of mechgen's repository run "
                           "python3 -m pip install -e \".[view]\" (or pip install bokeh)")


def explore(mech, t0=0.0, t1=1.0, n=NOTEBOOK_TIMES, trace=None, plots=None, ranges=None,
            vary=None, steps=None, show=True, resources="inline"):
    """Show the view of ``mech`` in a Jupyter notebook (``mech.explore()``): the page of
    ``mechgen view --html`` (cycles precomputed over the parameters' ranges, so that the
    sliders answer without a kernel round trip), in a frame of the notebook's output that
    holds the whole page: BokehJS embedded (``resources="inline"``, the default: it
    draws on a machine without the internet) or loaded from Bokeh's CDN
    (``resources="cdn"``: a smaller notebook). Returns the Page (``page.layout`` is the
    Bokeh layout, ``page.html`` the page's HTML); ``show=False`` only builds it."""
    need_bokeh()
    from .explorer import Explorer
    from .standalone import page_html, standalone_page
    if resources not in ("inline", "cdn"):
        raise ValueError(f"explore: resources must be 'inline' or 'cdn', got {resources!r}")
    ex = Explorer(mech, t0=t0, t1=t1, n=n, trace=trace, plots=plots, ranges=ranges)
    page = standalone_page(ex, vary=vary, steps=steps)
    if show:
        import html
        from IPython.display import HTML, display
        page.html = page_html(page, resources)
        display(HTML(f'<iframe srcdoc="{html.escape(page.html, quote=True)}" '
                     f'style="width: 100%; height: {FRAME_HEIGHT}px; border: 0" '
                     f'title="mechgen view: {html.escape(mech.name)}"></iframe>'))
    return page
