"""Random mechanisms with closed forms, shared by tests/test_random_mechanisms.py (the fast
profile) and benchmarks/random_mechanisms.py (the long one).

Each family is ONE parameterised mechgen Model (every dimension, pivot, phase and speed a
``m.param``), built once per session (``mechgen.compile``, on the tier TIER); a random mechanism is a
dictionary of parameter values passed through ``mech.with_params`` or a design table.
Its reference is a closed form written here (sequential circle intersections, evaluated on
second-order jets, tests/jets.py, for velocities and accelerations by the chain rule):
never mechgen's equations.

A family's assembly modes are the signs ``sigma`` of its circle intersections (one per
intersection); ``disc`` are the intersections' normalised discriminants, negative where
the mechanism cannot assemble (a lock window). The mode is fixed by the start; along a
motion the sign is kept, and a lock window ends the branch (its right answer is a
refusal)."""
from __future__ import annotations

import itertools
import math

import numpy as np

import jets as sp

TWO_PI = 2 * math.pi
# the tier a family's Mechanism answers in (None: $MECHGEN_TIER, else "auto"). The tests
# set "python": the generated text itself, judged point by point, without numba compiling
# seven modules (~100 s of CPU); the long profile (benchmarks/) keeps the default. The
# dask and CUDA-simulator tables still compile the file (their workers, their kernels).
TIER = None


def circle_point(p1, r1, p2, r2, sigma):
    """The point at r1 from p1 and r2 from p2 on side sigma (+1: left of p1 -> p2), and the
    normalised discriminant h^2 / r1^2 (negative: the circles do not meet)."""
    ex, ey = p2[0] - p1[0], p2[1] - p1[1]
    L2 = ex ** 2 + ey ** 2
    L = sp.sqrt(L2)
    x = (r1 ** 2 - r2 ** 2 + L2) / (2 * L)
    h2 = r1 ** 2 - x ** 2
    h = sigma * sp.sqrt(h2)
    return (p1[0] + (x * ex - h * ey) / L, p1[1] + (x * ey + h * ex) / L), h2 / r1 ** 2


def ang(p, q):
    """The angle of the vector from p to q."""
    return sp.atan2(q[1] - p[1], q[0] - p[0])


class Family:
    """One topology: ``model()`` (a mechgen Model), ``exprs(P, S, t)`` (coordinate ->
    closed form of parameters P, signs S and time t, a jet; and the discriminants) and
    ``draw(rng, kind)`` (random parameters of a variant)."""
    name = ""
    params: tuple = ()
    nsigma = 1
    variants: tuple = ("plain",)
    angles = ()        # extra angle-like coordinates beyond Th*

    def __init__(self):
        self._mech = None

    # -- the compiled mechanism, once --------------------------------------------------
    def mech(self):
        if self._mech is None:
            import mechgen
            self._mech = mechgen.compile(self.model(), tier=TIER)
            self.coords = tuple(self._mech.coordinates)
            self.angle_mask = np.array([c.startswith("Th") or c in self.angles
                                        for c in self.coords])
        return self._mech

    # -- the closed form on jets -----------------------------------------------------
    def _eval(self, p, sigma, ts):
        self.mech()
        t = sp.Jet(np.asarray(ts, dtype=float), 1.0, 0.0)
        return self.exprs({n: float(p[n]) for n in self.params}, [float(s) for s in sigma], t)

    def modes(self):
        return list(itertools.product((1.0, -1.0), repeat=self.nsigma))

    def judged_modes(self):
        """The modes a solution is judged against: ``modes()``, and for a family whose
        assemblies at one time include poses that are not modes (gears meshed whole turns
        of a gear further on), those too; a draw picks among ``modes()`` only."""
        return self.modes()

    def judged(self, sigma):
        """The key of ``judged_modes()`` that mode sigma (of ``modes()``) is."""
        return tuple(sigma)

    def exact(self, p, sigma, ts, upto=2):
        """[Q, QD, QDD] (arrays (len(ts), coordinates), up to level ``upto``) of mode
        sigma at times ts; NaN where the mode does not exist."""
        ts = np.asarray(ts, dtype=float)
        with np.errstate(all="ignore"):
            q, _ = self._eval(p, sigma, ts)
            out = []
            for lev in range(upto + 1):
                cols = []
                for c in self.coords:
                    x = q[c]
                    val = (getattr(x, ("v", "d", "dd")[lev]) if isinstance(x, sp.Jet)
                           else (x if lev == 0 else 0.0))
                    cols.append(np.broadcast_to(np.asarray(val, dtype=float), ts.shape))
                out.append(np.stack(cols, axis=-1))
        return out

    def disc(self, p, ts, sigma=None):
        """The smallest normalised discriminant of mode sigma at times ts (< 0: no
        assembly; a later intersection of a six-bar depends on the earlier signs)."""
        ts = np.asarray(ts, dtype=float)
        with np.errstate(all="ignore"):
            _, ds = self._eval(p, sigma or (1.0,) * self.nsigma, ts)
            vals = [np.broadcast_to(np.asarray(x.v if isinstance(x, sp.Jet) else x,
                                               dtype=float), ts.shape) for x in ds]
        d = np.min(np.stack(vals), axis=0)
        return np.where(np.isnan(d), -1.0, d)

    def period(self, p):
        return TWO_PI / abs(p["w"])


