"""Common subexpressions of a list of statements, scheduled just before their first use.

``emit`` runs one CSE pass over all expressions of the statements and returns statements
again (the IR of mechgen.compiler.codegen.ir), with each temporary assigned just before its first
use, so that a CSE pass over a whole function stays valid when some statements define
symbols that later ones read (a block solve, say). With ``variant`` (what a loop around
the statements changes) it also hoists what does not change out of the loop.

Temporaries that stand for a bare symbol, a number or their negation (``_t0 = -X3``) are
written into their uses instead; the others are numbered in order of appearance. Both go
through printer.Alias, which keeps the printed order of every sum and product, so the code
computes bit for bit what it computed with the temporaries.
"""
from __future__ import annotations

import sympy as sp

from .ir import Assign, Guard, Store, replaced
from .printer import Alias, Local, almost_everywhere


class TempNames:
    """The temporaries of one generated function: the names CSE gives them (a counter
    shared by all the CSE passes of the function) and the names they are printed with
    (``final``: numbered in order of appearance, trivial ones left out)."""

    def __init__(self, prefix="_t"):
        self.prefix = prefix
        self.count = 0
        self.final = 0

    def __iter__(self):
        return self

    def __next__(self):
        sym = Local(f"{self.prefix}{self.count}", real=True)
        self.count += 1
        return sym

    def next_final(self):
        sym = Local(f"{self.prefix}{self.final}", real=True)
        self.final += 1
        return sym


def _expr_of(st):
    return almost_everywhere(sp.sympify(st.bound if isinstance(st, Guard) else st.expr))


def _with(st, expr):
    return replaced(st, lambda _: expr)


def emit(statements, temps: TempNames | None = None, cse: bool = True, variant=None):
    """Statements with one CSE pass over their expressions, each temporary assigned just
    before its first use. Statements other than Assign, Store and Guard pass through.

    With ``variant`` (the symbols a loop around the statements changes), returns
    ``(before, inside)``: temporaries, assignments and guards that depend on none of them
    are hoisted before the loop."""
    temps = temps or TempNames()
    exprs, slots = [], []
    for st in statements:
        if isinstance(st, (Assign, Store, Guard)):
            slots.append((st, len(exprs)))
            exprs.append(_expr_of(st))
        else:
            slots.append((st, None))
    if cse and exprs:
        reps, reduced = sp.cse(exprs, symbols=temps, order="none")
    else:
        reps, reduced = [], exprs
    rep_index = {sym: k for k, (sym, _) in enumerate(reps)}
    moving = _moving(statements, slots, reps, reduced, variant)
    emitted = set()
    lines, hoisted = [], []

    def need(expr):
        todo = set()
        stack = [s for s in sp.sympify(expr).free_symbols if s in rep_index]
        while stack:
            s = stack.pop()
            if s in todo or s in emitted:
                continue
            todo.add(s)
            stack.extend(x for x in reps[rep_index[s]][1].free_symbols if x in rep_index)
        for s in sorted(todo, key=lambda x: rep_index[x]):
            target = lines if variant is None or s in moving else hoisted
            target.append(Assign(s, reps[rep_index[s]][1]))
            emitted.add(s)

    for st, k in slots:
        if k is None:
            lines.append(st)
            continue
        expr = reduced[k]
        need(expr)
        out = lines
        if variant is not None and isinstance(st, (Assign, Guard)):
            free = expr.free_symbols | ({st.value} if isinstance(st, Guard) else set())
            if not free & moving and not (isinstance(st, Assign) and st.target in moving):
                out = hoisted
        out.append(_with(st, expr))
    hoisted, lines = _settle(hoisted + lines, set(rep_index), temps, len(hoisted))
    return lines if variant is None else (hoisted, lines)


def _moving(statements, slots, reps, reduced, variant):
    """What a loop changes: its variables, and every temporary or assignment that reads
    one of them (to a fixed point, as assignments and temporaries read each other)."""
    moving = set(variant or ())
    if variant is None:
        return moving
    seen = set()
    for st in statements:
        if isinstance(st, Assign):
            if st.target in seen:       # assigned twice: its value changes in the loop
                moving.add(st.target)
            seen.add(st.target)
    changed = True
    while changed:
        changed = False
        for sym, expr in reps:
            if sym not in moving and expr.free_symbols & moving:
                moving.add(sym)
                changed = True
        for st, k in slots:
            if k is not None and isinstance(st, Assign) and st.target not in moving \
                    and reduced[k].free_symbols & moving:
                moving.add(st.target)
                changed = True
    return moving


def _trivial(expr):
    """(sign, what) when expr is a bare symbol or number (one that prints as a single
    token: an integer or a float), or the negation of one; else None."""
    if expr.is_Symbol:
        return 1, expr
    if expr.is_Mul and len(expr.args) == 2 and expr.args[0] == -1 and expr.args[1].is_Symbol:
        return -1, expr.args[1]
    if expr.is_Integer or expr.is_Float:
        return (-1, -expr) if expr.is_negative else (1, expr)
    return None


def _settle(statements, temporaries, temps, split):
    """Trivial temporaries written into their uses, the others renumbered (see the module
    docstring); ``split`` statements go before the loop, the rest inside it."""
    subs, out, where = {}, [], []
    for i, st in enumerate(statements):
        if isinstance(st, Assign) and st.target in temporaries:
            expr = st.expr.xreplace(subs)
            small = _trivial(expr)
            if small is not None:
                sign, what = small
                subs[st.target] = sign * Alias(what, st.target.name)
                continue
            alias = Alias(temps.next_final(), st.target.name)
            subs[st.target] = alias
            out.append(Assign(alias, expr))
        elif isinstance(st, (Assign, Store, Guard)):
            out.append(_with(st, _expr_of(st).xreplace(subs)) if subs else st)
        else:
            out.append(st)
        where.append(i < split)
    before = [st for st, b in zip(out, where) if b]
    inside = [st for st, b in zip(out, where) if not b]
    return before, inside
