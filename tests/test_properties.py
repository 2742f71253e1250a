"""Group laws and round trips, checked by hypothesis over three sampling regimes.

The regimes follow jaxlie's tests: rotation vectors of every size (up to 1e3), near the
identity (1e-12 .. 1e-3), and near a half-turn (pi - 1e-3 .. pi); plus uniformly random
rotations. Every property also runs over the batch shapes (), (1,) and (3, 1, 2).
"""

import math

import numpy as np
import pytest
from hypothesis import given
from hypothesis import strategies as st
from hypothesis.extra.numpy import arrays

import so3lib
from conftest import EPS

PI = math.pi
BATCHES = [(), (1,), (3, 1, 2)]


def unit_vectors():
    v = arrays(np.float64, 3, elements=st.floats(-1, 1, allow_subnormal=False))
    return v.filter(lambda a: np.linalg.norm(a) > 1e-3).map(lambda a: a / np.linalg.norm(a))


def rotation_vectors(lo, hi):
    """phi = theta n with theta drawn log-uniformly in [lo, hi]."""
    return st.tuples(unit_vectors(), st.floats(math.log(lo), math.log(hi))).map(
        lambda p: math.exp(p[1]) * p[0])


ANY = rotation_vectors(1e-12, 1e3)
NEAR_IDENTITY = rotation_vectors(1e-12, 1e-3)
NEAR_PI = st.tuples(unit_vectors(), st.floats(1e-13, 1e-3)).map(lambda p: (PI - p[1]) * p[0])
PRINCIPAL = st.one_of(rotation_vectors(1e-12, PI - 1e-6), NEAR_IDENTITY, NEAR_PI)
SEEDS = st.integers(0, 2**32 - 1)


def batch_of(phi, shape):
    """Copies of ``phi`` scaled a little differently across a batch of ``shape``."""
    k = np.linspace(0.5, 1.0, int(np.prod(shape, dtype=int))).reshape(shape + (1,))
    return phi * k if shape else phi


@pytest.mark.parametrize("shape", BATCHES)
@given(phi=st.one_of(ANY, NEAR_IDENTITY, NEAR_PI))
def test_exp_is_a_rotation(phi, shape):
    R = so3lib.exp(batch_of(phi, shape))
    assert R.shape == shape + (3, 3) and not np.isnan(R).any()
    # 16 eps: over 14 million random axes within 1e-2 of a half-turn the worst
    # max|R^T R - I| measured 15 eps (SciPy's from_rotvec: 7); a wrong kernel is far off
    assert np.all(so3lib.is_rotation(R, tol=16 * EPS))


@pytest.mark.parametrize("shape", BATCHES)
@given(phi=PRINCIPAL)
def test_log_inverts_exp_inside_the_ball(phi, shape):
    """log(exp(phi)) == phi for |phi| < pi (spec S21)."""
    phis = batch_of(phi, shape)
    L = so3lib.log(so3lib.exp(phis))
    assert L.shape == phis.shape and not np.isnan(L).any()
    theta = np.linalg.norm(phis, axis=-1, keepdims=True)
    # relative below theta = 1, absolute above; near pi the axis stays good to ~eps (S19)
    assert np.all(np.abs(L - phis) <= 16 * EPS * np.minimum(theta, 1.0))


@given(seed=SEEDS)
def test_exp_of_log_is_identity_for_every_rotation(seed):
    """exp(log R) == R for every rotation, half-turns included (spec S21)."""
    R = so3lib.random_rotation(np.random.default_rng(seed), (3, 1, 2))
    L = so3lib.log(R)
    assert not np.isnan(L).any() and np.all(np.linalg.norm(L, axis=-1) <= PI * (1 + EPS))
    assert np.abs(so3lib.exp(L) - R).max() <= 8 * EPS


@given(phi=NEAR_PI)
def test_exp_of_log_near_half_turn(phi):
    R = so3lib.exp(phi)
    assert np.abs(so3lib.exp(so3lib.log(R)) - R).max() <= 8 * EPS