def _loguniform(rng, lo, hi):
    return math.exp(rng.uniform(math.log(lo), math.log(hi)))


def _speed(rng):
    return float(rng.choice([-1.0, 1.0]) * rng.uniform(0.5, 12.0))


def _pivot(rng):
    return float(rng.uniform(-2, 2)), float(rng.uniform(-2, 2))


# -- four-bar: crank a about A, coupler b, rocker c about D = A + d (cos g, sin g) ----------
class FourBar(Family):
    name = "fourbar"
    params = ("ax", "ay", "d", "g", "a", "b", "c", "th0", "w")
    variants = ("grashof", "nearmiss", "lockwin", "any")

    def model(self):
        from mechgen import Model, T, cos, sin
        m = Model("rand_fourbar")
        ax, ay, d, g, a, b, c, th0, w = (m.param(n, v) for n, v in zip(
            self.params, (0.0, 0.0, 3.0, 0.0, 0.8, 2.5, 2.0, 1.0, 6.0)))
        ground = m.ground("ground", points=[(ax, ay), (ax + d * cos(g), ay + d * sin(g))])
        crank = m.body("crank", points=[(0, 0), (a, 0)], guess=(0, 0, 1.0))
        coupler = m.body("coupler", points=[(0, 0), (b, 0)], guess=(0.4, 0.7, 0.5))
        rocker = m.body("rocker", points=[(0, 0), (c, 0)], guess=(3, 0, 1.8))
        m.revolute(ground[1], crank[1])
        m.revolute(crank[2], coupler[1])
        m.revolute(ground[2], rocker[1])
        m.revolute(coupler[2], rocker[2])
        m.rotation_lock(crank, th0 + w * T, name="crank")
        return m

    def exprs(self, P, S, t):
        th = P["th0"] + P["w"] * t
        A = (P["ax"], P["ay"])
        D = (A[0] + P["d"] * sp.cos(P["g"]), A[1] + P["d"] * sp.sin(P["g"]))
        B = (A[0] + P["a"] * sp.cos(th), A[1] + P["a"] * sp.sin(th))
        C, h = circle_point(B, P["b"], D, P["c"], S[0])
        return {"X2": A[0], "Y2": A[1], "Th2": th, "X3": B[0], "Y3": B[1], "Th3": ang(B, C),
                "X4": D[0], "Y4": D[1], "Th4": ang(D, C)}, [h]

    def draw(self, rng, kind):
        ax, ay = _pivot(rng)
        p = dict(ax=ax, ay=ay, g=float(rng.uniform(-math.pi, math.pi)),
                 th0=float(rng.uniform(-math.pi, math.pi)), w=_speed(rng))
        a = float(rng.uniform(0.3, 1.5))
        d = a + float(rng.uniform(0.3, 3.0))
        if kind == "any":
            b, c = (float(v) for v in rng.uniform(0.3, 4.0, 2))
        elif kind == "grashof":          # the crank turns: |b - c| + m < d - a, b + c > a + d + m
            lo, hi = (d - a) * 0.0, d - a
            diff = float(rng.uniform(lo, 0.9 * hi))
            s = (a + d) * (1 + float(rng.uniform(0.02, 0.8)))
            b, c = (s + diff) / 2, (s - diff) / 2
        elif kind == "nearmiss":         # b + c = (a + d)(1 + eps): never locks, nearly toggles
            eps = _loguniform(rng, 1e-5, 1e-2)
            s = (a + d) * (1 + eps)
            diff = float(rng.uniform(0.0, 0.9 * (d - a)))
            b, c = (s + diff) / 2, (s - diff) / 2
        else:                            # a narrow lock window of width W about crank angle g + pi
            W = _loguniform(rng, 0.005, 0.5)
            s = math.sqrt(a * a + d * d + 2 * a * d * math.cos(W / 2))
            diff = float(rng.uniform(0.0, 0.9 * (d - a)))
            b, c = (s + diff) / 2, (s - diff) / 2
        if rng.uniform() < 0.5:
            b, c = c, b
        p.update(a=a, b=b, c=c, d=d)
        return p


