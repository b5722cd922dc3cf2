"""A two-stage gear train: gear A (pitch radius rA) on the input shaft drives gear B (rB)
keyed to gear C (rC) on the middle shaft (one compound body), which drives gear D (rD).

The first stage is a pair of gears on fixed shafts: gear_ratio, the rolling relation
alone (the shafts hold the centre distance). The output shaft is not fixed: gear D's
centre slides in a slot along the ground's x axis, and gears() (Mech's TwoGears2: centre
distance and rolling) holds it in mesh with C. The ratio is exact:
ωD / ωA = (−rA/rB)(−rC/rD) = rA rC / (rB rD)."""
from mechgen import Model, T, pi

m = Model("gear_train")

rA = m.param("rA", 1.0)
rB = m.param("rB", 3.0)
rC = m.param("rC", 1.5)
rD = m.param("rD", 2.5)
omega = m.param("omega", 2 * pi)

base = m.ground("base", points=[(0, 0), (4, 0), (10, 0)])
A = m.body("A", points=[(0, 0), (rA, 0)], guess=(0, 0, 0))
BC = m.body("BC", points=[(0, 0), (rB, 0), (rC, 0)], guess=(4, 0, 0))
D = m.body("D", points=[(0, 0), (rD, 0)], guess=(8, 0, 0))

m.revolute(base[1], A[1], name="input shaft")
m.revolute(base[2], BC[1], name="middle shaft")
m.point_on_line(D[1], base.line(2, 3), name="output slot")
m.gear_ratio(A[1], rA, BC[1], rB, name="stage 1")
m.gears(BC[1], rC, D[1], rD, name="stage 2")
m.rotation_lock(A, omega * T, name="input")
