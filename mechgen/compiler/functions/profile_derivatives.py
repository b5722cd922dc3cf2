"""The derivatives of a cam profile's coordinate as straight-line code, differentiated
operation by operation (forward mode) instead of as one expression.

A profile coordinate (a roller's offset curve, a motion law) differentiated three times
by sympy is a tree of tens of thousands of operations, and the CSE pass that turns it back
into code took most of a cam's build. Here the coordinate is taken apart once into single
operations t = f(u, v), each distinct one once; each t that depends on s gets a derivative
t' = Σ ∂f/∂u · u' (by the rules of the chain rule for +, ×, powers, sin, cos, ..., sympy's
``diff`` for other functions), itself taken apart the same way, and t'' comes from t': the
code of the k-th derivative grows linearly with k and with the coordinate's own code. A
Piecewise (a profile folds its pieces to the top) is differentiated branch by branch, its
conditions left as they are (as mechgen.model.library2d.profiles.derivative does). Temporaries read
once, constants and negated symbols are written into their uses, so that a line is an
expression again. The function is
the derivative sympy builds; its rounding differs in the last bits
(tests/test_cam_numeric.py compares them).
"""
from __future__ import annotations

import sympy as sp

from ..codegen.ir import Assign, Store
from ..codegen.printer import Local


class _Program:
    """Single operations in order (symbol -> expression over atoms) and their
    derivatives in ``var``; each distinct operation is held once."""

    def __init__(self, var):
        self.var = var
        self.exprs = {}
        self.order = []
        self.held = {}          # operation -> its symbol
        self.deriv = {}

    def take_apart(self, e):
        """An atom for ``e``: a number, a symbol, or the temporary of its last operation."""
        if e.is_Atom:
            return e
        sym = self.held.get(e)
        if sym is not None:
            return sym
        if isinstance(e, sp.Piecewise):
            op = sp.Piecewise(*[(self.take_apart(x), self._condition(c)) for x, c in e.args],
                              evaluate=False)
        else:
            op = e.func(*[self.take_apart(a) for a in e.args])
            if op.is_Atom:
                return op
        sym = self.held.get(op)
        if sym is None:
            sym = Local(f"_o{len(self.order)}", real=True)
            self.exprs[sym] = op
            self.order.append(sym)
            self.held[op] = sym
        self.held[e] = sym
        return sym

    def _condition(self, c):
        if c.is_Atom or c in (sp.true, sp.false):
            return c
        if isinstance(c, sp.core.relational.Relational):
            return c.func(self.take_apart(c.lhs), self.take_apart(c.rhs))
        return c.func(*[self._condition(a) for a in c.args])

    def d(self, sym):
        """The atom holding d sym / d var."""
        if sym == self.var:
            return sp.S.One
        if sym not in self.exprs:
            return sp.S.Zero            # a parameter or a number
        out = self.deriv.get(sym)
        if out is None:
            out = self.deriv[sym] = self.take_apart(self._rule(self.exprs[sym]))
        return out

    def _rule(self, op):
        """d op / d var of one operation, in the atoms and their derivatives."""
        if isinstance(op, sp.Piecewise):
            return sp.Piecewise(*[(self.d(x), c) for x, c in op.args], evaluate=False)
        args = op.args
        ds = [self.d(a) if not a.is_Number else sp.S.Zero for a in args]
        if all(d == 0 for d in ds):
            return sp.S.Zero
        if op.is_Add:
            return sp.Add(*ds)
        if op.is_Mul:
            return sp.Add(*[sp.Mul(*(args[:i] + (di,) + args[i + 1:]))
                            for i, di in enumerate(ds) if di != 0])
        if op.is_Pow and op.exp.is_Number:
            return op.exp * op.base ** (op.exp - 1) * ds[0]
        if isinstance(op, sp.sin):
            return sp.cos(args[0]) * ds[0]
        if isinstance(op, sp.cos):
            return -sp.sin(args[0]) * ds[0]
        terms = []
        for i, da in enumerate(ds):     # the chain rule through sympy's own derivative
            if da != 0:
                u = sp.Dummy()
                partial = sp.diff(op.func(*(args[:i] + (u,) + args[i + 1:])), u)
                terms.append(partial.xreplace({u: args[i]}) * da)
        return sp.Add(*terms)


class Derivatives:
    """The derivatives of one expression in ``var``, all orders from one program (the
    operations of d²/ds² are those of d/ds and more)."""

    def __init__(self, expr, var):
        self.prog = _Program(var)
        self.outs = [self.prog.take_apart(expr)]

    def statements(self, order):
        """Statements (Assign ..., Store("_v", ...)) computing d^order expr / d var^order;
        the temporaries are named _u0, _u1, ... in order."""
        while len(self.outs) <= order:
            self.outs.append(self.prog.d(self.outs[-1]))
        return _statements(self.prog, self.outs[order])


def _statements(prog, out):
    """The statements of the operations ``out`` needs, in order."""
    # the operations the result needs, and how often each is read
    reads, stack, need = {}, [out], set()
    while stack:
        s = stack.pop()
        if s not in prog.exprs or s in need:
            continue
        need.add(s)
        for a in _atoms(prog.exprs[s]):
            if a in prog.exprs:
                reads[a] = reads.get(a, 0) + 1
                stack.append(a)
    reads[out] = reads.get(out, 0) + 1
    # write the temporaries read once into their use (not into a condition, so that a
    # Piecewise keeps computing its conditions from named values)
    tested = set()
    for s in need:
        if isinstance(prog.exprs[s], sp.Piecewise):
            for _, c in prog.exprs[s].args:
                tested |= c.free_symbols
    inline = {s for s in need if reads.get(s, 0) == 1 and s not in tested}
    value, body = {}, []
    for sym in prog.order:
        if sym not in need:
            continue
        e = prog.exprs[sym].xreplace(value)       # its operands: names or expressions
        if sym in inline or _trivial(e):
            value[sym] = e
        else:
            value[sym] = Local(f"_u{len(body)}", real=True)
            body.append(Assign(value[sym], e))
    body.append(Store("_v", value.get(out, out)))
    return body


def _trivial(e):
    """A constant (1/π, 2π/3) or the negation of a symbol: written into its uses."""
    if not e.free_symbols:
        return not isinstance(e, sp.Piecewise)
    return e.is_Mul and len(e.args) == 2 and e.args[0] == -1 and e.args[1].is_Symbol


def _atoms(e):
    return e.free_symbols


__all__ = ["Derivatives"]