# -- offset slider-crank driven by its crank; the guide at angle g, offset e --------------------
class SliderCrank(Family):
    name = "slider_crank"
    params = ("ax", "ay", "g", "a", "b", "e", "th0", "w")
    variants = ("turning", "lockwin")

    def model(self):
        from mechgen import Model, T, cos, sin
        m = Model("rand_slider_crank")
        ax, ay, g, a, b, e, th0, w = (m.param(n, v) for n, v in zip(
            self.params, (0.0, 0.0, 0.0, 1.0, 3.0, 0.2, 0.0, 6.0)))
        nx, ny = -sin(g), cos(g)
        ground = m.ground("ground", points=[(ax, ay), (ax + e * nx, ay + e * ny),
                                            (ax + e * nx + cos(g), ay + e * ny + sin(g))])
        crank = m.body("crank", points=[(0, 0), (a, 0)], guess=(0, 0, 0))
        rod = m.body("rod", points=[(0, 0), (b, 0)], guess=(1, 0, 0))
        slider = m.body("slider", points=[(0, 0), (1, 0)], guess=(4, 0.2, 0))
        m.revolute(ground[1], crank[1])
        m.revolute(crank[2], rod[1])
        m.revolute(rod[2], slider[1])
        m.translate(ground.line(2, 3), slider.line(1, 2))
        m.rotation_lock(crank, th0 + w * T, name="crank")
        return m

    def exprs(self, P, S, t):
        th, g = P["th0"] + P["w"] * t, P["g"]
        A = (P["ax"], P["ay"])
        B = (A[0] + P["a"] * sp.cos(th), A[1] + P["a"] * sp.sin(th))
        bu, bv = P["a"] * sp.cos(th - g), P["a"] * sp.sin(th - g)
        h2 = P["b"] ** 2 - (P["e"] - bv) ** 2
        su = bu + S[0] * sp.sqrt(h2)
        Sx = A[0] + su * sp.cos(g) - P["e"] * sp.sin(g)
        Sy = A[1] + su * sp.sin(g) + P["e"] * sp.cos(g)
        return {"X2": A[0], "Y2": A[1], "Th2": th, "X3": B[0], "Y3": B[1],
                "Th3": ang(B, (Sx, Sy)), "X4": Sx, "Y4": Sy, "Th4": g}, [h2 / P["b"] ** 2]

    def draw(self, rng, kind):
        ax, ay = _pivot(rng)
        a = float(rng.uniform(0.3, 2.0))
        e = float(rng.uniform(-1, 1)) * a
        if kind == "turning":
            b = a + abs(e) + float(rng.uniform(0.05, 3.0)) * a
        else:                            # b < a + |e|: a narrow window where the rod is short
            W = _loguniform(rng, 0.005, 0.5)
            e = math.copysign(max(abs(e), 0.2 * a), e if e else 1.0)
            b = abs(e) + a * math.cos(W / 2)
        return dict(ax=ax, ay=ay, g=float(rng.uniform(-math.pi, math.pi)), a=a, b=b, e=e,
                    th0=float(rng.uniform(-math.pi, math.pi)), w=_speed(rng))


