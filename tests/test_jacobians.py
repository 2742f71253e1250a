"""The Jacobians of exp against 50-digit references, and their defining properties.

Tolerances, in the manner of ``tests/test_accuracy.py``: entrywise, relative to
``max(1, largest entry)`` of the reference,

* forward Jacobians: ``8 eps * max(1, theta)`` at every angle of the hard-case table
  (0 and subnormals up to 1e6);
* inverses (``theta < 2 pi``): the same times the conditioning ``max(1, 2 pi/(2 pi -
  theta))``, documented in ``right_jacobian_inv``;
* the scalar coefficients ``C`` and ``D``: ``4 eps`` relative (``D`` times the same
  conditioning near ``2 pi``).
"""

import math

import mpmath as mp
import numpy as np
import pytest
from cases import PI, hard_cases
from conftest import EPS
from hypothesis import given
from hypothesis import strategies as st
from reference_jacobians import (
    coefficients_ref,
    jacobian_by_differences,
    jacobian_inverse_by_mpmath,
    jacobian_ref,
    jacobian_series_ref,
)

import so3lib
from so3lib import (
    C,
    D,
    exp,
    hat,
    left_jacobian,
    left_jacobian_inv,
    log,
    ominus,
    oplus,
    right_jacobian,
    right_jacobian_inv,
)

TWO_PI = 2 * PI
CASES = hard_cases()
IDS = [label for label, _ in CASES]
INV_CASES = [(label, phi) for label, phi in CASES if np.linalg.norm(phi) < TWO_PI]
INV_IDS = [label for label, _ in INV_CASES]


def entry_error(J, J_ref):
    """max |J - J_ref| in units of eps * max(1, max |J_ref|)."""
    assert not np.isnan(J).any()
    return np.abs(J - J_ref).max() / (EPS * max(1.0, np.abs(J_ref).max()))


def conditioning(theta):
    return max(1.0, TWO_PI / (TWO_PI - theta)) if theta < TWO_PI else math.inf


# --- accuracy -----------------------------------------------------------------------------

@pytest.mark.parametrize("side, func", [("right", right_jacobian), ("left", left_jacobian)])
@pytest.mark.parametrize("phi", [c for _, c in CASES], ids=IDS)
def test_forward_jacobian_matches_reference(phi, side, func):
    theta = float(np.linalg.norm(phi))
    err = entry_error(func(phi), jacobian_ref(phi, side))
    assert err <= 8 * max(1.0, theta), f"error {err:.1f} eps at theta = {theta!r}"


@pytest.mark.parametrize("side, func", [("right", right_jacobian_inv),
                                        ("left", left_jacobian_inv)])
@pytest.mark.parametrize("phi", [c for _, c in INV_CASES], ids=INV_IDS)
def test_inverse_jacobian_matches_reference(phi, side, func):
    theta = float(np.linalg.norm(phi))
    err = entry_error(func(phi), jacobian_ref(phi, side, inverse=True))
    bound = 8 * max(1.0, theta) * conditioning(theta)
    assert err <= bound, f"error {err:.1f} eps at theta = {theta!r}"


def test_random_rotation_vectors_match_reference(rng):
    """300 random axes, angles log-uniform from 1e-12 to 1e3 (forward) and uniform in
    [0, 2 pi) (inverses): the same bounds as on the hard cases."""
    for _ in range(300):
        n = rng.standard_normal(3)
        n /= np.linalg.norm(n)
        phi = 10 ** rng.uniform(-12, 3) * n
        theta = float(np.linalg.norm(phi))
        assert entry_error(right_jacobian(phi), jacobian_ref(phi)) <= 8 * max(1.0, theta)
        phi = rng.uniform(0.0, TWO_PI) * n
        theta = float(np.linalg.norm(phi))
        if theta < TWO_PI:
            err = entry_error(right_jacobian_inv(phi), jacobian_ref(phi, inverse=True))
            assert err <= 8 * max(1.0, theta) * conditioning(theta), (theta, err)


@pytest.mark.parametrize("d", [1e-1, 1e-3, 1e-6, 1e-9, 1e-12])
def test_inverse_near_two_pi_is_within_its_conditioning(d):
    n = np.array([1.0, 2.0, 3.0]) / math.sqrt(14.0)
    phi = (TWO_PI - d) * n
    theta = float(np.linalg.norm(phi))
    J_inv = right_jacobian_inv(phi)
    err = entry_error(J_inv, jacobian_ref(phi, "right", inverse=True))
    assert err <= 8 * theta * conditioning(theta)
    # and it grows like 2 / (2 pi - theta), the reciprocal of the small singular value
    # (with the exact angle of phi: rounding |phi| itself moves 2 pi - theta by ~eps)
    with mp.workdps(50):
        half = mp.sqrt(sum(mp.mpf(float(x)) ** 2 for x in phi)) / 2
        largest = float(half / abs(mp.sin(half)))
    s = np.linalg.svd(J_inv, compute_uv=False)
    assert math.isclose(s.max(), largest, rel_tol=1e-6 + 8 * EPS * conditioning(theta))


