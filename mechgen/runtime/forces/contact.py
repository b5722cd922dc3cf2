"""The scalar force a contact transmits (``s.contact(name)``, ``sw.contact(name)``), read
from the generated module alone: its constraint kinds (CONSTRAINTS), the points each
constraint names (JOINTS, POINTS: a roller's rim point, a profile's sample points, a gear's
pitch marker) and Φ_q and λ at every point.

- A cam (cam_to_point, cam_to_line, cam_to_cam): the normal contact force, positive when
  the cam pushes the follower (cam_to_cam: cam 1 pushes cam 2); negative, the contact
  would have to pull: the follower has lost contact. The follower's force is what the
  constraint applies to its body, −Φ_q[rows]ᵀλ on its X, Y; the normal is the one
  across the profile's tangent, Φ_q's column of the contact parameter (∂Φ/∂s ∥ t(s)),
  or (a flat face) the gradient of the on-line row on the body's X, Y. Which way it
  points is read once, from the geometry of a reference configuration: a roller is
  pushed from the profile's nearest point towards its centre (outside the profile or in
  a groove alike), a knife edge outwards (it rides the profile's outside), a flat face
  away from the profile's side of its line, cam 2 away from cam 1's material.
- Gears (gears, gear_ratio): the tooth force along the line of action at the pitch point
  (pressure angle 0: the tangent to the pitch circles), W = the torque the mesh applies
  to a gear about its centre / its signed pitch radius, the same for both gears (each
  radius read from its pitch marker).
- A rack (rack_and_pinion, rack_ratio): the force the pinion applies to the rack along
  the rack's axis (its first point towards its second).
- A joint (revolute, translate, point_on_line): the magnitude of the force it carries
  (the pin force; the guide's or slot's normal force), never negative; the components
  and the moment are ``reaction``'s.
"""
from __future__ import annotations

import numpy as np

from .lookup import tables

CAM_KINDS = ("cam_to_point", "cam_to_line", "cam_to_cam")
GEAR_KINDS = ("gears", "gear_ratio")
RACK_KINDS = ("rack_and_pinion", "rack_ratio")
JOINT_KINDS = ("revolute", "translate", "point_on_line")
CONTACT_KINDS = CAM_KINDS + GEAR_KINDS + RACK_KINDS + JOINT_KINDS
CHUNK = 4096          # points whose Φ_q rows are held at once


def _rot(th, v):
    """v (..., 2) turned by th (scalar or (...))."""
    c, s = np.cos(th), np.sin(th)
    v = np.asarray(v)
    return np.stack([c * v[..., 0] - s * v[..., 1], s * v[..., 0] + c * v[..., 1]], axis=-1)


def _left(v):
    """v (..., 2) turned a quarter turn counter-clockwise."""
    v = np.asarray(v)
    return np.stack([-v[..., 1], v[..., 0]], axis=-1)


def _dot(a, b):
    return np.einsum("...i,...i->...", a, b)


def _nearest_on_polygon(poly, x):
    """(the point of the closed polygon ``poly`` nearest to x, its segment's index)."""
    a, b = poly, np.roll(poly, -1, axis=0)
    d = b - a
    length2 = np.einsum("ij,ij->i", d, d)
    length2[length2 == 0] = 1.0
    u = np.clip(np.einsum("ij,ij->i", x - a, d) / length2, 0.0, 1.0)
    foot = a + u[:, None] * d
    k = int(np.argmin(np.einsum("ij,ij->i", foot - x, foot - x)))
    return foot[k], k


def _inside(poly, x):
    """Whether the points x (k, 2) lie inside the closed polygon (even-odd rule)."""
    a, b = poly, np.roll(poly, -1, axis=0)
    x = np.atleast_2d(x)
    up = (a[None, :, 1] > x[:, None, 1]) != (b[None, :, 1] > x[:, None, 1])
    with np.errstate(divide="ignore", invalid="ignore"):
        cross_x = a[None, :, 0] + (x[:, None, 1] - a[None, :, 1]) * \
            (b[None, :, 0] - a[None, :, 0]) / (b[None, :, 1] - a[None, :, 1])
    return np.sum(up & (x[:, None, 0] < cross_x), axis=1) % 2 == 1


def _area_sign(poly):
    """+1 for a counter-clockwise closed polygon, −1 for a clockwise one."""
    x, y = poly[:, 0], poly[:, 1]
    return 1.0 if np.sum(x * np.roll(y, -1) - np.roll(x, -1) * y) >= 0 else -1.0


