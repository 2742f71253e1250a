r"""The rotation group SO(3): hat and vee, the exponential and the principal logarithm.

Notation (the course's, then other authors')
--------------------------------------------
=================  ===============================  ==================================
here               meaning                          elsewhere
=================  ===============================  ==================================
``hat(a)``         the skew matrix with             :math:`a^\wedge` (Barfoot), ``skew``,
                   ``hat(a) @ b == cross(a, b)``    :math:`[a]_\times` (Sola et al.)
``vee(M)``         inverse of ``hat``               :math:`M^\vee`
``omega``, ``tau`` angular velocity (rad/s) acting  Gallier: :math:`A = \tau\hat\omega`
                   for a time ``tau`` (s)
``phi``            rotation vector ``omega * tau``  Sola et al.: :math:`\boldsymbol\theta`
``theta``          angle ``|phi|``                  Gallier: :math:`\theta`
``exp(omega,tau)`` :math:`e^{\tau\hat\omega}`       Sola et al.: ``Exp``
``log(R, tau)``    principal logarithm / ``tau``    Sola et al.: ``Log``; the notes:
                                                    :math:`\ln_\tau R`
=================  ===============================  ==================================

The formulas are derived in notebooks 01, 02 and 04. Comments cite "spec Sn", the
numbered statements of the course's specification; the notebooks teach them in order
(S1-S5 in notebook 01, S6-S11 in 02, S12-S23 in 04, S24-S28 in 03), and the numerical
algorithms here are S23's, with the error analysis of S10, S11, S14 and S19.

References: the lecture notes and Gallier's textbook excerpt the course follows;
J. Sola, J. Deray, D. Atchuthan, "A micro Lie theory for state estimation in robotics"
(2018); J. Gallier, "Geometric Methods and Applications" (Rodrigues' formula and the
surjectivity of exp).
"""

import math

import numpy as np

from .validation import (ROTATION_TOL, as_matrices, as_times, as_tolerance, as_vectors,
                         broadcast_batch, check_rotation, check_skew, rotation_defects)

__all__ = ["hat", "vee", "exp", "log", "angle", "is_rotation", "random_rotation"]

# Batches are computed in blocks of _BLOCK rotations: the temporaries of a block (32 kB
# each) stay in the processor's cache, and the extra memory of a call stays well below
# the size of its result. Up to _FEW rotations are computed in plain floats, which is
# quicker than NumPy's overhead per call; both paths give the same bits.
_BLOCK = 4096
_FEW = 8

# Squared lengths between these bounds are formed as x*x + y*y + z*z without underflow or
# overflow; rotation vectors outside (|phi| < 1e-145 or > 1e145, and phi = 0) take the
# careful branches. Below 1e-145 the Taylor series of A and B stops at its first term:
# the next is below 1e-290 relative (spec S10).
_SQ_LO, _SQ_HI = 1e-290, 1e290

# |phi_i| below this bound cannot overflow |phi| (sqrt(3) * 1e300 < 1.8e308).
_PHI_SAFE = 1e300


def hat(v):
    r"""The skew matrix of a vector: ``hat(a) @ b == cross(a, b)``.

    .. math:: \hat a = \begin{pmatrix} 0 & -a_3 & a_2 \\ a_3 & 0 & -a_1 \\
              -a_2 & a_1 & 0 \end{pmatrix}

    Parameters
    ----------
    v : array_like, shape (..., 3)

    Returns
    -------
    M : ndarray, shape (..., 3, 3)
        Skew-symmetric: ``M.T == -M``. Notebook 01, equation (1.1).
    """
    v = as_vectors(v, 3, "v", "hat")
    x, y, z = v[..., 0], v[..., 1], v[..., 2]
    M = np.zeros(v.shape[:-1] + (3, 3))
    M[..., 0, 1], M[..., 0, 2] = -z, y
    M[..., 1, 0], M[..., 1, 2] = z, -x
    M[..., 2, 0], M[..., 2, 1] = -y, x
    return M


