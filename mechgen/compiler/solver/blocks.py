"""Structure of Φ: block-lower-triangular sorting (matching + Tarjan) and tearing.

Given Φ(q) square with a perfect matching of equations to unknowns, the equations fall
into blocks solved one after the other, as Modelica compilers do. Inside a block of more
than one unknown, tearing picks a few unknowns for Newton ("tears") so that the others
follow explicitly from equations linear in them.
"""
from __future__ import annotations

import sys
from dataclasses import dataclass, field

import sympy as sp

# How a block is solved (decided by mechgen.compiler.solver.plan): its unknown follows from its row
# explicitly; in closed form (one tear, a sin y + b cos y + c = 0 or A y² + B y + C = 0);
# or by Newton on its tears; an RRR dyad (two angles, see mechgen.compiler.solver.dyads) by the
# intersection of two circles, its assembly mode a sign.
EXPLICIT = "explicit"
CLOSED_FORM_TRIG = "closed_form_trig"
CLOSED_FORM_QUADRATIC = "closed_form_quadratic"
NEWTON = "newton"
DYAD_RRR = "dyad_rrr"   # two angles of bodies joined to each other and to known points
METHODS = (EXPLICIT, CLOSED_FORM_TRIG, CLOSED_FORM_QUADRATIC, NEWTON, DYAD_RRR)


@dataclass
class Block:
    eqs: list            # equation (row) indices
    vars: list           # coordinate (column) indices, vars[i] matched to eqs[i]
    kind: str = ""       # "explicit", "newton" (1 unknown), "torn", "newton_k"
    tears: list = field(default_factory=list)      # var indices iterated by Newton
    explicit: list = field(default_factory=list)   # [(eq, var)] in evaluation order
    residuals: list = field(default_factory=list)  # eq indices left as residuals

    @property
    def size(self):
        return len(self.vars)


def incidence(phi: sp.Matrix, q: sp.Matrix):
    """For each row, the sorted column indices of the coordinates it holds."""
    index = {s: j for j, s in enumerate(q)}
    return [sorted(index[s] for s in phi[i].free_symbols if s in index) for i in range(phi.rows)]


def match(inc, n):
    """A maximum matching rows -> columns by augmenting paths (Kuhn's algorithm).

    Returns (row_of_col, col_of_row) with -1 where unmatched."""
    row_of_col = [-1] * n
    col_of_row = [-1] * len(inc)

    def augment(i, seen):
        for c in inc[i]:
            if c in seen:
                continue
            seen.add(c)
            if row_of_col[c] == -1 or augment(row_of_col[c], seen):
                row_of_col[c], col_of_row[i] = i, c
                return True
        return False

    limit = sys.getrecursionlimit()
    sys.setrecursionlimit(max(limit, 4 * len(inc) + 100))
    try:
        for i, cols in enumerate(inc):       # cheap greedy pass first
            for c in cols:
                if row_of_col[c] == -1:
                    row_of_col[c], col_of_row[i] = i, c
                    break
        for i in range(len(inc)):
            if col_of_row[i] == -1:
                augment(i, set())
    finally:
        sys.setrecursionlimit(limit)
    return row_of_col, col_of_row


def tarjan(graph):
    """Strongly connected components, each emitted after the ones it reaches (iterative)."""
    index, low, on, stack, out = {}, {}, set(), [], []
    counter = 0
    for root in range(len(graph)):
        if root in index:
            continue
        work = [(root, 0)]
        while work:
            v, pos = work.pop()
            if pos == 0:
                index[v] = low[v] = counter
                counter += 1
                stack.append(v)
                on.add(v)
            succ = graph[v]
            if pos < len(succ):
                work.append((v, pos + 1))
                w = succ[pos]
                if w not in index:
                    work.append((w, 0))
                elif w in on:
                    low[v] = min(low[v], index[w])
                continue
            if low[v] == index[v]:
                comp = []
                while True:
                    w = stack.pop()
                    on.discard(w)
                    comp.append(w)
                    if w == v:
                        break
                out.append(sorted(comp))
            if work:
                parent = work[-1][0]
                low[parent] = min(low[parent], low[v])
    return out


