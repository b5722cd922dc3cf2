"""The scene a generated module states: its bodies (with colours), their points, the
joints between them, and the pose of every body over a motion.

Read from ``POINTS``, ``BODIES``, ``JOINTS``, ``BODY_POINTS`` and ``LOADS`` of the module and from
solved coordinates; nothing here draws.
"""
from __future__ import annotations

import re

import numpy as np

from ..errors import MechgenError
from .style import GROUND, PALETTE, tints

# body.at(x, y): a point fixed in a body at local (x, y), as in the model language
_AT = re.compile(r"^\s*(\w+)\s*\.\s*at\s*\(\s*([^,()]+?)\s*,\s*([^,()]+?)\s*\)\s*$")
# a point's global coordinate: "foot[3].x", "coupler.at(1.2, 0.8).y"
_COORDINATE = re.compile(r"^\s*(.+?)\s*\.\s*([xy])\s*$")


def point_coordinate(name):
    """(point name, 0 or 1) for a name such as ``foot[3].x`` or ``body.at(1, 2).y`` (a
    point's global x or y), else None. Coordinates and outputs never hold a dot."""
    found = _COORDINATE.match(name) if isinstance(name, str) else None
    if found is None:
        return None
    return found.group(1), "xy".index(found.group(2))


class Body:
    """One body of the scene: where its points are in ``POINTS`` and its colours."""

    def __init__(self, name, number, ground, origin, pts, every, th, color):
        self.name, self.number, self.ground = name, number, ground
        self.origin = origin        # index into POINTS of body[0], -1 for the ground
        self.pts = pts              # indices of P1, P2, ...
        self.every = every          # every POINTS index of this body
        self.th = th                # index of Th<n> in q, None for the ground
        self.fill, self.edge = color