GRID = np.concatenate([[0.0, 5e-324, 1e-310, 1e-200, 1e-16, 1e-8],
                       np.logspace(-6, 0.79, 60), [1.0, math.nextafter(2.0, 0), 2.0, 2.5,
                                                   PI - 1e-4, PI - 1e-8, PI, PI + 1e-8,
                                                   4.0, 6.0, TWO_PI - 1e-6]])


@pytest.mark.parametrize("t", GRID)
def test_coefficients_match_reference(t):
    ref = coefficients_ref(t)
    c, d = float(C(t)), float(D(t))
    assert abs(c - ref["C"]) <= 4 * EPS * ref["C"], (t, (c - ref["C"]) / (EPS * ref["C"]))
    bound = 4 * EPS * ref["D"] * conditioning(t)
    assert abs(d - ref["D"]) <= bound, (t, (d - ref["D"]) / (EPS * ref["D"]))


def test_coefficients_large_and_negative_angles():
    for t in (10.0, 100.0, 1e6, 1e200):
        assert abs(float(C(t)) - coefficients_ref(t)["C"]) <= 8 * EPS * coefficients_ref(t)["C"]
    assert np.array_equal(C([-0.5, 0.5]), C([0.5, 0.5]))
    assert np.array_equal(D([-3.0]), D([3.0]))
    assert C(0.25).shape == () and D([[0.1, 0.2]]).shape == (1, 2)


def test_written_forms_do_cancel():
    """Why C and D are not computed as written: at t = 1e-5 and near pi."""
    t = 1e-5
    naive_c = (t - math.sin(t)) / t**3
    assert abs(naive_c - coefficients_ref(t)["C"]) > 1e-8
    t = PI - 1e-7
    naive_d = 1 / t**2 - (1 + math.cos(t)) / (2 * t * math.sin(t))
    assert abs(naive_d - coefficients_ref(t)["D"]) > 1e4 * EPS * coefficients_ref(t)["D"]
    assert abs(float(D(t)) - coefficients_ref(t)["D"]) <= 2 * EPS * coefficients_ref(t)["D"]


# --- the references themselves ----------------------------------------------------------

@pytest.mark.parametrize("phi", [[0.3, -0.4, 1.2], [1e-3, 2e-3, -5e-4], [2.0, -1.0, 2.0],
                                 [0.0, 0.0, 3.1], [4.0, 3.0, 1.0]])
def test_reference_closed_form_equals_series_and_mpmath_inverse(phi):
    for side in ("right", "left"):
        assert entry_error(jacobian_ref(phi, side), jacobian_series_ref(phi, side)) <= 1
        assert entry_error(jacobian_ref(phi, side, inverse=True),
                           jacobian_inverse_by_mpmath(phi, side)) <= 1


@pytest.mark.parametrize("phi", [[0.3, -0.4, 1.2], [0.0, 2.5, 0.0], [1.0, 2.0, 2.0]])
def test_reference_equals_high_precision_differences(phi):
    assert entry_error(jacobian_ref(phi), jacobian_by_differences(phi)) <= 1


# --- properties ---------------------------------------------------------------------------

angles = st.one_of(st.floats(0.0, 1e-6), st.floats(1e-6, 3.0), st.floats(3.0, 3.2),
                   st.floats(3.2, 6.2))
axes = st.tuples(*[st.floats(-1.0, 1.0)] * 3).filter(lambda v: np.linalg.norm(v) > 0.1)


def _phi(theta, axis):
    axis = np.asarray(axis)
    return theta * axis / np.linalg.norm(axis)


@given(angles, axes)
def test_left_is_right_of_minus_phi_and_transpose(theta, axis):
    phi = _phi(theta, axis)
    Jr, Jl = right_jacobian(phi), left_jacobian(phi)
    assert np.abs(Jl - right_jacobian(-phi)).max() <= 2 * EPS
    assert np.abs(Jl - Jr.T).max() <= 2 * EPS
    assert np.abs(left_jacobian_inv(phi) - right_jacobian_inv(phi).T).max() <= \
        2 * EPS * max(1.0, np.abs(right_jacobian_inv(phi)).max())


