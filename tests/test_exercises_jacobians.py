"""The checkers of notebook 06 (so3lib.exercises.jacobians): right answers pass, wrong
ones get a message that names the mistake, nothing raises, and no message prints the
expected answer."""

import math

import numpy as np
import pytest
from checker_support import not_written, says_for

import so3lib.exercises.jacobians as ex
from so3lib import exp, hat, left_jacobian, right_jacobian
from so3lib.exercises.jacobians import (
    check_body_jacobian,
    check_C_stable,
    check_right_jacobian,
)


def jr_formula(phi):
    t, K = np.linalg.norm(phi), hat(phi)
    return np.eye(3) - (1 - np.cos(t)) / t**2 * K + (t - np.sin(t)) / t**3 * K @ K


def c_stable(t):
    if abs(t) < 0.1:
        t2 = t * t
        return 1 / 6 - t2 / 120 + t2 * t2 / 5040 - t2**3 / 362880
    return (t - math.sin(t)) / t**3


CHECKERS = [(check_right_jacobian, "right_jacobian_formula"),
            (check_C_stable, "C_stable"),
            (check_body_jacobian, "body_jacobian")]


@pytest.mark.parametrize("checker, name", CHECKERS)
@pytest.mark.parametrize("answer, pattern", [
    (None, "No answer yet"), (..., "No answer yet"), (3, "Expected a function"),
    (not_written, "Not written yet"), (lambda *a: None, "returned None"),
    (lambda *a: "x", "not a number"), (lambda *a: 1 / 0, "ZeroDivisionError"),
])
def test_common_mistakes(checker, name, answer, pattern):
    says_for(checker(answer), name, pattern)


def test_right_answers_pass():
    assert check_right_jacobian(jr_formula)
    assert check_right_jacobian(right_jacobian)
    assert check_C_stable(c_stable)
    assert check_C_stable(lambda t: float(so3lib_C(t)))
    assert check_body_jacobian(lambda phi, b: hat(exp(phi).T @ b) @ right_jacobian(phi))


def so3lib_C(t):
    from so3lib import C
    return C(t)


@pytest.mark.parametrize("answer, pattern", [
    (left_jacobian, "left Jacobian"),
    (lambda p: np.eye(3) - (1 - np.cos(np.linalg.norm(p))) / np.linalg.norm(p)**2 * hat(p),
     "hat.phi.\\^2 term"),
    (lambda p: np.eye(3) - hat(p) / 2, "first-order truncation"),
    (lambda p: np.eye(3), "identity"),
    (lambda p: np.zeros((2, 2)), r"shape \(2, 2\)"),
    (lambda p: np.full((3, 3), np.nan), "NaN"),
])
def test_right_jacobian_mistakes(answer, pattern):
    says_for(check_right_jacobian(answer), "right_jacobian_formula", pattern)


@pytest.mark.parametrize("answer, pattern", [
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
])
def test_body_jacobian_mistakes(answer, pattern):
    says_for(check_body_jacobian(answer), "body_jacobian", pattern)


def test_C_stable_threshold_too_low_is_refused():
    """Two series terms up to 0.002, the written form above: 5.6e-11 relative at 0.0025."""
    def early(t):
        return 1 / 6 - t * t / 120 if abs(t) < 0.002 else (t - math.sin(t)) / t**3
    fb = check_C_stable(early)
    assert not fb
    assert "Only small t" in fb.message and "0.1666" not in fb.message


def test_messages_never_show_the_expected_value():
    """A wrong answer's message names its own numbers, never the right Jacobian."""
    phi = np.array([0.0, 0.0, math.pi / 2])
    right = np.array2string(right_jacobian(phi), precision=4, suppress_small=True,
                            separator=", ")
    fb = check_right_jacobian(lambda p: np.eye(3))
    assert right not in repr(fb) and "expected" not in repr(fb).lower()
    fb = check_body_jacobian(lambda p, b: hat(exp(p).T @ b))
    assert "expected" not in repr(fb).lower()


def test_module_exposes_no_answer():
    assert sorted(ex.__all__) == ["check_C_stable", "check_body_jacobian",
                                  "check_right_jacobian"]
    public = [n for n in dir(ex) if not n.startswith("_") and callable(getattr(ex, n))]
    assert set(public) <= set(ex.__all__) | {"Feedback", "exp", "hat", "never_raises", "math"}
