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
    (lambda a: np.eye(3), "is not right"),
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


def test_labelled_inputs_diagnosis_and_reference_name():
    cases = [("the zero vector", ([0.0, 0.0, 0.0],)), ("a = (1, 2, 3)", ([1.0, 2.0, 3.0],))]

    def diagnose(got, args):
        return "You returned hat(a) squared." if np.allclose(got, so3lib.hat(args[0]) @ so3lib.hat(args[0])) else None

    fb = check_function(lambda a: so3lib.hat(a) @ so3lib.hat(a), so3lib.hat, cases, "hat",
                        diagnose=diagnose, hint="Build the matrix entry by entry.")
    assert not fb
    text = repr(fb)
    assert "for a = (1, 2, 3)" in text and "You returned hat(a) squared." in text
    assert text.endswith("Hint: Build the matrix entry by entry.")
    ok = check_function(so3lib.hat, so3lib.hat, cases, "hat", reference_name="the reference")
    assert ok and "agrees with the reference on 2 test inputs" in repr(ok)
    raised = check_function(lambda a: a[5], so3lib.hat, cases, "hat")
    assert "Calling it on the zero vector raised IndexError" in repr(raised)


def test_diagnose_is_not_called_on_malformed_results():
    def diagnose(got, args):
        raise AssertionError("must not be called")

    assert "shape" in repr(check_function(lambda a: np.zeros(2), so3lib.hat, INPUTS, "hat", diagnose=diagnose))
    assert "NaN" in repr(check_function(lambda a: np.full((3, 3), np.nan), so3lib.hat, INPUTS, "hat",
                                        diagnose=diagnose))


def test_messages_show_no_negative_zeros():
    fb = check_value(np.array([[-0.0, 1.0], [0.0, 2.0]]), np.eye(2), "M")
    assert "-0." not in repr(fb)


def test_diagnose_is_not_called_on_text():
    def diagnose(got, args):
        raise AssertionError("must not be called")

    fb = check_function(lambda a: "text", so3lib.hat, INPUTS, "hat", diagnose=diagnose)
    assert "not a number" in repr(fb)


def test_never_raises_turns_an_unforeseen_error_into_a_message():
    from so3lib.exercises import never_raises

    @never_raises("the answer")
    def checker(answer):
        return Feedback(True, "Correct") if answer[7] else Feedback(False, "Not yet")

    fb = checker([1.0])
    assert not fb and repr(fb).startswith("Not yet: the answer. The answer could not be checked (IndexError")
    assert checker.__name__ == "checker"


def test_messages_never_show_the_expected_value():
    """Neither the expected value nor the difference that would give it away."""
    fb = check_value(-14.0, 196.0, "c")
    assert not fb and "196" not in repr(fb) and "210" not in repr(fb)
    fb = check_value(197.0, 196.0, "c", hint="Use the Lemma twice.")
    assert "196" not in repr(fb) and "Hint: Use the Lemma twice." in repr(fb)
    assert "off by a sign" in repr(check_value(-196.0, 196.0, "c"))
    secret = np.array([[0.0, -3.125, 2.375], [3.125, 0.0, -1.5], [-2.375, 1.5, 0.0]])
    fb = check_function(lambda a: np.eye(3), lambda a: secret, INPUTS, "hat")
    assert not fb and "3.125" not in repr(fb) and "2.375" not in repr(fb)