@given(angles, axes)
def test_jacobian_times_inverse_is_identity(theta, axis):
    phi = _phi(theta, axis)
    for J, Jinv in ((right_jacobian(phi), right_jacobian_inv(phi)),
                    (left_jacobian(phi), left_jacobian_inv(phi))):
        scale = np.abs(Jinv).max()
        assert np.abs(J @ Jinv - np.eye(3)).max() <= 16 * EPS * scale
        assert np.abs(Jinv @ J - np.eye(3)).max() <= 16 * EPS * scale


@given(angles, axes)
def test_singular_values_are_one_and_sinc_half(theta, axis):
    """(6.10) of notebook 06: 1 along the axis, |sin(theta/2)/(theta/2)| twice across it."""
    phi = _phi(theta, axis)
    half = theta / 2
    small = abs(math.sin(half) / half) if theta > 0 else 1.0
    # mpmath's SVD of the float matrix: LAPACK's loses ~10 eps on a matrix this near I
    with mp.workdps(30):
        s = sorted(float(x) for x in mp.svd_r(mp.matrix(right_jacobian(phi).tolist()),
                                               compute_uv=False))
    assert np.allclose(s, np.sort([1.0, small, small]), rtol=0, atol=4 * EPS)
    if theta > 0:
        n = phi / theta
        assert np.allclose(right_jacobian(phi) @ n, n, atol=4 * EPS)


@pytest.mark.parametrize("theta", [1e-3, 0.5, 2.0, 3.1, PI, 4.5])
def test_first_order_expansion_of_exp(theta, rng):
    """exp(phi + delta) = exp(phi) exp(J_r delta) + O(|delta|^2), and on the left."""
    phi = _phi(theta, rng.standard_normal(3))
    direction = rng.standard_normal(3)
    ratios = []
    for h in (1e-2, 1e-3, 1e-4):
        delta = h * direction
        R = exp(phi + delta)
        right = np.abs(R - exp(phi) @ exp(right_jacobian(phi) @ delta)).max()
        left = np.abs(R - exp(left_jacobian(phi) @ delta) @ exp(phi)).max()
        plain = np.abs(R - exp(phi) @ exp(delta)).max()
        ratios.append(max(right, left) / h**2)
        assert max(right, left) < 0.1 * plain or theta < 1e-2
    assert max(ratios) < 5 * np.linalg.norm(direction) ** 2
    assert ratios[-1] <= 1.5 * ratios[0]       # second order: the ratio stays put


@pytest.mark.parametrize("theta", [1e-3, 0.5, 2.0, 3.0])
def test_first_order_expansion_of_log(theta, rng):
    """Log(exp(phi) exp(delta)) = phi + J_r^-1(phi) delta + O(|delta|^2)."""
    phi = _phi(theta, rng.standard_normal(3))
    delta = 1e-5 * rng.standard_normal(3)
    got = log(exp(phi) @ exp(delta))
    assert np.abs(got - (phi + right_jacobian_inv(phi) @ delta)).max() <= 1e-9
    got = log(exp(delta) @ exp(phi))
    assert np.abs(got - (phi + left_jacobian_inv(phi) @ delta)).max() <= 1e-9


@pytest.mark.parametrize("shape", [(), (1,), (4,), (3, 1, 2, 1)])
@pytest.mark.parametrize("func", [right_jacobian, left_jacobian, right_jacobian_inv,
                                  left_jacobian_inv])
def test_batches_equal_one_at_a_time(shape, func, rng):
    phi = rng.uniform(-2.0, 2.0, shape + (3,))
    J = func(phi)
    assert J.shape == shape + (3, 3) and J.dtype == np.float64
    flat = phi.reshape(-1, 3)
    one = np.array([func(p) for p in flat]).reshape(shape + (3, 3))
    assert np.array_equal(J, one)


def test_empty_batch_and_lists():
    assert right_jacobian(np.zeros((0, 3))).shape == (0, 3, 3)
    assert np.array_equal(right_jacobian([0, 0, 0]), np.eye(3))
    assert np.array_equal(right_jacobian_inv([0.0, -0.0, 0.0]), np.eye(3))
    assert right_jacobian([1, 2, 3]).dtype == np.float64


def test_huge_and_tiny_angles_are_finite():
    for phi in ([1e300, 1e300, 0.0], [5e-324, 0.0, 0.0], [1e-160, 1e-160, 1e-160]):
        for func in (right_jacobian, left_jacobian):
            assert np.isfinite(func(phi)).all()
    J = right_jacobian([0, 0, 1e200])            # -> I - 0 n^ + 1 n^2 = diag(0, 0, 1)
    assert np.allclose(J, np.diag([0.0, 0.0, 1.0]), atol=1e-199)


