"""The rates of the piecewise functions a model may hold (Abs, sign, Max, Min, floor,
ceiling, frac, Mod, Heaviside) as numbers: sympy differentiates them into DiracDelta or
leaves the Derivative unevaluated, which neither the generated module nor numpy can
compute. Each becomes its rate almost everywhere, the one a finite difference of the
quantity reads away from its jumps and kinks."""
from __future__ import annotations

import sympy as sp

_STEPS = (sp.floor, sp.ceiling, sp.sign, sp.Heaviside, sp.DiracDelta)


def _rate(d):
    """A Derivative sympy leaves unevaluated, almost everywhere: 0 for a step function's
    (floor, sign, ...), u' for frac(u)'s, u' − c' floor(u/c) for Mod(u, c)'s; None for
    any other."""
    f = d.expr
    if isinstance(f, _STEPS):
        return sp.S.Zero
    if isinstance(f, sp.frac):                      # u − floor(u)
        return almost_everywhere(sp.diff(f.args[0], *d.variable_count))
    if isinstance(f, sp.Mod):
        u, c = f.args
        return almost_everywhere(sp.diff(u, *d.variable_count)
                                 - sp.diff(c, *d.variable_count) * sp.floor(u / c))
    return None


def almost_everywhere(expr):
    """``expr`` with the rates of the piecewise functions a model may hold (Abs, sign,
    Max, floor, Mod, Heaviside) written as numbers: sympy's DiracDelta and unevaluated
    Derivatives of a step become 0, the rate a finite difference reads away from the jump
    (on the jump there is none), and Mod(u, c) moves as u does between its wraps."""
    if not isinstance(expr, sp.Basic) or not expr.has(sp.DiracDelta, sp.Derivative):
        return expr
    expr = expr.replace(lambda e: isinstance(e, sp.DiracDelta), lambda e: sp.S.Zero)
    expr = expr.replace(lambda e: isinstance(e, sp.Derivative) and _rate(e) is not None,
                        _rate)
    # the chain rule through such a function: Subs(d/dξ f(ξ), ξ, u), its rate now known
    return expr.replace(lambda e: isinstance(e, sp.Subs) and not e.expr.has(sp.Derivative),
                        lambda e: e.doit())
