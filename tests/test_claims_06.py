"""The claims of notebook 06 (derivatives of exp: the Jacobians) whose checks left the
notebook's visible cells: each against an independent reference (50-digit mpmath
differences, the 50-digit written forms of tests/reference_jacobians.py), never so3lib
against itself.

Where the notebook's checks went (the others are proved in tests/test_jacobians.py or in
the notebook's collapsed `verify` cells):

* (6.2) body and space velocity of R(t) = exp(t a) exp(t b) -> ``test_body_and_space_velocity``
* (6.3) ``oplus`` against 50-digit R0 exp(delta) -> ``test_oplus_is_R_exp_delta``
* (6.8) J_l = exp(phi) J_r -> ``test_left_jacobian_is_exp_times_right``
* the accuracy table of section 6 (J_r and J_r^-1 at eight angles) -> ``test_jacobian_table``,
  with 8 eps (not 8 eps per radian: the table's 800 eps at 100 rad was never approached)
* so3lib's C and D on the notebook's grids near 0 and near pi -> ``test_C_D_on_the_grids``
* the written (6.7) loses between 1 % of eps/theta and eps/theta -> ``test_written_jacobian_loses_eps_over_theta``
* (6.13) the residual's Jacobian -> ``test_residual_jacobian``
* section 7 (the rotation mean): the Hessian of 1/2 |Log(R^T R_i)|^2 -> ``test_hessian_of_half_squared_distance``
* (6.18) a gyroscope: d/dt Log R(t) = J_r^-1 omega_b -> ``test_rotation_vector_rate``
* exercise 6.1: float differences of Log miss J_r^-1 by 3e-12 to 2e-11 -> ``test_float_differences_of_log``
"""

import math

import mpmath as mp
import numpy as np
import pytest
from conftest import EPS
from reference_jacobians import coefficients_ref, exp_mp, jacobian_ref

from so3lib import (
    C,
    D,
    exp,
    hat,
    left_jacobian,
    log,
    ominus,
    oplus,
    random_rotation,
    right_jacobian,
    right_jacobian_inv,
)
from so3lib.measure import eps_error

DPS = 50


def _mpv(v):
    return [mp.mpf(float(x)) for x in np.asarray(v, dtype=float).ravel()]


def _f(M):
    return np.array([[float(M[i, j]) for j in range(M.cols)] for i in range(M.rows)])


def _vee(M):
    return [(M[2, 1] - M[1, 2]) / 2, (M[0, 2] - M[2, 0]) / 2, (M[1, 0] - M[0, 1]) / 2]


def _log_mp(M):
    """Log of an mpmath rotation with angle in (0, pi), by atan2 (4.9) and (4.11)."""
    v = _vee(M)
    s = mp.sqrt(sum(x * x for x in v))
    theta = mp.atan2(s, (M[0, 0] + M[1, 1] + M[2, 2] - 1) / 2)
    return [theta / s * x for x in v]


@pytest.mark.parametrize("t0", [0.0, 0.7, 2.0])
def test_body_and_space_velocity(t0):
    """(6.2) for R(t) = exp(t a) exp(t b): w_b = exp(-t b) a + b, w_s = a + exp(t a) b,
    w_s = R w_b, against 50-digit centred differences of the path."""
    a, b = np.array([0.5, 0.0, 0.2]), np.array([0.0, 1.0, -0.3])
    with mp.workdps(DPS):
        h = mp.mpf("1e-20")

        def path(t):
            return exp_mp([t * x for x in _mpv(a)]) * exp_mp([t * x for x in _mpv(b)])
        t = mp.mpf(t0)
        R = path(t)
        dR = (path(t + h) - path(t - h)) / (2 * h)
        w_b = np.array([float(x) for x in _vee(R.T * dR)])
        w_s = np.array([float(x) for x in _vee(dR * R.T)])
        R_f = _f(R)
    assert eps_error(exp(-t0 * b) @ a + b, w_b) <= 4
    assert eps_error(a + exp(t0 * a) @ b, w_s) <= 4
    assert eps_error(R_f @ w_b, w_s) <= 4


