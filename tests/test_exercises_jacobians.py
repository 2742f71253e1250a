"""The checkers of notebook 06 (so3lib.exercises.jacobians): right answers pass, wrong
ones get a message that names the mistake, nothing raises, and no message prints the
expected answer."""

import copy
import math

import numpy as np
import pytest
from checker_support import not_written, says_for

import so3lib.exercises.jacobians as ex
import so3lib
from so3lib import (
    exp,
    hat,
    left_jacobian,
    left_jacobian_inv,
    log,
    ominus,
    right_jacobian,
    right_jacobian_inv,
)
from so3lib.exercises.jacobians import (
    check_body_jacobian,
    check_C_stable,
    check_gauss_newton_step,
    check_ominus_jacobians,
)


def _computed_once(func):
    """FUNC with each result computed once per argument values (compared bit for bit,
    dtype and shape included) and a fresh copy handed back every time."""
    memo = {}

    def once(*args):
        key = tuple((np.asarray(a).dtype.str, np.shape(a), np.asarray(a).tobytes())
                    for a in args)
        if key not in memo:
            memo[key] = func(*args)
        return copy.deepcopy(memo[key])
    return once


@pytest.fixture(autouse=True, scope="module")
def _references_computed_once():
    """The checkers' verdicts -- against 50-digit centred differences of log (6.1, 178
    pairs) and of exp (6.3, 230 cases), and C in 80 digits (6.2) -- are pure functions of
    their arguments (the case and the learner's result), and the right answers below are
    checked many times over: each verdict is computed once, by the checker's own
    function, and later calls with the same result get the same verdict."""
    with pytest.MonkeyPatch.context() as mp:
        for name in ("_judge_61", "_judge_63", "_judge_62"):
            mp.setattr(ex, name, _computed_once(getattr(ex, name)))
        yield


def ominus_jacobians(R1, R0):
    phi = ominus(R1, R0)
    return right_jacobian_inv(phi), -left_jacobian_inv(phi)


def ominus_written(R1, R0):
    """The closed forms (6.9) as written, without so3lib's Jacobians."""
    phi = ominus(R1, R0)
    t, K = np.linalg.norm(phi), hat(phi)
    d = 1 / t**2 - (1 + np.cos(t)) / (2 * t * np.sin(t))
    return np.eye(3) + K / 2 + d * K @ K, -(np.eye(3) - K / 2 + d * K @ K)


def ominus_differences(R1, R0, h=1e-6):
    """Centred differences of log in floats: right to about 1e-10 only."""
    E = np.eye(3)
    j1 = [(log(R0.T @ R1 @ exp(h * e)) - log(R0.T @ R1 @ exp(-h * e))) / (2 * h) for e in E]
    j0 = [(log((R0 @ exp(h * e)).T @ R1) - log((R0 @ exp(-h * e)).T @ R1)) / (2 * h)
          for e in E]
    return np.column_stack(j1), np.column_stack(j0)


def c_stable(t):
    if abs(t) < 0.1:
        t2 = t * t
        return 1 / 6 - t2 / 120 + t2 * t2 / 5040 - t2**3 / 362880
    return (t - math.sin(t)) / t**3


CHECKERS = [(check_ominus_jacobians, "ominus_jacobians"),
            (check_C_stable, "C_stable"),
            (check_body_jacobian, "body_jacobian"),
            (check_gauss_newton_step, "gauss_newton_step")]


@pytest.mark.parametrize("checker, name", CHECKERS)
@pytest.mark.parametrize("answer, pattern", [
    (None, "No answer yet"), (..., "No answer yet"), (3, "Expected a function"),
    (not_written, "Not written yet"), (lambda *a: None, "returned None"),
    (lambda *a: "x", "not a number"), (lambda *a: 1 / 0, "ZeroDivisionError"),
])
def test_common_mistakes(checker, name, answer, pattern):
    says_for(checker(answer), name, pattern)


