"""The quick-return of seed 001 with masses, gravity and a cutting force: the torque the
crank's motor must give, the load on every pin, the shaking of the frame and the
flywheel (docs/reference/forces.md). The kinematics is examples/quick_return.py's; the cutting force
(``corte``) resists the slider while it moves to the left: the slow stroke, 70 % of the
crank's turn (the tool cuts slowly and returns quickly, as a shaper does)."""
from mechgen import Model, Piecewise, T, pi, velocity

m = Model("quick_return_forces")

longitud = m.param("longitud", 3.0)
velocidad = m.param("velocidad", 2 * pi)
anguloI = m.param("anguloI", 0.0)
corte = m.param("corte", 500.0)

base = m.ground("base", points=[(0, 0), (0, 5), (-5, 10), (12, 10)])
manivela = m.body("manivela", points=[(0, 0), (longitud, 0)], guess=(0, 5, 0),
                  mass=2.0, inertia=1.5, centroid=(longitud / 2, 0))
colisa = m.body("colisa", points=[(0, 0), (0, 9)], guess=(0, 0, -0.5),
                mass=5.0, inertia=33.75, centroid=(0, 4.5))
deslizadera = m.body("deslizadera", points=[(0, 0), (2, 0)], guess=(6, 10, 0),
                     mass=3.0, inertia=1.0, centroid=(1, 0.2))

m.revolute(base[2], manivela[1], name="O2")
m.rotation_lock(manivela, base, velocidad * T + anguloI, name="crank driver")
m.revolute(base[1], colisa[1], name="O4")
m.point_on_line(manivela[2], colisa.line(1, 2), name="slot")
m.relative_distance(colisa[2], deslizadera[1], 5, name="link")
m.translate(base.line(3, 4), deslizadera.line(1, 2), name="guide")

m.gravity(9.807)
slider_speed = velocity(deslizadera[1])[0]
m.force(deslizadera[1], (Piecewise((corte, slider_speed < 0), (0, True)), 0), name="cutting")
