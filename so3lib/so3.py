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

from .validation import (MAX_BATCH_AXES, ROTATION_TOL, as_matrices, as_times, as_tolerance,
                         as_vectors, broadcast_batch, check_rotation, check_skew,
                         rotation_defects)

__all__ = ["hat", "vee", "exp", "log", "angle", "is_rotation", "random_rotation"]

# Batches are computed in blocks of _BLOCK rotations by one kernel per function: the
# temporaries of a block (a few hundred kB) stay in the processor's cache, and the extra
# memory of a call stays well below the size of its result. One rotation is a block of
# one, so it takes the very same steps and gets the same bits as inside a batch.
_BLOCK = 4096

# Squared lengths between these bounds are formed as x*x + y*y + z*z without underflow or
# overflow; vectors outside take the careful branches (hypot, or exp's unit-axis form
# above |phi| = 1e145, where B = (1 - cos theta)/theta^2 would leave the normal floats).
_SQ_LO, _SQ_HI = 1e-290, 1e290


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

    with :math:`A(x) = \sin x / x` and :math:`B(x) = (1 - \cos x)/x^2
    = 2\sin^2(x/2)/x^2` (Rodrigues' formula, notebook 02, spec S7).

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
    the factor ``theta`` is the conditioning of the problem, spec S11).

    One tangent gives the whole matrix, at every angle from 0 up to ``theta = 1e145``.
    With ``h = theta/2``, ``t = tan(h)`` and ``u = t n = (t/h) phi/2`` (so ``|u| = t``),

    .. math:: R = \frac{(1 - t^2)\,I + 2uu^T + 2\hat u}{1 + t^2},

    which is Rodrigues' formula term by term: ``(1 - t^2)/(1 + t^2) = cos(theta)``,
    ``2t/(1 + t^2) = sin(theta)`` and ``2t^2/(1 + t^2) = 1 - cos(theta)`` (it is also the
    rotation of the unit quaternion ``(1, u)/sqrt(1 + t^2)``, notebook 05). Nothing
    cancels: not at small angles, where ``t/h`` is 1 to the last bit (no Taylor branch;
    ``theta^2`` is raised to 1e-300 first, so ``phi = 0`` gives ``I``), unlike the naive
    ``(1 - cos t)/t^2`` (notebook 02, "Small angles"); and not near ``theta = pi``,
    where ``t`` is large and every term keeps its digits. Above ``theta = 1e145`` the
    unit axis gives ``u = t n`` directly, so that nothing is squared at that scale.

    The entries are written out with the Lemma (``u u^T - |u|^2 I = hat(u)^2``) and
    summed by one exact matrix product (:func:`_from_tangent`). A batch is computed in
    blocks of a few thousand rotations by one kernel (:func:`_exp_block`); a single
    rotation takes the same steps in plain floats (:func:`_exp_one`), with the same bits,
    because NumPy's cost per call is most of the time of one rotation.

    The formula above is what ``exp`` computes, to the last bit (a test runs this):

    >>> import numpy as np
    >>> from so3lib import exp
    >>> same = []
    >>> for z in (1e-200, 1e-9, 1e-4, 0.5, 3.0, np.pi - 1e-9, 1e6, 1e140):  # phi = (0,0,z)
    ...     h = z / 2                               # theta = z
    ...     t = np.tan(h)
    ...     R = exp([0.0, 0.0, z])
    ...     same.append(bool(R[1, 0] == (t / h * z) / (1 + t * t)
    ...                      and R[0, 0] == (1 - t * t) / (1 + t * t)))
    >>> same
    [True, True, True, True, True, True, True, True]
    """
    omega = as_vectors(omega, 3, "omega", "exp", finite=False)    # NaN: found below
    tau = as_times(tau, "exp")
    if tau.ndim == 0:                           # phi = omega * scale, block by block
        batch, phi, scale = omega.shape[:-1], omega, float(tau)
    else:
        batch = broadcast_batch(omega.shape[:-1], tau, "exp", "omega")
        with np.errstate(over="ignore"):        # overflow is reported below
            phi, scale = omega * tau[..., None], 1.0
    rows = phi.reshape(-1, 3)
    if len(rows) == 1:                          # one rotation: plain floats are quicker
        R = _exp_one(*(scale * x for x in rows[0].tolist()))
        if R is not None:
            return np.array(R).reshape(batch + (3, 3))
    R = np.empty(batch + (3, 3))
    out = R.reshape(-1, 9)                      # each matrix as a row of nine entries
    for i in range(0, len(rows), _BLOCK):
        if not _exp_block(rows[i:i + _BLOCK], scale, out[i:i + _BLOCK]):
            as_vectors(omega, 3, "omega", "exp")    # raises for NaN and inf
            _check_rotation_vectors(omega, tau)     # raises if omega * tau overflows
            _exp_huge_block(rows[i:i + _BLOCK], scale, out[i:i + _BLOCK])
    return R


def _check_rotation_vectors(omega, tau):
    """Raise ValueError if ``phi = omega * tau`` or its length overflows float64."""
    with np.errstate(over="ignore", invalid="ignore"):
        phi = omega * tau[..., None]
        bad = ~np.isfinite(phi).all(axis=-1)
        if bad.any():
            idx = tuple(int(i) for i in np.argwhere(bad)[0])
            raise ValueError(f"exp: the rotation vector omega * tau overflows float64"
                             f"{' at index ' + _index(idx) if idx else ''}; expected "
                             f"|omega * tau| below about 1e308")
        theta, _ = _angle_and_axis(phi)
    if not np.isfinite(theta).all():
        raise ValueError("exp: the rotation angle |omega * tau| overflows float64; "
                         "expected an angle below about 1e308")


def _index(idx):
    return "[" + ", ".join(map(str, idx)) + "]"


# Rodrigues' formula as one matrix product. With 2u = 2 t n (h = theta/2, t = tan(h),
# n the unit axis) and d = 1 + t^2, each of the nine entries of R is the sum of two of
# the 13 numbers F = ((1 - t^2)/d, 2u_x/d, 2u_y/d, 2u_z/d, (2u_x/d)(2u_x), ...,
# (2u_z/d)(2u_z)): the diagonal (1 - t^2)/d + (2u_i/d)(2u_i)/2, the rest
# (2u_i/d)(2u_j)/2 -+ 2u_k/d, as hat(2u) places 2u_k. Row k of _COMBINE holds the
# coefficients (0, +-1 or 1/2) of F_k in the nine entries, row by row; R_ij and R_ji
# take the same product (i <= j).
_COMBINE = np.zeros((13, 9))
_COMBINE[0, ::4] = 1.0                          # 1 - t^2 on the diagonal
for _i in range(3):
    for _j in range(3):
        _COMBINE[4 + 3 * min(_i, _j) + max(_i, _j), 3 * _i + _j] = 0.5     # 2 u_i u_j
_COMBINE[[3, 2, 3, 1, 2, 1], [1, 2, 3, 5, 6, 7]] = [-1.0, 1.0, 1.0, -1.0, -1.0, 1.0]  # hat


def _from_tangent(k, p, t, out):
    r"""``out`` = the rotations with ``2u = k p`` and ``t = |u| = tan(theta/2)``, each
    matrix as a row of nine entries:

    .. math:: R = \frac{(1 - t^2)\,I + 2uu^T + 2\hat u}{1 + t^2}

    ``p`` has shape (3, m) (rotation vectors or unit axes, as columns), ``k`` and ``t``
    shape (m,). The product with ``_COMBINE`` adds two nonzero numbers per entry and
    exact zeros, so it rounds once, in any order of summation: a batch and one rotation
    get the same bits.
    """
    F = np.empty((13, len(t)))
    two_u = k * p
    tt = t * t
    np.subtract(1.0, tt, out=F[0])
    tt += 1.0                                   # 1 + t^2
    F[0] /= tt
    np.divide(two_u, tt, out=F[1:4])
    np.multiply(F[1:4, None, :], two_u, out=F[4:].reshape(3, 3, -1))   # 2u_i 2u_j / (1 + t^2)
    np.matmul(F.T, _COMBINE, out=out)


def _exp_block(rows, scale, out):
    r"""``out = exp(hat(scale * phi))`` for a block of rotation vectors, ``rows`` (m, 3).

    Returns False, computing nothing more, when some ``|phi|`` exceeds 1e145 or is not
    finite (:func:`_exp_huge_block` takes those). ``theta^2`` comes from ``einsum``,
    which gives inf rather than a warning when it overflows, and sums each row in the
    same order whatever the length of the block.
    """
    phi = _scaled(rows, scale)
    theta2 = np.einsum("ij,ij->i", phi, phi)
    if not theta2.max() <= _SQ_HI:              # also False for NaN
        return False
    h = np.sqrt(np.maximum(theta2, 1e-300))     # 1e-300: phi = 0 divides nothing by 0
    h *= 0.5                                    # half the angle
    t = np.tan(h)
    _from_tangent(t / h, phi.T, t, out)         # 2u = 2 t n = (t/h) phi
    return True


def _exp_one(x, y, z):
    """The nine entries of ``exp(hat(phi))`` for one ``phi = (x, y, z)``, in plain floats.

    The steps of :func:`_exp_block` and :func:`_from_tangent`, operation for operation,
    so that one rotation gets the bits it gets inside a batch (``tests/test_kernels.py``),
    in a third of the time NumPy's calls take for one; None above ``|phi| = 1e145`` or
    for NaN and inf, which the kernel then takes.
    """
    theta2 = (x * x + z * z) + y * y            # einsum's order for a row of three
    if not theta2 <= _SQ_HI:
        return None
    h = math.sqrt(max(theta2, 1e-300)) * 0.5
    t = float(np.tan(h))                        # NumPy's tan, as in the kernel
    k = t / h
    u = (k * x, k * y, k * z)                   # 2u
    den = t * t + 1.0
    c = (1.0 - t * t) / den
    ux, uy, uz = a = [ui / den for ui in u]
    uu = [[a[i] * u[j] * 0.5 for j in range(3)] for i in range(3)]
    entries = (c + uu[0][0], uu[0][1] - uz, uu[0][2] + uy,
               uu[0][1] + uz, c + uu[1][1], uu[1][2] - ux,
               uu[0][2] - uy, uu[1][2] + ux, c + uu[2][2])
    return [e + 0.0 for e in entries]           # -0.0 to 0.0, as the kernel's sums give


def _scaled(rows, scale):
    """``scale * rows``; inf where that overflows (reported by :func:`exp`)."""
    if scale == 1.0:
        return rows
    with np.errstate(over="ignore"):
        return rows * scale


def _exp_huge_block(rows, scale, out):
    """A block with some ``1e145 < |phi| < 1e308``: those rows from the unit axis,
    ``2u = 2 t n``, so that nothing is squared at the scale of ``phi``; the others as
    usual."""
    phi = _scaled(rows, scale)
    theta2 = np.einsum("ij,ij->i", phi, phi)
    huge = theta2 > _SQ_HI
    small = np.flatnonzero(~huge)
    if len(small):
        small_out = np.empty((len(small), 9))
        _exp_block(phi[small], 1.0, small_out)
        out[small] = small_out
    theta, n = _angle_and_axis(phi[huge])
    t = np.tan(0.5 * theta)
    huge_out = np.empty((len(n), 9))
    _from_tangent(t + t, n.T, t, huge_out)
    out[huge] = huge_out


def _validated_rotations(R, check, tol, func):
    R = as_matrices(R, 3, "R", func)
    if check:
        check_rotation(R, as_tolerance(tol, func), func)
    return R


# vee(R - R^T) from the nine entries of R row by row: R21 - R12, R02 - R20, R10 - R01.
_SKEW_PLUS = np.array([7, 2, 3])
_SKEW_MINUS = np.array([5, 6, 1])


def _skew_and_trace(r):
    """``v = vee(R - R^T) = 2 sin(theta) n`` and ``c = (tr R - 1)/2 = cos(theta)``.

    ``r`` has shape (9, m): the nine entries of ``R`` row by row, across m matrices.
    """
    v = r.take(_SKEW_PLUS, axis=0) - r.take(_SKEW_MINUS, axis=0)
    c = r[0] + r[4]
    c += r[8]
    c -= 1.0
    c *= 0.5
    return v, c


def _norm3(v):
    """Euclidean norm over the first axis of a (3, m) array, without overflow or underflow."""
    return np.hypot(np.hypot(v[0], v[1]), v[2])


def _half_norm(v):
    """``s = |v|/2`` for ``v`` of shape (3, m); hypot where the squares would underflow or
    overflow (``v = 0`` among them)."""
    with np.errstate(over="ignore"):            # check=False and huge entries: inf
        sq = v * v
        vv = sq[0] + sq[1]
        vv += sq[2]
    s = np.sqrt(vv)
    s *= 0.5
    if not (_SQ_LO <= vv.min() and vv.max() <= _SQ_HI):
        odd = (vv < _SQ_LO) | (vv > _SQ_HI)
        s[odd] = 0.5 * _norm3(v[:, odd])
    return s


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
    theta = np.empty(len(rows))
    for i in range(0, len(rows), _BLOCK):
        v, c = _skew_and_trace(rows[i:i + _BLOCK].T.copy())
        with np.errstate(invalid="ignore"):     # check=False: inf entries give NaN
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
        Nonzero time; broadcasts against the leading shape of ``R``. A ``tau`` so small
        that ``Log(R) / tau`` overflows float64 is refused.
    check : bool
        Refuse matrices that are not rotations (default). ``False`` skips the test for
        speed and then returns a number for any finite 3x3 matrix, with no error and no
        warning: the value means nothing unless ``R`` is a rotation. For example
        ``log(-np.eye(3), check=False)`` returns ``(pi, 0, 0)``, although ``-I`` is a
        reflection (det = -1) and has no logarithm at all.
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

    A batch is computed in blocks of a few thousand rotations by one kernel
    (:func:`_log_block`); a single rotation takes the same steps in plain floats
    (:func:`_log_one`), with the same bits, because NumPy's cost per call is most of the
    time of one rotation.
    """
    R = _validated_rotations(R, check, tol, "log")
    tau = as_times(tau, "log", nonzero=True)
    if tau.ndim:
        broadcast_batch(R.shape[:-2], tau, "log", "R")
    rows = R.reshape(-1, 9)                     # each matrix as a row of nine entries
    scale = float(tau) if tau.ndim == 0 else 1.0    # divide by a scalar tau block by block
    if len(rows) == 1:                          # one rotation: plain floats are quicker
        L = np.array(_log_one(rows[0].tolist(), scale)).reshape(R.shape[:-2] + (3,))
    else:
        L = np.empty(R.shape[:-2] + (3,))
        out = L.reshape(-1, 3)
        for i in range(0, len(rows), _BLOCK):
            _log_block(rows[i:i + _BLOCK].T.copy(), scale, out[i:i + _BLOCK])
    if tau.ndim:
        with np.errstate(over="ignore"):       # overflow: reported below
            L = L / tau[..., None] + 0.0       # + 0.0: no -0.0
    if abs(scale) < _TAU_SMALL or (tau.ndim and np.abs(tau).min() < _TAU_SMALL):
        _check_quotient(L, tau, "log")
    return L


