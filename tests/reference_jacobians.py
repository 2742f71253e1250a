r"""High-precision references for the Jacobians of exp (spec S22, S29).

As in ``tests/reference.py``: every float64 input is converted exactly, the formula is
evaluated at 50 significant digits *after* the cancellation it suffers, and each entry is
rounded once to float64. The written forms ``(t - sin t)/t^3`` and
``1/t^2 - (1 + cos t)/(2 t sin t)`` lose about ``2 log10(1/t)`` digits near 0 (and
``1 + cos t`` loses ``2 log10(1/(pi - t))`` near pi), so the working precision is raised
by that many digits plus a margin: at ``t = 5e-324`` that is about 700 digits.

Two independent routes are also given, to test the references themselves: the series
``J_r = sum_k (-hat(phi))^k/(k+1)!`` summed in mpmath, and mpmath's matrix inverse.
"""

import mpmath as mp
import numpy as np
from reference import DPS, _hat, _mp_vec, _to_float


def _extra_digits(theta):
    """Digits lost to cancellation in the written forms at the angle ``theta`` (mpf)."""
    extra = 10
    if 0 < theta < 1:
        extra += int(2 * -mp.log10(theta)) + 1
    dist = abs(theta - mp.pi)
    if 0 < dist < 1:
        extra += int(2 * -mp.log10(dist)) + 1
    return extra


def _coefficients(phi):
    """theta, B, C, D at high precision for the exact float vector ``phi``."""
    theta = mp.sqrt(sum(p * p for p in phi))
    if theta == 0:
        return theta, mp.mpf(1) / 2, mp.mpf(1) / 6, mp.mpf(1) / 12
    b = (1 - mp.cos(theta)) / theta**2
    c = (theta - mp.sin(theta)) / theta**3
    d = 1 / theta**2 - (1 + mp.cos(theta)) / (2 * theta * mp.sin(theta))
    return theta, b, c, d


def coefficients_ref(t):
    """Correctly rounded ``B(t)``, ``C(t)`` and ``D(t)`` of a float ``t``, as a dict."""
    with mp.workdps(DPS):
        x = abs(mp.mpf(float(t)))
        extra = _extra_digits(x)
    with mp.workdps(DPS + extra):
        _, b, c, d = _coefficients([mp.mpf(float(t)), mp.mpf(0), mp.mpf(0)])
        return {"B": float(b), "C": float(c), "D": float(d)}


def jacobian_ref(phi, side="right", inverse=False):
    r"""Correctly rounded :math:`J_r`, :math:`J_l` or their inverses at one 3-vector.

    The written forms: :math:`I \mp B\hat\varphi + C\hat\varphi^2` and
    :math:`I \pm \tfrac12\hat\varphi + D\hat\varphi^2` (upper sign: right).
    """
    with mp.workdps(DPS):
        p = _mp_vec(phi)
        extra = _extra_digits(mp.sqrt(sum(x * x for x in p)))
    with mp.workdps(DPS + extra):
        p = _mp_vec(phi)
        _, b, c, d = _coefficients(p)
        K = _hat(p)
        sign = -1 if side == "right" else 1
        if inverse:
            M = mp.eye(3) - sign * K / 2 + d * K * K
        else:
            M = mp.eye(3) + sign * b * K + c * K * K
        return _to_float(M)


def jacobian_series_ref(phi, side="right", terms=80):
    r"""The defining series :math:`\sum_k (\mp\hat\varphi)^k/(k+1)!` at 50 digits (for
    ``|phi|`` up to about 10, where 80 terms converge)."""
    with mp.workdps(DPS + 20):
        K = _hat(_mp_vec(phi)) * (-1 if side == "right" else 1)
        term, total = mp.eye(3), mp.eye(3)
        for k in range(1, terms):
            term = term * K / (k + 1)
            total += term
        return _to_float(total)


def jacobian_inverse_by_mpmath(phi, side="right"):
    """mpmath's dense inverse of the high-precision forward Jacobian (not the formula)."""
    with mp.workdps(DPS + 20):
        p = _mp_vec(phi)
        _, b, c, _ = _coefficients(p)
        K = _hat(p)
        sign = -1 if side == "right" else 1
        return _to_float(mp.inverse(mp.eye(3) + sign * b * K + c * K * K))


def exp_mp(phi):
    """``exp(hat(phi))`` as an mpmath matrix at the current precision (for differences)."""
    theta = mp.sqrt(sum(x * x for x in phi))
    K = _hat(phi)
    if theta == 0:
        return mp.eye(3)
    return mp.eye(3) + mp.sin(theta) / theta * K + 2 * (mp.sin(theta / 2) / theta) ** 2 * K * K


def jacobian_by_differences(phi, h="1e-20"):
    r"""The right Jacobian by centred differences at 60 digits: column ``j`` is
    :math:`\big(e^{-\hat\varphi} (e^{(\varphi + h e_j)^\wedge} - e^{(\varphi - h e_j)^\wedge})
    / 2h\big)^\vee`, an independent check of the closed form (error ~h^2)."""
    with mp.workdps(60):
        h = mp.mpf(h)
        p = _mp_vec(phi)
        R_T = exp_mp(p).T
        cols = []
        for j in range(3):
            e = [mp.mpf(0)] * 3
            e[j] = h
            D = R_T * (exp_mp([a + b for a, b in zip(p, e)])
                       - exp_mp([a - b for a, b in zip(p, e)])) / (2 * h)
            cols.append([D[2, 1], D[0, 2], D[1, 0]])
        return np.array([[float(cols[j][i]) for j in range(3)] for i in range(3)])
