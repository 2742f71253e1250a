"""Checkers of notebook 01 (so3lib.exercises.hat_map): right answers pass; missing,
raising, wrong-shape, NaN and typical wrong answers get a helpful message, never an
exception, and no message gives the answer away."""

import inspect
import re

import numpy as np
import pytest
import scipy.linalg
from checker_support import not_written as _not_written
from checker_support import says_for as _says

import so3lib
from so3lib.exercises import hat_map
from so3lib.exercises.hat_map import (
    check_power_coefficients,
    check_power_of_i_plus_hat,
    check_split,
)


def test_module_holds_no_answer():
    # only checkers are public, and no private function computes an exercise's answer
    public = [n for n, f in inspect.getmembers(hat_map, inspect.isfunction)
              if f.__module__ == hat_map.__name__ and not n.startswith("_")]
    assert sorted(public) == sorted(hat_map.__all__), public
    assert all(n.startswith("check_") for n in public), public
    assert not hasattr(hat_map, "power_coefficients")
    assert not hasattr(hat_map, "_sq")


# ------------------------------------------------------------------ 1.1 split

def _split(M):
    M = np.asarray(M, dtype=float)
    return (M + M.T) / 2, (M - M.T) / 2


def test_split_right_answers_pass():
    for func in (_split, lambda M: (np.asarray(M) - so3lib.hat(so3lib.vee((M - M.T) / 2)),
                                    so3lib.hat(so3lib.vee((M - M.T) / 2)))):
        fb = check_split(func)
        assert fb and repr(fb).startswith("Correct: split"), repr(fb)
        assert "tr(S^T K)" in repr(fb)


@pytest.mark.parametrize("student, pattern", [
    (None, "No answer yet"),
    (..., "No answer yet"),
    (_not_written, "Not written yet"),
    (lambda M: M[5], "raised IndexError"),
    (lambda M: M, "does not unpack into two matrices"),
    (lambda M: (M, M, M), "does not unpack into two matrices"),
    (lambda M: (np.zeros(3), M), r"S has shape \(3,\)"),
    (lambda M: (M, np.full((3, 3), np.nan)), "K contains NaN"),
    (lambda M: _split(M)[::-1], "swapped"),
    (lambda M: (M + M.T, M - M.T), "S \\+ K is 2M(.|\n)*divide by two"),
    (lambda M: (M, M.T), "S is not symmetric(.|\n)*Hint: Transposing"),
    (lambda M: (_split(M)[0], _split(M)[1] + np.eye(3)), "K is not skew"),
    (lambda M: (_split(M)[0] + 1.0, _split(M)[1]), "S \\+ K differs from M"),
])
def test_split_wrong_answers_get_a_message(student, pattern):
    _says(check_split(student), "split", pattern)


# ------------------------------------------------------------------ 1.2 (I + hat(a))^4

I4 = "(c0, c1, c2) for (I + hat(a))^4"
RIGHT = (1, 1 * 4 - 4 * 14, 6 - 14)          # I + 4 H + 6 H^2 + 4 H^3 + H^4, Lemma twice


def test_power_of_i_plus_hat_right_answers_pass():
    for answer in (RIGHT, list(RIGHT), np.array(RIGHT, dtype=float), (1.0, -52.0, -8.0)):
        fb = check_power_of_i_plus_hat(answer)
        assert fb and repr(fb).startswith("Correct: (c0, c1, c2)"), repr(fb)


def test_power_of_i_plus_hat_answer_is_the_matrix_power():
    # the property the checker tests, with SciPy's expm-free route: (I + H)^4 by products
    H = so3lib.hat([1.0, 2.0, 3.0])
    P = np.eye(3) + H
    c0, c1, c2 = RIGHT
    assert np.array_equal(P @ P @ P @ P, c0 * np.eye(3) + c1 * H + c2 * H @ H)


