"""Eccentric circle cam with a flat-faced translating follower (Mech's CamToLine1).

The cam, a circle of radius R whose centre sits e from the cam's pivot, turns at ω; the
follower's flat face (horizontal) slides up and down the vertical axis through the pivot.
Closed form: Y3 = e sin θ + R, θ = ω T (tests/test_cams.py).
"""
from mechgen import Line, Model, T, cos, pi, sin

m = Model("cam_eccentric")
R = m.param("R", 2.0)
e = m.param("e", 0.5)
w = m.param("w", 2 * pi)

ground = m.ground("ground", points=[(0, 0), (0, 1)])
cam = m.body("cam", guess=(0, 0, 0))
follower = m.body("follower", points=[(-1, 0), (1, 0), (0, 1)], guess=(0, 2.0, 0))

m.revolute(ground[1], cam[0])
m.rotation_lock(cam, w * T, name="cam angle")
m.translate(ground.line(1, 2), Line(follower[0], follower[3]))
disc = m.profile("disc", xy=lambda s: (e + R * cos(s), R * sin(s)))
m.cam_to_line(cam, disc, follower.line(1, 2), contact="s", guess=1.5)
