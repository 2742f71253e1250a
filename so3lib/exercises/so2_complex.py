r"""Checkers for the exercises of notebook 03, "SO(2) and complex numbers".

=============  ==========================================  ==============================
exercise       the learner writes                          checker
=============  ==========================================  ==============================
3.1            ``so2_log(R)``, the angle of a 2x2          :func:`check_so2_log`
               rotation, in :math:`(-\pi, \pi]`
3.2            ``R_end``, the 2x2 rotation reached with    :func:`check_varying_rate`
               the rate :math:`\omega(t) = \omega_0 + a t`
               at ``t = T_END``
3.3            ``unflip(qs)``, a logged sequence of unit   :func:`check_unflip`
               quaternions with the sign jumps removed
               (the double cover)
=============  ==========================================  ==============================

Every checker returns a :class:`~so3lib.exercises.Feedback` and never raises. A checker
holds no answer: it tests the defining property of one (``cos`` and ``sin`` of the angle
give ``R``'s first column; ``R_end`` solves ``dR/dt = R omega(t) J``; each row is
``+-q_k`` and neighbours are close) and names the usual mistake, but never prints the
expected value.
"""


import numpy as np

from .. import so2
from . import Feedback, _calls_watched, check_function, never_raises

__all__ = [
    "ACCEL",
    "OMEGA0",
    "Q33",
    "T_END",
    "check_so2_log",
    "check_unflip",
    "check_varying_rate",
    "logged_quaternions",
]

#: Exercise 3.2: the rate starts at OMEGA0 = omega_0 (rad/s) and grows by ACCEL = a
#: (rad/s every second, rad/s^2) ...
OMEGA0 = 0.5
ACCEL = 2.0
#: ... until T_END (s).
T_END = 1.5


def _angle_matrix(alpha):
    return so2.exp(float(alpha))


def _fmt(a):
    return np.array2string(np.asarray(a, dtype=float) + 0.0, precision=4,
                           suppress_small=True, separator=", ")


def _not_answered(fb):
    return any(s in fb.message for s in ("No answer yet", "Not written yet",
                                         "Expected a function"))


# Simplest first: the message names the first input on which an answer goes wrong.
# -0.7 catches arccos (no sign), 2.5 and -2.5 catch arctan(R21 / R11) (wrong quadrant),
# 4.0 needs wrapping into (-pi, pi]. 1e-9 catches arccos given the sign of R21: cos(1e-9)
# rounds to 1, so arccos returns 0 there (the hidden test has the same angle). Last, two
# half-turns on which np.arctan2 returns the double -pi, outside the doubles (-pi, pi]
# (notebook 03, section 7): -np.eye(2), whose R21 is the float -0.0, and a half-turn whose
# R21 is -1e-16, not zero, yet too small to move atan2 off -pi.
_LOG_ANGLES = (0.5, -0.7, 2.5, -2.5, 4.0, 1e-9)
_HALF_TURN = "-np.eye(2)"
_NEAR_CUT = "[[-1, 1e-16], [-1e-16, -1]]"
_NEAR_CUT_R = np.array([[-1.0, 1e-16], [-1e-16, -1.0]])
#: cos and sin of the answer must give R's first column to this (float64 gives ~1e-16;
#: the hidden test asks 1e-12 of the angle itself).
_LOG_TOL = 1e-12


def _try_call(func, *args):
    """``func(*args)`` as a float array, or None if it raises or is not numeric."""
    try:
        out = np.asarray(func(*args), dtype=float)
        return out if np.isfinite(out).all() else None
    except Exception:  # noqa: BLE001 (a checker never raises)
        return None


