"""The generalized forces of a model's masses and loads, in its coordinates (sympy only).

In body coordinates (X, Y, Th of each body's origin) a body's centroid is
r_G = (X, Y) + R(Th)·c. With J_P = ∂r_P/∂q the Jacobian of a point:

- applied, non-conservative, Q_a = Σ J_Pᵀ F (forces), + M on the body's Th (moments),
  − c·L̇·∂L/∂q (dampers, L the distance of their points);
- conservative, Q_c = −∂V/∂q, V = −Σ m g·r_G (gravity) + Σ ½k(L − L0)² (springs; a
  spring whose k or L0 reads the coordinates is an applied force −k(L − L0)·∂L/∂q instead);
- inertial, I = Σ m J_Gᵀ a_G + J θ̈ on Th, a_G = J_G q̈ + J̇_G q̇ (the centroid offset's
  velocity terms come from J̇_G);
- kinetic energy ½Σ(m|v_G|² + J θ̇²), potential V;
- the frame's share Q_f, the part of Q_a + Q_c that loads react on the frame with: a
  moment between a body and the ground, a spring or a damper with one end on the ground
  (the frame takes the opposite of what they apply; a force at a point, gravity and a
  moment on one body come from outside, not from the frame).

The multipliers of a solution satisfy Φ_qᵀ λ = Q_a + Q_c − I (level "dynamic"; level
"static" takes q̇ = q̈ = 0). A driver row's ``factor`` is ∂Φ/∂f, f its driven quantity, so
that the driver's effort (torque or force) is λ·factor and its power input λ·Φ_t.
"""
from __future__ import annotations

from dataclasses import dataclass

import sympy as sp

from ..geometry import T
from ..stages import stage_pieces
from ..symbolic import total_derivative


@dataclass(frozen=True)
class Dynamics:
    """The force terms of a model as sympy expressions of q, q̇, q̈, T and parameters."""
    applied: sp.Matrix        # Q_a, n × 1
    conservative: sp.Matrix   # Q_c = −∂V/∂q
    inertial: sp.Matrix       # I
    kinetic: sp.Expr
    potential: sp.Expr
    potential_t: sp.Expr      # ∂V/∂T (a load or spring that changes with time)
    frame: sp.Matrix          # Q_f: the part of Q_a + Q_c of the loads anchored on the frame
    drivers: tuple            # (row of Φ, factor ∂Φ/∂f) per driver row


def dynamics(model, eq=None) -> Dynamics:
    """The Dynamics of ``model`` (its equations ``eq`` for the rows and coordinates)."""
    eq = model.equations() if eq is None else eq
    q = list(eq.q)
    n = len(q)
    index = {c: j for j, c in enumerate(q)}
    coords = set(q)
    qd, qdd = list(eq.qd), list(eq.qdd)
    applied = sp.zeros(n, 1)
    inertial = sp.zeros(n, 1)
    frame = sp.zeros(n, 1)
    kinetic = sp.Integer(0)
    potential = sp.Integer(0)
    g = model.gravity_vector

    def jac(r):
        return sp.Matrix(r).jacobian(q)

    for body in model.moving_bodies:
        m, J, c = body.mass, body.inertia, body.centroid
        th = index[body.th]
        if m != 0:
            r_g = body.to_global(c)
            v_g = total_derivative(r_g, q, 1)
            a_g = total_derivative(r_g, q, 2)
            inertial += m * jac(r_g).T * a_g
            kinetic += m * (v_g[0] ** 2 + v_g[1] ** 2) / 2
            if g is not None:
                potential -= m * (g[0] * r_g[0] + g[1] * r_g[1])
        if J != 0:
            inertial[th] += J * qdd[th]
            kinetic += J * qd[th] ** 2 / 2
    for load in model.loads:
        if load.kind == "force":
            applied += jac(load.point.r).T * load.vector
        elif load.kind == "moment":
            anchored = any(body.is_ground for body in load.bodies)
            for body, sign in zip(load.bodies, (1, -1)):
                if not body.is_ground:
                    applied[index[body.th]] += sign * load.value
                    if anchored:
                        frame[index[body.th]] += sign * load.value
        elif load.kind == "spring":
            length = _distance(load.points)
            if _anchored(load.points):
                frame -= load.k * (length - load.length) * jac([length]).T
            if (sp.sympify(load.k).free_symbols | sp.sympify(load.length).free_symbols) & coords:
                # k or the free length read the coordinates: ½k(L − L0)² is no potential
                # of the tension k(L − L0) (its gradient would add ½(L − L0)²∂k/∂q and
                # −k(L − L0)∂L0/∂q), so the tension is an applied force
                applied -= load.k * (length - load.length) * jac([length]).T
            else:
                potential += load.k * (length - load.length) ** 2 / 2
        elif load.kind == "damper":
            length = _distance(load.points)
            rate = total_derivative(length, q, 1)
            applied -= load.c * rate * jac([length]).T
            if _anchored(load.points):
                frame -= load.c * rate * jac([length]).T
    conservative = -jac([potential]).T if potential != 0 else sp.zeros(n, 1)
    return Dynamics(applied=applied, conservative=conservative, inertial=inertial,
                    kinetic=kinetic, potential=potential, potential_t=sp.diff(potential, T),
                    frame=frame, drivers=driver_factors(model, eq))