@pytest.mark.parametrize("answer, pattern", [
    (None, "No answer yet"),
    (..., "No answer yet"),
    ((1, ..., 3), "still `...`"),
    ("1, -52, -8", "text \\(str\\)(.|\n)*without quotes"),
    ((1, 2), r"shape \(2,\)"),
    (5, r"shape \(\)"),
    ((1, np.nan, 2), "NaN or inf"),
    ((1 + 0j, 2, 3), "complex"),
    (np.eye(3), "3x3 matrix, but it is not"),
    (np.linalg.matrix_power(np.eye(3) + so3lib.hat([1, 2, 3]), 4), "that matrix is right"),
    ((1, 0, -14), "I \\+ hat\\(a\\)\\^4: the middle terms"),
    ((1, -13, -13), "binomial coefficients are missing"),
    ((1, 60, 20), "wrong sign"),
    ((1, 4 - 4 * np.sqrt(14), 6 - np.sqrt(14)), "with \\|a\\| where it has \\|a\\|\\^2"),
    ((1, -52, 6), "fourth power"),
    ((1, 4, -8), "third power"),
    ((1, -50, -8), "is not \\(I \\+ hat\\(a\\)\\)\\^4(.|\n)*Hint: I and hat\\(a\\) commute"),
    ((1, -52.0001, -8), "close, but(.|\n)*whole numbers"),
])
def test_power_of_i_plus_hat_wrong_answers_get_a_message(answer, pattern):
    _says(check_power_of_i_plus_hat(answer), I4, pattern)


@pytest.mark.parametrize("answer", [None, (1, 0, -14), (1, -13, -13), (1, 60, 20), (0, 0, 0),
                                    (1, -50, -8), np.eye(3), "x"])
def test_power_of_i_plus_hat_never_prints_the_answer(answer):
    text = repr(check_power_of_i_plus_hat(answer))
    for giveaway in ("52", "-8,", "-8)", "(1, -", "196"):
        assert giveaway not in text, text


def test_power_of_i_plus_hat_unreadable_answer_does_not_raise():
    class Weird:
        def __array__(self, *args, **kwargs):
            raise RuntimeError("cannot convert")
    _says(check_power_of_i_plus_hat(Weird()), I4, "could not be checked|not three numbers")


# ------------------------------------------------------------------ 1.3 all powers

def _student(a, p):
    a = np.asarray(a)
    if p == 0:
        return (1, 0, 0)
    k = (p - 1) // 2
    c = (-1) ** k * (a @ a) ** k
    return (0, c, 0) if p % 2 == 1 else (0, 0, c)


def _fitted(a, p):
    # a matrix power and a least-squares fit: the property holds, the method is not the formula
    H = so3lib.hat(a)
    basis = np.stack([np.eye(3).ravel(), H.ravel(), (H @ H).ravel()], axis=1)
    return np.linalg.lstsq(basis, np.linalg.matrix_power(H, p).ravel(), rcond=None)[0]


def _read_off(a, p):
    # the dot-product read-off of the notebook's figure, on a matrix power
    H = np.cross(np.eye(3), a)
    M, H2 = np.linalg.matrix_power(H, p), H @ H
    if p == 0:
        return (1.0, 0.0, 0.0)
    return (0.0, np.sum(M * H) / np.sum(H * H), np.sum(M * H2) / np.sum(H2 * H2))


def _nested(a, p):
    power = lambda H: np.linalg.matrix_power(H, p)   # noqa: E731 -- hidden in a lambda
    return _read_off(a, p) if power is None else _fitted(a, p)


def _fit_helper(a, p):
    # the fit, in a function of the learner's own defined outside the answer
    return _fitted(a, p)


def _via_helper(a, p):
    return _fit_helper(a, p)


_mpow = np.linalg.matrix_power            # a matrix route under another name


def _renamed(a, p):
    H = np.array([[0, -a[2], a[1]], [a[2], 0, -a[0]], [-a[1], a[0], 0]], dtype=float)
    M, H2 = _mpow(H, p), H @ H
    if p == 0:
        return (1.0, 0.0, 0.0)
    return (0.0, np.sum(M * H) / np.sum(H * H), np.sum(M * H2) / np.sum(H2 * H2))