def _so2_log_hint(func):
    """Recognise the usual slips of exercise 3.1 and say what went wrong."""
    got_pos = _try_call(func, _angle_matrix(0.5))
    if got_pos is not None and got_pos.shape == () and np.isclose(got_pos, -0.5):
        return ("For so2.exp(0.5) you returned -0.5: the sign is flipped. R[0, 1] is -sin a; "
                "the sine is R[1, 0], below the diagonal.")
    got_neg = _try_call(func, _angle_matrix(-0.7))
    if got_neg is not None and got_neg.shape == () and np.isclose(got_neg, 0.7):
        return ("For so2.exp(-0.7) you returned +0.7: the sign of alpha is lost (arccos of "
                "R[0, 0], for one, always returns a value in [0, pi]). Use the sine R[1, 0] "
                "as well.")
    got_q2 = _try_call(func, _angle_matrix(2.5))
    if got_q2 is not None and got_q2.shape == () and np.isclose(got_q2, 2.5 - np.pi):
        return ("For so2.exp(2.5) you returned 2.5 - pi: arctan(R[1, 0] / R[0, 0]) only "
                "sees the ratio sin/cos, so it cannot tell the second quadrant from the "
                "fourth. np.arctan2(sine, cosine) looks at both signs.")
    got_deg = _try_call(func, _angle_matrix(0.5))
    if got_deg is not None and got_deg.shape == () and np.isclose(got_deg, np.degrees(0.5)):
        return "The answer looks like degrees; the course works in radians."
    return ("R = [[cos a, -sin a], [sin a, cos a]]: the first column holds (cos a, sin a). "
            "Which NumPy function turns a (sine, cosine) pair into an angle in (-pi, pi]?")


@never_raises("so2_log")
def check_so2_log(func):
    r"""Exercise 3.1: ``func(R)`` must return the signed angle :math:`\alpha \in (-\pi, \pi]` of a
    planar rotation ``R`` (notebook 03, equation (3.12)).

    Tests the defining property on so2.exp(t) for t = 0.5, -0.7, 2.5, -2.5, 4.0 and 1e-9,
    and on two half-turns, ``-np.eye(2)`` (whose ``R[1, 0]`` is ``-0.0``) and
    ``[[-1, 1e-16], [-1e-16, -1]]``: the result lies in the doubles ``(-np.pi, np.pi]`` (the
    course's convention: the double ``-np.pi`` is never returned, a half-turn is ``np.pi``)
    and its cosine and sine are ``R[0, 0]`` and ``R[1, 0]`` to 1e-12.
    Names the usual slips: arccos of ``R[0, 0]`` (loses the sign, and at 1e-9 every digit,
    even with the sign of ``R[1, 0]`` attached), arctan of the ratio (loses the quadrant), a
    sign flipped by reading ``R[0, 1]``, degrees, a complex logarithm :math:`j\alpha`, lost
    precision, and plain ``np.arctan2`` next to the cut (returns the double ``-np.pi``, or with
    an atan2 that is only faithful the double below it). Refuses a
    function that calls ``so2.log``, which the exercise asks the learner to write.
    """
    name = "so2_log"
    if func is None or func is Ellipsis or not callable(func):
        return check_function(func, None, [], name)
    if func is so2.log:
        return Feedback(False, f"Not yet: {name}. That is so3lib's own so2.log; the exercise "
                               "asks you to write it from the entries of R.")
    for t in (*_LOG_ANGLES, _HALF_TURN, _NEAR_CUT):
        R = {_HALF_TURN: -np.eye(2), _NEAR_CUT: _NEAR_CUT_R}.get(t) if isinstance(t, str) \
            else _angle_matrix(t)
        label = t if isinstance(t, str) else f"so2.exp({t:g})"
        try:
            # every call of so2.log, however the learner's code reached it
            with _calls_watched({so2.log.__code__: "so2.log"}.get) as calls:
                got = func(R.copy())
        except NotImplementedError:
            return Feedback(False, f"Not yet: {name}. Not written yet: the function still "
                                   "raises NotImplementedError.")
        except Exception as err:  # noqa: BLE001 (the learner's code may raise anything)
            return Feedback(False, f"Not yet: {name}. Calling it on {label} raised "
                                   f"{type(err).__name__}: {err}")
        if calls:
            return Feedback(False, f"Not yet: {name}. Your function calls so2.log, which the "
                                   "exercise asks you not to use: compute the angle from the "
                                   "entries of R yourself.")
        if got is None:
            return Feedback(False, f"Not yet: {name}. It returned None on {label}: is the "
                                   "`return` missing?")
        if np.iscomplexobj(got):
            return Feedback(False, f"Not yet: {name}. On {label} it returned a complex number; "
                                   "the angle is a real number (for z = e^(j alpha), "
                                   "Log z = j alpha: alpha is its imaginary part).")
        try:
            a = np.asarray(got, dtype=float)
        except (TypeError, ValueError):
            return Feedback(False, f"Not yet: {name}. On {label} it returned a "
                                   f"{type(got).__name__}, not a number.")
        if a.shape != ():
            return Feedback(False, f"Not yet: {name}. On {label} the answer has shape "
                                   f"{a.shape}; expected shape () (one angle).")
        if not np.isfinite(a):
            return Feedback(False, f"Not yet: {name}. On {label} the answer is NaN or inf.")
        alpha = float(a)
        miss = max(abs(np.cos(alpha) - R[0, 0]), abs(np.sin(alpha) - R[1, 0]))
        same = miss <= _LOG_TOL
        if same and -np.pi < alpha <= np.pi:
            continue
        if same and t == _HALF_TURN:
            return Feedback(False, f"Not yet: {name}. On {label} it returned {alpha:.6g}, "
                                   "the double -np.pi, outside (-np.pi, np.pi]: this "
                                   "half-turn's R[1, 0] is the float -0.0, and "
                                   "np.arctan2(-0.0, -1.0) returns -np.pi.\nHint: return "
                                   "np.pi wherever np.arctan2 gives -np.pi or less.")
        if same and t == _NEAR_CUT:
            return Feedback(False, f"Not yet: {name}. On {label} it returned {alpha:.6g}, "
                                   "at or below the double -np.pi, outside (-np.pi, np.pi]. "
                                   "R[1, 0] is -1e-16 here, not zero, but -pi + 1e-16 rounds "
                                   "to the double -np.pi (a maths library that is not "
                                   "correctly rounded may even give the double below it): a "
                                   "test for R[1, 0] == 0 misses it.\nHint: look at what "
                                   "np.arctan2 returned, not at R: return np.pi wherever it "
                                   "gives -np.pi or less.")
        if same:
            return Feedback(False, f"Not yet: {name}. On {label} it returned {alpha:.6g}: "
                                   "the right rotation, but outside (-pi, pi].\nHint: the "
                                   "principal angle is the one in (-pi, pi]; np.arctan2 "
                                   "returns it directly.")
        if t == 1e-9 and alpha == 0.0:
            return Feedback(False, f"Not yet: {name}. On {label} it returned 0: every digit "
                                   "of this tiny angle is lost. cos(1e-9) = 1 - 5e-19 rounds "
                                   "to exactly 1.0, so arccos(R[0, 0]) gives 0 whatever sign "
                                   "you attach.\nHint: the sine R[1, 0] still holds the "
                                   "angle; use both entries.")
        if miss < 1e-4:
            return Feedback(False, f"Not yet: {name}. On {label} its cosine and sine miss R's "
                                   f"first column by {miss:.1e}, more than the {_LOG_TOL:g} "
                                   "float64 allows: digits are lost somewhere (single "
                                   "precision, rounding, or a formula that loses accuracy "
                                   "at this angle).\nHint: work in float64 from both "
                                   "entries R[1, 0] and R[0, 0]; a function that takes the "
                                   "pair (sine, cosine) keeps every digit at every angle.")
        return Feedback(False, f"Not yet: {name}. On {label} it returned {alpha:.6g}, whose "
                               "cosine and sine are not R's first column.\nHint: "
                               + _so2_log_hint(func))
    return Feedback(True, f"Correct: {name}. Its angles lie in (-pi, pi] and give R back "
                          f"on {len(_LOG_ANGLES) + 2} rotations, two half-turns on the cut "
                          "and next to it included.")


