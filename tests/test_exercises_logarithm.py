"""The checkers of notebook 04 (so3lib.exercises.logarithm): a right answer passes; a
missing answer, a raising function, a wrong shape, NaN and the usual wrong answers each
get a helpful message, never an exception."""

import numpy as np
import pytest

import so3lib
from checker_support import not_written as _not_written, says as _says
from so3lib.exercises.logarithm import (R41, TAU41, all_logs, check_all_logs,
                                        check_halfturn_axis, check_log_at_pi,
                                        check_sigma_and_axis)


# ----------------------------------------------------------------------- exercise 4.1

THETA = np.arccos((np.trace(R41) - 1) / 2)
V = np.array([R41[2, 1] - R41[1, 2], R41[0, 2] - R41[2, 0], R41[1, 0] - R41[0, 1]])
SIGMA, N = THETA / TAU41, V / (2 * np.sin(THETA))


def test_sigma_and_axis_right_answer_passes():
    fb = check_sigma_and_axis(SIGMA, N)
    assert fb and repr(fb).startswith("Correct: sigma and n")
    assert np.allclose(so3lib.exp(SIGMA * N, TAU41), R41)     # the exercise is consistent


@pytest.mark.parametrize("sigma, n, says", [
    (None, None, "sigma. No answer yet(.|\\n)*the axis n. No answer yet"),
    (..., N, "sigma. No answer yet"),
    (SIGMA, np.r_[N, 0.0], r"shape \(4,\); expected shape \(3,\)"),
    (np.nan, N, "NaN or inf"),
    (SIGMA, np.full(3, np.nan), "NaN or inf"),
    (THETA, N, "divide by tau"),
    (THETA * TAU41, N, "multiplied by tau"),
    (SIGMA, V, "divide by 2 sin"),
    (SIGMA, TAU41 * N, "should not contain tau"),
    (SIGMA, -N, "off by a sign"),
    (SIGMA, 1.5 * N, "length 1.5"),
    ("fast", N, "not a number"),
])
def test_sigma_and_axis_wrong_answers_get_a_message(sigma, n, says):
    _says(check_sigma_and_axis(sigma, n), says)


# ----------------------------------------------------------------------- exercise 4.3

def _halfturn_axis(R):
    j = int(np.argmax(np.diag(R)))
    col = R[:, j] + np.eye(3)[:, j]
    return col / np.sqrt(2 * (R[j, j] + 1))


def test_halfturn_axis_right_answer_passes_with_either_sign():
    fb = check_halfturn_axis(_halfturn_axis)
    assert fb and repr(fb).startswith("Correct: halfturn_axis")
    assert check_halfturn_axis(lambda R: -_halfturn_axis(R))


def _first_column(R):
    col = (R + np.eye(3))[:, 0]
    with np.errstate(invalid="ignore", divide="ignore"):
        return col / np.linalg.norm(col)


@pytest.mark.parametrize("student, says", [
    (None, "No answer yet"),
    (..., "No answer yet"),
    (3, "Expected a function"),
    (_not_written, "Not written yet"),
    (lambda R: 1 / 0, "raised ZeroDivisionError"),
    (lambda R: None, "returned None"),
    (lambda R: np.eye(3), r"shape \(3, 3\); expected a vector"),
    (lambda R: "n", "not an array of numbers"),
    (lambda R: np.full(3, np.nan), "NaN or inf"),
    (_first_column, "largest diagonal entry"),
    (lambda R: np.pi * _halfturn_axis(R), "logarithm pi n"),
    (lambda R: 2 * _halfturn_axis(R), "Right direction, but length 2"),
    (lambda R: np.array([1.0, 0.0, 0.0]), "every column of R \\+ I is a multiple of n"),
])
def test_halfturn_axis_wrong_answers_get_a_message(student, says):
    _says(check_halfturn_axis(student), says)


# ----------------------------------------------------------------------- exercise 4.2

def _all_logs(R, bound):
    phi = so3lib.log(R)
    theta = np.linalg.norm(phi)
    ks = range(-10, 11)
    return [(theta + 2 * np.pi * k) * phi / theta for k in ks if abs(theta + 2 * np.pi * k) < bound]


def test_all_logs_right_answer_passes_in_any_order():
    fb = check_all_logs(_all_logs)
    assert fb and repr(fb).startswith("Correct: all_logs")
    assert check_all_logs(lambda R, b: _all_logs(R, b)[::-1])


def test_all_logs_reference():
    R = so3lib.exp([0.0, 0.0, 1.0])
    phis = all_logs(R, 12.0)
    assert phis.shape == (4, 3)
    assert np.allclose(phis[:, 2], [1.0, 1.0 - 2 * np.pi, 1.0 + 2 * np.pi, 1.0 - 4 * np.pi])
    for phi in phis:
        assert np.allclose(so3lib.exp(phi), R)


@pytest.mark.parametrize("student, says", [
    (None, "No answer yet"),
    (_not_written, "Not written yet"),
    (lambda R, b: 1 / 0, "raised ZeroDivisionError"),
    (lambda R, b: None, "returned None"),
    (lambda R, b: np.zeros((2, 2)), r"shape \(2, 2\); expected shape \(m, 3\)"),
    (lambda R, b: np.full((2, 3), np.nan), "NaN or inf"),
    (lambda R, b: [p for p in _all_logs(R, b) if p @ so3lib.log(R) > 0], "k < 0 ones"),
    (lambda R, b: [-p for p in _all_logs(R, b)], "check each vector"),
    (lambda R, b: [so3lib.log(R)] * 5, "keep those"),
    (lambda R, b: [["a", "b", "c"]], "not an array of numbers"),
])
def test_all_logs_wrong_answers_get_a_message(student, says):
    _says(check_all_logs(student), says)


# ----------------------------------------------------------------------- exercise 4.4

def _log_at_pi(n):
    n = np.asarray(n, dtype=float)
    j = int(np.argmax(np.abs(n)))
    return np.pi * np.sign(n[j]) * n


def test_log_at_pi_right_answer_passes():
    fb = check_log_at_pi(_log_at_pi)
    assert fb and repr(fb).startswith("Correct: log_at_pi")


def _first_nonzero(n):
    n = np.asarray(n, dtype=float)
    return np.pi * np.sign(n[np.flatnonzero(n)[0]]) * n


@pytest.mark.parametrize("student, says", [
    (None, "No answer yet"),
    (_not_written, "Not written yet"),
    (lambda n: 1 / 0, "raised ZeroDivisionError"),
    (lambda n: np.pi, r"shape \(\); expected shape \(3,\)"),
    (lambda n: np.full(3, np.nan), "NaN or inf"),
    (lambda n: np.pi * np.asarray(n), "pi n as given"),
    (_first_nonzero, "first nonzero component positive"),
    (lambda n: -_log_at_pi(n), "largest component"),
])
def test_log_at_pi_wrong_answers_get_a_message(student, says):
    _says(check_log_at_pi(student), says)
