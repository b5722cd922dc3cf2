"""Disc cam with an offset translating roller follower, designed from its motion law.

The follower displacement over one turn of the cam (angle φ) is a cycloidal rise of h over
β, a dwell, a cycloidal return over β and a dwell. The roller centre travels on the pitch
curve P(φ) = R(−φ) (e, d0 + s(φ)) in the cam's frame (e the offset of the follower's axis,
d0 = √(rb² − e²), rb the base radius of the pitch curve); the cam profile is the pitch
curve offset inward by the roller radius ρ. Solving the mechanism gives the motion law
back: Y3 = d0 + s(ωT), Y3d = ω s', Y3dd = ω² s'' (tests/test_cams.py).
"""
from mechgen import Model, Piecewise, T, cos, pi, sin, sqrt

m = Model("cam_cycloidal")

h = m.param("h", 2.0)           # lift
e = m.param("e", 1.0)           # offset of the follower's axis
rb = m.param("rb", 5.0)         # base radius of the pitch curve
rho = m.param("rho", 0.75)      # roller radius
omega = m.param("omega", 2 * pi)
beta = 2 * pi / 3               # rise (and return) over 120°, dwell 60°, return, dwell 60°
d0 = sqrt(rb ** 2 - e ** 2)


def lift(phi):
    """s(φ) over one turn, 0 <= φ < 2π: rise, dwell, return, dwell (cycloidal)."""
    x1, x2 = phi / beta, (phi - pi) / beta
    return Piecewise((h * (x1 - sin(2 * pi * x1) / (2 * pi)), phi < beta),
                     (h, phi < pi),
                     (h * (1 - x2 + sin(2 * pi * x2) / (2 * pi)), phi < pi + beta),
                     (0, True))


def profile_xy(phi):
    """The cam profile: the pitch curve P(φ) offset by ρ towards the cam."""
    y = d0 + lift(phi)
    px, py = e * cos(phi) + y * sin(phi), -e * sin(phi) + y * cos(phi)   # R(−φ) (e, y)
    dx, dy = px.diff(phi), py.diff(phi)
    n = sqrt(dx ** 2 + dy ** 2)
    return px + rho * dy / n, py - rho * dx / n     # P − ρ n, n = (−P'y, P'x)/|P'| (clockwise)


ground = m.ground("ground", points=[(0, 0), (e, 0), (e, 1)])
cam = m.body("cam", guess=(0, 0, 0))
follower = m.body("follower", points=[(0, 0), (0, 2)], guess=(1, 4.9, 0))

m.revolute(ground[1], cam[0])
m.rotation_lock(cam, omega * T, name="cam angle")
m.translate(ground.line(2, 3), follower.line(1, 2))
disc = m.profile("disc", xy=profile_xy, periodic=True)
m.cam_to_point(cam, disc, follower[1], contact="phi", guess=0.0, radius=rho)
