"""`mechgen check`: Mech's CheckSystem and more (degrees of freedom, rank, structure)."""
from __future__ import annotations

import numpy as np
import sympy as sp

from ..model.geometry import T


def _assemble(eq, q0, params, t, maxit=50, tol=1e-12):
    """Gauss-Newton from the guess (least squares: works for non-square systems too).

    Returns (q, residual, iterations, converged)."""
    f = sp.lambdify((list(eq.q), list(eq.params), T), eq.phi, modules="numpy")
    J = sp.lambdify((list(eq.q), list(eq.params), T), eq.phi_q, modules="numpy")
    q = np.array(q0, dtype=float)
    m, n = eq.phi_q.shape

    def res(x):
        return np.array(f(list(x), params, t), dtype=float).reshape(m)

    r = res(q)
    for it in range(1, maxit + 1):
        if not np.all(np.isfinite(r)):
            return q, float("inf"), it, False
        A = np.array(J(list(q), params, t), dtype=float).reshape(m, n)
        dq = np.linalg.lstsq(A, -r, rcond=None)[0]
        q = q + dq
        r = res(q)
        if np.max(np.abs(dq), initial=0.0) < tol * (1 + np.max(np.abs(q))) or \
                np.max(np.abs(r), initial=0.0) < tol:
            break
    norm = float(np.max(np.abs(r), initial=0.0))
    return q, norm, it, norm < 1e-8


def check_report(model, t=0.0) -> tuple[str, bool]:
    """Mech's CheckSystem and more. Returns (text, ok).

    ok is False when equations are missing or the Jacobian is rank-deficient (a
    coordinate left free); redundant but consistent equations are reported, not failed.
    """
    from ..model.symbolic import numeric_jacobian, rank_analysis
    eq = model.equations()
    q_names = [str(c) for c in eq.q]
    n, m = len(eq.q), eq.phi.rows
    drivers = model.drivers
    driver_rows = sum(len(c.exprs) for c in drivers)
    params = list(model.param_defaults.values())
    bodies = [f"{b.name} = {b.number}" + (" (ground)" if b.is_ground else "")
              for b in model.bodies.values()]
    lines = [f"Model {model.name}" + (f"  [{model.source}]" if getattr(model, "source", None)
                                       else ""),
             f"  bodies:       {len(model.bodies)}: {', '.join(bodies)}",
             f"  coordinates:  {n}: {', '.join(q_names)}",
             f"  equations:    {m} from {len(model.constraints)} constraints",
             f"  drivers:      {len(drivers)}" +
             "".join(f"\n    {c.number} {c.label}" for c in drivers)]
    dof = n - (m - driver_rows)
    lines.append(f"  degrees of freedom: {dof} ({n} coordinates - {m - driver_rows} kinematic "
                 f"equations), {driver_rows} driven")
    ok = True
    if m < n:
        ok = False
        lines.append(f"  MISSING: {n - m} equation(s) fewer than coordinates: add "
                     f"{'a driver' if dof > driver_rows else 'constraints or drivers'}")
    elif m > n:
        lines.append(f"  over-determined: {m - n} equation(s) more than coordinates "
                     "(redundant constraints must be consistent)")
    unused = [q_names[j] for j in range(n) if all(eq.phi_q[i, j] == 0 for i in range(m))]
    if unused:
        ok = False
        lines.append(f"  coordinates in no equation: {', '.join(unused)}")

    guess = model.guess_vector()
    J0 = numeric_jacobian(eq, guess, params, t)
    rank0, rows, cols = rank_analysis(J0)
    lines.append(f"  Jacobian rank at the guess (t = {t:g}): {rank0} of {n}")
    q, residual, its, converged = _assemble(eq, guess, params, t)
    if converged:
        J = numeric_jacobian(eq, q, params, t)
        rank, rows, cols = rank_analysis(J)
        lines.append(f"  Jacobian rank assembled at t = {t:g} ({its} Gauss-Newton steps "
                     f"from the guess, residual {residual:.1e}): {rank} of {n}")
    else:
        rank = rank0
        lines.append(f"  could not assemble at t = {t:g} from the guess (residual "
                     f"{residual:.2g} after {its} steps): rank analysis at the guess")
    if rows and m > rank:
        lines.append(f"  redundant: {m - rank} dependent equation(s); the dependency involves:")
        lines += [f"    [{i + 1}] {eq.labels[i]}" for i in rows]
    if cols and rank < n:
        ok = False
        lines.append(f"  free: {n - rank} coordinate direction(s) not fixed by the equations; "
                     f"coordinates left free: {', '.join(q_names[j] for j in cols)}")

    from .blocks import sort_blocks
    values = dict(zip(eq.q, guess))
    values.update({sym: val for sym, val in model.params.values()})
    blocks = sort_blocks(eq.phi, eq.q, values)
    if blocks is None:
        lines.append("  structure: no block sorting (not square or structurally singular); "
                     "full Newton only")
    else:
        kinds = {}
        for b in blocks:
            kinds[b.kind] = kinds.get(b.kind, 0) + 1
        lines.append(f"  structure: {len(blocks)} blocks (" +
                     ", ".join(f"{v} {k}" for k, v in kinds.items()) + ")")
    lines.append("  check: " + ("True" if ok else "False"))
    return "\n".join(lines) + "\n", ok
