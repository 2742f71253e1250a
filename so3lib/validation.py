r"""Input checks shared by every public function of so3lib.

Each helper turns ``array_like`` input into a float64 ``ndarray`` of the expected
shape, or raises ``ValueError`` with a message that names the function, the argument,
what was wrong and what was expected.  The functions in :mod:`so3lib.so3` and
:mod:`so3lib.so2` call these helpers first; ``check=False`` skips the (costlier)
group-membership tests, never the shape tests.

Tolerance
---------
A matrix ``R`` counts as a rotation when

.. math:: \max_{ij} |(R^T R - I)_{ij}| \le \mathrm{tol} \quad\text{and}\quad
          |\det R - 1| \le \mathrm{tol},

with ``tol = ROTATION_TOL = 1e-6`` unless the caller passes another value.  That
accepts any rotation carried through a few thousand floating-point operations
(rounding noise is about 1e-15 per step) and a rotation stored in float32, and refuses
hand-typed four-digit entries (``0.7071`` is off by 7e-6), scaled matrices and
reflections.

How far an accepted matrix moves the logarithm: if ``R0`` is any rotation and
``delta = ||R - R0||_F`` (the Frobenius norm: the root of the sum of the squared
entries of ``R - R0``), then ``log(R)`` is within ``pi * delta`` (Euclidean norm) of a
logarithm of ``R0``, to first order in ``delta`` (spec S23). "A logarithm" because near
the cut at ``theta = pi`` the perturbation may pick the other one,
``Log R0 - 2 pi Log R0 / |Log R0|``. The constant is the largest gain of
:func:`so3lib.log`'s formulas from ``R`` to ``log(R)``, measured over every angle and
axis (``tests/test_accuracy.py``): 2.2, just above ``theta = pi/2`` with the axis along a
diagonal; so ``pi`` has room. In other norms of ``R - R0`` the factor grows with the
norm's ratio to Frobenius's: ``3 pi`` for the largest entry, ``sqrt(3) pi`` for the
spectral norm.
"""

import datetime
import math

import numpy as np

__all__ = [
    "ROTATION_TOL",
    "SKEW_RTOL",
    "as_vectors",
    "as_matrices",
    "as_times",
    "rotation_defects",
    "check_rotation",
    "check_skew",
    "as_tolerance",
    "broadcast_batch",
    "MAX_BATCH_AXES",
    "show",
    "as_numbers",
    "check_batch_axes",
]

#: Default tolerance of the rotation test (see the module docstring).
ROTATION_TOL = 1e-6

#: Most leading (batch) axes an argument may have: NumPy's iterators over several arrays
#: stop at 32 dimensions.
MAX_BATCH_AXES = 32

#: Relative tolerance of the skew-symmetry test in ``vee``: ``|M + M^T| <= SKEW_RTOL * |M|``.
SKEW_RTOL = 1e-8

# Batches are checked in blocks of _BLOCK matrices, so that the temporaries stay small (in
# cache, and far below the size of the batch); one matrix is a block of one. Arrays of up
# to _SMALL numbers are tested for finiteness in plain floats, quicker than a NumPy call.
_BLOCK = 4096
_SMALL = 32
_FLOAT64 = np.dtype(np.float64)


def _index(idx):
    """Format a batch index tuple for a message: (2,) -> '[2]', () -> ''."""
    return "[" + ", ".join(str(int(i)) for i in idx) + "]" if len(idx) else ""


def show(x, ref=1.0):
    """``x`` with just enough digits to tell it from ``ref``, for messages.

    ``1 + 4e-7`` prints as ``1.0000004``, not as ``1``: a message that prints the defect
    as the expected value hides it.
    """
    x = float(x)
    for digits in range(3, 17):
        if x == ref or float(f"{x:.{digits}g}") != ref:
            return f"{x:.{digits + (x != ref and digits > 3)}g}"   # and one digit more
    return repr(x)


def _describe(e):
    """What an element of an object array is, when it is not a real number; else None."""
    if e is None:
        return "None"
    if isinstance(e, (str, bytes, np.str_, np.bytes_)):
        return f"the text {e!r} (a {type(e).__name__}, not a number)"
    if isinstance(e, (bool, np.bool_)):
        return f"the boolean {e!r}"
    if isinstance(e, (complex, np.complexfloating)):
        return f"the complex number {e!r}"
    if isinstance(e, (np.datetime64, np.timedelta64, datetime.date, datetime.time,
                      datetime.timedelta)):
        return f"a date or time ({type(e).__name__})"
    if isinstance(e, int):
        try:
            float(e)
        except OverflowError:
            return (f"an int with {len(str(abs(e)))} digits, too large for a float "
                    f"(the largest is about 1.8e308)")
        return None
    try:
        float(e)
    except OverflowError:
        return f"{type(e).__name__} too large for a float (the largest is about 1.8e308)"
    except (TypeError, ValueError):
        return f"a {type(e).__name__}, not a number"
    return None