# -- offset slider-crank driven by its slider (the issue's reproducer and random ones) ----------
class SliderDriven(Family):
    name = "slider_driven"
    params = ("a", "b", "e", "xc", "amp", "f", "ph")
    variants = ("random",)

    def model(self):
        from mechgen import Model, T, pi, sin
        m = Model("rand_slider_driven")
        a, b, e, xc, amp, f, ph = (m.param(n, v) for n, v in zip(
            self.params, (1.0, 3.2, 0.4, 4.15, 0.6, 1.0, 0.0)))
        ground = m.ground("ground", points=[(0, 0), (0, e), (1, e)])
        crank = m.body("crank", points=[(0, 0), (a, 0)], guess=(0, 0, 0.3))
        rod = m.body("rod", points=[(0, 0), (b, 0)], guess=(1, 0.3, 0))
        slider = m.body("slider", points=[(0, 0), (1, 0)], guess=(4.15, 0.4, 0))
        m.revolute(ground[1], crank[1])
        m.revolute(crank[2], rod[1])
        m.revolute(rod[2], slider[1])
        m.translate(ground.line(2, 3), slider.line(1, 2))
        m.relative_x(slider[1], xc - amp * sin(2 * pi * f * T + ph), name="slider")
        return m

    def exprs(self, P, S, t):
        x = P["xc"] - P["amp"] * sp.sin(2 * math.pi * P["f"] * t + P["ph"])
        Sp = (x, P["e"])
        B, h = circle_point((0, 0), P["a"], Sp, P["b"], S[0])
        return {"X2": 0, "Y2": 0, "Th2": ang((0, 0), B), "X3": B[0], "Y3": B[1],
                "Th3": ang(B, Sp), "X4": x, "Y4": P["e"], "Th4": 0}, [h]

    def period(self, p):
        return 1.0 / abs(p["f"])

    @staticmethod
    def issue_params():
        """The issue's reproducer: a = 1, b = 3.2, e = 0.4, x2 - 0.6 sin(2 pi T)."""
        th2 = 0.5 + math.pi / 2 - 0.5625 * math.pi
        x2 = math.cos(th2) + math.sqrt(3.2 ** 2 - (math.sin(th2) - 0.4) ** 2)
        return dict(a=1.0, b=3.2, e=0.4, xc=x2, amp=0.6, f=1.0, ph=0.0), th2

    def draw(self, rng, kind):
        a = float(rng.uniform(0.3, 1.5))
        b = a + float(rng.uniform(0.3, 3.0))
        e = float(rng.uniform(-1, 1)) * min(a, b - a) * 0.9
        th = float(rng.uniform(-math.pi, math.pi))
        xc = a * math.cos(th) + math.sqrt(b * b - (a * math.sin(th) - e) ** 2)
        span = math.sqrt((a + b) ** 2 - e * e) - math.sqrt(max((b - a) ** 2 - e * e, 0.0))
        amp = float(rng.uniform(0.05, 0.6)) * span
        return dict(a=a, b=b, e=e, xc=xc, amp=amp, f=float(rng.uniform(0.5, 3.0)),
                    ph=float(rng.uniform(-math.pi, math.pi)))


