r"""The derivatives of exp: the right and left Jacobians of SO(3) and their inverses.

A small rotation vector :math:`\delta` added to :math:`\varphi` moves
:math:`e^{\hat\varphi}` by a small rotation, on the right or on the left:

.. math:: e^{(\varphi + \delta)^\wedge} \approx e^{\hat\varphi}\, e^{(J_r(\varphi)\delta)^\wedge}
          \approx e^{(J_l(\varphi)\delta)^\wedge}\, e^{\hat\varphi}

to first order in :math:`\delta`. Summing the series
:math:`J_r(\varphi) = \sum_{k\ge0} (-\hat\varphi)^k/(k+1)!` with the Lemma (notebook 06,
as notebook 02 sums the exponential) gives, with :math:`\theta = \lVert\varphi\rVert`,

.. math:: J_r(\varphi) = I - B(\theta)\,\hat\varphi + C(\theta)\,\hat\varphi^2, \qquad
          J_l(\varphi) = J_r(-\varphi) = J_r(\varphi)^T = I + B(\theta)\,\hat\varphi
          + C(\theta)\,\hat\varphi^2,

.. math:: J_r^{-1}(\varphi) = I + \tfrac12\hat\varphi + D(\theta)\,\hat\varphi^2, \qquad
          J_l^{-1}(\varphi) = I - \tfrac12\hat\varphi + D(\theta)\,\hat\varphi^2,

.. math:: B(t) = \frac{1 - \cos t}{t^2},\quad C(t) = \frac{t - \sin t}{t^3},\quad
          D(t) = \frac1{t^2} - \frac{1 + \cos t}{2t\sin t}
          = \frac{1 - (t/2)\cot(t/2)}{t^2}.

``B`` is the coefficient of Rodrigues' formula (:func:`so3lib.B`); ``C`` and ``D`` are
here. The singular values of :math:`J_r(\varphi)` are 1 (along the axis) and
:math:`\lvert\sin(\theta/2)/(\theta/2)\rvert` twice: across the axis :math:`J_r` turns by
:math:`-\theta/2` about it and scales by :math:`\sin(\theta/2)/(\theta/2)` (notebook 06,
section 5). So :math:`J_r` is singular exactly at :math:`\theta = 2\pi, 4\pi, \dots`,
where :math:`D` has its poles.

Notation
--------
- ``right_jacobian(phi)`` is :math:`J_r(\varphi)` of Sola et al. (appendix B) and
  Barfoot's :math:`J(-\phi)`; ``left_jacobian(phi)`` is their :math:`J_l(\varphi)` and
  Barfoot's :math:`J(\phi)`.
- ``oplus(R, delta)`` is :math:`R \oplus \delta = R e^{\hat\delta}` and
  ``ominus(R1, R0)`` is :math:`R_1 \ominus R_0 = \mathrm{Log}(R_0^T R_1)`: Sola et al.'s
  "right plus" and "right minus", with the perturbation in the body frame.

References: J. Sola, J. Deray, D. Atchuthan, "A micro Lie theory for state estimation in
robotics" (2018), appendix B; T. D. Barfoot, "State Estimation for
Robotics" (2017), chapter 7; notebook 06 of the course.
"""

import math
from fractions import Fraction

import numpy as np

from .so3 import exp, log
from .validation import ROTATION_TOL, as_matrices, as_times, as_vectors, check_rotation

__all__ = [
    "C",
    "D",
    "left_jacobian",
    "left_jacobian_inv",
    "ominus",
    "oplus",
    "right_jacobian",
    "right_jacobian_inv",
]

#: Below this angle ``C`` and ``D`` come from their Taylor series, above it from the
#: closed forms. At 2 the closed forms lose at most a factor 1.9 (C) and 2.8 (D) to
#: cancellation, and the series converge fast (their terms shrink by (t/2 pi)^2 and
#: faster), so the coefficients are within a few eps everywhere.
_SERIES_BELOW = 2.0

#: |phi| from here on is refused by the inverses: J_r is singular at 2 pi.
TWO_PI = 2.0 * math.pi


