r"""Checkers for the exercises of notebook 03, "SO(2) and complex numbers".

=============  ==========================================  ==============================
exercise       the learner writes                          checker
=============  ==========================================  ==============================
3.1            ``so2_log(R)``, the angle of a 2x2          :func:`check_so2_log`
               rotation, in :math:`(-\pi, \pi]`
3.2            ``R_end``, the 2x2 rotation reached with    :func:`check_varying_rate`
               the rate :math:`\omega(t) = \omega_0 + a t`
               at ``t = T_END``
3.3            ``quaternion(n, theta)``, the unit          :func:`check_quaternion`
               quaternion ``(w, x, y, z)`` of the
               rotation by ``theta`` about ``n``
=============  ==========================================  ==============================

Every checker returns a :class:`~so3lib.exercises.Feedback` and never raises.
"""

import numpy as np

from .. import so2
from . import Feedback, check_function, check_value, never_raises

__all__ = ["check_so2_log", "check_varying_rate", "check_quaternion", "quaternion",
           "OMEGA0", "ACCEL", "T_END"]

#: Exercise 3.2: the rate starts at OMEGA0 = omega_0 (rad/s) and grows by ACCEL = a
#: (rad/s every second, rad/s^2) ...
OMEGA0 = 0.5
ACCEL = 2.0
#: ... until T_END (s).
T_END = 1.5


def _angle_matrix(theta):
    return so2.exp(float(theta))


# Simplest first: the message names the first input on which an answer goes wrong.
# -0.7 catches arccos (no sign), 2.5 and -2.5 catch arctan(R21 / R11) (wrong quadrant),
# 4.0 needs wrapping into (-pi, pi].
_LOG_ANGLES = (0.5, -0.7, 2.5, -2.5, 4.0)
_LOG_INPUTS = [(_angle_matrix(t),) for t in _LOG_ANGLES]


def _try_call(func, *args):
    """``func(*args)`` as a float array, or None if it raises or is not numeric."""
    try:
        out = np.asarray(func(*args), dtype=float)
        return out if np.isfinite(out).all() else None
    except Exception:
        return None


def _so2_log_hint(func):
    """Recognise the two usual slips of exercise 3.1 and say what went wrong."""
    got_neg = _try_call(func, _angle_matrix(-0.7))
    if got_neg is not None and got_neg.shape == () and np.isclose(got_neg, 0.7):
        return ("For the rotation by -0.7 rad you returned +0.7: the cosine R[0, 0] alone "
                "cannot tell +theta from -theta (arccos always returns a value in [0, pi]). "
                "Use the sine R[1, 0] as well.")
    got_q2 = _try_call(func, _angle_matrix(2.5))
    if got_q2 is not None and got_q2.shape == () and np.isclose(got_q2, 2.5 - np.pi):
        return ("For the rotation by 2.5 rad you returned 2.5 - pi: arctan(R[1, 0] / R[0, 0]) "
                "only sees the ratio sin/cos, so it cannot tell the second quadrant from the "
                "fourth. np.arctan2(sine, cosine) looks at both signs.")
    got_deg = _try_call(func, _angle_matrix(0.5))
    if got_deg is not None and got_deg.shape == () and np.isclose(got_deg, np.degrees(0.5)):
        return "The answer looks like degrees; the course works in radians."
    return ("R = [[cos t, -sin t], [sin t, cos t]]: the first column holds (cos t, sin t). "
            "Which NumPy function turns a (sine, cosine) pair into an angle in (-pi, pi]?")


@never_raises("so2_log")
def check_so2_log(func):
    r"""Exercise 3.1: ``func(R)`` must return the angle :math:`\theta \in (-\pi, \pi]` of a
    planar rotation ``R`` (notebook 03, equation (3.12)).

    Tries rotations by 0.5, -0.7, 2.5, -2.5 and 4.0 rad (the last must come back as
    :math:`4 - 2\pi`), and names the usual slips: arccos of ``R[0, 0]`` (loses the sign)
    and arctan of the ratio (loses the quadrant).
    """
    name = "so2_log"
    fb = check_function(func, so2.log, _LOG_INPUTS, name, atol=1e-10, rtol=1e-10)
    if fb or "No answer yet" in fb.message or "Not written yet" in fb.message \
            or "Expected a function" in fb.message:
        return fb
    return Feedback(False, fb.message + "\nHint: " + _so2_log_hint(func))


