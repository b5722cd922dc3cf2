"""Parameter sensitivities (docs/reference/sensitivities.md): dq/dp, dq̇/dp, dq̈/dp at a solution
and along a sweep, from the sensitivity module the compiler emits beside a model's module
(``companion``: loaded or built when first asked), solved on Φ_q's blocks (``solve``); the
derivative of any named or symbolic quantity (``values``); tolerance bands (``tolerance``). Imported
when first used: a call that asks for none pays nothing."""
from __future__ import annotations

from ..results import Solution
from .solve import Sensitivities, of_solution, of_sweep, parameter_columns
from .values import sensitivity


def attach(mech, result, which):
    """``result`` (a Solution or Sweep of ``mech``) with its sensitivities to the
    parameters ``which`` (True: all; a name; a list of names) computed and attached
    (``result.sensitivities``); returns it."""
    if result.__class__ is Solution:        # (the most frequent, answered first)
        result.sensitivities = of_solution(mech, result, which)
        return result
    if "Q" not in result.__dict__:
        result.sensitivities = of_solution(mech, result, which)
    elif "P" in result.__dict__:            # a design table
        from .tables import of_table
        result.sensitivities = of_table(mech, result, which)
    else:
        result.sensitivities = of_sweep(mech, result, which)
    if getattr(type(result), "force_level", None) is not None and "P" not in result.__dict__:
        from .forces import attach_forces
        attach_forces(mech, result)
    return result


__all__ = ["Sensitivities", "attach", "of_solution", "of_sweep", "parameter_columns",
           "sensitivity"]