# -- inverted slider-crank: the crank pin on a guide line (offset e) of a rocker about O2 ---------
class Inverted(Family):
    name = "inverted"
    params = ("ox", "oy", "a", "e", "th0", "w")
    variants = ("turning", "lockwin")

    def model(self):
        from mechgen import Model, T
        m = Model("rand_inverted")
        ox, oy, a, e, th0, w = (m.param(n, v) for n, v in zip(
            self.params, (0.0, 2.0, 1.0, 0.2, 0.0, 6.0)))
        ground = m.ground("ground", points=[(0, 0), (ox, oy)])
        crank = m.body("crank", points=[(0, 0), (a, 0)], guess=(0, 0, 0))
        guide = m.body("guide", points=[(0, e), (1, e)], guess=(0, 2, -1.0))
        m.revolute(ground[1], crank[1])
        m.revolute(ground[2], guide[0])
        m.point_on_line(crank[2], guide.line(1, 2))
        m.rotation_lock(crank, th0 + w * T, name="crank")
        return m

    def exprs(self, P, S, t):
        th = P["th0"] + P["w"] * t
        B = (P["a"] * sp.cos(th), P["a"] * sp.sin(th))
        rho2 = (B[0] - P["ox"]) ** 2 + (B[1] - P["oy"]) ** 2
        psi = ang((P["ox"], P["oy"]), B)
        al = sp.asin(P["e"] / sp.sqrt(rho2))
        phi = psi - S[0] * al + (1 - S[0]) / 2 * math.pi
        return {"X2": 0, "Y2": 0, "Th2": th, "X3": P["ox"], "Y3": P["oy"], "Th3": phi}, \
            [(rho2 - P["e"] ** 2) / P["a"] ** 2]

    def draw(self, rng, kind):
        a = float(rng.uniform(0.3, 2.0))
        if kind == "turning":            # |e| below the closest approach |d - a|
            dd = a * float(rng.choice([rng.uniform(0.1, 0.8), rng.uniform(1.2, 4.0)]))
            e = float(rng.uniform(-0.9, 0.9)) * abs(dd - a)
        else:                            # |e| just above the closest approach |d - a|: a window
            dd = a * float(rng.uniform(1.2, 4.0))
            W = _loguniform(rng, 0.005, 0.5)
            e = float(rng.choice([-1, 1])) * math.sqrt(a * a + dd * dd - 2 * a * dd * math.cos(W / 2))
        gdir = float(rng.uniform(-math.pi, math.pi))
        return dict(ox=dd * math.cos(gdir), oy=dd * math.sin(gdir), a=a, e=e,
                    th0=float(rng.uniform(-math.pi, math.pi)), w=_speed(rng))


# -- six-bar: the four-bar plus a dyad from coupler point E (p, q) to ground pivot G -----------
class SixBar(Family):
    name = "sixbar"
    params = ("d", "a", "b", "c", "p", "q", "gx", "gy", "f", "h", "th0", "w")
    nsigma = 2
    variants = ("random",)

    def model(self):
        from mechgen import Model, T
        m = Model("rand_sixbar")
        d, a, b, c, p, q, gx, gy, f, h, th0, w = (m.param(n, v) for n, v in zip(
            self.params, (3.0, 0.8, 2.5, 2.0, 1.2, 0.8, 1.0, 3.0, 2.0, 2.0, 1.0, 6.0)))
        ground = m.ground("ground", points=[(0, 0), (d, 0), (gx, gy)])
        crank = m.body("crank", points=[(0, 0), (a, 0)], guess=(0, 0, 1.0))
        coupler = m.body("coupler", points=[(0, 0), (b, 0), (p, q)], guess=(0.4, 0.7, 0.5))
        rocker = m.body("rocker", points=[(0, 0), (c, 0)], guess=(3, 0, 1.8))
        link5 = m.body("link5", points=[(0, 0), (f, 0)], guess=(1, 1, 1))
        link6 = m.body("link6", points=[(0, 0), (h, 0)], guess=(1, 3, 0))
        m.revolute(ground[1], crank[1])
        m.revolute(crank[2], coupler[1])
        m.revolute(ground[2], rocker[1])
        m.revolute(coupler[2], rocker[2])
        m.revolute(coupler[3], link5[1])
        m.revolute(ground[3], link6[1])
        m.revolute(link5[2], link6[2])
        m.rotation_lock(crank, th0 + w * T, name="crank")
        return m

    def exprs(self, P, S, t):
        th = P["th0"] + P["w"] * t
        B = (P["a"] * sp.cos(th), P["a"] * sp.sin(th))
        D = (P["d"], 0)
        C, h1 = circle_point(B, P["b"], D, P["c"], S[0])
        t3 = ang(B, C)
        E = (B[0] + P["p"] * sp.cos(t3) - P["q"] * sp.sin(t3),
             B[1] + P["p"] * sp.sin(t3) + P["q"] * sp.cos(t3))
        G = (P["gx"], P["gy"])
        F, h2 = circle_point(E, P["f"], G, P["h"], S[1])
        return {"X2": 0, "Y2": 0, "Th2": th, "X3": B[0], "Y3": B[1], "Th3": t3,
                "X4": D[0], "Y4": D[1], "Th4": ang(D, C), "X5": E[0], "Y5": E[1],
                "Th5": ang(E, F), "X6": G[0], "Y6": G[1], "Th6": ang(G, F)}, [h1, h2]

    def draw(self, rng, kind):
        fb = FOURBAR.draw(rng, "grashof" if rng.uniform() < 0.7 else "any")
        p = dict(d=fb["d"], a=fb["a"], b=fb["b"], c=fb["c"], th0=fb["th0"], w=fb["w"],
                 p=float(rng.uniform(-1, 2)) * fb["b"], q=float(rng.uniform(-1, 1)) * fb["b"])
        p.update(gx=float(rng.uniform(-3, 5)), gy=float(rng.uniform(-3, 4)),
                 f=float(rng.uniform(1.0, 5.0)), h=float(rng.uniform(1.0, 5.0)))
        return p