class Contact:
    """One constraint's contact, its geometry read from a reference configuration
    (q_ref, t_ref): ``value(J, lam, q)`` is its scalar force at a point."""

    def __init__(self, mech, name, q_ref, t_ref):
        tab = tables(mech)
        mod = mech.module
        self.mech, self.tab = mech, tab
        self.label, self.rows, _ = tab.constraint(name, mech)
        number, kind = next((n, k) for n, k, lab, _, _ in mod.CONSTRAINTS if lab == self.label)
        self.kind = kind
        if kind not in CONTACT_KINDS:
            raise ValueError(f"contact: constraint {self.label!r} of model '{mech.name}' is a "
                             f"{kind}; contact forces are defined for {', '.join(CONTACT_KINDS)}"
                             " (any constraint's force and moment on a body: reaction())")
        joints = {n: pts for n, _, pts in getattr(mod, "JOINTS", ())}
        if number not in joints:
            raise ValueError(f"contact: the module of model '{mech.name}' does not list the "
                             "points its constraints name (JOINTS): build it again")
        self.pts = list(joints[number])
        self.body_of = [mod.POINTS[k][1] for k in self.pts]
        self.q_ref = np.asarray(q_ref, dtype=float)
        self.xy = mech.points_at(self.q_ref, t_ref)
        J = mech.jacobian(self.q_ref, t_ref)
        if kind in CAM_KINDS:
            getattr(self, f"_{kind}")(J)
        elif kind in GEAR_KINDS:
            self._gears()
        elif kind in RACK_KINDS:
            self._rack()
        else:
            self.body = self.body_of[0]

    # -- geometry at the reference configuration ----------------------------------------
    def _frame(self, body, q):
        """(origin, angle) of ``body`` at q ((0, 0), 0 for the ground)."""
        idx = self.tab.bodies[body]
        if idx is None:
            return np.zeros(2), 0.0
        return q[list(idx[:2])], q[idx[2]]

    def _local(self, body, xy):
        """The body-frame coordinates of a global point (or direction) at the reference."""
        origin, th = self._frame(body, self.q_ref)
        return _rot(-th, xy - origin)

    def _contact_columns(self, J):
        """The coordinates other than bodies' (contact parameters) these rows hold."""
        body_cols = {c for idx in self.tab.bodies.values() if idx is not None for c in idx}
        return [c for c in range(J.shape[1])
                if c not in body_cols and np.any(J[list(self.rows), c] != 0)]

    def _moving(self, *bodies):
        return next((b for b in bodies if self.tab.bodies[b] is not None), None)

    def _sign_of(self, v_ref, push):
        """+1 or −1: the sign that turns the normal v_ref the way the contact pushes."""
        if not np.dot(v_ref, push) != 0:
            raise ValueError(f"contact: cannot tell which way {self.label!r} pushes at the "
                             "reference configuration")
        return 1.0 if np.dot(v_ref, push) > 0 else -1.0

    def _tangent_normal(self, J, col, rows):
        return _left(J[rows, col])

    def _cam_to_point(self, J):
        follower = self.body_of[0]
        rest = list(range(1, len(self.pts)))
        roller = bool(rest) and self.body_of[1] == follower
        samples = self.xy[[self.pts[k] for k in rest[1:]] if roller else
                          [self.pts[k] for k in rest]]
        cols = self._contact_columns(J)
        if len(cols) != 1:
            raise ValueError(f"contact: {self.label!r}: expected one contact coordinate")
        self.col, self.xy_rows, self.body = cols[0], list(self.rows), follower
        centre = self.xy[self.pts[0]]
        foot, seg = _nearest_on_polygon(samples, centre)
        if roller:                  # from the profile towards the roller's centre
            push = centre - foot
        else:                       # a knife edge rides the outside: the outward normal
            along = np.roll(samples, -1, axis=0)[seg] - samples[seg]
            push = -_area_sign(samples) * _left(along)
        self.sign = self._sign_of(self._tangent_normal(J, self.col, self.xy_rows), push)

    def _cam_to_line(self, J):
        follower = self.body_of[0]
        samples = self.xy[[k for k, b in zip(self.pts, self.body_of) if b != follower]]
        self.body = follower
        moving = self._moving(follower, self.mech.module.POINTS[self.pts[-1]][1])
        xy_cols = list(self.tab.bodies[moving][:2])
        self.xy_cols = xy_cols
        self.row = max(self.rows, key=lambda r: np.hypot(*J[r, xy_cols]))
        push = self.xy[self.pts[0]] - samples.mean(axis=0)
        self.sign = self._sign_of(J[self.row, xy_cols], push)

    def _cam_to_cam(self, J):
        cam1, cam2 = self.body_of[0], self.body_of[-1]
        poly1 = self.xy[[k for k, b in zip(self.pts, self.body_of) if b == cam1]]
        poly2 = self.xy[[k for k, b in zip(self.pts, self.body_of) if b == cam2]]
        cols = self._contact_columns(J)
        if len(cols) != 2:
            raise ValueError(f"contact: {self.label!r}: expected two contact coordinates")
        moving = self._moving(cam1, cam2)
        xy_cols = list(self.tab.bodies[moving][:2])
        self.xy_rows = [r for r in self.rows if np.any(J[r, xy_cols] != 0)]
        self.col, self.body = cols[0], cam2
        gaps = [(np.linalg.norm(_nearest_on_polygon(poly1, x)[0] - x), k)
                for k, x in enumerate(poly2)]
        _, seg = _nearest_on_polygon(poly1, poly2[min(gaps)[1]])
        along = np.roll(poly1, -1, axis=0)[seg] - poly1[seg]
        push = -_area_sign(poly1) * _left(along)      # cam 1's outward normal
        if np.mean(_inside(poly1, poly2)) > 0.5:      # cam 2 inside cam 1: a hollow cam 1
            push = -push
        self.sign = self._sign_of(self._tangent_normal(J, self.col, self.xy_rows), push)

    def _gears(self):
        p1, m1, p2, m2 = self.pts[:4]
        gear = self._moving(self.body_of[0], self.body_of[2])
        centre, marker = (p1, m1) if gear == self.body_of[0] else (p2, m2)
        self.body = gear
        self.centre = self._local(gear, self.xy[centre])
        self.radius = float(self._local(gear, self.xy[marker])[0] - self.centre[0])

    def _rack(self):
        rack = self.body_of[2]
        self.body = rack
        origin, th = self._frame(rack, self.q_ref)
        u = _rot(-th, self.xy[self.pts[3]] - self.xy[self.pts[2]])
        self.axis = u / np.linalg.norm(u)

    # -- many points ----------------------------------------------------------------------
    def _body_force(self, gen, Q):
        """(F (K, 2), moment about the body's origin (K,), origin (K, 2), angle (K,)) that
        the constraint applies to self.body, from its generalized force gen (K, n); the
        ground's by Newton's third law, about the global origin."""
        idx = self.tab.bodies[self.body]
        if idx is not None:
            return (gen[:, list(idx[:2])], gen[:, idx[2]], Q[:, list(idx[:2])], Q[:, idx[2]])
        force, moment = np.zeros((len(gen), 2)), np.zeros(len(gen))
        for other in self.tab.bodies.values():
            if other is not None:
                f = gen[:, list(other[:2])]
                force -= f
                moment -= gen[:, other[2]] + Q[:, other[0]] * f[:, 1] - Q[:, other[1]] * f[:, 0]
        return force, moment, np.zeros((len(gen), 2)), np.zeros(len(gen))

    def values(self, JR, LAM, Q) -> np.ndarray:
        """The contact's scalar force at K points from Φ_q's rows of the constraint JR
        (K, rows, n), λ (K, m) and q (K, n)."""
        rows = list(self.rows)
        gen = -np.einsum("kri,kr->ki", JR, LAM[:, rows])
        force, moment, origin, th = self._body_force(gen, Q)
        kind = self.kind
        if kind in JOINT_KINDS:
            return np.hypot(force[:, 0], force[:, 1])
        if kind in GEAR_KINDS:
            d = -_rot(th, self.centre)          # from the gear's centre to the origin
            return (moment + d[:, 0] * force[:, 1] - d[:, 1] * force[:, 0]) / self.radius
        if kind in RACK_KINDS:
            return _dot(force, _rot(th, self.axis))
        at = {r: i for i, r in enumerate(rows)}
        if kind == "cam_to_line":
            normal = JR[:, at[self.row], self.xy_cols]
        else:
            normal = _left(JR[:, [at[r] for r in self.xy_rows], self.col])
        return self.sign * _dot(force, normal) / np.hypot(normal[:, 0], normal[:, 1])


