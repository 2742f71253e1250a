"""so3lib.measure: errors in whole eps, against hand-computed cases."""

import mpmath
import numpy as np
import pytest

from so3lib.measure import EPS, eps_error, report


def test_identical_is_zero():
    assert eps_error([1.0, 2.0], [1.0, 2.0]) == 0


def test_one_ulp_of_one_is_one_eps():
    assert eps_error(np.nextafter(1.0, 2.0), 1.0) == 1


def test_relative_for_large_reference():
    ref = 2.0**20
    assert eps_error(ref * (1 + 3 * EPS), ref) == 3


def test_absolute_for_small_reference():
    assert eps_error(1e-20 + 2 * EPS, 1e-20) == 2


def test_mpmath_reference_subtracts_before_rounding():
    with mpmath.workdps(50):
        ref = np.array([mpmath.mpf(1) / 3], dtype=object)
        got = np.array([1.0 / 3.0])
        assert eps_error(got.astype(object), ref) <= 1


def test_report_prints_verdict(capsys):
    assert report("x", 1.0 + 4 * EPS, 1.0, tol=2) is None
    assert capsys.readouterr().out == "x: error 4 eps (tolerance 2 eps): FAILS\n"


@pytest.mark.parametrize("got, ref", [([np.nan], [1.0]), ([1.0], [np.inf]), ([1.0, 2.0], [1.0])])
def test_refuses_nan_inf_and_shape_mismatch(got, ref):
    with pytest.raises(ValueError):
        eps_error(got, ref)
