"""The lengths that keep a loop of revolutes from closing, for `mechgen check`'s CANNOT
ASSEMBLE: where the constraints that contradict each other are one closed chain of
revolute joints (a four-bar, a five-bar: each body joined to the next at two points,
the ground counted once), with at most one driver turning a body pinned to the ground
(a crank), the report names the dimensions whose sum or difference fails.

Without a driver the chain closes where its longest link is at most the sum of the
others. With the crank at its driven angle, the rest of the chain must span the
distance δ from the crank's far joint to the ground's other pivot: δ at most the sum of
those links, and at least the longest of them minus the others.
"""
from __future__ import annotations

import math

import sympy as sp

from ..model.geometry import T

GROUND = "<ground>"       # the ground bodies, one node (a body name cannot hold "<")


def _node(body) -> str:
    return GROUND if body.is_ground else body.name


def _number(expr, values) -> float:
    return float(sp.sympify(expr).subs(values))


class _Link:
    """A body of the loop between its two joints: its length (a number and how it is
    written: a parameter's name where the length is one)."""

    def __init__(self, body, p, p_next, values):
        self.body, self.p, self.next = body, p, p_next
        if body is None:                # the ground: its two pivots' positions
            a, b = p.r, p_next.r
        else:
            a, b = sp.Matrix(p.local), sp.Matrix(p_next.local)
        expr = sp.simplify(sp.sqrt((b[0] - a[0]) ** 2 + (b[1] - a[1]) ** 2))
        self.length = _number(expr, values)
        name = "ground" if body is None else body.name
        if isinstance(expr, sp.Abs):
            expr = expr.args[0]
        self.text = f"{expr} ({name})" if expr.is_Symbol else f"{name} {p}–{p_next}"

    def said(self) -> str:
        return f"{self.text} = {self.length:.6g}"


def _chain(revolutes):
    """The revolutes in loop order as [(node, point in, point out)], or None when they
    are not one closed chain (every node joined exactly twice)."""
    ends = {}
    for c in revolutes:
        p1, p2 = c.points
        for p in (p1, p2):
            ends.setdefault(_node(p.body), []).append((c, p))
    if len(ends) < 3 or any(len(v) != 2 for v in ends.values()):
        return None
    order, node, came = [], GROUND if GROUND in ends else next(iter(ends)), None
    for _ in range(len(revolutes)):
        (c1, p1), (c2, p2) = ends[node]
        c_in, p_in, c_out, p_out = (c1, p1, c2, p2) if c2 is not came else (c2, p2, c1, p1)
        order.append((node, p_in, p_out))
        came = c_out
        q1, q2 = c_out.points
        node = _node(q2.body if q1 is p_out else q1.body)
    if node != order[0][0] or len({n for n, _, _ in order}) != len(order):
        return None
    return order


def _crank_angle(driver, body, values, t):
    """The angle the driver gives ``body`` at t (None unless that is all it does)."""
    if driver.kind != "rotation_lock" or len(driver.exprs) != 1:
        return None
    expr = sp.sympify(driver.exprs[0]).subs(values).subs(T, t)
    if expr.free_symbols != {body.th}:
        return None
    roots = sp.solve(expr, body.th)
    return float(roots[0]) if len(roots) == 1 and roots[0].is_number else None


def loop_dimensions(model, culprits, t) -> list:
    """Report lines naming the lengths that keep the loop of ``culprits`` (constraints)
    from closing at t; [] where the culprits are not such a loop or the lengths allow it
    (or a length is not a number at the parameters' defaults: the report goes without)."""
    try:
        return _dimensions(model, culprits, t)
    except (TypeError, ValueError, ZeroDivisionError, NotImplementedError):
        return []


def _dimensions(model, culprits, t) -> list:
    values = {sym: val for sym, val in model.params.values()}
    revolutes = [c for c in culprits if c.kind == "revolute" and hasattr(c, "points")]
    others = [c for c in culprits if c not in revolutes]
    if len(others) > 1 or any(not c.is_driver for c in others):
        return []
    order = _chain(revolutes)
    if order is None or order[0][0] != GROUND:
        return []
    bodies = {b.name: b for b in model.bodies.values()}
    links = [_Link(None if n == GROUND else bodies[n], p_in, p_out, values)
             for n, p_in, p_out in order]
    if not others:
        return _closure(links)
    # the crank: a body next to the ground, turned by the driver
    for k in (1, len(links) - 1):
        angle = _crank_angle(others[0], links[k].body, values, t)
        if angle is not None:
            return _spanned(links, k, angle, values, t)
    return []


def _closure(links) -> list:
    longest = max(links, key=lambda x: x.length)
    rest = [x for x in links if x is not longest]
    total = sum(x.length for x in rest)
    if longest.length <= total:
        return []
    return [f"  the loop cannot close: its longest link {longest.said()} > "
            f"{' + '.join(x.text for x in rest)} = {total:.6g}"]


def _spanned(links, k, angle, values, t) -> list:
    """The crank links[k] at ``angle``: can the links after it span the gap?"""
    crank = links[k]
    if k == 1:          # ground, crank, ..., ground: the chain runs on from its tip
        pivot, tip, rest, far, fixed = (crank.p, crank.next, links[2:], links[0].p,
                                        links[0].next)
    else:               # ..., crank, ground: the chain reaches its tip backwards
        pivot, tip, rest, far, fixed = (crank.next, crank.p, links[1:k], links[0].next,
                                        links[0].p)
    # the crank's tip: its pivot (the ground's point it turns about) plus its arm turned
    # by the driven angle
    arm = [_number(v, values) - _number(w, values) for v, w in zip(tip.local, pivot.local)]
    origin = [_number(v, values) for v in fixed.r]
    c, s = math.cos(angle), math.sin(angle)
    tip_at = (origin[0] + c * arm[0] - s * arm[1], origin[1] + s * arm[0] + c * arm[1])
    far_at = [_number(v, values) for v in far.r]
    gap = math.hypot(far_at[0] - tip_at[0], far_at[1] - tip_at[1])
    total = sum(x.length for x in rest)
    longest = max(rest, key=lambda x: x.length)
    shortest_gap = longest.length - (total - longest.length)
    names = " + ".join(x.text for x in rest)
    ground, crank_len = links[0].length, crank.length
    if math.isclose(gap, ground + crank_len, rel_tol=1e-9):
        left = f"{crank.text} + {links[0].text} = {gap:.6g}"
    elif math.isclose(gap, abs(ground - crank_len), rel_tol=1e-9):
        left = f"|{crank.text} − {links[0].text}| = {gap:.6g}"
    else:
        left = f"{tip}–{far} = {gap:.6g}"
    why = (f" (at t = {t:g} the driver turns {crank.body.name} to {angle:.6g} rad: {tip} "
           f"is {gap:.6g} from {far}, which {names} must span)")
    if gap > total * (1 + 1e-12):
        return [f"  the loop cannot close: {left} > {names} = {total:.6g}" + why]
    if gap < shortest_gap * (1 - 1e-12):
        others = [x.text for x in rest if x is not longest]
        others = others[0] if len(others) == 1 else f"({' + '.join(others)})"
        return [f"  the loop cannot close: {left} < {longest.text} − {others} = "
                f"{shortest_gap:.6g}" + why]
    return []
