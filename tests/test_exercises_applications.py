"""The checkers of notebook 05 (so3lib.exercises.applications): right answers pass, wrong
ones get a message that names the mistake, no message gives the answer away, the module
holds no answer, and nothing raises."""

import inspect
import math
import re

import mpmath
import numpy as np
import pytest

from so3lib import exp, hat, log
from so3lib.exercises import Feedback, applications
from so3lib.exercises.applications import (
    check_keyframes,
    check_rotation_mean,
    check_smooth_path,
    check_steps_needed,
    check_velocity_jump,
)


def _raise_not_implemented(*args):
    raise NotImplementedError


def _raise_value_error(*args):
    raise ValueError("boom")


def _assert_not_yet(fb, name, says):
    assert isinstance(fb, Feedback) and not fb
    text = repr(fb)
    assert text.startswith(f"Not yet: {name}"), text
    assert re.search(says, text), text


# --- common failure modes, for the four function exercises ----------------------------

FUNCTION_CHECKERS = [
    (check_keyframes, "keyframe_path", (3, 3)),
    (check_steps_needed, "steps_needed", ()),
    (check_velocity_jump, "velocity_jump", (3,)),
    (check_rotation_mean, "rotation_mean", (3, 3)),
]

COMMON_MISTAKES = [
    (None, "No answer yet"),
    (..., "No answer yet"),
    (42, "Expected a function"),
    (_raise_not_implemented, "Not written yet"),
    (_raise_value_error, "raised ValueError: boom"),
    (lambda *a: None, "returned None"),
    (lambda *a: np.zeros(7), r"has shape \(7,\); expected shape"),
    (lambda *a: "text", "not a number"),
]


@pytest.mark.parametrize("checker, name, shape", FUNCTION_CHECKERS)
@pytest.mark.parametrize("student, says", COMMON_MISTAKES)
def test_common_mistakes_get_a_message(checker, name, shape, student, says):
    _assert_not_yet(checker(student), name, says)


@pytest.mark.parametrize("checker, name, shape", FUNCTION_CHECKERS)
def test_nan_is_reported(checker, name, shape):
    _assert_not_yet(checker(lambda *a: np.full(shape, np.nan)), name, "NaN or inf")


def test_the_module_holds_no_answer():
    # Only checkers are public: no reference function a learner could import and pass.
    assert applications.__all__ == ["check_keyframes", "check_rotation_mean",
                                    "check_smooth_path", "check_steps_needed",
                                    "check_velocity_jump"]
    names = [n for n, f in inspect.getmembers(applications, inspect.isfunction)
             if f.__module__ == applications.__name__]
    assert not [n for n in names if "reference" in n]
    for name in names:
        if name.startswith("_") and name not in ("_ok", "_fail"):
            # no private helper takes the exercise's own arguments and returns an answer
            params = list(inspect.signature(getattr(applications, name)).parameters)
            assert params[:3] != ["Rs", "times", "t"] and params[:2] != ["Rs", "weights"], name


# --- 5.1 keyframes --------------------------------------------------------------------

def _keyframe_path(Rs, times, t):
    i = int(np.clip(np.searchsorted(times, t, side="right") - 1, 0, len(times) - 2))
    u = (t - times[i]) / (times[i + 1] - times[i])
    return Rs[i] @ exp(log(Rs[i].T @ Rs[i + 1]), u)


def _one_geodesic(Rs, times, t):
    return Rs[0] @ exp(log(Rs[0].T @ Rs[-1]), (t - times[0]) / (times[-1] - times[0]))


def _equal_spacing(Rs, times, t):
    k = len(times) - 1
    s = (t - times[0]) / (times[-1] - times[0]) * k
    j = int(np.clip(np.floor(s), 0, k - 1))
    return Rs[j] @ exp(log(Rs[j].T @ Rs[j + 1]), s - j)


def _blend(Rs, times, t):
    i = int(np.clip(np.searchsorted(times, t, side="right") - 1, 0, len(times) - 2))
    u = (t - times[i]) / (times[i + 1] - times[i])
    return (1 - u) * Rs[i] + u * Rs[i + 1]


def _right_side(Rs, times, t):
    i = int(np.clip(np.searchsorted(times, t, side="right") - 1, 0, len(times) - 2))
    u = (t - times[i]) / (times[i + 1] - times[i])
    return exp(log(Rs[i].T @ Rs[i + 1]), u) @ Rs[i]