def vee(M, check=True):
    r"""The vector of a skew matrix, the inverse of :func:`hat`.

    .. math:: M^\vee = (M_{32}, M_{13}, M_{21}) \quad (1\text{-based indices})

    Parameters
    ----------
    M : array_like, shape (..., 3, 3)
        Skew-symmetric up to ``SKEW_RTOL`` relative to its largest entry.
    check : bool
        Refuse a matrix that is not skew-symmetric (default). With ``False`` the
        entries below the diagonal are read and the rest is ignored.

    Returns
    -------
    v : ndarray, shape (..., 3)
    """
    M = as_matrices(M, 3, "M", "vee")
    if check:
        check_skew(M, "vee")
    return np.stack([M[..., 2, 1], M[..., 0, 2], M[..., 1, 0]], axis=-1)


def _angle_and_axis(phi):
    """Split rotation vectors into ``theta = |phi|`` and the unit axis ``n``, overflow-free.

    With ``m = max_i |phi_i|`` and ``q = phi / m``, ``theta = m |q|`` and ``n = q / |q|``:
    nothing is squared at the scale of ``phi``, so ``|phi| = 5e-200`` and ``5e200`` both
    come out right (spec S11). Where ``phi = 0``, ``theta = 0`` and ``n = 0``.
    """
    m = np.abs(phi).max(axis=-1)
    q = phi / np.where(m > 0, m, 1.0)[..., None]
    nq = np.sqrt(np.einsum("...i,...i->...", q, q))
    n = q / np.where(nq > 0, nq, 1.0)[..., None]
    return m * nq, n


def exp(omega, tau=1.0):
    r"""Rotation reached by the constant angular velocity ``omega`` acting for ``tau``.

    .. math:: R(\omega, \tau) = e^{\tau\hat\omega}
              = I + A(\theta)\,\hat\varphi + B(\theta)\,\hat\varphi^2,
              \qquad \varphi = \omega\tau,\ \theta = \lVert\varphi\rVert,

    with :math:`A(t) = \sin t / t` and :math:`B(t) = (1 - \cos t)/t^2
    = 2\sin^2(t/2)/t^2` (Rodrigues' formula, notebook 02, spec S7).

    Parameters
    ----------
    omega : array_like, shape (..., 3)
        Angular velocity, rad/s.
    tau : float or array_like, default 1.0
        Time, s. Broadcasts against the leading shape of ``omega``: one ``omega`` with
        an array of times gives the rotations along its path.

    Returns
    -------
    R : ndarray, shape (broadcast(omega.shape[:-1], tau.shape) + (3, 3))

    Notes
    -----
    Accurate to a few units of ``eps * max(1, theta)`` at every angle (spec S23;
    the factor ``theta`` is the conditioning of the problem, spec S11):

    * ``1e-145 <= theta <= 1e145``: one tangent gives both coefficients. With
      ``t = tan(theta/2)``, ``sin(theta) = 2t / (1 + t^2)`` and
      ``1 - cos(theta) = 2 sin^2(theta/2) = t sin(theta)``, so ``A = sin(theta)/theta``
      and ``B = A t / theta``. Nothing cancels: not at small angles, unlike the naive
      ``(1 - cos t)/t^2`` (notebook 02, "Small angles"), and not near ``theta = pi``,
      where ``t`` is large and ``2t / (1 + t^2)`` stays exact;
    * ``theta < 1e-145``: ``A = 1``, ``B = 1/2``, the Taylor series (spec S10), whose next
      terms are below 1e-290;
    * ``theta > 1e145``: the unit-axis form ``I + sin(t) hat(n) + 2 sin^2(t/2) hat(n)^2``,
      so ``hat(phi)^2`` cannot overflow.

    ``hat(u)^2 = u u^T - |u|^2 I`` (the Lemma) is written out entry by entry, with the
    diagonal as ``1 - b (u_j^2 + u_k^2)`` so that nothing cancels. A batch is computed in
    blocks of a few thousand rotations and a few rotations in plain floats, with the same
    formulas and the same bits.
    """
    omega = as_vectors(omega, 3, "omega", "exp")
    tau = as_times(tau, "exp")
    if tau.ndim == 0:                           # phi = omega * scale, block by block
        batch, phi, scale = omega.shape[:-1], omega, float(tau)
    else:
        batch = broadcast_batch(omega.shape[:-1], tau, "exp", "omega")
        with np.errstate(over="ignore"):        # overflow is reported below
            phi, scale = omega * tau[..., None], 1.0
    rows = phi.reshape(-1, 3)
    if len(rows) <= _FEW:
        R = [_exp_one(scale * x, scale * y, scale * z) for x, y, z in rows.tolist()]
        if None not in R:
            return np.array(R).reshape(batch + (3, 3))
    if not _largest_abs(phi) * abs(scale) <= _PHI_SAFE:   # rare: check the careful way
        _check_rotation_vectors(omega, tau)

    R = np.empty(batch + (3, 3))
    out = R.reshape(-1, 3, 3)
    for i in range(0, len(rows), _BLOCK):
        _exp_block(rows[i:i + _BLOCK], scale, out[i:i + _BLOCK])
    return R


