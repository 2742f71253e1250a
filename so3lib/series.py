r"""The exponential as a power series, and the scalar coefficients of Rodrigues' formula.

These are teaching tools: :func:`exp_series` sums the series that notebook 02 regroups
into Rodrigues' formula, and :func:`A` and :func:`B` are the two scalar functions that
the regrouping produces,

.. math:: e^{\hat\varphi} = \sum_{m \ge 0} \frac{\hat\varphi^m}{m!}
          = I + A(\theta)\,\hat\varphi + B(\theta)\,\hat\varphi^2,
          \qquad A(x) = \frac{\sin x}{x},\quad B(x) = \frac{1 - \cos x}{x^2}.

:func:`so3lib.exp` is the function to use for computing. It evaluates the same formula
in another way: the whole matrix from one tangent, ``t = tan(theta/2)``, with no
Taylor branch, at every angle up to ``theta = 1e145`` (see its Notes); :func:`A` and
:func:`B` here keep the textbook forms, with their Taylor series below ``1e-4``, for
comparison in the notebooks.
"""

import numpy as np

from .so3 import hat
from .validation import as_times, as_vectors

__all__ = ["exp_series", "A", "B"]

# Below this |t| two Taylor terms are exact to rounding (spec S10).
_TAYLOR_BELOW = 1e-4


def exp_series(omega, tau=1.0, terms=20):
    r"""The exponential series of :math:`\tau\hat\omega`, truncated after ``terms`` terms.

    .. math:: S_N = \sum_{m=0}^{N-1} \frac{(\tau\hat\omega)^m}{m!}

    Parameters
    ----------
    omega : array_like, shape (..., 3)
    tau : float or array_like, broadcastable to omega's leading shape
    terms : int, at least 1
        ``N``, the number of terms: ``terms=1`` gives ``I``, ``terms=2`` gives
        ``I + tau hat(omega)``. The error after ``N`` terms is about
        ``theta^N / N!`` (notebook 02).

    Returns
    -------
    S : ndarray, shape (..., 3, 3)
    """
    omega = as_vectors(omega, 3, "omega", "exp_series")
    tau = as_times(tau, "exp_series")
    if isinstance(terms, bool) or not isinstance(terms, (int, np.integer)) or terms < 1:
        raise ValueError(f"exp_series expects terms as an int >= 1 (the number of terms of "
                         f"the series); got {terms!r}")
    K = hat(omega * tau[..., None])
    term = np.broadcast_to(np.eye(3), K.shape).copy()
    total = term.copy()
    for m in range(1, int(terms)):
        term = term @ K / m            # (tau hat(omega))^m / m!
        total += term
    return total


def A(x):
    r"""The coefficient of :math:`\hat\varphi` in Rodrigues' formula.

    .. math:: A(x) = \frac{\sin x}{x} = \sum_{k\ge0} \frac{(-1)^k x^{2k}}{(2k+1)!},
              \qquad A(0) = 1

    ``sin(x)/x`` is accurate wherever ``x != 0``; below ``1e-4`` the Taylor form
    ``1 - x^2/6`` is used, which is exact to rounding there (spec S10).

    Parameters
    ----------
    x : float or array_like

    Returns
    -------
    ndarray or float, same shape as ``x``
    """
    x = as_times(x, "A", name="x")
    tiny = np.abs(x) < _TAYLOR_BELOW
    safe = np.where(tiny, 1.0, x)
    out = np.where(tiny, 1.0 - x * x / 6.0, np.sin(safe) / safe)
    return out[()] if out.ndim == 0 else out


def B(x):
    r"""The coefficient of :math:`\hat\varphi^2` in Rodrigues' formula.

    .. math:: B(x) = \frac{1 - \cos x}{x^2} = \frac{2\sin^2(x/2)}{x^2}
              = \sum_{k\ge0} \frac{(-1)^k x^{2k}}{(2k+2)!}, \qquad B(0) = \tfrac12

    The half-angle form has no cancellation; the naive ``(1 - cos x)/x^2`` returns 0 at
    ``x = 1e-8`` (notebook 02, "Small angles"). Below ``1e-4``, ``1/2 - x^2/24``.

    Parameters
    ----------
    x : float or array_like

    Returns
    -------
    ndarray or float, same shape as ``x``
    """
    x = as_times(x, "B", name="x")
    tiny = np.abs(x) < _TAYLOR_BELOW
    safe = np.where(tiny, 1.0, x)
    out = np.where(tiny, 0.5 - x * x / 24.0, 2.0 * (np.sin(0.5 * safe) / safe) ** 2)
    return out[()] if out.ndim == 0 else out

