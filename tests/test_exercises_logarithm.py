"""The checkers of notebook 04 (so3lib.exercises.logarithm): a right answer passes; a
missing answer, a raising function, a wrong shape, NaN and the usual wrong answers each
get a helpful message, never an exception; no message prints the expected answer, and
exercise 4.4 notices a call to a logarithm."""

import numpy as np
import pytest
from checker_support import not_written as _not_written
from checker_support import says as _says

import so3lib
from so3lib.exercises.logarithm import (
    ROTATION_TOL_41,
    check_all_logs,
    check_halfturn_axis,
    check_log_at_pi,
    check_nan_rotation,
    notes_recipe,
)

# ----------------------------------------------------------------------- exercise 4.1

DIAG = np.array([1.0, 1.0, 0.0]) / np.sqrt(2.0)
HALF = 2 * np.outer(DIAG, DIAG) - np.eye(3)                # c = -1 - 2 eps: NaN
SIDE = np.array([1.0, 0.0, 1.0]) / np.sqrt(2.0)
HALF2 = 2 * np.outer(SIDE, SIDE) - np.eye(3)               # c = -1 - 2 eps: NaN


def test_notes_recipe_is_the_notes_formula():
    omega = np.array([0.3, -0.2, 0.5])
    assert np.allclose(notes_recipe(so3lib.exp(omega, 2.0), 2.0), omega)
    assert np.array_equal(notes_recipe(np.eye(3)), np.zeros(3))      # (4.7): sigma = 0


@pytest.mark.parametrize("R", [
    HALF,
    HALF2,
    np.array([[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0 + 2.0**-51]]),   # c = 1 + eps
])
def test_nan_rotation_right_answers_pass(R):
    fb = check_nan_rotation(R)
    assert fb and repr(fb).startswith("Correct: R_nan"), repr(fb)
    assert np.isnan(notes_recipe(R)).any()


def test_nan_rotation_shows_a_tiny_result_as_it_is_not_as_zero():
    text = repr(check_nan_rotation(so3lib.exp([0.0, 0.0, np.pi])))   # the recipe gives ~1.8e-08
    assert "e-08" in text and "[0., 0., 0.]" not in text, text


def test_the_checks_own_examples_are_rotations_to_rounding():
    for R in (HALF, HALF2):
        assert np.abs(R.T @ R - np.eye(3)).max() <= ROTATION_TOL_41
        assert so3lib.is_rotation(R)


def test_nan_rotation_says_why_the_identity_gives_zero():
    # c = 1: the guard of (4.7); c just below 1 (R R^T of a computed rotation, exactly
    # symmetric): n = 0. The hint must not blame the guard for the second.
    _says(check_nan_rotation(np.eye(3)), r"guard of \(4\.7\)")
    below = next(P for P in (Q @ Q.T for Q in so3lib.random_rotation(1, 200))
                 if (np.trace(P) - 1) / 2 < 1)
    _says(check_nan_rotation(below), r"R - R\^T \(twice the skew part\) is exactly 0")
    assert "guard" not in repr(check_nan_rotation(below))


@pytest.mark.parametrize("R, says", [
    (None, "No answer yet"),
    (..., "No answer yet"),
    ("R", "not a matrix of numbers"),
    (np.eye(2), r"shape \(2, 2\)"),
    (np.full((3, 3), np.nan), "NaN or inf itself"),
    (np.diag([1.0 + 1e-9, 1.0, 1.0]), "not a rotation to rounding"),
    (np.diag([1.0, 1.0, -1.0]), "det R"),
    (np.eye(3), "identity to rounding"),
    (so3lib.random_rotation(0) @ so3lib.random_rotation(0).T, "identity to rounding"),
    (2 * np.outer([0.6, 0.8, 0.0], [0.6, 0.8, 0.0]) - np.eye(3), "skew part is exactly 0"),
    (so3lib.exp([1e-9, 0.0, 0.0]), "silent 0"),
    (so3lib.exp([0.3, -0.4, 1.2]), "lies inside \\[-1, 1\\]"),
    (so3lib.exp([0.0, 0.0, np.pi]), "half-turn to rounding(.|\\n)*Try other axes"),
    (so3lib.exp([3e-8, 0.0, 0.0]), "within rounding of 1"),
])
def test_nan_rotation_wrong_answers_get_a_message(R, says):
    _says(check_nan_rotation(R), says)


