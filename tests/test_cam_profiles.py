"""Cam profiles (m.profile with cam_to_point, cam_to_line, cam_to_cam): a profile
that jumps (a periodic law whose end misses its start, or two pieces that miss each other)
or has a corner under a roller, refused where it is declared instead of a follower that
jumps silently or a sweep that fails half-way blaming a lock; a polar law written over one
lobe (period=2π/k, periodic=True) makes the whole cam; an open track keeps its roller on
one side and has no join to be a cusp. Expected values come from the
geometry (closed forms, the envelope of the roller), never from mechgen."""
import math

import numpy as np
import pytest

import mechgen
from mechgen import Model, Piecewise, T, cos, pi, sin

BETA = 2 * pi / 3


def _slider(name, guess_y):
    """A cam turning at one turn per unit time about the origin, a follower sliding on the
    vertical axis x = 0."""
    m = Model(name)
    g = m.ground("g", points=[(0, 0), (0, 1)])
    cam = m.body("cam", guess=(0, 0, 0))
    f = m.body("f", points=[(0, 0), (0, 1)], guess=(0, guess_y, 0))
    m.revolute(g[1], cam[0])
    m.rotation_lock(cam, 2 * pi * T)
    m.translate(g.line(1, 2), f.line(1, 2))
    return m, cam, f


def _cycloidal(h, end=0, top=None):
    """A rise of h over 120°, a dwell at ``top`` (h), a return to ``end`` (0), a dwell."""
    top = h if top is None else top

    def law(phi):
        x1, x2 = phi / BETA, (phi - pi) / BETA
        c = lambda x: x - sin(2 * pi * x) / (2 * pi)       # noqa: E731
        return Piecewise((h * c(x1), phi < BETA), (top, phi < pi),
                         (top + (end - top) * c(x2), phi < pi + BETA), (end, True))
    return law


def _knife_cam(name, law, radius=None):
    """The pitch curve of a radial follower, (rb + s(φ)) at angle π/2 − φ in the cam's
    frame, the follower's point on it (a knife edge, or the centre of a roller on the
    profile itself)."""
    m, cam, f = _slider(name, 4.0)
    disc = m.profile("disc", xy=lambda p: ((4 + law(p)) * sin(p), (4 + law(p)) * cos(p)),
                     periodic=True)
    kw = {} if radius is None else dict(radius=radius)
    m.cam_to_point(cam, disc, f[1], contact="s", guess=0.0, **kw)
    return m


@pytest.mark.parametrize("radius", [None, 0.5])
def test_a_periodic_law_whose_end_misses_its_start_is_refused(radius):
    # before: accepted; the follower's Y3 went 4.05 (t = 0.99) -> 4.00 (t = 1.0), a jump
    # of the missing 0.05 at every turn, with Y3d = 0 and no error or warning
    with pytest.raises(mechgen.ModelError,
                       match=r"cam_to_point 4, cam 'cam': the profile 'disc' jumps at "
                             r"s = 6\.28319 \(its end does not meet its start\), from "
                             r"\(.*, 4\.05\) to \(0, 4\)"):
        _knife_cam("seam", _cycloidal(1.5, end=0.05), radius)
    _knife_cam("closes", _cycloidal(1.5), radius)                     # a closed law: fine


def test_two_pieces_that_miss_each_other_are_refused():
    """The dwell sits 0.02 above the end of the rise (at φ = 2π/3)."""
    with pytest.raises(mechgen.ModelError, match=r"jumps at s = 2\.0944\d*, from "):
        _knife_cam("step", _cycloidal(1.5, top=1.52))


def _d_shape(radius):
    """A disc of radius 2 cut flat by the chord y = −1: corners at θ = 7π/6 and 11π/6
    where the tangent turns by 60°."""
    m, cam, f = _slider("dshape", 2.5)
    d = m.profile("D", polar=lambda th: Piecewise((2, th < 7 * pi / 6),
                                                  (-1 / sin(th), th < 11 * pi / 6), (2, True)),
                  periodic=True)
    kw = {} if radius is None else dict(radius=radius)
    m.cam_to_point(cam, d, f[1], contact="s", guess=float(np.pi / 2), **kw)
    return m


def test_a_roller_on_a_corner_is_refused_a_knife_edge_rides_over_it(tmp_path):
    # before: accepted, and a sweep failed at t = 0.336 with a ConvergenceError that
    # blamed the driver ("ask for a configuration that cannot assemble")
    with pytest.raises(mechgen.ModelError, match=r"the profile 'D' has a corner at s = "
                                                 r"3\.66519 \(its tangent turns by 60° at once\)"):
        _d_shape(0.5)
    mech = mechgen.compile(_d_shape(None), outdir=str(tmp_path), tier="python")
    sw = mech.sweep(0, 1, 37)
    phi = np.mod(np.pi / 2 - 2 * np.pi * sw.t, 2 * np.pi)     # the cam's angle under the edge
    with np.errstate(divide="ignore"):
        r = np.where(np.sin(phi) >= -0.5, 2.0, -1 / np.sin(phi))
    assert np.max(np.abs(sw["Y3"] - r)) < 1e-9