# |Log R| <= pi, so Log(R) / tau is finite whenever |tau| >= pi / 1.7e308.
_TAU_SMALL = 1.9e-308


def _check_quotient(L, tau, func):
    """Raise ValueError where ``L = Log(R) / tau`` overflowed float64 (``tau`` tiny)."""
    bad = ~np.isfinite(L).all(axis=-1)
    if bad.any():
        idx = tuple(int(i) for i in np.argwhere(bad)[0])
        t = float(np.broadcast_to(tau, bad.shape)[idx])
        where = f" at index {_index(idx)}" if idx else ""
        raise ValueError(f"{func} divides Log(R) by tau, and the quotient overflows float64"
                         f"{where}: tau = {t:.3g} is too small; expected |tau| of at least "
                         f"|Log R| / 1.7e308 (|tau| >= {_TAU_SMALL:.2g} always works)")


def _log_block(r, scale, out):
    r"""``out = Log(R) / scale`` for a block of rotations; ``r`` (9, m) holds their entries.

    The steps of spec S23 on arrays with one row per entry of ``R``:
    ``v = vee(R - R^T)``, ``c = (tr R - 1)/2``, ``s = |v|/2``, ``theta = atan2(s, c)``;
    ``Log R = theta / (2 s) v`` where ``c >= 0``, and ``theta n`` where ``c < 0``, with
    ``n`` the normalised column of ``(R + R^T)/2 - c I`` with the largest diagonal entry,
    signed so that ``n . v >= 0``.
    """
    v, c = _skew_and_trace(r)
    with np.errstate(all="ignore"):            # _near_pi off its rows; check=False
        s = np.sqrt(_dot(v, v))
        s *= 0.5
        # s = 0 (v = 0, or |v| < 1e-154 squared to 0): raised to the least subnormal,
        # theta = atan2(s, c) = s near 0 and theta/(2s) = 1/2, the limit; pi near pi.
        np.maximum(s, 5e-324, out=s)
        theta = np.arctan2(s, c)
        phi = theta / (s + s) * v               # theta/(2s) -> 1/2 as s -> 0
        near_pi = c < 0
        if near_pi.any():
            phi = np.where(near_pi, _near_pi(r, v, c, theta), phi)
        phi /= scale
    phi += 0.0                                  # + 0.0 turns -0.0 into 0.0 for printing
    out[...] = phi.T


