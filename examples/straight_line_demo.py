"""A four-bar that must trace a straight segment, fitted and then toleranced
(docs/reference/sensitivities.md).

The task: a coupler point through ten points on the segment y = 4, 0 <= x <= 4 (any crank
phase at each: path generation without timing). ``mech.fit`` chooses the coupler, rocker,
ground and tracing-point lengths of examples/straight_line.py (the crank stays 1): a
design-table search over wide bounds, then Levenberg–Marquardt on the exact derivatives the
compiler emits (∂point/∂p from the sensitivity module, ∂point/∂t its rate). Then the shop's
question: with every length held to ±0.01 and each pin's radial clearance 0.005, how far
from straight is the real part? ``mech.tolerance`` answers by the linear worst case, RSS and
10,000 Monte Carlo samples (the nonlinear truth), with the stack-up of contributions.

    python3 examples/straight_line_demo.py      # prints the fit and the stack-up table,
                                                # draws docs/straight_line_fit.png and
                                                # docs/straight_line_band.png
"""
import os
import sys
import time

import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(HERE)
DOCS = os.path.join(ROOT, "docs")

TARGET = np.column_stack([np.linspace(0.0, 4.0, 10), np.full(10, 4.0)])
BOUNDS = {"b": (1.5, 4.0), "c": (1.5, 4.0), "d": (1.0, 4.0), "u": (3.0, 7.0)}
TOLERANCES = {name: 0.01 for name in ("a", "b", "c", "d", "u")}
CLEARANCES = {"O2": 0.005, "A": 0.005, "O4": 0.005, "B": 0.005}


def fitted(mech):
    """The fit of the segment, printed."""
    start = time.perf_counter()
    fit = mech.fit(point="coupler[3]", target=TARGET, params=BOUNDS, seed=1)
    print(f"fit: {fit.evaluations} evaluations in {time.perf_counter() - start:.1f} s")
    for name, value in fit.params.items():
        print(f"  {name} = {value:.6f}   (Hoekens' {mech.parameters[name]:g})")
    print(f"  RMS distance from the ten targets: {fit.error:.2e}")
    print(f"  passed at T = {', '.join(f'{t:.4f}' for t in fit.times)}")
    return fit


def stack_up(bands, name):
    """The contributions of each tolerance and clearance where the worst band is widest."""
    worst = bands["worst"]
    k = int(np.argmax(worst[name]["high"] - worst[name]["low"]))
    shares = worst.contributions(name)
    total = sum(float(v[k]) for v in shares.values())
    print(f"stack-up of {name} at T = {worst.times[k]:.4f} (the widest worst-case band):")
    print(f"  {'term':6s} {'tolerance':>12s} {'contribution':>13s} {'share':>7s}")
    for term, values in sorted(shares.items(), key=lambda kv: -float(kv[1][k])):
        tol = (f"±{TOLERANCES[term]:g}" if term in TOLERANCES
               else f"c = {CLEARANCES[term]:g}")
        print(f"  {term:6s} {tol:>12s} {float(values[k]):13.5f} "
              f"{100 * float(values[k]) / total:6.1f} %")
    for method, band in bands.items():
        got = band[name]
        lo, hi = np.min(got["low"] - got["nominal"]), np.max(got["high"] - got["nominal"])
        print(f"  {method:11s} {name} − nominal from {lo:+.5f} to {hi:+.5f} over the run")


def pictures(mech, fit, sw, bands):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    from mechgen import plot
    os.makedirs(DOCS, exist_ok=True)
    best = fit.mechanism
    whole = best.sweep(0, 1, 361)
    hoekens = mech.sweep(0, 1, 361)
    d = plot.draw(best, best.solve(float(fit.times[4])), sweep=whole, title=(
        "straight_line: the fitted four-bar through ten points of y = 4 (timing free)"))
    ax = d.ax
    ax.plot(hoekens["px"], hoekens["py"], color="0.6", lw=1, ls="--",
            label="Hoekens' linkage (a 1, b 2.5, c 2.5, d 2, u 5)")
    ax.plot(whole["px"], whole["py"], color="tab:blue", lw=1.2, label="the fitted path")
    ax.plot(TARGET[:, 0], TARGET[:, 1], "o", mfc="none", mec="tab:red", ms=7,
            label=f"targets (RMS distance {fit.error:.1e})")
    ax.legend(loc="lower left", fontsize=8)
    path = os.path.join(DOCS, "straight_line_fit.png")
    d.figure.savefig(path, dpi=100)
    plt.close(d.figure)
    print(f"wrote {os.path.relpath(path, ROOT)}")

    fig, axs = plt.subplots(1, 2, figsize=(13, 4.6))
    title = "straight_line (fitted): py over the straight run, lengths ±0.01, pin clearances 0.005"
    plot.band_plot(bands, "py", ax=axs[0], title="the tracing point's height py")
    plot.band_plot(bands, "py", ax=axs[1], deviation=True, legend=False,
                   title="py less its nominal value: the bands' widths")
    fig.suptitle(title)
    fig.tight_layout()
    path = os.path.join(DOCS, "straight_line_band.png")
    fig.savefig(path, dpi=100)
    plt.close(fig)
    print(f"wrote {os.path.relpath(path, ROOT)}")


def main():
    import mechgen
    mech = mechgen.compile(os.path.join(HERE, "straight_line.py"),
                           outdir=os.path.join(ROOT, "generated"))
    fit = fitted(mech)
    best = fit.mechanism
    lo, hi = float(np.min(fit.times)), float(np.max(fit.times))
    sw = best.sweep(lo, hi, 121, sensitivities=True)
    bands = {method: best.tolerance(sw, TOLERANCES, clearance=CLEARANCES, method=method,
                                    **({"samples": 10_000, "seed": 1}
                                       if method == "montecarlo" else {}))
             for method in ("worst", "rss", "montecarlo")}
    stack_up(bands, "py")
    if "--no-pictures" not in sys.argv:
        pictures(mech, fit, sw, bands)


if __name__ == "__main__":
    main()
