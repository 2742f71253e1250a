"""SO(2), the generator J and the correspondence with complex numbers (spec S24 to S27)."""

import math

import mpmath
import numpy as np
import pytest
from hypothesis import given
from hypothesis import strategies as st

import so3lib
from conftest import EPS
from reference import so2_exp_ref, so2_log_ref
from so3lib import so2

I2 = np.eye(2)


def test_J_cycle():
    """J^0..J^4 = I, J, -I, -J, I (spec S25)."""
    powers = [np.linalg.matrix_power(so2.J, p) for p in range(5)]
    for P, expected in zip(powers, [I2, so2.J, -I2, -so2.J, I2]):
        assert np.array_equal(P, expected)


def test_J_is_read_only():
    with pytest.raises(ValueError):
        so2.J[0, 0] = 1.0


def test_hat_is_the_3d_hat_restricted_to_the_plane():
    """hat((0, 0, w))[:2, :2] == w J: so the 2-D hat is +w J (errata N8)."""
    for w in (0.8, -2.0, 0.0):
        assert np.array_equal(so3lib.hat([0.0, 0.0, w])[:2, :2], so2.hat(w))
    assert np.array_equal(so2.vee(so2.hat([0.5, -1.5])), [0.5, -1.5])


@pytest.mark.parametrize("theta", [0.0, 1e-300, 1e-8, 0.7, -2.0, 3.0, math.pi, 100.0, 1e6])
def test_exp_matches_reference_and_3d(theta):
    R = so2.exp(theta)
    assert np.abs(R - so2_exp_ref(theta)).max() <= 2 * EPS
    assert np.array_equal(so3lib.exp([0.0, 0.0, theta])[:2, :2], R) or \
        np.abs(so3lib.exp([0.0, 0.0, theta])[:2, :2] - R).max() <= 4 * EPS * max(1, abs(theta))


@pytest.mark.parametrize("theta", [1e-300, 1e-8, 1.0, 3.0, 3.5, -3.5, -math.pi, 10.0])
def test_log_is_atan2_in_half_open_interval(theta):
    """Log R = atan2(R21, R11) in (-pi, pi] (spec S27)."""
    R = so2_exp_ref(theta)
    L = so2.log(R)
    assert -math.pi < L <= math.pi         # the doubles (-np.pi, np.pi]: never -np.pi
    ref = so2_log_ref(R)
    if ref == -math.pi:                    # the reference rounds the true angle, just above
        ref = math.pi                      # -pi, to the double -np.pi: the same half-turn
    assert abs(L - ref) <= 2 * EPS * max(1.0, abs(L))
    wrapped = theta - 2 * math.pi * round(theta / (2 * math.pi))
    assert abs(L - wrapped) <= 4 * EPS * max(1.0, abs(wrapped)) or abs(abs(wrapped) - math.pi) < 1e-15


def test_log_at_the_branch_cut_returns_plus_pi():
    assert so2.log(np.array([[-1.0, 0.0], [-0.0, -1.0]])) == math.pi
    assert so2.log(np.array([[-1.0, -0.0], [0.0, -1.0]])) == math.pi


@pytest.mark.parametrize("s", [-0.0, -1e-300, -1e-16, -2e-16, -3e-16])
def test_log_next_to_the_cut_returns_plus_pi(s):
    """atan2(s, -1) rounds to the double -np.pi for these s; the convention (the doubles
    (-np.pi, np.pi], notebook 03 section 7) makes it np.pi, within 5e-16 of the true angle
    modulo 2 pi."""
    assert np.arctan2(s, -1.0) == -np.pi
    R = np.array([[-1.0, -s], [s, -1.0]])
    L = so2.log(R)
    assert L == math.pi
    with mpmath.workdps(40):               # the true angle and L, modulo 2 pi
        d = mpmath.atan2(s, -1) - mpmath.mpf(L)
        d -= 2 * mpmath.pi * mpmath.nint(d / (2 * mpmath.pi))
        assert abs(d) < 5e-16              # two ulps of pi
    assert so2.log(np.stack([R, R]), 2.0).tolist() == [math.pi / 2, math.pi / 2]


def test_log_is_never_minus_pi_on_a_dense_sweep_through_the_cut():
    """Angles through pi in steps of about 1e-16: every result in the doubles (-np.pi, np.pi]."""
    s = np.concatenate([-np.geomspace(1e-18, 1e-14, 401), [-0.0, 0.0],
                        np.geomspace(1e-18, 1e-14, 401)])
    R = np.stack([np.stack([-np.ones_like(s), -s], -1), np.stack([s, -np.ones_like(s)], -1)], -2)
    L = so2.log(R)
    assert np.isfinite(L).all() and (L > -np.pi).all() and (L <= np.pi).all()
    assert (L[s < -4e-16] < 0).all()       # far enough from the cut, the negative side stays


def test_log_with_time_and_batches():
    thetas = np.array([[0.1, -0.2], [1.0, 3.0]])
    R = so2.exp(thetas, 0.5)
    assert R.shape == (2, 2, 2, 2)
    assert np.allclose(so2.log(R, 0.5), thetas, rtol=0, atol=4 * EPS)


@given(a=st.complex_numbers(max_magnitude=1e3, allow_nan=False, allow_infinity=False),
       b=st.complex_numbers(max_magnitude=1e3, allow_nan=False, allow_infinity=False))
def test_complex_correspondence_is_a_ring_homomorphism(a, b):
    """Phi(ab) = Phi(a) Phi(b), Phi(conj a) = Phi(a)^T, det Phi(a) = |a|^2 (spec S25)."""
    A, B = so2.from_complex(a), so2.from_complex(b)
    scale = max(1.0, abs(a) * abs(b))
    assert np.allclose(so2.from_complex(a * b), A @ B, rtol=0, atol=8 * EPS * scale)
    assert np.array_equal(so2.from_complex(np.conj(a)), A.T)
    assert math.isclose(np.linalg.det(A), abs(a) ** 2, rel_tol=1e-12, abs_tol=1e-300)
    assert so2.to_complex(A) == a


def test_exp_of_j_theta_is_the_rotation():
    """Phi(e^{j theta}) = exp(J theta) (spec S26)."""
    for th in (0.7, -2.0, 3.0):
        assert np.abs(so2.from_complex(np.exp(1j * th)) - so2.exp(th)).max() <= 2 * EPS
        assert np.isclose(so2.to_complex(so2.exp(th)), np.exp(1j * th), rtol=0, atol=2 * EPS)
    assert np.array_equal(so2.from_complex(1j), so2.J)


def test_log_keeps_the_doubles_minus_pi_to_pi_with_a_faithful_atan2(monkeypatch):
    """A C library whose atan2 is faithful but not correctly rounded may answer the half-turn
    with the double just below -np.pi, or the double just above np.pi: so2.log still
    returns np.pi, in the interval (-np.pi, np.pi] that it promises."""
    import so3lib.so2 as so2_module
    half_turn = np.array([[-1.0, 0.0], [-0.0, -1.0]])
    for outside in (np.nextafter(-np.pi, -4.0), np.nextafter(np.pi, 4.0)):
        monkeypatch.setattr(so2_module.np, "arctan2", lambda s, c, v=outside: np.full(np.shape(s), v))
        assert so2_module.log(half_turn) == np.pi
