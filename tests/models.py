"""The reference mechanisms of the tests, built as mechgen Models, beside their closed forms
(written here from the geometry with math/mpmath, never taken from mechgen).

- slider_crank / slider_crank_q: crank r about the origin at θ = θ0 + ωT, rod l, the
  slider's pin on the line y = e (an offset slider-crank; e = 0: in-line);
- four_bar / four_bar_q: crank a about the origin, coupler b, rocker c about (d, 0);
- quick_return / quick_return_q: seed 001's crank-driven quick-return
  (examples/quick_return.py; its closed form is tests/closed_forms.quick_return);
- sprung_crank: a driven crank with a spring and a damper whose constants are parameters
  (the loads' limits, the force arrows' names).

A builder takes the numbers, which of them are parameters (``params``: role -> the
parameter's name), the bodies' masses, and the names of joints and driver; its guess is the
closed form at T = 0 on the mode asked for, so a test never pastes a configuration. The
coordinates are in the models' order [X2, Y2, Th2, X3, Y3, Th3, X4, Y4, Th4].
"""
import math
from collections import namedtuple

import mpmath as mp

import closed_forms

SliderCrank = namedtuple("SliderCrank", "m ground crank rod slider")
FourBar = namedtuple("FourBar", "m ground crank coupler rocker")


def _value(m, params, role, value):
    """``value``, or the parameter standing for it where ``params`` names one."""
    return m.param(params[role], value) if role in params else value


def _body_kw(m, masses, body):
    """The mass, inertia and centroid of ``body`` (a (name, default) pair: a parameter)."""
    kw = dict((masses or {}).get(body, {}))
    for k, v in kw.items():
        if isinstance(v, tuple) and v and isinstance(v[0], str):
            kw[k] = m.param(*v)
    return kw


# -- the slider-crank -------------------------------------------------------------------------
def slider_crank_q(t, r=1.0, l=3.0, e=0.0, theta0=0.0, omega=2 * math.pi, side=1):
    """The slider-crank at T = t, the slider on the side of larger x (side=1) or smaller x
    (side=-1) of the crank pin: A = r(cos θ, sin θ), x = A_x + side √(l² − (e − A_y)²), the
    rod from A to (x, e). Plain floats for float t, mpmath numbers for mpf t."""
    lib = mp if isinstance(t, mp.mpf) else math
    th = theta0 + omega * t
    ax, ay = r * lib.cos(th), r * lib.sin(th)
    x = ax + side * lib.sqrt(l * l - (e - ay) ** 2)
    return [0, 0, th, ax, ay, lib.atan2(e - ay, x - ax), x, e, 0]


def slider_crank(name="slider_crank", r=1.0, l=3.0, e=0.0, theta0=0.0, omega=2 * math.pi, *,
                 params=(), ground=None, ground_name="ground", guide=(2, 3),
                 slider_points=((0, 0), (1, 0)),
                 masses=None, joints=(None, None, None, None), drive="crank", side=1):
    """The slider-crank of slider_crank_q as a Model: the ground ``ground_name``, its points
    ``ground`` (by default the origin and two points of the guide y = e), the guide its
    line ``guide``;
    the crank (0, 0)-(r, 0), the rod (0, 0)-(l, 0), the slider's first point its pin.
    ``params`` maps roles (r, l, e, theta0, omega) to parameter names; ``masses`` maps a
    body to its mass=, inertia=, centroid=; ``joints`` names the crank pivot, the crank pin,
    the slider pin and the guide; ``drive`` names the crank's rotation_lock (None: unnamed;
    False: no driver, the caller adds one). Returns (m, ground, crank, rod, slider)."""
    from mechgen import Model, T
    m = Model(name)
    params = dict(params)
    rr, ll, ee = (_value(m, params, k, v) for k, v in (("r", r), ("l", l), ("e", e)))
    th0, w = _value(m, params, "theta0", theta0), _value(m, params, "omega", omega)
    q = slider_crank_q(0.0, r, l, e, theta0, 0.0, side)
    base = m.ground(ground_name,
                    points=[(0, 0), (0, ee), (1, ee)] if ground is None else ground)
    crank = m.body("crank", points=[(0, 0), (rr, 0)], guess=tuple(q[0:3]),
                   **_body_kw(m, masses, "crank"))
    rod = m.body("rod", points=[(0, 0), (ll, 0)], guess=tuple(q[3:6]),
                 **_body_kw(m, masses, "rod"))
    slider = m.body("slider", points=list(slider_points), guess=tuple(q[6:9]),
                    **_body_kw(m, masses, "slider"))
    m.revolute(base[1], crank[1], name=joints[0])
    m.revolute(crank[2], rod[1], name=joints[1])
    m.revolute(rod[2], slider[1], name=joints[2])
    m.translate(base.line(*guide), slider.line(1, 2), name=joints[3])
    if drive is not False:
        m.rotation_lock(crank, th0 + w * T, name=drive)
    return SliderCrank(m, base, crank, rod, slider)