def _largest_abs(a):
    """``max |a_i|`` over all entries (0 for an empty array), without a temporary array."""
    if a.size <= 3:
        return max(map(abs, a.ravel().tolist()), default=0.0)
    return max(float(a.max()), -float(a.min()))


def _check_rotation_vectors(omega, tau):
    """Raise ValueError if ``phi = omega * tau`` or its length overflows float64."""
    with np.errstate(over="ignore", invalid="ignore"):
        phi = omega * tau[..., None]
        if not np.isfinite(phi).all():
            raise ValueError("exp: the rotation vector omega * tau overflows float64; "
                             "expected |omega * tau| below about 1e308")
        theta, _ = _angle_and_axis(phi)
    if not np.isfinite(theta).all():
        raise ValueError("exp: the rotation angle |omega * tau| overflows float64; "
                         "expected an angle below about 1e308")


def _coefficients(theta2):
    """``A = sin(theta)/theta`` and ``B = (1 - cos theta)/theta^2`` from ``theta^2``.

    One tangent, ``t = tan(theta/2)``, gives both: ``sin(theta) = 2t/(1 + t^2)`` and
    ``1 - cos(theta) = t sin(theta)``. For a float or an array alike: NumPy's tan of one
    number equals its tan of that number inside an array, so one rotation and a batch
    get the same bits.
    """
    theta = np.sqrt(theta2)
    t = np.tan(0.5 * theta)
    a = (t + t) / (1.0 + t * t) / theta
    return a, a * t / theta


def _rodrigues_entries(x, y, z, a, b):
    r"""The nine entries, row by row, of :math:`I + a\,\hat u + b\,\hat u^2`, ``u = (x, y, z)``.

    :math:`\hat u^2 = u u^T - \lVert u\rVert^2 I` (the Lemma), so the diagonal is
    ``1 - b (u_j^2 + u_k^2)`` (nothing cancels) and the entry ``(i, j)`` off it is
    ``b u_i u_j`` plus or minus ``a u_k``. In floats, for a few rotations;
    :func:`_exp_block` writes the same lines into a block of matrices.
    """
    xx, yy, zz = x * x, y * y, z * z
    bx, by = b * x, b * y
    bxy, bxz, byz = bx * y, bx * z, by * z
    ax, ay, az = a * x, a * y, a * z
    return (1.0 - b * (yy + zz), bxy - az, bxz + ay,
            bxy + az, 1.0 - b * (xx + zz), byz - ax,
            bxz - ay, byz + ax, 1.0 - b * (xx + yy))


def _exp_one(x, y, z):
    """The nine entries of ``exp(hat(phi))`` for one ``phi = (x, y, z)``, in floats;
    None when ``|phi| > 1e145`` or overflows (the block kernel then takes it)."""
    theta2 = x * x + y * y + z * z
    if theta2 > _SQ_HI:
        return None
    if theta2 < _SQ_LO:
        a, b = 1.0, 0.5                         # Taylor: A = 1 - theta^2/6, B = 1/2 - ...
    else:
        a, b = map(float, _coefficients(theta2))
    return _rodrigues_entries(x, y, z, a, b)