def _dot(a, b):
    """Dot products of the columns of two (3, m) arrays, summed in the order x, y, z."""
    ab = a * b
    d = ab[0] + ab[1]
    d += ab[2]
    return d


def _log_one(r, scale):
    """``Log(R) / scale`` for one rotation given by its nine entries, in plain floats.

    The steps of :func:`_log_block` and :func:`_near_pi`, operation for operation, so
    that one rotation gets the bits it gets inside a batch (``tests/test_kernels.py``),
    in a fraction of the time NumPy's calls take for one.
    """
    r00, r01, r02, r10, r11, r12, r20, r21, r22 = r
    v = (r21 - r12, r02 - r20, r10 - r01)
    c = ((r00 + r11) + r22 - 1.0) * 0.5
    s = max(math.sqrt((v[0] * v[0] + v[1] * v[1]) + v[2] * v[2]) * 0.5, 5e-324)
    theta = float(np.arctan2(s, c))             # NumPy's atan2, as in the kernel
    if c < 0:                                   # near pi: the symmetric part's column
        M = ((r00, r01, r02), (r10, r11, r12), (r20, r21, r22))
        sym = [[(M[i][j] + M[j][i]) * 0.5 for j in range(3)] for i in range(3)]
        for i in range(3):
            sym[i][i] -= c
        diag = [sym[i][i] for i in range(3)]
        j = diag.index(max(diag))               # the first largest diagonal entry
        col = [sym[i][j] for i in range(3)]
        k = theta / math.sqrt((col[0] * col[0] + col[1] * col[1]) + col[2] * col[2])
        if (col[0] * v[0] + col[1] * v[1]) + col[2] * v[2] < 0:
            k = -k
        phi = [k * x for x in col]
    else:
        k = theta / (s + s)
        phi = [k * x for x in v]
    return [x / scale + 0.0 for x in phi]       # + 0.0: -0.0 to 0.0