# -- geared five-bar: gears r1 about O1, r2 about O2 = O1 + (r1 + r2)(cos be, sin be) -------------
class GearedFiveBar(Family):
    name = "geared_fivebar"
    params = ("r1", "r2", "be", "cph", "a1", "a2", "l1", "l2", "th0", "w")
    variants = ("random",)

    def model(self):
        from mechgen import Model, T, cos, sin
        m = Model("rand_geared_fivebar")
        r1, r2, be, cph, a1, a2, l1, l2, th0, w = (m.param(n, v) for n, v in zip(
            self.params, (1.0, 2.0, 0.0, 0.0, 1.0, 1.0, 3.0, 3.0, 0.0, 6.0)))
        ground = m.ground("ground", points=[(0, 0), ((r1 + r2) * cos(be), (r1 + r2) * sin(be))])
        g1 = m.body("gear1", points=[(0, 0), (a1, 0)], guess=(0, 0, 0))
        g2 = m.body("gear2", points=[(0, 0), (a2, 0)], guess=(3, 0, 0))
        c1 = m.body("coupler1", points=[(0, 0), (l1, 0)], guess=(1, 0, 1.2))
        c2 = m.body("coupler2", points=[(0, 0), (l2, 0)], guess=(4, 0, 2.0))
        m.revolute(ground[1], g1[1])
        m.revolute(ground[2], g2[1])
        m.gear_ratio(g1[1], r1, g2[1], r2, cph, name="mesh")
        m.rotation_lock(g1, th0 + w * T, name="input")
        m.revolute(g1[2], c1[1])
        m.revolute(g2[2], c2[1])
        m.revolute(c1[2], c2[2], name="P")
        return m

    def judged_modes(self):
        # the rolling row holds modulo whole turns of gear 1 (it is wrapped, turns.py): with
        # gear 1 where its driver puts it, gear 2 may stand 2 pi r1/r2 k further on, a pose
        # the driver reaches a turn of gear 1 later or earlier; r2/r1 in {0.5, 1, 1.5, 2, 3}
        # gives at most 3 distinct ones modulo 2 pi (k = 0, 1, 2)
        return [s + (float(k),) for s in self.modes() for k in (0, 1, 2)]

    def judged(self, sigma):
        sigma = tuple(sigma)
        return sigma + (0.0,) if len(sigma) == self.nsigma else sigma

    def exprs(self, P, S, t):
        th1 = P["th0"] + P["w"] * t
        # rolling without slip: r1 (th1 - be) + r2 (th2 - be) = cph (+ 2 pi r1 k: a meshing
        # k turns of gear 1 on)
        mesh = S[1] if len(S) > 1 else 0.0
        th2 = (P["cph"] + (P["r1"] + P["r2"]) * P["be"] - P["r1"] * th1
               + TWO_PI * P["r1"] * mesh) / P["r2"]
        O2 = ((P["r1"] + P["r2"]) * sp.cos(P["be"]), (P["r1"] + P["r2"]) * sp.sin(P["be"]))
        A1 = (P["a1"] * sp.cos(th1), P["a1"] * sp.sin(th1))
        A2 = (O2[0] + P["a2"] * sp.cos(th2), O2[1] + P["a2"] * sp.sin(th2))
        Pp, h = circle_point(A1, P["l1"], A2, P["l2"], S[0])
        return {"X2": 0, "Y2": 0, "Th2": th1, "X3": O2[0], "Y3": O2[1], "Th3": th2,
                "X4": A1[0], "Y4": A1[1], "Th4": ang(A1, Pp), "X5": A2[0], "Y5": A2[1],
                "Th5": ang(A2, Pp)}, [h]

    def draw(self, rng, kind):
        r1 = float(rng.uniform(0.5, 1.5))
        r2 = r1 * float(rng.choice([0.5, 1.0, 1.5, 2.0, 3.0]))
        a1, a2 = float(rng.uniform(0.2, 1.0)) * r1, float(rng.uniform(0.2, 1.0)) * r2
        dmax = r1 + r2 + a1 + a2
        l1 = float(rng.uniform(0.55, 1.2)) * dmax
        l2 = float(rng.uniform(0.55, 1.2)) * dmax
        return dict(r1=r1, r2=r2, be=float(rng.uniform(-math.pi, math.pi)),
                    cph=float(rng.uniform(-1, 1)), a1=a1, a2=a2, l1=l1, l2=l2,
                    th0=float(rng.uniform(-math.pi, math.pi)), w=_speed(rng))


