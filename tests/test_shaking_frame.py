"""sw.shaking(): what the moving parts apply to the frame (docs/reference/forces.md), through the
constraints and through the loads anchored on it (a motor between a body and the ground,
a spring or a damper to a ground point), against the closed form of one body: the frame
takes the inertia forces and the loads that come from outside, Σ F_outside − m a_G and
Σ M_outside − (J α + r_G × m a_G), however the model's motor is written."""
import numpy as np
import pytest

import mechgen
from mechgen import Model, T, sin

M, J, C = 1.5, 0.2, (0.3, 0.1)          # the crank's mass, inertia and centroid
W, A = 2.0, 0.4                          # its angle: W T + A sin T
K, L0, CD = 30.0, 0.5, 0.7               # the spring and the damper
G = 9.81
GROUND = [(0, 0), (1.0, -0.8), (-0.6, -0.9)]
CRANK = [(0, 0), (0.5, 0), (0.2, 0.35)]


def _model(name, motor, gravity=False):
    """A crank pinned at the ground's origin, its angle prescribed, with a spring and a
    damper from ground points to its points and a motor moment of 3 + T: between the crank
    and the ground (motor "frame"), on the crank alone ("body") or none."""
    m = Model(name)
    base = m.ground("base", points=GROUND)
    crank = m.body("crank", points=CRANK, guess=(0, 0, 0.1), mass=M, inertia=J, centroid=C)
    m.revolute(base[1], crank[1], name="pin")
    m.rotation_lock(crank, base, W * T + A * sin(T), name="drive")
    m.spring(base[2], crank[2], K, L0, name="spring")
    m.damper(crank[3], base[3], CD, name="damper")
    if motor == "frame":
        m.moment(crank, base, 3 + T, name="motor")
    elif motor == "body":
        m.moment(crank, 3 + T, name="motor")
    if gravity:
        m.gravity(G)
    return m


def _closed(t, outside_moment, gravity):
    """(fx, fy, moment about the origin) the frame takes, by hand: the crank's angle θ, its
    centroid r_G = R(θ) c and a_G = α k × r_G − ω² r_G."""
    th = W * t + A * np.sin(t)
    om = W + A * np.cos(t)
    al = -A * np.sin(t)
    c, s = np.cos(th), np.sin(th)
    rx, ry = c * C[0] - s * C[1], s * C[0] + c * C[1]
    ax, ay = -al * ry - om * om * rx, al * rx - om * om * ry
    fx, fy = -M * ax, -M * ay
    mz = -(J * al + M * (rx * ay - ry * ax)) + outside_moment
    if gravity:
        fy -= M * G
        mz += rx * (-M * G)
    return np.column_stack([fx, fy, mz])


@pytest.mark.parametrize("motor,gravity", [("frame", False), ("body", False), (None, True)])
def test_shaking_takes_the_loads_anchored_on_the_frame(tmp_path, motor, gravity):
    mech = mechgen.compile(_model(f"shake_{motor}_{gravity}", motor, gravity),
                           outdir=str(tmp_path), tier="python")
    assert mech.module.FRAME_LOADS
    sw = mech.sweep(0.0, 3.0, 13, level="dynamic")
    outside = (3 + sw.t) if motor == "body" else 0.0     # a moment on the crank alone
    want = _closed(sw.t, outside, gravity)
    assert np.max(np.abs(sw.shaking() - want)) < 1e-11 * (1 + np.max(np.abs(want)))


def test_shaking_equals_the_ground_reactions_and_the_anchored_loads(tmp_path):
    # the same sum by another way: minus the reactions of the constraints on the ground,
    # plus the opposite of the spring's, damper's and motor's pull on the crank, each from
    # the sweep's own positions and velocities
    mech = mechgen.compile(_model("shake_sum", "frame"), outdir=str(tmp_path), tier="python")
    sw = mech.sweep(0.0, 3.0, 13, level="dynamic")
    total = np.zeros((len(sw.t), 3))
    for name in ("pin", "drive"):
        r = sw.reaction(name, on="base")               # about the base's origin
        total += r
    X, Y, Th = sw["X2"], sw["Y2"], sw["Th2"]
    Xd, Yd, Thd = sw["X2d"], sw["Y2d"], sw["Th2d"]

    def glob(p):
        c, s = np.cos(Th), np.sin(Th)
        return X + c * p[0] - s * p[1], Y + s * p[0] + c * p[1]

    def rate(p):
        c, s = np.cos(Th), np.sin(Th)
        return Xd - Thd * (s * p[0] + c * p[1]), Yd + Thd * (c * p[0] - s * p[1])

    # the spring pulls the crank's point towards its ground point; the frame takes the
    # opposite at the ground point
    px, py = glob(CRANK[1])
    dx, dy = px - GROUND[1][0], py - GROUND[1][1]
    ln = np.hypot(dx, dy)
    f = K * (ln - L0)
    fx, fy = f * dx / ln, f * dy / ln                  # on the frame, at its point
    total += np.column_stack([fx, fy, GROUND[1][0] * fy - GROUND[1][1] * fx])
    px, py = glob(CRANK[2])
    vx, vy = rate(CRANK[2])
    dx, dy = px - GROUND[2][0], py - GROUND[2][1]
    ln = np.hypot(dx, dy)
    f = CD * (dx * vx + dy * vy) / ln
    fx, fy = f * dx / ln, f * dy / ln
    total += np.column_stack([fx, fy, GROUND[2][0] * fy - GROUND[2][1] * fx])
    total[:, 2] -= 3 + sw.t                            # the motor's stator
    assert np.max(np.abs(sw.shaking() - total)) < 1e-10 * (1 + np.max(np.abs(total)))


def test_a_model_without_loads_on_the_frame_writes_the_stub(tmp_path):
    m = Model("shake_none")
    base = m.ground("base", points=[(0, 0)])
    crank = m.body("crank", points=[(0, 0), (1, 0)], guess=(0, 0, 0), mass=1.0)
    m.revolute(base[1], crank[1])
    m.rotation_lock(crank, base, T)
    m.moment(crank, 2.0)
    mech = mechgen.compile(m, outdir=str(tmp_path), tier="python")
    assert not mech.module.FRAME_LOADS
    out = np.ones(mech.n)
    mech.module.frame_loads(np.zeros(mech.n), np.zeros(mech.n), 0.0, mech.p, out)
    assert not out.any()