def _bernoulli(n):
    """The Bernoulli numbers B_0 .. B_n as exact fractions (Akiyama-Tanigawa)."""
    out, a = [], [Fraction(0)] * (n + 1)
    for m in range(n + 1):
        a[m] = Fraction(1, m + 1)
        for j in range(m, 0, -1):
            a[j - 1] = j * (a[j - 1] - a[j])
        out.append(a[0])                       # B_1 = +1/2 here; only even ones are used
    return out


# C(t) = sum_k (-1)^k t^(2k) / (2k+3)!: 13 terms are exact to rounding for t < 2.
_C_SERIES = [(-1) ** k / math.factorial(2 * k + 3) for k in range(13)]
# D(t) = sum_{n>=1} |B_2n| t^(2n-2) / (2n)! (from t/2 cot(t/2)); 18 terms for t < 2.
_D_SERIES = [float(abs(b) / math.factorial(m))
             for m, b in enumerate(_bernoulli(38)) if m >= 2 and m % 2 == 0]


def _horner(coeffs, t2):
    """sum_k coeffs[k] * t2**k."""
    out = np.full_like(t2, coeffs[-1])
    for c in reversed(coeffs[:-1]):
        out = out * t2 + c
    return out


def _C_scaled(theta):
    r"""``gamma = theta^2 C(theta) = 1 - sin(theta)/theta``, without cancellation."""
    small = theta < _SERIES_BELOW
    th = np.where(small, _SERIES_BELOW, theta)          # placeholder in the other branch
    with np.errstate(divide="ignore", invalid="ignore"):
        closed = 1.0 - np.sin(th) / th
    t2 = np.where(small, theta, 0.0) ** 2
    return np.where(small, t2 * _horner(_C_SERIES, t2), closed)


def _D_scaled(theta):
    r"""``delta = theta^2 D(theta) = 1 - (theta/2) cot(theta/2)``.

    Near pi the naive form's ``1 + cos(theta)`` cancels; with ``t = tan(theta/2)`` (the
    tangent that :func:`so3lib.exp` uses), ``(1 + cos theta)/sin(theta) = 1/t`` exactly,
    and ``1/t`` is small and accurate there. Near 0 the series.
    """
    small = theta < _SERIES_BELOW
    th = np.where(small, 3.0, theta)
    with np.errstate(divide="ignore", invalid="ignore"):
        closed = 1.0 - 0.5 * th / np.tan(0.5 * th)
    t2 = np.where(small, theta, 0.0) ** 2
    return np.where(small, t2 * _horner(_D_SERIES, t2), closed)


def C(t):
    r"""The coefficient of :math:`\hat\varphi^2` in the Jacobians, :math:`(t - \sin t)/t^3`.

    .. math:: C(t) = \frac{t - \sin t}{t^3} = \frac16 - \frac{t^2}{120} + \frac{t^4}{5040}
              - \cdots

    Parameters
    ----------
    t : float or array_like of angles (any shape; the sign does not matter, ``C`` is even)

    Returns
    -------
    ndarray of the shape of ``t`` (a 0-d array for a number)

    Notes
    -----
    As written, ``t - sin t`` cancels: at ``t = 1e-5`` ``C`` keeps 5 digits, below
    ``t = 1e-8`` none. Below ``|t| = 2`` its Taylor series (13 terms, exact to rounding);
    above, the closed form, which loses at most a factor 2 there. Within a few eps
    relative of a 50-digit reference at every ``t`` (notebook 06, "Numerics").
    """
    t = _angles(t, "C")
    with np.errstate(over="ignore", under="ignore"):
        gamma = _C_scaled(t)                # theta^2 C, series below 2
        small = t < _SERIES_BELOW
        t2 = np.where(small, t, 1.0) ** 2
        series = _horner(_C_SERIES, t2)
        big = np.where(small, 1.0, t)
        return np.where(small, series, gamma / big / big)


