"""Quick-return mechanism of seed 001 in two stages (Mech's TimeSwitch): the crank turns
forward, angle velocidad*T, up to T = 0.5 and back, velocidad*(1 - T), after it. The
positions are continuous at the switch; the velocities reverse there."""
from mechgen import Model, T, pi, location

m = Model("quick_return_stages")

longitud = m.param("longitud", 3.0)
velocidad = m.param("velocidad", 2 * pi)

base = m.ground("base", points=[(0, 0), (0, 5), (-5, 10), (12, 10)])
manivela = m.body("manivela", points=[(0, 0), (longitud, 0)], guess=(0, 5, 0))
colisa = m.body("colisa", points=[(0, 0), (0, 9)], guess=(0, 0, -0.5))
deslizadera = m.body("deslizadera", points=[(0, 0), (2, 0)], guess=(6, 10, 0))

m.revolute(base[2], manivela[1])
with m.stage("forward", until=0.5):
    m.rotation_lock(manivela, base, velocidad * T, name="crank forward")
with m.stage("back"):
    m.rotation_lock(manivela, base, velocidad * (1 - T), name="crank back")
m.revolute(base[1], colisa[1])
m.point_on_line(manivela[2], colisa.line(1, 2))
m.relative_distance(colisa[2], deslizadera[1], 5)
m.translate(base.line(3, 4), deslizadera.line(1, 2))

m.output("stroke_x", location(deslizadera[1])[0])
