"""``FourBar``: two RR dyads joined by the coupler, analysed over the poses, and
``synthesis.fourbars``: every four-bar made of a pair of the poses' dyads."""
from __future__ import annotations

import math

import numpy as np

from .defects import analyse, coupler_pin, crank_pin, mode, transmission
from .dyads import Dyad, dyads as make_dyads
from .poses import as_poses, place, rotation

GRASHOF_EDGE = 1e-9


def grashof(lengths) -> str:
    """The Grashof type of a four-bar with links (a input, b coupler, c output, d ground)."""
    a, b, c, d = lengths
    s, p, q, l = sorted(lengths)
    gap = (s + l) - (p + q)
    if abs(gap) <= GRASHOF_EDGE * l:
        return "change-point"
    if gap > 0:
        return "triple-rocker"
    shortest = min(lengths)
    if d == shortest:
        return "drag-link"
    if b == shortest and a != shortest and c != shortest:
        return "double-rocker"
    return "crank-rocker"


class FourBar:
    """A four-bar through poses: ``input`` (the driven dyad) and ``output`` (:class:`Dyad`),
    ``lengths`` (a input crank, b coupler, c output link, d ground), ``grashof``,
    ``defects`` (a set drawn from {"circuit", "branch", "order"}), ``transmission`` (min and
    max transmission angle over the motion between the poses, degrees), ``times`` (the
    model's times at which it reaches each pose; NaN for a pose it cannot reach from the
    first), ``direction`` (+1: the input turns counter-clockwise), ``modes`` (each pose's
    assembly mode) and ``poses``."""

    def __init__(self, input, output, poses):
        self.input, self.output = input, output
        self.poses = np.array(poses, dtype=float)
        O2, O4 = np.array(input.fixed), np.array(output.fixed)
        uA, uB = np.array(input.moving), np.array(output.moving)
        A = np.array([place(p, uA) for p in self.poses])
        B = np.array([place(p, uB) for p in self.poses])
        a = float(np.linalg.norm(A[0] - O2))
        b = float(np.linalg.norm(uB - uA))
        c = float(np.linalg.norm(B[0] - O4))
        d = float(np.linalg.norm(O4 - O2))
        if min(a, b, c, d) <= 1e-12 * max(a, b, c, d, 1e-300):
            raise ValueError(f"dyads {input} and {output} make no four-bar (a link of "
                             f"length 0: a, b, c, d = {a:g}, {b:g}, {c:g}, {d:g})")
        self.lengths = (a, b, c, d)
        self.grashof = grashof(self.lengths)
        self.phis = np.arctan2(A[:, 1] - O2[1], A[:, 0] - O2[0])
        self.modes = tuple(mode(A[j], B[j], O4) for j in range(len(self.poses)))
        found, self.direction, times, (lo, hi) = analyse(
            O2, O4, a, b, c, self.phis, self.modes)
        self.defects = frozenset(found)
        self.times = tuple(float(t) for t in times)
        self.transmission = transmission(O2, O4, a, b, c, lo, hi)

    @property
    def pivots(self):
        """(O2, O4): the input and output fixed pivots."""
        return self.input.fixed, self.output.fixed

    def quality(self) -> float:
        """The transmission angle's least distance from a toggle over the motion, degrees."""
        lo, hi = self.transmission
        return min(lo, 180.0 - hi)

    def pose_at(self, t):
        """The coupler frame's (x, y, angle) at model time t (following pose 1's mode)."""
        a, b, c, _ = self.lengths
        O2, O4 = np.array(self.input.fixed), np.array(self.output.fixed)
        A = crank_pin(O2, a, self.phis[0] + self.direction * t)
        B = coupler_pin(A, O4, b, c, self.modes[0])
        if B is None:
            return None
        uA, uB = np.array(self.input.moving), np.array(self.output.moving)
        th = math.atan2(*(B - A)[::-1]) - math.atan2(*(uB - uA)[::-1])
        xy = A - rotation(th) @ uA
        return float(xy[0]), float(xy[1]), float(th)

    def model(self, name="fourbar", direction=None):
        """A mechgen Model of this four-bar: ground pivots O2, O4; the input ``crank``
        driven by rotation_lock(crank, ground, phi0 ± T) (one radian per time unit, turning
        the way that meets the poses in order, or ``direction`` (+1: counter-clockwise) when
        given; phi0 its angle at pose 1, reached at T = 0);
        the body ``coupler`` whose frame is the poses' frame (coupler[0] at a pose's (x, y),
        its x axis at the pose's angle; its points: the input's moving pivot, the output's,
        and the poses' point and axis, coupler.line(3, 4)); the ``output`` link; the guess:
        pose 1's configuration, in the mode that reaches the poses. Parameters: the pivots
        (x_O2, y_O2, x_O4, y_O4), the links a and c, the coupler's pivots (x_A, y_A, x_B,
        y_B) and phi0."""
        from ..model.geometry import T
        from ..model.language import Model
        a, b, c, _ = self.lengths
        O2, O4 = self.input.fixed, self.output.fixed
        uA, uB = self.input.moving, self.output.moving
        p1 = self.poses[0]
        B1 = place(p1, uB)
        m = Model(name)
        xO2, yO2 = m.param("x_O2", O2[0]), m.param("y_O2", O2[1])
        xO4, yO4 = m.param("x_O4", O4[0]), m.param("y_O4", O4[1])
        la, lc = m.param("a", a), m.param("c", c)
        xA, yA = m.param("x_A", uA[0]), m.param("y_A", uA[1])
        xB, yB = m.param("x_B", uB[0]), m.param("y_B", uB[1])
        phi0 = m.param("phi0", float(self.phis[0]))
        ground = m.ground("ground", points=[(xO2, yO2), (xO4, yO4)])
        crank = m.body("crank", points=[(0, 0), (la, 0)],
                       guess=(float(O2[0]), float(O2[1]), float(self.phis[0])))
        axis = 0.5 * b
        coupler = m.body("coupler", points=[(xA, yA), (xB, yB), (0, 0), (axis, 0)],
                         guess=(float(p1[0]), float(p1[1]), float(p1[2])))
        psi1 = math.atan2(B1[1] - O4[1], B1[0] - O4[0])
        output = m.body("output", points=[(0, 0), (lc, 0)],
                        guess=(float(O4[0]), float(O4[1]), psi1))
        m.revolute(ground[1], crank[1], name="O2")
        way = self.direction if direction is None else (1 if direction > 0 else -1)
        m.rotation_lock(crank, ground, phi0 + way * T, name="crank driver")
        m.revolute(crank[2], coupler[1], name="A")
        m.revolute(ground[2], output[1], name="O4")
        m.revolute(coupler[2], output[2], name="B")
        return m

    def verify(self, check=None, tier="python"):
        """The defects as mechgen's own solver meets them: this four-bar's model swept
        from pose 1 both ways (synthesis.verify): a Verdict (``.defects``, ``.times``,
        ``.modes``, ``.stops``). ``check``: a SolverCheck to reuse its compiled model."""
        from .verify import SolverCheck
        return (check or SolverCheck(tier=tier))(self)

    def __repr__(self):
        a, b, c, d = self.lengths
        flags = ", ".join(sorted(self.defects)) or "no defects"
        return (f"FourBar(O2={_pt(self.input.fixed)}, O4={_pt(self.output.fixed)}, "
                f"a={a:.4g}, b={b:.4g}, c={c:.4g}, d={d:.4g}, {self.grashof}, {flags}, "
                f"transmission {self.transmission[0]:.1f}–{self.transmission[1]:.1f}°)")