def _world_step_on_the_right(Rs, times, t):
    # the world-frame step Log(R_(i+1) R_i^T) multiplied on the body side of R_i
    i = int(np.clip(np.searchsorted(times, t, side="right") - 1, 0, len(times) - 2))
    u = (t - times[i]) / (times[i + 1] - times[i])
    return Rs[i] @ exp(log(Rs[i + 1] @ Rs[i].T), u)


def _not_divided(Rs, times, t):
    i = int(np.clip(np.searchsorted(times, t, side="right") - 1, 0, len(times) - 2))
    return Rs[i] @ exp(log(Rs[i].T @ Rs[i + 1]), t - times[i])


def _projected_blend(Rs, times, t):
    U, _, Vt = np.linalg.svd(_blend(Rs, times, t))
    return U @ Vt


def test_keyframes_right_answers_pass():
    fb = check_keyframes(_keyframe_path)
    assert fb and repr(fb).startswith("Correct: keyframe_path")

    def world_form(Rs, times, t):              # the same geodesic, written in the world frame
        i = int(np.clip(np.searchsorted(times, t, side="right") - 1, 0, len(times) - 2))
        u = (t - times[i]) / (times[i + 1] - times[i])
        return exp(log(Rs[i + 1] @ Rs[i].T), u) @ Rs[i]
    assert check_keyframes(world_form)


@pytest.mark.parametrize("student, says", [
    (_blend, "entrywise blend"),
    (_one_geodesic, "one geodesic from the first keyframe to the last"),
    (_equal_spacing, "equally spaced"),
    (_right_side, "on the right"),
    (_world_step_on_the_right, "seen from the world frame"),
    (lambda Rs, times, t: Rs[0], "jumps from keyframe to keyframe|at a keyframe"),
    (_not_divided, "divide it by the segment's duration"),
    (_projected_blend, "pushed back onto SO\\(3\\) by an SVD"),
    (lambda Rs, times, t: 2 * _keyframe_path(Rs, times, t), "not a rotation"),
    (lambda Rs, times, t: _keyframe_path(Rs, times, t) @ exp([0.0, 0.0, 0.01]), "rad away"),
])
def test_keyframes_typical_mistakes_are_named(student, says):
    fb = check_keyframes(student)
    _assert_not_yet(fb, "keyframe_path", says)
    assert "Hint:" in repr(fb)


# --- 5.2 how many Euler steps keep the body's size ------------------------------------

def _length_mp(speed, T, N):
    # |R_N e_x| after N Euler steps, at 50 digits: (1 + (speed T / N)^2)^(N / 2).
    with mpmath.workdps(50):
        return (1 + (mpmath.mpf(speed) * T / N) ** 2) ** (mpmath.mpf(N) / 2)


def _steps_needed(speed, T, tol):
    # smallest N by simulation: matrix powers of one Euler step, from a low start
    def length(N):
        step = np.eye(3) + (T / N) * hat([0.0, 0.0, speed])
        return np.linalg.norm(np.linalg.matrix_power(step, N)[:, 0])
    N = max(1, int((speed * T) ** 2 / (2 * np.log1p(tol))) - 3)
    while N > 1 and length(N - 1) <= 1 + tol:
        N -= 1
    while length(N) > 1 + tol:
        N += 1
    return N


def test_steps_needed_cases_are_far_from_rounding():
    # Each case's answer N has length(N) <= 1 + tol < length(N - 1) at 50 digits, with a
    # margin far above float64 rounding, so a float simulation cannot land on the wrong N.
    for _, (speed, T, tol) in applications._STEPS_CASES:
        N = _steps_needed(speed, T, tol)
        with mpmath.workdps(50):
            assert _length_mp(speed, T, N) <= 1 + mpmath.mpf(tol) - mpmath.mpf("1e-12")
            if N > 1:
                assert _length_mp(speed, T, N - 1) >= 1 + mpmath.mpf(tol) + mpmath.mpf("1e-12")
        assert abs(applications._euler_length(speed, T, N) - float(_length_mp(speed, T, N))) < 1e-13


def test_steps_needed_right_answers_pass():
    fb = check_steps_needed(_steps_needed)
    assert fb and repr(fb).startswith("Correct: steps_needed")
    assert check_steps_needed(lambda v, T, tol: float(_steps_needed(v, T, tol)))


def _predicted(v, T, tol):
    return math.ceil((v * T) ** 2 / (2 * math.log1p(tol)))


def test_steps_needed_a_case_where_the_prediction_is_one_too_many():
    # the prediction alone is an approximation: on one case it overshoots by one step
    assert any(_predicted(*args) == _steps_needed(*args) + 1
               for _, args in applications._STEPS_CASES)
    assert any(_predicted(*args) == _steps_needed(*args) for _, args in applications._STEPS_CASES)