@never_raises("the rotation R_end at t = T_END")
def check_varying_rate(answer):
    r"""Exercise 3.2: the 2x2 rotation reached at ``T_END`` by the rate
    :math:`\omega(t) = \omega_0 + a t` starting from the identity.

    In the plane all rotations commute, so the answer is :math:`e^{J\alpha}` with
    :math:`\alpha = \int_0^T \omega\,dt = \omega_0 T + a T^2/2` (notebook 03, (3.13)).
    Recognises the rate taken at the end or at the start instead of its integral, and an
    angle handed in instead of the matrix.
    """
    name = "the rotation R_end at t = T_END"
    alpha = OMEGA0 * T_END + 0.5 * ACCEL * T_END ** 2
    expected = so2.exp(alpha)
    hint = ("Integrate the rate: alpha = int_0^T (omega0 + a t) dt = omega0 T + a T^2 / 2, "
            "then R_end = so2.exp(alpha).")
    if answer is None or answer is Ellipsis:
        return check_value(answer, expected, name)
    try:
        arr = np.asarray(answer, dtype=float)
    except Exception:
        arr = None
    if arr is not None and np.isfinite(arr).all():
        if arr.shape == ():
            extra = (" (and that angle is right)" if np.isclose(float(arr), alpha)
                     else "")
            return Feedback(False, f"Not yet: {name}. You gave a number{extra}; the "
                                   "exercise asks for the 2x2 rotation matrix: pass the "
                                   "angle to so2.exp.")
        if arr.shape == (2, 2):
            for label, wrong in (("the rate at the end times T", (OMEGA0 + ACCEL * T_END) * T_END),
                                 ("the rate at the start times T", OMEGA0 * T_END)):
                if np.allclose(arr, so2.exp(wrong), atol=1e-8):
                    hint = (f"Your matrix turns by {wrong:g} rad, {label}. The rate changes "
                            "during the motion; the angle is its integral, "
                            "omega0 T + a T^2 / 2.")
    return check_value(answer, expected, name, atol=1e-9, rtol=1e-9, hint=hint)


def quaternion(n, theta):
    r"""The unit quaternion :math:`q = \cos(\theta/2) + u \sin(\theta/2)`, ``(w, x, y, z)``.

    ``u = (0, n)`` is the pure quaternion of the unit axis ``n`` (notebook 03, (3.17));
    the reference answer of exercise 3.3.

    Parameters
    ----------
    n : array_like, shape (3,), unit length
    theta : float, rad

    Returns
    -------
    q : ndarray, shape (4,), scalar part first
    """
    n = np.asarray(n, dtype=float)
    return np.concatenate([[np.cos(theta / 2)], np.sin(theta / 2) * n])


_QUAT_INPUTS = [
    (np.array([0.0, 0.0, 1.0]), np.pi / 2),
    (np.array([1.0, -2.0, 2.0]) / 3.0, 2.0),
    (np.array([0.6, 0.0, 0.8]), 5.0),
    (np.array([0.0, 1.0, 0.0]), 0.0),
]


def _quat_hint(func):
    for n, theta in _QUAT_INPUTS[:3]:
        got = _try_call(func, n.copy(), theta)
        if got is None or got.shape != (4,):
            continue
        q = quaternion(n, theta)
        if np.allclose(got, -q, atol=1e-9):
            return ("You returned -q. It gives the same rotation (q and -q both do: the "
                    "double cover), but the formula asked for is cos(theta/2) + u sin(theta/2); "
                    "look for a stray minus sign.")
        if np.allclose(got, quaternion(n, 2 * theta), atol=1e-9):
            return ("Your quaternion uses the full angle theta. A quaternion turns a vector "
                    "twice, once from each side in q x conj(q), so it carries theta/2.")
        if np.allclose(got, np.roll(q, -1), atol=1e-9):
            return "Your components are (x, y, z, w); the exercise wants the scalar part first."
    return "q = (cos(theta/2), sin(theta/2) n_x, sin(theta/2) n_y, sin(theta/2) n_z)."


@never_raises("quaternion")
def check_quaternion(func):
    r"""Exercise 3.3: ``func(n, theta)`` must return :math:`(\cos\frac\theta2,
    \sin\frac\theta2\, n)`, scalar part first.

    Recognises ``-q`` (the same rotation, another quaternion), the full angle in place of
    the half angle, and the scalar part written last.
    """
    name = "quaternion"
    fb = check_function(func, quaternion, _QUAT_INPUTS, name, atol=1e-10, rtol=1e-10)
    if fb:
        return Feedback(True, f"Correct: {name}. It gives (cos(theta/2), sin(theta/2) n) on "
                              f"{len(_QUAT_INPUTS)} test inputs.")
    if "No answer yet" in fb.message or "Not written yet" in fb.message \
            or "Expected a function" in fb.message:
        return fb
    return Feedback(False, fb.message + "\nHint: " + _quat_hint(func))