def _object_to_float(arr, name, func, complex_ok=False):
    """An object array of numbers as float64 (complex128 with ``complex_ok``); ValueError
    naming the first element that is not a number."""
    out = np.empty(arr.shape, dtype=np.complex128 if complex_ok else np.float64)
    flat = out.reshape(-1)
    convert = complex if complex_ok else float
    for k, e in enumerate(arr.reshape(-1).tolist() if arr.ndim else [arr.item()]):
        what = _describe(e)
        if complex_ok and isinstance(e, (complex, np.complexfloating)):
            what = None
        if what is not None:
            idx = np.unravel_index(k, arr.shape) if arr.ndim else ()
            where = f"{name}{_index(idx)}" if idx else name
            kind = "complex numbers" if complex_ok else "real numbers"
            raise ValueError(f"{func} expects {name} as {kind}; {where} is {what}")
        flat[k] = convert(e)
    return out


def as_numbers(x, name, func, complex_ok=False):
    """Return ``x`` as a float64 array (complex128 with ``complex_ok``), or raise
    ValueError naming what it holds instead of numbers.

    Refused, each with a message naming what was found: masked arrays (the mask would be
    ignored), None, text (str and bytes, also inside lists), dates and times
    (``datetime64``, ``timedelta64``), structured and other non-numeric dtypes, booleans,
    complex numbers, object arrays holding any of these, numbers too large for a float
    (a Python int above 1.8e308, or a long double), and ragged nested lists.
    """
    if type(x) is np.ndarray and x.dtype == _FLOAT64 and not complex_ok:
        return x                                # the usual case: nothing to convert
    if isinstance(x, np.ma.MaskedArray):
        raise ValueError(f"{func} expects {name} as a plain array of numbers; got a "
                         f"masked array, whose mask would be ignored: fill or drop the "
                         f"masked entries first ({name}.filled(value) or {name}.compressed())")
    if x is None:
        raise ValueError(f"{func} expects {name} as {'complex' if complex_ok else 'real'} "
                         f"numbers; got None")
    try:
        arr = np.asarray(x)
    except (ValueError, TypeError, OverflowError) as err:  # ragged nested lists and the like
        raise ValueError(f"{func} expects {name} as an array of real numbers; "
                         f"could not read it as an array ({err})") from None
    if arr.dtype == _FLOAT64 and not complex_ok:
        return arr
    kind = arr.dtype.kind
    got = None
    if complex_ok and kind in "iufc":
        return arr.astype(np.complex128)
    if kind in "iu":
        return arr.astype(np.float64)
    if kind == "f":                             # float16, float32, long double
        with np.errstate(over="raise"):
            try:
                return arr.astype(np.float64)
            except FloatingPointError:
                got = f"values too large for float64 (dtype {arr.dtype})"
    elif kind == "O":
        return _object_to_float(arr, name, func, complex_ok)
    elif kind == "c":
        got = f"complex values (dtype {arr.dtype})"
    elif kind == "b":
        got = "booleans"
    elif kind in "US":
        got = f"text (dtype {arr.dtype}); convert strings to numbers first"
    elif kind in "Mm":
        got = (f"dates or times (dtype {arr.dtype}); convert them to plain numbers "
               f"first, e.g. a duration in seconds: t / np.timedelta64(1, 's')")
    elif arr.dtype.names is not None:
        got = f"a structured array with fields {arr.dtype.names} (dtype {arr.dtype})"
    else:
        got = f"an array of dtype {arr.dtype}"
    what = "complex numbers" if complex_ok else "real numbers"
    raise ValueError(f"{func} expects {name} as {what}; got {got}")


def _as_real_array(x, name, func):
    return as_numbers(x, name, func)


def check_batch_axes(arr, core, name, func):
    """Refuse more than MAX_BATCH_AXES leading axes (NumPy's iterators stop at 32)."""
    axes = arr.ndim - core
    if axes > MAX_BATCH_AXES:
        raise ValueError(f"{func} expects at most {MAX_BATCH_AXES} batch axes; {name} has "
                         f"{axes} (shape {arr.shape})")