def test_right_answers_pass():
    assert check_ominus_jacobians(ominus_jacobians)
    assert check_ominus_jacobians(lambda R1, R0: np.stack(ominus_jacobians(R1, R0)))
    assert check_C_stable(c_stable)
    assert check_body_jacobian(lambda phi, b: hat(exp(phi).T @ b) @ right_jacobian(phi))


def so3lib_C(t):
    from so3lib import C
    return C(t)


def _phi(R1, R0):
    return ominus(R1, R0)


@pytest.mark.parametrize("answer, pattern", [
    (lambda R1, R0: ominus_jacobians(R1, R0)[::-1], "swapped"),
    (lambda R1, R0: (right_jacobian_inv(_phi(R1, R0)), left_jacobian_inv(_phi(R1, R0))),
     "J0 has the wrong sign"),
    (lambda R1, R0: (right_jacobian(_phi(R1, R0)), -left_jacobian(_phi(R1, R0))),
     "J1 is J_r.phi., the derivative of exp.*J0 uses a Jacobian of exp"),
    (lambda R1, R0: (left_jacobian_inv(_phi(R1, R0)), -left_jacobian_inv(_phi(R1, R0))),
     "J1 has the perturbation on the wrong side"),
    (lambda R1, R0: (right_jacobian_inv(_phi(R1, R0)), -right_jacobian_inv(_phi(R1, R0))),
     "J0 has the perturbation on the wrong side"),
    (ominus_differences, "finite differences cannot reach"),
    (lambda R1, R0: right_jacobian_inv(_phi(R1, R0)), r"shape \(3, 3\).*pair"),
    (lambda R1, R0: (np.full((3, 3), np.nan),) * 2, "NaN"),
    (lambda R1, R0: (np.eye(3), -np.eye(3)), "J1 and J0 differ"),
])
def test_ominus_jacobians_mistakes(answer, pattern):
    says_for(check_ominus_jacobians(answer), "ominus_jacobians", pattern)


@pytest.mark.parametrize("answer, pattern", [
    (lambda t: float(so3lib_C(t)), "calls so3lib's C"),
    (so3lib.C, "calls so3lib's C"),
    (lambda t: float(so3lib.jacobians.C(t)), "calls so3lib's C"),
    (lambda t: float(getattr(so3lib, "C" + "")(t)), "calls so3lib's C"),  # hidden from a reading
    (lambda t: (float(so3lib.jacobians._horner(so3lib.jacobians._C_SERIES, t * t))
                if abs(t) < 2 else (t - math.sin(t)) / t**3), "calls so3lib's C"),  # its series
    (lambda t: (float(so3lib.jacobians._C_scaled(np.array(abs(t)))) / t**2
                if t else 1 / 6), "calls so3lib's C"),                  # theta^2 C, unscaled
    (lambda t: (t - math.sin(t)) / t**3, "0/0.*Taylor"),
    (lambda t: 1 / 6 if abs(t) < 1e-100 else (t - math.sin(t)) / t**3,
     "Only small t.*cancels"),
    (lambda t: 1 / 6 - t * t / 120, "Only larger t.*series used too far"),
    (lambda t: c_stable(abs(t)) * (1 if t >= 0 else -1), "C is even"),
    (lambda t: 1 / 6 - t * t / 120 if abs(t) < 0.002 else (t - math.sin(t)) / t**3,
     "Only small t.*cancels"),
])
def test_C_stable_mistakes(answer, pattern):
    says_for(check_C_stable(answer), "C_stable", pattern)


@pytest.mark.parametrize("answer, pattern", [
    (lambda p, b: hat(exp(p).T @ b), "J_r.phi. is missing"),
    (lambda p, b: -hat(exp(p).T @ b) @ right_jacobian(p), "off by a sign"),
    (lambda p, b: hat(exp(p).T @ b) @ left_jacobian(p), "uses J_l"),
    (lambda p, b: right_jacobian(p) @ hat(exp(p).T @ b), "wrong order"),
    (lambda p, b: hat(exp(p) @ b) @ right_jacobian(p), "exp.phi.\\^T b .the body"),
    (lambda p, b: np.column_stack([(exp(p + 1e-6 * e).T @ b - exp(p - 1e-6 * e).T @ b) / 2e-6
                                   for e in np.eye(3)]), "finite differences cannot reach"),
])
def test_body_jacobian_mistakes(answer, pattern):
    says_for(check_body_jacobian(answer), "body_jacobian", pattern)