def test_oplus_is_R_exp_delta(rng):
    """(6.3): R0 (+) (R1 (-) R0) against R0 exp(delta) in 50 digits, 30 random pairs."""
    for R0, R1 in random_rotation(rng, (30, 2)):
        d = ominus(R1, R0)
        with mp.workdps(DPS):
            ref = _f(mp.matrix(R0.tolist()) * exp_mp(_mpv(d)))
        assert eps_error(oplus(R0, d), ref) <= 8


@pytest.mark.parametrize("phi", [[0.3, -0.4, 1.2], [1e-9, 2e-9, -2e-9], [2.0, -1.0, 2.0],
                                 [4.0, 1.0, -3.0]])
def test_left_jacobian_is_exp_times_right(phi):
    """(6.8): J_l = exp(phi) J_r (the small rotation moved across exp(phi) by (1.4))."""
    phi = np.array(phi)
    ref = jacobian_ref(phi, "left")
    assert eps_error(exp(phi) @ right_jacobian(phi), ref) <= 8
    assert eps_error(left_jacobian(phi), ref) <= 8


@pytest.mark.parametrize("theta", [1e-40, 1e-8, 1e-3, 1.0, math.pi - 1e-8, math.pi, 5.0, 100.0])
def test_jacobian_table(theta):
    """The table that was section 6's cell: J_r within 8 eps (of max(1, max |J|)) of the
    written form at 120 digits, and J_r^-1 within 8 eps times its conditioning."""
    phi = theta * np.array([1.0, 2.0, 3.0]) / math.sqrt(14)
    assert eps_error(right_jacobian(phi), jacobian_ref(phi)) <= 8
    if theta < 2 * math.pi:
        cond = max(1.0, 2 * math.pi / (2 * math.pi - theta))
        assert eps_error(right_jacobian_inv(phi), jacobian_ref(phi, inverse=True)) <= 8 * cond


def test_C_D_on_the_grids():
    """so3lib's C and D within 4 eps relative on the notebook's grids: 120 angles from 1e-8
    to 2, and 120 from pi - 0.5 to pi - 1e-10 (the written forms' figure)."""
    small = np.logspace(-8, 0.3, 120)
    near_pi = np.pi - np.logspace(-10, -0.3, 120)
    for t in small:
        ref = coefficients_ref(t)
        assert abs(float(C(t)) - ref["C"]) <= 4 * EPS * ref["C"], t
        assert abs(float(D(t)) - ref["D"]) <= 4 * EPS * ref["D"], t
    for t in near_pi:
        ref = coefficients_ref(t)
        assert abs(float(D(t)) - ref["D"]) <= 4 * EPS * ref["D"], t


@pytest.mark.parametrize("theta", [1e-7, 1e-5, 1e-3])
def test_written_jacobian_loses_eps_over_theta(theta):
    """The written (6.7) in floats is off by between 1 % of eps/theta and eps/theta (34 to
    69 times below eps/theta where cos is correctly rounded, 1 to 3 times where it is an ulp
    off): the loss grows like 1/theta, as section 6 says."""
    p = theta * np.array([1.0, 2.0, 3.0]) / math.sqrt(14)
    K = hat(p)
    written = (np.eye(3) - (1 - np.cos(theta)) / theta**2 * K
               + (theta - np.sin(theta)) / theta**3 * K @ K)
    err = eps_error(written, jacobian_ref(p))
    assert 0.01 / theta < err <= 1 / theta, err


@pytest.mark.parametrize("phi", [[0.4, -1.0, 2.0], [1e-6, 0.0, -2e-6], [2.0, -1.0, 2.2]])
def test_residual_jacobian(phi):
    """(6.13): d(exp(phi) a)/dphi = -exp(phi) hat(a) J_r(phi), against 50-digit differences."""
    phi, a = np.array(phi), np.array([0.7, -1.3, 0.4])
    with mp.workdps(DPS):
        h = mp.mpf("1e-20")
        p, av = _mpv(phi), mp.matrix(_mpv(a))
        cols = []
        for j in range(3):
            e = [h if i == j else 0 for i in range(3)]
            up = exp_mp([x + y for x, y in zip(p, e)])
            down = exp_mp([x - y for x, y in zip(p, e)])
            cols.append([float(x) for x in (up * av - down * av) / (2 * h)])
    fd = np.array(cols).T
    assert eps_error(-exp(phi) @ hat(a) @ right_jacobian(phi), fd) <= 8


