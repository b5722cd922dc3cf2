"""Four-bar linkage of seed 000 as bodies joined by revolutes: crank a = 0.8, coupler
b = 2.5, rocker c = 2, ground d = 3, crank angle θ2 = π/3 (+ ω T)."""
from mechgen import Model, T, pi

m = Model("fourbar")

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

m.revolute(ground[1], crank[1])
m.revolute(crank[2], coupler[1])
m.revolute(ground[2], rocker[1])
m.revolute(coupler[2], rocker[2])
m.rotation_lock(crank, theta2 + omega * T, name="crank angle")
