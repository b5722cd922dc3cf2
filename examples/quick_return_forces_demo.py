"""A worked force analysis: the seed's quick-return with masses, gravity and a cutting force
on the slider (examples/quick_return_forces.py), over one turn of the crank at constant
speed: the torque the crank's motor must give, the flywheel that keeps its speed within
±2.5 %, the power balance, the loads on the pins, and the pictures README.md shows
(written to docs/).

Run from anywhere:  python3 examples/quick_return_forces_demo.py
"""
import os
import sys

import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(HERE)
POINTS = 1001        # one crank turn, T = 0 .. 1, both ends
CS = 0.05            # coefficient of speed fluctuation: ±2.5 % about the mean speed
DRAWN_AT = 0.7       # the drawing's instant: the slider moving right, the cutting force on


def analyse(mech):
    """The numbers of one turn, printed; returns the sweep."""
    from mechgen.plot.forceplots import cycle_mean, driven

    sw = mech.sweep(0.0, 1.0, POINTS, level="dynamic")
    torque = sw.driver("crank driver")
    angle = np.degrees(driven(sw, "crank driver")[0])
    k = int(np.argmax(np.abs(torque)))
    print(f"crank torque: largest in size {torque[k]:.2f} at {angle[k]:.1f}° "
          f"(T = {sw.t[k]:.3f}), mean over the turn {cycle_mean(angle, torque):.2f}, "
          f"from {torque.min():.2f} to {torque.max():.2f}")
    fly = sw.flywheel(CS)
    print(f"flywheel for cs = {CS}: energy fluctuation {fly['energy']:.1f}, inertia "
          f"{fly['inertia']:.1f}, mean power {fly['mean_power']:.1f}")
    power = sw.power()
    worst = np.abs(power["residual"]).max() / np.abs(power["drivers"]).max()
    print(f"power balance: drivers + loads - kinetic - potential, at most "
          f"{worst:.1e} of the largest input power")
    for name, body in (("O2", "manivela"), ("slot", "manivela"), ("O4", "colisa"),
                       ("link", "deslizadera"), ("guide", "deslizadera")):
        f = sw.reaction(name, on=body)
        size = np.hypot(f[:, 0], f[:, 1])
        print(f"  {name} on {body}: largest force {size.max():.1f} at T = "
              f"{sw.t[int(np.argmax(size))]:.3f}")
    shaking = sw.shaking()
    print(f"shaking force on the frame: largest {np.hypot(*shaking[:, :2].T).max():.1f}")
    return sw


def pictures(mech, sw):
    """docs/quick_return_forces_torque.png, _polar.png and _draw.png."""
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    from mechgen import plot

    docs = os.path.join(ROOT, "docs")
    os.makedirs(docs, exist_ok=True)

    def save(fig, name):
        path = os.path.join(docs, name)
        fig.savefig(path, dpi=100)
        plt.close(fig)
        print(f"wrote {os.path.relpath(path, ROOT)}")

    e = plot.effort(sw, "crank driver", title="quick-return with a cutting force: the crank's "
                    "torque over one turn")
    fly = sw.flywheel(CS)
    e.ax.text(0.02, 0.25, f"flywheel for ±{100 * CS / 2:g} % speed: ΔE = {fly['energy']:.0f}, "
              f"I = {fly['inertia']:.0f}", transform=e.ax.transAxes, fontsize=9,
              bbox=dict(facecolor="white", edgecolor="#cccccc", alpha=0.9))
    save(e.figure, "quick_return_forces_torque.png")

    fig, axs = plt.subplots(2, 1, figsize=(7.2, 6.4))
    polars = [plot.polar(sw, "slot", on="manivela", ax=axs[0], marks=12,
                         title="the crank pin: the slot's force on the crank"),
              plot.polar(sw, "O4", on="base", ax=axs[1], marks=12,
                         title="the lever's bearing O4: its load on the frame")]
    fig.tight_layout()
    for p in polars:         # the angles' labels clear of the loci, as laid out
        p.place_labels()
    save(fig, "quick_return_forces_polar.png")

    s = mech.solve(DRAWN_AT, level="dynamic")
    fig, axs = plt.subplots(1, 2, figsize=(13.0, 5.0))
    plot.draw(mech, s, ax=axs[0], forces=True,
              title=f"T = {DRAWN_AT}: pin forces, the motor's torque, the loads")
    plot.draw(mech, s, ax=axs[1], forces="colisa",
              title=f"T = {DRAWN_AT}: the lever's free body diagram (−m·a: its inertia)")
    fig.tight_layout()
    save(fig, "quick_return_forces_draw.png")


def main():
    import mechgen

    mech = mechgen.compile(os.path.join(HERE, "quick_return_forces.py"),
                           outdir=os.path.join(ROOT, "generated"))
    sw = analyse(mech)
    pictures(mech, sw)
    return 0


if __name__ == "__main__":
    sys.exit(main())