def _recursive(a, p):
    # the formula by recursion, hat(a)^p = -|a|^2 hat(a)^(p-2): a helper of its own, itself
    a = np.asarray(a, dtype=float)
    if p <= 2:
        return _student(a, p)
    return tuple(-(a @ a) * np.asarray(_recursive(a, p - 2), dtype=float))


def _closure_route():
    power = np.linalg.matrix_power

    def answer(a, p):
        H = np.cross(np.eye(3), a)
        return (0.0, *np.asarray(power(H, p))[0, 1:])   # nonsense, refused before it runs
    return answer


def _loop_of_products(a, p):
    # a hand-built hat(a) and a loop of @: the one matrix route the checker cannot see
    a = np.asarray(a, dtype=float)
    H = np.array([[0, -a[2], a[1]], [a[2], 0, -a[0]], [-a[1], a[0], 0]])
    M = np.eye(3)
    for _ in range(p):
        M = M @ H
    if p == 0 or not a.any():                 # at a = 0 the read-off below is 0 / 0
        return (float(p == 0), 0.0, 0.0)
    H2 = H @ H
    return (0.0, np.sum(M * H) / np.sum(H * H), np.sum(M * H2) / np.sum(H2 * H2))


def _hand_hat(a):
    a = np.asarray(a, dtype=float)
    return np.array([[0, -a[2], a[1]], [a[2], 0, -a[0]], [-a[1], a[0], 0]])


def _fit(H, M):
    # the three coefficients of M on I, H, H^2, by the normal equations
    basis = np.stack([np.eye(3).ravel(), H.ravel(), (H @ H).ravel()], axis=1)
    return tuple(np.linalg.solve(basis.T @ basis, basis.T @ M.ravel()))


def _fractional_pinv(a, p):
    # scipy's matrix power and a pseudo-inverse fit: a matrix route by other names
    H = _hand_hat(a)
    M = np.real(scipy.linalg.fractional_matrix_power(H, p)) if p else np.eye(3)
    basis = np.stack([np.eye(3).ravel(), H.ravel(), (H @ H).ravel()], axis=1)
    return tuple(np.linalg.pinv(basis) @ M.ravel())


def _loop_solve(a, p):
    H, M = _hand_hat(a), np.eye(3)
    for _ in range(p):
        M = M @ H
    return _fit(H, M)


def _via_funm(a, p):
    # a matrix function that is the power: funm(H, x -> x^p)
    H = _hand_hat(a)
    M = np.real(scipy.linalg.funm(H, lambda x: x ** p))
    return (float(p == 0), np.sum(M * H) / max(np.sum(H * H), 1.0), 0.0)


def _eigen(a, p):
    H = _hand_hat(a)
    w, V = np.linalg.eig(H)
    M = np.real(V @ np.diag(w ** p) @ np.linalg.inv(V))
    return (1.0, 0.0, 0.0) if p == 0 else (0.0, np.sum(M * H) / np.sum(H * H),
                                           np.sum(M * (H @ H)) / np.sum((H @ H) ** 2))


def _own_solve():
    # a notebook whose helper, the formula, happens to be called `solve`
    space = {"np": np}
    exec("def solve(a, p):\n"
         "    if p == 0:\n"
         "        return (1.0, 0.0, 0.0)\n"
         "    c = (-1) ** ((p - 1) // 2) * (a @ a) ** ((p - 1) // 2)\n"
         "    return (0.0, c, 0.0) if p % 2 else (0.0, 0.0, c)\n"
         "def power_coefficients(a, p):\n"
         "    return solve(np.asarray(a, dtype=float), p)\n", space)
    return space["power_coefficients"]


def test_power_coefficients_right_answers_pass():
    fb = check_power_coefficients(_student)
    assert fb and repr(fb).startswith("Correct: power_coefficients"), repr(fb)
    assert "p = 400" in repr(fb) and "one of them 0" in repr(fb)