# ----------------------------------------------------------------------- exercise 4.3

def _halfturn_axis(R):
    j = int(np.argmax(np.diag(R)))
    col = R[:, j] + np.eye(3)[:, j]
    return col / np.sqrt(2 * (R[j, j] + 1))


def test_halfturn_axis_right_answer_passes_with_either_sign():
    fb = check_halfturn_axis(_halfturn_axis)
    assert fb and repr(fb).startswith("Correct: halfturn_axis")
    assert "of 10 half-turns" in repr(fb), repr(fb)
    assert check_halfturn_axis(lambda R: -_halfturn_axis(R))


def _first_column(R):
    col = (R + np.eye(3))[:, 0]
    with np.errstate(invalid="ignore", divide="ignore"):
        return col / np.linalg.norm(col)


def _signs_from_row_one(R):
    """|n_j| from the diagonal (R_jj = 2 n_j^2 - 1), signs from row 1 (R_1j = 2 n_1 n_j):
    wrong where n_1 = 0 and the other two components have opposite signs."""
    n = np.sqrt(np.clip((np.diag(R) + 1) / 2, 0.0, None))
    return np.where(np.arange(3) > 0, np.where(R[0] < -1e-12, -n, n), n)


def _first_nonzero_column(R):
    """The first column of R + I that is not exactly zero: right on exact half-turns,
    wrong on computed ones, where a column that should be zero holds rounding noise."""
    M = R + np.eye(3)
    j = next(k for k in range(3) if M[:, k].any())
    return M[:, j] / np.linalg.norm(M[:, j])


def _first_column_above(R, small=1e-12):
    """The first column of R + I longer than ``small``: wrong where n_1 is 1e-9."""
    M = R + np.eye(3)
    j = next(k for k in range(3) if np.linalg.norm(M[:, k]) > small)
    return M[:, j] / np.linalg.norm(M[:, j])


def _signs_from_row_j(R):
    """|n_k| = sqrt((R_kk + 1)/2) from the diagonal, signs from row j of the largest
    diagonal entry: the square root halves the digits of a tiny n_k."""
    n = np.sqrt(np.clip((np.diag(R) + 1) / 2, 0.0, None))
    j = int(np.argmax(np.diag(R)))
    return np.where((R[j] < 0) & (np.arange(3) != j), -n, n)


def _skew_axis(R):
    v = np.array([R[2, 1] - R[1, 2], R[0, 2] - R[2, 0], R[1, 0] - R[0, 1]])
    with np.errstate(invalid="ignore", divide="ignore"):
        return v / np.linalg.norm(v)