def _anchored(points) -> bool:
    """Whether a spring's or damper's points join a moving body to the frame (one of
    them fixed in the ground, the other not)."""
    return sum(bool(getattr(p.body, "is_ground", False)) for p in points) == 1


def _distance(points):
    d = points[0].r - points[1].r
    return sp.sqrt(d[0] ** 2 + d[1] ** 2)


def driver_factors(model, eq):
    """(row, ∂Φ/∂f) per row of a driver (a constraint whose rows hold T). A row
    g(q) − f(T) (rotation_lock, relative_x, relative_y, an axis angle, and relative_angle's
    atan2 row, which is θ(q) − angle near its root) gives −1: the driven quantity is g,
    its rate ν. A relative_distance row |r1 − r2|² − d(T)² drives d = |r1 − r2|:
    −2|r1 − r2| (from the constraint's own |r1 − r2|², since d(T)² may hold constants:
    d = sqrt(0.09 + 0.02 sin T) gives the row |r1 − r2|² − 0.09 − 0.02 sin T). A stage
    row (a Piecewise in T) takes each stage's factor.
    Any other row that does not separate into g(q) + h(T) gets NaN: its effort is not
    defined by this slice."""
    drivers = {c.number: c for c in model.constraints if c.is_driver}
    coords = set(eq.q)
    staged = stage_pieces(model) if getattr(model, "stages", None) else {}
    out = []
    for i, (number, k) in enumerate(eq.rows):
        con = drivers.get(number)
        if (number, k) in staged:
            if T in sp.sympify(eq.phi[i]).free_symbols:
                out.append((i, _stage_factor(staged[(number, k)], coords)))
        elif con is not None:
            out.append((i, _row_factor(con, k, sp.sympify(eq.phi[i]), coords)))
    return tuple(out)


def _row_factor(con, k, row, coords):
    """The factor of row k of driver ``con`` (its expression ``row``): a row without T
    does no driving (0: a rack_and_pinion whose c holds T drives by its rolling row, its
    offset row only holds), and a constraint with several rows in T (origin_lock along
    a path, a loop in T) has no single driven quantity: NaN (its effort is not defined;
    summing its rows' efforts would add an x force to a y force)."""
    if con.kind == "hold":                  # a build's hold row, q − value: no T
        return _factor(row, con.kind, coords)
    timed = [T in sp.sympify(e).free_symbols for e in con.exprs]
    if sum(timed) > 1:
        return sp.nan
    if not timed[k]:
        return sp.Integer(0)
    return _factor(row, con.kind, coords, getattr(con, "squared", None))


