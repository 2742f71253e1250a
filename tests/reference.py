r"""A high-precision reference for the accuracy tests (spec S29).

Every binary64 input is a dyadic rational, so ``mpmath.mpf(x)`` holds it exactly. The
formulas are evaluated at 50 significant digits and each output is rounded once to the
nearest binary64, which gives the correctly rounded exact result (up to a tie that 50
digits cannot resolve, which has probability ~1e-34 per entry).

The logarithm is evaluated on the matrix as given, never projected onto SO(3) first, so
that for a matrix at distance delta from SO(3) it differs from any correct algorithm by
O(delta) only.

The formulas are independent of so3lib's code paths: exp uses Rodrigues with the exact
product ``omega * tau``, and :func:`expm_ref` is mpmath's general matrix exponential,
used to test the reference itself.
"""

import mpmath as mp
import numpy as np

DPS = 50


def _mp_vec(v):
    return [mp.mpf(float(x)) for x in np.asarray(v, dtype=float).ravel()]


def _hat(p):
    x, y, z = p
    return mp.matrix([[0, -z, y], [z, 0, -x], [-y, x, 0]])


def _to_float(M):
    return np.array([[float(M[i, j]) for j in range(M.cols)] for i in range(M.rows)])


def exp_ref(omega, tau=1.0):
    r"""Correctly rounded :math:`e^{\tau\hat\omega}` for one 3-vector and one scalar time.

    :math:`R = I + A\hat\varphi + B\hat\varphi^2` with :math:`\varphi = \omega\tau` formed
    exactly, :math:`A = \sin\theta/\theta` and :math:`B = 2\sin^2(\theta/2)/\theta^2`
    (no cancellation even at 50 digits).
    """
    with mp.workdps(DPS):
        t = mp.mpf(float(tau))
        phi = [w * t for w in _mp_vec(omega)]
        theta = mp.sqrt(sum(p * p for p in phi))
        if theta == 0:
            return np.eye(3)
        a = mp.sin(theta) / theta
        b = 2 * (mp.sin(theta / 2) / theta) ** 2
        K = _hat(phi)
        return _to_float(mp.eye(3) + a * K + b * K * K)


def expm_ref(omega, tau=1.0):
    """Correctly rounded exponential of ``tau * hat(omega)`` by mpmath's general expm."""
    with mp.workdps(DPS):
        t = mp.mpf(float(tau))
        phi = [w * t for w in _mp_vec(omega)]
        return _to_float(mp.expm(_hat(phi)))


def log_info(R):
    """The high-precision logarithm of one 3x3 matrix, and how it was reached.

    Returns a dict with ``phi`` (mpmath vector), ``theta`` (mpf) and ``pi_ambiguous``
    (True when the skew part is exactly zero and the angle is pi: both signs qualify).
    """
    with mp.workdps(DPS):
        M = mp.matrix(np.asarray(R, dtype=float).tolist())
        v = [M[2, 1] - M[1, 2], M[0, 2] - M[2, 0], M[1, 0] - M[0, 1]]
        s = mp.sqrt(sum(x * x for x in v)) / 2
        c = (M[0, 0] + M[1, 1] + M[2, 2] - 1) / 2
        theta = mp.atan2(s, c)
        if c >= 0:
            if s == 0:
                return {"phi": [mp.mpf(0)] * 3, "theta": mp.mpf(0), "pi_ambiguous": False}
            k = theta / (2 * s)
            return {"phi": [k * x for x in v], "theta": theta, "pi_ambiguous": False}
        # symmetric part: (R + R^T)/2 - c I = (1 - c) n n^T; largest diagonal column
        B = (M + M.T) / 2 - c * mp.eye(3)
        j = max(range(3), key=lambda i: B[i, i])
        col = [B[i, j] for i in range(3)]
        norm = mp.sqrt(sum(x * x for x in col))
        n = [x / norm for x in col]
        d = sum(a * b for a, b in zip(n, v))
        if d < 0:
            n = [-x for x in n]
        return {"phi": [theta * x for x in n], "theta": theta, "pi_ambiguous": d == 0}


def log_ref(R, tau=1.0):
    """Correctly rounded ``Log(R) / tau`` for one 3x3 matrix (spec S14, S19)."""
    info = log_info(R)
    with mp.workdps(DPS):
        t = mp.mpf(float(tau))
        return np.array([float(x / t) for x in info["phi"]])


def coeffs_ref(t):
    """The scalar coefficients A(t) = sin t / t and B(t) = (1 - cos t)/t^2, rounded."""
    with mp.workdps(DPS):
        x = mp.mpf(float(t))
        if x == 0:
            return {"A": 1.0, "B": 0.5}
        return {"A": float(mp.sin(x) / x), "B": float(2 * (mp.sin(x / 2) / x) ** 2)}


def so2_exp_ref(theta, tau=1.0):
    """Correctly rounded planar rotation by ``theta * tau`` (the product taken exactly)."""
    with mp.workdps(DPS):
        t = mp.mpf(float(theta)) * mp.mpf(float(tau))
        c, s = mp.cos(t), mp.sin(t)
        return np.array([[float(c), float(-s)], [float(s), float(c)]])


def so2_log_ref(R, tau=1.0):
    """Correctly rounded ``atan2(R[1,0], R[0,0]) / tau`` in (-pi, pi]."""
    with mp.workdps(DPS):
        R = np.asarray(R, dtype=float)
        th = mp.atan2(mp.mpf(float(R[1, 0])), mp.mpf(float(R[0, 0])))
        if th == -mp.pi:
            th = mp.pi
        return float(th / mp.mpf(float(tau)))