def test_C_stable_series_kept_too_long_is_refused():
    """Four series terms up to 0.3: 1e-11 relative at 0.3, between the old test angles."""
    def late(t):
        if abs(t) < 0.3:
            t2 = t * t
            return 1 / 6 - t2 / 120 + t2 * t2 / 5040 - t2**3 / 362880
        return (t - math.sin(t)) / t**3
    fb = check_C_stable(late)
    assert not fb
    assert "Only larger t" in fb.message and "0.1666" not in fb.message


def test_C_stable_threshold_too_low_is_refused():
    """Two series terms up to 0.002, the written form above: 5.6e-11 relative at 0.0025."""
    def early(t):
        return 1 / 6 - t * t / 120 if abs(t) < 0.002 else (t - math.sin(t)) / t**3
    fb = check_C_stable(early)
    assert not fb
    assert "Only small t" in fb.message and "0.1666" not in fb.message


def _ominus_with_D(D_of):
    """(6.9) with a learner's own coefficient D(t)."""
    def answer(R1, R0):
        phi = ominus(R1, R0)
        t, K = np.linalg.norm(phi), hat(phi)
        d = D_of(t)
        return np.eye(3) + K / 2 + d * K @ K, -(np.eye(3) - K / 2 + d * K @ K)
    return answer


def _D_written(t):
    return 1 / t**2 - (1 + np.cos(t)) / (2 * t * np.sin(t))


@pytest.mark.parametrize("D_of", [
    lambda t: 1 / 12 if t < 1 else _D_written(t),                       # 1e-3 off at 0.9
    lambda t: 1 / 12 + t * t / 720 if t < 1.2 else _D_written(t),
    lambda t: 1 / 12 + t * t / 720 + t**4 / 30240 if t < 0.5 else _D_written(t),
])
def test_ominus_jacobians_D_kept_too_far_is_refused(D_of):
    """A Taylor series of D kept too far is wrong only on a range of turns: the pairs,
    5 % apart, catch it, by name."""
    says_for(check_ominus_jacobians(_ominus_with_D(D_of)), "ominus_jacobians",
             r"along hat\(phi\)\^2.*Taylor series kept too far")


def test_ominus_jacobians_stable_D_of_ones_own_passes():
    def D_own(t):
        if t < 0.5:
            return 1 / 12 + t * t / 720 + t**4 / 30240 + t**6 / 1209600 + t**8 / 47900160
        return (1 - (t / 2) / np.tan(t / 2)) / t**2
    assert check_ominus_jacobians(_ominus_with_D(D_own))


def test_body_jacobian_J_r_with_series_kept_too_far_is_refused():
    """A J_r of one's own with B and C from two and one Taylor terms below 1 rad: wrong by
    1e-8 at 0.03 rad, where the first three cases (0, 1.3 and 3 rad) would not look."""
    def J_r(p):
        t, K = np.linalg.norm(p), hat(p)
        if t < 1.0:
            b, c = 0.5 - t * t / 24, 1 / 6
        else:
            b, c = (1 - np.cos(t)) / t**2, (t - np.sin(t)) / t**3
        return np.eye(3) - b * K + c * K @ K
    says_for(check_body_jacobian(lambda p, b: hat(exp(p).T @ b) @ J_r(p)), "body_jacobian",
             r"(?s)phi = \(0\.01.*Taylor series too far")


