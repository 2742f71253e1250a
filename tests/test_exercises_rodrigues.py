"""Checkers of notebook 02 (so3lib.exercises.rodrigues): right answers pass; missing,
raising, wrong-shape, NaN and typical wrong answers get a helpful message, never an
exception."""

import math
import warnings

import numpy as np
import pytest

import so3lib
from checker_support import not_written as _not_written, says_for as _says
from so3lib.exercises.rodrigues import check_B, check_partial_sum, check_quarter_turn


# ------------------------------------------------------------------ 2.1 partial sums

def _by_hand(omega, tau, terms):
    K = tau * so3lib.hat(omega)
    term, total = np.eye(3), np.eye(3)
    for m in range(1, terms):
        term = term @ K / m
        total = total + term
    return total


def test_partial_sum_right_answers_pass():
    for func in (_by_hand, so3lib.exp_series):
        fb = check_partial_sum(func)
        assert fb and repr(fb).startswith("Correct: partial_sum"), repr(fb)


def _elementwise(omega, tau, terms):
    K = tau * so3lib.hat(omega)
    return sum(K ** m / math.factorial(m) for m in range(terms))


@pytest.mark.parametrize("student, pattern", [
    (None, "No answer yet"),
    (..., "No answer yet"),
    (_not_written, "Not written yet"),
    (lambda w, t, n: np.linalg.inv(np.zeros((3, 3))), "raised LinAlgError"),
    (lambda w, t, n: np.eye(2), r"shape \(2, 2\); expected shape \(3, 3\)"),
    (lambda w, t, n: np.full((3, 3), np.nan), "NaN or inf"),
    (lambda w, t, n: _by_hand(w, t, n + 1), "You summed 2 terms instead of 1"),
    (lambda w, t, n: _by_hand(w, t, n - 1) if n > 1 else np.eye(3), "summed 1 terms instead of 2"),
    (_elementwise, r"raises each ENTRY"),
    (lambda w, t, n: sum(np.linalg.matrix_power(t * so3lib.hat(w), m) for m in range(n)),
     r"divided by m!"),
    (lambda w, t, n: _by_hand(w, 1.0, n), r"multiply hat\(omega\) by tau"),
    (lambda w, t, n: so3lib.exp(w, t), r"Hint: partial_sum\(omega, tau, N\) is the sum"),
])
def test_partial_sum_wrong_answers_get_a_message(student, pattern):
    _says(check_partial_sum(student), "partial_sum", pattern)


# ------------------------------------------------------------------ 2.2 quarter turn

QUARTER = np.array([[0.0, -1.0, 0.0], [1.0, 0.0, 0.0], [0.0, 0.0, 1.0]])


def test_quarter_turn_right_answers_pass():
    assert check_quarter_turn(QUARTER)
    assert check_quarter_turn(QUARTER.astype(int).tolist())
    assert check_quarter_turn(so3lib.exp([0, 0, np.pi / 2]))


@pytest.mark.parametrize("answer, pattern", [
    (None, "No answer yet"),
    (..., "No answer yet"),
    (np.eye(2), r"shape \(2, 2\); expected shape \(3, 3\)"),
    (np.full((3, 3), np.nan), "NaN or inf"),
    (QUARTER.T, "wrong direction"),
    (np.eye(3) + (1 + 2 / np.pi) * so3lib.hat([0, 0, 1]), "errata N1"),
    (np.exp(so3lib.hat([0, 0, np.pi / 2])), "entry by entry"),
    (so3lib.exp([0, 0, 90.0]), "radians"),
    (np.eye(3), "first column of R is \\(0, 1, 0\\)"),
    ("R", "not a number"),
])
def test_quarter_turn_wrong_answers_get_a_message(answer, pattern):
    _says(check_quarter_turn(answer), "the rotation reached", pattern)


# ------------------------------------------------------------------ 2.3 stable B

def test_B_right_answers_pass():
    def half_angle(t):
        return 0.5 if t == 0 else 2 * (math.sin(t / 2) / t) ** 2

    def taylor_then_closed(t):
        return 0.5 - t * t / 24 if abs(t) < 1e-4 else (1 - math.cos(t)) / t ** 2 \
            if abs(t) > 0.5 else 2 * (math.sin(t / 2) / t) ** 2
    for func in (half_angle, taylor_then_closed, so3lib.B):
        fb = check_B(func)
        assert fb and repr(fb).startswith("Correct: B_stable"), repr(fb)


def _naive(t):
    return (1 - math.cos(t)) / t ** 2


def _naive_numpy(t):
    with np.errstate(all="ignore"):
        return (1 - np.cos(np.float64(t))) / np.float64(t) ** 2


def _no_limit(t):
    return 2 * (math.sin(t / 2) / t) ** 2


@pytest.mark.parametrize("student, pattern", [
    (None, "No answer yet"),
    (..., "No answer yet"),
    (_not_written, "Not written yet"),
    (lambda t: math.log(-1), "raised ValueError"),
    (lambda t: np.array([t, t]), r"shape \(2,\); expected shape \(\)"),
    (lambda t: float("nan"), "NaN or inf"),
    (_naive, r"B_stable\(1e-08\)(.|\n)*naive \(1 - cos t\)/t\^2"),
    (_naive_numpy, r"naive"),
    (_no_limit, r"B_stable\(0\) raised ZeroDivisionError(.|\n)*limit 1/2"),
    (lambda t: 0.5 - t * t / 24, r"B_stable\(1\)(.|\n)*Taylor polynomial is accurate only near"),
    (lambda t: math.sin(t) / t, r"That is A\(t\)"),
    (lambda t: (1 - math.cos(t)) / t, r"denominator is t\^2"),
])
def test_B_wrong_answers_get_a_message(student, pattern):
    with warnings.catch_warnings():
        warnings.simplefilter("error")          # and the checker itself warns about nothing
        fb = check_B(student)
    _says(fb, "B_stable", pattern)