@pytest.mark.parametrize("student, says", [
    (None, "No answer yet"),
    (..., "No answer yet"),
    (3, "Expected a function"),
    (_not_written, "Not written yet"),
    (lambda R: 1 / 0, "raised ZeroDivisionError(.|\\n)*column of R \\+ I"),
    (lambda R: None, "returned None"),
    (lambda R: np.eye(3), r"shape \(3, 3\); expected a vector"),
    (lambda R: "n", "not an array of numbers"),
    (lambda R: np.full(3, np.nan), "NaN or inf"),
    (_first_column, "largest diagonal entry"),
    (_signs_from_row_one, "which is not its axis"),
    (_skew_axis, "R - R\\^T \\(twice the skew part\\) is 0"),
    (_first_nonzero_column, "with rounding noise(.|\\n)*should be 0 \\(or tiny\\)"),
    (_first_column_above, "with rounding noise(.|\\n)*mostly noise"),
    # thresholds of 1e-8 and 1e-6 skip the 1e-9 axis's column, but not that of the axis
    # with a 1e-5 component, which gives the axis only to about 5e-11
    (lambda R: _first_column_above(R, 1e-8), "with rounding noise(.|\\n)*mostly noise"),
    (lambda R: _first_column_above(R, 1e-6), "with rounding noise(.|\\n)*mostly noise"),
    (_signs_from_row_j, "with rounding noise(.|\\n)*square root"),
    (lambda R: np.pi * _halfturn_axis(R), "logarithm pi n"),
    (lambda R: 2 * _halfturn_axis(R), "right direction, but length 2, not 1"),
    (lambda R: np.array([1.0, 0.0, 0.0]) if R[2, 2] > 0.9 else _halfturn_axis(R),
     "every column of R \\+ I is a multiple of n"),
    (lambda R: so3lib.log(R) / np.pi, "It calls log, a logarithm"),
    (lambda R: _halfturn_axis(R) if so3lib.angle(R) > 3 else None, "It calls angle"),
])
def test_halfturn_axis_wrong_answers_get_a_message(student, says):
    _says(check_halfturn_axis(student), says)


@pytest.mark.parametrize("factor", [np.pi, 2.0, 0.5])
def test_halfturn_axis_wrong_length_is_not_called_a_wrong_axis(factor):
    # a multiple of the axis gives 2 u u^T - I = R once normalised: the message must name
    # the length, not print "differs from R by 0" after "not its axis"
    text = repr(check_halfturn_axis(lambda R: factor * _halfturn_axis(R)))
    assert "right direction" in text and "not its axis" not in text, text
    assert "differs from R by 0" not in text, text


def test_halfturn_axis_messages_do_not_show_the_axis():
    text = repr(check_halfturn_axis(lambda R: np.array([0.0, 1.0, 0.0])))
    assert "expected" not in text and "+-[" not in text, text


# ----------------------------------------------------------------------- exercise 4.2

def _all_logs(R, bound):
    phi = so3lib.log(R)
    theta = np.linalg.norm(phi)
    kmax = int(bound / (2 * np.pi)) + 1
    ks = range(-kmax, kmax + 1)
    return [(theta + 2 * np.pi * k) * phi / theta for k in ks if abs(theta + 2 * np.pi * k) < bound]


def _all_logs_ks(R, bound, kmax):
    """A range of k that is too short: |k| <= kmax."""
    phi = so3lib.log(R)
    theta = np.linalg.norm(phi)
    return [(theta + 2 * np.pi * k) * phi / theta for k in range(-kmax, kmax + 1)
            if abs(theta + 2 * np.pi * k) < bound]


def test_all_logs_right_answer_passes_in_any_order():
    fb = check_all_logs(_all_logs)
    assert fb and repr(fb).startswith("Correct: all_logs")
    assert check_all_logs(lambda R, b: _all_logs(R, b)[::-1])
    assert check_all_logs(lambda R, b: np.array(_all_logs(R, b)))    # none: shape (0,)
    assert check_all_logs(lambda R, b: np.array(_all_logs(R, b)).reshape(-1, 3))


@pytest.mark.parametrize("student, says", [
    (None, "No answer yet"),
    (3, "Expected a function"),
    (_not_written, "Not written yet"),
    (lambda R, b: 1 / 0, "raised ZeroDivisionError"),
    (lambda R, b: None, "returned None"),
    (lambda R, b: np.zeros((2, 2)), r"shape \(2, 2\); expected shape \(m, 3\)"),
    (lambda R, b: np.full((2, 3), np.nan), "NaN or inf"),
    (lambda R, b: [p for p in _all_logs(R, b) if p @ so3lib.log(R) > 0], "k < 0 ones"),
    (lambda R, b: [so3lib.log(R)], "returned 1 logarithm, all right"),
    (lambda R, b: _all_logs(R, b)[:2], "negative ones included"),
    (lambda R, b: [-p for p in _all_logs(R, b)], "is not a logarithm of R"),
    (lambda R, b: [so3lib.log(R)] * 5, "the same logarithm"),
    (lambda R, b: _all_logs(R, b + 10), "not below the bound"),
    (lambda R, b: [["a", "b", "c"]], "not an array of numbers"),
    (lambda R, b: _all_logs_ks(R, b, int(b / (2 * np.pi))), "How far must k run"),
    (lambda R, b: _all_logs_ks(R, b, 3), "How far must k run"),
    (lambda R, b: _all_logs_ks(R, b, 10), "How far must k run"),     # a fixed range
    (lambda R, b: _all_logs_ks(R, b, 100), "all_logs\\(R, 2000\\)"),   # a generous one
    (lambda R, b: [so3lib.log(R)] + [p for p in _all_logs(R, b)
                                     if np.abs(p - so3lib.log(R)).max() > 1e-9],
     "all_logs\\(R, 2\\)(.|\\n)*not below the bound"),                  # Log R always
])
def test_all_logs_wrong_answers_get_a_message(student, says):
    _says(check_all_logs(student), says)


