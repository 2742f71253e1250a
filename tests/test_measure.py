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


def test_report_prints_the_verdict_not_the_count(capsys):
    # a check that passes names its tolerance only: the same line whether this machine's
    # rounding gives 1 eps or 2 (strict nbval compares it on every processor)
    for err in (0, 1, 2):
        assert report("x", 1.0 + err * EPS, 1.0, tol=2) is None
        assert capsys.readouterr().out == "x: within 2 eps: ok\n"


def test_report_with_no_tolerance_says_identical(capsys):
    report("x", 1.0, 1.0, tol=0)
    assert capsys.readouterr().out == "x: identical: ok\n"
    report("x", np.nextafter(1.0, 2.0), 1.0, tol=0)
    assert capsys.readouterr().out == "x: error 1 eps, more than the 0 eps allowed: FAILS\n"


def test_a_failing_report_prints_its_count(capsys):
    report("x", 1.0 + 4 * EPS, 1.0, tol=2)
    assert capsys.readouterr().out == "x: error 4 eps, more than the 2 eps allowed: FAILS\n"


@pytest.mark.parametrize("tol", [-1, 2.5, True, "8", None])
def test_report_refuses_a_tolerance_that_is_not_a_whole_number(tol):
    with pytest.raises(ValueError, match="whole number of eps"):
        report("x", 1.0, 1.0, tol=tol)


def test_a_failure_shown_on_purpose_prints_its_bound(capsys):
    report("x", 1.0 + 2.0**30 * EPS, 1.0, tol=8, over=1e6)
    assert capsys.readouterr().out == "x: error over 1e6 eps (tolerance 8 eps): FAILS\n"
    report("x", 1.0 + 2.0**30 * EPS, 1.0, tol=8, over=2500)
    assert capsys.readouterr().out == "x: error over 2500 eps (tolerance 8 eps): FAILS\n"
    # a formula that stopped failing as much as shown prints its count, which nbval sees
    report("x", 1.0 + 100 * EPS, 1.0, tol=8, over=1e6)
    assert capsys.readouterr().out == "x: error 100 eps, more than the 8 eps allowed: FAILS\n"
    report("x", 1.0, 1.0, tol=8, over=1e6)
    assert capsys.readouterr().out == "x: within 8 eps: ok\n"


@pytest.mark.parametrize("over", [8, 3, -1.0, float("inf"), float("nan"), "1e6", True])
def test_report_refuses_a_bound_not_above_the_tolerance(over):
    with pytest.raises(ValueError, match="over must be"):
        report("x", 1.0, 1.0, tol=8, over=over)


def test_report_refuses_nan():
    with pytest.raises(ValueError, match="NaN"):
        report("x", np.nan, 1.0)


@pytest.mark.parametrize("got, ref", [([np.nan], [1.0]), ([1.0], [np.inf]), ([1.0, 2.0], [1.0])])
def test_refuses_nan_inf_and_shape_mismatch(got, ref):
    with pytest.raises(ValueError):
        eps_error(got, ref)