def _integrate_rate(T, steps=1000):
    """R(T) for dR/dt = R (omega0 + a t) J, R(0) = I, by the classical Runge-Kutta method:
    the definition of the motion, with no formula for its answer (error 6e-12 at T_END
    with 1000 steps, far below the 1e-9 the check allows)."""
    J = so2.J
    R, h = np.eye(2), T / steps
    for i in range(steps):
        t = i * h
        k1 = R @ ((OMEGA0 + ACCEL * t) * J)
        k2 = (R + h / 2 * k1) @ ((OMEGA0 + ACCEL * (t + h / 2)) * J)
        k3 = (R + h / 2 * k2) @ ((OMEGA0 + ACCEL * (t + h / 2)) * J)
        k4 = (R + h * k3) @ ((OMEGA0 + ACCEL * (t + h)) * J)
        R = R + h / 6 * (k1 + 2 * k2 + 2 * k3 + k4)
    return R


@never_raises("the rotation R_end at t = T_END")
def check_varying_rate(answer):
    r"""Exercise 3.2: the 2x2 rotation reached at ``T_END`` by the rate
    :math:`\omega(t) = \omega_0 + a t` starting from the identity.

    Tests the definition: ``answer`` must agree, within 1e-9, with the solution of
    :math:`\dot R = R\,\omega(t)J`, :math:`R(0) = I`, integrated numerically (RK4).
    Recognises the rate taken at the end or at the start instead of its integral, the
    transpose, a matrix that is not a rotation, and an angle handed in instead of the
    matrix. A near miss (an entry off by less than 0.05) is told its size, not its angle,
    which would print close to the answer's.
    """
    name = "the rotation R_end at t = T_END"
    hint = ("Integrate the rate: in the plane rotations commute, so only the total angle "
            "int_0^T omega(t) dt matters (3.13); then pass it to so2.exp.")
    if answer is None or answer is Ellipsis:
        return Feedback(False, f"Not yet: {name}. No answer yet: replace the `...` with a "
                               "2x2 rotation matrix and run the cell again.")
    if np.iscomplexobj(answer):
        return Feedback(False, f"Not yet: {name}. You gave a complex number; the exercise "
                               "asks for the 2x2 rotation matrix: so2.from_complex turns a "
                               "unit complex number into one (3.9).")
    try:
        arr = np.asarray(answer, dtype=float)
    except (TypeError, ValueError):
        return Feedback(False, f"Not yet: {name}. The answer is a {type(answer).__name__}, "
                               "not a number or an array of numbers.")
    if not np.isfinite(arr).all():
        return Feedback(False, f"Not yet: {name}. The answer contains NaN or inf.")
    if arr.shape == ():
        return Feedback(False, f"Not yet: {name}. You gave a number; the exercise asks for "
                               "the 2x2 rotation matrix: pass the angle to so2.exp.")
    if arr.shape != (2, 2):
        return Feedback(False, f"Not yet: {name}. The answer has shape {arr.shape}; a "
                               "planar rotation is a 2x2 matrix.")
    reached = _integrate_rate(T_END)
    if np.abs(arr - reached).max() <= 1e-9:
        return Feedback(True, f"Correct: {name}. It agrees with the motion integrated step "
                              "by step (RK4).")
    off_orth = float(np.abs(arr.T @ arr - np.eye(2)).max())
    det = float(np.linalg.det(arr))
    if off_orth > 1e-6 or abs(det - 1.0) > 1e-6:
        return Feedback(False, f"Not yet: {name}. Your matrix is not a rotation: R^T R "
                               f"differs from I by {off_orth:.2g} and det R = {det:.4g}; a "
                               "rotation has R^T R = I and det R = 1.\nHint: build it with "
                               "so2.exp(angle), or as [[cos, -sin], [sin, cos]] of one "
                               "angle.")
    miss = float(np.abs(arr - reached).max())
    if miss < 0.05:
        # A near miss: its angle would print as the answer's, so give the size of the miss.
        why = (f"Your matrix is close, but an entry is off by {miss:.1e}, more than the 1e-9 "
               "the check allows: compute the angle exactly (the integral in closed form), "
               "not by a numerical sum.")
    else:
        turned = float(np.arctan2(arr[1, 0], arr[0, 0]))
        why = f"Your matrix turns by {turned:.4g} rad (mod 2 pi); the motion ends elsewhere."
    if np.abs(arr - reached.T).max() <= 1e-9:
        why += " It is the transpose of the rotation reached: it turns the other way."
    for label, wrong in (("the rate at the end times T", (OMEGA0 + ACCEL * T_END) * T_END),
                         ("the rate at the start times T", OMEGA0 * T_END)):
        if np.allclose(arr, so2.exp(wrong), atol=1e-8):
            hint = (f"Your matrix turns by {label}. The rate changes during the motion; the "
                    "angle is its integral.")
    return Feedback(False, f"Not yet: {name}. {why}\nHint: {hint}")


