"""A press started by its motor, with a small and a large flywheel (issue 22's example):
`mech.simulate` releases the crank's driver at t = 0 and the motor T0 (1 − ω/ω0) brings
the press up to speed against the work it presses once a turn; the picture is the crank's
speed over time, and the numbers what a designer reads from it: how long to reach speed,
the mean speed and its fluctuation once running, the peak motor torque.

    python3 examples/press_motor_demo.py        # writes docs/press_motor_speed.png
"""
import os

import numpy as np

import mechgen

HERE = os.path.dirname(os.path.abspath(__file__))
DOCS = os.path.join(os.path.dirname(HERE), "docs")
FLYWHEELS = (0.05, 2.0)         # kg m² on the crank
T1, POINTS = 4.0, 801


def run(mech, flywheel):
    """The simulated start and the figures of its last second (the press running)."""
    sw = mech.with_params(flywheel=flywheel).simulate(0.0, T1, POINTS, free=["crank driver"],
                                                      rtol=1e-9, atol=1e-11)
    w = -sw["Th2d"]                         # the crank turns clockwise
    late = sw.t >= T1 - 1.0
    mean = float(w[late].mean())
    reach = float(sw.t[np.argmax(w >= 0.9 * mean)])
    fluct = float((w[late].max() - w[late].min()) / mean)
    print(f"flywheel {flywheel:g} kg m²: 90 % of speed at t = {reach:.3f} s; running at "
          f"{mean:.2f} rad/s ({mean * 30 / np.pi:.1f} rpm), from {w[late].min():.2f} to "
          f"{w[late].max():.2f} (coefficient of fluctuation {fluct:.3f}); "
          f"{sw.steps} steps")
    return sw, w


def main():
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    mech = mechgen.compile(os.path.join(HERE, "press_motor.py"))
    fig, ax = plt.subplots(figsize=(7.5, 3.8))
    for flywheel, color in zip(FLYWHEELS, ("#c0392b", "#2471a3")):
        sw, w = run(mech, flywheel)
        ax.plot(sw.t, w * 30 / np.pi, color=color, lw=1.4,
                label=f"flywheel {flywheel:g} kg m²")
    w0 = mech.parameters["w0"]
    ax.axhline(w0 * 30 / np.pi, color="0.4", ls="--", lw=1, label="the motor's no-load speed")
    ax.set_xlabel("time [s]")
    ax.set_ylabel("crank speed [rpm]")
    ax.set_title("a press started by its motor, pressing once a turn")
    ax.set_xlim(0, T1)
    ax.set_ylim(bottom=0)
    ax.grid(alpha=0.3)
    ax.legend(loc="lower right", fontsize=9)
    fig.tight_layout()
    os.makedirs(DOCS, exist_ok=True)
    path = os.path.join(DOCS, "press_motor_speed.png")
    fig.savefig(path, dpi=100)
    print(f"wrote {os.path.relpath(path, os.path.dirname(HERE))}")


if __name__ == "__main__":
    main()