def _exp_block(phi, scale, R):
    r"""``R = exp(hat(scale * phi))`` for a block of rotation vectors ``phi``, shape (m, 3).

    Rodrigues' formula (notebook 02, spec S7) on contiguous arrays of components, with
    :math:`\hat\varphi^2 = \varphi\varphi^T - \theta^2 I` (the Lemma) written out:

    .. math:: R = I + A\,\hat\varphi + B\,\hat\varphi^2 =
              \begin{pmatrix} 1 - B(y^2 + z^2) & Bxy - Az & Bxz + Ay \\
                               Bxy + Az & 1 - B(x^2 + z^2) & Byz - Ax \\
                               Bxz - Ay & Byz + Ax & 1 - B(x^2 + y^2) \end{pmatrix},

    with :math:`A = \sin\theta/\theta`, :math:`B = (1 - \cos\theta)/\theta^2` and
    :math:`\theta^2 = x^2 + y^2 + z^2`. The same lines as :func:`_rodrigues_entries`,
    written into ``R`` directly.
    """
    x, y, z = phi.T.copy()                      # three contiguous arrays (m,)
    if scale != 1.0:
        x *= scale
        y *= scale
        z *= scale
    with np.errstate(over="ignore"):           # |phi| > 1e154 squares to inf: careful
        xx, yy, zz = x * x, y * y, z * z
        theta2 = xx + yy
        theta2 += zz
    careful = not (_SQ_LO <= theta2.min() and theta2.max() <= _SQ_HI)
    if careful:                                 # phi = 0, |phi| < 1e-145 or > 1e145
        tiny, huge = theta2 < _SQ_LO, theta2 > _SQ_HI
        theta2[tiny | huge] = 1.0               # placeholder, replaced below
    a, b = _coefficients(theta2)                # A and B
    if careful:
        a[tiny], b[tiny] = 1.0, 0.5             # Taylor, as in _exp_one
        if huge.any():                          # unit axis n, a = sin, b = 1 - cos
            theta, n = _angle_and_axis(np.stack([x[huge], y[huge], z[huge]], axis=-1))
            t = np.tan(0.5 * theta)
            a[huge] = (t + t) / (1.0 + t * t)
            b[huge] = a[huge] * t
            x[huge], y[huge], z[huge] = n.T
            xx[huge], yy[huge], zz[huge] = n.T * n.T

    out = R.reshape(len(R), 9)                  # entries row by row: R00 R01 R02 R10 ...
    np.subtract(1.0, b * (yy + zz), out=out[:, 0])
    np.subtract(1.0, b * (xx + zz), out=out[:, 4])
    np.subtract(1.0, b * (xx + yy), out=out[:, 8])
    bx, by = b * x, b * y
    bxy, bxz, byz = bx * y, bx * z, by * z      # B x y, B x z, B y z
    ax, ay, az = a * x, a * y, a * z            # A x, A y, A z
    np.subtract(bxy, az, out=out[:, 1])
    np.add(bxy, az, out=out[:, 3])
    np.add(bxz, ay, out=out[:, 2])
    np.subtract(bxz, ay, out=out[:, 6])
    np.subtract(byz, ax, out=out[:, 5])
    np.add(byz, ax, out=out[:, 7])


def _validated_rotations(R, check, tol, func):
    R = as_matrices(R, 3, "R", func)
    if check:
        check_rotation(R, as_tolerance(tol, func), func)
    return R


def _skew_and_trace(r):
    """``v = vee(R - R^T) = 2 sin(theta) n`` and ``c = (tr R - 1)/2 = cos(theta)``.

    ``r`` holds the nine entries of ``R`` row by row: floats, or arrays over a block.
    """
    r00, r01, r02, r10, r11, r12, r20, r21, r22 = r
    v = (r21 - r12, r02 - r20, r10 - r01)
    return v, 0.5 * (r00 + r11 + r22 - 1.0)


def _norm3(v):
    """Euclidean norm over the last axis without overflow or underflow."""
    return np.hypot(np.hypot(v[..., 0], v[..., 1]), v[..., 2])