@given(phi=ANY, wrap=st.integers(-3, 3))
def test_log_wraps_into_the_principal_ball(phi, wrap):
    """Adding whole turns along the axis does not change the rotation (spec S20)."""
    theta = np.linalg.norm(phi)
    longer = phi * (theta + 2 * PI * wrap) / theta
    assert np.abs(so3lib.exp(longer) - so3lib.exp(phi)).max() <= 32 * EPS * max(1.0, abs(theta + 2 * PI * wrap))


@given(omega=ANY, t1=st.floats(-3, 3), t2=st.floats(-3, 3))
def test_one_parameter_subgroup(omega, t1, t2):
    """R(omega, t1) R(omega, t2) == R(omega, t1 + t2) (spec S9)."""
    lhs = so3lib.exp(omega, t1) @ so3lib.exp(omega, t2)
    rhs = so3lib.exp(omega, t1 + t2)
    scale = max(1.0, np.linalg.norm(omega) * (abs(t1) + abs(t2)))
    assert np.abs(lhs - rhs).max() <= 16 * EPS * scale


@given(omega=ANY, tau=st.floats(-10, 10))
def test_inverse_is_transpose_and_reversed_time(omega, tau):
    """R(omega, tau)^T == R(omega, -tau) == R(-omega, tau) (spec S9)."""
    R = so3lib.exp(omega, tau)
    assert np.array_equal(R.T, so3lib.exp(omega, -tau))
    assert np.array_equal(so3lib.exp(-omega, tau), so3lib.exp(omega, -tau))


@given(omega=ANY, tau=st.floats(-10, 10).filter(lambda t: abs(t) >= 1e-300))
def test_log_with_time_is_angular_velocity(omega, tau):
    """exp(log(R, tau), tau) == R for every tau != 0 (down to 1e-300: below 2e-308,
    Log(R)/tau can overflow, and log refuses it; test_bad_input.py)."""
    R = so3lib.exp(omega)
    assert np.abs(so3lib.exp(so3lib.log(R, tau), tau) - R).max() <= 8 * EPS


@given(a=arrays(np.float64, 3, elements=st.floats(-1e3, 1e3)),
       b=arrays(np.float64, 3, elements=st.floats(-1e3, 1e3)))
def test_hat_is_cross_product(a, b):
    assert np.allclose(so3lib.hat(a) @ b, np.cross(a, b), rtol=1e-14, atol=1e-9)
    assert np.array_equal(so3lib.vee(so3lib.hat(a)), a)
    assert np.array_equal(so3lib.hat(a).T, -so3lib.hat(a))


@given(seed=SEEDS, a=arrays(np.float64, 3, elements=st.floats(-10, 10)))
def test_hat_is_equivariant(seed, a):
    """hat(R a) == R hat(a) R^T (spec S1)."""
    R = so3lib.random_rotation(seed)
    assert np.allclose(so3lib.hat(R @ a), R @ so3lib.hat(a) @ R.T, rtol=0, atol=1e-13 * max(1, np.abs(a).max()))


@pytest.mark.parametrize("shape", BATCHES)
@given(seed=SEEDS)
def test_batched_call_equals_single_calls(seed, shape):
    rng = np.random.default_rng(seed)
    phis = rng.standard_normal(shape + (3,)) * 2
    R = so3lib.exp(phis)
    L = so3lib.log(R)
    for idx in np.ndindex(*shape):
        assert np.array_equal(R[idx], so3lib.exp(phis[idx]))
        assert np.array_equal(L[idx], so3lib.log(R[idx]))


def test_exp_broadcasts_times_against_omegas():
    """One omega and an array of times gives the rotations along its path."""
    taus = np.linspace(0, 2, 5)
    R = so3lib.exp([0.0, 0.0, 1.0], taus)
    assert R.shape == (5, 3, 3)
    assert np.array_equal(R[3], so3lib.exp([0.0, 0.0, 1.0], taus[3]))
    assert so3lib.exp(np.ones((4, 1, 3)), np.ones(2)).shape == (4, 2, 3, 3)
    assert so3lib.log(R, taus[1:2]).shape == (5, 3)
