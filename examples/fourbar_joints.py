"""Joints with their own coordinate (Mech's GenRevolute2, GenTranslate2).

``fourbar_gen``: the four-bar of seed 000 (examples/fourbar.py), its crank pinned to the
ground by gen_revolute, whose angle phi is a coordinate: the driver is phi − (θ2 + ω T)
and s["phi"] reads the crank angle directly. It moves as fourbar.py, driven by
rotation_lock.

``slider_crank_gen``: a slider-crank whose slider is held by gen_translate; its travel s
along the guide is a coordinate, x = a cos θ + sqrt(b² − (a sin θ)²)."""
from mechgen import Line, Model, T, pi

m = Model("fourbar_gen")
a = m.param("a", 0.8)
b = m.param("b", 2.5)
c = m.param("c", 2.0)
d = m.param("d", 3.0)
theta2 = m.param("theta2", pi / 3)
omega = m.param("omega", 2 * pi)
ground = m.ground("ground", points=[(0, 0), (d, 0)])
crank = m.body("crank", points=[(0, 0), (a, 0)], guess=(0, 0, 1.0))
coupler = m.body("coupler", points=[(0, 0), (b, 0)], guess=(0.4, 0.7, 0.5))
rocker = m.body("rocker", points=[(0, 0), (c, 0)], guess=(3, 0, 1.8))
# the angle from the ground's x axis to the crank's (axes by direction: their angles in
# their bodies are 0 whatever the parameters, and the row reads Th2 - phi)
crank_joint = m.gen_revolute(Line(ground[1], direction=(1, 0)),
                             Line(crank[1], direction=(1, 0)), "phi", guess=1.0)
phi = crank_joint.coordinate
m.revolute(crank[2], coupler[1])
m.revolute(ground[2], rocker[1])
m.revolute(coupler[2], rocker[2])
m.constraint(phi - (theta2 + omega * T), name="crank angle")

s = Model("slider_crank_gen")
ra = s.param("a", 1.0)
rb = s.param("b", 3.0)
w = s.param("omega", 2 * pi)
base = s.ground("base", points=[(0, 0), (1, 0)])
crank2 = s.body("crank", points=[(0, 0), (ra, 0)], guess=(0, 0, 0.3))
rod = s.body("rod", points=[(0, 0), (rb, 0)], guess=(1, 0.3, -0.1))
slider = s.body("slider", points=[(0, 0), (1, 0)], guess=(3.9, 0, 0))
travel = s.coordinate("travel", guess=3.9)
s.revolute(base[1], crank2[1])
s.revolute(crank2[2], rod[1])
s.revolute(rod[2], slider[1])
s.gen_translate(base.line(1, 2), slider.line(1, 2), travel, name="guide")
s.rotation_lock(crank2, 0.3 + w * T, name="input")
