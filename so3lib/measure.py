r"""How far a computed result is from a reference, in a form a notebook can print.

A notebook's check should say how large the error is, not print a bare ``True``, and its
printed output must stay the same from run to run (strict nbval compares it). Errors are
therefore given in whole units of the float64 machine epsilon,
``eps = 2**-52 ~ 2.2e-16``, rounded up:

.. math:: \text{error in eps} = \left\lceil \frac{\max_i |x_i - r_i|}
          {\varepsilon \cdot \max(1, \max_i |r_i|)} \right\rceil

so 0 means bit-for-bit equal and 1 means "within one rounding of a number of size 1".

What a notebook prints is the verdict against a tolerance fixed beforehand, not the count
itself: the last bit or two of a result depend on the machine (the BLAS kernel that sums
a matrix product, NumPy's SIMD code for ``sin`` and ``tan``, the C library), so "error 1
eps" on one processor is "error 2 eps" on another, while "within 8 eps" is true on both.
Only a check that fails prints its count.

>>> from so3lib.measure import eps_error, report
>>> eps_error(0.1 + 0.2, 0.3)
1
>>> report("0.1 + 0.2 = 0.3", 0.1 + 0.2, 0.3, tol=4)
0.1 + 0.2 = 0.3: within 4 eps: ok
>>> report("0.1 + 0.2 = 0.3", 0.1 + 0.2, 0.3, tol=0)
0.1 + 0.2 = 0.3: error 1 eps, more than the 0 eps allowed: FAILS
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


def _power(x):
    """``1e6`` for 1e6, ``2.5e+03`` otherwise: a bound as a reader writes it."""
    k = math.log10(x)
    return f"1e{round(k)}" if x > 0 and math.isclose(k, round(k), abs_tol=1e-12) else f"{x:g}"


def report(label, got, ref, tol=8, scale=None, over=None):
    """Print one line: ``LABEL: within TOL eps: ok`` (``LABEL: identical: ok`` when ``tol``
    is 0), or, when the error is over ``tol``, ``LABEL: error N eps, more than the TOL eps
    allowed: FAILS``.

    ``over`` is for a check that shows a formula failing: when the error is larger than
    ``over`` eps the line says ``LABEL: error over OVER eps (tolerance TOL eps): FAILS``,
    a bound rather than the count, which moves with the machine's rounding; an error of
    ``over`` or less prints the count as usual (so a formula that stopped failing as
    shown is seen).

    Returns nothing, so that a call as a cell's last line adds no ``Out[]``; use
    :func:`eps_error` for the number. The line of a check that passes names only its
    tolerance, so it is the same on every machine (strict nbval compares it) as long as
    the error stays within the tolerance there.

    Raises
    ------
    ValueError
        If ``tol`` is not a whole number 0 or more, ``over`` is not a number above
        ``tol``, or the error cannot be measured (see :func:`eps_error`).
    """
    if not (isinstance(tol, (int, np.integer)) and not isinstance(tol, (bool, np.bool_))
            and tol >= 0):
        raise ValueError(f"report: tol must be a whole number of eps, 0 or more; got {tol!r}")
    if over is not None and not (isinstance(over, (int, float, np.integer, np.floating))
                                 and not isinstance(over, (bool, np.bool_))
                                 and math.isfinite(over) and over > tol):
        raise ValueError(f"report: over must be a number of eps larger than tol = {tol}; "
                         f"got {over!r}")
    err = eps_error(got, ref, scale)
    if over is not None and err > over:
        print(f"{label}: error over {_power(over)} eps (tolerance {tol} eps): FAILS")
    elif err > tol:
        print(f"{label}: error {err} eps, more than the {tol} eps allowed: FAILS")
    elif tol == 0:
        print(f"{label}: identical: ok")
    else:
        print(f"{label}: within {tol} eps: ok")
