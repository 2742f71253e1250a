r"""Checkers for the exercises of notebook 02, "Rodrigues' formula from the series".

=============  ==========================================  ============================
exercise       the learner writes                          checker
=============  ==========================================  ============================
2.1            ``partial_sum(omega, tau, terms)``: the     :func:`check_partial_sum`
               first ``terms`` terms of the series
2.2            ``R``, the rotation reached by              :func:`check_quarter_turn`
               ``omega = (0, 0, pi/2)`` in ``tau = 1``
2.3            ``B_stable(t) = (1 - cos t)/t^2``,          :func:`check_B`
               accurate at every ``t``, ``B(0) = 1/2``
=============  ==========================================  ============================

Every checker returns a :class:`~so3lib.exercises.Feedback` and never raises. When an
answer is wrong, the checker compares it with the usual mistakes (one term too many,
an element-by-element power, the notes' printed formula, the naive ``1 - cos``) and
names the one it matches.
"""

import math

import numpy as np

from ..series import B, exp_series
from ..so3 import exp, hat
from . import Feedback, check_function, check_value, never_raises

__all__ = ["check_partial_sum", "check_quarter_turn", "check_B"]

#: The angular velocity and time of exercise 2.2.
OMEGA_QUARTER = np.array([0.0, 0.0, np.pi / 2])
TAU_QUARTER = 1.0


def _close(got, alt, atol=1e-9, rtol=1e-9):
    """Whether ``got`` equals the alternative ``alt`` (False for anything unreadable)."""
    try:
        g = np.asarray(got, dtype=float)
        a = np.asarray(alt, dtype=float)
        return g.shape == a.shape and bool(np.isfinite(g).all()) and \
            bool(np.allclose(g, a, atol=atol, rtol=rtol))
    except Exception:
        return False


def _with_hint(fb, hint):
    """``fb`` with its hint replaced by ``hint`` (the generic hint is cut off)."""
    message = fb.message.split("\nHint: ")[0]
    return Feedback(False, f"{message}\nHint: {hint}")


def _check_each(func, reference, inputs, name, atol, rtol, hint, diagnose):
    """Like :func:`check_function`, but a wrong answer is passed to ``diagnose``.

    ``diagnose(got, args)`` returns a more specific hint, or None. Returns the Feedback
    of the first failing input, or None when every input passes.
    """
    for args in inputs:
        fb = check_function(func, reference, [args], name, atol=atol, rtol=rtol, hint=hint)
        if fb:
            continue
        try:
            got = func(*[np.array(a, copy=True) if isinstance(a, np.ndarray) else a
                         for a in args])
            specific = diagnose(got, args)
        except Exception:
            specific = None
        return _with_hint(fb, specific) if specific else fb
    return None


# ---------------------------------------------------------------- exercise 2.1

_SUM_INPUTS = [
    (np.array([0.0, 0.0, 1.0]), 1.0, 1),
    (np.array([0.0, 0.0, 1.0]), 1.0, 2),
    (np.array([0.3, -0.4, 1.2]), 0.7, 6),
    (np.array([1.0, 2.0, 3.0]), 0.5, 6),
    (np.array([1.0, 2.0, 3.0]), -0.25, 9),
]

_SUM_HINT = ("partial_sum(omega, tau, N) is the sum over m = 0, 1, ..., N-1 of "
             "(tau hat(omega))^m / m!: N terms, the first one I. Build each term from the "
             "previous one: term = term @ (tau * hat(omega)) / m.")


def _diagnose_sum(got, args):
    omega, tau, terms = args
    K = tau * hat(omega)
    if _close(got, exp_series(omega, tau, terms + 1)):
        return (f"You summed {terms + 1} terms instead of {terms}: terms = N means the powers "
                "m = 0, ..., N-1, as in range(N).")
    if terms > 1 and _close(got, exp_series(omega, tau, terms - 1)):
        return (f"You summed {terms - 1} terms instead of {terms}: terms = N means the powers "
                "m = 0, ..., N-1, as in range(N), starting with the identity.")
    if _close(got, sum(np.linalg.matrix_power(K, m) for m in range(terms))):
        return "Each power must be divided by m! (math.factorial(m))."
    if _close(got, sum(K ** m / math.factorial(m) for m in range(terms))):
        return ("`K ** m` on a NumPy array raises each ENTRY to the power m. The matrix power is "
                "np.linalg.matrix_power(K, m), or build it with K @ K @ ...")
    if tau != 1.0 and _close(got, exp_series(omega, 1.0, terms)):
        return "The series is in tau * hat(omega): multiply hat(omega) by tau."
    return None


