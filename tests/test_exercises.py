"""The exercise checkers: helpful feedback, and never an exception (so3lib.exercises)."""

import re

import numpy as np
import pytest

import so3lib
from so3lib.exercises import Feedback, check_function, check_value

INPUTS = [([1.0, 2.0, 3.0],), ([0.0, 0.0, 0.0],)]


def check_hat(func):
    return check_function(func, so3lib.hat, INPUTS, "hat")


def test_correct_function_passes():
    fb = check_hat(lambda a: so3lib.hat(a))
    assert fb and isinstance(fb, Feedback) and repr(fb).startswith("Correct: hat")


@pytest.mark.parametrize("student, says", [
    (None, "No answer yet"),
    (..., "No answer yet"),
    (42, "Expected a function"),
    (lambda a: (_ for _ in ()).throw(NotImplementedError()), "Not written yet"),
    (lambda a: None, "returned None"),
    (lambda a: 1 / 0, "raised ZeroDivisionError"),
    (lambda a: np.zeros(3), r"has shape \(3,\); expected shape \(3, 3\)"),
    (lambda a: np.full((3, 3), np.nan), "NaN or inf"),
    (lambda a: -so3lib.hat(a), "off by a sign"),
    (lambda a: "hat", "not a number"),
    (lambda a: np.eye(3), "expected"),
])
def test_wrong_functions_get_a_message_not_an_exception(student, says):
    fb = check_hat(student)
    assert not fb
    assert repr(fb).startswith("Not yet: hat.")
    assert re.search(says, repr(fb)), repr(fb)


def test_transposed_matrix_is_recognised():
    R = so3lib.exp([0.1, 0.2, 0.3])
    fb = check_value(R.T, R, "the rotation")
    assert not fb and "transpose" in repr(fb)


def test_values():
    assert check_value(np.pi, np.pi, "the angle")
    assert "No answer yet" in repr(check_value(None, 1.0, "x"))
    assert "No answer yet" in repr(check_value(..., 1.0, "x"))
    fb = check_value(3.0, np.pi, "the angle", hint="Use atan2.")
    assert not fb and "Hint: Use atan2." in repr(fb)
    assert not check_value([1.0, 2.0], [1.0, 2.0, 3.0], "v")
    assert check_value(1 + 1j, 1 + 1j, "z")
    assert not check_value(object(), 1.0, "x")
