"""The quick-return of seed 001 as a family of designs: the crank's length, the height of
the crank's pivot (base[2]) and the slotted lever's length (colisa[2]) are parameters,
for dimensional synthesis (mech.optimize; see the README)."""
from mechgen import Model, T, pi, location

m = Model("quick_return_synthesis")

longitud = m.param("longitud", 3.0)      # crank length
altura = m.param("altura", 5.0)          # height of the crank's pivot above the lever's
palanca = m.param("palanca", 9.0)        # slotted lever's length
velocidad = m.param("velocidad", 2 * pi)

base = m.ground("base", points=[(0, 0), (0, altura), (-5, 10), (12, 10)])
manivela = m.body("manivela", points=[(0, 0), (longitud, 0)], guess=(0, 5, 0))
colisa = m.body("colisa", points=[(0, 0), (0, palanca)], guess=(0, 0, -0.5))
deslizadera = m.body("deslizadera", points=[(0, 0), (2, 0)], guess=(6, 10, 0))

m.revolute(base[2], manivela[1])
m.rotation_lock(manivela, base, velocidad * T, name="crank driver")
m.revolute(base[1], colisa[1])
m.point_on_line(manivela[2], colisa.line(1, 2))
m.relative_distance(colisa[2], deslizadera[1], 5)
m.translate(base.line(3, 4), deslizadera.line(1, 2))
