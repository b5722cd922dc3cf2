"""Four-bar linkage of seed 000 by its vector loop a e^{iθ2} + b e^{iθ3} − c e^{iθ4} − d = 0,
split into real and imaginary parts: two equations in θ3, θ4 (equations 1.1.2, 1.1.3)."""
from mechgen import Model, T, cos, pi, sin

m = Model("fourbar_loop")

a = m.param("a", 0.8)
b = m.param("b", 2.5)
c = m.param("c", 2.0)
d = m.param("d", 3.0)
theta1 = m.param("theta1", 0.0)
theta2 = m.param("theta2", pi / 3)
omega = m.param("omega", 0.0)

th3 = m.coordinate("theta3", guess=0.5)
th4 = m.coordinate("theta4", guess=1.8)

th2 = theta2 + omega * T
m.constraint(a * cos(th2) + b * cos(th3) - c * cos(th4) - d * cos(theta1), name="loop real")
m.constraint(a * sin(th2) + b * sin(th3) - c * sin(th4) - d * sin(theta1), name="loop imaginary")