def _pt(p):
    return f"({p[0]:.4g}, {p[1]:.4g})"


def fourbars(poses, samples=12, **choices):
    """Every four-bar made of two RR dyads of the poses (both ways round: each dyad as the
    input once), defect-free ones first, then by the transmission angle's distance from a
    toggle. ``samples`` and ``choices`` (fixed=, moving=) go to dyads() (for three or four
    poses, samples² four-bars)."""
    poses = as_poses(poses, 3, 5)
    rr = [d for d in make_dyads(poses, samples, sliders=False, **choices) if d.kind == "RR"]
    out = []
    for i, first in enumerate(rr):
        for j, second in enumerate(rr):
            if i == j:
                continue
            try:
                out.append(FourBar(first, second, poses))
            except ValueError:
                continue
    out.sort(key=lambda f: (len(f.defects), -f.quality()))
    return out


def four_bar(input, output, poses) -> FourBar:
    """The FourBar of two given dyads (Dyad or (fixed, moving) pairs) through ``poses``."""
    poses = as_poses(poses, 2)
    return FourBar(_dyad(input), _dyad(output), poses)


def _dyad(d):
    if isinstance(d, Dyad):
        return d
    fixed, moving = d
    return Dyad(tuple(float(v) for v in fixed), tuple(float(v) for v in moving))