@never_raises("partial_sum")
def check_partial_sum(func):
    r"""Exercise 2.1: ``func(omega, tau, terms)`` must equal :func:`so3lib.exp_series`.

    .. math:: S_N = \sum_{m=0}^{N-1} \frac{(\tau\hat\omega)^m}{m!}
    """
    name = "partial_sum"
    fb = _check_each(func, exp_series, _SUM_INPUTS, name, 1e-10, 1e-10, _SUM_HINT,
                     _diagnose_sum)
    if fb is not None:
        return fb
    return Feedback(True, f"Correct: {name}. It agrees with so3lib.exp_series on "
                          f"{len(_SUM_INPUTS)} test inputs, from 1 term to 9.")


# ---------------------------------------------------------------- exercise 2.2

@never_raises("the rotation reached by omega = (0, 0, pi/2) in tau = 1")
def check_quarter_turn(answer):
    r"""Exercise 2.2: the rotation :math:`R(\omega, \tau)` for ``omega = (0, 0, pi/2)``, ``tau = 1``.

    Recognises the transpose (the clockwise turn), the notes' printed formula without
    the square (errata N1), an element-by-element ``np.exp`` and degrees for radians.
    """
    name = "the rotation reached by omega = (0, 0, pi/2) in tau = 1"
    expected = exp(OMEGA_QUARTER, TAU_QUARTER)
    W = hat(OMEGA_QUARTER)
    w = float(np.linalg.norm(OMEGA_QUARTER))
    th = w * TAU_QUARTER
    printed = np.eye(3) + W / w * math.sin(th) + W / w ** 2 * (1 - math.cos(th))
    hint = ("theta = |omega| tau = pi/2 and n = (0, 0, 1), so sin(theta) = 1 and "
            "1 - cos(theta) = 1: R = I + hat(n) + hat(n)^2. The x axis must go to the y axis, "
            "so the first column of R is (0, 1, 0).")
    if _close(answer, expected.T):
        hint = ("That is the turn in the wrong direction (the transpose). A positive angle "
                "about +z turns the x axis towards the y axis: R @ (1, 0, 0) = (0, 1, 0).")
    elif _close(answer, printed):
        hint = ("That is the notes' printed last line, whose third term has hat(omega) "
                "where hat(omega)^2 belongs (errata N1). Square it and try again.")
    elif _close(answer, np.exp(W * TAU_QUARTER)):
        hint = ("np.exp works entry by entry; it is not the matrix exponential. Use "
                "Rodrigues' formula, so3lib.exp or scipy.linalg.expm.")
    elif _close(answer, exp(np.degrees(OMEGA_QUARTER), TAU_QUARTER)):
        hint = "Angles are in radians: the angular velocity is pi/2 rad/s, not 90."
    return check_value(answer, expected, name, atol=1e-8, rtol=1e-8, hint=hint)


# ---------------------------------------------------------------- exercise 2.3

# Simplest first; the small angles come before t = 0 so that the naive formula is caught
# by its visible failure (0 instead of 0.5 at 1e-8) before its division by zero.
_B_INPUTS = [(1.0,), (2.5,), (-0.5,), (1e-8,), (1e-5,), (1e-3,), (0.0,), (30.0,)]

_B_HINT = ("Avoid the subtraction 1 - cos(t) for small t: use the half-angle form "
           "2 sin(t/2)^2 / t^2, and return the limit 1/2 at t = 0 (or the Taylor form "
           "1/2 - t^2/24 for |t| < 1e-4).")


def _diagnose_B(got, args):
    (t,) = args
    with np.errstate(all="ignore"):
        t64 = np.float64(t)
        naive = (1.0 - np.cos(t64)) / t64 ** 2
        taylor = 0.5 - t64 ** 2 / 24.0
        taylor3 = taylor + t64 ** 4 / 720.0
    if t != 0 and _close(got, naive, atol=0, rtol=1e-15):
        return ("This is the naive (1 - cos t)/t^2. Near t = 0, cos(t) rounds to a number "
                "next to 1 and the subtraction cancels almost every digit (at t = 1e-8 it "
                "gives 0). " + _B_HINT)
    if abs(t) >= 0.5 and (_close(got, taylor) or _close(got, taylor3)):
        return ("A Taylor polynomial is accurate only near t = 0. Use it for small |t| "
                "and the closed form elsewhere.")
    if t != 0 and _close(got, math.sin(t) / t):
        return "That is A(t) = sin(t)/t, the other coefficient. B(t) = (1 - cos t)/t^2."
    if t != 0 and _close(got, (1 - math.cos(t)) / t):
        return "The denominator is t^2, not t."
    return None


@never_raises("B_stable")
def check_B(func):
    r"""Exercise 2.3: ``func(t)`` must give :math:`B(t) = (1 - \cos t)/t^2` to 1e-12 relative.

    Tries ``t`` from 1 down to 1e-8, then ``t = 0`` (where ``B = 1/2``) and ``t = 30``.
    """
    name = "B_stable"
    fb = _check_each(func, B, _B_INPUTS, name, 1e-15, 1e-12, _B_HINT, _diagnose_B)
    if fb is not None:
        return fb
    return Feedback(True, f"Correct: {name}. It is accurate to 1e-12 (relative) at "
                          "t = 0, 1e-8, ..., 30.")
