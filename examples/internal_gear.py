"""Internal gears: a pinion meshing inside a ring gear (a negative pitch radius), and a
planetary set.

``internal_gear``: pinion (radius rp) and ring (radius −rr) on fixed shafts rr − rp
apart; both turn the same way, ω_ring / ω_pinion = rp / rr.

``planetary``: the sun (rs) on the input shaft drives a planet (rp) carried by an arm,
which also meshes with the fixed ring (the ground, radius −(rs + 2 rp)). The arm turns at
ω_arm = ω_sun rs / (rs + rr) and the planet at ω_planet = ω_arm − (rs/rp)(ω_sun − ω_arm)
(Willis). The planets' centre line turns with the arm: the rolling rows need no fixed
direction."""
from mechgen import Model, T, pi

m = Model("internal_gear")
rp = m.param("rp", 1.0)
rr = m.param("rr", 2.5)
omega = m.param("omega", 2 * pi)
base = m.ground("base", points=[(0, 0), (rr - rp, 0)])
ring = m.body("ring", points=[(0, 0), (rr, 0)], guess=(0, 0, 0))
pinion = m.body("pinion", points=[(0, 0), (rp, 0)], guess=(rr - rp, 0, 0))
m.revolute(base[1], ring[1], name="ring shaft")
m.revolute(base[2], pinion[1], name="pinion shaft")
m.gear_ratio(pinion[1], rp, ring[1], -rr, name="mesh")
m.rotation_lock(pinion, omega * T, name="input")

p = Model("planetary")
rs = p.param("rs", 1.0)
rq = p.param("rq", 0.75)
w = p.param("omega", 2 * pi)
frame = p.ground("frame", points=[(0, 0)])
sun = p.body("sun", points=[(0, 0), (rs, 0)], guess=(0, 0, 0))
arm = p.body("arm", points=[(0, 0), (rs + rq, 0)], guess=(0, 0, 0))
planet = p.body("planet", points=[(0, 0), (rq, 0)], guess=(rs + rq, 0, 0))
p.revolute(frame[1], sun[1], name="sun shaft")
p.revolute(frame[1], arm[1], name="arm shaft")
p.revolute(arm[2], planet[1], name="planet pin")
p.gear_ratio(sun[1], rs, planet[1], rq, name="sun-planet")
p.gear_ratio(planet[1], rq, frame[1], -(rs + 2 * rq), name="planet-ring")
p.rotation_lock(sun, w * T, name="input")
