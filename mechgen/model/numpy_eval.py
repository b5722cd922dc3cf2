"""Sympy expressions evaluated with numpy on arrays, each distinct subexpression once.

The contact-geometry check of a cam (mechgen.model.library2d.profiles.check_contact) needs a
profile's coordinates and their first two derivatives at a few thousand parameter values.
``lambdify`` prints each expression as one Python expression first: a profile's second
derivative is a tree of tens of thousands of operations whose subtrees repeat, and its
printing took seconds. ``evaluate`` walks the expressions as the graph they are (sympy
shares equal subexpressions), computing each node once on the whole array; a kind of node
it does not know is handed to ``lambdify`` alone.
"""
from __future__ import annotations

import numpy as np
import sympy as sp
from sympy.logic import boolalg

from .rates import almost_everywhere

_UNARY = {
    sp.sin: np.sin, sp.cos: np.cos, sp.tan: np.tan, sp.exp: np.exp, sp.log: np.log,
    sp.asin: np.arcsin, sp.acos: np.arccos, sp.atan: np.arctan, sp.sinh: np.sinh,
    sp.cosh: np.cosh, sp.tanh: np.tanh, sp.asinh: np.arcsinh, sp.acosh: np.arccosh,
    sp.atanh: np.arctanh, sp.Abs: np.abs, sp.sign: np.sign, sp.floor: np.floor,
    sp.ceiling: np.ceil, sp.cot: lambda x: 1 / np.tan(x), sp.sec: lambda x: 1 / np.cos(x),
    sp.csc: lambda x: 1 / np.sin(x),
}
_BINARY = {sp.atan2: np.arctan2, sp.Mod: np.mod}
_COMPARE = {sp.StrictLessThan: np.less, sp.LessThan: np.less_equal,
            sp.StrictGreaterThan: np.greater, sp.GreaterThan: np.greater_equal,
            sp.Eq: np.equal, sp.Ne: np.not_equal}


# n-ary nodes folded pairwise
_FOLDED = {sp.Min: np.minimum, sp.Max: np.maximum, boolalg.And: np.logical_and,
           boolalg.Or: np.logical_or}


class _Graph:
    def __init__(self, values):
        self.memo = dict(values)

    def __call__(self, e):
        out = self.memo.get(e)
        if out is None:
            out = self._node(e)
            self.memo[e] = out
        return out

    def _node(self, e):
        if e.is_Number or e.is_NumberSymbol:
            return float(e)
        if e.is_Symbol:
            raise ValueError(f"evaluate: no value for the symbol {e}")
        if e is sp.true or e is sp.false:
            return bool(e)
        cls = type(e)
        if cls is sp.Add:
            out = self(e.args[0])
            for a in e.args[1:]:
                out = out + self(a)
            return out
        if cls is sp.Mul:
            out = self(e.args[0])
            for a in e.args[1:]:
                out = out * self(a)
            return out
        if cls is sp.Pow:
            base, p = self(e.base), e.exp
            if p == sp.S.Half:
                return np.sqrt(base)
            if p == -sp.S.Half:
                return 1 / np.sqrt(base)
            if p.is_Integer:
                return np.power(base, float(p)) if p < 0 else np.power(base, int(p))
            return np.power(base, self(p))
        if cls in _UNARY:
            return _UNARY[cls](self(e.args[0]))
        if cls in _BINARY:
            return _BINARY[cls](self(e.args[0]), self(e.args[1]))
        if cls in _FOLDED:
            f = _FOLDED[cls]
            out = self(e.args[0])
            for a in e.args[1:]:
                out = f(out, self(a))
            return out
        if cls in _COMPARE:
            return _COMPARE[cls](self(e.lhs), self(e.rhs))
        if cls is boolalg.Not:
            return np.logical_not(self(e.args[0]))
        if cls is sp.Piecewise:
            return self._piecewise(e)
        if hasattr(cls, "_imp_") and not isinstance(e, sp.Symbol):   # wrap(s, P)
            return cls._imp_(*[self(a) for a in e.args])
        return self._lambdified(e)

    def _piecewise(self, e):
        """The first branch whose condition holds, NaN where none does (as lambdify)."""
        out, taken = np.nan, False
        for value, cond in e.args:
            c = self(cond)
            pick = np.logical_and(np.logical_not(taken), c)
            if np.all(pick):
                v = self(value)
                out = np.where(pick, v, out) if np.ndim(out) else v
            elif np.any(pick):
                out = np.where(pick, self(value), out)
            taken = np.logical_or(taken, c)
            if np.all(taken):
                break
        return out

    def _lambdified(self, e):
        syms = sorted(e.free_symbols, key=str)
        f = sp.lambdify(syms, e, modules="numpy")
        return f(*[self(s) for s in syms])


def evaluate(exprs, values, shape):
    """The float arrays of ``exprs`` (of ``shape``) with ``values`` (symbol -> number or
    array of ``shape``) put in; each distinct subexpression is computed once."""
    graph = _Graph({k: v for k, v in values.items()})
    out = []
    with np.errstate(all="ignore"):
        for e in exprs:
            v = np.asarray(graph(almost_everywhere(sp.sympify(e))), dtype=float)
            out.append(np.broadcast_to(v, shape))
    return out


__all__ = ["evaluate"]
