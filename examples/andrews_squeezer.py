"""Andrews' squeezing mechanism: the seven-body benchmark of multibody integrators
(Hairer & Wanner, Solving ODEs II, VII.7; the IVP test set's "andrews" problem).

A crank (body 1, about O) turned by a constant motor torque drives, through body 2, the
joint E where three further pairs of links meet: body 3 (about B) with a stiff spring to
C, bodies 4–5 (about A) and bodies 6–7 (about A). Seven bodies, ten pins, one degree of
freedom and no driver: the build holds the crank's angle at its guess for the kinematics,
and ``mech.simulate(0, 0.03, ...)`` lets the torque turn it (tests/test_andrews.py and
benchmarks/bench_andrews.py compare with the test set's published solution at t = 0.03).

Hairer's coordinates are relative angles: β = Th1, Θ = Th2 − Th1, γ = Th3, Φ = Th4 − Th5,
δ = Th5, Ω = Th6 − Th7, ε = Th7. The guess is the test set's consistent start. Lengths
in m, masses in kg, inertias in kg m² (about each centroid), the torque in N m.
"""
from math import cos, sin

from mechgen import Model

m = Model("andrews_squeezer")

# the test set's data
m1, m2, m3, m4, m5, m6, m7 = .04325, .00365, .02373, .00706, .07050, .00706, .05498
i1, i2, i3, i4, i5, i6, i7 = 2.194e-6, 4.410e-7, 5.255e-6, 5.667e-7, 1.169e-5, 5.667e-7, 1.912e-5
xa, ya, xb, yb, xc, yc = -.06934, -.00227, -.03635, .03273, .014, .072
d, da, e, ea, rr, ra = 28e-3, 115e-4, 2e-2, 1421e-5, 7e-3, 92e-5
ss, sa, sb, sc, sd = 35e-3, 1874e-5, 1043e-5, 18e-3, 2e-2
ta, tb, u, ua, ub = 2308e-5, 916e-5, 4e-2, 1228e-5, 449e-5
zf, zt, fa = 2e-2, 4e-2, 1421e-5
c0, l0 = 4530.0, 7785e-5

mom = m.param("mom", 0.033)              # the motor's torque on the crank

# the start: β, Θ, γ, Φ, δ, Ω, ε of the test set
beta, theta, gamma = -0.0617138900142764496358948458001, 0.0, 0.455279819163070380255912382449
phi, delta = 0.222668390165885884674473185609, 0.487364979543842550225598953530
omega, eps = -0.222668390165885884674473185609, 1.23054744454982119249735015568


O = (0.0, 0.0)
F = (rr * cos(beta), rr * sin(beta))                # the crank pin
G = (xa + zt * cos(delta), ya + zt * sin(delta))    # body 5's pin of body 4
H = (xa + u * sin(eps), ya - u * cos(eps))          # body 7's pin of body 6

frame = m.ground("frame", points=[O, (xa, ya), (xb, yb), (xc, yc)])       # O, A, B, C
crank = m.body("crank", points=[(0, 0), (rr, 0)], guess=(0, 0, beta),
               mass=m1, inertia=i1, centroid=(ra, 0))                     # O, F
rod = m.body("rod", points=[(0, 0), (-d, 0)], guess=(*F, beta + theta),
             mass=m2, inertia=i2, centroid=(-da, 0))                      # F, E
arm3 = m.body("arm3", points=[(0, 0), (0, -ss), (sd, -sc)], guess=(xb, yb, gamma),
              mass=m3, inertia=i3, centroid=(sa, sb))                     # B, E, D
link4 = m.body("link4", points=[(0, 0), (0, -e)], guess=(*G, phi + delta),
               mass=m4, inertia=i4, centroid=(0, -(e - ea)))              # G, E
arm5 = m.body("arm5", points=[(0, 0), (zt, 0)], guess=(xa, ya, delta),
              mass=m5, inertia=i5, centroid=(ta, tb))                     # A, G
link6 = m.body("link6", points=[(0, 0), (zf, 0)], guess=(*H, omega + eps),
               mass=m6, inertia=i6, centroid=(zf - fa, 0))                # H, E
arm7 = m.body("arm7", points=[(0, 0), (0, -u)], guess=(xa, ya, eps),
              mass=m7, inertia=i7, centroid=(ua, ub))                     # A, H

m.revolute(frame[1], crank[1], name="O")
m.revolute(crank[2], rod[1], name="F")
m.revolute(rod[2], arm3[2], name="E3")
m.revolute(frame[3], arm3[1], name="B")
m.revolute(rod[2], link4[2], name="E4")
m.revolute(link4[1], arm5[2], name="G")
m.revolute(frame[2], arm5[1], name="A5")
m.revolute(rod[2], link6[2], name="E6")
m.revolute(link6[1], arm7[2], name="H")
m.revolute(frame[2], arm7[1], name="A7")

m.moment(crank, mom, name="motor")
m.spring(frame[4], arm3[3], c0, l0, name="spring")                        # C to D