# -- cam train: an eccentric disc cam (R, e) driving a roller (rho) on an arm (L) about G --------
class CamArm(Family):
    name = "cam_arm"
    params = ("R", "e", "rho", "gx", "gy", "L", "th0", "w")
    variants = ("random",)
    angles = ("s",)

    def model(self):
        from mechgen import Model, T, cos, sin
        m = Model("rand_cam_arm")
        R, e, rho, gx, gy, L, th0, w = (m.param(n, v) for n, v in zip(
            self.params, (2.0, 0.5, 0.5, 4.0, 3.0, 3.5, 0.0, 6.0)))
        ground = m.ground("ground", points=[(0, 0), (gx, gy)])
        cam = m.body("cam", guess=(0, 0, 0))
        arm = m.body("arm", points=[(0, 0), (L, 0)], guess=(4, 3, -2.0))
        m.revolute(ground[1], cam[0])
        m.rotation_lock(cam, th0 + w * T, name="cam angle")
        m.revolute(ground[2], arm[1])
        disc = m.profile("disc", xy=lambda s: (e + R * cos(s), R * sin(s)))
        m.cam_to_point(cam, disc, arm[2], contact="s", guess=0.5, radius=rho)
        return m

    def exprs(self, P, S, t):
        th = P["th0"] + P["w"] * t
        C = (P["e"] * sp.cos(th), P["e"] * sp.sin(th))
        G = (P["gx"], P["gy"])
        Pc, h = circle_point(C, P["R"] + P["rho"], G, P["L"], S[0])
        return {"X2": 0, "Y2": 0, "Th2": th, "X3": G[0], "Y3": G[1], "Th3": ang(G, Pc),
                "s": ang(C, Pc) - th}, [h]

    def draw(self, rng, kind):
        R = float(rng.uniform(1.0, 3.0))
        e = float(rng.uniform(0.05, 0.6)) * R
        rho = float(rng.uniform(0.1, 0.6)) * R
        gd = R + rho + e + float(rng.uniform(0.3, 3.0))
        ga = float(rng.uniform(-math.pi, math.pi))
        # the arm reaches the roller circle at every cam angle: |gd - (R + rho)| + e < L < gd + R + rho - e
        lo, hi = gd - (R + rho) + e, gd + R + rho - e
        L = lo + float(rng.uniform(0.05, 0.95)) * (hi - lo)
        return dict(R=R, e=e, rho=rho, gx=gd * math.cos(ga), gy=gd * math.sin(ga), L=L,
                    th0=float(rng.uniform(-math.pi, math.pi)), w=_speed(rng))


FOURBAR = FourBar()
FAMILIES = {f.name: f for f in (FOURBAR, SliderCrank(), SliderDriven(), Inverted(), SixBar(),
                                GearedFiveBar(), CamArm())}
