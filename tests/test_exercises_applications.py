"""The checkers of notebook 05 (so3lib.exercises.applications): right answers pass,
wrong ones get a message that names the mistake, and nothing raises."""

import re

import numpy as np
import pytest

from so3lib import exp, hat, log, vee
from so3lib.exercises import Feedback
from so3lib.exercises.applications import (check_angular_velocity, check_euler_stretch,
                                           check_interpolate, check_rotation_mean,
                                           interpolate_reference, rotation_mean_reference)


def _raise_not_implemented(*args):
    raise NotImplementedError


def _raise_value_error(*args):
    raise ValueError("boom")


def _assert_not_yet(fb, name, says):
    assert isinstance(fb, Feedback) and not fb
    text = repr(fb)
    assert text.startswith(f"Not yet: {name}"), text
    assert re.search(says, text), text


# --- common failure modes, for the three function exercises ---------------------------

FUNCTION_CHECKERS = [
    (check_interpolate, "interpolate", (3, 3)),
    (check_angular_velocity, "angular_velocity", (3,)),
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


# --- 5.1 interpolate ------------------------------------------------------------------

def test_interpolate_right_answer_passes():
    fb = check_interpolate(lambda R0, R1, s: R0 @ exp(log(R0.T @ R1), s))
    assert fb and repr(fb).startswith("Correct: interpolate")


def test_interpolate_left_form_is_also_right():
    # R0 exp(s log(R0^T R1)) = exp(s log(R1 R0^T)) R0: the same geodesic.
    assert check_interpolate(lambda R0, R1, s: exp(log(R1 @ R0.T), s) @ R0)


@pytest.mark.parametrize("student, says", [
    (lambda R0, R1, s: (1 - s) * R0 + s * R1, "entrywise blend"),
    (lambda R0, R1, s: exp(log(R0.T @ R1), s) @ R0, "on the right"),
    (lambda R0, R1, s: R0 @ exp(log(R1 @ R0.T), s), r"log\(R1 R0\^T\)"),
    (lambda R0, R1, s: R0 @ exp(log(R0.T @ R1), 1 - s), "backwards"),
    (lambda R0, R1, s: 2 * R0 @ exp(log(R0.T @ R1), s), "not a rotation"),
    (lambda R0, R1, s: (R0 @ exp(log(R0.T @ R1), s)).T, "transpose"),
])
def test_interpolate_typical_mistakes_are_named(student, says):
    fb = check_interpolate(student)
    _assert_not_yet(fb, "interpolate", says)
    assert "Hint:" in repr(fb)


def test_interpolate_reference_is_on_the_geodesic():
    R0, R1 = exp([0.3, -0.5, 0.2]), exp([-0.4, 0.9, 1.1])
    mid = interpolate_reference(R0, R1, 0.5)
    assert np.allclose(interpolate_reference(mid, R1, 1.0), R1)
    assert np.isclose(np.linalg.norm(log(R0.T @ mid)), 0.5 * np.linalg.norm(log(R0.T @ R1)))


# --- 5.2 Euler's stretch factor -------------------------------------------------------

def test_euler_stretch_right_answer_passes():
    assert check_euler_stretch(1.01 ** 100)


def test_euler_stretch_simulated_answer_passes():
    R, step = np.eye(3), np.eye(3) + 0.05 * hat([0.0, 0.0, 2.0])
    for _ in range(200):
        R = R @ step
    fb = check_euler_stretch(np.linalg.norm(R @ [1.0, 0.0, 0.0]))
    assert fb and "2.7" in repr(fb)


@pytest.mark.parametrize("answer, says", [
    (None, "No answer yet"),
    (..., "No answer yet"),
    ("about 2.7", "not a number"),
    ([2.7, 1.0], r"has shape \(2,\)"),
    (float("nan"), "NaN or inf"),
    (1.0, "not a rotation"),
    (1.01 ** 200, "squared length"),
    (1.1 ** 200, "right triangle"),
    (1.1 ** 100, "right triangle"),
    (np.sqrt(1.01), "one step"),
    (3.0, "expected 2.7048"),
])
def test_euler_stretch_wrong_answers_get_a_message(answer, says):
    fb = check_euler_stretch(answer)
    _assert_not_yet(fb, "the length", says)


# --- 5.3 angular velocity -------------------------------------------------------------

def test_angular_velocity_right_answer_passes():
    fb = check_angular_velocity(lambda R0, R1, dt: log(R0.T @ R1, dt))
    assert fb and repr(fb).startswith("Correct: angular_velocity")


@pytest.mark.parametrize("student, says", [
    (lambda R0, R1, dt: log(R1 @ R0.T, dt), "fixed"),
    (lambda R0, R1, dt: log(R0.T @ R1), "divide by dt"),
    (lambda R0, R1, dt: dt * log(R0.T @ R1), "multiplied by dt"),
    (lambda R0, R1, dt: vee(R0.T @ (R1 - R0) / dt, check=False), "finite difference"),
    (lambda R0, R1, dt: -log(R0.T @ R1, dt), "off by a sign"),
])
def test_angular_velocity_typical_mistakes_are_named(student, says):
    _assert_not_yet(check_angular_velocity(student), "angular_velocity", says)


# --- 5.4 weighted mean of rotations ---------------------------------------------------

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


def test_rotation_mean_reference_is_stationary_and_bi_invariant(rng):
    Rs = exp(0.5 * rng.standard_normal((8, 3)))
    w = rng.uniform(0.5, 2.0, 8)
    M = rotation_mean_reference(Rs, w)
    assert np.abs(w @ log(M.T @ Rs)).max() < 1e-12
    Q = exp([0.7, -0.2, 0.4])
    assert np.allclose(rotation_mean_reference(Q @ Rs @ Q.T, w), Q @ M @ Q.T, atol=1e-12)
    two = np.stack([exp([0.0, 0.0, 0.4]), exp([0.0, 0.0, -0.4])])
    assert np.allclose(rotation_mean_reference(two, [1.0, 3.0]), exp([0.0, 0.0, -0.2]))
