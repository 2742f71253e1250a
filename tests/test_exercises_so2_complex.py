"""The checkers of notebook 03 (so3lib.exercises.so2_complex): a right answer passes; a
missing answer, a raising function, a wrong shape, NaN and the usual wrong answers each
get a helpful message, never an exception."""

import numpy as np
import pytest

from checker_support import not_written as _not_written, says as _says
from so3lib import so2
from so3lib.exercises.so2_complex import (ACCEL, OMEGA0, T_END, check_quaternion,
                                          check_so2_log, check_varying_rate, quaternion)


# ----------------------------------------------------------------------- exercise 3.1

def test_so2_log_right_answer_passes():
    fb = check_so2_log(lambda R: np.arctan2(R[1, 0], R[0, 0]))
    assert fb and repr(fb).startswith("Correct: so2_log")


@pytest.mark.parametrize("student, says", [
    (None, "No answer yet"),
    (..., "No answer yet"),
    (_not_written, "Not written yet"),
    (lambda R: 1 / 0, "raised ZeroDivisionError"),
    (lambda R: np.array([1.0, 2.0]), r"has shape \(2,\); expected shape \(\)"),
    (lambda R: np.nan, "NaN or inf"),
    (lambda R: np.arccos(R[0, 0]), r"cannot tell \+theta from -theta"),
    (lambda R: np.arctan(R[1, 0] / R[0, 0]), "second quadrant from the\\s+fourth"),
    (lambda R: np.degrees(np.arctan2(R[1, 0], R[0, 0])), "degrees"),
    (lambda R: "angle", "not a number"),
])
def test_so2_log_wrong_answers_get_a_message(student, says):
    _says(check_so2_log(student), says)


def test_so2_log_wrapping_is_required():
    # right in (-pi, pi) except that 4.0 is not wrapped
    def unwrapped(R):
        t = np.arctan2(R[1, 0], R[0, 0])
        return t + 2 * np.pi if np.isclose(t, 4.0 - 2 * np.pi) else t
    _says(check_so2_log(unwrapped), "expected -2.28319")


# ----------------------------------------------------------------------- exercise 3.2

def test_varying_rate_right_answer_passes():
    alpha = OMEGA0 * T_END + ACCEL * T_END ** 2 / 2
    assert check_varying_rate(so2.exp(alpha))
    assert check_varying_rate(so2.exp(alpha).tolist())


@pytest.mark.parametrize("answer, says", [
    (None, "No answer yet"),
    (..., "No answer yet"),
    (np.eye(3), r"shape \(3, 3\); expected shape \(2, 2\)"),
    (np.full((2, 2), np.nan), "NaN or inf"),
    (3.0, "You gave a number \\(and that angle is right\\)"),
    (so2.exp((OMEGA0 + ACCEL * T_END) * T_END), "the rate at the end times T"),
    (so2.exp(OMEGA0 * T_END), "the rate at the start times T"),
    (so2.exp(-3.0), "transpose"),
    ("R", "not a number"),
])
def test_varying_rate_wrong_answers_get_a_message(answer, says):
    _says(check_varying_rate(answer), says)


# ----------------------------------------------------------------------- exercise 3.3

def test_quaternion_right_answer_passes():
    fb = check_quaternion(lambda n, theta: np.r_[np.cos(theta / 2), np.sin(theta / 2) * n])
    assert fb and repr(fb).startswith("Correct: quaternion")
    assert np.allclose(quaternion([0, 0, 1], np.pi), [0, 0, 0, 1], atol=1e-16)


@pytest.mark.parametrize("student, says", [
    (None, "No answer yet"),
    (_not_written, "Not written yet"),
    (lambda n, t: n[5], "raised IndexError"),
    (lambda n, t: n, r"has shape \(3,\); expected shape \(4,\)"),
    (lambda n, t: np.full(4, np.nan), "NaN or inf"),
    (lambda n, t: -quaternion(n, t), "double cover"),
    (lambda n, t: quaternion(n, 2 * t), "theta/2"),
    (lambda n, t: np.roll(quaternion(n, t), -1), "scalar part first"),
    (lambda n, t: np.r_[np.cos(t / 2), n], "expected"),
])
def test_quaternion_wrong_answers_get_a_message(student, says):
    _says(check_quaternion(student), says)
