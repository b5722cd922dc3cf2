"""Hoekens' straight-line four-bar: a crank (a = 1) about the origin, a rocker (c = 2.5)
about (d = 2, 0), a coupler from the crank pin to the rocker's end (b = 2.5) carrying its
tracing point P at u = 5 along it (the coupler's far end). For a part of each turn P runs
very nearly along a straight line: the linkage examples/straight_line_demo.py fits to a
straight segment, then sizes by its tolerances."""
from mechgen import Model, T, location, pi

m = Model("straight_line")

a = m.param("a", 1.0)          # crank
b = m.param("b", 2.5)          # coupler, crank pin to rocker pin
c = m.param("c", 2.5)          # rocker
d = m.param("d", 2.0)          # ground, between the pivots
u = m.param("u", 5.0)          # the tracing point's distance along the coupler
speed = m.param("speed", 2 * pi)

ground = m.ground("ground", points=[(0, 0), (d, 0)])
crank = m.body("crank", points=[(0, 0), (a, 0)], guess=(0, 0, 0.3))
coupler = m.body("coupler", points=[(0, 0), (b, 0), (u, 0)], guess=(0.95, 0.3, 0.9))
rocker = m.body("rocker", points=[(0, 0), (c, 0)], guess=(2, 0, 1.9))

m.revolute(ground[1], crank[1], name="O2")
m.rotation_lock(crank, ground, speed * T, name="crank driver")
m.revolute(crank[2], coupler[1], name="A")
m.revolute(ground[2], rocker[1], name="O4")
m.revolute(coupler[2], rocker[2], name="B")

m.output("px", location(coupler[3])[0])
m.output("py", location(coupler[3])[1])
