"""Quick-return mechanism of seed 001, section 2B: driven by the slider, whose position
X4 = 4.13931 + 5.40447 sin 2πT was fitted from a 20-point interpolation of the crank-driven
stroke. It overshoots the true stroke, so the mechanism locks near T = 0.246 and 0.754."""
from mechgen import Model, T, pi, sin

m = Model("quick_return_slider")

longitud = m.param("longitud", 3.0)
centro = m.param("centro", 4.13931)
amplitud = m.param("amplitud", 5.40447)

base = m.ground("base", points=[(0, 0), (0, 5), (-5, 10), (12, 10)])
manivela = m.body("manivela", points=[(0, 0), (longitud, 0)], guess=(0, 5, 1.88496))
colisa = m.body("colisa", points=[(0, 0), (0, 9)], guess=(0, 0, 0.117504))
deslizadera = m.body("deslizadera", points=[(0, 0), (2, 0)], guess=(3.83079, 10, 0))

m.revolute(base[2], manivela[1])
m.revolute(base[1], colisa[1])
m.point_on_line(manivela[2], colisa.line(1, 2))
m.relative_distance(colisa[2], deslizadera[1], 5)
m.translate(base.line(3, 4), deslizadera.line(1, 2))
m.relative_x(deslizadera[1], centro + amplitud * sin(2 * pi * T), name="slider driver")
