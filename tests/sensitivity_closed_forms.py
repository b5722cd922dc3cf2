"""Closed-form kinematics of the mechanisms of tests/test_sensitivity_references.py, written
out here independently of mechgen (mpmath only: circle intersections, the cam's and the
gears' geometry), and their derivatives by mpmath's own differentiation (mp.diff): in t
for q̇ and q̈, in a parameter for ∂q/∂p, mixed in t and the parameter for ∂q̇/∂p and ∂q̈/∂p,
the drivers' laws held (T fixed) — the reference values of docs/reference/sensitivities.md's
sensitivities.

Each closed form is ``fn(t, **params) -> [mpf, ...]``, the coordinates in the order the
test's model declares them (X2, Y2, Th2, X3, ..., then the extra coordinates). Angles are
measured continuously about a fixed reference angle (``ang``), so that no atan2 cut lies
under mp.diff's stencil and the value is the one a solver following the motion from the
model's guess reports."""
import math

import mpmath as mp
import numpy as np

DPS = 40


# -- geometry --------------------------------------------------------------------------------
def ang(y, x, ref=0.0):
    """The angle of the vector (x, y), in (ref − π, ref + π]: ref plus the atan2 of the
    vector turned back by ref (ref a fixed float, so the angle is smooth where mp.diff
    evaluates it)."""
    c, s = mp.cos(ref), mp.sin(ref)
    return ref + mp.atan2(y * c - x * s, x * c + y * s)


def circles(p, r1, q, r2, side):
    """The intersection of the circle about p of radius r1 and the circle about q of
    radius r2 on the left (side=+1) or right (side=−1) of the direction p → q."""
    dx, dy = q[0] - p[0], q[1] - p[1]
    L = mp.sqrt(dx * dx + dy * dy)
    ex, ey = dx / L, dy / L
    x = (r1 * r1 - r2 * r2 + L * L) / (2 * L)
    h = mp.sqrt(r1 * r1 - x * x)
    return (p[0] + x * ex - side * h * ey, p[1] + x * ey + side * h * ex)


def dyad(A, b, O, c, side, ref3, ref4):
    """A four-bar's dyad: the joint B, b from the pin A and c from the fixed pivot O, on
    ``side`` of A → O; the angles of A → B and O → B about ref3 and ref4."""
    B = circles(A, b, O, c, side)
    return B, ang(B[1] - A[1], B[0] - A[0], ref3), ang(B[1] - O[1], B[0] - O[0], ref4)


# -- the mechanisms ---------------------------------------------------------------------------
def fourbar(t, a, b, c, d, omega, theta0):
    """Four-bar: crank (body 2, points (0,0), (a,0)) about the origin at θ = θ0 + ωT,
    coupler (3, (0,0), (b,0)), rocker (4, (0,0), (c,0)) about (d, 0); the joint B above
    the line from the crank pin to the rocker's pivot (the mode of the guess Th3 ≈ 0.5,
    Th4 ≈ 1.8). Coordinates X2..Th4."""
    th = theta0 + omega * t
    A = (a * mp.cos(th), a * mp.sin(th))
    _, th3, th4 = dyad(A, b, (d, 0), c, +1, 0.5, 1.8)
    return [0, 0, th, A[0], A[1], th3, d, 0, th4]


def fourbar_outputs(t, a, b, c, d, omega, theta0, u=0.5, v=0.8):
    """The four-bar's declared outputs: ``px``, the x of the coupler point at local (u, v)
    (u, v numbers), and ``tip_y``, the y of the rocker's tip (c, 0) — explicit in c."""
    th = theta0 + omega * t
    A = (a * mp.cos(th), a * mp.sin(th))
    B, th3, _ = dyad(A, b, (d, 0), c, +1, 0.5, 1.8)
    return [A[0] + u * mp.cos(th3) - v * mp.sin(th3), B[1]]


def slider_crank(t, r, l, e, omega=2 * math.pi, theta0=0.4):
    """Offset slider-crank: crank (2, (0,0), (r,0)) about the origin at θ = θ0 + ωT, rod
    (3, (0,0), (l,0)), slider (4) on the line y = e, on the side of larger x. Coordinates
    X2..Th4: the slider's origin (x, e), its angle 0."""
    th = theta0 + omega * t
    Ax, Ay = r * mp.cos(th), r * mp.sin(th)
    x = Ax + mp.sqrt(l * l - (e - Ay) ** 2)
    return [0, 0, th, Ax, Ay, ang(e - Ay, x - Ax, 0.0), x, e, 0]


def inverted_slider_crank(t, L, h, rod, omega=2 * math.pi, theta0=0.0):
    """Quick return (examples/quick_return.py with its crank L, the crank's pivot (0, h)
    above the lever's pivot at the origin, the slider's rod ``rod``): crank (2) about
    (0, h) at θ = θ0 + ωT, its pin P = (L cos θ, h + L sin θ); the slotted lever (3, its
    axis the local y axis, 9 long) about the origin through P; the slider (4) on y = 10,
    ``rod`` from the lever's end E = 9 P/|P|, on the side of larger x."""
    th = theta0 + omega * t
    px, py = L * mp.cos(th), h + L * mp.sin(th)
    rho = mp.sqrt(px * px + py * py)
    ex, ey = 9 * px / rho, 9 * py / rho
    x4 = ex + mp.sqrt(rod * rod - (10 - ey) ** 2)
    return [0, h, th, 0, 0, ang(-px, py, 0.0), x4, 10, 0]


