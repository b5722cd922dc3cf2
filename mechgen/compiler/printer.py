"""Printing sympy expressions as numba-friendly Python, and scheduling shared subexpressions.

Expressions use the model's own names (``X2``, ``Th3``, ``longitud``) as local variables;
common subexpressions become ``_t0, _t1, ...`` and are emitted just before first use, so
that a CSE pass over a whole function stays valid when some statements define symbols that
later ones read (a block solve, say).
"""
from __future__ import annotations

from dataclasses import dataclass

import sympy as sp
from sympy.printing.pycode import PythonCodePrinter


class NumbaPrinter(PythonCodePrinter):
    """Python code with ``math`` functions and floats printed to full precision."""

    def _print_Float(self, expr):
        return repr(float(expr))

    def _print_Rational(self, expr):
        return f"{float(expr.p)}/{float(expr.q)}" if expr.q != 1 else f"{expr.p}"

    def _print_Pow(self, expr, rational=False):
        base, exp = expr.as_base_exp()
        if exp == sp.Rational(1, 2):
            return f"math.sqrt({self._print(base)})"
        if exp == -1:
            return f"1.0/{self.parenthesize(base, 100)}"
        if exp.is_Integer and 2 <= exp <= 4:
            # parenthesised: a power binds tighter than the product it becomes, and sympy's
            # Mul printer puts it after "/" without parentheses of its own
            b = self.parenthesize(base, 100)
            return "(" + "*".join([b] * int(exp)) + ")"
        if exp.is_Integer and -4 <= exp <= -2:
            b = self.parenthesize(base, 100)
            return "1.0/(" + "*".join([b] * int(-exp)) + ")"
        return super()._print_Pow(expr, rational=rational)


_PRINTER = NumbaPrinter({"fully_qualified_modules": True, "standard": "python3"})


def pycode(expr) -> str:
    return _PRINTER.doprint(sp.sympify(expr))


@dataclass
class Assign:
    """``target = expr`` (target a Symbol; its name becomes the local variable)."""
    target: sp.Symbol
    expr: object
    comment: str = ""


@dataclass
class Store:
    """``out[index] = expr``: writes into an output array."""
    lhs: str
    expr: object
    comment: str = ""


@dataclass
class Guard:
    """``if not (abs(value) > bound): return status`` — a pivot check before a division.

    ``value`` must be a Symbol assigned earlier; ``bound`` an expression."""
    value: sp.Symbol
    bound: object
    status: str


@dataclass
class Line:
    """A literal line (a comment or control flow)."""
    text: str


class TempNames:
    """A shared counter so temporaries are unique within a generated function."""

    def __init__(self, prefix="_t"):
        self.prefix = prefix
        self.count = 0

    def __iter__(self):
        return self

    def __next__(self):
        sym = sp.Symbol(f"{self.prefix}{self.count}", real=True)
        self.count += 1
        return sym


def emit(statements, temps: TempNames | None = None, cse: bool = True, variant=None):
    """Lines of code for statements, with one CSE pass over all their expressions and each
    temporary emitted just before its first use.

    With ``variant`` (the symbols a loop around the statements changes), returns
    ``(before, inside)``: temporaries that depend on none of them are hoisted before the loop."""
    temps = temps or TempNames()
    exprs = []
    slots = []
    for st in statements:
        if isinstance(st, (Assign, Store)):
            slots.append((st, len(exprs)))
            exprs.append(sp.sympify(st.expr))
        elif isinstance(st, Guard):
            slots.append((st, len(exprs)))
            exprs.append(sp.sympify(st.bound))
        else:
            slots.append((st, None))
    if cse and exprs:
        reps, reduced = sp.cse(exprs, symbols=temps, order="none")
    else:
        reps, reduced = [], exprs
    rep_index = {sym: k for k, (sym, _) in enumerate(reps)}
    emitted = set()
    lines = []
    hoisted = []
    # what the loop changes: its variables, and every temporary or assignment that reads
    # one of them (to a fixed point, as assignments and temporaries read each other);
    # assignments and guards that read none of them are hoisted with their temporaries
    moving = set(variant or ())
    if variant is not None:
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
                if isinstance(st, Assign) and st.target not in moving \
                        and reduced[k].free_symbols & moving:
                    moving.add(st.target)
                    changed = True

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
            target.append(f"{s.name} = {pycode(reps[rep_index[s]][1])}")
            emitted.add(s)

    for st, k in slots:
        if isinstance(st, Line):
            lines.append(st.text)
            continue
        expr = reduced[k]
        need(expr)
        out = lines
        if variant is not None and isinstance(st, (Assign, Guard)):
            free = expr.free_symbols | ({st.value} if isinstance(st, Guard) else set())
            if not free & moving and not (isinstance(st, Assign) and st.target in moving):
                out = hoisted
        if isinstance(st, Assign):
            tail = f"  # {st.comment}" if st.comment else ""
            out.append(f"{st.target.name} = {pycode(expr)}{tail}")
        elif isinstance(st, Store):
            tail = f"  # {st.comment}" if st.comment else ""
            out.append(f"{st.lhs} = {pycode(expr)}{tail}")
        else:
            out.append(f"if not abs({st.value.name}) > {pycode(expr)}:")
            out.append(f"    return {st.status}")
    return lines if variant is None else (hoisted, lines)