def _check_finite(arr, name, func):
    """Raise ValueError naming the first NaN or infinite entry of ``arr``."""
    # Fast test first: a sum is finite only if every term is (a NaN or an infinity
    # propagates), so one pass without a temporary array clears the usual case. A sum
    # that overflows although every entry is finite falls through to the full test.
    if arr.size <= _SMALL:
        if all(map(math.isfinite, arr.ravel().tolist())):
            return
    else:
        with np.errstate(over="ignore", invalid="ignore"):
            if math.isfinite(np.add.reduce(arr, axis=None)):
                return
    finite = np.isfinite(arr)
    if not finite.all():
        idx = tuple(np.argwhere(~finite)[0])
        bad = arr[idx]
        kind = "NaN" if np.isnan(bad) else "an infinite value"
        where = f" at index {_index(idx)}" if idx else ""
        raise ValueError(f"{func} expects finite numbers; {name} has {kind}{where}")


def as_vectors(x, dim, name, func, finite=True):
    """Return ``x`` as a finite float64 array of shape ``(..., dim)``.

    Parameters
    ----------
    x : array_like, shape (..., dim)
    dim : int
        Length of the last axis (3 for so(3), 2 for the plane).
    name, func : str
        Argument and function names used in error messages.
    finite : bool
        Refuse NaN and inf (default). ``False`` leaves that test to a caller that finds
        them on its way anyway, and must then call again with ``True`` to report them.
    """
    arr = _as_real_array(x, name, func)
    if arr.ndim == 0 or arr.shape[-1] != dim:
        raise ValueError(f"{func} expects {name} of shape (..., {dim}), a {dim}-vector or a "
                         f"batch of them; got shape {arr.shape}")
    check_batch_axes(arr, 1, name, func)
    if finite:
        _check_finite(arr, name, func)
    return arr


def as_matrices(m, dim, name, func):
    """Return ``m`` as a finite float64 array of shape ``(..., dim, dim)``."""
    arr = _as_real_array(m, name, func)
    if arr.ndim < 2 or arr.shape[-2:] != (dim, dim):
        raise ValueError(f"{func} expects {name} of shape (..., {dim}, {dim}), a {dim}x{dim} "
                         f"matrix or a batch of them; got shape {arr.shape}")
    check_batch_axes(arr, 2, name, func)
    _check_finite(arr, name, func)
    return arr


def as_times(tau, func, nonzero=False, name="tau"):
    """Return ``tau`` (or another real scalar argument) as a finite float64 array.

    Any shape is accepted; it broadcasts against the batch later.

    With ``nonzero=True`` a zero time is refused: the logarithm divides by ``tau``.
    """
    if type(tau) is float and math.isfinite(tau) and (tau != 0.0 or not nonzero):
        return np.array(tau)                    # the usual case, one number: done
    arr = _as_real_array(tau, name, func)
    check_batch_axes(arr, 0, name, func)
    _check_finite(arr, name, func)
    if nonzero and (arr == 0).any():
        idx = tuple(np.argwhere(arr == 0)[0])
        where = f" (at index {_index(idx)})" if idx else ""
        raise ValueError(f"{func} divides by the time {name}, so {name} must be nonzero; "
                         f"got {name} = 0{where}")
    return arr


def _defects(r, dim):
    r"""The entries of :math:`R^T R - I` on and above the diagonal, and :math:`\det R`.

    ``r`` holds the entries of ``R`` row by row (``r[3 * i + j]`` is :math:`R_{ij}` for
    ``dim = 3``), each an array across a block of matrices; :func:`_block_defects` uses
    these lines for 2x2 matrices (3x3 ones go on stacked arrays there).
    """
    if dim == 3:
        r00, r01, r02, r10, r11, r12, r20, r21, r22 = r
        gram = (r00 * r00 + r10 * r10 + r20 * r20 - 1.0,      # (R^T R)_ij = col_i . col_j
                r01 * r01 + r11 * r11 + r21 * r21 - 1.0,
                r02 * r02 + r12 * r12 + r22 * r22 - 1.0,
                r00 * r01 + r10 * r11 + r20 * r21,
                r00 * r02 + r10 * r12 + r20 * r22,
                r01 * r02 + r11 * r12 + r21 * r22)
        det = (r00 * (r11 * r22 - r12 * r21) - r01 * (r10 * r22 - r12 * r20)
               + r02 * (r10 * r21 - r11 * r20))               # cofactors of the first row
    else:
        r00, r01, r10, r11 = r
        gram = (r00 * r00 + r10 * r10 - 1.0, r01 * r01 + r11 * r11 - 1.0,
                r00 * r01 + r10 * r11)
        det = r00 * r11 - r01 * r10
    return gram, det


