"""Gears and rack and pinion (Mech's TwoGears2, TwoGears1, RackAndPinion2, RackAndPinion1).

A gear is a body with a pitch circle of radius r about one of its points; a negative
radius makes it an internal gear (a ring, teeth inside). Two meshing gears at p1, p2
(radii r1, r2) keep their centres r1 + r2 apart and roll without slipping:

    r1 (Th1 − β) + r2 (Th2 − β) = c,        β the angle of the centre line

(Mech's constant C: e_i = Th_i − β is the angle from the centre line to gear i's x axis;
β is the angle of the pitch direction w = r1 u/(r1 + r2), u = r(p2) − r(p1): from gear 1's
centre to the pitch point, for an internal gear too, either gear first). mechgen writes the rolling
relation as the angle from w to the direction ψ = (r1 Th1 + r2 Th2 − c)/(r1 + r2):

    (r1 + r2) atan2(w × e_ψ, w · e_ψ),   e_ψ = (cos ψ, sin ψ)      (mesh_angle)

= (r1 + r2)(ψ − β) wrapped to (−π, π]: the relation above up to whole turns of the centre
line. It vanishes only at the physical meshing: half a turn of phase away, where
u × e_ψ (the row of earlier releases) vanished too, it is ±π (r1 + r2); the atan2's cut
lies there, never on a motion, so the row is smooth when a planet goes round its sun.

A rack is an axis (fixed in its body) that is the rack's pitch line; the pinion's centre
p lies r to the left of it (to the right with a negative r) and rolls along it:

    s + r (Th_p − Th_a − α) − c = 0,        s = (r(p) − a.first) · u / |u|

(c: Mech's C, the travel s at which the pinion's x axis is parallel to the rack).
"""
from __future__ import annotations

import sympy as sp

from ...errors import ModelError
from ..constraints import Constraint, checked_line, checked_point, cross2, dot2
from ..geometry import T
from .joints import body_fixed


def _radius(model, value, kind, which):
    r = model._expr(value, f"{kind}: the radius {which}")
    if T in r.free_symbols:
        raise ModelError(f"{kind}: the radius {which} ({r}) may not depend on T")
    if r.is_zero:
        raise ModelError(f"{kind}: the radius {which} is 0; a gear needs a pitch radius")
    return r


def _txt(e):
    """A value as a label writes it: 0.5, not 0.500000000000000."""
    return repr(float(e)) if isinstance(e, sp.Float) else f"{e}"


def _phase(model, value, kind):
    return model._expr(value, f"{kind}: the phase constant c")


def pitch_marker(p, r):
    """The point r along the x axis of p's body from p: its distance from p is the drawn
    pitch radius, its side the radius' sign (a negative radius: an internal gear)."""
    return p.body.at(p.local[0] + r, p.local[1])


class mesh_angle(sp.Function):  # noqa: N801 - printed as the function it stands for
    """mesh_angle(ux, uy, ψ, k): the angle from the vector k u to the direction e_ψ =
    (cos ψ, sin ψ) in (−π, π], atan2(k u × e_ψ, k u · e_ψ) = ψ − β wrapped, β the angle
    of k u (k ≠ 0: only its sign counts).

    It prints (as text, Mathematica, LaTeX and code) as that atan2; its derivatives are
    those of ψ − atan2(uy, ux): ∂/∂ux = uy/|u|², ∂/∂uy = −ux/|u|², ∂/∂ψ = 1 (and 0 in k),
    so that Φ_q, ν and γ of a gear row are short (sympy's derivative of the atan2 would
    carry the sines and cosines of ψ into every term)."""

    nargs = 4
    wraps = True        # its slope in ψ is 1, yet not linear (compiler.solver.blocks.linear_in)

    @classmethod
    def eval(cls, ux, uy, psi, k):
        if all(a.is_Number for a in (ux, uy, psi, k)):
            return sp.atan2(*_across_along(ux, uy, psi, k))
        return None

    def as_atan2(self):
        return sp.atan2(*_across_along(*self.args))

    def fdiff(self, argindex=1):
        ux, uy, _, _ = self.args
        return (uy / (ux ** 2 + uy ** 2), -ux / (ux ** 2 + uy ** 2), sp.Integer(1),
                sp.Integer(0))[argindex - 1]

    def _eval_is_real(self):
        return True

    def _eval_evalf(self, prec):
        return self.as_atan2()._eval_evalf(prec)

    def _pythoncode(self, printer):
        return printer._print(self.as_atan2())

    def _sympystr(self, printer):
        return printer._print(self.as_atan2())

    def _mcode(self, printer):
        return printer._print(self.as_atan2())

    def _latex(self, printer):
        return printer._print(self.as_atan2())

    @staticmethod
    def _imp_(ux, uy, psi, k):       # lambdify: numpy, element-wise
        import numpy as np
        c, s = np.cos(psi), np.sin(psi)
        return np.arctan2(k * (ux * s - uy * c), k * (ux * c + uy * s))


def _across_along(ux, uy, psi, k=1):
    """(k u × e_ψ, k u · e_ψ) = k |u| (sin(ψ − β), cos(ψ − β))."""
    return (k * (ux * sp.sin(psi) - uy * sp.cos(psi)), k * (ux * sp.cos(psi) + uy * sp.sin(psi)))