def test_messages_never_show_the_expected_value():
    """A wrong answer's message names its own numbers, never the right Jacobians."""
    fb = check_ominus_jacobians(lambda R1, R0: (np.eye(3), -np.eye(3)))
    R0 = exp(np.array([0.4, -0.9, 1.3]))
    R1 = R0 @ exp(np.array([1e-3, 2e-3, -1e-3]))
    for J in ominus_jacobians(R1, R0):
        for digits in (3, 4, 6):
            shown = np.array2string(J, precision=digits, suppress_small=True, separator=", ")
            assert shown not in repr(fb)
    assert "expected" not in repr(fb).lower()
    fb = check_body_jacobian(lambda p, b: hat(exp(p).T @ b))
    assert "expected" not in repr(fb).lower()


def test_module_exposes_no_answer():
    assert sorted(ex.__all__) == ["check_C_stable", "check_body_jacobian",
                                  "check_gauss_newton_step", "check_ominus_jacobians"]
    public = [n for n in dir(ex) if not n.startswith("_") and callable(getattr(ex, n))]
    assert set(public) <= set(ex.__all__) | {"Feedback", "exp", "hat", "never_raises", "math"}


def test_C_stable_reference_is_mpmath_not_the_library():
    """The checker judges against (t - sin t)/t^3 in mpmath, independent of so3lib.C,
    and hands out only the relative error, never C itself."""
    import mpmath as mp
    for t in (1e-300, 1e-30, 1e-8, 0.1, 2.0, math.pi, 100.0, -0.5):
        with mp.workdps(700):                  # 1e-300: t - sin t cancels 600 digits
            x = mp.mpf(abs(t))
            want = float((x - mp.sin(x)) / x**3)
        assert ex._judge_62(t, want)[0] <= 1e-15
        assert 0.5e-11 <= ex._judge_62(t, want * (1 + 1e-11))[0] <= 2e-11
    assert "_C_lib(t)" not in open(ex.__file__).read()


def test_no_helper_hands_out_an_answer():
    """Issue 24: the references of 6.1-6.3 are used inside the checkers' judges, never
    returned (a judge gives a verdict, a size of error and a note)."""
    for name in ("_C_ref", "_fd_ominus", "_fd_body"):
        assert not hasattr(ex, name)
    phi, b = np.array([0.3, -0.4, 1.2]), np.array([1.0, -2.0, 0.5])
    assert ex._judge_63(phi, b, np.zeros((3, 3)))[0] is False
    ok1, ok0, diff, _ = ex._judge_61(phi, np.zeros((3, 3)), np.zeros((3, 3)))
    assert not ok1 and not ok0 and isinstance(diff, float)


def test_ominus_jacobians_written_D_is_refused():
    """(6.9) as written is 0/0 at R1 = R0, and with that branch mended it still loses
    1 + cos theta near a half-turn (7e-9 at pi - 1e-7): both are refused."""
    says_for(check_ominus_jacobians(ominus_written), "ominus_jacobians",
             r"R1 = R0.*NaN.*0/0 in D")
    says_for(check_ominus_jacobians(_ominus_with_D(
        lambda t: 1 / 12 if t == 0 else _D_written(t))), "ominus_jacobians",
        r"3\.14159.*along hat\(phi\)\^2")


@pytest.mark.parametrize("terms, cut", [(8, 1.76), (11, 2.34), (14, 2.98), (2, 0.2)])
def test_ominus_jacobians_D_series_cut_over_grid(terms, cut):
    """Taylor D with `terms` terms below `cut`, (6.11) above: wrong by 1e-11 to 3e-10
    just below `cut`, which the 17 pairs of an earlier version let through."""
    coeffs = so3lib.jacobians._D_SERIES[:terms]

    def D_of(t):
        if t < cut:
            return sum(c * t**(2 * k) for k, c in enumerate(coeffs))
        return (1 - (t / 2) / np.tan(t / 2)) / t**2
    assert not check_ominus_jacobians(_ominus_with_D(D_of))