def _block_defects(rows, dim):
    """``orth = max|R^T R - I|`` and ``det R`` of a block of matrices given as rows of entries.

    For 3x3 matrices on stacked arrays, ``C[i, j]`` holding ``R_ij`` across the block:
    ``(R^T R)_ij = sum_k R_ki R_kj`` and ``det R = r_0 . (r_1 x r_2)`` (the rows), each
    sum taken in the order k = 0, 1, 2 whatever the size of the block, so that one matrix
    and a batch get the same verdict. Callers silence overflow (huge entries give inf).
    """
    if dim == 2:
        gram, det = _defects(rows.T.copy(), dim)   # one contiguous array per entry
        orth = np.abs(gram[0])
        for g in gram[1:]:
            np.maximum(orth, np.abs(g), out=orth)
        return orth, det
    C = rows.T.copy().reshape(3, 3, -1)
    gram = (C[:, :, None, :] * C[:, None, :, :]).sum(axis=0).reshape(9, -1)
    gram[::4] -= 1.0                            # R^T R - I
    orth = np.abs(gram).max(axis=0)
    r1, r2 = C[1], C[2]
    cross = r1.take(_NEXT, axis=0) * r2.take(_AFTER, axis=0)
    cross -= r1.take(_AFTER, axis=0) * r2.take(_NEXT, axis=0)   # r_1 x r_2
    det = (C[0] * cross).sum(axis=0)
    return orth, det


def _defects_one(r):
    """``orth`` and ``det`` of one 3x3 matrix (nine floats, row by row), in plain floats:
    the steps of :func:`_block_defects`, operation for operation, for the same verdict."""
    C = (r[0:3], r[3:6], r[6:9])
    gram = [[(C[0][i] * C[0][j] + C[1][i] * C[1][j]) + C[2][i] * C[2][j] for j in range(3)]
            for i in range(3)]
    for i in range(3):
        gram[i][i] -= 1.0
    entries = [abs(g) for row in gram for g in row]
    orth = math.nan if any(map(math.isnan, entries)) else max(entries)
    r1, r2 = C[1], C[2]
    cross = [r1[(i + 1) % 3] * r2[(i + 2) % 3] - r1[(i + 2) % 3] * r2[(i + 1) % 3]
             for i in range(3)]
    det = (C[0][0] * cross[0] + C[0][1] * cross[1]) + C[0][2] * cross[2]
    return (math.inf if math.isnan(orth) else orth), det


# (a x b)_i = a_{i+1} b_{i+2} - a_{i+2} b_{i+1}, indices modulo 3.
_NEXT = np.array([1, 2, 0])
_AFTER = np.array([2, 0, 1])


def rotation_defects(R):
    r"""Distances of each 3x3 or 2x2 matrix from the rotation group.

    Returns
    -------
    orth : ndarray, shape (...)
        :math:`\max_{ij} |(R^T R - I)_{ij}|`.
    det : ndarray, shape (...)
        :math:`\det R`.
    """
    with np.errstate(all="ignore"):            # huge entries: inf defects, no warnings
        return _rotation_defects(R)


def _rotation_defects(R):
    dim = R.shape[-1]
    if dim not in (2, 3):
        gram = np.einsum("...ki,...kj->...ij", R, R)
        orth = np.abs(gram - np.eye(dim)).max(axis=(-2, -1))
        return orth, np.linalg.det(R)
    rows = R.reshape(-1, dim * dim)             # each matrix as a row of entries
    orth, det = np.empty(len(rows)), np.empty(len(rows))
    for i in range(0, len(rows), _BLOCK):
        orth[i:i + _BLOCK], det[i:i + _BLOCK] = _block_defects(rows[i:i + _BLOCK], dim)
    batch = R.shape[:-2]
    return orth.reshape(batch)[()], det.reshape(batch)[()]