@pytest.mark.parametrize("student, names", [
    (_fitted, "hat, lstsq, matrix_power"),
    (_read_off, "cross, matrix_power"),
    (_nested, r"cross, hat, lstsq, matrix_power \(inside _fitted, _read_off\)"),
    (_via_helper, r"hat, lstsq, matrix_power \(inside _fitted\)"),
    (_renamed, "matrix_power"),
    (_closure_route(), "cross, matrix_power"),
    (_fractional_pinv, "fractional_matrix_power, pinv"),
    (_via_funm, "funm"),
    (_loop_solve, r"solve \(inside _fit\)"),
    (_eigen, "eig, inv"),
])
def test_power_coefficients_refuses_a_matrix_route(student, names):
    _says(check_power_coefficients(student), "power_coefficients",
          f"calls {names}(.|\n)*asks for the formula")


def test_power_coefficients_follows_helpers_without_false_alarms():
    # a learner's own helper that computes the formula (here the answer itself, by
    # recursion) is followed and passes
    fb = check_power_coefficients(_recursive)
    assert fb and repr(fb).startswith("Correct: power_coefficients"), repr(fb)
    # a helper named like a matrix route is the learner's own: followed, not refused
    fb = check_power_coefficients(_own_solve())
    assert fb and repr(fb).startswith("Correct: power_coefficients"), repr(fb)


def test_power_coefficients_cannot_see_a_loop_of_products():
    # documented limit (the task says so): only named matrix routes are refused
    assert check_power_coefficients(_loop_of_products)


def test_power_coefficients_tests_a_large_power():
    def right_only_up_to_12(a, p):
        c = _student(a, p)
        return c if p <= 12 else tuple(-np.asarray(c, dtype=float))
    _says(check_power_coefficients(right_only_up_to_12), "power_coefficients",
          r"power_coefficients\(\[0\.6, 0\. , 0\.8\], 400\)(.|\n)*p = 400 is even")


