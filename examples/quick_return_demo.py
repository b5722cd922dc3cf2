"""The main job: build the seed's quick-return mechanism, solve it, print what Mech prints,
and draw its pictures into docs/ (the ones README.md shows).

Run from anywhere:  python3 examples/quick_return_demo.py
"""
import os
import sys

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(HERE)


def main():
    import mechgen
    from mechgen.compiler.build import build
    from mechgen.model.loader import load_models

    model = load_models(os.path.join(HERE, "quick_return.py"))[0]
    path = build(model, os.path.join(ROOT, "generated"))
    print(f"built {os.path.relpath(path, ROOT)}")
    mech = mechgen.load(path)

    for t in (0.0, 0.5, 0.85):
        s = mech.solve(t)
        print(f"SolveMech[{t}]: Th3 = {s['Th3']:.6g}, X4 = {s['X4']:.6g}")
    s = mech.solve(0.85, guess={"X4": 1.0})
    print(f"second assembly mode at 0.85: Th3 = {s['Th3']:.6g}, X4 = {s['X4']:.6g}")
    s = mech.solve(0.15, level="acceleration")
    print(f"SolveMech[0.15, Acceleration]: Th3d = {s['Th3d']:.6g}, X4d = {s['X4d']:.6g}, "
          f"Th3dd = {s['Th3dd']:.6g}, X4dd = {s['X4dd']:.6g}")
    sw = mech.sweep(0.0, 1.0, 21, level="acceleration")
    print(f"SolveMech[{{0, 1}}, 20]: X4 from {sw['X4'].min():.6g} to {sw['X4'].max():.6g}")
    pictures(mech)
    return 0


def pictures(mech):
    """Seed 001's pictures, written to docs/ (shown in README.md): the mechanism drawn as in
    its "DEFINICION GRAFICA" pages, animated over one crank turn, and the slider stroke X4(T)
    for the family longitud = 1.5, 2.25, 3 of its section 5."""
    import time

    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    from mechgen import plot

    docs = os.path.join(ROOT, "docs")
    os.makedirs(docs, exist_ok=True)
    # the seed's own shapes: the base outline (Edge) and the crank disk (Disk, radius 4)
    seed_look = {"base": plot.Edge([3, 4, (12, 0), (-5, 0), (-5, 10), (-5, 8), 2, (-5, 2)]),
                 "manivela": plot.Disk(1, 4.0)}

    path = os.path.join(docs, "quick_return.png")
    d = plot.draw(mech, mech.solve(0.0), artists=seed_look, labels=True, axes=True,
                  legend=True)
    d.figure.savefig(path, dpi=100)
    plt.close(d.figure)
    print(f"wrote {os.path.relpath(path, ROOT)}")

    start = time.perf_counter()
    path = os.path.join(docs, "quick_return.gif")
    frames = mech.sweep(0.0, 1.0, 100)
    a = plot.animate(mech, frames, path, trace="colisa[2]", fps=25, artists=seed_look,
                     legend=True)
    plt.close(a.figure)
    print(f"wrote {os.path.relpath(path, ROOT)} ({len(a)} frames in "
          f"{time.perf_counter() - start:.1f} s)")

    path = os.path.join(docs, "quick_return_x4.png")
    family = [mech.with_params(longitud=L).sweep(0.0, 1.0, 101) for L in (1.5, 2.25, 3.0)]
    lines = plot.plot(family, "X4", title="quick_return: slider stroke X4 for three crank lengths")
    lines[0].figure.savefig(path, dpi=100)
    plt.close(lines[0].figure)
    print(f"wrote {os.path.relpath(path, ROOT)}")


if __name__ == "__main__":
    sys.exit(main())
