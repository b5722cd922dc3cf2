"""Printing sympy expressions as numba-friendly Python.

Symbols print through a name map (mechgen.compiler.codegen.names): a model's own names
(``X2``, ``Th3``, ``longitud``) stay as they are unless the generated module uses the
same name for itself, when they get a mangled form (``q`` becomes ``q_``).

Three kinds of symbols belong to the code generator, never to a model:
- ``Local``: a local of the generated code (``_t0``, ``_r0``, ``_iters``); a model symbol
  of the same name (a parameter called ``_t0``) is a different symbol.
- ``Derived``: a name the code generator makes from model names (``_sin_Th3``,
  ``_dY4_dX4``); it prints with the mapped names of its parts.
- ``Alias``: a symbol that takes the place of a CSE temporary. It prints as its
  ``target`` (a renumbered temporary, or the symbol or number a trivial temporary stood
  for) but sorts in sums and products exactly as the temporary did, so that the printed
  order of operations, and with it every floating-point result, stays the same.
"""
from __future__ import annotations

import sympy as sp
from sympy.printing.pycode import PythonCodePrinter

from ...model.rates import almost_everywhere


class Local(sp.Symbol):
    """A local variable of the generated code, printed by its name."""

    @classmethod
    def class_key(cls):     # sorts among plain symbols, by its name
        return 2, 0, "Symbol"


class Derived(sp.Symbol):
    """A name made of fixed text and model symbols, e.g. ``("_sin_", Th3)``; as a sympy
    symbol it is named by the plain concatenation (the sort order of earlier releases),
    and two different part lists are two different symbols even where those agree."""

    def __new__(cls, *parts):
        name = "".join(p if isinstance(p, str) else p.name for p in parts)
        obj = sp.Symbol.__xnew__(cls, name, real=True)   # not cached by name alone
        obj.parts = tuple(parts)
        return obj

    def __getnewargs_ex__(self):
        return self.parts, {}

    def _hashable_content(self):
        return super()._hashable_content() + (self.parts,)

    @classmethod
    def class_key(cls):     # sorts among plain symbols, by its name
        return 2, 0, "Symbol"


class Alias(sp.Symbol):
    """Prints as ``target``; sorts as the symbol named ``key`` (see the module docstring)."""

    def __new__(cls, target, key: str):
        obj = sp.Symbol.__xnew__(cls, f"{key}->{target}", real=True)
        obj.target, obj.key = target, key
        return obj

    def __getnewargs_ex__(self):
        return (self.target, self.key), {}

    def _hashable_content(self):
        return super()._hashable_content() + (self.target, self.key)

    @classmethod
    def class_key(cls):
        return 2, 0, "Symbol"

    def sort_key(self, order=None):
        return self.class_key(), (1, (self.key,)), sp.S.One.sort_key(), sp.S.One


class NumbaPrinter(PythonCodePrinter):
    """Python code with ``math`` functions, floats to full precision and symbols by name."""

    def __init__(self, names=None):
        super().__init__({"fully_qualified_modules": True, "standard": "python3"})
        self.names = names

    def _print_Symbol(self, expr):
        if isinstance(expr, Alias):
            return self._print(expr.target)
        if self.names is not None:
            return self.names.ident(expr)
        return expr.name

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


_PLAIN = NumbaPrinter()


def printer_for(names=None) -> NumbaPrinter:
    """The printer of a name map (None: every symbol by its own name)."""
    return _PLAIN if names is None else NumbaPrinter(names)


def pycode(expr, names=None) -> str:
    """``expr`` as Python code, its symbols named by ``names`` (a Names, or None)."""
    return printer_for(names).doprint(almost_everywhere(sp.sympify(expr)))
