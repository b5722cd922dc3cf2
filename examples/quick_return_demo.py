"""The main job: build the seed's quick-return mechanism, solve it, print what Mech prints.

Run from anywhere:  python3 examples/quick_return_demo.py
"""
import os
import sys

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(HERE)


def main():
    import mechgen
    from mechgen.build import build
    from mechgen.loader import load_models

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
    return 0


if __name__ == "__main__":
    sys.exit(main())