@pytest.mark.parametrize("student, says", [
    (None, "No answer yet"),
    (..., "No answer yet"),
    (lambda v, T, tol: "many", "not a number"),
    (lambda v, T, tol: [1, 2], r"has shape \(2,\)"),
    (lambda v, T, tol: float("nan"), "NaN or inf"),
    (lambda v, T, tol: _steps_needed(v, T, tol) - 1 if _steps_needed(v, T, tol) > 1 else 0,
     "too small|whole number"),
    (lambda v, T, tol: _steps_needed(v, T, tol) + 1, "smallest N"),
    (lambda v, T, tol: 0.5 + _steps_needed(v, T, tol), "whole number"),
    (lambda v, T, tol: _steps_needed(v, T, 2 * tol + tol**2), "too small"),
    (lambda v, T, tol: _steps_needed(v, T, np.sqrt(1 + tol) - 1), "squared length"),
    (lambda v, T, tol: 10**6, "smallest N"),
    (_predicted, "the prediction .* rounded up"),
    (lambda v, T, tol: max(1, int(np.floor((v * T) ** 2 / (2 * np.log1p(tol))))),
     r"length 1 \+ tol \+ \d"),
])
def test_steps_needed_wrong_answers_get_a_message(student, says):
    fb = check_steps_needed(student)
    _assert_not_yet(fb, "steps_needed", says)
    assert not re.search(r"expected (?!shape)", repr(fb)) and "20100" not in repr(fb)
    assert "Hint:" in repr(fb) or "No answer" in repr(fb)


# --- 5.3 the jump of the angular velocity ---------------------------------------------

def _jump(Rs, times):
    return log(Rs[1].T @ Rs[2]) / (times[2] - times[1]) - log(Rs[0].T @ Rs[1]) / (times[1] - times[0])


def test_velocity_jump_right_answers_pass():
    fb = check_velocity_jump(_jump)
    assert fb and repr(fb).startswith("Correct: velocity_jump")

    def rotated_first(Rs, times):               # omega_before seen from R1: the same vector
        before = log(Rs[0].T @ Rs[1]) / (times[1] - times[0])
        return log(Rs[1].T @ Rs[2]) / (times[2] - times[1]) - (Rs[1].T @ Rs[0]) @ before
    assert check_velocity_jump(rotated_first)


@pytest.mark.parametrize("student, says", [
    (lambda Rs, times: -_jump(Rs, times), "off by a sign"),
    (lambda Rs, times: Rs[1] @ _jump(Rs, times), "world frame"),
    (lambda Rs, times: log(Rs[1].T @ Rs[2]) - log(Rs[0].T @ Rs[1]), "divided by the time"),
    (lambda Rs, times: log(Rs[0].T @ Rs[2]) / (times[2] - times[0])
     - log(Rs[0].T @ Rs[1]) / (times[1] - times[0]), "from the middle keyframe"),
    (lambda Rs, times: np.zeros(3), "not the difference"),
    (lambda Rs, times: (log(Rs[1].T @ Rs[2]) - log(Rs[0].T @ Rs[1])) / (times[2] - times[1]),
     "divided by the time|its own segment's duration"),
])
def test_velocity_jump_typical_mistakes_are_named(student, says):
    fb = check_velocity_jump(student)
    _assert_not_yet(fb, "velocity_jump", says)
    assert "expected" not in repr(fb).lower()


# --- 5.5 weighted mean of rotations ---------------------------------------------------

def _karcher(Rs, weights):
    w = np.asarray(weights, float) / np.sum(weights)
    M = Rs[0]
    for _ in range(50):
        step = w @ log(M.T @ Rs)
        M = M @ exp(step)
        if np.linalg.norm(step) < 1e-13:
            break
    return M


def _karcher_unnormalised(Rs, weights):
    M = Rs[0]
    for _ in range(50):
        M = M @ exp(np.asarray(weights, float) @ log(M.T @ Rs))
    return M


def _chordal(Rs, weights):
    w = np.asarray(weights, float) / np.sum(weights)
    U, _, Vt = np.linalg.svd(np.einsum("i,ijk->jk", w, Rs))
    return U @ np.diag([1, 1, np.sign(np.linalg.det(U @ Vt))]) @ Vt


def test_rotation_mean_right_answer_passes():
    fb = check_rotation_mean(_karcher)
    assert fb and repr(fb).startswith("Correct: rotation_mean")