# --------------------------------------------------------------------------- 3.3

def logged_quaternions(seed, m=41):
    r"""A logged attitude: unit quaternions ``(w, x, y, z)`` of a body that turns by
    :math:`3.2\pi` about a slowly tilting axis, sampled ``m`` times, as a logger stores
    them: its conversion returns whichever of :math:`\pm q` has :math:`w \ge 0`, and some
    rows are stored with the other sign. Data for exercise 3.3 (notebook 03).

    Returns
    -------
    qs : ndarray, shape (m, 4)
    """
    rng = np.random.default_rng(seed)
    t = np.linspace(0.0, 1.0, m)
    theta = 3.2 * np.pi * t
    axis = np.stack([np.cos(1.5 * t), np.sin(1.5 * t), np.full_like(t, 1.0)], axis=1)
    axis /= np.linalg.norm(axis, axis=1, keepdims=True)
    qs = np.concatenate([np.cos(theta / 2)[:, None], np.sin(theta / 2)[:, None] * axis],
                        axis=1)
    flip = (qs[:, 0] < 0) ^ (rng.random(m) < 0.2)
    flip[0] = False
    qs[flip] *= -1.0
    return qs


#: Exercise 3.3: a logged attitude with sign jumps, one quaternion (w, x, y, z) per row.
Q33 = logged_quaternions(33)
Q33.setflags(write=False)

