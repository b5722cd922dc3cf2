"""One small model per constraint form, for the constraint reference (docs/constraints.md).

Every model has the same parts: the ground ``base`` with points P1 = (0, 0), P2 = (4, 0),
P3 = (4, 3), and two moving bodies, ``a`` (body 2: X2, Y2, Th2; P1 = (0, 0), P2 = (2, 0))
and ``b`` (body 3: X3, Y3, Th3; P1 = (0, 0), P2 = (0, 1)), and a parameter ``L`` (5).
Each model holds one constraint, so that

    mechgen equations docs/constraint_examples.py --model point_on_line

prints that constraint's rows alone. The reference quotes those rows; a test
(tests/test_constraint_reference.py) checks that they are what the printer gives today.
The models are not meant to move (one constraint does not make a mechanism).
"""
from mechgen import Line, Model, T, pi, sin


def parts(name):
    """A model ``name`` with the common parts: (model, base, a, b, L)."""
    m = Model(name)
    L = m.param("L", 5.0)
    base = m.ground("base", points=[(0, 0), (4, 0), (4, 3)])
    a = m.body("a", points=[(0, 0), (2, 0)], guess=(0, 0, 0))
    b = m.body("b", points=[(0, 0), (0, 1)], guess=(2, 0, 0))
    return m, base, a, b, L

m1, base, a, b, L = parts("revolute")
m1.revolute(a[2], b[1])

m2, base, a, b, L = parts("translate")
m2.translate(base.line(1, 2), a.line(1, 2))

m3, base, a, b, L = parts("point_on_line")
m3.point_on_line(a[2], b.line(1, 2))

m4, base, a, b, L = parts("relative_distance")
m4.relative_distance(a[2], b[1], L)

m5, base, a, b, L = parts("rotation_lock")
m5.rotation_lock(a, b, pi / 2)

m6, base, a, b, L = parts("rotation_lock_driver")
m6.rotation_lock(a, base, 2 * pi * T)

m7, base, a, b, L = parts("rotation_lock_one")
m7.rotation_lock(a, pi / 4)

m8, base, a, b, L = parts("relative_x")
m8.relative_x(a[2], 3)

m9, base, a, b, L = parts("relative_x_two")
m9.relative_x(a[2], b[1], L)

m10, base, a, b, L = parts("relative_x_driver")
m10.relative_x(b[1], 4 + sin(2 * pi * T))

m11, base, a, b, L = parts("relative_y")
m11.relative_y(a[2], 1)

m12, base, a, b, L = parts("relative_y_two")
m12.relative_y(base[3], b[2], L)

m13, base, a, b, L = parts("parallel")
m13.parallel(a.line(1, 2), b.line(1, 2))

m14, base, a, b, L = parts("orthogonal")
m14.orthogonal(a.line(1, 2), b.line(1, 2))

m15, base, a, b, L = parts("relative_angle")
m15.relative_angle(a.line(1, 2), b.line(1, 2), pi / 3)

m16, base, a, b, L = parts("relative_angle_general")
m16.relative_angle(base.line(1, 2), Line(a[2], b[1]), pi / 3)

m17, base, a, b, L = parts("constraint")
m17.constraint(a.x**2 + a.y**2 - L**2)

m18, base, a, b, L = parts("origin")
m18.revolute(base[3], a[0])

m19, base, a, b, L = parts("at_point")
m19.point_on_line(b.at(1, 2), Line(base[1], direction=(1, 1)))

m20, base, a, b, L = parts("named")
m20.revolute(a[2], b[1], name="elbow")

# cams (mechgen.model.library2d.cams): body a carries the profile, b follows; one constraint each
cam1, base, a, b, L = parts("cam_to_point")
disc = cam1.profile("disc", polar=lambda th: L / 2 + sin(th) / 2)
cam1.cam_to_point(a, disc, b[1], contact="s", guess=1.5)

cam2, base, a, b, L = parts("cam_to_point_roller")
disc = cam2.profile("disc", polar=lambda th: L / 2 + sin(th) / 2)
cam2.cam_to_point(a, disc, b[1], contact="s", guess=1.5, radius=0.4)

cam3, base, a, b, L = parts("cam_to_line")
disc = cam3.profile("disc", polar=lambda th: L / 2 + sin(th) / 2)
cam3.cam_to_line(a, disc, b.line(1, 2), contact="s", guess=0.0)

cam4, base, a, b, L = parts("cam_to_cam")
disc = cam4.profile("disc", polar=lambda th: L / 2 + sin(th) / 2)
oval = cam4.profile("oval", xy=lambda s: (2 * sin(s), L * sin(s + pi / 2) / 4))
cam4.cam_to_cam(a, disc, b, oval, contact=("s1", "s2"), guess=(0.0, pi))

# -- Mech's 2D library: gears, racks, more constraints, joints with a coordinate, loops
from mechgen import I, exp  # noqa: E402

m21, base, a, b, L = parts("gears")
m21.gears(a[1], 1, b[1], 2)

m22, base, a, b, L = parts("gear_ratio")
m22.gear_ratio(a[1], 1, b[1], -3)

m23, base, a, b, L = parts("rack_and_pinion")
m23.rack_and_pinion(b[1], 0.5, base.line(1, 2))

m24, base, a, b, L = parts("rack_ratio")
m24.rack_ratio(b[1], 0.5, a.line(1, 2), 1)

m25, base, a, b, L = parts("point_on_lines")
m25.point_on_lines(b[1], base.line(1, 3), a.line(1, 2))

m26, base, a, b, L = parts("origin_lock")
m26.origin_lock(a, b)

m27, base, a, b, L = parts("origin_lock_offset")
m27.origin_lock(a, (1, L))

m28, base, a, b, L = parts("directed_distance")
m28.directed_distance(a[2], b[1], base.line(1, 2), L)

m29, base, a, b, L = parts("directed_distance_origin")
m29.directed_distance(a[2], (3, 4))

m30, base, a, b, L = parts("gen_revolute")
m30.gen_revolute(base.line(1, 2), a.line(1, 2), "phi")

m31, base, a, b, L = parts("gen_translate")
m31.gen_translate(base.line(1, 2), a.line(1, 2), "s")

m32, base, a, b, L = parts("loop")
m32.loop(2 * exp(I * a.th) + L * exp(I * b.th) - 4)