@pytest.mark.parametrize("student, says", [
    (lambda Rs, w: Rs.mean(axis=0), "entrywise mean"),
    (lambda Rs, w: np.einsum("i,ijk->jk", w / w.sum(), Rs), "entrywise mean"),
    (lambda Rs, w: _karcher(Rs, np.ones(len(Rs))), "weights were ignored"),
    (_chordal, "chordal mean"),
    (lambda Rs, w: Rs[0], "attitude error"),
    (_karcher_unnormalised, "sum of the weights"),
    (lambda Rs, w: 3 * _karcher(Rs, w), "not a rotation"),
])
def test_rotation_mean_typical_mistakes_are_named(student, says):
    _assert_not_yet(check_rotation_mean(student), "rotation_mean", says)


# --- 5.4 no kink: a geodesic cubic through the keyframes ---------------------------------

def _geo(P, Q, u):
    return P @ exp(log(P.T @ Q), u)


def _cubic(third=1 / 3, left=False, arrive_sign=-1, per_second=True):
    """De Casteljau with geodesics on each segment; the keywords make the usual mistakes."""
    def smooth_path(Rs, times, ws, t):
        i = int(np.clip(np.searchsorted(times, t, side="right") - 1, 0, len(times) - 2))
        h = times[i + 1] - times[i]
        u = (t - times[i]) / h
        k = third * (h if per_second else 1.0)
        if left:
            A, B = exp(k * ws[i]) @ Rs[i], exp(arrive_sign * k * ws[i + 1]) @ Rs[i + 1]
        else:
            A, B = Rs[i] @ exp(k * ws[i]), Rs[i + 1] @ exp(arrive_sign * k * ws[i + 1])
        P = [Rs[i], A, B, Rs[i + 1]]
        while len(P) > 1:
            P = [_geo(P[j], P[j + 1], u) for j in range(len(P) - 1)]
        return P[0]
    return smooth_path


def test_smooth_path_right_answer_passes():
    fb = check_smooth_path(_cubic())
    assert fb and repr(fb).startswith("Correct: smooth_path")


def _segment_geodesic(Rs, times, ws, t):
    return _keyframe_path(Rs, times, t)


@pytest.mark.parametrize("student, says", [
    (None, "No answer yet"),
    (42, "Expected a function"),
    (lambda Rs, times, ws, t: (_ for _ in ()).throw(NotImplementedError()), "Not written yet"),
    (lambda Rs, times, ws, t: 1 / 0, "raised ZeroDivisionError"),
    (lambda Rs, times, ws, t: None, "returned None"),
    (lambda Rs, times, ws, t: np.full((3, 3), np.nan), "NaN or inf"),
    (lambda Rs, times, ws, t: np.eye(3), "not at R_1"),
    (_segment_geodesic, "as in 5.1"),
    (_cubic(third=1.0), "3 times"),
    (_cubic(left=True), "another frame"),
    (_cubic(arrive_sign=+1), "wrong way"),
    (_cubic(per_second=False), "divided by the segment's duration"),
    (lambda Rs, times, ws, t: 1.5 * _cubic()(Rs, times, ws, t), "not at R_0|not a rotation"),
])
def test_smooth_path_typical_mistakes_are_named(student, says):
    fb = check_smooth_path(student)
    _assert_not_yet(fb, "smooth_path", says)
    assert "expected" not in repr(fb).lower() or "Expected a function" in repr(fb)


def test_smooth_path_kink_inside_a_segment_is_found():
    # Right at every keyframe, but the segment is two geodesic halves with a corner.
    right = _cubic()

    def cornered(Rs, times, ws, t):
        i = int(np.clip(np.searchsorted(times, t, side="right") - 1, 0, len(times) - 2))
        mid = 0.5 * (times[i] + times[i + 1])
        Rm = right(Rs, times, ws, mid) @ exp([0.0, 0.0, 0.05])
        if abs(t - times[i]) < 1e-3 or abs(t - times[i + 1]) < 1e-3:
            return right(Rs, times, ws, t)
        if t <= mid:
            return _geo(right(Rs, times, ws, times[i] + 1e-3), Rm,
                        (t - times[i] - 1e-3) / (mid - times[i] - 1e-3))
        return _geo(Rm, right(Rs, times, ws, times[i + 1] - 1e-3),
                    (t - mid) / (times[i + 1] - 1e-3 - mid))
    _assert_not_yet(check_smooth_path(cornered), "smooth_path", "kink inside the segment")
