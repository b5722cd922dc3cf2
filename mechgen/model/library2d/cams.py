"""Cam constraints (Mech's CamToPoint1, CamToLine1, CamToCam1) and the ``Model`` methods
that declare them (``CamsMixin``, inherited by ``Model``).

A cam is a body carrying a profile (mechgen.model.library2d.profiles) in its own frame; the
contact parameter s of each profile is an extra coordinate of the model, with its own
name, guess, velocity and acceleration. With c(s) the profile point in the cam's frame,
R the cam's rotation and r_c(s) = (X, Y) + R c(s) its global position, t(s) = R c'(s):

- ``cam_to_point``: a knife-edge follower point p stays on the profile,
  r(p) − r_c(s) = 0 (rows x, y); with ``radius=ρ`` (a roller centred at p) the centre
  stays on the profile offset along its outward normal n(s) = R (y', −x')/‖c'‖ (for a
  counter-clockwise profile; the sign follows the profile's orientation and ``side``):
  r(p) − r_c(s) − ρ n(s) = 0.
- ``cam_to_line``: a flat-faced follower, the axis a touches the profile:
  (a.first − r_c(s)) × u = 0 (on line) and t(s) × u = 0 (tangent).
- ``cam_to_cam``: two profiles touch: r_c1(s1) − r_c2(s2) = 0 (x, y) and t1 × t2 = 0.

Each row counts like any other constraint: net, each removes one degree of freedom
(Mech's "1"). The contact geometry is checked when the constraint is declared, at the
parameters' defaults (profiles.check_contact): a profile that jumps, a cusp, a corner
under a roller, a flat face or another cam, a roller larger than a hollow's radius of
curvature or a flat face on a concave part is a ModelError naming the constraint, the cam
and the parameter value.
"""
from __future__ import annotations

import sympy as sp

from ...errors import ModelError
from ..constraints import Constraint, checked_body, checked_line, checked_point, cross2
from ..geometry import Point
from .profiles import Profile, check_contact, make_profile

PROFILE_POINTS = 96     # points of a profile listed for pictures (plot.glyphs.cams reads)


def _profile(value, kind, pos):
    if not isinstance(value, Profile):
        raise ModelError(f"{kind}: argument {pos} must be a profile made by m.profile(...), "
                         f"got {value!r}")
    return value


def _on_cam(cam, profile, s):
    """(r_c(s), t(s), c'(s)) of ``profile`` on body ``cam`` at parameter ``s``."""
    x, y = profile.curve(s)
    c = sp.Matrix([x, y])
    d = (sp.diff(x, s), sp.diff(y, s))
    return cam.to_global(c), cam.rotate(d), d


class CamToPoint(Constraint):
    """``cam_to_point(cam, profile, p, s[, radius])``: r(p) − r_c(s) − ρ n(s) = 0 (ρ = 0:
    a knife edge), rows x and y."""

    kind = "cam_to_point"
    components = ("x", "y")

    def build(self, cam, profile, p, s, radius=None, sign=1):
        cam = checked_body(self.model, cam, self.kind, 1)
        profile = _profile(profile, self.kind, 2)
        p = checked_point(self.model, p, self.kind, 3)
        r, _, d = _on_cam(cam, profile, s)
        res = p.r - r
        text = f"{cam}, {profile}, {p}, {s}"
        if radius is not None:
            n = cam.rotate((sign * d[1], -sign * d[0])) / sp.sqrt(d[0] ** 2 + d[1] ** 2)
            res = res - radius * n
            text += f", radius={float(radius):g}" if radius.is_Float else f", radius={radius}"
        self.exprs = [res[0], res[1]]
        return text


class CamToLine(Constraint):
    """``cam_to_line(cam, profile, a, s)``: (a.first − r_c(s)) × u = 0 and t(s) × u = 0."""

    kind = "cam_to_line"
    components = ("on line", "tangent")

    def build(self, cam, profile, a, s):
        cam = checked_body(self.model, cam, self.kind, 1)
        profile = _profile(profile, self.kind, 2)
        a = checked_line(self.model, a, self.kind, 3)
        r, t, _ = _on_cam(cam, profile, s)
        u = a.u
        self.exprs = [cross2(a.first.r - r, u), cross2(t, u)]
        return f"{cam}, {profile}, {a}, {s}"


