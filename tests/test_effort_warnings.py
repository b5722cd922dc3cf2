"""A driver's effort from λ and its factors (runtime/forces/points.efforts) leaks no numpy
warning where a point has no force balance (an infinite λ beside a zero factor, a NaN
point of a design that did not solve): the effort there is NaN, the others exact."""
import warnings

import numpy as np

from mechgen.runtime.forces.points import efforts


def test_infinite_lambda_times_zero_factor_is_nan_without_a_warning():
    LAM = np.array([[1.0, 2.0, 3.0], [np.inf, 1.0, 0.0], [np.nan, 1.0, 1.0]])
    FACTORS = np.array([[2.0, 0.5], [0.0, 1.0], [1.0, 1.0]])
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        with np.errstate(all="raise"):
            out = efforts(LAM, FACTORS, rows=(0, 2), cols=(0, 1))
    assert out[0] == 1.0 * 2.0 + 3.0 * 0.5
    assert np.isnan(out[1]) and np.isnan(out[2])


def test_design_table_shape_and_infinite_factor():
    LAM = np.ones((2, 3, 2))
    FACTORS = np.ones((2, 3, 1))
    FACTORS[1, 2, 0] = np.inf
    LAM[0, 1, 0] = 0.0
    FACTORS[0, 1, 0] = np.inf
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        out = efforts(LAM, FACTORS, rows=(0,), cols=(0,))
    assert out.shape == (2, 3)
    assert np.isnan(out[1, 2]) and np.isnan(out[0, 1])
    assert np.sum(np.isfinite(out)) == 4 and np.all(out[np.isfinite(out)] == 1.0)
