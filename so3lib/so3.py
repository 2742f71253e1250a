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

The formulas are those of the course notebooks 01, 02 and 04 and of
``design/spec.md`` (sections A to C); the numerical algorithms are spec S23.

References: the lecture notes and Gallier's textbook excerpt the course follows;
J. Sola, J. Deray, D. Atchuthan, "A micro Lie theory for state estimation in robotics"
(2018); J. Gallier, "Geometric Methods and Applications" (Rodrigues' formula and the
surjectivity of exp).
"""

import numpy as np

from .validation import (ROTATION_TOL, as_matrices, as_times, as_tolerance, as_vectors,
                         check_rotation, check_skew, rotation_defects)

__all__ = ["hat", "vee", "exp", "log", "angle", "is_rotation", "random_rotation"]

# Below this angle the coefficients A and B use two Taylor terms: the first omitted term
# is below 1e-18 relative (spec S10), and it avoids sin(t/2) underflowing to 0 for
# subnormal t.
_TAYLOR_BELOW = 1e-4


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

    * ``theta < 1e-4``: ``A = 1 - t^2/6``, ``B = 1/2 - t^2/24`` (Taylor, spec S10);
    * ``theta < 1``: ``A = sin(t)/t`` and ``B = 2 (sin(t/2)/t)^2``, which has no
      cancellation, unlike the naive ``(1 - cos t)/t^2`` (notebook 02, "Small angles");
    * ``theta >= 1``: the unit-axis form ``I + sin(t) hat(n) + 2 sin^2(t/2) hat(n)^2``,
      so ``hat(phi)^2`` cannot overflow.

    ``hat(u)^2 = u u^T - |u|^2 I`` (the Lemma) is written out entry by entry, with the
    diagonal as ``1 - b (u_j^2 + u_k^2)`` so that nothing cancels.
    """
    omega = as_vectors(omega, 3, "omega", "exp")
    tau = as_times(tau, "exp")
    with np.errstate(over="ignore", invalid="ignore"):   # overflow is reported below
        phi = omega * tau[..., None]
        theta, n = _angle_and_axis(phi)
    if not np.isfinite(phi).all():
        raise ValueError("exp: the rotation vector omega * tau overflows float64; "
                         "expected |omega * tau| below about 1e308")
    if not np.isfinite(theta).all():
        raise ValueError("exp: the rotation angle |omega * tau| overflows float64; "
                         "expected an angle below about 1e308")

    # u is phi itself below theta = 1 and the unit axis n above; a, b the matching
    # coefficients, so that R = I + a hat(u) + b hat(u)^2 in both regimes.
    big = theta >= 1.0
    safe = np.where(theta > 0, theta, 1.0)
    u = np.where(big[..., None], n, phi)
    s, h = np.sin(safe), np.sin(0.5 * safe)
    tiny = theta < _TAYLOR_BELOW
    t2 = np.where(tiny, theta, 0.0) ** 2    # only used where tiny; no overflow elsewhere
    a = np.where(big, s, np.where(tiny, 1.0 - t2 / 6.0, s / safe))
    b = np.where(big, 2.0 * h * h, np.where(tiny, 0.5 - t2 / 24.0, 2.0 * (h / safe) ** 2))

    x, y, z = u[..., 0], u[..., 1], u[..., 2]
    R = np.empty(u.shape[:-1] + (3, 3))
    R[..., 0, 0] = 1.0 - b * (y * y + z * z)
    R[..., 1, 1] = 1.0 - b * (x * x + z * z)
    R[..., 2, 2] = 1.0 - b * (x * x + y * y)
    bxy, bxz, byz = b * x * y, b * x * z, b * y * z
    ax, ay, az = a * x, a * y, a * z
    R[..., 0, 1], R[..., 1, 0] = bxy - az, bxy + az
    R[..., 0, 2], R[..., 2, 0] = bxz + ay, bxz - ay
    R[..., 1, 2], R[..., 2, 1] = byz - ax, byz + ax
    return R


def _validated_rotations(R, check, tol, func):
    R = as_matrices(R, 3, "R", func)
    if check:
        check_rotation(R, as_tolerance(tol, func), func)
    return R


def _skew_and_trace(R):
    """``v = vee(R - R^T) = 2 sin(theta) n`` and ``c = (tr R - 1)/2 = cos(theta)``."""
    v = np.stack([R[..., 2, 1] - R[..., 1, 2],
                  R[..., 0, 2] - R[..., 2, 0],
                  R[..., 1, 0] - R[..., 0, 1]], axis=-1)
    c = 0.5 * (R[..., 0, 0] + R[..., 1, 1] + R[..., 2, 2] - 1.0)
    return v, c


def _norm3(v):
    """Euclidean norm over the last axis without overflow or underflow."""
    return np.hypot(np.hypot(v[..., 0], v[..., 1]), v[..., 2])


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
    v, c = _skew_and_trace(R)
    return np.arctan2(0.5 * _norm3(v), c)


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
    exactly symmetric (``v = 0``) this function returns the one whose largest component
    is positive (the first of equal largest components); when ``R`` carries rounding
    noise the noise picks the sign, and either answer is correct to that noise.
    """
    R = _validated_rotations(R, check, tol, "log")
    tau = as_times(tau, "log", nonzero=True)
    v, c = _skew_and_trace(R)
    s = 0.5 * _norm3(v)
    theta = np.arctan2(s, c)

    # Branch c >= 0: theta / (2 s) v; theta/(2s) -> 1/2 as s -> 0, and v = 0 at R = I.
    with np.errstate(divide="ignore", invalid="ignore"):
        phi = np.where((s > 0)[..., None], (theta / (2.0 * s))[..., None] * v, 0.0)

    near_pi = c < 0
    if near_pi.any():
        Rn, vn, cn = R[near_pi], v[near_pi], c[near_pi]
        B = 0.5 * (Rn + np.swapaxes(Rn, -1, -2)) - cn[:, None, None] * np.eye(3)
        j = np.argmax(np.diagonal(B, axis1=-2, axis2=-1), axis=-1)
        col = np.take_along_axis(B, j[:, None, None], axis=-1)[..., 0]
        n = col / _norm3(col)[:, None]
        flip = np.einsum("...i,...i->...", n, vn) < 0
        n[flip] = -n[flip]
        phi[near_pi] = theta[near_pi][:, None] * n

    return phi / tau[..., None] + 0.0   # + 0.0 turns -0.0 into 0.0 for printing


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
