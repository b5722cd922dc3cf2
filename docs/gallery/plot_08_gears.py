"""
Gears and racks
===============

Mech's gears: ``examples/gear_train.py`` (two stages, one of them ``gear_ratio`` and the
other ``gears``), ``examples/internal_gear.py`` (a pinion inside a ring gear, a negative
pitch radius, and a planetary set) and ``examples/rack_pinion.py`` (a pinion on a fixed
shaft driving a rack, and a pinion rolling along a fixed rack).
"""
import os

import mechgen
from mechgen import plot

ROOT = os.path.abspath(os.path.join("..", ".."))     # docs/gallery/, where it runs
EXAMPLES = os.path.join(ROOT, "examples")

MODELS = (("gear_train.py", None), ("internal_gear.py", "internal_gear"),
          ("internal_gear.py", "planetary"), ("rack_pinion.py", "rack_pinion"),
          ("rack_pinion.py", "rolling_pinion"))
for path, name in MODELS:
    model = mechgen.load_model(os.path.join(EXAMPLES, path), name=name)
    mech = mechgen.compile(model)
    s = mech.solve(0.1, level="velocity")
    rates = ", ".join(f"{c}d = {s[c + 'd']:.4g}" for c in mech.coordinates if c.startswith("Th"))
    print(f"{model.name}: {rates}")
    plot.draw(mech, s, title=f"{model.name} at T = 0.1")
