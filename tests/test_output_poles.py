"""Outputs near their poles: docs/reference/model.md's output functions and
docs/reference/runtime.md's sweep analysis against the quick-return's closed form
(tests/closed_forms.py, mpmath): an intersection of two axes that turn parallel, the roots
of an angle that wraps at ±π, roots and extremes around a pole, the extremes and roots of a rate from a sweep at level position.

The quick-return of seed 001 with A = manivela.at(1, 0.5) (crank) and B = colisa.at(0.3, 6)
(lever): at T = 1/4 the crank is vertical and the lever upright, so A = (-0.5, 6) and
B = (0.3, 6) and Line(A, B) is parallel to the ground's line y = 10 (by symmetry: u × v
is round-off, ~1e-17). The crank's direction (1, 2) has the angle θ + atan2(2, 1), which
wraps from +π to −π once a turn.
"""
import math

import mpmath as mp
import numpy as np
import pytest

import mechgen
from mechgen import Line, T, angle, intersection, pi
from closed_forms import quick_return

T_PARALLEL = 0.25
T_ANGLE_ZERO = 1 - math.atan2(2, 1) / (2 * math.pi)        # θ + atan2(2, 1) = 2π


def quick_return_model(name):
    m = mechgen.Model(name)
    base = m.ground("base", points=[(0, 0), (0, 5), (-5, 10), (12, 10)])
    man = m.body("manivela", points=[(0, 0), (3, 0)], guess=(0, 5, 0))
    col = m.body("colisa", points=[(0, 0), (0, 9)], guess=(0, 0, -0.5))
    des = m.body("deslizadera", points=[(0, 0), (2, 0)], guess=(6, 10, 0))
    m.revolute(base[2], man[1])
    m.rotation_lock(man, base, 2 * pi * T)
    m.revolute(base[1], col[1])
    m.point_on_line(man[2], col.line(1, 2))
    m.relative_distance(col[2], des[1], 5)
    m.translate(base.line(3, 4), des.line(1, 2))
    return m, base, man, col, des


@pytest.fixture(scope="module")
def parts(tmp_path_factory):
    m, base, man, col, des = quick_return_model("audit3_outputs")
    ix = intersection(Line(man.at(1, 0.5), col.at(0.3, 6)), base.line(3, 4))[0]
    m.output("ix", ix)
    m.output("ang_dir", angle(Line(man[2], direction=(1, 2))))
    mech = mechgen.compile(m, outdir=str(tmp_path_factory.mktemp("audit3_outputs")),
                           tier="python")
    return mech, ix


def ix_reference(t, order=0):
    """x of the intersection of Line(A, B) with y = 10, and its rates, from the closed form."""
    def ix(u):
        q = quick_return(u)
        th2, th3 = q[2], q[5]
        ax, ay = q[0] + mp.cos(th2) - 0.5 * mp.sin(th2), q[1] + mp.sin(th2) + 0.5 * mp.cos(th2)
        bx = q[3] + 0.3 * mp.cos(th3) - 6 * mp.sin(th3)
        by = q[4] + 0.3 * mp.sin(th3) + 6 * mp.cos(th3)
        return ax + (10 - ay) * (bx - ax) / (by - ay)
    with mp.workdps(30):
        return float(mp.diff(ix, mp.mpf(t), order))


def test_the_intersection_of_axes_turning_parallel_is_nan_not_a_huge_number(parts):
    mech, ix = parts
    s = mech.solve(T_PARALLEL, level="acceleration")
    # was -4.6e17, -2.6e35 (velocity) from the round-off in u x v; evaluate gave -inf
    assert math.isnan(s["ix"]) and math.isnan(s["ixd"]) and math.isnan(s["ixdd"])
    assert math.isnan(mech.evaluate(ix, s))
    assert math.isnan(mech.evaluate(mechgen.dt(ix), s))
    s = mech.solve(0.3, level="acceleration")            # away from it: the closed form
    for k, name in enumerate(("ix", "ixd", "ixdd")):
        assert s[name] == pytest.approx(ix_reference(0.3, k), rel=1e-9)
    assert mech.evaluate(ix, s) == pytest.approx(ix_reference(0.3), rel=1e-12)


def test_the_intersection_of_always_parallel_axes_is_a_model_error():
    m, base, man, col, des = quick_return_model("audit3_parallel")
    with pytest.raises(mechgen.ModelError, match="parallel at every configuration"):
        intersection(col.line(1, 2), Line(col[1], direction=(0, -2)))
    with pytest.raises(mechgen.ModelError, match="parallel"):
        intersection(base.line(3, 4), Line(base[1], direction=(1, 0)))


def test_roots_of_an_angle_skip_its_wrap_at_pi(parts):
    mech, _ = parts
    for n in (40, 41):
        r = mech.sweep(0, 1, n, level="velocity").roots("ang_dir")
        # a 'falling' root at t = 0.3238 with value -3.14159 (the wrap) came first
        assert len(r) == 1 and r[0].kind == "rising"
        assert r[0].t == pytest.approx(T_ANGLE_ZERO, abs=1e-11) and abs(r[0].value) < 1e-12


