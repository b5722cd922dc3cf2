"""Jansen's leg (the Strandbeest linkage, his "holy numbers"): seven moving bodies (the
crank, five links and the foot), 21 coordinates. The guesses are the exact assembly at
crank angle 0, computed from the link lengths by intersecting circles; a Strandbeest-size
model for benchmarks."""
import math

from mechgen import Model, T, pi


def _third(p, q, r1, r2, up):
    """The point at distance r1 from p and r2 from q, left of p->q (up=1) or right."""
    dx, dy = q[0] - p[0], q[1] - p[1]
    L = math.hypot(dx, dy)
    a = (r1 ** 2 - r2 ** 2 + L ** 2) / (2 * L)
    h = math.sqrt(r1 ** 2 - a ** 2)
    return (p[0] + a * dx / L - up * h * dy / L, p[1] + a * dy / L + up * h * dx / L)


def _frame(origin, x_end, p=None):
    """The angle of the frame at origin whose x axis points to x_end; p in that frame."""
    ang = math.atan2(x_end[1] - origin[1], x_end[0] - origin[0])
    if p is None:
        return ang
    dx, dy = p[0] - origin[0], p[1] - origin[1]
    return (math.cos(ang) * dx + math.sin(ang) * dy, -math.sin(ang) * dx + math.cos(ang) * dy)


a, l, m_ = 38.0, 7.8, 15.0
b, c, d, e, f, g, h, i, j, k = 41.5, 39.3, 40.1, 55.8, 39.4, 36.7, 65.7, 49.0, 50.0, 61.9
O, B, A = (0.0, 0.0), (-a, -l), (m_, 0.0)
C = _third(B, A, b, j, 1)
E = _third(B, A, c, k, -1)
D = _third(B, C, d, e, 1)
F = _third(D, E, f, g, -1)
G = _third(E, F, i, h, 1)


def leg(m, body=None, crank_length=m_, upper_length=j, lower_length=k, foot_length=g):
    """Jansen's leg built into model ``m``: the frame, the seven bodies, the eleven pins and
    the crank turning once a unit of time; returns the bodies by name. ``body(m, name,
    points, guess, length)`` makes each body (plain ones by default; a model with masses
    passes its own), and ``crank_length`` (and the upper and lower links' and the foot's
    lengths) may be parameters (the guesses stay those of the holy numbers)."""
    if body is None:
        def body(m, name, points, guess, length):
            return m.body(name, points=points, guess=guess)
    frame = m.ground("frame", points=[O, B])
    crank = body(m, "crank", [(0, 0), (crank_length, 0)], (0, 0, 0), m_)
    upper = body(m, "upper", [(0, 0), (upper_length, 0)], (*A, _frame(A, C)), j)
    hip = body(m, "hip", [(0, 0), (b, 0), _frame(B, C, D)], (*B, _frame(B, C)), b)
    lower = body(m, "lower", [(0, 0), (lower_length, 0)], (*A, _frame(A, E)), k)
    cee = body(m, "cee", [(0, 0), (c, 0)], (*B, _frame(B, E)), c)
    eff = body(m, "eff", [(0, 0), (f, 0)], (*D, _frame(D, F)), f)
    foot = body(m, "foot", [(0, 0), (foot_length, 0), _frame(E, F, G)], (*E, _frame(E, F)), g)
    m.revolute(frame[1], crank[1])
    m.rotation_lock(crank, 2 * pi * T, name="crank angle")
    m.revolute(crank[2], upper[1])
    m.revolute(crank[2], lower[1])
    m.revolute(frame[2], hip[1])
    m.revolute(upper[2], hip[2])
    m.revolute(frame[2], cee[1])
    m.revolute(cee[2], lower[2])
    m.revolute(cee[2], foot[1])
    m.revolute(hip[3], eff[1])
    m.revolute(eff[2], foot[2])
    return dict(frame=frame, crank=crank, upper=upper, hip=hip, lower=lower, cee=cee,
                eff=eff, foot=foot)


m = Model("strandbeest_leg")
leg(m)
