"""The stage example of docs/constraints.md (section "stages"): a crank that turns out and
back, its driver switching law at T = 0.5. Print it with
``mechgen equations docs/stage_examples.py``."""
from mechgen import Model, T, pi

m = Model("stages")
w = m.param("w", 2 * pi)
base = m.ground("base", points=[(0, 0)])
a = m.body("a", points=[(0, 0), (2, 0)], guess=(0, 0, 0))
m.revolute(base[1], a[1])
with m.stage("out", until=0.5):
    m.rotation_lock(a, w * T, name="turn out")
with m.stage("back"):
    m.rotation_lock(a, w * (1 - T), name="turn back")
