"""Claims of notebooks 00 and 01 whose checks left the notebooks' text (issue 21: a notebook
shows the numbers that teach; the tests prove the rest). Each test names the cell it came
from; the references are independent of so3lib's code paths: NumPy's cross product,
sympy, and 50-digit mpmath."""

import math

import mpmath as mp
import numpy as np
import pytest
import sympy as sp

import so3lib
from conftest import EPS
from reference import exp_ref

A = np.array([1.0, 2.0, 3.0])


# --- notebook 00 ---------------------------------------------------------------------

def test_00_setup_check_asks_for_the_python_the_makefile_needs():
    """00, "Before you start" (the set-up check) and "Where to run it": the Python they ask
    for is the Makefile's minimum, 3.11.5 (Debian 12's 3.11.2 says no, not yes)."""
    import json
    import re
    from pathlib import Path
    root = Path(__file__).resolve().parents[1]
    need = re.search(r"sys\.version_info >= \((3, 11, \d+)\)", (root / "Makefile").read_text())
    assert need, "the Makefile's version check moved"
    cells = json.loads((root / "notebooks" / "00_start_here.ipynb").read_text())["cells"]
    text = "\n".join("".join(c["source"]) for c in cells)
    assert f"sys.version_info >= ({need.group(1)})" in text
    version = need.group(1).replace(", ", ".")
    assert f"Python {version} or newer" in text and "Python 3.11 or newer" not in text


def test_00_sin_of_float_pi_is_about_1_2e_16():
    """00, "so3lib.log at the same two rotations" (the print of the recipe's two factors):
    sin(fl(pi)) is pi - fl(pi), about 1.2e-16, not 0."""
    with mp.workdps(50):
        gap = float(mp.pi - mp.mpf(math.pi))
    assert 1.2e-16 < np.sin(np.pi) < 1.25e-16
    assert abs(np.sin(np.pi) - gap) <= EPS * gap
    half_turn = np.diag([1.0, -1.0, -1.0])
    assert not (half_turn - half_turn.T).any()


def test_00_recipe_factor_jumps_once_arccos_returns_float_pi():
    """00, the figure of the recipe's two factors near pi: once pi - t is 1e-8 or less,
    arccos((tr R - 1)/2) is fl(pi) and theta / (2 sin theta) is about 1.3e16, while it
    follows t / (2 sin t) (exact, 50 digits) above: to 1e-6 relative down to 1e-5, to 1 %
    at 1e-7 (arccos has lost half the digits there)."""
    def factor(t):
        c = np.cos(t)
        th = np.arccos((1.0 + c + c - 1) / 2)
        return th, th / (2 * np.sin(th))

    for gap in (1e-9, 3e-9, 1e-10, 1e-12):
        th, f = factor(np.pi - gap)
        assert th == np.pi and 1.2e16 < f < 1.4e16
    for gap, tol in ((1e-1, 1e-6), (1e-3, 1e-6), (1e-5, 1e-6), (1e-7, 1e-2)):
        t = np.pi - gap
        with mp.workdps(50):
            exact = float(mp.mpf(t) / (2 * mp.sin(mp.mpf(t))))
        assert abs(factor(t)[1] - exact) <= tol * exact



def test_00_recipe_near_pi_loses_up_to_eps_over_4_sin_squared():
    """00, under the figure "Why it fails near a half-turn": near pi the recipe's relative
    error reaches about eps / (4 sin^2 t) and stays under twice that (the dashed line of the
    last figure): about 6e-9 at pi - t = 1e-4, half the digits. The reference is t itself,
    against which the rotation is written out entry by entry."""
    def recipe_x(t):
        c, s = np.cos(t), np.sin(t)
        th = np.arccos((1.0 + c + c - 1) / 2)
        return th / (2 * np.sin(th)) * (s - (-s))

    for gap in (1e-2, 1e-3, 1e-4, 1e-5, 1e-6, 1e-7):
        ts = np.pi - np.linspace(0.9 * gap, 1.1 * gap, 101)
        worst = max(abs(recipe_x(t) - t) / t / (EPS / (4 * np.sin(t) ** 2)) for t in ts)
        assert 0.5 < worst < 2
    ts = np.pi - np.linspace(0.9e-4, 1.1e-4, 101)
    assert 3e-9 < max(abs(recipe_x(t) - t) / t for t in ts) < 1e-8

