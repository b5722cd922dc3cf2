"""Four-bar linkage of seed 000, written as the seed writes it: the vector loop

    ecpos := a e^{iθ2} + b e^{iθ3} − c e^{iθ4} − d e^{iθ1} = 0              (1.1.1)

whose real and imaginary parts (Maple's evalc(Re(ecpos)), evalc(Im(ecpos)): equations
1.1.2 and 1.1.3) are two equations in θ3, θ4; m.loop splits it the same way."""
from mechgen import I, Model, T, exp, pi

m = Model("fourbar_loop")

a = m.param("a", 0.8)
b = m.param("b", 2.5)
c = m.param("c", 2.0)
d = m.param("d", 3.0)
theta1 = m.param("theta1", 0.0)
theta2 = m.param("theta2", pi / 3)
omega = m.param("omega", 0.0)

theta3 = m.coordinate("theta3", guess=0.5)
theta4 = m.coordinate("theta4", guess=1.8)

th2 = theta2 + omega * T
m.loop(a * exp(I * th2) + b * exp(I * theta3) - c * exp(I * theta4) - d * exp(I * theta1))
