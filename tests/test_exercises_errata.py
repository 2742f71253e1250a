"""The checkers of the errata appendix A1 (so3lib.exercises.errata): right answers pass,
wrong ones get a message that names the mistake, and nothing raises."""

import re

import numpy as np
import pytest

from so3lib import exp, log
from so3lib.exercises import Feedback
from so3lib.exercises.errata import check_power_table, check_wrapped_velocity


def _assert_not_yet(fb, name, says):
    assert isinstance(fb, Feedback) and not fb
    text = repr(fb)
    assert text.startswith(f"Not yet: {name}"), text
    assert re.search(says, text), text


# --- A1.1 the table of powers ---------------------------------------------------------

def test_power_table_right_answer_passes():
    assert check_power_table([1, 2j, -4, -8j, 16])
    assert check_power_table([(2j) ** p for p in range(5)])


@pytest.mark.parametrize("answer, says", [
    (None, "No answer yet"),
    (..., "No answer yet"),
    ("1, 2j, -4", "not a number"),
    ([1, 2j, -4, -8j], r"has shape \(4,\); expected shape \(5,\)"),
    ([1, 2j, np.nan, -8j, 16], "NaN or inf"),
    ([2j, -4, -8j, 16, 32j], "as printed"),
    ([1, 2, -4, -8, 16], "imaginary"),
    ([1, -2j, -4, 8j, 16], "flipped"),
    ([1, 2j, -4, -8j, 17], "expected"),
])
def test_power_table_wrong_answers_get_a_message(answer, says):
    _assert_not_yet(check_power_table(answer), "the table", says)


# --- A1.2 what log(exp) really returns ------------------------------------------------

def _wrapped(omega, tau):
    phi = np.asarray(omega, float) * tau
    theta = np.linalg.norm(phi)
    if theta == 0:
        return np.zeros(3)
    r = theta % (2 * np.pi)
    scale = r / theta if r <= np.pi else -(2 * np.pi - r) / theta
    return scale * phi / tau


def _raise(exc):
    def f(omega, tau):
        raise exc
    return f


def test_wrapped_velocity_right_answers_pass():
    fb = check_wrapped_velocity(_wrapped)
    assert fb and repr(fb).startswith("Correct: wrapped_velocity")
    assert check_wrapped_velocity(lambda w, t: log(exp(w, t), t))      # the library's way


def _no_zero_case(omega, tau):
    phi = np.asarray(omega, float) * tau
    theta = np.linalg.norm(phi)
    r = theta % (2 * np.pi)
    scale = r / theta if r <= np.pi else -(2 * np.pi - r) / theta
    return scale * phi / tau


@pytest.mark.parametrize("student, says", [
    (None, "No answer yet"),
    (..., "No answer yet"),
    ("w", "Expected a function"),
    (_raise(NotImplementedError()), "Not written yet"),
    (_raise(ZeroDivisionError("division by zero")), "raised ZeroDivisionError"),
    (lambda w, t: None, "returned None"),
    (lambda w, t: np.zeros((3, 3)), r"has shape \(3, 3\); expected shape \(3,\)"),
    (lambda w, t: "x", "not a number"),
    (lambda w, t: np.full(3, np.nan), "NaN or inf"),
    (lambda w, t: w, "notes' claim"),
    (lambda w, t: (np.linalg.norm(w * t) % (2 * np.pi)) / np.linalg.norm(w * t) * w,
     "notes' claim.*other way"),
    (lambda w, t: _wrapped(w, t) if np.linalg.norm(w * t) < 2 * np.pi else
     (np.linalg.norm(w * t) % (2 * np.pi)) / np.linalg.norm(w * t) * w, r"not into \[0, pi\]"),
    (lambda w, t: -_wrapped(w, t) if t < 0 else _wrapped(w, t), "off by a sign"),
])
def test_wrapped_velocity_wrong_answers_get_a_message(student, says):
    with np.errstate(invalid="ignore", divide="ignore"):
        fb = check_wrapped_velocity(student)
    _assert_not_yet(fb, "wrapped_velocity", says)


def test_zero_rotation_nan_is_reported():
    with np.errstate(invalid="ignore", divide="ignore"):
        fb = check_wrapped_velocity(_no_zero_case)
    _assert_not_yet(fb, "wrapped_velocity", "NaN or inf")