def D(t):
    r"""The coefficient of :math:`\hat\varphi^2` in the inverse Jacobians.

    .. math:: D(t) = \frac1{t^2} - \frac{1 + \cos t}{2t\sin t}
              = \frac{1 - (t/2)\cot(t/2)}{t^2}
              = \frac1{12} + \frac{t^2}{720} + \frac{t^4}{30240} + \cdots

    Parameters
    ----------
    t : float or array_like of angles (any shape; ``D`` is even), ``|t| < 2 pi``
        for the inverse Jacobians; ``D`` has poles at ``t = 2 pi k``, ``k != 0``.

    Returns
    -------
    ndarray of the shape of ``t`` (a 0-d array for a number)

    Notes
    -----
    The written form cancels twice: near 0 (two terms of size ``1/t^2`` whose
    difference is 1/12) and near pi (``1 + cos t`` of size ``(pi - t)^2/2``). Below
    ``|t| = 2`` the series :math:`\sum_{n\ge1} |B_{2n}|\,t^{2n-2}/(2n)!` (Bernoulli
    numbers, from the series of :math:`x\cot x`); above, ``(1 - (t/2)/tan(t/2))/t^2``,
    in which nothing cancels near pi. Within a few eps relative of a 50-digit
    reference for ``|t| < 2 pi``, times the conditioning ``2 pi / (2 pi - |t|)`` near
    the pole (notebook 06, "Numerics").
    """
    t = _angles(t, "D")
    with np.errstate(over="ignore", under="ignore", divide="ignore"):
        delta = _D_scaled(t)
        small = t < _SERIES_BELOW
        t2 = np.where(small, t, 1.0) ** 2
        series = _horner(_D_SERIES, t2)
        big = np.where(small, 1.0, t)
        return np.where(small, series, delta / big / big)


def _angles(t, func):
    """``|t|`` as a finite float64 array of any shape, or ValueError."""
    return np.abs(as_times(t, func, name="t"))


def _axis_angle(phi):
    """``theta = |phi|`` and the unit axis ``n`` (0 where ``phi = 0``), overflow-free:
    with ``m = max|phi_i|`` and ``q = phi/m``, ``theta = m |q|`` and ``n = q/|q|``."""
    m = np.abs(phi).max(axis=-1)
    q = phi / np.where(m > 0, m, 1.0)[..., None]
    nq = np.sqrt(np.einsum("...i,...i->...", q, q))
    n = q / np.where(nq > 0, nq, 1.0)[..., None]
    with np.errstate(over="ignore"):
        theta = m * nq
    return theta, n


def _assemble(n, a, b):
    r""":math:`I + a\,\hat n + b\,\hat n^2` for unit ``n``, entry by entry; the diagonal of
    :math:`\hat n^2 = nn^T - I` is written as :math:`-(n_j^2 + n_k^2)`, so nothing cancels."""
    x, y, z = n[..., 0], n[..., 1], n[..., 2]
    xx, yy, zz = x * x, y * y, z * z
    J = np.empty(n.shape[:-1] + (3, 3))
    J[..., 0, 0] = 1.0 - b * (yy + zz)
    J[..., 1, 1] = 1.0 - b * (xx + zz)
    J[..., 2, 2] = 1.0 - b * (xx + yy)
    bxy, bxz, byz = b * x * y, b * x * z, b * y * z
    ax, ay, az = a * x, a * y, a * z
    J[..., 0, 1], J[..., 1, 0] = bxy - az, bxy + az
    J[..., 0, 2], J[..., 2, 0] = bxz + ay, bxz - ay
    J[..., 1, 2], J[..., 2, 1] = byz - ax, byz + ax
    return J


def _split(phi, func):
    phi = as_vectors(phi, 3, "phi", func)
    theta, n = _axis_angle(phi)
    if not np.isfinite(theta).all():
        raise ValueError(f"{func}: the rotation angle |phi| overflows float64; expected an "
                         "angle below about 1e308")
    return theta, n


def _forward(phi, sign, func):
    r"""``I + sign * theta B(theta) n^ + theta^2 C(theta) n^2``, the unit-axis form.

    ``theta B(theta) = (1 - cos theta)/theta = 2 sin^2(theta/2)/theta`` (no cancellation)
    and ``theta^2 C(theta) = 1 - sin(theta)/theta`` (series below 2): both are O(theta)
    and O(theta^2) at small angles and O(1) at large ones, so nothing under- or
    overflows and ``hat(phi)^2`` is never formed.
    """
    theta, n = _split(phi, func)
    with np.errstate(divide="ignore", invalid="ignore", under="ignore"):
        s = np.sin(0.5 * theta)
        beta = np.where(theta > 0, 2.0 * s * (s / np.where(theta > 0, theta, 1.0)), 0.0)
        gamma = _C_scaled(theta)
    return _assemble(n, sign * beta, gamma)


