"""The functions of cam profiles (mechgen.model.library2d.profiles.ProfileFunction) in a generated
module: one jitted helper per profile coordinate and derivative order that the equations,
the points or the outputs use, ``_profile_disc_x_ss(s, h, e)``, computing its expression
with one CSE pass (a derivative: its forward-mode program, see profile_helpers). Call
sites print as calls to it (ProfileFunction._pythoncode)."""
from __future__ import annotations

import sympy as sp

from ...model.dag import replace
from ...model.library2d.profiles import ProfileFunction
from ..codegen.ir import Code, Helper, Store
from ..codegen.printer import Local
from ..codegen.schedule import emit
from .profile_derivatives import Derivatives


def used_profiles(exprs):
    """The ProfileFunction classes the expressions call, by name."""
    found = {}
    for e in exprs:
        for f in sp.sympify(e).atoms(ProfileFunction):
            found[f.func.__name__] = f.func
    return [found[k] for k in sorted(found)]


def profile_helpers(model, eq, cse=True, extra=()):
    """[Helper] of every profile function that Φ, Φ_q, γ, the points or the outputs call.

    A coordinate itself is its expression with one CSE pass; its derivatives come from
    one forward-mode program per coordinate (mechgen.compiler.functions.profile_derivatives), not
    from sympy's derivative of the whole expression (much larger, and slow to take apart
    again). Without CSE (``cse=False``) each is sympy's derivative, printed whole."""
    exprs = list(eq.phi) + list(eq.phi_q) + list(eq.gamma) + list(model.outputs.values())
    exprs += list(extra)            # (a sensitivity module's derivatives)
    for con in model.constraints:
        for pt in getattr(con, "points", ()):
            exprs += list(pt.r)
    out, memos, programs = [], {}, {}
    for cls in used_profiles(exprs):
        args = [Local("_s", real=True)] + [Local(f"_a{k}", real=True)
                                           for k in range(len(cls.params))]
        rule = dict(zip((cls.var,) + cls.params, args))
        memo = memos.setdefault((cls.var,) + cls.params, {})   # shared by x, y, x', ...
        if cls.order and cse and not cls.wrt:
            key = (cls.base, cls.expr, cls.var, cls.params)
            if key not in programs:
                programs[key] = Derivatives(replace(cls.expr, rule, memo), args[0])
            statements = programs[key].statements(cls.order)
        else:
            statements = [Store("_v", replace(cls.diffed(), rule, memo))]
        shown = ", ".join(["s"] + [p.name for p in cls.params])
        doc = (f"Profile coordinate {cls.base}" + (f", derivative {cls.order}" if cls.order
                                                    else "") + f", of ({shown}).")
        body = tuple(emit(statements, cse=cse)) + (Code("return _v"),)
        out.append(Helper(f"_profile_{cls.__name__}", ", ".join(a.name for a in args), doc,
                          body))
    return out
