"""The hat map, the Lemma, angle, is_rotation and uniform sampling (spec S1 to S5, S8, S12, S13)."""

import math

import numpy as np
import sympy as sp

import so3lib
from conftest import EPS
from reference import exp_ref


def test_hat_of_example_vector():
    a, b = np.array([1.0, 2.0, 3.0]), np.array([4.0, 5.0, 6.0])
    assert np.array_equal(so3lib.hat(a) @ b, [-3.0, 6.0, -3.0])
    assert np.array_equal(so3lib.hat(a) @ a, np.zeros(3))


def test_lemma_exactly_on_integers():
    """hat(a)^2 = a a^T - |a|^2 I, hat(a)^3 = -|a|^2 hat(a), and all powers (S2 to S4)."""
    a = np.array([1.0, 2.0, 3.0])
    H = so3lib.hat(a)
    assert np.array_equal(H @ H, np.outer(a, a) - 14 * np.eye(3))
    assert np.array_equal(H @ H @ H, -14 * H)
    P = np.eye(3)
    for p in range(1, 13):
        P = P @ H
        k = (p - 1) // 2
        assert np.array_equal(P, (-1) ** k * 14 ** k * (H if p % 2 else H @ H))


def test_lemma_symbolically():
    a = sp.Matrix(sp.symbols("a1 a2 a3", real=True))
    H = sp.Matrix([[0, -a[2], a[1]], [a[2], 0, -a[0]], [-a[1], a[0], 0]])
    n2 = (a.T * a)[0]
    assert sp.simplify(H ** 2 - (a * a.T - n2 * sp.eye(3))) == sp.zeros(3)
    assert sp.simplify(H ** 3 + n2 * H) == sp.zeros(3)
    assert sp.simplify((H ** 2).trace() + 2 * n2) == 0


def test_spectrum_of_hat():
    ev = sorted(np.linalg.eigvals(so3lib.hat([1.0, 2.0, 3.0])), key=lambda z: z.imag)
    assert np.allclose(ev, [-1j * math.sqrt(14), 0, 1j * math.sqrt(14)], atol=1e-14)


def test_exp_is_rotation_about_its_axis_by_its_angle():
    """R n = n and R x = cos x + sin (n x x) for x perpendicular to n (spec S8)."""
    w = np.array([0.2, -0.7, 0.4])
    R, th, n = so3lib.exp(w), np.linalg.norm(w), w / np.linalg.norm(w)
    assert np.abs(R @ n - n).max() <= 2 * EPS
    x = np.cross(n, [1.0, 0.0, 0.0])
    x /= np.linalg.norm(x)
    assert np.allclose(R @ x, math.cos(th) * x + math.sin(th) * np.cross(n, x), rtol=0, atol=4 * EPS)
    assert abs(so3lib.angle(R) - th) <= 2 * EPS


def test_trace_and_skew_identities():
    """tr R = 1 + 2 cos theta and vee(R - R^T) = 2 sin theta n (spec S12, S13)."""
    w = np.array([0.4, 1.1, -0.8])
    R, th, n = exp_ref(w), np.linalg.norm(w), w / np.linalg.norm(w)
    assert abs(np.trace(R) - (1 + 2 * math.cos(th))) <= 4 * EPS
    assert np.abs(so3lib.vee(R - R.T) - 2 * math.sin(th) * n).max() <= 4 * EPS


def test_angle_range_and_batch(rng):
    R = so3lib.random_rotation(rng, (50,))
    th = so3lib.angle(R)
    assert th.shape == (50,) and np.all((th >= 0) & (th <= math.pi))
    assert np.allclose(th, np.linalg.norm(so3lib.log(R), axis=-1), rtol=0, atol=4 * EPS)
    assert so3lib.angle(np.diag([1.0, -1.0, -1.0])) == math.pi
    assert so3lib.angle(np.eye(3)) == 0.0


def test_random_rotation_shapes_and_seeding():
    assert so3lib.random_rotation(0).shape == (3, 3)
    assert so3lib.random_rotation(0, 5).shape == (5, 3, 3)
    assert so3lib.random_rotation(0, (3, 1, 2)).shape == (3, 1, 2, 3, 3)
    assert so3lib.random_rotation(0, 0).shape == (0, 3, 3)
    assert np.array_equal(so3lib.random_rotation(7, 4), so3lib.random_rotation(np.random.default_rng(7), 4))
    assert so3lib.is_rotation(so3lib.random_rotation(1, 1000), tol=8 * EPS).all()


def test_random_rotation_is_uniform():
    """Haar measure: the angle has CDF (theta - sin theta)/pi, and R e_z is uniform on S^2."""
    from scipy import stats   # here, not at the top: importing scipy.stats takes a second
    R = so3lib.random_rotation(np.random.default_rng(12345), 20000)
    th = so3lib.angle(R)
    assert stats.kstest(th, lambda t: (t - np.sin(t)) / np.pi).pvalue > 0.01
    z = R[:, 2, 2]                               # (R e_z)_z is uniform on [-1, 1]
    assert stats.kstest(z, stats.uniform(loc=-1, scale=2).cdf).pvalue > 0.01
    assert np.abs(R.mean(axis=0)).max() < 0.03   # E[R] = 0 under the Haar measure