def _inverse(phi, sign, func):
    r"""``I + sign * (theta/2) n^ + theta^2 D(theta) n^2``, for ``|phi| < 2 pi``."""
    theta, n = _split(phi, func)
    if (theta >= TWO_PI).any():
        idx = np.argwhere(theta >= TWO_PI)[0] if theta.ndim else ()
        where = f" at index {list(map(int, idx))}" if len(idx) else ""
        raise ValueError(f"{func} expects |phi| < 2 pi, where the Jacobian is invertible "
                         f"(it is singular at |phi| = 2 pi); got |phi| = "
                         f"{float(theta[tuple(idx)]):.17g}{where}")
    with np.errstate(under="ignore"):
        delta = _D_scaled(theta)
    return _assemble(n, sign * 0.5 * theta, delta)


def right_jacobian(phi):
    r"""The right Jacobian of exp: :math:`e^{(\varphi+\delta)^\wedge} \approx
    e^{\hat\varphi} e^{(J_r(\varphi)\delta)^\wedge}`.

    .. math:: J_r(\varphi) = \sum_{k\ge0} \frac{(-\hat\varphi)^k}{(k+1)!}
              = I - \frac{1 - \cos\theta}{\theta^2}\,\hat\varphi
              + \frac{\theta - \sin\theta}{\theta^3}\,\hat\varphi^2,
              \qquad \theta = \lVert\varphi\rVert

    (Sola et al., appendix B; notebook 06). Its singular values are 1 and
    :math:`\lvert\sin(\theta/2)/(\theta/2)\rvert` (twice).

    Parameters
    ----------
    phi : array_like, shape (..., 3)
        Rotation vectors (any length: the angle may exceed pi).

    Returns
    -------
    J : ndarray, shape (..., 3, 3)

    Raises
    ------
    ValueError
        If ``phi`` is not an array of real 3-vectors, has NaN or inf, or ``|phi|``
        overflows.

    Notes
    -----
    Computed as :math:`I - \beta\,\hat n + \gamma\,\hat n^2` with the unit axis ``n``,
    :math:`\beta = 2\sin^2(\theta/2)/\theta` and :math:`\gamma = \theta^2 C(\theta)`
    (see :func:`C`): nothing cancels and nothing overflows. Within a few eps of a
    50-digit reference, relative to ``max(1, largest entry)``, times ``max(1, theta)``,
    for every ``|phi|`` from 0 and subnormals to 1e6 and beyond
    (``tests/test_jacobians.py``).
    """
    return _forward(phi, -1.0, "right_jacobian")


def left_jacobian(phi):
    r"""The left Jacobian of exp: :math:`e^{(\varphi+\delta)^\wedge} \approx
    e^{(J_l(\varphi)\delta)^\wedge} e^{\hat\varphi}`.

    .. math:: J_l(\varphi) = \sum_{k\ge0} \frac{\hat\varphi^k}{(k+1)!}
              = I + \frac{1 - \cos\theta}{\theta^2}\,\hat\varphi
              + \frac{\theta - \sin\theta}{\theta^3}\,\hat\varphi^2
              = J_r(-\varphi) = J_r(\varphi)^T

    (Sola et al., appendix B; Barfoot's :math:`J`). Parameters, result, errors and accuracy
    as :func:`right_jacobian`.
    """
    return _forward(phi, 1.0, "left_jacobian")


