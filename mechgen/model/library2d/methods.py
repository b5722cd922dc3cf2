"""The Model methods for the rest of Mech's 2D library: gears, rack and pinion,
point_on_lines, origin_lock, directed_distance, the joints with their own coordinate
(gen_revolute, gen_translate) and the complex vector loop (loop).

``Mech2D`` is a mixin that ``Model`` inherits; the constraint classes are in ``gears``
and ``joints``. docs/constraints.md shows each kind's printed rows.
"""
from __future__ import annotations

import sympy as sp

from ...errors import ModelError
from ..constraints import KINDS
from .gears import KINDS_GEARS, GearRatio, Gears, RackAndPinion, RackRatio
from .joints import (KINDS_JOINTS, DirectedDistance, GenRevolute, GenTranslate, Loop,
                     OriginLock, PointOnLines)

KINDS.update({c.kind: c for c in (*KINDS_GEARS, *KINDS_JOINTS)})


class Mech2D:
    """Model methods for gears, racks, more of Mech's constraints, joints with their own
    coordinate and the complex loop form."""

    def _add_drawn(self, cls, args, name):
        """_add, then the points the constraint's picture needs (pitch markers)."""
        con = self._add(cls, args, name)
        con.points = list(con.drawn)
        return con

    # -- gears ----------------------------------------------------------------------
    def gears(self, p1, r1, p2, r2, c=0, name=None):
        """Two meshing gears (Mech's TwoGears2): gear 1 is p1's body with pitch radius r1
        about p1, gear 2 p2's body with r2 about p2; a negative radius is an internal gear
        (a ring). Two rows: the centres stay r1 + r2 apart,
        ‖r(p2) − r(p1)‖² − (r1 + r2)² = 0, and the gears roll without slipping,
        r1 (Th1 − β) + r2 (Th2 − β) = c (β the centre line's angle), written
        u × (cos ψ, sin ψ) = 0 with u = r(p2) − r(p1), ψ = (r1 Th1 + r2 Th2 − c)/(r1 + r2).
        ``c`` is Mech's phase constant: r1 e1 + r2 e2, e_i the angle from the centre line
        to gear i's x axis in a meshing position (0: both x axes along the centre line)."""
        return self._add_drawn(Gears, (p1, r1, p2, r2, c), name)

    def gear_ratio(self, p1, r1, p2, r2, c=0, name=None):
        """The rolling row of gears() alone (Mech's TwoGears1): for gears whose centres
        other constraints already hold r1 + r2 apart (a gear train on fixed shafts, a
        planet on its arm), where the distance row would be redundant."""
        return self._add_drawn(GearRatio, (p1, r1, p2, r2, c), name)

    def rack_and_pinion(self, p, r, a, c=0, name=None):
        """A pinion of pitch radius r centred at p (on the pinion's body) meshing with a
        rack whose pitch line is axis ``a`` (fixed in the rack's body; Mech's
        RackAndPinion2). Two rows: p lies r to the left of the axis (to its right with a
        negative r), u × (r(p) − a.first)/‖u‖ − r = 0, and rolls along it,
        (r(p) − a.first) · u/‖u‖ + r (Th_p − Th_a − α) − c = 0 (α the axis' angle in the
        rack; ``c`` the travel at which the pinion's x axis is parallel to the rack)."""
        return self._add_drawn(RackAndPinion, (p, r, a, c), name)

    def rack_ratio(self, p, r, a, c=0, name=None):
        """The rolling row of rack_and_pinion() alone (Mech's RackAndPinion1), for a
        pinion whose distance to the rack other constraints already hold."""
        return self._add_drawn(RackRatio, (p, r, a, c), name)

    # -- more of Mech's constraints -------------------------------------------------
    def point_on_lines(self, p, a1, a2, name=None):
        """Point ``p`` at the intersection of axes ``a1`` and ``a2`` (Mech's
        PointOnLines2): two rows, (a1.first − r(p)) × u1 and (a2.first − r(p)) × u2."""
        return self._add(PointOnLines, (p, a1, a2), name)

    def origin_lock(self, b1, b2=None, offset=None, name=None):
        """The origin of body ``b1`` held at the origin of body ``b2`` plus ``offset`` (a
        global (dx, dy); Mech's OriginLock2): X_b1 − X_b2 − dx = 0, Y_b1 − Y_b2 − dy = 0.
        ``origin_lock(b)`` and ``origin_lock(b, (x, y))`` hold it at a global point. The
        bodies' angles stay free."""
        return self._add_drawn(OriginLock, (b1, b2, offset), name)

    def directed_distance(self, p1, p2, direction=None, d=None, name=None):
        """Point ``p1`` lies ``d`` from point ``p2`` measured along ``direction`` (an axis,
        or a global (dx, dy); Mech's DirectedDistance1): (r(p1) − r(p2)) · u/‖u‖ − d = 0.
        ``directed_distance(p1, direction, d)`` measures from the global origin; without
        ``d`` the distance is ‖u‖. With T in ``d`` it is a driver."""
        return self._add(DirectedDistance, (p1, p2, direction, d), name)

    # -- joints with their own coordinate -------------------------------------------
    def _with_coordinate(self, cls, a1, a2, coord, guess, name):
        made = None
        if isinstance(coord, str):
            made = self.coordinate(coord, guess=0.0 if guess is None else guess)
            coord = made
        elif guess is not None:
            raise ModelError(f"{cls.kind}: guess= goes with a new coordinate's name; "
                             f"{coord} has its guess from m.coordinate()")
        try:
            return self._add_drawn(cls, (a1, a2, coord), name)
        except ModelError:
            if made is not None:          # a rejected joint leaves the model as it was
                self.coords.remove(made)
                del self.guess[made]
                del self._names[made.name]
            raise

    def gen_revolute(self, a1, a2, coordinate, guess=None, name=None):
        """A revolute that brings its angle as a coordinate (Mech's GenRevolute2): the
        first points of axes ``a1`` and ``a2`` (each fixed in one body) coincide, and the
        angle from a1 to a2, (Th_b2 + α2) − (Th_b1 + α1), is the coordinate. Three rows
        (x, y, angle), one coordinate: it takes two degrees of freedom away as a
        revolute does. ``coordinate`` is a new name (with ``guess=``) or a symbol from
        ``m.coordinate``; ``constraint(phi - law)`` drives it, ``s["phi"]`` reads it and
        the returned constraint's ``.coordinate`` is its symbol. Mech writes the axes
        the other way round: GenRevolute2[axis1, axis2] is gen_revolute(axis2, axis1)."""
        return self._with_coordinate(GenRevolute, a1, a2, coordinate, guess, name)

    def gen_translate(self, a1, a2, coordinate, guess=None, name=None):
        """A slider that brings its travel as a coordinate (Mech's GenTranslate2): axis
        ``a2`` slides along axis ``a1`` without turning (rows parallel and offset, as
        translate) and its first point lies ``coordinate`` from a1's first point along
        a1: (a2.first − a1.first) · u1/‖u1‖ − s = 0 (row travel). ``coordinate`` as for
        gen_revolute; GenTranslate2[axis1, axis2] is gen_translate(axis2, axis1)."""
        return self._with_coordinate(GenTranslate, a1, a2, coordinate, guess, name)

    # -- the complex loop form --------------------------------------------------------
    def loop(self, z, name=None):
        """A vector loop written as one complex equation z = 0, the vectors as
        ``length*exp(I*angle)`` (seed 000: ``a*exp(I*th2) + b*exp(I*th3) - c*exp(I*th4) -
        d*exp(I*th1)``): two rows, its real and its imaginary part (Maple's
        evalc(Re(z)), evalc(Im(z))), labelled "loop 1 re" and "loop 1 im" (the second
        loop of a model "loop 2 re", ...). Coordinates, parameters and T are real."""
        return self._add(Loop, (sp.sympify(z) if not isinstance(z, sp.Basic) else z,), name)
