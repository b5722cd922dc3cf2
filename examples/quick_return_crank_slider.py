"""Quick-return mechanism of seed 001 handed over from one driver to another (Mech's
StageSwitch): driven by its crank (section 2A) up to T = 0.25, when the crank stands
upright, the lever is vertical and the slider at X4 = sqrt(24); driven by its slider
(section 2B) after it, X4 = sqrt(24) + amplitud sin(2 pi (T - 0.25)), a law chosen to start
where the crank left the slider. The positions are continuous at the switch."""
from mechgen import Model, T, pi, sin, sqrt

m = Model("quick_return_crank_slider")

longitud = m.param("longitud", 3.0)
velocidad = m.param("velocidad", 2 * pi)
amplitud = m.param("amplitud", 1.0)

base = m.ground("base", points=[(0, 0), (0, 5), (-5, 10), (12, 10)])
manivela = m.body("manivela", points=[(0, 0), (longitud, 0)], guess=(0, 5, 0))
colisa = m.body("colisa", points=[(0, 0), (0, 9)], guess=(0, 0, -0.5))
deslizadera = m.body("deslizadera", points=[(0, 0), (2, 0)], guess=(6, 10, 0))

m.revolute(base[2], manivela[1])
m.revolute(base[1], colisa[1])
m.point_on_line(manivela[2], colisa.line(1, 2))
m.relative_distance(colisa[2], deslizadera[1], 5)
m.translate(base.line(3, 4), deslizadera.line(1, 2))
with m.stage("crank", until=0.25):
    m.rotation_lock(manivela, base, velocidad * T, name="crank driver")
with m.stage("slider"):
    m.relative_x(deslizadera[1], sqrt(24) + amplitud * sin(2 * pi * (T - 0.25)),
                 name="slider driver")
