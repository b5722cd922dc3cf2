"""The solver plan: everything decided about a module before its code is written, as frozen
data computed once.

- the blocks of Φ in solving order (block-lower-triangular sorting and tearing, see
  mechgen.compiler.solver.blocks), pruned to what the requested outputs need, the blocks that
  stay the same at every point of a sweep first (``steady``);
- per block, how it is solved: ``explicit``, in closed form (``closed_form_trig``:
  a sin y + b cos y + c = 0; ``closed_form_quadratic``: A y² + B y + C = 0) or ``newton``;
- the solved mask, the derivative level, the coordinates that come out constant;
- whether function calls (sin, cos, ...) of solved coordinates are shared across blocks,
  the names they are shared under, and how large functions are split into parts.
"""
from __future__ import annotations

from dataclasses import dataclass, replace

import sympy as sp

from ...errors import ModelError
from ...model.geometry import T
from ...protocol import LEVEL, LEVELS
from .blocks import (CLOSED_FORM_QUADRATIC, CLOSED_FORM_TRIG, DYAD_RRR, EXPLICIT, METHODS,
                     NEWTON, incidence, linear_in, sort_blocks)
from .dyads import rrr_form, sign_at, signed
from .position import Rows, position_code

CHUNK_STORES = 48      # straight-line functions longer than this are split into parts
CHUNK_LINES = 160      # lines of the position solver per part, for large models
SHARE_MAX = 40         # models up to this many coordinates share function calls across blocks


@dataclass(frozen=True)
class BlockPlan:
    """One block: its rows and unknowns (``vars[i]`` matched to ``rows[i]``), the unknowns
    Newton iterates on (``tears``), the ones that follow explicitly (``explicit``, pairs
    (row, unknown) in evaluation order), the rows left as residuals, and the method.
    ``form`` holds the coefficients of a closed form: (a, b, c) or (A, B, C), or an RRR
    dyad's (cx, cy, u1x, u1y, u2x, u2y) (mechgen.compiler.solver.dyads); ``sign``: a dyad's
    assembly sign at the model's guess (its block determinant's), ``where``: its joint."""
    kind: str
    vars: tuple
    rows: tuple
    tears: tuple = ()
    explicit: tuple = ()
    residuals: tuple = ()
    method: str = NEWTON
    form: tuple = ()
    sign: int = 0
    where: str = ""

    @property
    def size(self):
        return len(self.vars)

    def __post_init__(self):
        if self.method not in METHODS:
            raise ValueError(f"unknown method {self.method!r}")
        if self.method in (CLOSED_FORM_TRIG, CLOSED_FORM_QUADRATIC) and \
                (len(self.tears) != 1 or len(self.form) != 3):
            raise ValueError("a closed form solves one tear from three coefficients")
        if self.method == DYAD_RRR and (len(self.tears) != 2 or len(self.form) != 6):
            raise ValueError("an RRR dyad solves two angles from six coefficients")


@dataclass(frozen=True)
class SolverPlan:
    """The solver plan of one module (see the module docstring)."""
    sorted: bool
    blocks: tuple                 # BlockPlan, solving order, after pruning
    solved: tuple                 # per coordinate: computed by the sorted solver
    level: int                    # 0 position, 1 velocity, 2 acceleration
    outputs: tuple                # output names built
    cse: bool
    closed_forms: str             # "all", "cheap" or "none"
    known: tuple = ()             # (coordinate, value): coordinates that come out constant
    share: bool = False           # calls of solved coordinates shared across blocks
    position: object = None       # the position solver's code per block (PositionCode)
    position_parts: tuple = ()    # block indices per part; () when it is one function
    chunk_stores: int = CHUNK_STORES
    chunk_lines: int = CHUNK_LINES
    steady: int = 0               # the leading blocks that stay the same along a sweep

    @property
    def known_values(self):
        return dict(self.known)


