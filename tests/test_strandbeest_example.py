"""examples/strandbeest.py (Jansen's leg, 21 coordinates: the Strandbeest-size model of the
start-up benchmark) solves: followed in small steps from its guess, every body sits where
the leg's construction by circle intersections puts it at that crank angle."""
import math
import os

import numpy as np

from conftest import EXAMPLES, GENERATED
from mechgen.model.loader import load_models


def _construction(t):
    """{body: (x, y, angle)} of the leg at time t, by intersecting circles (the example's
    own _third and _frame, with the crank pin turned to 2πt)."""
    import runpy
    ns = runpy.run_path(os.path.join(EXAMPLES, "strandbeest.py"))
    third, frame = ns["_third"], ns["_frame"]
    a, l, m_ = 38.0, 7.8, 15.0
    b, c, d, e, f, g, h, i, j, k = 41.5, 39.3, 40.1, 55.8, 39.4, 36.7, 65.7, 49.0, 50.0, 61.9
    th = 2 * math.pi * t
    B, A = (-a, -l), (m_ * math.cos(th), m_ * math.sin(th))
    C = third(B, A, b, j, 1)
    E = third(B, A, c, k, -1)
    D = third(B, C, d, e, 1)
    F = third(D, E, f, g, -1)
    return {"crank": (0.0, 0.0, th), "upper": (*A, frame(A, C)), "hip": (*B, frame(B, C)),
            "lower": (*A, frame(A, E)), "cee": (*B, frame(B, E)), "eff": (*D, frame(D, F)),
            "foot": (*E, frame(E, F))}


def test_the_strandbeest_example_solves_as_its_construction():
    import mechgen
    model = load_models(os.path.join(EXAMPLES, "strandbeest.py"))[0]
    mech = mechgen.load(os.path.join(GENERATED, f"{model.name}.py"))
    assert len(mech.coordinates) == 21
    s = mech.solve(0.0)
    assert np.allclose(s.q, mech.guess, atol=1e-9)
    for t in np.linspace(0.0, 1.0, 41)[1:]:
        s = mech.solve(float(t), guess=s)
        for body, (x, y, ang) in _construction(float(t)).items():
            number = model.bodies[body].number
            assert abs(s[f"X{number}"] - x) < 1e-8 and abs(s[f"Y{number}"] - y) < 1e-8, (t, body)
            turn = s[f"Th{number}"] - ang
            assert abs(math.sin(turn)) < 1e-9 and math.cos(turn) > 0, (t, body)