def right_jacobian_inv(phi):
    r"""The inverse of the right Jacobian, for ``|phi| < 2 pi``.

    .. math:: J_r^{-1}(\varphi) = I + \tfrac12\hat\varphi
              + \Big(\frac1{\theta^2} - \frac{1 + \cos\theta}{2\theta\sin\theta}\Big)
              \hat\varphi^2

    (Sola et al., appendix B). To first order, :math:`\mathrm{Log}(e^{\hat\varphi}
    e^{\hat\delta}) \approx \varphi + J_r^{-1}(\varphi)\,\delta` for
    :math:`\lVert\varphi\rVert < \pi`.

    Parameters
    ----------
    phi : array_like, shape (..., 3), with ``|phi| < 2 pi``

    Returns
    -------
    Jinv : ndarray, shape (..., 3, 3)

    Raises
    ------
    ValueError
        For bad input as :func:`right_jacobian`, and for ``|phi| >= 2 pi`` (compared in
        float64, so ``|phi| = 2 * math.pi`` is refused): there :math:`J_r` is singular.

    Notes
    -----
    Near ``2 pi`` the inverse grows like :math:`2\pi/(2\pi - \theta)` (its largest singular
    value is the reciprocal of the small one, :math:`(\theta/2)/\sin(\theta/2)`), and it
    is ill-conditioned: a relative change ``eps`` in ``theta`` changes it by about
    ``eps * 2 pi / (2 pi - theta)`` relative. The error bound is therefore a few eps
    relative to ``max(1, largest entry)``, times ``max(1, theta)`` and times
    ``max(1, 2 pi / (2 pi - theta))``; at 1e-3 below ``2 pi`` the largest singular value is
    about 6300 and the entries carry some 12 fewer bits. The
    coefficient is :math:`\theta^2 D(\theta)` (see :func:`D`), computed without the
    cancellations of the written form.
    """
    return _inverse(phi, 1.0, "right_jacobian_inv")


def left_jacobian_inv(phi):
    r"""The inverse of the left Jacobian, for ``|phi| < 2 pi``.

    .. math:: J_l^{-1}(\varphi) = I - \tfrac12\hat\varphi
              + \Big(\frac1{\theta^2} - \frac{1 + \cos\theta}{2\theta\sin\theta}\Big)
              \hat\varphi^2 = J_r^{-1}(\varphi)^T

    Parameters, result, errors, accuracy and the behaviour near ``2 pi`` as
    :func:`right_jacobian_inv`.
    """
    return _inverse(phi, -1.0, "left_jacobian_inv")


def oplus(R, delta):
    r"""A rotation perturbed by a small rotation vector in its own (body) frame.

    .. math:: R \oplus \delta = R\, e^{\hat\delta}

    (Sola et al.'s "right plus").

    Parameters
    ----------
    R : array_like, shape (..., 3, 3)
        Rotations (within ``ROTATION_TOL``).
    delta : array_like, shape (..., 3)
        Rotation vectors; the leading shapes of ``R`` and ``delta`` broadcast.

    Returns
    -------
    ndarray, shape (broadcast leading shape, 3, 3)

    Raises
    ------
    ValueError
        If ``R`` is not a batch of rotations, ``delta`` not a batch of 3-vectors, or
        their leading shapes do not broadcast.
    """
    R = as_matrices(R, 3, "R", "oplus")
    check_rotation(R, ROTATION_TOL, "oplus")
    delta = as_vectors(delta, 3, "delta", "oplus")
    _broadcast(R.shape[:-2], delta.shape[:-1], "oplus", "R", "delta")
    return R @ exp(delta)


def ominus(R1, R0):
    r"""The rotation vector that takes ``R0`` to ``R1``, in ``R0``'s own frame.

    .. math:: R_1 \ominus R_0 = \mathrm{Log}(R_0^T R_1), \qquad
              R_0 \oplus (R_1 \ominus R_0) = R_1

    (Sola et al.'s "right minus"); the principal logarithm, so
    ``|R1 ominus R0| <= pi``.

    Parameters
    ----------
    R1, R0 : array_like, shape (..., 3, 3)
        Rotations whose leading shapes broadcast.

    Returns
    -------
    ndarray, shape (broadcast leading shape, 3)

    Raises
    ------
    ValueError
        If either is not a batch of rotations, or the shapes do not broadcast.
    """
    R1 = as_matrices(R1, 3, "R1", "ominus")
    R0 = as_matrices(R0, 3, "R0", "ominus")
    check_rotation(R1, ROTATION_TOL, "ominus", name="R1")
    check_rotation(R0, ROTATION_TOL, "ominus", name="R0")
    _broadcast(R1.shape[:-2], R0.shape[:-2], "ominus", "R1", "R0")
    return log(np.swapaxes(R0, -1, -2) @ R1)


def _broadcast(a, b, func, name_a, name_b):
    try:
        return np.broadcast_shapes(a, b)
    except ValueError:
        raise ValueError(f"{func} expects {name_a} and {name_b} whose batch shapes "
                         f"broadcast; got {a} and {b}") from None