def make_plan(model, eq, sort=True, level="acceleration", outputs=None, cse=True,
              closed_forms="cheap") -> SolverPlan:
    """The plan of ``model`` (its expanded equations ``eq``) for the given build options."""
    # "all" and "cheap" (the default): every block of a standard form is solved in closed
    # form (since the forms whose root a sign picks cost a sweep no call, "cheap" leaves
    # none out any more); "none": Newton everywhere
    if closed_forms is True:
        closed_forms = "all"
    if closed_forms not in ("all", "cheap", "none", False):
        raise ValueError(f"closed_forms must be all, cheap or none, got {closed_forms!r}")
    closed_forms = closed_forms or "none"
    lvl = LEVEL[level]
    q = list(eq.q)
    at = {s: v for s, v in zip(q, model.guess_vector())}
    at.update({sym: val for sym, val in model.params.values()})
    blocks = sort_blocks(eq.phi, eq.q, at) if sort else None
    solved = [True] * len(q)
    names = list(model.outputs) if outputs is None else list(outputs)
    outs, need = _demand(model, eq, names, lvl, outputs is not None)
    if blocks is not None and outputs is not None:
        blocks = _prune(eq, blocks, need)
        kept = {v for b in blocks for v in b.vars}
        solved = [j in kept for j in range(len(q))]
    steady = 0
    if blocks is not None:
        blocks, steady = _steady_first(eq, blocks)
    plan = SolverPlan(sorted=blocks is not None, blocks=(), solved=tuple(solved), level=lvl,
                outputs=tuple(outs), cse=cse, closed_forms=closed_forms,
                chunk_stores=CHUNK_STORES, chunk_lines=CHUNK_LINES, steady=steady)
    if blocks is None:
        return plan
    planned, known, rows = [], {}, Rows(eq)
    for b in blocks:
        planned.append(_block_plan(b, eq, rows.at(known), closed_forms, at))
        if b.kind == "explicit":
            value = _explicit_value(eq, rows.at(known), *b.explicit[0])
            if value is not None:     # a constant coordinate: substitute it forward
                known[q[b.vars[0]]] = value
    plan = replace(plan, blocks=tuple(planned), known=tuple(known.items()))
    return _lay_out_position(plan, eq, len(q) <= SHARE_MAX, rows)


def _lay_out_position(plan, eq, share, rows):
    """The position solver's code with calls shared across blocks where the model is small
    enough and the solver stays one function; else unshared, split into parts of about
    CHUNK_LINES lines (numba compiles many small functions much faster than one large)."""
    code = position_code(plan, eq, share, rows)
    if share and code.lines > 2 * plan.chunk_lines:
        code = position_code(plan, eq, False, rows)
        share = False
    parts = ()
    if code.lines > 2 * plan.chunk_lines:
        groups, current, size = [], [], 0
        for k, piece in enumerate(code.pieces):
            if current and size + piece.lines > plan.chunk_lines:
                groups.append(tuple(current))
                current, size = [], 0
            current.append(k)
            size += piece.lines
        groups.append(tuple(current))
        parts = tuple(groups)
    return replace(plan, share=share, position=code, position_parts=parts)


def _demand(model, eq, names, level, pruning):
    """The outputs to build and the coordinates they need (demand-driven pruning: only the
    blocks the requested coordinates and outputs depend on, and through ``level`` only the
    derivative levels asked for)."""
    index = {}
    for vector in (eq.q, eq.qd, eq.qdd):
        index.update({c.name: j for j, c in enumerate(vector)})
    if not pruning:
        return names, set()
    need, outs = set(), []
    for name in names:
        if name in model.outputs:
            outs.append(name)
            syms = model.outputs[name].free_symbols
            if (syms & set(eq.qdd) and level < 2) or (syms & set(eq.qd) and level < 1):
                raise ModelError(f"output '{name}' needs a higher derivative level than "
                                 f"--level {LEVELS[level]}")
            need |= {index[s.name] for s in syms if s.name in index}
        elif name in index:
            need.add(index[name])
        else:
            known = ", ".join(list(model.outputs) + [c.name for c in eq.q])
            raise ModelError(f"--outputs: {name!r} is neither an output nor a coordinate of "
                             f"model '{model.name}' (known: {known})")
    return outs, need


def _prune(eq, blocks, need):
    inc = incidence(eq.phi, eq.q)
    block_of = {v: k for k, b in enumerate(blocks) for v in b.vars}
    keep, stack = set(), [block_of[j] for j in need]
    while stack:
        k = stack.pop()
        if k in keep:
            continue
        keep.add(k)
        for e in blocks[k].eqs:
            stack.extend(block_of[v] for v in inc[e] if block_of[v] not in keep)
    return [b for k, b in enumerate(blocks) if k in keep]


def _steady_first(eq, blocks):
    """(blocks, count): ``blocks`` with those that stay the same at every point of a sweep
    first, ``count`` of them. Such a block's rows hold neither the time nor any coordinate
    but its own and those of earlier such blocks (a slider's angle fixed by its guide, a
    point placed by parameters alone): it reads nothing solved after it, so the order
    stays a solving order, and the fast sweep solves it once, before its loop (sweep.py).
    The other blocks keep their order."""
    q, known = list(eq.q), set(eq.params)
    steady, rest = [], []
    for b in blocks:
        own = {q[v] for v in b.vars}
        syms = set().union(*(eq.phi[e].free_symbols for e in b.eqs))
        if T not in syms and syms <= known | own:
            steady.append(b)
            known |= own
        else:
            rest.append(b)
    return steady + rest, len(steady)