def sort_blocks(phi: sp.Matrix, q: sp.Matrix, at: dict | None = None):
    """Blocks in solving order, or None when Φ is not square or structurally singular.

    ``at`` maps symbols to numbers (the guess, parameter defaults) and steers tearing
    away from coefficients that vanish there.
    """
    m, n = phi.rows, len(q)
    if m != n:
        return None
    inc = incidence(phi, q)
    row_of_col, col_of_row = match(inc, n)
    if any(c == -1 for c in col_of_row):
        return None
    # eq i depends on eq row_of_col[c] for every other column c it holds
    graph = [[row_of_col[c] for c in inc[i] if c != col_of_row[i]] for i in range(m)]
    blocks = []
    for comp in tarjan(graph):
        eqs = comp
        vars_ = [col_of_row[i] for i in eqs]
        blocks.append(classify(Block(eqs=eqs, vars=vars_), phi, q, inc, at or {}))
    return blocks


def linear_in(expr, var):
    """(coefficient, rest) when expr = coefficient·var + rest with both free of var."""
    if var not in expr.free_symbols:
        return None
    if any(getattr(f, "wraps", False) and var in f.free_symbols
           for f in expr.atoms(sp.Function)):
        return None     # a wrapped angle (a gear's mesh_angle): a constant slope, a sawtooth
    coef = sp.diff(expr, var)
    if var in coef.free_symbols:
        return None
    rest = expr.subs(var, 0)
    if coef == 0 or coef.has(sp.Piecewise):
        return None     # a coefficient that changes with the stage may vanish: Newton
    return coef, rest


def _magnitude(expr, at):
    try:
        val = complex(expr.subs(at).evalf())
        return abs(val)
    except (TypeError, ValueError):
        return 0.0


def classify(block: Block, phi, q, inc, at) -> Block:
    if block.size == 1:
        e, v = block.eqs[0], block.vars[0]
        lin = linear_in(phi[e], q[v])
        block.kind = "explicit" if lin is not None else "newton"
        if lin is not None:
            block.explicit = [(e, v)]
        else:
            block.tears, block.residuals = [v], [e]
        return block
    best = None
    for first in block.vars:
        plan = _tear(block, phi, q, inc, at, first)
        if plan is None:
            continue
        tears, explicit, residuals, worst = plan
        score = (len(tears), -worst)
        if best is None or score < best[0]:
            best = (score, tears, explicit, residuals)
    if best is None or len(best[1]) == block.size:
        block.kind = "newton_k"
        block.tears, block.residuals = list(block.vars), list(block.eqs)
        return block
    _, block.tears, block.explicit, block.residuals = best
    block.kind = "torn"
    return block


def _tear(block, phi, q, inc, at, first):
    """Greedy tearing starting with ``first`` as a tear variable."""
    unknown = set(block.vars)
    eqs = list(block.eqs)
    tears, explicit = [first], []
    unknown.discard(first)
    worst = float("inf")
    while unknown:
        progress = False
        for e in eqs:
            if any(e == x for x, _ in explicit):
                continue
            left = [c for c in inc[e] if c in unknown]
            if len(left) != 1:
                continue
            lin = linear_in(phi[e], q[left[0]])
            if lin is None:
                continue
            mag = _magnitude(lin[0], at)
            if mag < 1e-9:
                continue
            worst = min(worst, mag)
            explicit.append((e, left[0]))
            unknown.discard(left[0])
            progress = True
            break
        if not progress:
            # tear the unknown that appears in most remaining equations
            used = {x for x, _ in explicit}
            counts = {v: sum(1 for e in eqs if e not in used and v in inc[e]) for v in unknown}
            v = max(sorted(unknown), key=lambda c: counts[c])
            tears.append(v)
            unknown.discard(v)
    used = {x for x, _ in explicit}
    residuals = [e for e in eqs if e not in used]
    if len(residuals) != len(tears):
        return None
    return tears, explicit, residuals, worst