def test_all_logs_messages_do_not_print_the_lengths_expected():
    text = repr(check_all_logs(lambda R, b: [so3lib.log(R)]))
    assert "expected" not in text and "5.283" not in text and "7.283" not in text, text


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


def _by_log(n):
    return so3lib.log(2 * np.outer(n, n) - np.eye(3))


def _by_angle(n):
    R = 2 * np.outer(n, n) - np.eye(3)
    so3lib.angle(R)
    return _log_at_pi(n)


def _by_scipy(n):
    from scipy.spatial.transform import Rotation
    return Rotation.from_matrix(2 * np.outer(n, n) - np.eye(3)).as_rotvec()


@pytest.mark.parametrize("student, says", [
    (None, "No answer yet"),
    (3, "Expected a function"),
    (_not_written, "Not written yet"),
    (lambda n: 1 / 0, "raised ZeroDivisionError"),
    (lambda n: None, "returned None"),
    (lambda n: np.pi, r"shape \(\); expected a rotation vector"),
    (lambda n: np.full(3, np.nan), "NaN or inf"),
    (lambda n: np.pi * np.asarray(n), "pi n as given"),
    (_first_nonzero, "first nonzero component positive"),
    (lambda n: -_log_at_pi(n), "largest component"),
    (lambda n: 2 * _log_at_pi(n), "not \\+-pi n"),
    (_by_log, "It calls log, a logarithm"),
    (_by_angle, "It calls angle, a logarithm"),
    (_by_scipy, "a logarithm: the exercise asks"),
])
def test_log_at_pi_wrong_answers_get_a_message(student, says):
    _says(check_log_at_pi(student), says)


def test_log_at_pi_watch_leaves_no_profiler_behind():
    import sys
    check_log_at_pi(_by_log)
    check_log_at_pi(lambda n: 1 / 0)
    assert sys.getprofile() is None


def test_log_at_pi_watches_the_public_names_only():
    # The watch keys on the code of so3lib.log and so3lib.angle themselves, so a
    # rewrite of the library's private helpers cannot blind it.
    import so3lib
    from so3lib.exercises import logarithm as ex

    assert {so3lib.log.__code__, so3lib.angle.__code__} <= set(ex._LOG_CODES)
    _says(check_log_at_pi(lambda n: so3lib.log(2 * np.outer(n, n) - np.eye(3))),
          "It calls log, a logarithm")


def test_log_at_pi_watches_the_private_helpers():
    # Reaching into so3lib.so3 for the logarithm behind log() is still calling a logarithm.
    import so3lib.so3 as so3

    def by_log_one(n):
        R = 2 * np.outer(n, n) - np.eye(3)
        return np.array(so3._log_one(R.ravel().tolist(), 1.0))

    def by_log_block(n):
        R = 2 * np.outer(n, n) - np.eye(3)
        out = np.empty((1, 3))
        so3._log_block(R.reshape(1, 9).T.copy(), 1.0, out)
        return out[0]

    _says(check_log_at_pi(by_log_one), "It calls so3lib.so3._log_one, a logarithm")
    _says(check_log_at_pi(by_log_block), "It calls so3lib.so3._log_block, a logarithm")


