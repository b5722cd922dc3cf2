"""Rack and pinion.

``rack_pinion``: a pinion of pitch radius r turns on a fixed shaft r above the rack's pitch
line; the rack slides along the ground (translate), so the rolling row alone (rack_ratio,
Mech's RackAndPinion1) moves it: its travel is s = r θ.

``rolling_pinion``: the rack is the ground's x axis and the pinion a free body driven by
its angle; rack_and_pinion (Mech's RackAndPinion2) holds its centre r above the rack and
rolls it: the centre's x is c − r θ (turning counter-clockwise, it rolls to the left)."""
from mechgen import Model, T, pi

m = Model("rack_pinion")
r = m.param("r", 0.8)
omega = m.param("omega", pi)
base = m.ground("base", points=[(0, 0), (1, 0), (0, r)])
pinion = m.body("pinion", points=[(0, 0), (r, 0)], guess=(0, r, 0))
rack = m.body("rack", points=[(-3, 0), (3, 0)], guess=(0, 0, 0))
m.revolute(base[3], pinion[1], name="shaft")
m.translate(base.line(1, 2), rack.line(1, 2), name="guide")
m.rack_ratio(pinion[1], r, rack.line(1, 2), 3, name="mesh")
m.rotation_lock(pinion, omega * T, name="input")

p = Model("rolling_pinion")
rad = p.param("r", 0.8)
w = p.param("omega", pi)
c = p.param("c", 1.0)
ground = p.ground("ground", points=[(-4, 0), (4, 0)])
wheel = p.body("wheel", points=[(0, 0), (rad, 0)], guess=(1, 0.8, 0))
p.rack_and_pinion(wheel[1], rad, ground.line(1, 2), c + 4, name="mesh")
p.rotation_lock(wheel, w * T, name="input")