_UNFLIP_INPUTS = [Q33, logged_quaternions(7, 30), logged_quaternions(2026, 57)]


@never_raises("unflip")
def check_unflip(func):
    r"""Exercise 3.3: ``func(qs)`` must return the logged quaternions with the sign jumps
    removed.

    Tests the defining properties on three logs: the same shape; row 0 unchanged; every
    row ``+-`` the logged one (the same rotation, by the double cover); and neighbouring
    rows close, :math:`q_k \cdot q_{k-1} > 0`. Recognises the usual slip, comparing a row
    with the *logged* previous row instead of the corrected one, and the logger's own
    rule (:math:`w \ge 0`), which is what made the jumps.
    """
    name = "unflip"
    if func is None or func is Ellipsis or not callable(func):
        return check_function(func, None, [], name)
    for i, qs in enumerate(_UNFLIP_INPUTS):
        label = "Q33" if i == 0 else f"test log {i + 1} ({len(qs)} rows)"
        try:
            got = func(np.array(qs, copy=True))
        except NotImplementedError:
            return Feedback(False, f"Not yet: {name}. Not written yet: the function still "
                                   "raises NotImplementedError.")
        except Exception as err:  # noqa: BLE001 (the learner's code may raise anything)
            return Feedback(False, f"Not yet: {name}. On {label} it raised "
                                   f"{type(err).__name__}: {err}")
        if got is None:
            return Feedback(False, f"Not yet: {name}. It returned None on {label}: is the "
                                   "`return` missing?")
        try:
            a = np.asarray(got, dtype=float)
        except (TypeError, ValueError):
            return Feedback(False, f"Not yet: {name}. On {label} it returned a "
                                   f"{type(got).__name__}, not an array of numbers.")
        if a.shape != qs.shape:
            return Feedback(False, f"Not yet: {name}. On {label} it returned shape "
                                   f"{a.shape}; expected the input's shape {qs.shape}.")
        if not np.isfinite(a).all():
            return Feedback(False, f"Not yet: {name}. On {label} it returned NaN or inf.")
        if np.abs(a[0] - qs[0]).max() > 1e-12:
            return Feedback(False, f"Not yet: {name}. On {label} row 0 changed; keep the "
                                   "first quaternion as logged, and fix the others to "
                                   "follow it.")
        plus = np.abs(a - qs).max(axis=1) <= 1e-12
        minus = np.abs(a + qs).max(axis=1) <= 1e-12
        if not (plus | minus).all():
            k = int(np.flatnonzero(~(plus | minus))[0])
            return Feedback(False, f"Not yet: {name}. On {label} row {k} is {_fmt(a[k])}, "
                                   "neither q_k nor -q_k: that is another rotation.\nHint: "
                                   "only the sign of a row may change.")
        dots = np.einsum("ij,ij->i", a[1:], a[:-1])
        if (dots > 0).all():
            continue
        k = int(np.flatnonzero(dots <= 0)[0]) + 1
        if (a[:, 0] >= 0).all():
            hint = ("You made every w >= 0. That is the logger's own rule, and it is what "
                    "made the jumps: a path that turns past pi reaches w < 0 smoothly.")
        elif minus[k - 1] and a[k] @ qs[k - 1] > 0:
            hint = ("You compared row k with the *logged* row k - 1, but that row had been "
                    "flipped itself. Compare with the row you have already corrected.")
        else:
            hint = ("Walk down the rows and flip q_k when q_k . q_(k-1) < 0, with q_(k-1) "
                    "the row you have already corrected.")
        return Feedback(False, f"Not yet: {name}. On {label} rows {k - 1} and {k} still "
                               f"jump: their dot product is {dots[k - 1]:.3f}, not "
                               f"positive.\nHint: {hint}")
    return Feedback(True, f"Correct: {name}. On {len(_UNFLIP_INPUTS)} logs every row is "
                          "the logged rotation and neighbours never jump.")
