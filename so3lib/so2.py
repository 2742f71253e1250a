r"""Planar rotations SO(2), their generator J, and unit complex numbers.

The 2-D analogue of :mod:`so3lib.so3`, and the comparison the lecture notes draw
(notebook 03, spec S24 to S27):

==================  =====================================  ============================
here                meaning                                complex numbers
==================  =====================================  ============================
``J``               ``[[0, -1], [1, 0]]``, ``J @ J == -I`` ``j`` (multiply by ``j``)
``hat(w)``          ``w * J``, the 2-D hat                 ``j w``
``exp(theta, tau)`` ``cos(t) I + sin(t) J``, t = theta tau ``e^{j t}``
``log(R, tau)``     ``atan2(R[1,0], R[0,0]) / tau``,       ``arg(z) / tau``
                    in the doubles ``(-np.pi, np.pi]``
``from_complex(z)`` ``Re(z) I + Im(z) J``                  ``z``
==================  =====================================  ============================

``J`` is the counter-clockwise generator, and the 3-D hat restricted to the plane:
``hat((0, 0, w))[:2, :2] == w * J``. The lecture notes' ``hat(omega) = -J omega`` holds
only with the opposite sign convention ``J' = -J`` (errata N8).
"""

import numpy as np

from .validation import (ROTATION_TOL, as_matrices, as_numbers, as_times, as_tolerance,
                         broadcast_batch, check_batch_axes, check_rotation, check_skew)

__all__ = ["J", "hat", "vee", "exp", "log", "to_complex", "from_complex"]

#: The generator of planar rotations, the matrix of multiplication by j.
J = np.array([[0.0, -1.0], [1.0, 0.0]])
J.setflags(write=False)


def hat(w):
    r"""The 2-D hat map: an angular rate to its skew matrix, :math:`\hat w = w J`.

    Parameters
    ----------
    w : float or array_like, shape (...)

    Returns
    -------
    W : ndarray, shape (..., 2, 2)
    """
    w = as_times(w, "so2.hat", name="w")
    return w[..., None, None] * J


def vee(W, check=True):
    r"""Inverse of :func:`hat`: the rate ``w`` with ``W = w J`` (read from ``W[1, 0]``).

    Parameters
    ----------
    W : array_like, shape (..., 2, 2)
        Skew-symmetric.
    check : bool
        Refuse a matrix that is not skew-symmetric (default).

    Returns
    -------
    w : ndarray, shape (...)
    """
    W = as_matrices(W, 2, "W", "so2.vee")
    if check:
        check_skew(W, "so2.vee", name="W")
    return W[..., 1, 0].copy()


def exp(theta, tau=1.0):
    r"""Planar rotation by the angle ``theta * tau`` (counter-clockwise).

    .. math:: e^{J\theta\tau} = \cos(\theta\tau) I + \sin(\theta\tau) J
              = \begin{pmatrix}\cos & -\sin\\ \sin & \cos\end{pmatrix}

    The series of :math:`e^{Jt}` splits into even powers (:math:`J^{2k} = (-1)^k I`,
    cosine) and odd powers (:math:`J^{2k+1} = (-1)^k J`, sine), as :math:`e^{jt}` does.

    Parameters
    ----------
    theta : float or array_like, shape (...)
        Angular rate (or angle when ``tau = 1``).
    tau : float or array_like, broadcastable against ``theta``

    Returns
    -------
    R : ndarray, shape (broadcast(theta, tau) + (2, 2))
    """
    theta = as_times(theta, "so2.exp", name="theta")
    tau = as_times(tau, "so2.exp")
    broadcast_batch(theta.shape, tau, "so2.exp", "theta")
    with np.errstate(over="ignore"):
        t = theta * tau
    if not np.isfinite(t).all():
        raise ValueError("so2.exp: the angle theta * tau overflows float64; expected "
                         "|theta * tau| below about 1.8e308")
    c, s = np.cos(t), np.sin(t)
    return np.stack([np.stack([c, -s], axis=-1), np.stack([s, c], axis=-1)], axis=-2)