class CamToCam(Constraint):
    """``cam_to_cam(cam1, profile1, cam2, profile2, s1, s2)``: r_c1(s1) − r_c2(s2) = 0
    (x, y) and t1 × t2 = 0 (tangent)."""

    kind = "cam_to_cam"
    components = ("x", "y", "tangent")

    def build(self, cam1, profile1, cam2, profile2, s1, s2):
        cam1 = checked_body(self.model, cam1, self.kind, 1)
        profile1 = _profile(profile1, self.kind, 2)
        cam2 = checked_body(self.model, cam2, self.kind, 3)
        profile2 = _profile(profile2, self.kind, 4)
        r1, t1, _ = _on_cam(cam1, profile1, s1)
        r2, t2, _ = _on_cam(cam2, profile2, s2)
        d = r1 - r2
        self.exprs = [d[0], d[1], cross2(t1, t2)]
        return f"{cam1}, {profile1}, {cam2}, {profile2}, {s1}, {s2}"


CAM_KINDS = {c.kind: c for c in (CamToPoint, CamToLine, CamToCam)}


def contact_problems(model, values) -> list:
    """What the contact-geometry check (profiles.check_contact) finds wrong with each cam
    of ``model`` at the parameters ``values`` (name -> number; the others at their
    defaults), as messages: the check runs where a cam is declared, at the defaults only,
    and a mechanism's with_params asks again (a roller grown past a hollow's radius of
    curvature rolls on a curve that is not the one the cam cuts)."""
    from types import SimpleNamespace
    proxy = SimpleNamespace(params={k: (sym, float(values.get(k, val)))
                                    for k, (sym, val) in model.params.items()})
    out = []
    for con in model.constraints:
        for where, prof, kw, nu in getattr(con, "checks", ()):
            try:
                now = check_contact(where, proxy, prof, **kw)
            except ModelError as exc:
                out.append(exc.message)
                continue
            if now != nu and kw.get("radius") is not None:
                out.append(f"{where}: the profile '{prof}' runs the other way round here: "
                           "the roller, on the side asked at the model's parameters, is now "
                           "on its other side")
    return out


def profile_points(cam, profile, n=PROFILE_POINTS):
    """``n`` points of the profile fixed in the cam (for pictures), parameters kept."""
    out = []
    for k in range(n):
        s = sp.Integer(2 * k) * profile.period / (2 * n) if k else sp.Integer(0)
        x, y = profile.curve(s)
        out.append(Point(cam, (sp.sympify(x), sp.sympify(y)), f"{cam.name}~{profile}[{k}]"))
    return out