def test_00_recipe_factor_relative_change_per_radian_is_about_1_over_sin_near_pi():
    """00, under the figure "Why it fails near a half-turn": f(theta) = theta / (2 sin theta)
    changes near pi by d ln f / d theta, about 1 / sin t (within 1 % once pi - t <= 1e-2);
    and (R - R^T)^vee = 2 sin(theta) n, the skew part's length on the slide of the recipe."""
    with mp.workdps(40):
        for gap in ("1e-2", "1e-4", "1e-8"):
            t = mp.pi - mp.mpf(gap)
            slope = mp.diff(lambda th: mp.log(th / (2 * mp.sin(th))), t)
            assert abs(slope * mp.sin(t) - 1) < 0.01
    th_ = sp.symbols("theta", real=True)
    n = sp.Matrix(sp.symbols("n1:4", real=True))
    N = sp.Matrix([[0, -n[2], n[1]], [n[2], 0, -n[0]], [-n[1], n[0], 0]])
    R = sp.eye(3) + sp.sin(th_) * N + (1 - sp.cos(th_)) * N * N
    S = R - R.T
    assert sp.simplify(sp.Matrix([S[2, 1], S[0, 2], S[1, 0]]) - 2 * sp.sin(th_) * n) == sp.zeros(3, 1)


# --- notebook 01 ---------------------------------------------------------------------

def test_01_hat_times_b_is_the_cross_product_for_random_vectors():
    """01, the interactive velocity field (cell "Turn it"): hat(a) b = a x b, within 2 eps
    of np.cross, for a unit axis and points around it (the notebook drew them)."""
    rng = np.random.default_rng(2101)
    a = rng.standard_normal((200, 3))
    a /= np.linalg.norm(a, axis=1, keepdims=True)
    b = rng.standard_normal((200, 3))
    got = np.einsum("nij,nj->ni", so3lib.hat(a), b)
    assert np.abs(got - np.cross(a, b)).max() <= 2 * EPS * np.abs(b).max()


def test_01_cross_product_turns_with_a_rotation_and_flips_with_a_mirror():
    """01, (1.4) and the mirror: (Ra) x (Rb) = (det R) R (a x b), for 30 rotations and 30
    rotations times a mirror (the scatter the notebook drew), within 16 eps; hat(Ma) =
    -M hat(a) M^T for the 30 with a mirror. The rotations are rounded 50-digit exponentials."""
    rng = np.random.default_rng(1401)
    mirror = np.diag([1.0, 1.0, -1.0])
    for _ in range(30):
        Q = exp_ref(rng.uniform(-3, 3, 3))
        a, b = rng.standard_normal(3), rng.standard_normal(3)
        scale = np.linalg.norm(a) * np.linalg.norm(b)
        for T, sign in ((Q, 1.0), (Q @ mirror, -1.0)):
            assert np.sign(np.linalg.det(T)) == sign
            lhs = np.cross(T @ a, T @ b)
            assert np.abs(lhs - sign * T @ np.cross(a, b)).max() <= 16 * EPS * scale
            H = so3lib.hat(a)
            assert np.abs(so3lib.hat(T @ a) - sign * T @ H @ T.T).max() <= 16 * EPS * np.abs(a).max()


def test_01_projector_of_the_lemma():
    """01, "What hat(a)^2 does": P = I - n n^T is a projector (P P = P), and hat(a)^2 x =
    -|a|^2 x for x orthogonal to a, within 8 eps (relative to |a|^2 |x|)."""
    n = A / np.linalg.norm(A)
    P = np.eye(3) - np.outer(n, n)
    assert np.abs(P @ P - P).max() <= 8 * EPS
    H = so3lib.hat(A)
    x = np.cross(A, [1.0, 0.0, 0.0])
    assert np.abs(H @ H @ x - -(A @ A) * x).max() <= 8 * EPS * (A @ A) * np.abs(x).max()


