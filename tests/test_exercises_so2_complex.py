"""The checkers of notebook 03 (so3lib.exercises.so2_complex): a right answer passes; a
missing answer, a raising function, a wrong shape, NaN and the usual wrong answers each
get a helpful message, never an exception."""

import numpy as np
import pytest
from checker_support import not_written as _not_written
from checker_support import says as _says

from so3lib import so2
from so3lib.exercises.so2_complex import (
    ACCEL,
    OMEGA0,
    Q33,
    T_END,
    check_so2_log,
    check_unflip,
    check_varying_rate,
    logged_quaternions,
)

# ----------------------------------------------------------------------- exercise 3.1

def _so2_log_right(R):
    a = np.arctan2(R[1, 0], R[0, 0])
    return np.pi if a <= -np.pi else a      # on the cut atan2 gives -pi (a faithful one: or below)


def test_so2_log_right_answer_passes():
    fb = check_so2_log(_so2_log_right)
    assert fb and repr(fb).startswith("Correct: so2_log")
    assert "two half-turns on the cut and next to it included" in repr(fb)


def test_so2_log_plain_arctan2_is_caught_on_minus_zero():
    # np.arctan2(-0.0, -1.0) is -pi: outside (-pi, pi]; the message names -0.0
    assert np.arctan2(-np.eye(2)[1, 0], -1.0) == -np.pi
    _says(check_so2_log(lambda R: np.arctan2(R[1, 0], R[0, 0])),
          r"On -np.eye\(2\) it returned -3.14159, the double -np.pi, outside .*-0.0")


def test_so2_log_testing_for_a_zero_sine_is_caught_next_to_the_cut():
    # R21 = -1e-16 is not zero, yet np.arctan2 rounds -pi + 1e-16 to the double -np.pi
    def zero_test(R):
        if R[1, 0] == 0 and R[0, 0] < 0:
            return np.pi
        return np.arctan2(R[1, 0], R[0, 0])
    assert np.arctan2(-1e-16, -1.0) <= -np.pi      # -np.pi correctly rounded; a faithful atan2: or below
    _says(check_so2_log(zero_test),
          r"On \[\[-1, 1e-16\], \[-1e-16, -1\]\] it returned -3.14159, .*R\[1, 0\] == 0 misses it")


@pytest.mark.parametrize("student, says", [
    (None, "No answer yet"),
    (..., "No answer yet"),
    (_not_written, "Not written yet"),
    (lambda R: 1 / 0, "raised ZeroDivisionError"),
    (3, "Expected a function"),
    (lambda R: np.array([1.0, 2.0]), r"has shape \(2,\); expected shape \(\)"),
    (lambda R: np.nan, "NaN or inf"),
    (lambda R: np.arccos(R[0, 0]), r"sign of alpha is lost \(arccos"),
    (lambda R: np.arctan(R[1, 0] / R[0, 0]), "second quadrant from the\\s+fourth"),
    (lambda R: np.degrees(np.arctan2(R[1, 0], R[0, 0])), "degrees"),
    (lambda R: "angle", "not a number"),
])
def test_so2_log_wrong_answers_get_a_message(student, says):
    _says(check_so2_log(student), says)


def test_so2_log_refuses_so2_log_however_it_is_reached():
    """The task says "not so2.log": a call by the module, by a name imported before the
    checker ran, or so2.log itself handed in, is refused; the answer's right value does
    not save it."""
    from so3lib.so2 import log as imported_log
    for student in (so2.log, lambda R: so2.log(R), lambda R: float(imported_log(R)),
                    lambda R: getattr(so2, "l" + "og")(R)):
        fb = check_so2_log(student)
        assert not fb
        _says(fb, "so2.log")
    # np.log is not so2.log: a complex logarithm from the entries is the learner's own
    def from_complex_log(R):
        a = np.log(complex(R[0, 0], R[1, 0])).imag
        return np.pi if a <= -np.pi else a
    assert check_so2_log(from_complex_log)


def test_so2_log_flipped_sign_and_complex_answers_get_their_own_hint():
    _says(check_so2_log(lambda R: np.arctan2(R[0, 1], R[0, 0])), r"sign is flipped\. R\[0, 1\]")
    _says(check_so2_log(lambda R: np.abs(np.arctan2(R[1, 0], R[0, 0]))), "sign of alpha is lost")
    _says(check_so2_log(lambda R: np.log(complex(R[0, 0], R[1, 0]))), "returned a complex number")


