"""Audit of the 2D library (cams, gears, racks, joints with their own coordinate,
loops, stages): each expected value is computed here from the geometry (closed forms,
mpmath), never taken from mechgen."""
import math

import numpy as np
import pytest

import mechgen
from mechgen import Model, T


def _compile(m, tmp_path):
    return mechgen.compile(m, outdir=str(tmp_path), tier="python")


def _same_angle(a, b, tol=1e-9):
    return abs(math.remainder(a - b, 2 * math.pi)) < tol


# -- internal gears declared ring first ---------------------------------------------------
def _internal_pair(ring_first):
    """A pinion (radius 1) at (1.5, 0) inside a ring (radius 2.5) at the origin, both on
    fixed shafts, the pinion driven: with c = 0 every x axis along +x (from the ring's
    centre through the pinion's to the pitch point (2.5, 0)) is a meshing position
    (docs/constraints.md: e1 = e2 = 0), so the ring turns at rp/rr from 0."""
    m = Model("ring_first" if ring_first else "pinion_first")
    b = m.ground("b", points=[(0, 0), (1.5, 0)])
    ring = m.body("ring", points=[(0, 0)], guess=(0, 0, 0))
    pin = m.body("pin", points=[(0, 0)], guess=(1.5, 0, 0))
    m.revolute(b[1], ring[1])
    m.revolute(b[2], pin[1])
    if ring_first:
        m.gear_ratio(ring[1], -2.5, pin[1], 1.0)
    else:
        m.gear_ratio(pin[1], 1.0, ring[1], -2.5)
    m.rotation_lock(pin, 2 * T)
    return m


@pytest.mark.parametrize("ring_first", [False, True])
def test_an_internal_pair_meshes_at_phase_c_whichever_gear_comes_first(ring_first, tmp_path):
    mech = _compile(_internal_pair(ring_first), tmp_path)
    for t in (0.0, 0.1, 1.0):
        s = mech.solve(t, level="velocity")
        assert _same_angle(s["Th2"], 2 * t / 2.5), (t, s["Th2"])
        assert s["Th2d"] == pytest.approx(0.8, abs=1e-12)


def _planetary(ring_first):
    """Sun (1) driven, planet (0.6) on an arm, fixed ring (2.2) = the ground; the all-zero
    pose meshes both pairs at c = 0, so the arm turns at ω rs/(rs + rr) from 0 (Willis)."""
    p = Model("planet_ring_first" if ring_first else "planet_first")
    frame = p.ground("frame", points=[(0, 0)])
    sun = p.body("sun", points=[(0, 0)], guess=(0, 0, 0))
    planet = p.body("planet", points=[(0, 0)], guess=(1.6, 0, 0))
    arm = p.body("arm", points=[(0, 0), (1.6, 0)], guess=(0, 0, 0))
    p.revolute(frame[1], sun[1])
    p.revolute(frame[1], arm[1])
    p.revolute(arm[2], planet[1])
    p.gear_ratio(sun[1], 1.0, planet[1], 0.6)
    if ring_first:
        p.gear_ratio(frame[1], -2.2, planet[1], 0.6)
    else:
        p.gear_ratio(planet[1], 0.6, frame[1], -2.2)
    p.rotation_lock(sun, 2 * T)
    return p


@pytest.mark.parametrize("ring_first", [False, True])
def test_a_planetary_arm_starts_where_its_gears_mesh_at_phase_c(ring_first, tmp_path):
    mech = _compile(_planetary(ring_first), tmp_path)
    w_arm = 2 * 1.0 / 3.2
    for t in (0.0, 0.3, 2.0):
        s = mech.solve(t, level="velocity")
        assert _same_angle(s["Th4"], w_arm * t), (t, s["Th4"])
        assert s["Th4d"] == pytest.approx(w_arm, abs=1e-12)