# ----------------------------------------------------------------------- exercise 4.5

from so3lib.exercises.logarithm import LOG_TOL_45, check_principal_log  # noqa: E402


def _vee_skew(R):
    return np.array([R[2, 1] - R[1, 2], R[0, 2] - R[2, 0], R[1, 0] - R[0, 1]])


def _principal_log(R):
    """(4.9), (4.11), (4.15)-(4.16) in NumPy: the exercise's solution."""
    v = _vee_skew(R)
    s, c = np.linalg.norm(v) / 2, (np.trace(R) - 1) / 2
    theta = np.arctan2(s, c)
    if c >= 0:
        return np.zeros(3) if s == 0 else theta / (2 * s) * v
    B = (R + R.T) / 2 - c * np.eye(3)
    j = int(np.argmax(np.diag(B)))
    n = B[:, j] / np.linalg.norm(B[:, j])
    return theta * (n if n @ v >= 0 else -n)


def _skew_only(R):
    """(4.11) everywhere, with the atan2 angle and a branch at 0."""
    v = _vee_skew(R)
    s, c = np.linalg.norm(v) / 2, (np.trace(R) - 1) / 2
    return np.zeros(3) if s == 0 else np.arctan2(s, c) / (2 * s) * v


def _acos_angle(R, clip=True, guard=True):
    """The notes' arccos angle with (4.11) below pi/2 and (4.15)-(4.16) above."""
    c = (np.trace(R) - 1) / 2
    with np.errstate(all="ignore"):
        theta = np.arccos(np.clip(c, -1, 1) if clip else c)
        v = _vee_skew(R)
        if c >= 0:
            if guard and theta == 0:
                return np.zeros(3)
            return theta / (2 * np.sin(theta)) * v
    B = (R + R.T) / 2 - c * np.eye(3)
    j = int(np.argmax(np.diag(B)))
    n = B[:, j] / np.linalg.norm(B[:, j])
    return theta * (n if n @ v >= 0 else -n)


def _no_sign(R):
    c = (np.trace(R) - 1) / 2
    if c >= 0:
        return _principal_log(R)
    B = (R + R.T) / 2 - c * np.eye(3)
    j = int(np.argmax(np.diag(B)))
    n = B[:, j] / np.linalg.norm(B[:, j])
    return np.arctan2(np.linalg.norm(_vee_skew(R)) / 2, c) * n * (-1 if n[0] > 0.7 else 1)


def _no_zero_branch(R):
    v = _vee_skew(R)
    s, c = np.linalg.norm(v) / 2, (np.trace(R) - 1) / 2
    with np.errstate(all="ignore"):
        return _principal_log(R) if c < 0 else np.arctan2(s, c) / (2 * s) * v


def test_principal_log_right_answers_pass():
    fb = check_principal_log(_principal_log)
    assert fb and repr(fb).startswith("Correct: principal_log"), repr(fb)
    # either sign at a half-turn
    assert check_principal_log(lambda R: -_principal_log(R) if np.array_equal(R, R.T)
                               else _principal_log(R))
    # the solution meets its own tolerance with a wide margin on every case
    from so3lib.exercises.logarithm import _log_inputs
    for kind, _, R, p in _log_inputs():
        got = _principal_log(R)
        if kind in ("exp", "id"):
            assert np.abs(got - p).max() <= LOG_TOL_45 / 16 * min(1.0, np.linalg.norm(p) or 1.0)


def test_principal_log_so3lib_log_is_refused_but_would_pass():
    # so3lib.log is a correct answer (the property test does not compute one itself) ...
    from so3lib.exercises import logarithm as ex
    assert check_principal_log.__wrapped__ is not None
    _says(check_principal_log(so3lib.log), "It calls log, a logarithm")
    _says(check_principal_log(lambda R: so3lib.angle(R) * np.ones(3)), "It calls angle")

    def by_logm(R):
        from scipy.linalg import logm
        L = np.real(logm(R))
        return np.array([L[2, 1], L[0, 2], L[1, 0]])

    _says(check_principal_log(by_logm), "It calls scipy.linalg.logm, a logarithm")
    assert ex.LOG_TOL_45 == LOG_TOL_45