@pytest.mark.parametrize("phi", [[0.3, -0.4, 1.2], [0.05, 0.02, -0.01], [1.5, 2.0, -1.0]])
def test_hessian_of_half_squared_distance(phi):
    """Section 8: g(delta) = 1/2 |Log(exp(-delta) exp(phi))|^2 has Hessian at 0 with
    eigenvalue 1 along phi and (theta/2) cot(theta/2) across it, against 50-digit second
    differences."""
    phi = np.array(phi)
    theta = float(np.linalg.norm(phi))
    n = phi / theta
    closed = np.outer(n, n) + (theta / 2) / math.tan(theta / 2) * (np.eye(3) - np.outer(n, n))
    with mp.workdps(DPS):
        h = mp.mpf("1e-12")
        E = exp_mp(_mpv(phi))

        def g(d):
            return sum(x * x for x in _log_mp(exp_mp([-x for x in d]) * E)) / 2
        H = np.zeros((3, 3))
        for i in range(3):
            for j in range(3):
                def step(si, sj, i=i, j=j):
                    return [si * h * (k == i) + sj * h * (k == j) for k in range(3)]
                H[i, j] = float((g(step(1, 1)) - g(step(1, -1)) - g(step(-1, 1))
                                 + g(step(-1, -1))) / (4 * h * h))
    assert np.abs(H - closed).max() <= 1e-12
    assert np.linalg.eigvalsh(closed).max() <= 1 + 1e-15           # below N I per residual


@pytest.mark.parametrize("t0", [0.3, 1.2, 2.4])
def test_rotation_vector_rate(t0):
    """(6.18): for R(t) = exp(t a) exp(t b), the rotation vector phi(t) = Log R(t) has
    d phi/dt = J_r^-1(phi) omega_b with omega_b = exp(-t b) a + b, against 50-digit
    differences of Log R(t)."""
    a, b = np.array([0.5, 0.0, 0.2]), np.array([0.0, 1.0, -0.3])
    with mp.workdps(DPS):
        h = mp.mpf("1e-20")

        def phi_of(t):
            return _log_mp(exp_mp([t * x for x in _mpv(a)]) * exp_mp([t * x for x in _mpv(b)]))
        t = mp.mpf(t0)
        phi = np.array([float(x) for x in phi_of(t)])
        rate = np.array([float((u - d) / (2 * h))
                         for u, d in zip(phi_of(t + h), phi_of(t - h))])
    w_b = exp(-t0 * b) @ a + b
    assert eps_error(right_jacobian_inv(phi) @ w_b, rate) <= 16
    assert np.abs(w_b - rate).max() > 1e-3          # and J_r cannot be left out


@pytest.mark.parametrize("theta, lo, hi", [(1.3, 1e-12, 1e-11), (3.0, 5e-12, 1e-10), (0.01, 0.0, 1e-13)])
def test_float_differences_of_log(theta, lo, hi):
    """Exercise 6.1's solution: centred differences of Log in floats, at the best of 200
    steps h, miss J_r^-1 by about 3e-12 at 1.3 rad and about 1e-11 at 3 rad (so a check
    to 1e-12 needs the closed forms); only near 0 do they get much closer. Bands, not last
    digits: which step wins depends on how sin and cos round."""
    phi = theta * np.array([1.0, 2.0, -2.0]) / 3
    R = exp(phi)
    ref = jacobian_ref(phi, inverse=True)
    best = math.inf
    for h in np.geomspace(1e-8, 1e-2, 200):
        cols = [(log(R @ exp(h * e)) - log(R @ exp(-h * e))) / (2 * h) for e in np.eye(3)]
        best = min(best, np.abs(np.column_stack(cols) - ref).max())
    assert lo < best < hi
