r"""How far a computed result is from a reference, in a form a notebook can print.

A notebook's check should say how large the error is, not print a bare ``True``, and its
printed output must stay the same from run to run (strict nbval compares it). Errors are
therefore given in whole units of the float64 machine epsilon,
``eps = 2**-52 ~ 2.2e-16``, rounded up:

.. math:: \text{error in eps} = \left\lceil \frac{\max_i |x_i - r_i|}
          {\varepsilon \cdot \max(1, \max_i |r_i|)} \right\rceil

so 0 means bit-for-bit equal and 1 means "within one rounding of a number of size 1".

>>> from so3lib.measure import eps_error, report
>>> eps_error(0.1 + 0.2, 0.3)
1
>>> report("0.1 + 0.2 = 0.3", 0.1 + 0.2, 0.3, tol=4)
0.1 + 0.2 = 0.3: error 1 eps (tolerance 4 eps): ok
"""

import math

import numpy as np

__all__ = ["EPS", "eps_error", "report"]

#: The float64 machine epsilon, 2**-52: the gap between 1.0 and the next float.
EPS = float(np.finfo(np.float64).eps)


def eps_error(got, ref, scale=None):
    """Largest absolute difference between ``got`` and ``ref``, in units of ``eps * scale``.

    Parameters
    ----------
    got, ref : array_like of the same shape (real or complex; ``ref`` may be exact
        Python or mpmath numbers, which are converted to float64 only after subtracting
        when both are mpmath)
    scale : float, optional
        What one eps is relative to; by default ``max(1, max|ref|)``, so the error is
        absolute for small entries and relative for large ones.

    Returns
    -------
    int
        The error rounded up to a whole number of eps (0 when identical).

    Raises
    ------
    ValueError
        If the shapes differ, or either side contains NaN or inf (a check must never
        pass on a NaN).
    """
    g = np.asarray(got)
    r = np.asarray(ref)
    if g.dtype == object or r.dtype == object:     # mpmath or Python numbers: subtract first
        diff = np.vectorize(lambda a, b: abs(complex(a - b)), otypes=[float])(g, r)
        size = np.vectorize(lambda b: abs(complex(b)), otypes=[float])(r)
    else:
        if g.shape != r.shape:
            raise ValueError(f"eps_error compares arrays of one shape; got {g.shape} and {r.shape}")
        diff = np.abs(g.astype(complex if np.iscomplexobj(g) else float)
                      - r.astype(complex if np.iscomplexobj(r) else float))
        size = np.abs(r)
    if g.shape != r.shape:
        raise ValueError(f"eps_error compares arrays of one shape; got {g.shape} and {r.shape}")
    if not (np.isfinite(diff).all() and np.isfinite(size).all()):
        raise ValueError("eps_error: the result or the reference contains NaN or inf")
    if scale is None:
        scale = max(1.0, float(size.max(initial=0.0)))
    if not (math.isfinite(scale) and scale > 0):
        raise ValueError(f"eps_error: scale must be a positive finite number; got {scale!r}")
    return math.ceil(float(diff.max(initial=0.0)) / (EPS * scale))


def report(label, got, ref, tol=8, scale=None):
    """Print one line, ``LABEL: error N eps (tolerance TOL eps): ok`` (or ``FAILS``).

    Returns nothing, so that a call as a cell's last line adds no ``Out[]``; use
    :func:`eps_error` for the number. The line is stable under strict nbval as long as
    the error is.
    """
    err = eps_error(got, ref, scale)
    verdict = "ok" if err <= tol else "FAILS"
    print(f"{label}: error {err} eps (tolerance {tol} eps): {verdict}")