def test_so2_log_arccos_with_the_sign_of_r21_is_refused_at_a_tiny_angle():
    """arccos(R11) with R21's sign is right to 1e-15 at the larger angles, but cos(1e-9)
    rounds to 1: it returns 0 there. The hidden test refuses it; the checker must too."""
    def arccos_signed(R):
        if R[1, 0] == 0 and R[0, 0] < 0:
            return np.pi
        return np.copysign(np.arccos(R[0, 0]), R[1, 0])
    _says(check_so2_log(arccos_signed), r"so2.exp\(1e-09\) it returned 0: every digit")


def test_so2_log_lost_precision_gets_the_size_of_the_miss():
    fb = check_so2_log(lambda R: float(np.float32(np.arctan2(R[1, 0] + 0.0, R[0, 0]))))
    _says(fb, r"miss R's first column by [0-9.]+e-0[5-9], more than the 1e-12")


def test_so2_log_other_right_answers_pass():
    """Any float64 route from the entries that keeps its digits passes: arcsin with the
    quadrant from R11, or atan2 with -np.pi mapped to np.pi by np.where."""
    def from_arcsin(R):
        a = np.arcsin(R[1, 0])
        if R[0, 0] < 0:
            a = np.pi - a
        return a - 2 * np.pi if a > np.pi else a
    assert check_so2_log(from_arcsin)
    assert check_so2_log(lambda R: np.where(np.arctan2(R[1, 0], R[0, 0]) <= -np.pi, np.pi,
                                            np.arctan2(R[1, 0], R[0, 0])))


def test_so2_log_adding_plus_zero_mends_only_the_negative_zero():
    # R21 + 0.0 turns -0.0 into 0.0, but -1e-16 stays negative: atan2 still gives -np.pi
    _says(check_so2_log(lambda R: np.arctan2(R[1, 0] + 0.0, R[0, 0])),
          r"On \[\[-1, 1e-16\], \[-1e-16, -1\]\] it returned -3.14159")


def test_so2_log_wrapping_is_required():
    # right in (-pi, pi) except that 4.0 is not wrapped
    def unwrapped(R):
        t = np.arctan2(R[1, 0], R[0, 0])
        return t + 2 * np.pi if np.isclose(t, 4.0 - 2 * np.pi) else t
    _says(check_so2_log(unwrapped), r"right rotation, but outside \(-pi, pi\]")


# ----------------------------------------------------------------------- exercise 3.2

def test_varying_rate_right_answer_passes():
    alpha = OMEGA0 * T_END + ACCEL * T_END ** 2 / 2
    assert check_varying_rate(so2.exp(alpha))
    assert check_varying_rate(so2.exp(alpha).tolist())


@pytest.mark.parametrize("answer, says", [
    (None, "No answer yet"),
    (..., "No answer yet"),
    (np.eye(3), r"shape \(3, 3\); a planar rotation is a 2x2 matrix"),
    (np.full((2, 2), np.nan), "NaN or inf"),
    (3.0, "You gave a number"),
    (so2.exp((OMEGA0 + ACCEL * T_END) * T_END), "the rate at the end times T"),
    (so2.exp(OMEGA0 * T_END), "the rate at the start times T"),
    (so2.exp(-3.0), "transpose"),
    ("R", "not a number"),
])
def test_varying_rate_wrong_answers_get_a_message(answer, says):
    _says(check_varying_rate(answer), says)


def test_varying_rate_refuses_a_matrix_that_is_not_a_rotation():
    """A scaled rotation turns by the right angle; the message says it is no rotation
    instead of 'turns by 3 rad ... ends elsewhere'."""
    alpha = OMEGA0 * T_END + ACCEL * T_END ** 2 / 2
    for answer in (2 * so2.exp(alpha), alpha * so2.J):
        text = repr(check_varying_rate(answer))
        _says(check_varying_rate(answer), r"not a rotation: R\^T R differs from I")
        assert "turns by" not in text, text