def _lobed(name, **kw):
    """A three-lobed cam r = 2 + 0.3 cos 3θ under a roller of radius 0.4 on the axis
    x = 0.3."""
    m = Model(name)
    g = m.ground("g", points=[(0, 0), (0.3, 0), (0.3, 1)])
    cam = m.body("cam", guess=(0, 0, 0))
    f = m.body("f", points=[(0, 0), (0, 1)], guess=(0.3, 2.6, 0))
    m.revolute(g[1], cam[0])
    m.rotation_lock(cam, 2 * pi * T)
    m.translate(g.line(2, 3), f.line(1, 2))
    d = m.profile("lobes", polar=lambda th: 2 + 0.3 * cos(3 * th), **kw)
    m.cam_to_point(cam, d, f[1], contact="s", guess=float(np.pi / 2), radius=0.4)
    return m


def test_a_polar_law_written_over_one_lobe_makes_the_whole_cam(tmp_path):
    # before: period=2π/3 wrapped cos θ and sin θ too, the profile was the first lobe's
    # sector alone and the declaration was refused as "a cusp at s = 2.09335"
    mech = mechgen.compile(_lobed("lobe", period=2 * pi / 3, periodic=True),
                           outdir=str(tmp_path), tier="python")
    sw = mech.sweep(0, 3, 7)                          # 3 turns in 6 steps
    ph = np.linspace(0, 2 * np.pi, 200001)
    rr = 2 + 0.3 * np.cos(3 * ph)
    ref = []
    for a in 2 * np.pi * sw.t:                        # the roller's envelope, sampled
        px, py = rr * np.cos(ph + a) - 0.3, rr * np.sin(ph + a)
        ok = np.abs(px) <= 0.4
        ref.append(np.max(py[ok] + np.sqrt(0.16 - px[ok] ** 2)))
    assert np.max(np.abs(sw["Y3"] - np.array(ref))) < 1e-6
    with pytest.raises(mechgen.ModelError, match=r"period must divide one turn"):
        _lobed("lobe2", period=2.0, periodic=True)


def _dented(rho):
    """A roller on r = 2 + 0.4 cos 3θ, whose hollows have a radius of curvature of 1.28."""
    m, cam, f = _slider("dented", 2.5)
    r = m.param("rho", rho)
    d = m.profile("dented", polar=lambda th: 2 + 0.4 * cos(3 * th))
    m.cam_to_point(cam, d, f[1], contact="s", guess=float(np.pi / 2), radius=r)
    return m


def test_with_params_asks_the_contact_check_again(tmp_path):
    # before: with_params(rho=1.5) said nothing (the check ran at the default 0.3 only),
    # and a sweep then stopped at t = 0.084 with a ConvergenceError about a lock (toggle)
    import warnings
    mech = mechgen.compile(_dented(0.3), outdir=str(tmp_path), tier="python")
    with pytest.warns(RuntimeWarning, match=r"model 'dented' with rho=1\.5: cam_to_point 4, "
                                            r"cam 'cam': the roller \(radius 1\.5\) is larger "
                                            r"than the radius of curvature 1\.28"):
        big = mech.with_params(rho=1.5)
    assert big.parameters["rho"] == 1.5
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        ok = mech.with_params(rho=1.0)                 # smaller than 1.28: fine, silent
    sw = ok.sweep(0, 1, 13)
    ph = np.linspace(0, 2 * np.pi, 100001)
    rr = 2 + 0.4 * np.cos(3 * ph)
    ref = []
    for a in 2 * np.pi * sw.t:                        # the roller's envelope, sampled
        px, py = rr * np.cos(ph + a), rr * np.sin(ph + a)
        keep = np.abs(px) <= 1.0
        ref.append(np.max(py[keep] + np.sqrt(1.0 - px[keep] ** 2)))
    assert np.max(np.abs(sw["Y3"] - np.array(ref))) < 1e-6


def test_with_params_says_when_the_profile_turns_the_other_way(tmp_path):
    """An ellipse (2 cos s, b sin s): b < 0 runs it clockwise, which turns the roller's
    "outside" (fixed where declared) to its inside."""
    m, cam, f = _slider("flip", 2.0)
    b = m.param("b", 1.5)
    d = m.profile("ell", xy=lambda s: (2 * cos(s), b * sin(s)))
    m.cam_to_point(cam, d, f[1], contact="s", guess=float(np.pi / 2), radius=0.5)
    mech = mechgen.compile(m, outdir=str(tmp_path), tier="python")
    assert mech.solve(0)["Y3"] == pytest.approx(2.0, abs=1e-12)    # b + 0.5 above the pivot
    # before: no warning, and solve(0) of b = -1.5 gave Y3 = -1.0, the roller inside the
    # cam 0.5 above its lowest point (the same ellipse: physically Y3 = 2.0)
    with pytest.warns(RuntimeWarning, match=r"with b=-1\.5: .*'ell' runs the other way round"):
        mech.with_params(b=-1.5)


def _compile(m, tmp_path):
    return mechgen.compile(m, outdir=str(tmp_path), tier="python")


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