def contact_values(mech, names, ts, Q, LAM) -> dict:
    """{label: the contact force at every point (ts[k], Q[k], LAM[k])} for each constraint
    of ``names`` (one name: its array alone); NaN where λ is NaN (no force balance), zero
    where the model has no mass or loads. Each constraint's geometry is read at the first
    finite point; Φ_q's rows at every point, CHUNK points at a time."""
    one = isinstance(names, (str, int))
    tab = tables(mech)
    labels = [tab.constraint(name, mech)[0] for name in ([names] if one else names)]
    ts = np.atleast_1d(np.asarray(ts, dtype=float))
    Q, LAM = np.atleast_2d(Q), np.atleast_2d(LAM)
    good = np.flatnonzero(np.all(np.isfinite(LAM), axis=1) & np.all(np.isfinite(Q), axis=1))
    out = {label: np.full(len(ts), np.nan) for label in labels}
    if good.size:
        cons = [Contact(mech, label, Q[good[0]], ts[good[0]]) for label in labels]
        if not tab.forces:               # no mass, no loads: every λ, every force is zero
            for label in labels:
                out[label][good] = 0.0
        else:
            _fill(mech, cons, ts, Q, LAM, good, out)
    return out[labels[0]] if one else out


def _fill(mech, cons, ts, Q, LAM, good, out):
    """Each contact's values at the points ``good``, Φ_q CHUNK points at a time."""
    for a in range(0, len(good), CHUNK):
        ks = good[a:a + CHUNK]
        JK = np.empty((len(ks), mech.m, mech.n))
        for i, k in enumerate(ks):
            mech.module.phi_q(Q[k], float(ts[k]), mech.p, JK[i])
        for con in cons:
            out[con.label][ks] = con.values(JK[:, list(con.rows)], LAM[ks], Q[ks])


def contact_labels(mech, kinds=CAM_KINDS + GEAR_KINDS + RACK_KINDS) -> list:
    """The labels of the module's constraints of these kinds, in the model's order."""
    return [label for _, kind, label, _, _ in mech.module.CONSTRAINTS if kind in kinds]