def _half_norm(v):
    """``s = |v|/2`` for a block (``v`` three arrays); hypot where the squares would
    underflow or overflow (``v = 0`` among them)."""
    vx, vy, vz = v
    with np.errstate(over="ignore"):           # overflow: recomputed below
        vv = vx * vx + vy * vy + vz * vz
    s = 0.5 * np.sqrt(vv)
    if not (_SQ_LO <= vv.min() and vv.max() <= _SQ_HI):
        odd = (vv < _SQ_LO) | (vv > _SQ_HI)
        s[odd] = 0.5 * _norm3(np.stack([vx[odd], vy[odd], vz[odd]], axis=-1))
    return s


def _half_norm_one(v):
    """``s = |v|/2`` for one ``v`` (three floats), as :func:`_half_norm` computes it."""
    vv = v[0] * v[0] + v[1] * v[1] + v[2] * v[2]
    if _SQ_LO <= vv <= _SQ_HI:
        return 0.5 * math.sqrt(vv)
    return 0.5 * float(np.hypot(np.hypot(v[0], v[1]), v[2]))


def angle(R, check=True, tol=ROTATION_TOL):
    r"""Rotation angle :math:`\theta \in [0, \pi]` of each rotation matrix.

    .. math:: \theta = \operatorname{atan2}\!\Big(\tfrac12\lVert(R - R^T)^\vee\rVert,\
              \tfrac12(\operatorname{tr} R - 1)\Big)

    ``atan2`` rather than ``arccos((tr R - 1)/2)``: arccos loses half the digits near 0
    and pi and returns NaN when rounding pushes its argument past 1 (spec S14,
    notebook 04).

    Parameters
    ----------
    R : array_like, shape (..., 3, 3)
    check : bool
        Refuse matrices that are not rotations within ``tol`` (default).
    tol : float

    Returns
    -------
    theta : ndarray, shape (...)
    """
    R = _validated_rotations(R, check, tol, "angle")
    rows = R.reshape(-1, 9)                     # each matrix as a row of nine entries
    if len(rows) <= _FEW:
        theta = np.array([float(np.arctan2(_half_norm_one(v), c))
                          for v, c in map(_skew_and_trace, rows.tolist())])
        return theta.reshape(R.shape[:-2])[()]
    theta = np.empty(len(rows))
    for i in range(0, len(rows), _BLOCK):
        v, c = _skew_and_trace(rows[i:i + _BLOCK].T.copy())
        theta[i:i + _BLOCK] = np.arctan2(_half_norm(v), c)
    return theta.reshape(R.shape[:-2])[()]


def log(R, tau=1.0, check=True, tol=ROTATION_TOL):
    r"""Principal logarithm of rotations, divided by the time ``tau``.

    .. math:: \ln_\tau R = \frac{\operatorname{Log} R}{\tau} = \frac{\theta\,n}{\tau},
              \qquad e^{\tau\,\widehat{\ln_\tau R}} = R,\quad \theta \in [0, \pi]

    ``Log R`` is the rotation vector of angle at most pi whose exponential is ``R``
    (notebook 04, spec S15 to S19). With ``tau`` it is the angular velocity that
    reaches ``R`` in time ``tau`` by the shortest turn.

    Parameters
    ----------
    R : array_like, shape (..., 3, 3)
        Rotation matrices (within ``tol``, see :mod:`so3lib.validation`).
    tau : float or array_like, default 1.0
        Nonzero time; broadcasts against the leading shape of ``R``.
    check : bool
        Refuse matrices that are not rotations (default). ``False`` skips the test for
        speed; the result for a non-rotation is then meaningless.
    tol : float

    Returns
    -------
    phi : ndarray, shape (broadcast(R.shape[:-2], tau.shape) + (3,))
        ``|phi * tau| <= pi``.

    Notes
    -----
    ``v = vee(R - R^T) = 2 sin(theta) n``, ``c = (tr R - 1)/2 = cos(theta)`` and
    ``theta = atan2(|v|/2, c)`` (spec S12 to S14). Then

    * ``c >= 0`` (theta <= pi/2): ``Log R = theta / (2 sin theta) v`` with
      ``sin theta = |v|/2``; no series is needed, and ``Log I = 0``;
    * ``c < 0`` (theta > pi/2): the skew part is small and its direction unreliable
      near pi (0/0 at pi), so the axis comes from the symmetric part,
      ``(R + R^T)/2 - c I = (1 - c) n n^T``: its column with the largest diagonal entry,
      normalised (that entry is at least 1/3). The sign is the one with ``n . v >= 0``
      (spec S19, notebook 04, "Near pi").

    At exactly ``theta = pi`` both ``+pi n`` and ``-pi n`` are logarithms. When ``R`` is
    exactly symmetric (``v = 0``) this function returns the one whose component of largest
    absolute value is positive (the first such component on a tie); when ``R`` carries rounding
    noise the noise picks the sign, and either answer is correct to that noise.

    A batch is computed in blocks of a few thousand rotations and a few rotations in
    plain floats, with the same steps and the same bits.
    """
    R = _validated_rotations(R, check, tol, "log")
    tau = as_times(tau, "log", nonzero=True)
    broadcast_batch(R.shape[:-2], tau, "log", "R")
    rows = R.reshape(-1, 9)                     # each matrix as a row of nine entries
    scale = float(tau) if tau.ndim == 0 else 1.0    # divide by a scalar tau block by block
    if len(rows) <= _FEW:
        L = np.array([[p / scale + 0.0 for p in _log_one(r)] for r in rows.tolist()])
        L = L.reshape(R.shape[:-2] + (3,))
        return L if tau.ndim == 0 else L / tau[..., None] + 0.0
    L = np.empty(R.shape[:-2] + (3,))
    out = L.reshape(-1, 3)
    for i in range(0, len(rows), _BLOCK):
        _log_block(rows[i:i + _BLOCK], scale, out[i:i + _BLOCK])
    return L if tau.ndim == 0 else L / tau[..., None] + 0.0   # + 0.0: no -0.0


