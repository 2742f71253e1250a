"""Checkers of notebook 00 (so3lib.exercises.start_here): right predictions pass; missing,
wrong-shape, NaN and the usual wrong predictions get a message that names the mistake,
never an exception, and no message gives the answer away."""

import inspect
import math

import mpmath as mp
import numpy as np
import pytest
from checker_support import says_for as _says

from so3lib.exercises import start_here
from so3lib.exercises.start_here import check_nan_threshold, check_spin_prediction

SPIN = "your prediction for omega = (0, 0, 5)"
ANGLE = 2 * math.pi - 5                     # the shortest turn that reaches exp((0, 0, 5))
LOG = [0.0, 0.0, 5 - 2 * math.pi]


def test_module_holds_no_answer():
    public = [n for n, f in inspect.getmembers(start_here, inspect.isfunction)
              if f.__module__ == start_here.__name__ and not n.startswith("_")]
    assert sorted(public) == sorted(start_here.__all__) and all(n.startswith("check_") for n in public)
    source = inspect.getsource(start_here)
    for answer in ("2 * np.pi - 5", "2 * math.pi - 5", "5 - 2", "1.28", "1.05e-8", "1.8e-8"):
        assert answer not in source, answer


# ------------------------------------------------------------------ 0.1 predict the spin

@pytest.mark.parametrize("angle, log", [
    (ANGLE, LOG),
    (np.float64(ANGLE), np.array(LOG)),
    (ANGLE, (0, 0, 5 - 2 * np.pi)),
    (1.2832, [0.0, 0.0, -1.2832]),           # typed from what the solution cell prints
    (1.283, [0, 0, -1.283]),                 # three decimal places, as the task asks
])
def test_spin_prediction_right_answers_pass(angle, log):
    fb = check_spin_prediction(angle, log)
    assert fb and repr(fb).startswith(f"Correct: {SPIN}"), repr(fb)


@pytest.mark.parametrize("angle, log, pattern", [
    (None, LOG, "predicted_angle: No answer yet"),
    (ANGLE, ..., "predicted_log: No answer yet"),
    ("1.28", LOG, "text, not a number"),
    ([ANGLE, ANGLE], LOG, r"shape \(2,\)"),
    (float("nan"), LOG, "NaN or inf"),
    (1j, LOG, "complex"),
    (5.0, LOG, "5, the angle turned"),
    (-ANGLE, LOG, "negative"),
    (4.0, LOG, "more than pi"),
    (1.0, LOG, "not the angle of a turn that reaches R"),
    (1.28, LOG, "predicted_angle is close, but not to three decimal places"),
    (1.3, [0.0, 0.0, -1.3], "predicted_angle is close, but not to three decimal places"),
    (ANGLE, [0.0, 0.0, -1.28], "predicted_log is close, but not to three decimal places"),
    (1.283, [0.0, 0.0, 1.283], "wrong way round"),
    (ANGLE, np.eye(3), "3x3 matrix"),
    (ANGLE, [0.0, 5.0], r"shape \(2,\)"),
    (ANGLE, [0.0, 0.0, 5.0], "longer than pi"),
    (ANGLE, [0.0, 0.0, 2 * math.pi - 5], "wrong way round"),
    (ANGLE, [0.0, 0.0, 1.0], "not a rotation vector that reaches R"),
    (ANGLE, [ANGLE, 0.0, 0.0], "not a rotation vector that reaches R"),
])
def test_spin_prediction_wrong_answers_get_a_message(angle, log, pattern):
    fb = check_spin_prediction(angle, log)
    _says(fb, SPIN, pattern)
    assert "1.28" not in repr(fb) and "5 - 2" not in repr(fb)


def test_spin_prediction_angle_is_checked_by_the_trace_not_by_a_stored_value():
    # the property: cos(angle) = (tr R - 1)/2 = cos 5 with the angle in [0, pi]; at 50
    # digits the angle that has it is 2 pi - 5, and the checker accepts exactly that one
    with mp.workdps(50):
        exact = float(2 * mp.pi - 5)
    assert check_spin_prediction(exact, [0.0, 0.0, -exact])
    assert check_spin_prediction(exact + 5e-4, [0.0, 0.0, -exact])      # three decimals
    assert not check_spin_prediction(exact + 3e-3, [0.0, 0.0, -exact])
    assert not check_spin_prediction(exact, [0.0, 0.0, -exact - 3e-3])


# ------------------------------------------------------------------ 0.2 where NaN starts

def _recipe_nan(t):
    """The recipe, written here again (arccos of the trace, theta / (2 sin theta) times the
    skew part), at the turn by t about x: NaN or not."""
    c, s = math.cos(t), math.sin(t)
    trace = 1.0 + c + c
    with np.errstate(invalid="ignore", divide="ignore"):
        th = np.arccos(np.float64((trace - 1) / 2))
        return bool(np.isnan(th / (2 * np.sin(th)) * 2 * s))


def test_the_recipe_turns_nan_between_1e8_and_2e8():
    """The claim of notebook 00 (figure title, exercise 0.2's solution): NaN below about
    2e-8, a number above it; the edge is sqrt(1.5 eps) where cos rounds correctly."""
    eps = np.finfo(float).eps
    assert _recipe_nan(1e-8) and not _recipe_nan(2e-8)
    assert _recipe_nan(0.99 * math.sqrt(1.5 * eps)) and not _recipe_nan(1.01 * math.sqrt(1.5 * eps))
    assert math.cos(0.99 * math.sqrt(eps / 2)) == 1.0 and math.cos(1.01 * math.sqrt(eps / 2)) < 1.0


@pytest.mark.parametrize("t", [1e-8, math.sqrt(np.finfo(float).eps / 2), 1.5e-8, 2e-8, 5e-8])
def test_nan_threshold_right_answers_pass(t):
    fb = check_nan_threshold(t)
    assert fb and repr(fb).startswith("Correct: t_nan"), repr(fb)


@pytest.mark.parametrize("t, pattern", [
    (None, "No answer yet"),
    (..., "No answer yet"),
    ("1e-8", "text"),
    ([1e-8], r"shape \(1,\)"),
    (float("inf"), "NaN or inf"),
    (0.0, "between 0 and 1"),
    (-1e-8, "between 0 and 1"),
    (2.0, "between 0 and 1"),
    (np.finfo(float).eps, "three times your t_nan the recipe still returns NaN"),
    (3e-9, "three times your t_nan the recipe still returns NaN"),
    (1e-4, "a third of your t_nan the recipe still returns a number"),
    (1e-7, "a third of your t_nan the recipe still returns a number"),
])
def test_nan_threshold_wrong_answers_get_a_message(t, pattern):
    fb = check_nan_threshold(t)
    _says(fb, "t_nan", pattern)
    assert "e-08" not in repr(fb) and "e-8" not in repr(fb).replace(repr(t), "")
