"""Disc cam driving an oscillating roller-follower arm, designed from its motion law.

The cam turns at ω about the origin (angle φ = ωT, driven kinematically: no return
spring, the roller stays on the profile by the constraint). The arm turns about a ground
pivot A = (a, 0); its roller, of radius ρ, is centred L along it. Over one turn of the cam
the arm swings by a cycloidal rise of h (towards the cam's outside), a dwell, a cycloidal
return and a dwell: ψ(φ) = ψ0 − s(φ). The roller centre C(φ) = A + L (cos ψ, sin ψ) traces
the pitch curve P(φ) = R(−φ) C(φ) in the cam's frame; the profile is P offset by ρ
towards the cam. Solving the mechanism gives the law back: Th_arm = ψ0 − s(ωT), the
contact parameter phi = ωT.
"""
from mechgen import Piecewise, T, cos, pi, sin, sqrt
from mechgen import Model

m = Model("cam_roller_arm")

h = m.param("h", 0.3)           # swing of the arm (rad)
a = m.param("a", 6.0)           # arm pivot, on the x axis
L = m.param("L", 4.5)           # arm length, pivot to roller centre
psi0 = m.param("psi0", 2.7)     # arm angle at the dwell nearest the cam
rho = m.param("rho", 0.5)       # roller radius
omega = m.param("omega", 2 * pi)
beta = 2 * pi / 3               # rise (and return) over 120°, dwell 60°, return, dwell 60°


def swing(phi):
    """s(φ) over one turn, 0 <= φ < 2π: rise, dwell, return, dwell (cycloidal)."""
    x1, x2 = phi / beta, (phi - pi) / beta
    return Piecewise((h * (x1 - sin(2 * pi * x1) / (2 * pi)), phi < beta),
                     (h, phi < pi),
                     (h * (1 - x2 + sin(2 * pi * x2) / (2 * pi)), phi < pi + beta),
                     (0, True))


def profile_xy(phi):
    """The cam profile: the pitch curve P(φ) offset by ρ towards the cam."""
    psi = psi0 - swing(phi)
    cx, cy = a + L * cos(psi), L * sin(psi)
    px, py = cx * cos(phi) + cy * sin(phi), -cx * sin(phi) + cy * cos(phi)   # R(−φ) C
    dx, dy = px.diff(phi), py.diff(phi)
    n = sqrt(dx ** 2 + dy ** 2)
    return px + rho * dy / n, py - rho * dx / n     # P − ρ n, n = (−P'y, P'x)/|P'| (clockwise)


ground = m.ground("ground", points=[(0, 0), (a, 0)])
cam = m.body("cam", guess=(0, 0, 0))
arm = m.body("arm", points=[(0, 0), (L, 0)], guess=(6.0, 0, 2.7))

m.revolute(ground[1], cam[0])
m.rotation_lock(cam, omega * T, name="cam angle")
m.revolute(ground[2], arm[1])
disc = m.profile("disc", xy=profile_xy, periodic=True)
m.cam_to_point(cam, disc, arm[2], contact="phi", guess=0.0, radius=rho)