@pytest.mark.parametrize("n", [40, 41])
def test_roots_and_extremes_around_a_pole(parts, n):
    mech, _ = parts
    sw = mech.sweep(0, 1, n, level="velocity")
    # n = 41 samples the parallel instant: its -4.6e17 made every value 'zero' and no root
    # or extreme was found; n = 40 reported the two poles as roots (values -2.4e12, -1.9e12)
    r = sw.roots("ix")
    assert [e.kind for e in r] == ["falling", "rising"]
    for e in r:
        assert abs(ix_reference(e.t)) < 1e-9 and abs(e.value) < 1e-9
    ex = sw.extrema("ix")
    assert [e.kind for e in ex] == ["max", "min"]
    for e in ex:
        assert abs(ix_reference(e.t, 1)) < 1e-8
        assert e.value == pytest.approx(ix_reference(e.t), rel=1e-12)


def test_interpolating_a_quantity_that_is_nan_somewhere_says_where(parts):
    mech, _ = parts
    sw = mech.sweep(0, 1, 41, level="velocity")
    with pytest.raises(ValueError, match=r"'ix' is not a number at t = 0.25"):
        sw.interpolate("ix")


def test_extremes_and_roots_of_a_rate_from_a_position_sweep(parts):
    mech, _ = parts
    sw = mech.sweep(0, 1, 21)                       # level position: KeyError before
    ex = sw.extrema("X4d")
    ref = mech.sweep(0, 1, 21, level="acceleration").extrema("X4d")
    assert np.array_equal(ex.t, ref.t) and np.array_equal(ex.value, ref.value)
    with mp.workdps(30):
        for e in ex:
            acc = mp.diff(lambda u: quick_return(u)[6], mp.mpf(e.t), 2)
            vel = mp.diff(lambda u: quick_return(u)[6], mp.mpf(e.t), 1)
            assert abs(float(acc)) < 1e-8 and e.value == pytest.approx(float(vel), rel=1e-12)
    r = sw.roots("X4d")
    assert np.allclose(r.t, mech.sweep(0, 1, 21).extrema("X4").t, atol=1e-12)
    assert sw.level == "position"                   # the caller's sweep is left as it was
    with pytest.raises(ValueError, match="third derivative"):
        sw.extrema("X4dd")


def test_outputs_at_an_exactly_parallel_instant_are_nan_in_both_tiers(tmp_path):
    """The crank's axis is parallel to the ground's y = 10 at T = 0 exactly (u × v =
    51 sin 0 = 0.0): the compiled outputs raised ZeroDivisionError there (numba's
    division), losing a sweep's whole column; the plain tier gave -inf."""
    import importlib.util
    m, base, man, col, des = quick_return_model("audit3_exact_parallel")
    m.output("icx", intersection(man.line(1, 2), base.line(3, 4))[0])
    mech = mechgen.compile(m, outdir=str(tmp_path), tier="python")
    s = mech.solve(0.0, level="acceleration")
    assert all(math.isnan(s[n]) for n in ("icx", "icxd", "icxdd"))
    assert mech.solve(0.1)["icx"] == pytest.approx(
        5 / math.tan(0.2 * math.pi), rel=1e-12)      # the crank axis from (0, 5)
    spec = importlib.util.spec_from_file_location("audit3_exact_parallel_numba",
                                                  str(tmp_path / "audit3_exact_parallel.py"))
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)                 # numba's njit: compiled when called
    out = np.empty(1)
    for fn in (module.outputs, module.outputs_d, module.outputs_dd):
        fn(s.q, s.qd, s.qdd, 0.0, mech.p, out)
        assert math.isnan(out[0])


def test_a_sample_a_hair_from_a_pole_does_not_set_the_zero_tolerance(parts):
    """A sample 3e-9 from the time the axes turn parallel (ix = -5.1e8, its rate 1.7e17)
    made the zero tolerance 5e-3 (1e-11 of the largest value): roots() reported a node
    where ix = -9.0e-4 as an exact root, 6e-6 from the true one, and extrema() found
    none (every rate 'zero')."""
    mech, _ = parts
    pole = 0.875599355894975          # Line(A, B) parallel to y = 10 (u x v = 0 by Brent)
    ts = np.sort(np.concatenate([np.linspace(0, 1, 41), [pole + 3e-9, 0.33291]]))
    sw = mech.sweep(0, 1, len(ts), times=ts, level="velocity")
    assert abs(sw["ix"][np.searchsorted(ts, pole + 3e-9)]) > 1e8
    r = sw.roots("ix")
    assert [e.kind for e in r] == ["falling", "rising"]
    assert all(abs(ix_reference(e.t)) < 1e-9 for e in r)
    ex = sw.extrema("ix")
    assert [e.kind for e in ex] == ["max", "min"]
    assert all(abs(ix_reference(e.t, 1)) < 1e-8 for e in ex)