def _log_one(r):
    """``Log R`` for one rotation given by its nine entries ``r``, in floats: the steps of
    :func:`_log_block`."""
    v, c = _skew_and_trace(r)
    s = _half_norm_one(v)
    theta = float(np.arctan2(s, c))
    if c >= 0:
        k = theta / (2.0 * s) if s > 0 else 0.0
        return [k * vi for vi in v]
    # near pi: the column of (R + R^T)/2 - c I with the largest diagonal entry
    r00, r01, r02, r10, r11, r12, r20, r21, r22 = r
    d0, d1, d2 = r00 - c, r11 - c, r22 - c
    s01, s02, s12 = 0.5 * (r01 + r10), 0.5 * (r02 + r20), 0.5 * (r12 + r21)
    if d0 >= d1 and d0 >= d2:
        col = (d0, s01, s02)
    elif d1 >= d2:
        col = (s01, d1, s12)
    else:
        col = (s02, s12, d2)
    k = theta / math.sqrt(col[0] * col[0] + col[1] * col[1] + col[2] * col[2])
    if col[0] * v[0] + col[1] * v[1] + col[2] * v[2] < 0:
        k = -k
    return [k * ci for ci in col]


def _near_pi(r, v, c, theta):
    """``theta n`` for a block, with ``n`` from the symmetric part (spec S19).

    Computed for every row of the block and used where ``c < 0``: there the largest
    diagonal entry of ``(R + R^T)/2 - c I`` is at least ``(1 - c)/3 > 1/3``, so nothing
    divides by zero; in the other rows it may, and those values are dropped.
    """
    r00, r01, r02, r10, r11, r12, r20, r21, r22 = r
    d0, d1, d2 = r00 - c, r11 - c, r22 - c             # diagonal of (R + R^T)/2 - c I
    s01, s02, s12 = 0.5 * (r01 + r10), 0.5 * (r02 + r20), 0.5 * (r12 + r21)
    j0 = (d0 >= d1) & (d0 >= d2)                       # the first largest diagonal entry
    j1 = d1 >= d2
    col = (np.where(j0, d0, np.where(j1, s01, s02)),   # its column
           np.where(j0, s01, np.where(j1, d1, s12)),
           np.where(j0, s02, np.where(j1, s12, d2)))
    with np.errstate(over="ignore", divide="ignore", invalid="ignore"):
        k = theta / np.sqrt(col[0] * col[0] + col[1] * col[1] + col[2] * col[2])
        np.negative(k, out=k, where=col[0] * v[0] + col[1] * v[1] + col[2] * v[2] < 0)
        return [k * ci for ci in col]