def _first_failure(R, tol):
    """Flat index, ``orth`` and ``det`` of the first matrix of ``R`` that is not a rotation
    within ``tol``, or None. Block by block, stopping at the first failing block."""
    dim = R.shape[-1]
    rows = R.reshape(-1, dim * dim)
    if len(rows) == 1 and dim == 3:             # one matrix: plain floats are quicker
        orth, det = _defects_one(rows[0].tolist())
        if orth <= tol and abs(det - 1.0) <= tol:           # NaN counts as failing
            return None
        return 0, orth, det
    for i in range(0, len(rows), _BLOCK):
        orth, det = _block_defects(rows[i:i + _BLOCK], dim)
        worst = np.maximum(orth, np.abs(det - 1.0))            # NaN stays NaN
        if not worst.max() <= tol:                              # NaN counts as failing
            k = int(np.argmax(~(worst <= tol)))
            o = float(orth[k])
            return i + k, (math.inf if math.isnan(o) else o), float(det[k])
    return None


def check_rotation(R, tol, func, name="R"):
    """Raise ValueError unless every matrix of ``R`` is a rotation within ``tol``.

    The message names the first failing matrix of a batch and what was measured, with
    enough digits to show the defect (``det = 1.0000015``, never ``det = 1``).
    """
    with np.errstate(all="ignore"):            # huge entries: inf defects, no warnings
        failure = _first_failure(R, tol)
    if failure is None:
        return
    k, o, d = failure
    idx = tuple(int(i) for i in np.unravel_index(k, R.shape[:-2]))
    which = f"{name}{_index(idx)}" if idx else name
    expected = (f"{func} expects rotation matrices: {name}^T {name} = I and det {name} = +1 "
                f"within tol={tol:g}")
    M = R[idx]
    largest = float(np.abs(M).max())
    if not (math.isfinite(o) and math.isfinite(d)):
        problem = (f"{which} has entries as large as {largest:.3g}, so {name}^T {name} "
                   f"overflows float64 (a rotation's entries are at most 1 in size)")
    elif o <= tol:
        problem = (f"{which} has det = {show(d, -1.0)}: a reflection, not a rotation" if d < 0
                   else f"{which} has det = {show(d)}, which differs from +1 by "
                        f"{abs(d - 1.0):.2g}")
    else:
        problem = f"{which} is not orthogonal: max|{name}^T {name} - I| = {o:.2e}"
        gram = M.T @ M
        k2 = np.trace(gram) / M.shape[-1]
        if k2 == 0:
            problem += " (it is the zero matrix)"
        elif np.abs(gram - k2 * np.eye(M.shape[-1])).max() <= tol * k2:
            kind = "rotation" if d > 0 else "reflection"
            problem += f" (it is a {kind} scaled by {show(np.sqrt(k2))})"
        elif d < 0:
            problem += f", and det = {d:.3g} < 0"
    raise ValueError(f"{expected}; {problem}")


def check_skew(M, func, name="M", rtol=SKEW_RTOL):
    """Raise ValueError unless every matrix of ``M`` is skew-symmetric.

    The test is relative, ``max|M + M^T| <= rtol * max|M|``, so it does not depend on
    the scale of ``M``; the zero matrix passes. It is computed on ``(M + M^T)/2`` so that
    entries near the largest float do not overflow.
    """
    half = np.abs(0.5 * M + 0.5 * np.swapaxes(M, -1, -2)).max(axis=(-2, -1))
    scale = np.abs(M).max(axis=(-2, -1))
    bad = half > (0.5 * rtol) * scale
    if bad.any():
        idx = tuple(np.argwhere(bad)[0]) if bad.ndim else ()
        which = f"{name}{_index(idx)}" if idx else name
        raise ValueError(f"{func} expects a skew-symmetric matrix ({name}^T = -{name}); "
                         f"{which} has max|{name} + {name}^T|/2 = {float(half[idx]):.2e} "
                         f"against max|{name}| = {float(scale[idx]):.2e} (expected at most "
                         f"{rtol / 2:g} times that)")


def as_tolerance(tol, func):
    """Return ``tol`` as a float, or raise ValueError unless it is finite and >= 0."""
    try:
        value = float(tol)
    except (TypeError, ValueError):
        raise ValueError(f"{func} expects tol as a nonnegative number; got {tol!r}") from None
    if not math.isfinite(value) or value < 0:
        raise ValueError(f"{func} expects tol as a finite nonnegative number; got {tol!r}")
    return value


def broadcast_batch(batch, tau, func, name):
    """The batch shape of ``name`` (shape ``batch``) broadcast against ``tau``'s shape.

    Raises ValueError naming both shapes when they do not broadcast.
    """
    try:
        return np.broadcast_shapes(batch, tau.shape)
    except ValueError:
        raise ValueError(f"{func} expects tau as a scalar or an array that broadcasts against "
                         f"the batch shape {batch} of {name}; got tau of shape {tau.shape}") from None