def massive_slider_crank(name="sc"):
    """The slider-crank above (crank 0.2, rod 0.7, θ = 0.3 + 3T) with masses, on the ground
    "base" (0, 0), (1, 0), (0, 0.3), its guide base.line(1, 2), joints A, B, C, slide and
    driver "drive" named: (m, base, crank, rod, slider)."""
    return slider_crank(
        name, r=0.2, l=0.7, e=0.0, theta0=0.3, omega=3, ground=[(0, 0), (1, 0), (0, 0.3)],
        ground_name="base", guide=(1, 2), slider_points=((0, 0), (0.1, 0)),
        masses={"crank": dict(mass=1.0, inertia=0.01, centroid=(0.1, 0)),
                "rod": dict(mass=2.0, inertia=0.1, centroid=(0.35, 0)),
                "slider": dict(mass=0.5)},
        joints=("A", "B", "C", "slide"), drive="drive")


def sprung_crank(name="sprung_crank"):
    """A crank turning 2π rad/s with mass mm (a parameter, default 1), a spring ``spr``
    (k = kk, free length L0) and a damper ``dmp`` (c = cc) from its tip to the ground
    point (0, 3); its pivot "pivot" and driver "drive" named."""
    from mechgen import Model, T
    m = Model(name)
    g = m.ground("g", points=[(0, 0), (0, 3)])
    mm = m.param("mm", 1.0)
    crank = m.body("crank", points=[(0, 0), (1, 0)], guess=(0, 0, 0), mass=mm,
                   inertia=0.1, centroid=(0.5, 0))
    m.revolute(g[1], crank[1], name="pivot")
    m.rotation_lock(crank, 2 * math.pi * T, name="drive")
    kk, L0, cc = m.param("kk", 100.0), m.param("L0", 0.5), m.param("cc", 2.0)
    m.spring(crank[2], g[2], kk, L0, name="spr")
    m.damper(crank[2], g[2], cc, name="dmp")
    return m


# -- the four-bar -----------------------------------------------------------------------------


def four_bar_q(t, a=1.0, b=3.0, c=2.0, d=3.0, theta0=0.0, omega=2 * math.pi, mode=1):
    """The four-bar at T = t: A = a(cos θ, sin θ); B at b from A and c from O4 = (d, 0), left
    of the line from A to O4 (mode=1) or right of it (mode=-1); the coupler from A to B,
    the rocker from O4 to B. Plain floats for float t, mpmath numbers for mpf t."""
    lib = mp if isinstance(t, mp.mpf) else math
    th = theta0 + omega * t
    ax, ay = a * lib.cos(th), a * lib.sin(th)
    dx, dy = d - ax, -ay
    f = lib.sqrt(dx * dx + dy * dy)
    along = (b * b - c * c + f * f) / (2 * f)
    h = mode * lib.sqrt(b * b - along * along)
    bx = ax + (along * dx - h * dy) / f
    by = ay + (along * dy + h * dx) / f
    return [0, 0, th, ax, ay, lib.atan2(by - ay, bx - ax), d, 0, lib.atan2(by, bx - d)]


def four_bar(name="four_bar", a=1.0, b=3.0, c=2.0, d=3.0, theta0=0.0, omega=2 * math.pi, *,
             params=(), masses=None, joints=(None, None, None, None), drive="crank", mode=1):
    """The four-bar of four_bar_q as a Model: ground (0, 0), (d, 0); crank (0, 0)-(a, 0),
    coupler (0, 0)-(b, 0), rocker (0, 0)-(c, 0) pivoted at its origin. ``params``: roles
    a, b, c, d, theta0, omega to parameter names. Returns (m, ground, crank, coupler,
    rocker); ``drive`` as in slider_crank."""
    from mechgen import Model, T
    m = Model(name)
    params = dict(params)
    aa, bb, cc, dd = (_value(m, params, k, v) for k, v in zip("abcd", (a, b, c, d)))
    th0, w = _value(m, params, "theta0", theta0), _value(m, params, "omega", omega)
    q = four_bar_q(0.0, a, b, c, d, theta0, 0.0, mode)
    base = m.ground("ground", points=[(0, 0), (dd, 0)])
    crank = m.body("crank", points=[(0, 0), (aa, 0)], guess=tuple(q[0:3]),
                   **_body_kw(m, masses, "crank"))
    coupler = m.body("coupler", points=[(0, 0), (bb, 0)], guess=tuple(q[3:6]),
                     **_body_kw(m, masses, "coupler"))
    rocker = m.body("rocker", points=[(0, 0), (cc, 0)], guess=tuple(q[6:9]),
                    **_body_kw(m, masses, "rocker"))
    m.revolute(base[1], crank[1], name=joints[0])
    m.revolute(crank[2], coupler[1], name=joints[1])
    m.revolute(coupler[2], rocker[2], name=joints[2])
    m.revolute(base[2], rocker[1], name=joints[3])
    if drive is not False:
        m.rotation_lock(crank, th0 + w * T, name=drive)
    return FourBar(m, base, crank, coupler, rocker)


# -- the quick-return -------------------------------------------------------------------------
def quick_return():
    """Seed 001's crank-driven quick-return (examples/quick_return.py) as a Model; its
    closed form is quick_return_q (tests/closed_forms.quick_return)."""
    from conftest import example_model
    return example_model("quick_return")


def quick_return_q(t, longitud=3, velocidad=None, anguloI=0, side=1):
    """The quick-return at T = t (tests/closed_forms.quick_return, mpmath)."""
    return closed_forms.quick_return(t, longitud, velocidad, anguloI, side)
