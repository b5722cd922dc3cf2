"""
The main job: quick_return_demo
===============================

``examples/quick_return_demo.py`` builds the quick-return, solves it, prints what Mech
prints and draws the seed's pictures (the mechanism with the seed's own base outline and
crank disk, an animation of one turn, the slider's stroke for three crank lengths). Run
here as it is, its pictures written to a scratch folder rather than ``docs/``.
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


demo = example("quick_return_demo")
demo.ROOT = scratch = tempfile.mkdtemp()      # its module and pictures go here, not docs/
demo.main()

# %%
# The pictures it drew (the animation is ``quick_return.gif`` beside them).
for name in ("quick_return.png", "quick_return_x4.png"):
    show(os.path.join(scratch, "docs", name))
