"""Tolerance bands against time (docs/reference/sensitivities.md, mech.tolerance): a quantity's
nominal curve, the linear worst case shaded, the RSS band (±3σ) shaded over it, and the Monte Carlo
envelope (its samples' minimum and maximum) dashed; ``band_plot(band, "X4")`` with one Band, or
``band_plot({"worst": b1, "rss": b2, "montecarlo": b3}, "X4")`` (or a list) to draw several methods
over one another. Units as plot.timeplot gives them."""
from __future__ import annotations

import numpy as np

from .style import INK
from .timeplot import model_units, shown, unit

# method: (colour, how it is drawn, legend text)
LOOK = {"worst": ("#f0a202", "fill", "worst case (linear)"),
        "rss": ("#2e86de", "fill", "RSS, ±3σ (σ = tol/3)"),
        "montecarlo": ("#c0392b", "dashed", "Monte Carlo envelope")}
ORDER = ("worst", "rss", "montecarlo")      # drawn in this order: the widest first


def _bands(bands) -> dict:
    """{method: Band} from a Band, a list of Bands or a mapping."""
    if hasattr(bands, "method") and hasattr(bands, "contributions"):
        return {bands.method: bands}
    if hasattr(bands, "values") and hasattr(bands, "items"):
        items = list(bands.values())
    else:
        items = list(bands)
    out = {}
    for b in items:
        if not hasattr(b, "method"):
            raise TypeError(f"band_plot() takes Bands (mech.tolerance), got {b!r}")
        out[b.method] = b
    if not out:
        raise ValueError("band_plot(): give at least one Band")
    return out


def label_of(mech, name, length=None, time="s", angle="rad") -> str:
    """The quantity's axis label, with its unit where mechgen knows it."""
    text = name if isinstance(name, str) else str(name)
    if not isinstance(name, str):
        return text
    try:
        u = unit(mech, name, length=length, time=time, angle=angle)
    except (KeyError, ValueError):
        u = ""
    return f"{text} [{u}]" if u else text


def terms(band) -> str:
    """The tolerances and clearances of a band, as a subtitle."""
    parts = [f"{p} ±{hi:g}" if lo == -hi else f"{p} {lo:+g}/{hi:+g}"
             for p, (lo, hi) in band.tolerances.items()]
    parts += [f"{c} clearance {v:g}" for c, v in band.clearances.items()]
    return ", ".join(parts)


def band_plot(bands, name, ax=None, length=None, time=None, title=None, deviation=False,
              legend=True):
    """Draw ``name``'s bands against time on ``ax`` (a new figure when None); returns
    the axes. ``deviation=True`` draws each band less the nominal value (the nominal is
    then the zero line): the bands' shapes, which a quantity's own swing can hide. A
    Monte Carlo band's legend says how many samples it kept. ``length`` and ``time``
    name the axes' units (default: the model's declared units, else seconds and none
    stated); an angle is drawn in degrees where the model shows angles so."""
    bands = _bands(bands)
    first = next(iter(bands.values()))
    mech = first.mechanism
    length, time, angle = model_units(mech, length, time)
    t = np.asarray(first.times, dtype=float)
    if t.size < 2:
        raise ValueError("band_plot(): a band over a sweep of at least 2 points (this one "
                         "is at one time)")
    own = ax is None
    if own:
        import matplotlib.pyplot as plt
        _, ax = plt.subplots(figsize=(7.5, 4.4))
    nominal = None
    for method in ORDER:
        if method not in bands:
            continue
        b = bands[method]
        got = b[name]
        low = shown(mech, name, np.asarray(got["low"], dtype=float))
        high = shown(mech, name, np.asarray(got["high"], dtype=float))
        if low.ndim != 1:
            raise ValueError(f"band_plot(): {name!r} is a vector quantity; take one component")
        nominal = shown(mech, name, np.asarray(got["nominal"], dtype=float))
        if deviation:
            low, high = low - nominal, high - nominal
        colour, how, text = LOOK[method]
        if method == "montecarlo":
            text = f"{text} ({b.used:,} samples" + (f", {b.failed} failed)" if b.failed else ")")
        if how == "fill":
            ax.fill_between(b.times, low, high, color=colour, alpha=0.28 if method == "worst"
                            else 0.38, linewidth=0, label=text)
            ax.plot(b.times, low, color=colour, linewidth=0.8)
            ax.plot(b.times, high, color=colour, linewidth=0.8)
        else:
            ax.plot(b.times, low, color=colour, linestyle="--", linewidth=1.3, label=text)
            ax.plot(b.times, high, color=colour, linestyle="--", linewidth=1.3)
    ax.plot(t, 0 * nominal if deviation else nominal, color=INK, linewidth=1.6,
            label="nominal")
    ax.set_xlabel(f"time T [{time}]")
    what = label_of(mech, name, length, time, angle)
    ax.set_ylabel(f"{what.split(' [')[0]} − nominal" + (f" [{what.split(' [')[1]}"
                                                        if " [" in what else "")
                  if deviation else what)
    ax.grid(True, color="#dddddd", linewidth=0.7)
    if legend:
        handles, labels = ax.get_legend_handles_labels()
        order = [labels.index("nominal")] + [i for i, lab in enumerate(labels)
                                             if lab != "nominal"]
        ax.legend([handles[i] for i in order], [labels[i] for i in order], fontsize="small",
                  loc="best")
    if title is None:
        title = f"{mech.name}: {what.split(' [')[0]}" + (" − nominal" if deviation else "") \
            + f", tolerance bands\n{terms(first)}"
    if title:
        ax.set_title(title, fontsize="medium")
    if own:
        ax.figure.tight_layout()
    return ax
