"""A FourBar written out as a model file: the text of FourBar.model() in the model language
(parameters with their numbers, the bodies, the joints, the crank's driver), which
``mechgen build`` compiles like any other model file; the poses and the times at which the
model reaches them are kept in the file's docstring and as POSES and TIMES."""
from __future__ import annotations

import math
import re

import numpy as np

from .poses import place


def identifier(name) -> str:
    """``name`` made a model name: letters, digits and underscores, not starting with a
    digit ("fourbar" when nothing is left)."""
    text = re.sub(r"\W+", "_", str(name)).strip("_")
    if not text:
        return "fourbar"
    return "m_" + text if text[0].isdigit() else text


def model_source(fourbar, name="fourbar", source=None) -> str:
    """The model file of ``fourbar`` (a synthesis.FourBar): a Model named ``name`` built as
    FourBar.model(name) builds it. ``source``: where the poses came from, for the
    docstring."""
    name = identifier(name)
    a, b, c, d = fourbar.lengths
    O2, O4 = fourbar.input.fixed, fourbar.output.fixed
    uA, uB = fourbar.input.moving, fourbar.output.moving
    poses = np.asarray(fourbar.poses, dtype=float)
    p1 = poses[0]
    B1 = place(p1, uB)
    psi1 = math.atan2(B1[1] - O4[1], B1[0] - O4[0])
    phi1 = float(fourbar.phis[0])
    sign = "+" if fourbar.direction > 0 else "-"
    turn = "counter-clockwise" if sign == "+" else "clockwise"
    flags = ", ".join(sorted(fourbar.defects)) or "no defects"
    lo, hi = fourbar.transmission
    rows = "\n".join(f"    {j + 1}  x = {x:.6g}, y = {y:.6g}, angle = {th:.6g} rad"
                     f"   at T = {t:.6g}" for j, ((x, y, th), t)
                     in enumerate(zip(poses, fourbar.times)))
    where = f" ({source})" if source else ""
    listed = "\n".join(f"    ({_num(x)}, {_num(y)}, {_num(th)})," for x, y, th in poses)
    r = _num
    return f'''"""A four-bar through {len(poses)} poses{where}, made by mechgen synthesize:
{fourbar.grashof}, {flags}, transmission angle {lo:.1f}–{hi:.1f}°; links a = {a:.6g}
(crank), b = {b:.6g} (coupler), c = {c:.6g} (output), d = {d:.6g} (ground).

The crank turns {turn}, one radian per unit of T. The coupler's frame is the
poses' frame: coupler[3] (its origin) lies on a pose's (x, y) and coupler[3] -> coupler[4]
along its angle, at these times:
{rows}
"""
from mechgen import Model, T

POSES = [
{listed}
]
TIMES = [{", ".join(_num(t) for t in fourbar.times)}]

m = Model({name!r})

x_O2 = m.param("x_O2", {r(O2[0])})
y_O2 = m.param("y_O2", {r(O2[1])})
x_O4 = m.param("x_O4", {r(O4[0])})
y_O4 = m.param("y_O4", {r(O4[1])})
a = m.param("a", {r(a)})
c = m.param("c", {r(c)})
x_A = m.param("x_A", {r(uA[0])})
y_A = m.param("y_A", {r(uA[1])})
x_B = m.param("x_B", {r(uB[0])})
y_B = m.param("y_B", {r(uB[1])})
phi0 = m.param("phi0", {r(phi1)})

ground = m.ground("ground", points=[(x_O2, y_O2), (x_O4, y_O4)])
crank = m.body("crank", points=[(0, 0), (a, 0)],
               guess=({r(O2[0])}, {r(O2[1])}, {r(phi1)}))
coupler = m.body("coupler", points=[(x_A, y_A), (x_B, y_B), (0, 0), ({r(0.5 * b)}, 0)],
                 guess=({r(p1[0])}, {r(p1[1])}, {r(p1[2])}))
output = m.body("output", points=[(0, 0), (c, 0)],
                guess=({r(O4[0])}, {r(O4[1])}, {r(psi1)}))

m.revolute(ground[1], crank[1], name="O2")
m.rotation_lock(crank, ground, phi0 {sign} T, name="crank driver")
m.revolute(crank[2], coupler[1], name="A")
m.revolute(ground[2], output[1], name="O4")
m.revolute(coupler[2], output[2], name="B")
'''


def _num(x) -> str:
    """The shortest text that reads back as the same float (no -0)."""
    return repr(float(x) + 0.0)