class CamsMixin:
    """The cam methods of ``Model`` (mechgen.model.language)."""

    def profile(self, name=None, xy=None, polar=None, points=None, period=None,
                periodic=False) -> Profile:
        """A cam profile in a cam body's own frame; give exactly one of
        ``xy=lambda s: (x(s), y(s))`` (parametric), ``polar=lambda th: r(th)`` (the curve
        (r cos θ, r sin θ)) or ``points=[(x, y), ...]`` (the smooth periodic cubic spline
        through them, its parameter running 0..2π once round the table at equal steps).
        ``period``: the parameter range of one turn (default 2π); ``periodic=True`` calls
        the function with the parameter wrapped into [0, period) (for a law written over
        one turn only, such as a piecewise rise–dwell–return–dwell; a polar profile turns
        once in 2π, its r over a period that divides 2π: one lobe). Expressions may hold
        parameters. ``name`` (default ``profile1``, ``profile2``, ...) names it in labels."""
        if name is None:
            k = 1
            while f"profile{k}" in self._names:
                k += 1
            name = f"profile{k}"
        self._check_name(name, "profile")
        prof = make_profile(self, name, xy=xy, polar=polar, points=points, period=period,
                            periodic=periodic)
        self._claim(name, "profile")
        return prof

    def _cam(self, cls, args, contacts, guesses, name, checks):
        """Declare the contact coordinates, then the constraint; a failure leaves the
        model as it was."""
        number = len(self.constraints) + 1
        where = f"{cls.kind} {number}" + (f" ({name})" if name else "")
        signs = [check_contact(f"{where}, cam '{cam}'", self, prof, **kw)
                 for cam, prof, kw in checks]
        before = (list(self.coords), dict(self.guess), dict(self._names))
        try:
            syms = [self.coordinate(c, guess=g) for c, g in zip(contacts, guesses)]
            con = self._add(cls, args(syms, signs), name)
        except BaseException:
            self.coords[:], self._names = before[0], before[2]
            self.guess.clear()
            self.guess.update(before[1])
            self._equations = None
            raise
        con.contacts = tuple(syms)
        con.checks = [(f"{where}, cam '{cam}'", prof, kw, nu)
                      for (cam, prof, kw), nu in zip(checks, signs)]
        return con

    def _contact_names(self, contact, k):
        number = len(self.constraints) + 1
        if contact is None:
            return [f"s{number}"] if k == 1 else [f"s{number}_{i}" for i in (1, 2)]
        names = [contact] if isinstance(contact, str) else list(contact)
        if len(names) != k:
            raise ModelError(f"contact= must name {k} coordinate{'s' if k > 1 else ''}, "
                             f"got {contact!r}")
        return names

    def cam_to_point(self, cam, profile, point, contact=None, guess=0.0, radius=None,
                     side="outside", name=None):
        """A point follower on a cam (Mech's CamToPoint1): ``point`` (of another body)
        stays on ``profile`` of body ``cam``; two equations and one new coordinate, the
        contact parameter named ``contact`` (default ``s<n>``, n the constraint's number)
        with ``guess``. ``radius=ρ``: a roller of radius ρ centred at ``point`` rolls on
        the profile (``side="outside"`` the cam, or ``"inside"`` a groove or hollow cam):
        the centre stays on the profile offset by ρ along its normal."""
        if side not in ("outside", "inside"):
            raise ModelError(f"cam_to_point: side must be 'outside' or 'inside', got {side!r}")
        if radius is not None:
            radius = self._expr(radius, "cam_to_point: the radius")
        sgn = 1 if side == "outside" else -1
        kw = dict(radius=radius, side=sgn) if radius is not None else {}
        con = self._cam(CamToPoint,
                        lambda syms, nus: (cam, profile, point, syms[0], radius, sgn * nus[0]),
                        self._contact_names(contact, 1), [guess], name,
                        [(cam, _profile(profile, "cam_to_point", 2), kw)])
        extra = []
        if radius is not None:     # a rim point of the roller, for pictures
            extra = [Point(point.body, (point.local[0] + radius, point.local[1]),
                           f"{point}~rim")]
        con.points = [point] + extra + profile_points(cam, profile)
        return con

    def cam_to_line(self, cam, profile, axis, contact=None, guess=0.0, name=None):
        """A flat-faced follower on a cam (Mech's CamToLine1): ``axis`` (of another body)
        touches ``profile`` of body ``cam``, the contact point on the line and the
        profile's tangent parallel to it; two equations and one new coordinate (the
        contact parameter). The profile must be convex."""
        con = self._cam(CamToLine, lambda syms, nus: (cam, profile, axis, syms[0]),
                        self._contact_names(contact, 1), [guess], name,
                        [(cam, _profile(profile, "cam_to_line", 2), dict(convex=True))])
        ends = [axis.first] + ([axis.second] if axis.second is not None else [])
        con.points = ends + profile_points(cam, profile)
        return con

    def cam_to_cam(self, cam1, profile1, cam2, profile2, contact=None, guess=(0.0, 0.0),
                   name=None):
        """Two cams touching (Mech's CamToCam1): ``profile1`` of ``cam1`` and ``profile2``
        of ``cam2`` share a point and a tangent there; three equations and two new
        coordinates (the contact parameters, ``contact=(s1, s2)``, ``guess=(g1, g2)``)."""
        try:
            g1, g2 = guess
        except (TypeError, ValueError):
            raise ModelError(f"cam_to_cam: guess must be a pair (g1, g2), got {guess!r}") \
                from None
        con = self._cam(CamToCam,
                        lambda syms, nus: (cam1, profile1, cam2, profile2, syms[0], syms[1]),
                        self._contact_names(contact, 2), [g1, g2], name,
                        [(cam1, _profile(profile1, "cam_to_cam", 2), dict(corners=True)),
                         (cam2, _profile(profile2, "cam_to_cam", 4), dict(corners=True))])
        con.points = profile_points(cam1, profile1) + profile_points(cam2, profile2)
        return con


__all__ = ["CamsMixin", "CamToPoint", "CamToLine", "CamToCam", "CAM_KINDS", "PROFILE_POINTS",
           "contact_problems"]