def rolling_row(u, psi, total, r1):
    """(r1 + r2) times the angle from the pitch direction w = r1 u/(r1 + r2) to e_ψ, in
    (−π, π]: (r1 + r2) atan2(w × e_ψ, w · e_ψ). w points from gear 1's centre to the
    pitch point, whichever gear is the ring: the pitch point is r(p1) + r1 u/(r1 + r2)
    (an external pair: r1 û; a pinion in a ring: −r1 û; a ring round its pinion: |r1| û).
    Zero exactly where w points along e_ψ, the gears meshed at phase c; where it points
    against e_ψ (phase c + π (r1 + r2), which u × e_ψ = 0 allows too) the row is
    ±π (r1 + r2), not 0. The atan2's cut lies there, half a turn of phase from every
    solution, so Φ is smooth along any motion; at a solution the row's gradient is that
    of u × e_ψ."""
    # the sign of r1 (r1 + r2) turns u into w; a number's sign is folded, a parameter's
    # kept (u/(r1 + r2) alone pointed away from the pitch point for a ring given first,
    # meshing it half a turn of phase from c)
    lead = r1 * total
    side = 1 if lead.is_positive else -1 if lead.is_negative else lead
    return total * mesh_angle(u[0], u[1], psi, side)


class _Gears(Constraint):
    """Two gears; ``components`` picks the rows ("distance", "rolling")."""

    def build(self, p1, r1, p2, r2, c=0):
        kind = self.kind
        p1 = checked_point(self.model, p1, kind, 1)
        r1 = _radius(self.model, r1, kind, "r1")
        p2 = checked_point(self.model, p2, kind, 3)
        r2 = _radius(self.model, r2, kind, "r2")
        c = _phase(self.model, c, kind)
        if p1.body is p2.body:
            raise ModelError(f"{kind}: both gears are body {p1.body}; gears mesh between "
                             "two bodies")
        total = sp.simplify(r1 + r2)
        if total.is_zero:
            raise ModelError(f"{kind}: r1 + r2 = 0 (radii {r1}, {r2}): the gears would share "
                             "their centre; an internal gear must be larger than its pinion")
        u = p2.r - p1.r
        psi = (r1 * p1.body.th + r2 * p2.body.th - c) / total
        rows = {"distance": u[0] ** 2 + u[1] ** 2 - total ** 2,
                "rolling": rolling_row(u, psi, total, r1)}
        self.exprs = [rows[k] for k in self.components]
        self.radii = (r1, r2)
        self.drawn = [p1, pitch_marker(p1, r1), p2, pitch_marker(p2, r2)]
        return f"{p1}, {_txt(r1)}, {p2}, {_txt(r2)}" + ("" if c == 0 else f", {_txt(c)}")


class Gears(_Gears):
    """``gears(p1, r1, p2, r2, c=0)``: two meshing gears (Mech's TwoGears2): the centres
    ‖r(p2) − r(p1)‖² − (r1 + r2)² = 0 (row distance) and the rolling relation
    (r1 + r2) atan2(w × e_ψ, w · e_ψ) = 0, w = u/(r1 + r2), ψ = (r1 Th1 + r2 Th2 − c)/(r1 + r2)
    (row rolling)."""

    kind = "gears"
    components = ("distance", "rolling")


class GearRatio(_Gears):
    """``gear_ratio(p1, r1, p2, r2, c=0)``: the rolling relation of two gears alone (Mech's
    TwoGears1), for gears whose centres other constraints already hold."""

    kind = "gear_ratio"
    components = ("rolling",)


class _Rack(Constraint):
    def build(self, p, r, a, c=0):
        kind = self.kind
        p = checked_point(self.model, p, kind, 1)
        r = _radius(self.model, r, kind, "r")
        a = checked_line(self.model, a, kind, 3)
        c = _phase(self.model, c, kind)
        rack, alpha = body_fixed(a, kind, 3)
        if rack is p.body:
            raise ModelError(f"{kind}: the pinion's centre {p} and the rack {a!r} are on the "
                             "same body")
        u, length = a.u, a.length
        d = p.r - a.first.r
        rows = {"offset": cross2(u, d) / length - r,
                "rolling": dot2(d, u) / length + r * (p.body.th - rack.th - alpha) - c}
        self.exprs = [rows[k] for k in self.components]
        self.radii = (r,)
        marker = pitch_marker(p, r)
        self.drawn = [p, marker, a.first, a.second if a.second is not None else
                      a.first.body.at(a.first.local[0] + a.local_direction[0],
                                      a.first.local[1] + a.local_direction[1])]
        return f"{p}, {_txt(r)}, {a}" + ("" if c == 0 else f", {_txt(c)}")


class RackAndPinion(_Rack):
    """``rack_and_pinion(p, r, a, c=0)``: a pinion of radius r centred at p on the rack
    whose pitch line is axis a (Mech's RackAndPinion2): p lies r to the left of a,
    u × (r(p) − a.first)/|u| − r = 0 (row offset), and rolls along it,
    (r(p) − a.first) · u/|u| + r (Th_p − Th_a − α) − c = 0 (row rolling)."""

    kind = "rack_and_pinion"
    components = ("offset", "rolling")


class RackRatio(_Rack):
    """``rack_ratio(p, r, a, c=0)``: the rolling row of rack_and_pinion alone (Mech's
    RackAndPinion1), for a pinion whose distance to the rack is already held."""

    kind = "rack_ratio"
    components = ("rolling",)


KINDS_GEARS = (Gears, GearRatio, RackAndPinion, RackRatio)
