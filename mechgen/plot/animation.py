"""A sweep animated: one drawing whose artists move in place frame by frame, with the
paths of traced points; rendered as RGB frames, written as a GIF (pillow) or a movie
(ffmpeg)."""
from __future__ import annotations

import os

import numpy as np

from ..errors import MechgenError
from ..runtime.results import Sweep
from .drawing import add_path, draw, trace_paths
from .scene import Scene

MOVIES = (".mp4", ".m4v", ".mov", ".mkv")


class Animation:
    """What animate() made: the Drawing, its traces, ``frames()`` (RGB arrays),
    ``save(path)`` and, for notebooks and windows, a matplotlib FuncAnimation
    (``.animation``) stepping the same artists."""

    def __init__(self, drawing, step, n, fps, traces):
        self.drawing = drawing
        self.traces = traces
        self.fps = fps
        self.path = None
        self._step = step
        self._n = n
        self._anim = None

    def __len__(self):
        return self._n

    @property
    def figure(self):
        return self.drawing.figure

    @property
    def animation(self):
        """A blit-free matplotlib FuncAnimation moving the drawing's artists in place."""
        if self._anim is None:
            from matplotlib.animation import FuncAnimation
            self._anim = FuncAnimation(self.figure, self._step, frames=self._n,
                                       interval=1000.0 / self.fps, blit=False, repeat=True,
                                       cache_frame_data=False)
        return self._anim

    def frames(self, dpi=None):
        """Render every frame as an (h, w, 3) uint8 array. The still parts (axes, ticks,
        grid) are rendered once; each frame moves the artists in place and draws only them."""
        from matplotlib.backends.backend_agg import FigureCanvasAgg
        fig = self.figure
        canvas = fig.canvas if isinstance(fig.canvas, FigureCanvasAgg) else FigureCanvasAgg(fig)
        old_dpi = fig.dpi
        if dpi is not None:
            fig.set_dpi(dpi)
        moving = self.drawing.moving()
        try:
            for a in moving:
                a.set_animated(True)
            canvas.draw()
            background = canvas.copy_from_bbox(fig.bbox)
            for f in range(self._n):
                self._step(f)
                canvas.restore_region(background)
                for a in sorted(self.drawing.moving(), key=lambda a: a.get_zorder()):
                    a.axes.draw_artist(a) if a.axes is not None else fig.draw_artist(a)
                yield np.asarray(canvas.buffer_rgba())[..., :3].copy()
        finally:
            for a in self.drawing.moving():
                a.set_animated(False)
            if dpi is not None:
                fig.set_dpi(old_dpi)

    def save(self, path, fps=None, dpi=80, progress=None):
        """Write a GIF (pillow) or, with ffmpeg on the PATH, an MP4 (.mp4, .mov, .mkv).
        ``progress(done, total)``, where given, is called after each frame rendered (a
        long film's progress and estimate: mechgen animate prints them)."""
        fps = self.fps if fps is None else fps
        ext = check_movie_path(path)
        tell = progress if progress is not None else (lambda done, total: None)
        if ext == ".gif":
            from PIL import Image
            images = []
            for f in self.frames(dpi):
                images.append(Image.fromarray(f))
                tell(len(images), self._n)
            # one palette for the whole film: from a few frames side by side
            picks = images[:: max(1, len(images) // 4)][:4]
            sheet = Image.new("RGB", (sum(i.width for i in picks), picks[0].height))
            x = 0
            for im in picks:
                sheet.paste(im, (x, 0))
                x += im.width
            palette = sheet.quantize(colors=127, method=Image.Quantize.MEDIANCUT)
            colors = np.array(palette.getpalette()[:3 * 127]).reshape(-1, 3)
            colors[colors.min(axis=1) >= 244] = 255      # paper stays white, not 252-grey
            palette.putpalette(colors.ravel().tolist() + [255, 255, 255] * (256 - len(colors)))
            film = [im.quantize(palette=palette, dither=Image.Dither.NONE) for im in images]
            film[0].save(str(path), save_all=True, append_images=film[1:],
                         duration=int(round(1000.0 / fps)), loop=0, optimize=False)
        else:
            from matplotlib import animation as manim
            writer = manim.FFMpegWriter(fps=fps)
            with writer.saving(self.figure, str(path), dpi):
                for f in range(self._n):
                    self._step(f)
                    writer.grab_frame()
                    tell(f + 1, self._n)
        self._step(0)
        self.path = path
        return path


def check_movie_path(path) -> str:
    """The extension of an animation file name, or a MechgenError saying what works."""
    ext = os.path.splitext(str(path))[1].lower()
    if ext == ".gif":
        return ext
    if ext in MOVIES:
        from matplotlib import animation as manim
        if not manim.writers.is_available("ffmpeg"):
            raise MechgenError(f"writing {path} needs ffmpeg on the PATH; install it or write "
                               "a .gif instead")
        return ext
    raise MechgenError(f"cannot write an animation as {str(path)!r}: give a .gif (or "
                       f"{', '.join(MOVIES)} with ffmpeg installed)")


def repeats_first(P, tol=1e-7) -> bool:
    """True when the last of frames P (F, N, 2) shows the configuration of the first (a
    sweep over one period, both ends included): every point back where it started."""
    if P.shape[0] < 3:
        return False
    span = float(np.ptp(P.reshape(-1, 2), axis=0).max()) or 1.0
    return bool(np.abs(P[-1] - P[0]).max() <= tol * span)


def animate(mech, sweep, path=None, *, trace=(), fps=25, ax=None, dpi=80, periodic=None,
            **kwargs):
    """Animate a sweep (``mech.sweep(0, 1, 200)``): one drawing whose artists move in place
    frame by frame; ``trace`` names points whose paths are drawn: POINTS labels,
    ``body[k]``, or ``body.at(x, y)`` for a point the model does not name (a coupler
    curve). Writes ``path`` (.gif with pillow, .mp4 with ffmpeg) when given.

    A film loops: when the sweep's last configuration is its first (one period, both
    ends included) the last frame is left out, so that the loop does not stop on a
    repeated picture (``periodic=False`` keeps every frame, ``True`` drops the last one
    whatever it shows). Other keywords go to draw(). Returns an :class:`Animation`."""
    if not isinstance(sweep, Sweep):
        raise TypeError(f"animate() takes a Sweep (mech.sweep(t0, t1, n)), got {sweep!r}")
    if not len(sweep):
        raise MechgenError("animate(): the sweep holds no points")
    if path is not None:
        check_movie_path(path)
    P, Q, T = sweep.points(), sweep.Q, sweep.t
    paths = trace_paths(Scene(mech), trace, P, Q)      # an unknown point fails before drawing
    drop = repeats_first(P) if periodic is None else bool(periodic) and len(T) > 1
    n = len(T) - 1 if drop else len(T)
    kwargs.setdefault("width", 7.0)
    # draw() draws each whole path (and frames it): here faint and dashed, with the part
    # travelled so far drawn over it frame by frame
    d = draw(mech, sweep[0], ax=ax, sweep=sweep, trace=trace, **kwargs)
    fulls = d.artists.get("traces", [])[:len(paths)]     # (then the dots that move)
    for full in fulls:
        full.set(linewidth=0.8, alpha=0.4, linestyle="--")
    lines = [(xy, add_path(d.ax, d.structure, body, xy[:1], linewidth=1.8, alpha=1.0,
                           zorder=4.5)) for body, xy in paths]
    d.artists.setdefault("traces", []).extend(part for _, part in lines)

    def step(f):
        d.set_state(P[f], Q[f], T[f])
        upto = f + 1 if f < n - 1 else len(T)    # the last frame closes the curve
        for xy, line in lines:
            line.set_data(xy[:upto, 0], xy[:upto, 1])
        return ()

    out = Animation(d, step, n, fps, [line for _, line in lines])
    if path is not None:
        out.save(path, dpi=dpi)
    return out