@pytest.mark.parametrize("cut", [0.002, 0.01, 0.029, 0.1])
def test_body_jacobian_constant_B_C_below_a_cut_is_refused(cut):
    """B = 1/2 and C = 1/6 below `cut`: wrong by about cut/6 there (3e-6 at 0.029, which
    six cases at 0, 0.03, 0.3, ... let through)."""
    def J_r(p):
        t, K = np.linalg.norm(p), hat(p)
        if t < cut:
            b, c = 0.5, 1 / 6
        else:
            b, c = (1 - np.cos(t)) / t**2, (t - np.sin(t)) / t**3
        return np.eye(3) - b * K + c * K @ K
    assert not check_body_jacobian(lambda p, b: hat(exp(p).T @ b) @ J_r(p))


@pytest.mark.parametrize("terms, cut", [(9, 3.0), (10, 3.6), (11, 3.9), (11, 4.4)])
def test_C_stable_series_kept_past_two_is_refused(terms, cut):
    """Taylor C with `terms` terms up to `cut` > 2: wrong by 1.3e-12 to 1.5e-11 above
    2 rad, where the dense grid once stopped."""
    coeffs = [(-1)**k / math.factorial(2 * k + 3) for k in range(terms)]

    def late(t):
        if abs(t) < cut:
            return sum(c * (t * t)**k for k, c in enumerate(coeffs))
        return (t - math.sin(t)) / t**3
    says_for(check_C_stable(late), "C_stable", "Only larger t")


@pytest.mark.parametrize("cut", [0.0, 1e-8])
def test_body_jacobian_written_B_C_mended_only_near_zero_is_refused(cut):
    """The written (6.7) with J_r = I at |phi| <= cut: off by about eps/theta below 1e-6
    (7e-10 at 1e-9, where cos theta rounds to 1), which turns from 1e-4 up let through."""
    def J_r(p):
        t, K = np.linalg.norm(p), hat(p)
        if t <= cut:
            return np.eye(3)
        return np.eye(3) - (1 - np.cos(t)) / t**2 * K + (t - np.sin(t)) / t**3 * K @ K
    says_for(check_body_jacobian(lambda p, b: hat(exp(p).T @ b) @ J_r(p)), "body_jacobian",
             r"(?s)\|phi\| = 1e-09 rad.*not within 1e-12")


def test_ominus_jacobians_theta_squared_underflow_is_refused():
    """(6.11) mended only at theta = 0, with a norm that does not underflow: at a turn of
    3e-200 rad theta^2 is 0 and D is 0/0."""
    def D_of(t):
        return 1 / 12 if t == 0 else (1 - (t / 2) / np.tan(t / 2)) / t**2

    def answer(R1, R0):
        phi = ominus(R1, R0)
        t, K = math.hypot(*phi), hat(phi)
        d = D_of(t)
        return np.eye(3) + K / 2 + d * K @ K, -(np.eye(3) - K / 2 + d * K @ K)
    says_for(check_ominus_jacobians(answer), "ominus_jacobians", r"3e-200.*NaN.*underflows")


def test_C_stable_tiny_t_lost_is_named_and_hint_keeps_the_term_count():
    """30 digits lose t - sin t at 1e-300: named as a small-t loss (not 'larger t'); no
    hint hands over how many series terms a threshold needs."""
    import mpmath as mp

    def few_digits(t):
        if t == 0:
            return 1 / 6
        with mp.workdps(30):
            x = mp.mpf(t)
            return float((x - mp.sin(x)) / x**3)
    fb = check_C_stable(few_digits)
    assert not fb
    assert "Only small t go wrong (below 0.01)" in fb.message
    for answer in (few_digits, lambda t: 1 / 6 - t * t / 120, (lambda t: (t - math.sin(t)) / t**3)):
        assert "362880" not in check_C_stable(answer).message


def test_C_stable_short_series_across_0_01_is_one_fault():
    """Two Taylor terms below 0.1 fail from about 0.0055 to 0.1, on both sides of the
    0.01 that separates 'small' t: named as a truncated series, not 'both small and
    large t'."""
    def short(t):
        t = abs(t)
        return 1 / 6 - t * t / 120 if t < 0.1 else (t - math.sin(t)) / t**3
    fb = check_C_stable(short)
    says_for(fb, "C_stable", "series used too far")
    assert "Both small and large" not in fb.message and "0.1666" not in fb.message