def test_varying_rate_near_miss_gives_the_size_not_the_angle():
    """An angle a little off would print as the answer's own (3 rad to four digits); the
    message gives the size of the miss instead. A complex number gets its own message."""
    alpha = OMEGA0 * T_END + ACCEL * T_END ** 2 / 2
    text = repr(check_varying_rate(so2.exp(alpha + 1e-6)))
    assert "off by 9.9e-07" in text and "turns by" not in text, text
    # a left Riemann sum of 1000 steps is 2e-3 off: its angle (2.998) is not printed
    t = np.arange(1000) * T_END / 1000
    text = repr(check_varying_rate(so2.exp(np.sum((OMEGA0 + ACCEL * t) * T_END / 1000))))
    assert "off by 2.2e-03" in text and "2.99" not in text, text
    _says(check_varying_rate(np.exp(1j * alpha)), "complex number.*so2.from_complex")


def test_checkers_never_print_the_expected_value():
    """A wrong answer's message names the learner's value and the mistake, never the
    answer: the angle 3 of exercise 3.2, the matrix it gives, or so2.exp(4.0)'s angle."""
    alpha = OMEGA0 * T_END + ACCEL * T_END ** 2 / 2
    for answer in (so2.exp(alpha + 0.1), so2.exp(-alpha), np.eye(2)):
        text = repr(check_varying_rate(answer))
        assert "expected" not in text and "-0.99" not in text and "0.1411" not in text, text
    text = repr(check_so2_log(lambda R: 0.1))
    assert "expected" not in text and "-2.283" not in text and "0.5 " not in text, text


# ----------------------------------------------------------------------- exercise 3.3

def _unflip(qs):
    out = np.array(qs, dtype=float)
    for k in range(1, len(out)):
        if out[k] @ out[k - 1] < 0:
            out[k] = -out[k]
    return out


def _unflip_against_the_log(qs):
    out = np.array(qs, dtype=float)
    for k in range(1, len(out)):
        if qs[k] @ qs[k - 1] < 0:
            out[k] = -out[k]
    return out


def test_unflip_right_answer_passes():
    fb = check_unflip(_unflip)
    assert fb and repr(fb).startswith("Correct: unflip")
    assert check_unflip(lambda qs: _unflip(qs).tolist())


def test_the_logs_have_jumps_and_unit_rows():
    for qs in (Q33, logged_quaternions(7, 30)):
        assert np.allclose(np.linalg.norm(qs, axis=1), 1.0)
        assert (np.einsum("ij,ij->i", qs[1:], qs[:-1]) < 0).sum() >= 3
        fixed = _unflip(qs)
        assert (np.einsum("ij,ij->i", fixed[1:], fixed[:-1]) > 0.9).all()


@pytest.mark.parametrize("student, says", [
    (None, "No answer yet"),
    (..., "No answer yet"),
    ("q", "Expected a function"),
    (_not_written, "Not written yet"),
    (lambda qs: qs[5, 9], "raised IndexError"),
    (lambda qs: None, "returned None"),
    (lambda qs: qs[:, :3], r"shape \(41, 3\); expected the input's shape \(41, 4\)"),
    (lambda qs: np.full(qs.shape, np.nan), "NaN or inf"),
    (lambda qs: "qs", "not an array of numbers"),
    (lambda qs: -_unflip(qs), "row 0 changed"),
    (lambda qs: np.vstack([qs[:1], 2 * _unflip(qs)[1:]]), "neither q_k nor -q_k"),
    (lambda qs: qs * np.where(qs[:, :1] < 0, -1.0, 1.0), "every w >= 0"),
    (_unflip_against_the_log, r"logged\* row k - 1"),
    (lambda qs: qs, "flip q_k when"),
])
def test_unflip_wrong_answers_get_a_message(student, says):
    _says(check_unflip(student), says)


def test_so2_log_an_atan2_one_float_below_minus_pi():
    """IEEE 754 leaves atan2 to the maths library: one that is only faithful may return the
    double just below -np.pi next to the cut. The checker names that result, and the
    solution's test (at or below -np.pi) mends it."""
    def low_atan2(y, x):
        a = np.arctan2(y, x)
        return np.nextafter(a, -4.0) if a == -np.pi and y != 0 else a
    _says(check_so2_log(lambda R: low_atan2(R[1, 0] + 0.0, R[0, 0])),   # -0.0 mended only
          r"On \[\[-1, 1e-16\], \[-1e-16, -1\]\] it returned -3.14159, at or below the double")

    def mended(R):
        a = low_atan2(R[1, 0], R[0, 0])
        return np.pi if a <= -np.pi else a
    assert check_so2_log(mended)