def test_hat_and_series_agree_at_a_moderate_angle():
    phi = np.array([0.3, -0.4, 1.2])
    K = hat(phi)
    series = sum(np.linalg.matrix_power(-K, k) / math.factorial(k + 1) for k in range(30))
    assert np.abs(right_jacobian(phi) - series).max() <= 4 * EPS


# --- bad input ----------------------------------------------------------------------------

@pytest.mark.parametrize("func", [right_jacobian, left_jacobian, right_jacobian_inv,
                                  left_jacobian_inv])
@pytest.mark.parametrize("bad, says", [
    ([1.0, 2.0], r"shape \(\.\.\., 3\)"),
    (np.zeros((3, 3, 2)), r"shape \(\.\.\., 3\)"),
    ([1.0, np.nan, 0.0], "NaN"),
    ([np.inf, 0.0, 0.0], "infinite"),
    ([1j, 0, 0], "complex"),
    (["a", "b", "c"], "real numbers"),
    ([True, False, True], "booleans"),
    ([[1.0, 2.0, 3.0], [1.0, 2.0]], "could not read"),
    ([1.5e308, 1.5e308, 0.0], "overflows"),
])
def test_bad_input_raises_value_error(func, bad, says):
    with pytest.raises(ValueError, match=says):
        func(bad)


@pytest.mark.parametrize("func", [right_jacobian_inv, left_jacobian_inv])
@pytest.mark.parametrize("theta", [TWO_PI, 7.0, 100.0])
def test_inverse_refuses_two_pi_and_beyond(func, theta):
    with pytest.raises(ValueError, match=r"\|phi\| < 2 pi"):
        func([0.0, theta, 0.0])
    with pytest.raises(ValueError, match=r"at index \[1\]"):
        func([[0.0, 1.0, 0.0], [0.0, theta, 0.0]])


def test_inverse_accepts_the_float_below_two_pi():
    J = right_jacobian_inv([0.0, 0.0, math.nextafter(TWO_PI, 0.0)])
    assert np.isfinite(J).all() and np.abs(J).max() > 1e14


@pytest.mark.parametrize("func", [C, D])
@pytest.mark.parametrize("bad", [np.nan, [1.0, np.inf], "x", 1j])
def test_coefficients_refuse_bad_input(func, bad):
    with pytest.raises(ValueError):
        func(bad)


# --- oplus and ominus ---------------------------------------------------------------------

def test_oplus_ominus_round_trip(rng):
    R0 = so3lib.random_rotation(rng, 5)
    R1 = so3lib.random_rotation(rng, 5)
    d = ominus(R1, R0)
    assert d.shape == (5, 3) and (np.linalg.norm(d, axis=-1) <= PI).all()
    assert np.abs(oplus(R0, d) - R1).max() <= 16 * EPS
    delta = rng.uniform(-1, 1, (5, 3))
    assert np.abs(ominus(oplus(R0, delta), R0) - delta).max() <= 16 * EPS


def test_oplus_broadcasts_and_matches_definition(rng):
    R = so3lib.random_rotation(rng)
    deltas = rng.uniform(-1, 1, (4, 3))
    out = oplus(R, deltas)
    assert out.shape == (4, 3, 3)
    assert np.array_equal(out[2], R @ exp(deltas[2]))
    assert ominus(R, so3lib.random_rotation(rng, 4)).shape == (4, 3)


@pytest.mark.parametrize("call, says", [
    (lambda: oplus(2 * np.eye(3), [0, 0, 1]), "rotation matrices"),
    (lambda: oplus(np.eye(3), [0, 1]), r"delta of shape"),
    (lambda: oplus(np.eye(3)[None].repeat(2, 0), np.zeros((3, 3))), "broadcast"),
    (lambda: ominus(np.eye(3), np.diag([1.0, 1.0, -1.0])), "R0"),
    (lambda: ominus(np.eye(2), np.eye(3)), r"R1 of shape"),
    (lambda: ominus(np.eye(3)[None].repeat(2, 0), np.eye(3)[None].repeat(3, 0)),
     "broadcast"),
])
def test_oplus_ominus_bad_input(call, says):
    with pytest.raises(ValueError, match=says):
        call()


def test_mpmath_precision_is_left_alone():
    before = mp.mp.dps
    jacobian_ref([1e-300, 0.0, 0.0])
    assert mp.mp.dps == before