# -- an open profile (a translating cam's track): the roller's side ------------------------
def _track(c0, name):
    """A wavy track y = c0 + 0.5 sin x fixed in a slider that moves along x, a roller
    (radius 0.3) on a vertical guide at x = 2: the same track, c0 apart in the cam's frame."""
    m = Model(name)
    g = m.ground("g", points=[(0, 0), (1, 0), (2.0, 0), (2.0, 1)])
    cam = m.body("cam", points=[(0, 0), (1, 0)], guess=(0, 0, 0))
    f = m.body("f", points=[(0, 0), (0, 1)], guess=(2.0, c0 + 0.5 * math.sin(2.0), 0))
    m.translate(g.line(1, 2), cam.line(1, 2))
    m.relative_x(cam[0], 0.5 * T)
    m.translate(g.line(3, 4), f.line(1, 2))
    prof = m.profile("trk", xy=lambda s: (s, c0 + 0.5 * mechgen.sin(s)))
    m.cam_to_point(cam, prof, f[1], contact="s", guess=2.0, radius=0.3)
    return m


def test_an_open_track_keeps_its_roller_on_one_side_wherever_it_lies(tmp_path):
    """Shifting the track by c0 in its cam's frame shifts the follower by c0: the roller's
    side may not depend on where the frame's origin is (it flipped below the track at
    c0 = -1, above it at c0 = 0 and 1). Closed form: the roller's centre lies 0.3 along
    the normal of the track, at the point where it meets x = 2 (found by bisection)."""
    got = {}
    for k, c0 in enumerate((-1.0, 0.0, 1.0)):
        mech = _compile(_track(c0, f"track{k}"), tmp_path)
        got[c0] = mech.solve(0.0)["Y3"] - c0
    assert got[0.0] == pytest.approx(got[1.0], abs=1e-12)
    assert got[-1.0] == pytest.approx(got[0.0], abs=1e-12)
    # the right of the direction of travel (+x): below the track, as documented
    def centre_x(s):
        return s + 0.3 * 0.5 * math.cos(s) / math.hypot(1, 0.5 * math.cos(s)) - 2.0
    lo, hi = 1.0, 3.0
    for _ in range(200):
        mid = 0.5 * (lo + hi)
        lo, hi = (mid, hi) if centre_x(mid) < 0 else (lo, mid)
    s = 0.5 * (lo + hi)
    want = 0.5 * math.sin(s) - 0.3 / math.hypot(1, 0.5 * math.cos(s))
    assert got[0.0] == pytest.approx(want, abs=1e-10)


def test_an_open_arc_track_is_not_a_cusp(tmp_path):
    """A half circle of radius 3 (period π, open) on a slider moving at 0.2 along x, a knife
    edge on a vertical guide at x = 0.5: y = sqrt(9 − (0.5 − 0.2 t)²). Its end's tangent is
    against its start's, which for a closed profile would be a cusp at the join (the
    declaration was refused: 'has a cusp at s = 3.14002'); an open track has no join."""
    m = Model("arc_track")
    g = m.ground("g", points=[(0, 0), (1, 0), (0.5, 0), (0.5, 1)])
    cam = m.body("cam", points=[(0, 0), (1, 0)], guess=(0, 0, 0))
    f = m.body("f", points=[(0, 0), (0, 1)], guess=(0.5, 2.9, 0))
    m.translate(g.line(1, 2), cam.line(1, 2))
    m.relative_x(cam[0], 0.2 * T)
    m.translate(g.line(3, 4), f.line(1, 2))
    prof = m.profile("arc", xy=lambda s: (3 * mechgen.cos(s), 3 * mechgen.sin(s)), period=mechgen.pi)
    m.cam_to_point(cam, prof, f[1], contact="s", guess=1.4)
    mech = _compile(m, tmp_path)
    for t in (0.0, 1.0, 4.0):
        s = mech.solve(t, level="velocity")
        x = 0.5 - 0.2 * t
        assert s["Y3"] == pytest.approx(math.sqrt(9 - x * x), abs=1e-12)
        assert s["Y3d"] == pytest.approx(0.2 * x / math.sqrt(9 - x * x), abs=1e-12)
