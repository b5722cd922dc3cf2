"""A mechanical press: a crank-slider driven by an induction-like motor whose torque falls
with speed, T = T0 (1 − ω/ω0), started from rest; the ram meets the work near the bottom
of its stroke (a pressing force while it moves down through the last 20 mm). The crank
carries a flywheel of inertia ``flywheel``. The crank's driver only sets the start
(at rest, crank at the top): `mech.simulate(..., free=["crank driver"])` releases it and
the motor takes over (examples/press_motor_demo.py)."""
from mechgen import Model, Piecewise, T, dt, location, pi, rotation, velocity

m = Model("press_motor")

flywheel = m.param("flywheel", 0.5)      # kg m², on the crank
T0 = m.param("T0", 400.0)                # N m, the motor's stall torque
w0 = m.param("w0", 40.0)                 # rad/s, its no-load speed
press = m.param("press", 3000.0)         # N, the work's resistance
w = m.param("w", 0.0)                    # the start: at rest

r, l = 0.1, 0.45                         # crank and connecting rod, m
base = m.ground("base", points=[(0, 0), (0, -1)])
crank = m.body("crank", points=[(0, 0), (r, 0)], guess=(0, 0, pi / 2), mass=8.0,
               inertia=0.02 + flywheel, centroid=(0.0, 0))
rod = m.body("rod", points=[(0, 0), (l, 0)], guess=(0, r, -pi / 2), mass=6.0,
             inertia=6.0 * l ** 2 / 12, centroid=(l / 2, 0))
ram = m.body("ram", points=[(0, 0), (0, -1)], guess=(0, r - l, 0), mass=40.0, inertia=1.0)

m.revolute(base[1], crank[1], name="main bearing")
m.revolute(crank[2], rod[1], name="crank pin")
m.revolute(rod[2], ram[1], name="wrist pin")
m.translate(base.line(1, 2), ram.line(1, 2), name="guide")
m.rotation_lock(crank, pi / 2 - w * T, name="crank driver")
m.gravity(9.81)
m.moment(crank, -T0 * (1 + dt(rotation(crank)) / w0), name="motor")   # turning clockwise

ram_y = location(ram[1])[1]
ram_speed = velocity(ram[1])[1]
m.force(ram[1], (0, Piecewise((press, (ram_y < -(l - r) + 0.02) & (ram_speed < 0)),
                              (0, True))), name="work")
