r"""Checkers for the exercises of notebook 00, "Start here": two predictions.

=============  ===========================================  ================================
exercise       the learner writes                           checker
=============  ===========================================  ================================
0.1            ``predicted_angle`` and ``predicted_log``:   :func:`check_spin_prediction`
               what ``angle(R)`` and ``log(R)`` return for
               ``R = exp((0, 0, 5))``, spun for 1 s
               (to three decimal places)
0.2            ``t_nan``: the angle below which the         :func:`check_nan_threshold`
               textbook recipe for the logarithm returns
               NaN, to within a factor of 3
=============  ===========================================  ================================

Every checker returns a :class:`~so3lib.exercises.Feedback` and never raises. A checker
holds no answer: it tests the defining property of what the learner hands in. The angle
of 0.1 is the one number ``theta`` in ``[0, pi]`` with ``1 + 2 cos(theta) = tr R``; the
logarithm is a vector ``phi`` of length at most ``pi`` with ``exp(phi) = R`` (``so3lib.exp``
builds both sides). The threshold of 0.2 is right when the recipe gives NaN at a third of
it and a number at three times it. A wrong answer is named by the mistake it matches (the
angle turned instead of the principal one, the turn the wrong way round), never by its
distance from the right one.
"""

import math

import numpy as np

from ..so3 import exp
from . import Feedback, never_raises

__all__ = ["check_nan_threshold", "check_spin_prediction"]

_NOT_ANSWERED = ("No answer yet: replace the `...` (or `None`) with your answer and run "
                 "the cell again.")

#: The spin of exercise 0.1: omega = (0, 0, 5) rad/s for tau = 1 s.
OMEGA_SPIN = np.array([0.0, 0.0, 5.0])
#: How close exercise 0.1's numbers must be: the task asks for three decimal places.
TOL = 1e-3
#: Further off than TOL but within this: the right answer, typed with too few digits.
_NEAR = 0.05
_DIGITS = ("{} is close, but not to three decimal places: type more digits, or write it "
           "as an expression (np.pi is pi).")


def _fail(name, why, hint=None):
    """A "Not yet" Feedback: what is wrong, then the hint."""
    return Feedback(False, f"Not yet: {name}. {why}" + (f"\nHint: {hint}" if hint else ""))


def _number(x):
    """``(float, None)`` for a finite real number, else ``(None, sentence)``."""
    if x is None or x is Ellipsis:
        return None, _NOT_ANSWERED
    if isinstance(x, (str, bytes)):
        return None, "It is text, not a number: write the number itself, without quotes."
    try:
        if np.iscomplexobj(x):
            return None, "It is a complex number; it should be real."
        arr = np.asarray(x, dtype=float)
    except Exception:  # noqa: BLE001 -- a checker never raises
        return None, f"It is a {type(x).__name__}, not a number."
    if arr.shape != ():
        return None, f"It has shape {arr.shape}; it should be one number."
    if not np.isfinite(arr):
        return None, "It is NaN or inf."
    return float(arr), None


def _vector(x):
    """``(array of shape (3,), None)`` for three finite reals, else ``(None, sentence)``."""
    if x is None or x is Ellipsis:
        return None, _NOT_ANSWERED
    if isinstance(x, (str, bytes)):
        return None, "It is text, not a vector: write the three numbers, without quotes."
    try:
        if np.iscomplexobj(x):
            return None, "It contains a complex number; it should be real."
        arr = np.asarray(x, dtype=float)
    except Exception:  # noqa: BLE001 -- a checker never raises
        return None, f"It is a {type(x).__name__}, not three numbers."
    if arr.shape == (3, 3):
        return None, ("It is a 3x3 matrix; log returns a vector, three numbers "
                      "(an angular velocity times the time).")
    if arr.shape != (3,):
        return None, f"It has shape {arr.shape}; log returns three numbers, shape (3,)."
    if not np.isfinite(arr).all():
        return None, "It contains NaN or inf."
    return arr, None


# ---------------------------------------------------------------- exercise 0.1

_ANGLE_HINT = ("angle(R) reports the smallest turn that reaches R: a number from 0 to pi. "
               "Spinning 5 rad counter-clockwise ends where a shorter turn the other way "
               "ends. How long is that shorter turn?")
_LOG_HINT = ("log(R) is the rotation vector of that shortest turn: its length is angle(R) "
             "and exp of it must give R back. Which way round (the sign along z) does the "
             "shortest turn go?")


