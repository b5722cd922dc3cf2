"""Human-readable reports: the equations (as Mech prints them) and the system check."""
from __future__ import annotations

import numpy as np
import sympy as sp

from .geometry import T


def _numeric(expr, model, numeric):
    if not numeric:
        return expr
    subs = {sym: sp.Float(val, 6) if val != int(val) else sp.Integer(int(val))
            for sym, val in model.params.values()}
    return expr.subs(subs)


def equations_text(model, numeric=False, latex=False) -> str:
    """Φ, Φ_q, ν = −Φ_t and γ, each row labelled with its constraint."""
    eq = model.equations()
    fmt = sp.latex if latex else sp.sstr
    lines = []
    head = (lambda s: f"% {s}") if latex else (lambda s: s)

    def show(e):
        return fmt(_numeric(e, model, numeric))

    lines.append(head(f"Model {model.name}: {eq.phi.rows} equations, {len(eq.q)} coordinates"))
    lines.append(head("q = [" + ", ".join(map(str, eq.q)) + "]"))
    if model.params:
        lines.append(head("parameters: " + ", ".join(f"{n} = {v:g}" for n, v in model.param_defaults.items())))
    lines.append("")
    sections = [("Phi (constraints, = 0)", eq.phi), ("nu = -Phi_t (velocity right side)", eq.nu),
                ("gamma (acceleration right side, Phi_q qdd = gamma)", eq.gamma)]
    width = len(str(eq.phi.rows))
    for title, vec in sections[:1]:
        lines.append(head(title))
        for i in range(vec.rows):
            lines.append(_row(i, width, eq.labels[i], show(vec[i]) + (" = 0" if not latex else " = 0"), latex))
        lines.append("")
    lines.append(head("Phi_q (Jacobian, nonzero entries)"))
    for i in range(eq.phi_q.rows):
        for j in range(eq.phi_q.cols):
            if eq.phi_q[i, j] != 0:
                lines.append(_row(i, width, f"d/d{eq.q[j]}", show(eq.phi_q[i, j]), latex))
    lines.append("")
    for title, vec in sections[1:]:
        lines.append(head(title))
        for i in range(vec.rows):
            lines.append(_row(i, width, eq.labels[i], show(vec[i]), latex))
        lines.append("")
    return "\n".join(lines).rstrip() + "\n"


def _row(i, width, label, text, latex):
    if latex:
        return f"{text} \\qquad \\text{{({i + 1}) {label}}} \\\\"
    return f"  [{i + 1:>{width}}] {text}    # {label}"


def check_report(model, t=0.0) -> tuple[str, bool]:
    """Mech's CheckSystem and more. Returns (text, ok)."""
    eq = model.equations()
    n, m = len(eq.q), eq.phi.rows
    drivers = model.drivers
    lines = [f"Model {model.name}", f"  bodies: {len(model.bodies)} "
             f"({', '.join(model.bodies)})",
             f"  coordinates: {n} ({', '.join(map(str, eq.q))})",
             f"  equations: {m} from {len(model.constraints)} constraints",
             f"  drivers: {len(drivers)}" + (f" ({', '.join(c.label for c in drivers)})" if drivers else "")]
    ok = True
    dof_free = n - (m - len(drivers))
    lines.append(f"  degrees of freedom (coordinates minus non-driving equations): {dof_free}")
    if m < n:
        ok = False
        lines.append(f"  NOT SQUARE: {n - m} equation(s) missing: add constraints or drivers")
    elif m > n:
        lines.append(f"  over-determined: {m - n} more equation(s) than coordinates "
                     "(redundant constraints must be consistent)")
    # numeric rank at the guess
    values = {s: v for s, v in zip(eq.q, model.guess_vector())}
    values.update({sym: val for sym, val in model.params.values()})
    values[T] = t
    J = np.array(eq.phi_q.subs(values).evalf(), dtype=float)
    u, s, vt = np.linalg.svd(J)
    tol = 1e-9 * (s[0] if s.size else 1.0)
    rank = int(np.sum(s > tol))
    lines.append(f"  Jacobian rank at the guess (t = {t:g}): {rank} of {n}")
    if rank < min(m, n) or m > rank:
        left = u[:, rank:]
        if left.shape[1]:
            w = np.max(np.abs(left), axis=1)
            rows = [i for i in range(m) if w[i] > 0.1 * w.max()]
            lines.append("  dependent (redundant) equations among: ")
            lines += [f"    [{i + 1}] {eq.labels[i]}" for i in rows]
        right = vt[rank:, :]
        if right.shape[0]:
            w = np.max(np.abs(right), axis=0)
            cols = [str(eq.q[j]) for j in range(n) if w[j] > 0.1 * w.max()]
            lines.append(f"  coordinates left free (not fixed by the equations): {', '.join(cols)}")
        if rank < n:
            ok = False
    from .blocks import sort_blocks
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