def test_01_unit_axis_square_plus_identity_is_n_n_transpose():
    """01, "Two directions, alternating signs": hat(n)^2 + I = n n^T (so hat(n)^2 is not
    -I), within 8 eps; its largest entry is 9/14 (the notebook prints 0.64)."""
    n = A / np.linalg.norm(A)
    N = so3lib.hat(n)
    assert np.abs(N @ N + np.eye(3) - np.outer(n, n)).max() <= 8 * EPS
    assert abs(np.abs(N @ N + np.eye(3)).max() - 9 / 14) <= 8 * EPS


def test_01_power_law_symbolically_for_k_up_to_5():
    """01, (1.7) and (1.8) for k = 0..5 (the notebook's sympy cell prints the same)."""
    a = sp.Matrix(sp.symbols("a1 a2 a3", real=True))
    H = sp.Matrix([[0, -a[2], a[1]], [a[2], 0, -a[0]], [-a[1], a[0], 0]])
    n2 = (a.T * a)[0]
    for k in range(6):
        c = (-1) ** k * n2 ** k
        assert sp.expand(H ** (2 * k + 1) - c * H) == sp.zeros(3)
        assert sp.expand(H ** (2 * k + 2) - c * H ** 2) == sp.zeros(3)


def test_01_eigenvalues_of_hat():
    """01, (1.10): the eigenvalues of hat((1, 2, 3)) are 0 and +-i sqrt(14), within 16 eps
    of 50-digit sqrt(14)."""
    with mp.workdps(50):
        r14 = float(mp.sqrt(14))
    ev = np.array(sorted(np.linalg.eigvals(so3lib.hat(A)), key=lambda z: z.imag))
    assert np.abs(ev - np.array([-1j * r14, 0, 1j * r14])).max() <= 16 * EPS * r14


@pytest.mark.parametrize("tau, fit, coef", [(0.0, 32, 16), (0.7, 32, 16), (1.5, 32, 16),
                                            (2.4, 32, 16), (4.0, 64, 64), (4.83, 256, 256)])
def test_01_fitted_series_coefficients_are_1_sin_and_1_minus_cos(tau, fit, coef):
    """01, "A numerical preview" and "A peek ahead": the 40-term partial sum of the series
    of exp(tau hat(omega)) fitted as c0 I + alpha hat(omega) + beta hat(omega)^2 by least
    squares gives c0 = 1, alpha = sin(theta)/|omega|, beta = (1 - cos theta)/|omega|^2
    (theta = |omega| tau, 50-digit mpmath), within 16 eps (the notebook reports c0 = 1
    within 16 eps from 25 terms at tau = 0.7), and leaves a misfit within 32 eps of the sum,
    up to theta = pi; over the rest of the whole turn the notebook draws, whose
    terms reach 85, within 64 eps at theta = 5.2 and 256 eps at 2 pi."""
    omega = np.array([0.3, -0.4, 1.2])
    W = so3lib.hat(omega)
    basis = np.stack([np.eye(3).ravel(), W.ravel(), (W @ W).ravel()], axis=1)
    S = sum(np.linalg.matrix_power(tau * W, m) / math.factorial(m) for m in range(40))
    coeffs = np.linalg.lstsq(basis, S.ravel(), rcond=None)[0]
    assert np.abs(basis @ coeffs - S.ravel()).max() <= fit * EPS
    with mp.workdps(50):
        w = mp.sqrt(sum(mp.mpf(float(x)) ** 2 for x in omega))
        th = w * mp.mpf(tau)
        alpha, beta = float(mp.sin(th) / w), float((1 - mp.cos(th)) / w ** 2)
    assert np.abs(coeffs - [1.0, alpha, beta]).max() <= coef * EPS