def _stage_factor(pieces, coords):
    """∂Φ/∂f of a stage row: each stage's factor from its own constraint (its kind, and a
    relative_distance's |r1 − r2|²), joined as a Piecewise in T; a row of a stage whose
    constraint does not drive (holds no T) gets NaN there."""
    factors = []
    for con, k, cond in pieces:
        row = sp.sympify(con.exprs[k])
        factor = _row_factor(con, k, row, coords) if con.is_driver else sp.nan
        factors.append((factor, cond))
    if all(f == factors[0][0] for f, _ in factors):
        return factors[0][0]
    return sp.Piecewise(*factors)


def _factor(row, kind, coords, squared=None):
    """∂Φ/∂f of one driver row (driver_factors); ``squared``: a relative_distance's
    |r1 − r2|²."""
    if kind == "hold":
        return sp.Integer(-1)               # q − value: the effort is the force along q
    if kind == "relative_angle":
        return sp.Integer(-1)               # θ(q) − angle, wrapped (constraints.RelativeAngle)
    if isinstance(row, sp.Piecewise):
        pieces = [(_factor(e, kind, coords, squared), c) for e, c in row.args]
        if all(f == pieces[0][0] for f, _ in pieces):
            return pieces[0][0]
        return sp.Piecewise(*pieces)
    timed = [a for a in sp.Add.make_args(row) if T in a.free_symbols]
    untimed = [a for a in sp.Add.make_args(row) if T not in a.free_symbols]
    if any(a.free_symbols & coords for a in timed) or not timed:
        return sp.nan
    if kind == "relative_distance":
        return -2 * sp.sqrt(sp.Add(*untimed) if squared is None else squared)
    return sp.Integer(-1)


def forces_lines(model, eq, show, rows) -> list:
    """The text of ``mechgen equations`` for the masses and loads: M (I = M q̈ + h), h, Q_a,
    Q_c and V, per coordinate (``show`` prints an expression, ``rows`` lays out labelled
    rows as the kinematic ones)."""
    dyn = dynamics(model, eq)
    q, qdd = list(eq.q), list(eq.qdd)
    n = len(q)
    mass = dyn.inertial.jacobian(qdd)
    mass = mass.applyfunc(_tidy)
    h = (dyn.inertial - mass * sp.Matrix(qdd)).applyfunc(_tidy)
    width = max(len(str(c)) for c in q) + 2

    def tag(name):
        return f"[{name}]".ljust(width)

    def vector(vec):
        return rows([((tag(q[j]), show(vec[j])), "") for j in range(n) if vec[j] != 0]) \
            or ["  (zero)"]

    lines = ["", "Forces: Phi_q^T lambda = Q_a + Q_c - (M qdd + h)       [Mech: Generalized]"]
    for b in model.moving_bodies:
        if b.mass != 0 or b.inertia != 0:
            lines.append(f"  body {b.name}: mass {show(b.mass)}, inertia {show(b.inertia)} "
                         f"about the centroid ({show(b.centroid[0])}, {show(b.centroid[1])})")
    if model.gravity_vector is not None:
        gx, gy = model.gravity_vector
        lines.append(f"  gravity: ({show(gx)}, {show(gy)})")
    for load in model.loads:
        lines.append(f"  {load.label}")
    lines += ["", "M, the mass matrix (nonzero entries)"]
    entries = [((f"[{q[i]}, {q[j]}]", show(mass[i, j])), "") for i in range(n) for j in range(n)
               if mass[i, j] != 0]
    lines += rows(entries) or ["  (zero)"]
    lines += ["", "h, the velocity terms of I = M qdd + h"] + vector(h)
    lines += ["", "Q_a, applied (forces, moments, dampers)"] + vector(dyn.applied)
    lines += ["", "Q_c = -dV/dq, conservative (gravity, springs)"] + vector(dyn.conservative)
    lines += ["", f"V = {show(dyn.potential)}"]
    return lines


def _tidy(e):
    """An entry as printed: expanded, sin² + cos² folded, and the ~1e-19 that cancelling
    floating coefficients leave shown as 0."""
    e = sp.expand(e)
    e = e.xreplace({f: 0 for f in e.atoms(sp.Float) if abs(f) < 1e-15})
    return sp.trigsimp(e) if e.has(sp.sin, sp.cos) else e