def _log_block(rows, scale, out):
    r"""``out = Log(R) / scale`` for a block of rotations given as rows of nine entries.

    The steps of spec S23 on contiguous arrays, one per entry of ``R``:
    ``v = vee(R - R^T)``, ``c = (tr R - 1)/2``, ``s = |v|/2``, ``theta = atan2(s, c)``;
    ``Log R = theta / (2 s) v`` where ``c >= 0``, and ``theta n`` where ``c < 0``, with
    ``n`` the normalised column of ``(R + R^T)/2 - c I`` with the largest diagonal entry,
    signed so that ``n . v >= 0``.
    """
    r = rows.T.copy()                           # nine contiguous arrays (m,)
    v, c = _skew_and_trace(r)
    s = _half_norm(v)
    theta = np.arctan2(s, c)
    with np.errstate(divide="ignore", invalid="ignore"):
        k = np.where(s > 0, theta / (2.0 * s), 0.0)     # theta/(2s) -> 1/2 as s -> 0
    phi = [k * vi for vi in v]

    near_pi = c < 0
    if near_pi.any():
        phi = [np.where(near_pi, p_pi, p) for p_pi, p in zip(_near_pi(r, v, c, theta), phi)]

    for j, p in enumerate(phi):
        out[:, j] = p / scale + 0.0             # + 0.0 turns -0.0 into 0.0 for printing


def is_rotation(R, tol=ROTATION_TOL):
    r"""Whether each matrix is a rotation: :math:`R^T R = I` and :math:`\det R = 1`.

    Parameters
    ----------
    R : array_like, shape (..., 3, 3)
    tol : float
        Largest accepted ``max|R^T R - I|`` and ``|det R - 1|``.

    Returns
    -------
    ok : bool or ndarray of bool, shape (...)
    """
    R = as_matrices(R, 3, "R", "is_rotation")
    tol = as_tolerance(tol, "is_rotation")
    orth, det = rotation_defects(R)
    ok = (orth <= tol) & (np.abs(det - 1.0) <= tol)
    return bool(ok) if ok.ndim == 0 else ok


def random_rotation(rng=None, size=None):
    r"""Rotations drawn uniformly (Haar measure) from SO(3).

    A 4-vector of independent standard normals, normalised, is a uniform unit
    quaternion :math:`q = (w, \mathbf{v})`; its rotation is

    .. math:: R(q) = (w^2 - \lVert\mathbf v\rVert^2) I + 2\mathbf v\mathbf v^T + 2w\hat{\mathbf v}.

    Parameters
    ----------
    rng : numpy.random.Generator, int or None
        A generator, or a seed for one. Pass one for reproducible notebooks.
    size : None, int or tuple of int
        Batch shape; ``None`` gives a single (3, 3) matrix.

    Returns
    -------
    R : ndarray, shape (*size, 3, 3)
    """
    if rng is None or isinstance(rng, (int, np.integer)):
        rng = np.random.default_rng(rng)
    elif not isinstance(rng, np.random.Generator):
        raise ValueError("random_rotation expects rng as a numpy.random.Generator, an int "
                         f"seed or None; got {type(rng).__name__}")
    if size is None:
        shape = ()
    else:
        try:
            shape = (int(size),) if np.ndim(size) == 0 else tuple(int(k) for k in size)
        except (TypeError, ValueError):
            shape = None
        if shape is None or any(k < 0 for k in shape):
            raise ValueError("random_rotation expects size as None, a nonnegative int or a "
                             f"tuple of them; got {size!r}")
    g = rng.standard_normal(shape + (4,))
    norm = np.sqrt(np.einsum("...i,...i->...", g, g))
    w, vec = g[..., 0] / norm, g[..., 1:] / norm[..., None]
    R = 2.0 * vec[..., :, None] * vec[..., None, :] + 2.0 * w[..., None, None] * hat(vec)
    diag = w * w - np.einsum("...i,...i->...", vec, vec)
    R += diag[..., None, None] * np.eye(3)
    return R