WATT_O6 = (6.0, 3.0)
WATT_ARM = -1.0          # the angle of the ternary rocker's third point from its link line


def watt_sixbar(t, a, c, g, e, f, b=2.5, d=3.0, omega=2 * math.pi, theta0=math.pi / 3):
    """Watt six-bar (Watt II): the four-bar a, b, c, d (crank 2 at θ = θ0 + ωT, coupler 3,
    the ternary rocker 4 about (d, 0) with points (0,0), (c,0), g (cos γ, sin γ), γ =
    WATT_ARM); its third point R drives a second dyad: link 5 ((0,0), (e,0)) from R to the
    tip of rocker 6 ((0,0), (f,0)) about O6 = WATT_O6, the joint C on the left of R → O6."""
    th = theta0 + omega * t
    A = (a * mp.cos(th), a * mp.sin(th))
    _, th3, th4 = dyad(A, b, (d, 0), c, +1, 0.5, 1.8)
    R = (d + g * mp.cos(th4 + WATT_ARM), g * mp.sin(th4 + WATT_ARM))
    _, th5, th6 = dyad(R, e, WATT_O6, f, +1, 1.0, 2.0)
    return [0, 0, th, A[0], A[1], th3, d, 0, th4, R[0], R[1], th5, WATT_O6[0], WATT_O6[1], th6]


def eccentric_cam(t, R, e, rho, f, w=2 * math.pi):
    """An eccentric circular cam (2): the circle of radius R about local (e, 0), turning
    about the origin at θ = wT (profile parameter s: the point (e + R cos s, R sin s), its
    outward normal (cos s, sin s)). A flat-faced follower (3) slides on the y axis, its face
    (local x axis) on the top of the cam: Y3 = e sin θ + R, contact where θ + s1 = π/2.
    A roller follower (4) of radius ρ slides along y = f (its origin the roller's centre,
    Th4 = 0) on the right of the cam: its centre is R + ρ from the cam's centre c,
    X4 = c_x + √((R + ρ)² − (f − c_y)²), contact where θ + s2 is the angle of the centre
    seen from c. Coordinates X2, Y2, Th2, X3, Y3, Th3, X4, Y4, Th4, s1, s2."""
    th = w * t
    cx, cy = e * mp.cos(th), e * mp.sin(th)
    x4 = cx + mp.sqrt((R + rho) ** 2 - (f - cy) ** 2)
    s2 = ang(f - cy, x4 - cx, 0.5) - th
    return [0, 0, th, 0, e * mp.sin(th) + R, 0, x4, f, 0, mp.pi / 2 - th, s2]


GEAR_PHASE = 1.2         # c of gear_ratio: rA ThA + rB ThB = c


def geared_fourbar(t, rA, rB, a, b, omega=2 * math.pi, c=2.0, d=3.0):
    """A four-bar whose crank is a gear: gear A (2, radius rA) on a shaft at (−(rA + rB), 0)
    driven at ThA = ωT meshes (gear_ratio, the centre line along +x) with gear B (3,
    radius rB) about the origin, rA ThA + rB ThB = GEAR_PHASE; gear B carries the crank pin
    (a, 0); coupler 4 ((0,0), (b,0)), rocker 5 ((0,0), (c,0)) about (d, 0), the joint
    above the line from the pin to the pivot."""
    thA = omega * t
    thB = (GEAR_PHASE - rA * thA) / rB
    A = (a * mp.cos(thB), a * mp.sin(thB))
    _, th4, th5 = dyad(A, b, (d, 0), c, +1, 0.5, 1.8)
    return [-(rA + rB), 0, thA, 0, 0, thB, A[0], A[1], th4, d, 0, th5]


# -- derivatives ------------------------------------------------------------------------------
def _cached(fn, params, name=None):
    """fn as a function of (t) or (t, p) (p: the parameter ``name``), remembering each
    evaluation: mp.diff evaluates every component at the same points (and at the same
    working precision, which it raises with the order: part of the key)."""
    memo = {}

    def at(tt, pp=None):
        key = (tt, pp, mp.mp.prec)
        if key not in memo:
            kw = dict(params)
            if name is not None:
                kw[name] = pp
            memo[key] = fn(tt, **kw)
        return memo[key]
    return at


def motion(fn, t, params, dps=DPS):
    """q, q̇, q̈ of fn at T = t, as float arrays."""
    with mp.workdps(dps):
        tt = mp.mpf(t)
        kw = {k: mp.mpf(v) for k, v in params.items()}
        at = _cached(fn, kw)
        n = len(at(tt))
        return tuple(np.array([float(mp.diff(lambda u, k=k: at(u)[k], tt, order))
                               for k in range(n)]) for order in (0, 1, 2))


def sensitivities(fn, t, params, names, dps=DPS):
    """(∂q/∂p, ∂q̇/∂p, ∂q̈/∂p) of fn at T = t: three float arrays (n, len(names)), the
    columns in the order of ``names``, each a mixed derivative by mpmath (order 0, 1, 2
    in t and 1 in the parameter)."""
    with mp.workdps(dps):
        tt = mp.mpf(t)
        kw = {k: mp.mpf(v) for k, v in params.items()}
        n = len(fn(tt, **kw))
        out = [np.empty((n, len(names))) for _ in range(3)]
        for j, name in enumerate(names):
            at = _cached(fn, kw, name)
            for order in range(3):
                for k in range(n):
                    out[order][k, j] = float(mp.diff(lambda u, p, k=k: at(u, p)[k],
                                                     (tt, kw[name]), (order, 1)))
        return tuple(out)