def log(R, tau=1.0, check=True, tol=ROTATION_TOL):
    r"""Principal logarithm of planar rotations, an angle in :math:`(-\pi, \pi]`, over ``tau``.

    .. math:: \ln_\tau R = \frac{\operatorname{atan2}(R_{21}, R_{11})}{\tau}

    atan2 is well conditioned at every angle; the only discontinuity is the branch cut
    at :math:`\pm\pi`. The convention: the result lies in the *doubles*
    ``(-np.pi, np.pi]``, so a half-turn gives ``np.pi``, never ``-np.pi`` (spec S27).
    atan2 returns the double ``-np.pi`` on the cut (``R[1, 0]`` the float ``-0.0``,
    ``R[0, 0] < 0``) and next to it (a negative ``R[1, 0]`` up to about 3.4e-16 in size,
    so small that :math:`-\pi + |R_{21}|` rounds to that double); ``np.pi`` is returned
    instead: the same half-turn, since modulo :math:`2\pi` the two doubles are
    :math:`2(\pi - \mathrm{fl}(\pi)) \approx 2.45\cdot10^{-16}` rad apart, about 0.55 of an ulp
    of pi (one ulp of pi, the gap between neighbouring doubles there, is 4.4e-16).

    Parameters
    ----------
    R : array_like, shape (..., 2, 2)
    tau : float or array_like, nonzero
        Broadcasts against the leading shape of ``R``. A ``tau`` so small that the angle
        divided by it overflows float64 is refused.
    check : bool
        Refuse matrices that are not rotations within ``tol`` (default).
    tol : float

    Returns
    -------
    theta : ndarray, shape (...)
    """
    R = as_matrices(R, 2, "R", "so2.log")
    if check:
        check_rotation(R, as_tolerance(tol, "so2.log"), "so2.log")
    tau = as_times(tau, "so2.log", nonzero=True)
    broadcast_batch(R.shape[:-2], tau, "so2.log", "R")
    s, c = R[..., 1, 0], R[..., 0, 0]
    # atan2 gives the double -np.pi for s = -0.0 with c < 0, and for a negative s so small
    # that -pi + |s| rounds to it; both are the half-turn, returned as np.pi (the doubles
    # (-np.pi, np.pi], as the docstring says). Its distance to the true angle, modulo 2 pi,
    # is below 5e-16 either way (2.45e-16 apart, about half an ulp of pi). A C library whose atan2 is faithful but
    # not correctly rounded may return the double just outside [-np.pi, np.pi] (the real
    # pi lies between two doubles): below -np.pi is the half-turn too, above np.pi is np.pi.
    theta = np.arctan2(s, c)
    theta = np.where(theta <= -np.pi, np.pi, np.minimum(theta, np.pi))
    with np.errstate(over="ignore"):           # reported below
        out = theta / tau
    if not np.isfinite(out).all():
        idx = tuple(int(i) for i in np.argwhere(~np.isfinite(out))[0]) if out.ndim else ()
        t = float(np.broadcast_to(tau, out.shape)[idx])
        where = f" at index [{', '.join(map(str, idx))}]" if idx else ""
        raise ValueError(f"so2.log divides the angle by tau, and the quotient overflows "
                         f"float64{where}: tau = {t:.3g} is too small; expected |tau| of at "
                         f"least |angle| / 1.7e308 (|tau| >= 1.9e-308 always works)")
    return out[()] if out.ndim == 0 else out


def from_complex(z):
    r"""The real 2x2 matrix of a complex number: :math:`\Phi(a + jb) = aI + bJ`.

    :math:`\Phi` respects products and conjugates (:math:`\Phi(z_1z_2) =
    \Phi(z_1)\Phi(z_2)`, :math:`\Phi(\bar z) = \Phi(z)^T`, :math:`\det\Phi(z) = |z|^2`),
    so a unit complex number maps to a rotation (spec S25).

    Parameters
    ----------
    z : complex or array_like of complex, shape (...)

    Returns
    -------
    M : ndarray, shape (..., 2, 2)
    """
    arr = as_numbers(z, "z", "so2.from_complex", complex_ok=True)
    check_batch_axes(arr, 0, "z", "so2.from_complex")
    if not np.isfinite(arr).all():
        raise ValueError("so2.from_complex expects finite complex numbers; z has NaN or inf")
    a, b = arr.real, arr.imag
    return a[..., None, None] * np.eye(2) + b[..., None, None] * J


def to_complex(M, tol=1e-9):
    r"""The complex number of a matrix :math:`aI + bJ`: returns :math:`a + jb`.

    Parameters
    ----------
    M : array_like, shape (..., 2, 2)
        Of the form ``[[a, -b], [b, a]]`` within ``tol`` relative to its largest entry
        (every rotation is; a general 2x2 matrix is not).
    tol : float

    Returns
    -------
    z : complex or ndarray of complex, shape (...)
    """
    M = as_matrices(M, 2, "M", "so2.to_complex")
    tol = as_tolerance(tol, "so2.to_complex")
    off = np.maximum(np.abs(M[..., 0, 0] - M[..., 1, 1]), np.abs(M[..., 0, 1] + M[..., 1, 0]))
    scale = np.abs(M).max(axis=(-2, -1))
    bad = off > tol * scale
    if bad.any():
        idx = tuple(np.argwhere(bad)[0]) if bad.ndim else ()
        where = f"M[{', '.join(map(str, idx))}]" if idx else "M"
        raise ValueError("so2.to_complex expects a matrix of the form a I + b J = "
                         f"[[a, -b], [b, a]]; {where} differs from that form by "
                         f"{float(off[idx]):.2e}")
    z = 0.5 * (M[..., 0, 0] + M[..., 1, 1]) + 0.5j * (M[..., 1, 0] - M[..., 0, 1])
    return z[()] if z.ndim == 0 else z
