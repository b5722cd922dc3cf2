"""Synthesis from positions (docs/reference/synthesis.md): the dyads that guide a body through 3, 4
or 5 poses (Burmester), the four-bars they make with their defects, Grashof type and transmission
angle, each handed over as a mechgen Model; and Freudenstein's function generation.

A layer beside ``bridge``, above the model language and the runtime: numpy and scipy for
the numbers, ``mechgen.model`` for the Model a FourBar builds (imported when built).

    poses.py      poses checked; displacements, poles, the equal-distance rows
    curves.py     3 poses: the family sampled; 4 poses: the centre-point curve sampled
    burmester.py  5 poses: every real Burmester pair (a quartic)
    sliders.py    PR / RP dyads: body points with collinear positions (and inverted)
    dyads.py      Dyad, dyads()
    defects.py    a four-bar's closed-form position analysis: modes, toggles, defects
    fourbar.py    FourBar (.model()), fourbars()
    function.py   function(): Freudenstein
    verify.py     a four-bar's defects decided by its compiled model swept (SolverCheck)
    export.py     a FourBar written out as a model file (model_source)
"""
from .dyads import Dyad, dyads
from .fourbar import FourBar, four_bar, fourbars, grashof
from .function import function
from .curves import circle_cubic as circle_point_cubic
from .curves import cubic as centre_point_cubic
from .verify import SolverCheck, Verdict, defects_by_solver
from .export import identifier, model_source

__all__ = ["Dyad", "dyads", "FourBar", "four_bar", "fourbars", "function", "grashof",
           "centre_point_cubic", "circle_point_cubic", "SolverCheck", "Verdict",
           "defects_by_solver", "identifier", "model_source"]