class Scene:
    """Bodies, points and joints of a loaded mechanism, from its generated module.
    ``colors`` ({body name: colour}) overrides the palette."""

    def __init__(self, mech, colors=None):
        mod = mech.module
        self.name = mech.name
        self.labels = [label for label, _ in mod.POINTS]
        owner = [body for _, body in mod.POINTS]
        self.owner = owner
        stated = {name: (origin, tuple(pts))
                  for name, origin, pts in getattr(mod, "BODY_POINTS", ())}
        self.joints = [(n, kind, tuple(used)) for n, kind, used in getattr(mod, "JOINTS", ())]
        self.loads = [(n, kind, tuple(used)) for n, kind, used in getattr(mod, "LOADS", ())]
        self.bodies, self.by_name = [], {}
        index = {c: k for k, c in enumerate(mech.coordinates)}
        colors = dict(colors or {})
        moving = 0
        for name, number, ground in mod.BODIES:
            every = [k for k, b in enumerate(owner) if b == name]
            if name in stated:
                origin, pts = stated[name]
            else:  # a module without BODY_POINTS: its labels are all we have
                tag = f"{name}[0]"
                origin = -1 if ground else self.labels.index(tag) if tag in self.labels else -1
                pts = tuple(k for k in every if k != origin)
            th = None if ground else index.get(f"Th{number}")
            if ground:
                color = GROUND
            else:
                color = PALETTE[moving % len(PALETTE)]
                moving += 1
            if name in colors:
                color = tints(colors.pop(name))
            body = Body(name, number, bool(ground), origin, pts, every, th, color)
            self.bodies.append(body)
            self.by_name[name] = body
        if colors:
            raise MechgenError(f"colors: no body named {', '.join(map(repr, colors))} in "
                               f"'{self.name}' (bodies: {', '.join(self.by_name)})")
        if not self.labels:
            raise MechgenError(f"'{self.name}' has no bodies with points to draw (a model "
                               "written in coordinates only, such as a loop-closure model, "
                               "has no geometry; plot its quantities with plot())")

    def point(self, label) -> int:
        """The POINTS index of a label: a POINTS label, or ``body[k]`` (P-number k)."""
        if isinstance(label, (int, np.integer)):
            if 0 <= label < len(self.labels):
                return int(label)
            raise MechgenError(f"point index {label} out of range ({len(self.labels)} points)")
        if label in self.labels:
            return self.labels.index(label)
        name, _, rest = str(label).partition("[")
        if name in self.by_name and rest.endswith("]") and rest[:-1].isdigit():
            body, k = self.by_name[name], int(rest[:-1])
            if k == 0 and body.origin >= 0:
                return body.origin
            if 1 <= k <= len(body.pts):
                return body.pts[k - 1]
        raise MechgenError(f"'{self.name}' has no point {label!r}; its points: "
                           f"{', '.join(self.point_names())}; or body.at(x, y) for any "
                           f"point fixed in a body (bodies: {', '.join(self.by_name)})")

    def point_names(self) -> list:
        """Every point name point() and locate() take, in body order: ``body[0]`` (the
        body's origin; the ground's is the global origin), ``body[1]``, ... (a point that
        coincides with another is listed under each of its names), then any other label
        of the module's POINTS."""
        out = []
        for b in self.bodies:
            if b.ground or b.origin >= 0:
                out.append(f"{b.name}[0]")
            out += [f"{b.name}[{k}]" for k in range(1, len(b.pts) + 1)]
        # (a cam's profile points, "cam~disc[5]", are the drawing's, not named points)
        return out + [label for label in self.labels if label not in out and "~" not in label]

    def locate(self, label):
        """Where a point is over a motion: ``(body, path)``, ``path(P, Q)`` giving its
        positions (F, 2) over frames P (F, N, 2), Q (F, n). ``label`` is a point of the
        module (see point()) or ``body.at(x, y)``: the point at local (x, y) of a body,
        which the model need not name (a coupler point whose curve to trace)."""
        # a label of the module's own (a point the model placed with body.at(expr, ...),
        # "ring.at(-rr, 0)") is that point, not a local position to parse
        found = _AT.match(label) if isinstance(label, str) and label not in self.labels \
            else None
        if found is None:
            ground = next((b for b in self.bodies if b.ground and label == f"{b.name}[0]"
                           and label not in self.labels), None)
            if ground is not None:      # the ground's origin: the global one, never moving
                return ground, lambda P, Q: np.zeros((P.shape[0], 2))
            k = self.point(label)
            return self.by_name[self.owner[k]], lambda P, Q: P[:, k]
        name, xs, ys = found.groups()
        if name not in self.by_name:
            raise MechgenError(f"'{self.name}' has no body {name!r} (in {label!r}; bodies: "
                               f"{', '.join(self.by_name)})")
        try:
            xy = np.array([float(xs), float(ys)])
        except ValueError:
            raise MechgenError(f"{label!r}: body.at(x, y) takes two numbers") from None
        body, i = self.by_name[name], self.bodies.index(self.by_name[name])
        if not body.ground and body.origin < 0:
            raise MechgenError(f"{label!r}: the module does not state where body {name!r} "
                               "has its origin; trace one of its points instead")

        def path(P, Q):
            org, ang = self.poses(P, Q)
            c, s = np.cos(ang[:, i]), np.sin(ang[:, i])
            return org[:, i] + np.column_stack([c * xy[0] - s * xy[1], s * xy[0] + c * xy[1]])
        return body, path

    def poses(self, P, Q):
        """Origins (F, nb, 2) and angles (F, nb) of every body over frames P (F, N, 2)."""
        F = P.shape[0]
        org = np.zeros((F, len(self.bodies), 2))
        ang = np.zeros((F, len(self.bodies)))
        for i, b in enumerate(self.bodies):
            if b.ground:
                continue
            if b.origin >= 0:
                org[:, i] = P[:, b.origin]
            if b.th is not None:
                ang[:, i] = Q[:, b.th]
        return org, ang
