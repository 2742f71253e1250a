"""Checkers of notebook 01 (so3lib.exercises.hat_map): right answers pass; missing,
raising, wrong-shape, NaN and typical wrong answers get a helpful message, never an
exception."""

import numpy as np
import pytest

import so3lib
from checker_support import not_written as _not_written, says_for as _says
from so3lib.exercises.hat_map import (check_fifth_power, check_hat,
                                      check_power_coefficients, power_coefficients)


# ------------------------------------------------------------------ 1.1 hat

def test_hat_right_answers_pass():
    def by_hand(a):
        a1, a2, a3 = a
        return np.array([[0, -a3, a2], [a3, 0, -a1], [-a2, a1, 0]])
    for func in (so3lib.hat, by_hand, lambda a: np.cross(np.eye(3), a)):
        fb = check_hat(func)
        assert fb and repr(fb).startswith("Correct: hat_matrix"), repr(fb)


@pytest.mark.parametrize("student, pattern", [
    (None, "No answer yet"),
    (..., "No answer yet"),
    (_not_written, "Not written yet"),
    (lambda a: a[5], "raised IndexError"),
    (lambda a: np.zeros(3), r"shape \(3,\); expected shape \(3, 3\)"),
    (lambda a: np.full((3, 3), np.nan), "NaN or inf"),
    (lambda a: so3lib.hat(a).T, r"off by a sign(.|\n)*Hint: Row 1 of hat\(a\) is \(0, -a3, a2\)"),
    (lambda a: np.diag(a), "Hint: Row 1"),
])
def test_hat_wrong_answers_get_a_message(student, pattern):
    _says(check_hat(student), "hat_matrix", pattern)


def test_hat_message_shows_no_negative_zero():
    # hat((1, 0, 0)) holds -0.0 entries; "-0." in a message reads like a sign error
    text = repr(check_hat(lambda a: so3lib.hat(a).T))
    assert "off by a sign" in text and "-0." not in text, text


# ------------------------------------------------------------------ 1.2 fifth power

def test_fifth_power_right_answer_passes():
    assert check_fifth_power(196)
    assert check_fifth_power(np.float64(14.0) ** 2)


@pytest.mark.parametrize("answer, pattern", [
    (None, "No answer yet"),
    (..., "No answer yet"),
    ([196, 196], r"shape \(2,\); expected shape \(\)"),
    (float("nan"), "NaN or inf"),
    (-196, "wrong sign"),
    (-14, "factor of hat\\(a\\)\\^3"),
    (14 ** 4, "power of \\|a\\|"),
    (100, "Start from the Lemma"),
    ("196x", "not a number"),
    (196 * so3lib.hat([1, 2, 3]), "that matrix is right(.|\n)*number c itself"),
    (-5 * so3lib.hat([1, 2, 3]), "not hat\\(a\\)\\^5"),
])
def test_fifth_power_wrong_answers_get_a_message(answer, pattern):
    _says(check_fifth_power(answer), "the coefficient c", pattern)


def test_fifth_power_unreadable_answer_does_not_raise():
    class Weird:
        def __array__(self, *args, **kwargs):
            raise RuntimeError("cannot convert")
    _says(check_fifth_power(Weird()), "the coefficient c", "could not be checked|not a number")


# ------------------------------------------------------------------ 1.3 all powers

def test_power_coefficients_reference_matches_matrix_powers():
    for a in ([1.0, 2.0, 3.0], [0.5, -1.0, 0.25], [0.0, 0.0, 2.0]):
        H = so3lib.hat(a)
        basis = np.stack([np.eye(3), H, H @ H])
        for p in range(0, 11):
            c = power_coefficients(a, p)
            assert np.allclose(np.tensordot(c, basis, 1), np.linalg.matrix_power(H, p))


def test_power_coefficients_right_answer_passes():
    def student(a, p):
        a = np.asarray(a)
        if p == 0:
            return (1, 0, 0)
        k = (p - 1) // 2
        c = (-1) ** k * (a @ a) ** k
        return (0, c, 0) if p % 2 == 1 else (0, 0, c)
    fb = check_power_coefficients(student)
    assert fb and repr(fb).startswith("Correct: power_coefficients"), repr(fb)
    assert check_power_coefficients(power_coefficients)


def _forgets_identity(a, p):
    c = power_coefficients(a, p)
    return c if p else np.array([0.0, 0.0, -1.0 / float(np.dot(a, a))])


def _wrong_sign(a, p):
    return -power_coefficients(a, p) if p >= 3 else power_coefficients(a, p)


def _uses_norm_not_square(a, p):
    if p == 0:
        return np.array([1.0, 0.0, 0.0])
    k = (p - 1) // 2
    c = (-1) ** k * np.linalg.norm(a) ** k
    return np.array([0.0, c, 0.0]) if p % 2 else np.array([0.0, 0.0, c])


@pytest.mark.parametrize("student, pattern", [
    (None, "No answer yet"),
    (..., "No answer yet"),
    (_not_written, "Not written yet"),
    (lambda a, p: 1 / 0, "raised ZeroDivisionError"),
    (lambda a, p: (0, 1), r"shape \(2,\); expected shape \(3,\)"),
    (lambda a, p: (np.nan, 0, 0), "NaN or inf"),
    (_forgets_identity, r"power_coefficients\(.*0\)(.|\n)*hat\(a\)\^0 is the identity"),
    (_wrong_sign, r"p = 3 is odd"),
    (_uses_norm_not_square, r"p = 3 is odd(.|\n)*\(a @ a\)\*\*k|p = 4 is even"),
])
def test_power_coefficients_wrong_answers_get_a_message(student, pattern):
    _says(check_power_coefficients(student), "power_coefficients", pattern)
