"""The power series and the coefficients A and B (spec S6, S10)."""

import math

import numpy as np
import pytest
import sympy as sp

import so3lib
from conftest import EPS
from reference import coeffs_ref, expm_ref


def test_series_converges_to_rodrigues():
    """60 terms of the series equal Rodrigues to rounding (spec S6)."""
    w, tau = np.array([0.3, -0.4, 1.2]), 0.7
    S = so3lib.exp_series(w, tau, terms=60)
    assert np.abs(S - so3lib.exp(w, tau)).max() < 1e-15
    assert np.abs(S - expm_ref(w, tau)).max() < 1e-15


def test_first_terms():
    w = np.array([0.1, 0.2, 0.3])
    K = so3lib.hat(w)
    assert np.array_equal(so3lib.exp_series(w, terms=1), np.eye(3))
    assert np.array_equal(so3lib.exp_series(w, terms=2), np.eye(3) + K)
    assert np.allclose(so3lib.exp_series(w, terms=3), np.eye(3) + K + K @ K / 2, rtol=0, atol=1e-17)


@pytest.mark.parametrize("theta", [0.5, 2.0, 6.0])
def test_truncation_error_is_bounded_by_first_omitted_term(theta):
    """After N terms the error is at most about theta^N / N! (the series of e^theta)."""
    w = theta * np.array([2.0, -1.0, 2.0]) / 3.0
    R = expm_ref(w)
    for N in range(1, 30):
        err = np.abs(so3lib.exp_series(w, terms=N) - R).max()
        tail = sum(theta ** m / math.factorial(m) for m in range(N, N + 60))
        assert err <= tail + 4 * EPS


def test_series_batches_over_omegas_and_times():
    S = so3lib.exp_series(np.ones((4, 3)), np.linspace(0, 1, 4), terms=25)
    assert S.shape == (4, 3, 3)
    assert np.allclose(S, so3lib.exp(np.ones((4, 3)), np.linspace(0, 1, 4)), rtol=0, atol=1e-15)


@pytest.mark.parametrize("t", [0.0, 5e-324, 1e-300, 1e-8, 9.9e-5, 1e-4, 1e-3, 0.1, 1.0, 3.0, 100.0, -2.0])
def test_coefficients_match_reference(t):
    ref = coeffs_ref(t)
    assert abs(so3lib.A(t) - ref["A"]) <= 2 * EPS * abs(ref["A"])
    assert abs(so3lib.B(t) - ref["B"]) <= 4 * EPS * abs(ref["B"])


def test_naive_B_fails_where_stable_B_does_not():
    """(1 - cos t)/t^2 is 0 at t = 1e-8; the library's B is 1/2 (spec S10)."""
    t = 1e-8
    assert (1 - math.cos(t)) / t ** 2 == 0.0
    assert so3lib.B(t) == 0.5


def test_taylor_coefficients_symbolically():
    t = sp.symbols("t")
    assert sp.series(sp.sin(t) / t, t, 0, 6).removeO() == 1 - t ** 2 / 6 + t ** 4 / 120
    assert sp.series((1 - sp.cos(t)) / t ** 2, t, 0, 6).removeO() == \
        sp.Rational(1, 2) - t ** 2 / 24 + t ** 4 / 720


def test_coefficients_batch():
    t = np.array([[0.0, 1e-5], [1.0, 2.0]])
    assert so3lib.A(t).shape == (2, 2) and so3lib.B(t).shape == (2, 2)
    assert isinstance(so3lib.A(0.5), float)
