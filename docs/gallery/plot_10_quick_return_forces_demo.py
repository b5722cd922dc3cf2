"""
A worked force analysis: quick_return_forces_demo
=================================================

``examples/quick_return_forces_demo.py`` analyses one turn of the crank at constant speed
(1,001 points): the torque's extremes and mean, the flywheel, the power balance, the
largest joint forces and the shaking. Run here as it is, its pictures written to a scratch
folder rather than ``docs/``.
"""
import importlib.util
import os
import tempfile

import matplotlib.image as mpimg
import matplotlib.pyplot as plt

ROOT = os.path.abspath(os.path.join("..", ".."))     # docs/gallery/, where it runs


def example(name):
    """The example script examples/NAME.py, imported as a module."""
    spec = importlib.util.spec_from_file_location(name, os.path.join(ROOT, "examples",
                                                                     name + ".py"))
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


def show(path):
    """A picture the example wrote, shown here."""
    fig, ax = plt.subplots(figsize=(8, 6))
    ax.imshow(mpimg.imread(path))
    ax.set_axis_off()
    fig.tight_layout()


demo = example("quick_return_forces_demo")
demo.ROOT = scratch = tempfile.mkdtemp()      # its module and pictures go here, not docs/
demo.main()

# %%
# The pictures it drew.
for name in ("torque", "draw", "polar"):
    show(os.path.join(scratch, "docs", f"quick_return_forces_{name}.png"))