@never_raises("your prediction for omega = (0, 0, 5)")
def check_spin_prediction(predicted_angle, predicted_log):
    r"""Exercise 0.1: ``angle(R)`` and ``log(R)`` for ``R = exp((0, 0, 5))``.

    The angle must lie in :math:`[0, \pi]` and satisfy :math:`\cos\theta = \cos 5` (the
    trace of R is :math:`1 + 2\cos 5`); the vector must have length at most :math:`\pi`
    and exponentiate to R (``so3lib.exp`` on both sides). The task asks for three decimal
    places (or an expression), so each test holds to ``TOL`` = 1e-3: a value typed from
    the four decimals the solution cell prints passes. Recognises an answer that is right but typed with too few
    digits, the angle turned (5) in place of the principal angle, a negative angle, the
    vector (0, 0, 5) itself (exp gives R, but it is longer than pi), and the short turn
    taken the wrong way round.
    """
    name = "your prediction for omega = (0, 0, 5)"
    theta, why = _number(predicted_angle)
    if why:
        return _fail(name, "predicted_angle: " + why, None if why == _NOT_ANSWERED
                     else _ANGLE_HINT)
    phi, why = _vector(predicted_log)
    if why:
        return _fail(name, "predicted_log: " + why, None if why == _NOT_ANSWERED
                     else _LOG_HINT)
    R = exp(OMEGA_SPIN)
    tol = TOL
    in_range = -tol <= theta <= math.pi + tol
    off = abs(math.cos(theta) - math.cos(5.0))          # 0 for an angle that reaches R
    if not (in_range and off <= tol):
        if abs(theta - 5.0) <= tol:
            why = ("predicted_angle is 5, the angle turned. angle(R) sees only R, and R is "
                   "also reached by a shorter turn: it reports the shortest, from 0 to pi.")
        elif theta < -tol:
            why = ("predicted_angle is negative. angle(R) is a length, from 0 to pi: the "
                   "direction of the turn is in log's vector, not in the angle.")
        elif theta > math.pi + tol:
            why = "predicted_angle is more than pi, and angle(R) is always from 0 to pi."
        elif off <= _NEAR:
            why = _DIGITS.format("predicted_angle")
        else:
            why = ("with predicted_angle, 1 + 2 cos(angle) is not the trace of R: it is not "
                   "the angle of a turn that reaches R.")
        return _fail(name, why, _ANGLE_HINT)
    length = float(np.sqrt(phi @ phi))
    miss = float(np.abs(exp(phi) - R).max())
    reaches = miss <= tol
    if reaches and length <= math.pi + tol:
        if abs(length - theta) > 2 * tol:
            return _fail(name, "predicted_log is a logarithm of R, but its length is not "
                               "predicted_angle: the two predictions disagree.", _LOG_HINT)
        return Feedback(True, f"Correct: {name}. predicted_angle is in [0, pi] with "
                              "1 + 2 cos(angle) = tr R, and exp(predicted_log) is R with "
                              "|predicted_log| = predicted_angle (to three decimal places): "
                              "the shortest turn, the other way round.")
    if reaches:
        why = ("exp(predicted_log) is R, but predicted_log is longer than pi: log returns "
               "the shortest turn that reaches R, and this is a longer one.")
    elif float(np.abs(exp(-phi) - R).max()) <= _NEAR:
        why = ("predicted_log turns the wrong way round: exp of it is the turn that undoes "
               "R, not R. Going the short way from where 5 rad counter-clockwise ends means "
               "turning clockwise about z.")
    elif miss <= _NEAR and length <= math.pi + _NEAR:
        why = _DIGITS.format("predicted_log")
    else:
        why = "exp(predicted_log) is not R: it is not a rotation vector that reaches R."
    return _fail(name, why, _LOG_HINT)


# ---------------------------------------------------------------- exercise 0.2

def _recipe_nan(t):
    """True when the textbook recipe, theta = arccos((tr R - 1)/2) and
    phi = theta/(2 sin theta) (R - R^T)^vee, gives NaN at the turn by t about x written
    out from cos t and sin t (as notebook 00 does)."""
    c, s = np.cos(t), np.sin(t)
    R = np.array([[1.0, 0.0, 0.0], [0.0, c, -s], [0.0, s, c]])
    with np.errstate(invalid="ignore", divide="ignore"):
        theta = np.arccos((np.trace(R) - 1) / 2)
        phi = theta / (2 * np.sin(theta)) * np.array(
            [R[2, 1] - R[1, 2], R[0, 2] - R[2, 0], R[1, 0] - R[0, 1]])
    return bool(np.isnan(phi).any())


_NAN_HINT = ("The recipe divides 0 by 0 when arccos returns exactly 0, that is when "
             "(tr R - 1)/2 is exactly 1. Near 1, cos t = 1 - t^2/2 + ..., and the floats "
             "just below 1 are eps/2 apart (eps = 2.2e-16): below which t does 1 - t^2/2 "
             "round to 1?")


@never_raises("t_nan")
def check_nan_threshold(t_nan):
    r"""Exercise 0.2: the angle below which the recipe returns NaN, within a factor 3.

    The defining property, tested directly: the recipe gives NaN at ``t_nan / 3`` and a
    number at ``3 * t_nan``. Names which side is wrong, never how far.
    """
    name = "t_nan"
    t, why = _number(t_nan)
    if why:
        return _fail(name, why, None if why == _NOT_ANSWERED else _NAN_HINT)
    if not 0 < t < 1:
        return _fail(name, "t_nan should be an angle between 0 and 1 rad: the recipe works "
                           "at 1 rad, and at 0 there is nothing below.", _NAN_HINT)
    if not _recipe_nan(t / 3):
        return _fail(name, "At a third of your t_nan the recipe still returns a number: "
                           "it breaks only at smaller angles.", _NAN_HINT)
    if _recipe_nan(3 * t):
        return _fail(name, "At three times your t_nan the recipe still returns NaN: it "
                           "breaks at larger angles than that.", _NAN_HINT)
    return Feedback(True, f"Correct: {name}. The recipe returns NaN at a third of your "
                          "t_nan and a number at three times it.")
