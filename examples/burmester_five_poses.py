"""Five positions of a gate (x, y of a point on it, its angle), read off a layout: which
four-bars carry the gate through all five, in order, on one assembly mode, without a toggle?

Burmester's answer (mechgen.synthesis, docs/reference/synthesis.md): every real pair of fixed and
moving pivots (here four, found exactly from a quartic), every four-bar two of them make (twelve,
each dyad once as the crank), screened for circuit, branch and order defects, ranked by the
transmission angle. The best one's ``BEST.model(name)`` is a model like any other
(``mechgen.compile`` builds it; ``mechgen synthesize examples/gate_poses.csv -o gate.py`` writes it
as a model file); run this file to print the table and draw the linkage through the poses to
docs/burmester_five_poses.png. (It is not a model file itself: its model comes from a root-finder,
whose last digits are the machine's.)"""
import os

from mechgen import synthesis

POSES = [(0.845, 0.606, 0.360), (0.689, 0.823, 0.180), (0.368, 0.818, 0.054),
         (0.075, 0.592, 0.021), (-0.027, 0.263, 0.088)]

DYADS = synthesis.dyads(POSES)
LINKS = synthesis.fourbars(POSES)          # defect-free first, then by transmission angle
BEST = LINKS[0]


def table():
    print(f"{len(DYADS)} real Burmester pairs (fixed pivot; moving pivot in the gate's frame):")
    for d in DYADS:
        print(f"  ({d.fixed[0]:8.4f}, {d.fixed[1]:8.4f});  ({d.moving[0]:8.4f}, "
              f"{d.moving[1]:8.4f})   residual {d.residual:.1e}")
    print(f"{len(LINKS)} four-bars:")
    print("   a       b       c       d     Grashof         defects            transmission")
    for f in LINKS:
        a, b, c, d = f.lengths
        flags = ", ".join(sorted(f.defects)) or "-"
        print(f"  {a:6.3f}  {b:6.3f}  {c:6.3f}  {d:6.3f}  {f.grashof:14s}  {flags:17s}  "
              f"{f.transmission[0]:5.1f}–{f.transmission[1]:5.1f}°")


def picture(path):
    import tempfile

    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    import numpy as np

    import mechgen
    from mechgen import plot

    mech = mechgen.compile(BEST.model("burmester_gate"), outdir=tempfile.mkdtemp(),
                           tier="python")
    t_end = BEST.times[-1]
    sweep = mech.sweep(0.0, t_end, 121)
    d = plot.draw(mech, mech.solve(BEST.times[2]), sweep=sweep, trace=("coupler[3]",),
                  title=f"burmester_gate: {BEST.grashof}, transmission "
                        f"{BEST.transmission[0]:.0f}–{BEST.transmission[1]:.0f}°")
    ax = d.ax
    length = 0.25
    for k, (x, y, th) in enumerate(POSES):
        ax.annotate("", xy=(x + length * np.cos(th), y + length * np.sin(th)), xytext=(x, y),
                    arrowprops=dict(arrowstyle="->", color="crimson", lw=1.6))
        ax.plot([x], [y], "o", color="crimson", ms=4)
        ax.text(x - 0.06, y - 0.08, str(k + 1), color="crimson", fontsize=9)
    for t, (x, y, th) in zip(BEST.times, POSES):     # the model reaches every pose
        s = mech.solve(t)
        assert abs(s["X3"] - x) < 1e-9 and abs(s["Y3"] - y) < 1e-9
    d.ax.figure.savefig(path, dpi=100)
    plt.close(d.ax.figure)
    print(f"wrote {path}")


if __name__ == "__main__":
    table()
    root = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
    os.makedirs(os.path.join(root, "docs"), exist_ok=True)
    picture(os.path.join(root, "docs", "burmester_five_poses.png"))