def _near_pi(r, v, c, theta):
    """``theta n`` for a block, with ``n`` from the symmetric part (spec S19).

    Computed for every matrix of the block and used where ``c < 0``: there the largest
    diagonal entry of ``(R + R^T)/2 - c I`` is at least ``(1 - c)/3 > 1/3``, so nothing
    divides by zero; elsewhere it may, and those values are dropped.
    """
    M = r.reshape(3, 3, -1)
    sym = M + M.transpose(1, 0, 2)
    sym *= 0.5
    sym.reshape(9, -1)[::4] -= c                # (R + R^T)/2 - c I
    j = np.argmax(sym.reshape(9, -1)[::4], axis=0)   # the first largest diagonal entry
    col = np.where(j == 0, sym[:, 0], np.where(j == 1, sym[:, 1], sym[:, 2]))   # its column
    k = theta / np.sqrt(_dot(col, col))
    np.negative(k, out=k, where=_dot(col, v) < 0)
    return k * col


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
        A generator, or a nonnegative int seed for one. Pass one for reproducible
        notebooks. ``True``, floats and strings are refused.
    size : None, int or tuple of int
        Batch shape (nonnegative ints; not ``True``, ``2.7`` or ``"3"``); ``None`` gives a
        single (3, 3) matrix.

    Returns
    -------
    R : ndarray, shape (*size, 3, 3)
    """
    if rng is None or (isinstance(rng, (int, np.integer)) and not isinstance(rng, bool)
                       and rng >= 0):
        rng = np.random.default_rng(rng)
    elif not isinstance(rng, np.random.Generator):
        raise ValueError("random_rotation expects rng as a numpy.random.Generator, a "
                         f"nonnegative int seed or None; got {rng!r} ({type(rng).__name__})")
    shape = _batch_shape(size)
    g = rng.standard_normal(shape + (4,))
    norm = np.sqrt(np.einsum("...i,...i->...", g, g))
    w, vec = g[..., 0] / norm, g[..., 1:] / norm[..., None]
    R = 2.0 * vec[..., :, None] * vec[..., None, :] + 2.0 * w[..., None, None] * hat(vec)
    diag = w * w - np.einsum("...i,...i->...", vec, vec)
    R += diag[..., None, None] * np.eye(3)
    return R


def _batch_shape(size):
    """``size`` of :func:`random_rotation` as a shape tuple, or ValueError."""
    def is_count(k):
        return (isinstance(k, (int, np.integer)) and not isinstance(k, (bool, np.bool_))
                and 0 <= k < 2**63)
    if size is None:
        return ()
    if is_count(size):
        return (int(size),)
    if isinstance(size, (tuple, list)) and all(map(is_count, size)):
        if len(size) > MAX_BATCH_AXES:
            raise ValueError(f"random_rotation expects at most {MAX_BATCH_AXES} batch axes; "
                             f"size has {len(size)}")
        return tuple(int(k) for k in size)
    raise ValueError("random_rotation expects size as None, a nonnegative int or a tuple "
                     f"of them; got {size!r} ({type(size).__name__})")