def _explicit_value(eq, rows, e, v):
    """The value of an explicit unknown when it is a constant (else None); ``rows``: Φ
    with the constants found so far."""
    coef, rest = linear_in(rows[e], eq.q[v])
    value = -rest / coef if coef.is_number else (sp.Integer(0) if rest == 0 else None)
    return value if value is not None and value.is_number else None


def _block_plan(b, eq, rows, closed_forms, at):
    plan = BlockPlan(kind=b.kind, vars=tuple(b.vars), rows=tuple(b.eqs), tears=tuple(b.tears),
                     explicit=tuple(tuple(x) for x in b.explicit),
                     residuals=tuple(b.residuals),
                     method=EXPLICIT if b.kind == "explicit" else NEWTON)
    if closed_forms != "none" and len(b.tears) == 2:
        form = rrr_form(plan, eq, rows)
        if form is not None:
            where = eq.labels[plan.residuals[0]].split(" ", 1)[-1].rsplit(" ", 1)[0]
            return replace(plan, method=DYAD_RRR, form=form, where=where,
                           sign=sign_at(form, plan, eq, at))
    if b.kind == "explicit" or len(b.tears) != 1 or closed_forms == "none":
        return plan
    found = _closed_form(b, eq, rows, closed_forms)
    return plan if found is None else replace(plan, method=found[0], form=found[1])


def _closed_form(b, eq, phi, closed_forms):
    """A block with one tear whose residual, once the explicit unknowns are substituted,
    has a standard form solved without iterating: a sin y + b cos y + c (a crank or lever
    angle) or A y² + B y + C (a two-circle intersection). (method, coefficients), or None
    when the residual has neither form. A form whose root is picked by a sign
    (mechgen.compiler.solver.dyads.signed) costs no more than a warm Newton: the sweep keeps the
    sign and takes y from the last point without calls."""
    q = eq.q
    y = q[b.tears[0]]
    subs = {}
    for e, v in b.explicit:
        coef, rest = linear_in(phi[e], q[v])
        subs[q[v]] = (-rest / coef).subs(subs)
    r = phi[b.residuals[0]].subs(subs)
    try:
        # clear denominators free of y: the same roots, fewer divisions at run time
        num, den = sp.fraction(sp.together(r))
        if not den.free_symbols & {y}:
            r = num
        ex = sp.expand(r)
    except Exception:  # noqa: BLE001 - an expression sympy cannot expand: keep Newton
        return None
    trig = _collect_form(ex, [sp.sin(y), sp.cos(y)])
    quad = None if trig else _collect_form(ex, [y ** 2, y])
    if trig and (sp.sin(y) in trig or sp.cos(y) in trig):
        ka, kb, kc = (sp.sympify(trig.get(sp.sin(y), 0)), sp.sympify(trig.get(sp.cos(y), 0)),
                      sp.sympify(trig.get(1, 0)))
        if ka.is_number and kb.is_number and sp.sqrt(ka ** 2 + kb ** 2) == 0:
            return None
        return CLOSED_FORM_TRIG, (ka, kb, kc)
    if quad and y ** 2 in quad:
        return CLOSED_FORM_QUADRATIC, (quad[y ** 2], quad.get(y, 0), quad.get(1, 0))
    return None


def _collect_form(expr, terms):
    """{term: coefficient} (and {1: the rest}) when expr is linear in the given terms with
    coefficients free of their variable, else None."""
    variable = set().union(*(t.free_symbols for t in terms))
    parts = sp.collect(expr, terms, evaluate=False)
    if not set(parts) <= set(terms) | {sp.Integer(1)}:
        return None
    if any(c.free_symbols & variable for c in parts.values()):
        return None
    return parts


def summary(block: BlockPlan, q) -> str:
    """How a block is solved, in words (the module docstring's solving order)."""
    names = [str(q[v]) for v in block.tears]
    rest = [str(q[v]) for _, v in block.explicit]
    tail = f"; {', '.join(rest)} explicit" if rest else ""
    if block.method == EXPLICIT:
        return "explicit"
    if block.method == DYAD_RRR:
        return f"RRR dyad at {block.where}, sign {block.sign:+d}"
    sign = ", the guess's sign" if signed(block.method, block.form) else ""
    if block.method == CLOSED_FORM_TRIG:
        y = names[0]
        return f"closed form: a sin({y}) + b cos({y}) + c = 0{sign}{tail}"
    if block.method == CLOSED_FORM_QUADRATIC:
        y = names[0]
        return f"closed form: A {y}^2 + B {y} + C = 0{sign}{tail}"
    if block.size == 1:
        return "Newton"
    return f"Newton on {', '.join(names)}{tail}"
