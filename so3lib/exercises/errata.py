r"""Checkers for the exercises of the errata appendix (notebook A1).

=========================  ===============================================================
checker                    the exercise
=========================  ===============================================================
``check_power_table``      A1.1 the corrected table :math:`(j\omega)^p`, p = 0..4, at
                           :math:`\omega = 2` (errata N4)
``check_wrapped_velocity`` A1.2 ``wrapped_velocity(omega, tau)``: what
                           :math:`\ln_\tau(e^{\tau\hat\omega})` really returns, predicted
                           without ``log`` (errata N15)
=========================  ===============================================================

Each checker returns a :class:`so3lib.exercises.Feedback` and never raises.
"""

import numpy as np

from ..so3 import exp, log
from . import (_NOT_ANSWERED, Feedback, _compare, _fail, _ok, check_function,
               never_raises)

__all__ = ["check_power_table", "check_wrapped_velocity", "POWER_TABLE_OMEGA"]

#: The angular velocity of exercise A1.1.
POWER_TABLE_OMEGA = 2.0


@never_raises("the table of (j omega)^p for p = 0..4 at omega = 2")
def check_power_table(values):
    r"""Exercise A1.1: the five numbers :math:`(j\omega)^0, \dots, (j\omega)^4` at omega = 2.

    The answer is ``[1, 2j, -4, -8j, 16]``. The notes' table, read as printed, gives
    ``[2j, -4, -8j, 16, 32j]``: every entry is the next power.
    """
    name = "the table of (j omega)^p for p = 0..4 at omega = 2"
    if values is None or values is Ellipsis:
        return _fail(name, _NOT_ANSWERED)
    w = POWER_TABLE_OMEGA
    expected = np.array([(1j * w) ** p for p in range(5)])
    hint = "Multiply by j omega one step at a time, starting from (j omega)^0 = 1; j^2 = -1."
    result = _compare(values, expected, name, 1e-12, 1e-12, None)
    if result is None:
        return _fail(name, _NOT_ANSWERED)
    if result is True:
        return _ok(name, "The printed table was off by one power.")
    extra = ""
    try:
        got = np.asarray(values, dtype=complex)
    except (TypeError, ValueError):
        got = None
    if got is not None and got.shape == (5,) and np.isfinite(got).all():
        if np.allclose(got, (1j * w) * expected):
            extra = (" This is the table as printed in the notes: each entry is the next "
                     "power. (j omega)^0 = 1, not j omega.")
        elif np.allclose(got, expected.real + expected.imag) or \
                np.allclose(got, np.abs(expected.real) + np.abs(expected.imag)):
            extra = (" The odd powers are imaginary: (j omega)^(2k+1) = j (-1)^k "
                     "omega^(2k+1) (errata N5). Write j as 1j in Python.")
        elif np.allclose(got, np.conj(expected)):
            extra = " The signs of the odd powers are flipped: j^1 = j and j^3 = -j."
    return Feedback(False, result.message + extra + f"\nHint: {hint}")


def _wrapped_velocity_reference(omega, tau):
    return log(exp(omega, tau), tau)


_WRAP_CASES = [
    ("omega = (0, 0, 1) rad/s, tau = 1 s (less than half a turn)",
     (np.array([0.0, 0.0, 1.0]), 1.0)),
    ("omega = (0, 0, 4) rad/s, tau = 1 s (4 rad: more than half a turn)",
     (np.array([0.0, 0.0, 4.0]), 1.0)),
    ("omega = (5/3)(1, 2, 2) rad/s, tau = 1 s (5 rad about a general axis)",
     (np.array([1.0, 2.0, 2.0]) * 5.0 / 3.0, 1.0)),
    ("omega = (0.3, -0.4, 1.2) rad/s, tau = 6 s (7.8 rad: more than a full turn)",
     (np.array([0.3, -0.4, 1.2]), 6.0)),
    ("omega = (0, 0, 5.5) rad/s, tau = 2 s (11 rad: nearly two turns)",
     (np.array([0.0, 0.0, 5.5]), 2.0)),
    ("omega = (0, 0, 2) rad/s, tau = -0.5 s (a negative time)",
     (np.array([0.0, 0.0, 2.0]), -0.5)),
    ("omega = (0, 0, 0), tau = 1 s (no rotation at all)",
     (np.array([0.0, 0.0, 0.0]), 1.0)),
]


def _diagnose_wrapped(got, omega, tau):
    omega = np.asarray(omega, float)
    phi = omega * tau
    theta = float(np.linalg.norm(phi))
    if np.allclose(got, omega, atol=1e-9):
        return (" This is omega itself, the notes' claim that log undoes exp (errata N15). "
                "It holds only while |omega| |tau| < pi; here the angle is "
                f"{theta:.4g} rad, and the principal log turns at most pi, the shorter way "
                "round, which past half a turn is the other way.")
    if theta > 0:
        r = theta % (2 * np.pi)
        if np.allclose(got, r / theta * omega, atol=1e-9):
            return (" The angle is wrapped into [0, 2 pi) but not into [0, pi]: beyond half a "
                    "turn the shorter way round is the other way, along -n, with angle "
                    "2 pi - r.")
    return None


def check_wrapped_velocity(func):
    r"""Exercise A1.2: ``wrapped_velocity(omega, tau)`` predicts
    :math:`\ln_\tau(e^{\tau\hat\omega})`, the angular velocity the principal logarithm
    returns, without calling ``log``: with :math:`\varphi = \omega\tau`,
    :math:`\theta = \lVert\varphi\rVert` and :math:`r = \theta \bmod 2\pi`, it is
    :math:`(r/\theta)\,\omega` if :math:`r \le \pi` and :math:`-((2\pi - r)/\theta)\,\omega`
    otherwise (and 0 when :math:`\varphi = 0`).
    """
    name = "wrapped_velocity"
    hint = ("phi = omega tau has angle theta = |phi|. Reduce theta modulo 2 pi to r; if r > pi, "
            "the shortest turn is 2 pi - r the other way. Divide the resulting rotation vector "
            "by tau, and treat omega = 0 separately.")
    fb = check_function(func, _wrapped_velocity_reference, _WRAP_CASES, name, atol=1e-9,
                        rtol=0.0, hint=hint, diagnose=lambda got, args: _diagnose_wrapped(got, *args))
    if not fb:
        return fb
    return _ok(name, f"It predicts what log returns in {len(_WRAP_CASES)} cases: exp and log "
                     "are inverses only below half a turn.")