@pytest.mark.parametrize("student, says", [
    (None, "No answer yet"),
    (3, "Expected a function"),
    (_not_written, "Not written yet"),
    (lambda R: 1 / 0, "raised ZeroDivisionError"),
    (lambda R: None, "returned None"),
    (lambda R: np.zeros((3, 3)), r"shape \(3, 3\)"),
    (_no_zero_branch, "the identity(.|\\n)*0/0"),
    (lambda R: _acos_angle(R, guard=False), "the identity(.|\\n)*0/0"),
    (_acos_angle, "1e-9 rad(.|\\n)*rounds to exactly 1"),
    (_skew_only, "pi - 1e-4 rad(.|\\n)*not accurate near pi"),
    (lambda R: _acos_angle(R) if np.trace(R) > 1 else _principal_log(R),
     "1e-9 rad(.|\\n)*rounds to exactly 1"),
    (lambda R: _principal_log(R) if np.trace(R) > -0.5 else _acos_angle(R),
     "pi - 1e-4 rad(.|\\n)*not accurate near pi"),
    (_no_sign, "wrong sign(.|\\n)*\\(4\\.16\\)"),
    (lambda R: -_principal_log(R), "rotation by 1 rad(.|\\n)*off by a sign"),
    (lambda R: 2 * _principal_log(R), "exp of your answer is not R"),
    (lambda R: _principal_log(R) - 2 * np.pi * _principal_log(R)
     / max(np.linalg.norm(_principal_log(R)), 1e-300) if np.trace(R) < 0 else _principal_log(R),
     "more than pi|off by"),
    (lambda R: np.ones(3) if not np.any(R - np.eye(3)) else _principal_log(R),
     "the zero vector, \\(4\\.10\\)"),
])
def test_principal_log_wrong_answers_get_a_message(student, says):
    _says(check_principal_log(student), says)


def test_principal_log_names_the_symmetric_part_for_c_below_0():
    def plus_identity(R):           # (4.14)'s R + I used below pi: not parallel to n there
        if np.trace(R) >= 1:
            return _principal_log(R)
        v = _vee_skew(R)
        theta = np.arctan2(np.linalg.norm(v) / 2, (np.trace(R) - 1) / 2)
        B = R + np.eye(3)
        j = int(np.argmax(np.diag(B)))
        n = B[:, j] / np.linalg.norm(B[:, j])
        return theta * (n if n @ v >= 0 else -n)

    _says(check_principal_log(plus_identity), "2.5 rad(.|\\n)*mind the - c I")


def test_principal_log_zero_and_nan_at_an_exact_half_turn():
    def zero_at_pi(R):
        return np.zeros(3) if np.array_equal(R, R.T) and np.trace(R) < 0 else _principal_log(R)

    def nan_at_pi(R):
        return np.full(3, np.nan) if np.array_equal(R, R.T) and np.trace(R) < 0 \
            else _principal_log(R)

    _says(check_principal_log(zero_at_pi), "exact half-turn(.|\\n)*A zero at a half-turn")
    _says(check_principal_log(nan_at_pi), "exact half-turn(.|\\n)*NaN or inf(.|\\n)*symmetric")


def test_principal_log_messages_do_not_show_the_answer():
    for student in (_skew_only, _acos_angle, _no_sign, lambda R: np.ones(3)):
        text = repr(check_principal_log(student))
        assert "expected" not in text.lower().replace("expected a rotation vector", ""), text
        assert "1.5708" not in text, text


def test_principal_log_never_raises_and_leaves_no_profiler():
    import sys
    for student in (lambda R: R, lambda R: "x", lambda R: [1, 2], object()):
        assert not check_principal_log(student)
    assert sys.getprofile() is None