# --- 6.4 capstone: one Gauss-Newton step ---------------------------------------------

def _gn_step(phi, a, b, jacobian=right_jacobian):
    """phi + Delta of (6.14), the residual's Jacobian (6.13) with ``jacobian`` in J_r's place."""
    R = exp(phi)
    r = (a @ R.T - b).ravel()
    J = np.vstack([-R @ hat(x) @ jacobian(phi) for x in a])
    return phi - np.linalg.solve(J.T @ J, J.T @ r)


def _no_jr(phi, a, b):
    return _gn_step(phi, a, b, jacobian=lambda p: np.eye(3))


def _oplus_step(phi, a, b):
    R = exp(phi)
    r = (a @ R.T - b).ravel()
    J = np.vstack([-R @ hat(x) for x in a])
    return log(so3lib.oplus(R, -np.linalg.solve(J.T @ J, J.T @ r)))


def _lstsq_step(phi, a, b):
    R = exp(phi)
    J = np.vstack([-R @ hat(x) @ right_jacobian(phi) for x in a])
    return phi + np.linalg.lstsq(J, -(a @ R.T - b).ravel(), rcond=None)[0]


def test_gauss_newton_step_right_answers_pass():
    assert check_gauss_newton_step(_gn_step)
    assert check_gauss_newton_step(_lstsq_step)
    assert check_gauss_newton_step(lambda p, a, b: list(_gn_step(p, a, b)))


@pytest.mark.parametrize("answer, pattern", [
    (_no_jr, r"J_r\(phi\) is missing"),
    (lambda p, a, b: 2 * p - _gn_step(p, a, b), "wrong sign"),
    (lambda p, a, b: _gn_step(p, a, b) - p, "returned the step Delta itself"),
    (_oplus_step, r"R \(\+\) Delta of section 7"),
    (lambda p, a, b: _gn_step(p, a, b, jacobian=left_jacobian), r"J_l = J_r\^T"),
    (lambda p, a, b: _gn_step(p, a, b)[:2], r"shape \(3,\)"),
    (lambda p, a, b: np.full(3, np.nan), "NaN"),
    (lambda p, a, b: p + 0.5 * (_gn_step(p, a, b) - p), "do(es)? not minimise"),
])
def test_gauss_newton_step_mistakes(answer, pattern):
    says_for(check_gauss_newton_step(answer), "gauss_newton_step", pattern)


def test_gauss_newton_step_problems_repel_the_step_without_J_r():
    """The checker's claim: on its problems with answers turned by 2.5 to 3 rad, twelve
    steps without J_r from phi = 0 stay more than 1e-3 rad from Kabsch's rotation, while
    the step with J_r reaches it (so the runs tell the two apart)."""
    for theta, axis in ex._PROBLEMS_64:
        a, b, R_star = ex._wahba_64(theta, axis)
        U, _, Vt = np.linalg.svd(b.T @ a)                # Kabsch, (6.15), computed here
        assert np.abs(R_star - U @ np.diag([1.0, 1.0, np.linalg.det(U @ Vt)]) @ Vt).max() < 1e-14
        p_jr, p_no = np.zeros(3), np.zeros(3)
        for _ in range(12):
            p_jr, p_no = _gn_step(p_jr, a, b), _no_jr(p_no, a, b)
        assert so3lib.angle(R_star.T @ exp(p_jr)) < 1e-9
        if theta >= 2.5:
            assert so3lib.angle(R_star.T @ exp(p_no)) > 1e-3, theta


def test_gauss_newton_step_messages_never_show_the_expected_value():
    for answer in (_no_jr, lambda p, a, b: p + 0.5 * (_gn_step(p, a, b) - p)):
        fb = repr(check_gauss_newton_step(answer))
        assert "expected" not in fb.lower()
        for theta, axis in ex._PROBLEMS_64:
            a, b, R_star = ex._wahba_64(theta, axis)
            for digits in (2, 3, 4):
                assert np.array2string(log(R_star), precision=digits) not in fb