def _divides_by_norm(a, p):
    # hat(a)^p = |a|^p hat(n)^p, with the coefficient divided back by |a| (or |a|^2):
    # right for a != 0, NaN at a = 0
    a = np.asarray(a, dtype=float)
    r = np.linalg.norm(a)
    if p == 0:
        return (1.0, 0.0, 0.0)
    s = (-1) ** ((p - 1) // 2)
    with np.errstate(invalid="ignore", divide="ignore"):
        return (0.0, s * r**p / r, 0.0) if p % 2 else (0.0, 0.0, s * r**p / r**2)


def _divides_by_float_norm(a, p):
    r = float(np.sqrt(np.dot(a, a)))
    if p == 0:
        return (1.0, 0.0, 0.0)
    s = (-1) ** ((p - 1) // 2)
    return (0.0, s * r**p / r, 0.0) if p % 2 else (0.0, 0.0, s * r**p / r**2)


def _half_integer_k(a, p):
    # k = (p - 1) / 2 for every p: at an even p, (-1)**0.5 is complex
    if p == 0:
        return (1.0, 0.0, 0.0)
    k = (p - 1) / 2
    c = (-1) ** k * float(np.dot(a, a)) ** k
    return (0.0, c, 0.0) if p % 2 else (0.0, 0.0, c)


def _identity_at_zero(a, p):
    return (1.0, 0.0, 0.0) if not np.any(a) else _student(a, p)


def _forgets_identity(a, p):
    return _student(a, p) if p else (0.0, 0.0, -1.0 / float(np.dot(a, a)))


def _wrong_sign(a, p):
    return tuple(-np.asarray(_student(a, p))) if p >= 3 else _student(a, p)


def _uses_norm_not_square(a, p):
    if p == 0:
        return (1.0, 0.0, 0.0)
    k = (p - 1) // 2
    c = (-1) ** k * np.linalg.norm(a) ** k
    return (0.0, c, 0.0) if p % 2 else (0.0, 0.0, c)


@pytest.mark.parametrize("student, pattern", [
    (None, "No answer yet"),
    (..., "No answer yet"),
    (_not_written, "Not written yet"),
    (lambda a, p: 1 / 0, "raised ZeroDivisionError"),
    (lambda a, p: (0, 1), r"shape \(2,\); it should have shape \(3,\)"),
    (lambda a, p: (np.nan, 0, 0), "NaN or inf"),
    (lambda a, p: None, "returned None"),
    (_forgets_identity, r"power_coefficients\(.*, 0\)(.|\n)*hat\(a\)\^0 is the identity"),
    (_wrong_sign, r"minus hat\(a\)\^3(.|\n)*sign is wrong(.|\n)*p = 3 is odd"),
    (_uses_norm_not_square, r"p = 3 is odd(.|\n)*\(a @ a\)\*\*k|p = 4 is even"),
    (_divides_by_norm, r"\[0\., 0\., 0\.\], 1\), the answer contains NaN(.|\n)*At a = 0"),
    (_divides_by_float_norm, r"\[0\., 0\., 0\.\], 1\) raised ZeroDivisionError(.|\n)*At a = 0"),
    (_identity_at_zero, r"\[0\., 0\., 0\.\], 1\), c0 I(.|\n)*At a = 0"),
    (_half_integer_k, r", 2\), the answer contains a complex number(.|\n)*p = 2 is even"),
])
def test_power_coefficients_wrong_answers_get_a_message(student, pattern):
    _says(check_power_coefficients(student), "power_coefficients", pattern)


def _off_by_one(a, p):
    c = np.asarray(_student(a, p), dtype=float)
    return tuple(c + (c != 0)) if p else (1.0, 0.0, 0.0)


@pytest.mark.parametrize("student", [_forgets_identity, _wrong_sign, _uses_norm_not_square,
                                     _off_by_one, lambda a, p: (0.0, 1.0, 0.0)])
def test_power_coefficients_messages_show_no_expected_coefficients(student):
    text = repr(check_power_coefficients(student))
    assert "(1, 0, 0)" not in text and "expected" not in text, text
    # nothing measured against the answer: from the size of the difference and the
    # learner's own coefficient, the right one could be worked out. Only the input shown
    # (a and p) and the hint's small integers may appear.
    numbers = re.findall(r"\d+\.\d*[1-9]\d*|\de[+-]?\d+", text.split("\nHint:")[0])
    assert all(x in ("0.5", "0.25", "0.6", "0.8") for x in numbers), text


def _off_at(p_wrong):
    # right everywhere except at one p, where every coefficient is off by one
    def student(a, p):
        c = np.asarray(_student(a, p), dtype=float)
        return tuple(c + 1.0) if p == p_wrong else tuple(c)
    return student


@pytest.mark.parametrize("p_wrong", [1, 2, 3, 4, 5, 6, 11, 12, 400])
def test_power_coefficients_hints_do_not_work_the_case_out(p_wrong):
    # the vector a and p are shown with the hint; k's value and (1.7) or (1.8) written out
    # for that p would together be the expected coefficients of that case
    text = repr(check_power_coefficients(_off_at(p_wrong)))
    assert f"p = {p_wrong} is {'odd' if p_wrong % 2 else 'even'}" in text, text
    k = (p_wrong - 1) // 2
    for giveaway in (f"k = {k}", "(-1)^k", "c0 = c2 = 0", "c0 = c1 = 0"):
        assert giveaway not in text, text


def test_power_coefficients_gives_each_call_its_own_copy():
    # an answer that changes its argument in place is judged on what it returns (the
    # notebook's hidden test passes a copy to every call too)
    def squares_in_place(a, p):
        a **= 2
        return _student(np.sqrt(a), p)
    fb = check_power_coefficients(squares_in_place)
    assert fb, repr(fb)


def test_split_complex_parts_are_named():
    _says(check_split(lambda M: (M + 0j, 0 * M)), "split", "S contains a complex number")
