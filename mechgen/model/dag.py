"""Sympy on expression graphs: ``diff`` and ``xreplace`` once per distinct subexpression.

A cam profile's coordinate (a roller's offset curve, a motion law folded into a
Piecewise) differentiated three times is a large tree whose subtrees repeat many times;
``sp.diff`` differentiates every occurrence again, and each of its calls walks the whole
result once more (``Derivative.__new__`` canonicalises it), so the third derivative of a
profile took seconds. ``Differentiator`` applies the very rules that ``diff`` applies
(``Add``, ``Mul``'s Leibniz form, ``Pow``, the chain rule of ``Function``) in the same
order of operations, so that it builds the same expression, bit for bit and print for
print, but memoised on each node; any other kind of node (``Abs``, ``Min``, ...) goes to
``sp.diff`` itself. tests/test_cams.py compares the two on every cam profile.
``replace`` is ``xreplace`` with the same memo (the generated module's profile helpers put
their argument names into such expressions).
"""
from __future__ import annotations

import sympy as sp
from sympy.core.basic import Basic
from sympy.core.expr import AtomicExpr
from sympy.core.function import Function

_MUL_N = sp.Mul._eval_derivative_n_times
_BASIC_N = Basic._eval_derivative_n_times
_ADD = sp.Add._eval_derivative
_POW = sp.Pow._eval_derivative
_FUNCTION = Function._eval_derivative


class Differentiator:
    """d/d``var`` of expressions, memoised per node (one per variable: the memo is kept
    for later orders, whose expressions share most of their nodes)."""

    def __init__(self, var):
        self.var = var
        self._memo = {}
        self._has = {}

    def has_var(self, e) -> bool:
        """``var`` among the free symbols of ``e``, memoised for the nodes that cannot
        bind a symbol (the others ask ``free_symbols``)."""
        found = self._has.get(e)
        if found is None:
            if e.is_Atom:
                found = e == self.var
            elif isinstance(e, (sp.Add, sp.Mul, sp.Pow, Function, sp.Piecewise,
                                sp.core.relational.Relational, sp.logic.boolalg.Boolean)) \
                    and not isinstance(e, sp.Lambda):
                found = any(self.has_var(a) for a in e.args)
            else:
                found = self.var in e.free_symbols
            self._has[e] = found
        return found

    def __call__(self, e):
        """``sp.diff(e, var)``."""
        e = sp.sympify(e)
        out = self._memo.get(e)
        if out is None:
            out = self._diff(e)
            self._memo[e] = out
        return out

    def _diff(self, e):
        var = self.var
        if not self.has_var(e):         # Derivative.__new__'s quick exit
            return sp.S.Zero
        cls = type(e)
        if isinstance(e, AtomicExpr) and e.is_Symbol:
            return sp.S.One if e == var else sp.S.Zero
        if cls._eval_derivative_n_times is _MUL_N:
            # Mul._eval_derivative_n_times(var, 1): the Leibniz sum, one factor differentiated
            args = e.args
            terms = []
            for i in range(len(args)):
                p = sp.Mul(*[self(a) if k == i else a for k, a in enumerate(args)])
                terms.append(1 * p)
            return sp.Add(*terms)
        if cls._eval_derivative_n_times is _BASIC_N:
            rule = cls._eval_derivative
            if rule is _ADD:
                return e.func(*[self(a) for a in e.args])
            if rule is _POW:
                dbase, dexp = self(e.base), self(e.exp)
                return e * (dexp * sp.log(e.base) + dbase * e.exp / e.base)
            if rule is _FUNCTION:
                terms = []
                for i, a in enumerate(e.args, start=1):
                    da = self(a)
                    if da.is_zero:
                        continue
                    try:
                        df = e.fdiff(i)
                    except sp.ArgumentIndexError:
                        df = Function.fdiff(e, i)
                    terms.append(df * da)
                return sp.Add(*terms)
        return sp.diff(e, var)


def replace(expr, rule, memo=None):
    """``expr.xreplace(rule)``, each distinct subexpression rebuilt once (``memo``, a dict,
    may be shared by calls with the same ``rule``)."""
    memo = {} if memo is None else memo

    def walk(e):
        if not isinstance(e, Basic):
            return e
        out = memo.get(e)
        if out is None:
            if e in rule:
                out = rule[e]
            elif e.args:
                args = [walk(a) for a in e.args]
                changed = any(a is not b for a, b in zip(args, e.args))
                out = e.func(*args) if changed else e
            else:
                out = e
            memo[e] = out
        return out

    return walk(sp.sympify(expr))


_BY_VAR: dict = {}


def differentiator(var) -> Differentiator:
    """The memoised d/d``var`` (one per symbol, shared by every profile in it)."""
    d = _BY_VAR.get(var)
    if d is None:
        d = _BY_VAR[var] = Differentiator(var)
    return d


__all__ = ["Differentiator", "differentiator", "replace"]
