r"""Checkers for the exercises of notebook 04, "The logarithm".

=============  ==========================================  ==============================
exercise       the learner writes                          checker
=============  ==========================================  ==============================
4.1            ``R_nan``, a rotation (to rounding) on      :func:`check_nan_rotation`
               which the lecture notes' recipe returns
               NaN
4.2            ``all_logs(R, bound)``, every rotation      :func:`check_all_logs`
               vector of length below ``bound`` whose
               exponential is ``R``, one per row
4.3            ``halfturn_axis(R)``, the unit axis of a    :func:`check_halfturn_axis`
               rotation by pi (either sign), without
               calling a logarithm
4.4            ``log_at_pi(n)``, the one of pi n and       :func:`check_log_at_pi`
               -pi n that the half-turn construction
               (4.14) returns for ``2 n n^T - I``
               (``so3lib.log`` uses it), predicted
               without calling a logarithm
4.5            ``principal_log(R)``, the whole             :func:`check_principal_log`
               logarithm, (4.9), (4.11) and
               (4.15)-(4.16), accurate near 0, near
               pi and at pi, without calling one
=============  ==========================================  ==============================

Every checker returns a :class:`~so3lib.exercises.Feedback` and never raises. A checker
holds no answer: it tests the defining property of one (``exp(phi) == R``, a unit ``n``
with ``2 n n^T - I == R``, the count and spacing of the logarithms) and names the usual
mistake, but never prints the expected value.
"""

import inspect

import numpy as np

from .. import so3 as _so3
from ..so3 import angle, exp, log
from . import Feedback, _calls_watched, check_function, never_raises

__all__ = [
    "AXIS_TOL_43",
    "LOG_TOL_45",
    "ROTATION_TOL_41",
    "check_all_logs",
    "check_halfturn_axis",
    "check_log_at_pi",
    "check_nan_rotation",
    "check_principal_log",
    "notes_recipe",
]

#: Exercise 4.1: how far from orthogonal (max |R^T R - I|) and from det 1 the matrix may be:
#: a few roundings, so that only a genuine rotation counts.
ROTATION_TOL_41 = 1e-13


def _unanswered(fb):
    """True for the messages that need no extra hint (nothing written yet)."""
    return any(s in fb.message for s in ("No answer yet", "Not written yet",
                                         "Expected a function"))


def _not_a_rotation_vector(name, label, a):
    """The feedback when NAME returned, for LABEL, something other than 3 numbers (A is
    its value as floats, or None)."""
    shape = "something that is not numbers" if a is None else f"shape {a.shape}"
    return Feedback(False, f"Not yet: {name}. For {label} it returned {shape}; "
                           "expected a rotation vector of shape (3,).")


def _as_float(x):
    try:
        return np.asarray(x, dtype=float)
    except Exception:  # noqa: BLE001 (a checker never raises)
        return None


def _fmt(a):
    return np.array2string(np.asarray(a, dtype=float) + 0.0, precision=4,
                           suppress_small=True, separator=", ")


def _fmt_any(a):
    """Like :func:`_fmt`, but a vector whose entries are all tiny shows their size
    (``[0, 0, 1.8e-08]``, not ``[0., 0., 0.]``)."""
    a = np.asarray(a, dtype=float) + 0.0
    if 0 < np.abs(a).max() < 1e-3:
        return np.array2string(a, separator=", ", formatter={"float_kind": lambda x: f"{x:.2g}"})
    return _fmt(a)


def _not_written(name):
    return Feedback(False, f"Not yet: {name}. Not written yet: the function still "
                           "raises NotImplementedError.")


def _call(func, name, label, *args):
    """``(result, None)``, or ``(None, Feedback)`` when calling ``func`` fails."""
    try:
        got = func(*[np.array(a, copy=True) if isinstance(a, np.ndarray) else a
                     for a in args])
    except NotImplementedError:
        return None, _not_written(name)
    except Exception as err:  # noqa: BLE001 (the learner's code may raise anything)
        return None, Feedback(False, f"Not yet: {name}. For {label} it raised "
                                     f"{type(err).__name__}: {err}")
    if got is None:
        return None, Feedback(False, f"Not yet: {name}. It returned None for {label}: is "
                                     "the `return` missing?")
    return got, None


# --------------------------------------------------------------------------- 4.1

def notes_recipe(R, tau=1.0):
    r"""The lecture notes' logarithm (notebook 04, (4.5) to (4.7)), their steps as printed
    except for :math:`\omega = \sigma n` in place of their :math:`\tau n` (errata N13):

    .. math:: \sigma = \frac1\tau\arccos\frac{\operatorname{tr}R - 1}{2},\quad
              n = \frac{(R - R^T)^\vee}{2\sin(\sigma\tau)},\quad
              \omega = \sigma n\ (\omega = 0 \text{ if } \sigma = 0)

    with ``np.arccos`` not clipped. It is the object of exercise 4.1, not an answer to
    it. NumPy's warnings are silenced; a NaN is returned as it comes.

    Parameters
    ----------
    R : array_like, shape (3, 3)
    tau : float, > 0

    Returns
    -------
    omega : ndarray, shape (3,)
    """
    R = np.asarray(R, dtype=float)
    with np.errstate(all="ignore"):
        sigma = np.arccos((np.trace(R) - 1) / 2) / tau                       # (4.5)
        if sigma == 0:
            return np.zeros(3)                                              # (4.7)
        v = np.array([R[2, 1] - R[1, 2], R[0, 2] - R[2, 0], R[1, 0] - R[0, 1]])
        n = v / (2 * np.sin(sigma * tau))                                   # (4.6)
        return sigma * n


@never_raises("R_nan")
def check_nan_rotation(R_nan):
    r"""Exercise 4.1: ``R_nan`` must be a rotation matrix to rounding (``max|R^T R - I|``
    and ``|det R - 1|`` at most :data:`ROTATION_TOL_41`) on which :func:`notes_recipe`
    returns NaN.

    Recognises a matrix that is not a rotation, the identity (which the recipe's own
    :math:`\sigma = 0` rule handles) and a tiny rotation, on which the recipe returns a
    silent zero instead of NaN.
    """
    name = "R_nan"
    if R_nan is None or R_nan is Ellipsis:
        return Feedback(False, f"Not yet: {name}. No answer yet: replace the `...` with "
                               "a 3x3 rotation matrix and run the cell again.")
    R = _as_float(R_nan)
    if R is None:
        return Feedback(False, f"Not yet: {name}. It is a {type(R_nan).__name__}, not a "
                               "matrix of numbers.")
    if R.shape != (3, 3):
        return Feedback(False, f"Not yet: {name}. It has shape {R.shape}; a rotation of "
                               "space is a 3x3 matrix.")
    if not np.isfinite(R).all():
        return Feedback(False, f"Not yet: {name}. It contains NaN or inf itself; the "
                               "exercise asks for a genuine rotation on which the recipe "
                               "makes a NaN.")
    off = float(np.abs(R.T @ R - np.eye(3)).max())
    det = float(np.linalg.det(R))
    if off > ROTATION_TOL_41 or abs(det - 1) > ROTATION_TOL_41:
        return Feedback(False, f"Not yet: {name}. It is not a rotation to rounding: "
                               f"max|R^T R - I| = {off:.2g} and det R = {det:.17g}; both "
                               f"must be within {ROTATION_TOL_41:g} of I and 1.\nHint: "
                               "build it from so3lib (exp, random_rotation, products of "
                               "rotations), so that it carries only rounding errors.")
    omega = notes_recipe(R)
    c = (np.trace(R) - 1) / 2
    if not np.isfinite(omega).all():
        return Feedback(True, f"Correct: {name}. It is a rotation to rounding, and the "
                              f"recipe returns NaN: c = (tr R - 1)/2 = {c:.17g} lies "
                              "outside [-1, 1], where arccos is not defined.")
    theta = float(angle(R))
    near = -1.0 if c < 0 else 1.0                   # the end of [-1, 1] that c is near
    rounding = 4 * np.finfo(float).eps              # a few roundings of c
    if not omega.any() and theta <= 1e-12:
        why = ("c = 1 exactly, so sigma = 0 and the guard of (4.7) gives omega = 0" if c == 1
               else "c is just below 1 and R - R^T (twice the skew part) is exactly 0, so n = 0 "
                    "and omega = 0")
        hint = (f"Your R is the identity to rounding: {why}, correctly. Look for a rotation "
                "where c = (tr R - 1)/2 can leave [-1, 1] by rounding.")
    elif not omega.any() and c < 0:
        hint = ("Your R is a half-turn whose skew part is exactly 0, so n = 0 and the "
                "recipe returns a silent 0: wrong (exp(0) = I), but not a NaN. Here c = "
                f"{c:.17g}; on other half-turns rounding pushes c just below -1.")
    elif not omega.any():
        hint = (f"Your R turns by {theta:.2g} rad, yet c rounds to exactly 1, so sigma = "
                "0 and (4.7) returns a silent 0: a wrong answer, but not a NaN. Where else "
                "is c = +-1, so that rounding can push it outside [-1, 1]?")
    elif abs(c - near) <= rounding and near < 0:
        hint = (f"Your R is a half-turn to rounding, but on it c = (tr R - 1)/2 = {c:.17g} "
                "stayed inside [-1, 1], so arccos is defined and no NaN appears. You are "
                "close: on other half-turns rounding pushes c just below -1. Try other axes.")
    elif abs(c - near) <= rounding:
        hint = (f"On your R, c = (tr R - 1)/2 = {c:.17g} is within rounding of 1 but stayed "
                "inside [-1, 1], so arccos is defined and no NaN appears. Which rotation "
                "should give c exactly 1, so that rounding can push c just above it?")
    else:
        hint = (f"On your R, c = (tr R - 1)/2 = {c:.17g} lies inside [-1, 1] and "
                "sin(sigma tau) is not 0, so every step is defined. A NaN needs an arccos "
                "outside [-1, 1], 0/0 or 0 * inf: which angles bring c to +-1?")
    return Feedback(False, f"Not yet: {name}. On it the recipe returns the finite "
                           f"vector {_fmt_any(omega)}.\nHint: {hint}")


# --------------------------------------------------------------------------- 4.2

# The last four catch a range of k that is too short: a bound of 40 rad needs k from -6
# to 5, and a turn by 3 rad below a bound of 10 needs k = -2, which a range of
# |k| <= int(bound / (2 pi)) (here 1) misses; a bound of 160 rad needs |k| up to 25,
# which a range fixed in advance (say k from -10 to 10) misses; and a bound of 2000 rad
# needs |k| up to 318, which a generous fixed range (k from -100 to 100) misses.
_ALL_LOG_INPUTS = [
    (exp([0.0, 0.0, 1.0]), 7.0),
    (exp([0.3, -0.4, 1.2]), 10.0),
    (exp(2.5 * np.array([2.0, -1.0, 2.0]) / 3.0), 40.0),
    (exp([0.0, 3.0, 0.0]), 10.0),
    (exp([-1.1, 0.4, 0.8]), 160.0),
    (exp([0.7, -0.2, 0.4]), 2000.0),
    (exp([0.0, 2.5, 0.0]), 2.0),        # a bound below theta: no logarithm, not even Log R
]


def _count_below(theta, bound):
    """How many of the lengths |theta + 2 pi k|, k an integer, are below ``bound``."""
    kmax = int(bound // (2 * np.pi)) + 2
    return sum(abs(theta + 2 * np.pi * k) < bound for k in range(-kmax, kmax + 1))


@never_raises("all_logs")
def check_all_logs(func):
    r"""Exercise 4.2: ``func(R, bound)`` must return, one per row and in any order, every
    rotation vector :math:`\varphi` with :math:`e^{\hat\varphi} = R` and
    :math:`\lVert\varphi\rVert <` ``bound``.

    Tests the defining properties: each row is finite, shorter than ``bound``, along the
    rotation's axis and has ``exp(row) == R``; no two rows are equal; and there are as
    many rows as integers ``k`` with :math:`|\theta + 2\pi k| <` ``bound``. Recognises the
    usual slip: only ``k >= 0``, forgetting the logarithms that point along ``-n``. A
    range of ``k`` that stops one short (``|k| <= bound / 2 pi``) misses a row on the
    fourth rotation, and one fixed in advance misses rows on the fifth (bound 160, so
    ``|k| <= 10`` falls short) or the sixth (bound 2000: ``|k| <= 100`` falls short).
    The seventh has a bound below its angle: no rows at all, so ``Log R`` kept
    unconditionally is refused.
    """
    name = "all_logs"
    if func is None or func is Ellipsis or not callable(func):
        return check_function(func, None, [], name)
    for R, bound in _ALL_LOG_INPUTS:
        theta = float(angle(R))
        n = log(R) / theta
        label = f"all_logs(R, {bound:g}) with R a rotation by {theta:.4g} rad"
        got, fail = _call(func, name, label, R, bound)
        if fail is not None:
            return fail
        a = _as_float(got)
        if a is None:
            return Feedback(False, f"Not yet: {name}. {label} returned something that is "
                                   "not an array of numbers (a list of 3-vectors is fine).")
        if a.shape == (3,):
            a = a[None, :]
        if a.size == 0:                 # np.array([]) for "none": shape (0,)
            a = a.reshape(0, 3)
        if a.ndim != 2 or a.shape[1] != 3:
            return Feedback(False, f"Not yet: {name}. {label} returned shape {a.shape}; "
                                   "expected shape (m, 3), one rotation vector per row.")
        if not np.isfinite(a).all():
            return Feedback(False, f"Not yet: {name}. {label} returned NaN or inf.")
        errs = np.abs(exp(a) - R).max(axis=(1, 2)) if len(a) else np.zeros(0)
        lengths = np.linalg.norm(a, axis=1)
        for i in np.flatnonzero((errs > 1e-8) | (lengths >= bound))[:1]:
            if errs[i] > 1e-8:
                return Feedback(False, f"Not yet: {name}. Row {i} of {label}, "
                                       f"{_fmt(a[i])}, is not a logarithm of R: exp of it "
                                       f"differs from R by {errs[i]:.2g}.\nHint: every "
                                       "logarithm is (theta + 2 pi k) n with n the unit "
                                       "axis of log(R); check each row.")
            return Feedback(False, f"Not yet: {name}. Row {i} of {label} has length "
                                   f"{lengths[i]:.4g}, not below the bound.")
        order = np.argsort(a @ n, kind="stable")   # equal rows end up side by side
        same = np.abs(np.diff(a[order], axis=0)).max(axis=1) <= 1e-8 if len(a) > 1 else []
        for i in np.flatnonzero(same)[:1]:
            j, i = sorted((int(order[i]), int(order[i + 1])))
            return Feedback(False, f"Not yet: {name}. {label}: rows {j} and {i} "
                                   "are the same logarithm; list each once.\nHint: "
                                   "the logarithms are (theta + 2 pi k) n, one for "
                                   "each integer k with |theta + 2 pi k| < bound.")
        count = _count_below(theta, bound)
        if len(a) == count:
            continue
        if len(a) > count:      # cannot happen with distinct valid rows; kept for safety
            return Feedback(False, f"Not yet: {name}. {label} returned {len(a)} rows, "
                                   "more than there are logarithms below the bound.")
        if (a @ n > 0).all():
            hint = ("You have the k >= 0 ones. The k < 0 ones, (theta - 2 pi |k|) n, point "
                    "along -n and have length 2 pi |k| - theta: turning the other way round "
                    "reaches the same R.")
        else:
            hint = ("The logarithms are (theta + 2 pi k) n for every integer k, negative "
                    "ones included; keep those with |theta + 2 pi k| < bound. How far must "
                    "k run? |k| can reach (bound + theta) / (2 pi), more than bound / (2 pi).")
        found = f"{len(a)} logarithm" + ("" if len(a) == 1 else "s")
        return Feedback(False, f"Not yet: {name}. {label} returned {found}, "
                               "all right, but some logarithms shorter than the bound are "
                               f"missing.\nHint: {hint}")
    return Feedback(True, f"Correct: {name}. It finds every logarithm below the bound, "
                          f"each once, for {len(_ALL_LOG_INPUTS)} rotations.")


# --------------------------------------------------------------------------- 4.3

def _halfturn(n):
    n = np.asarray(n, dtype=float)
    return 2.0 * np.outer(n, n) - np.eye(3)


# The third axis is e_z: column 0 (and 1) of R + I is then zero, which catches a
# solution that always normalises the first column. The fourth, (0, 0.6, -0.8), has
# n_1 = 0 and two components of opposite signs: it catches magnitudes read off the
# diagonal (R_jj = 2 n_j^2 - 1) with signs taken from row 1 (R_1j = 2 n_1 n_j), which
# is 0 there.
_HALF_AXES = [
    np.array([1.0, 0.0, 0.0]),
    np.array([1.0, 1.0, 0.0]) / np.sqrt(2.0),
    np.array([0.0, 0.0, 1.0]),
    np.array([0.0, 0.6, -0.8]),
    np.array([1.0, 2.0, 3.0]) / np.sqrt(14.0),
    np.array([0.3, -0.5, 0.8]) / np.linalg.norm([0.3, -0.5, 0.8]),
]


#: Exercise 4.3: how far ``2 n n^T - I`` may be from ``R`` (and ``|n|`` from 1). The
#: half-turn construction gets within a few 1e-16; a component read off the diagonal as
#: ``sqrt((R_jj + 1)/2)`` turns rounding noise of 1e-16 into an error near 1e-9 when
#: ``n_j`` is tiny (the square root halves the digits, as arccos does near 0), and fails.
AXIS_TOL_43 = 1e-12

# Half-turns computed as exp(pi n), with rounding noise: about the last axis; about e_z,
# where columns 1 and 2 of R + I hold only noise (1.2e-16), which catches a solution that
# takes the first column that is not exactly zero; and about an axis whose first
# component is 1e-9, where column 1 of R + I, 2e-9 n plus noise, is nonzero but gives the
# axis only to about 1e-7, which catches a small threshold in place of the largest entry,
# and the diagonal gives n_1 only to about 1e-9 (AXIS_TOL_43); and about an axis whose
# first component is 1e-5, where column 1 (length 2e-5) gives the axis only to about
# 5e-11, which catches any threshold on the column's length below 2e-5 (1e-8 and 1e-6
# pass the 1e-9 axis, whose column is shorter than them).
_NOISY_AXES = [
    _HALF_AXES[-1],
    np.array([0.0, 0.0, 1.0]),
    np.array([1e-9, 0.6, -0.8]) / np.linalg.norm([1e-9, 0.6, -0.8]),
    np.array([1e-5, 0.28, 0.96]) / np.linalg.norm([1e-5, 0.28, 0.96]),
]


def _halfturn_inputs():
    """(label, R) pairs; the label shows the input matrix, never its axis. The last four
    are ``exp(pi n)``, with rounding noise."""
    exact = [(f"R = {(np.round(R, 4) + 0.0).tolist()}", R)
             for R in (_halfturn(n) for n in _HALF_AXES)]
    noisy = [(f"R = {(np.round(R, 4) + 0.0).tolist()} (exp(pi n), with rounding noise)", R)
             for R in (exp(np.pi * n) for n in _NOISY_AXES)]
    return exact + noisy


@never_raises("halfturn_axis")
def check_halfturn_axis(func):
    r"""Exercise 4.3: ``func(R)`` must return a unit axis ``n`` of a rotation by pi,
    ``R + I = 2 n n^T`` (notebook 04, (4.13)); either sign is accepted.

    Tests the defining property: ``n`` has length 1 and ``2 n n^T - I`` is ``R``, within
    :data:`AXIS_TOL_43`, on six exact half-turns and four computed ones that carry
    rounding noise. Recognises a column that is not normalised, :math:`\pi n` in place of
    ``n``, the zero column (NaN) that comes from always taking the first column, and a
    column or a diagonal entry that is only noise. Refuses a call to a logarithm
    (``log(R) / pi`` would do), watched as in exercise 4.4.
    """
    name = "halfturn_axis"
    if func is None or func is Ellipsis or not callable(func):
        return check_function(func, None, [], name)
    for label, R in _halfturn_inputs():
        (got, fail), called = _logarithms_called(_call, func, name, label, R)
        if fail is not None:
            if "raised" in fail.message:
                return Feedback(False, fail.message + "\nHint: the axis is a column of "
                                                      "R + I, divided by its length.")
            return fail
        if called:
            return Feedback(False, f"Not yet: {name}. It calls {called[0]}, a logarithm: "
                                   "the exercise asks you to build the axis yourself, from "
                                   "R alone.\nHint: R + I = 2 n n^T, so every column of "
                                   "R + I is a multiple of n.")
        a = _as_float(got)
        if a is None:
            return Feedback(False, f"Not yet: {name}. For {label} it returned a "
                                   f"{type(got).__name__}, not an array of numbers.")
        if a.shape != (3,):
            return Feedback(False, f"Not yet: {name}. For {label} it returned shape "
                                   f"{a.shape}; expected a vector of shape (3,).")
        if not np.isfinite(a).all():
            return Feedback(False, f"Not yet: {name}. For {label} it returned "
                                   f"{_fmt(a)}, with NaN or inf.\nHint: at a half-turn "
                                   "R - R^T (twice the skew part) is 0, and a column of R + I, "
                                   "2 n_j n, is zero when n_j = 0: either gives 0/0. Take "
                                   "the column j with the largest diagonal entry R[j, j]: "
                                   "then 2 n_j^2 = R[j, j] + 1 >= 2/3.")
        length = float(np.linalg.norm(a))
        if abs(length - 1) <= AXIS_TOL_43 and np.abs(_halfturn(a) - R).max() <= AXIS_TOL_43:
            continue
        u = a / length if length > 0 else a
        along = length > 0 and np.abs(_halfturn(u) - R).max() <= AXIS_TOL_43
        if along:               # the right line, the wrong length: say that, not "0"
            if abs(length - np.pi) <= 1e-7:
                hint = "That is the logarithm pi n; the exercise asks for the unit axis n."
            else:
                hint = ("Divide the column by its length, sqrt(2 (R[j, j] + 1)).")
            return Feedback(False, f"Not yet: {name}. For {label} it returned {_fmt(a)}: "
                                   f"right direction, but length {length:.4g}, not 1, so "
                                   "2 n n^T - I is not R.\nHint: " + hint)
        hint = ("R + I = 2 n n^T, so every column of R + I is a multiple of n: take "
                "the one with the largest diagonal entry and normalise it.")
        if "noise" in label:
            hint = ("On a computed half-turn the entries of R carry rounding noise of "
                    "about 1e-16. A column of R + I that should be 0 (or tiny) is then "
                    "mostly noise, and a short column gives the axis only to about 1e-16 "
                    "divided by its length. A small n_j read off the diagonal as "
                    "sqrt((R[j, j] + 1)/2) is noisy too: the square root turns 1e-16 into "
                    "1e-8. "
                    + hint)
        return Feedback(False, f"Not yet: {name}. For {label} it returned {_fmt(a)}, "
                               "which is not its axis: even normalised, 2 n n^T - I differs "
                               f"from R by {np.abs(_halfturn(u) - R).max():.2g} (allowed: "
                               f"{AXIS_TOL_43:g}).\nHint: {hint}")
    return Feedback(True, f"Correct: {name}. It finds the axis (up to its sign, which is "
                          f"free at a half-turn) of {len(_HALF_AXES) + len(_NOISY_AXES)} "
                          "half-turns.")


# --------------------------------------------------------------------------- 4.4

_PI_AXES = [
    np.array([1.0, 0.0, 0.0]),
    np.array([0.0, -1.0, 0.0]),
    np.array([-0.8, 0.6, 0.0]),
    np.array([0.0, 0.6, -0.8]),
    np.array([1.0, -2.0, 2.0]) / 3.0,      # two largest components of equal size
    np.array([-0.6, 0.0, 0.8]),
    np.array([0.6, 0.0, -0.8]),
]

#: The functions whose call counts as "calling a logarithm" in exercise 4.4, recognised
#: by their code objects: so3lib's public ``log`` and ``angle``, and the private helpers
#: of ``so3lib.so3`` that compute a logarithm or an angle (``_log_one``, ``_log_block``,
#: ``_near_pi``, ...), so that reaching into the module does not slip past the watch.
#: Any module function of ``so3lib.so3`` whose name contains "log" is included, so a
#: helper added later is watched too.
_LOG_HELPERS = ("_log_one", "_log_block", "_near_pi", "_skew_and_trace", "_half_norm")


def _log_codes():
    codes = {log.__code__: "log", angle.__code__: "angle"}
    for fname, f in vars(_so3).items():
        if (inspect.isfunction(f) and f.__module__ == _so3.__name__
                and (fname in _LOG_HELPERS or "log" in fname)):
            codes.setdefault(f.__code__, f"so3lib.so3.{fname}")
    return codes


_LOG_CODES = _log_codes()


def _logarithms_called(func, *args):
    """Run ``func(*args)``; return its result (or the exception) and the names of the
    logarithms it called: so3lib's ``log`` and ``angle`` and the private helpers of
    ``so3lib.so3`` behind them, anything in SciPy's ``scipy.spatial.transform`` (``Rotation``),
    and SciPy's general matrix logarithm ``scipy.linalg.logm``."""
    def name_of(code):
        if code in _LOG_CODES:
            return _LOG_CODES[code]
        path = code.co_filename.replace("\\", "/")
        if "scipy/spatial/transform" in path:
            return f"scipy.spatial.transform ({code.co_name})"
        if "scipy/linalg" in path and code.co_name == "logm":
            return "scipy.linalg.logm"
        return None

    with _calls_watched(name_of) as seen:
        try:
            out = func(*args)
        except Exception as err:  # noqa: BLE001 (reported by the caller)
            out = err
    return out, seen


@never_raises("log_at_pi")
def check_log_at_pi(func):
    r"""Exercise 4.4: ``func(n)`` must predict which of :math:`\pm\pi n` the half-turn
    construction (4.14) gives for the exactly symmetric half-turn ``2 n n^T - I``: the
    logarithm ``so3lib.log`` returns there (it uses (4.14)), without
    calling a logarithm (so3lib's ``log`` or ``angle``, their private helpers in
    ``so3lib.so3``, or SciPy's rotations): the checker watches the calls.

    Recognises a call to a logarithm, :math:`\pi n` returned as given (ignoring the
    convention) and the other common convention, "first nonzero component positive".
    """
    name = "log_at_pi"
    if func is None or func is Ellipsis or not callable(func):
        return check_function(func, None, [], name)
    outs = []
    for n in _PI_AXES:
        label = f"n = {_fmt(n)}"
        got, called = _logarithms_called(func, n.copy())
        if isinstance(got, NotImplementedError):
            return _not_written(name)
        if isinstance(got, Exception):
            return Feedback(False, f"Not yet: {name}. For {label} it raised "
                                   f"{type(got).__name__}: {got}")
        if called:
            return Feedback(False, f"Not yet: {name}. It calls {called[0]}, a "
                                   "logarithm: the exercise asks you to predict the answer "
                                   "from n alone.\nHint: in (4.14), column j of R + I is "
                                   "2 n_j n; which sign is left after dividing it by its "
                                   "length?")
        if got is None:
            return Feedback(False, f"Not yet: {name}. It returned None for {label}: is the "
                                   "`return` missing?")
        a = _as_float(got)
        if a is None or a.shape != (3,):
            return _not_a_rotation_vector(name, label, a)
        if not np.isfinite(a).all():
            return Feedback(False, f"Not yet: {name}. For {label} it returned NaN or inf.")
        outs.append(a)
    wrong = [(n, a) for n, a in zip(_PI_AXES, outs)
             if np.abs(a - log(_halfturn(n))).max() > 1e-10]
    if not wrong:
        return Feedback(True, f"Correct: {name}. It predicts the sign (4.14) gives for "
                              f"{len(_PI_AXES)} half-turns, without calling a logarithm.")
    n, a = wrong[0]
    if min(np.abs(a - np.pi * n).max(), np.abs(a + np.pi * n).max()) > 1e-10:
        return Feedback(False, f"Not yet: {name}. For n = {_fmt(n)} it returned {_fmt(a)}, "
                               "which is not +-pi n, so not a logarithm of the half-turn "
                               "at all.\nHint: the answer is pi n or -pi n; the rule picks "
                               "the sign.")
    rule = ("(4.14) picks j where R[j, j] = 2 n_j^2 - 1 is largest, so |n_j| is the "
            "largest component (the first, if two are equally large), and divides column j, "
            "2 n_j n, by its length 2 |n_j|: what sign does that leave on component j?")
    if all(np.allclose(o, np.pi * m, atol=1e-10) for o, m in zip(outs, _PI_AXES)):
        hint = ("You returned pi n as given. Both +pi n and -pi n are logarithms of the "
                "half-turn, and the matrix 2 n n^T - I does not know which n you started "
                "from, so (4.14) returns one of them by its own arithmetic. " + rule)
    elif all(np.allclose(o, np.pi * m * np.sign(m[np.flatnonzero(np.abs(m) > 1e-12)[0]]),
                         atol=1e-10) for o, m in zip(outs, _PI_AXES)):
        hint = ("You made the first nonzero component positive. That is a fine convention, "
                "but (4.14) divides by the column of the largest diagonal entry, so its "
                "sign is fixed by the largest component (in absolute value; the first of "
                "equally large ones).")
    else:
        hint = rule
    return Feedback(False, f"Not yet: {name}. For n = {_fmt(n)} it returned {_fmt(a)}: a "
                           "logarithm of the half-turn, but not the sign (4.14) gives."
                           f"\nHint: {hint}")


# --------------------------------------------------------------------------- 4.5

#: Exercise 4.5: how far the learner's logarithm may be from the rotation vector put in,
#: relative to ``min(1, theta)``: 1e-13 is some 450 eps, far above the few eps of a
#: NumPy version of (4.9), (4.11) and (4.15)-(4.16), and far below the errors of the
#: formulas that fail: (4.11) at pi - 1e-6 is off by about 1e-10, an arccos angle there
#: by about 2e-10, and at 1e-9 rad arccos gives the angle 0.
LOG_TOL_45 = 1e-13


def _unit(v):
    v = np.asarray(v, dtype=float)
    return v / np.linalg.norm(v)


# (kind, what the label says, phi put in or the axis of an exact half-turn). The kinds:
# "exp": R = exp(phi), whose principal logarithm is phi (|phi| < pi); "pi": the exactly
# symmetric half-turn 2 n n^T - I, whose logarithms are +-pi n; "noisy": exp(pi n), a
# computed half-turn whose skew part is rounding noise, so either sign is right.
_LOG_CASES = [
    ("exp", "a rotation by 1 rad", 1.0 * _unit([0.3, -0.4, 1.2])),
    ("id", "the identity", np.zeros(3)),
    ("exp", "a rotation by 1e-5 rad", 1e-5 * _unit([2.0, -1.0, 2.0])),
    ("exp", "a rotation by 1e-9 rad", 1e-9 * _unit([-0.5, 0.7, 0.3])),
    ("exp", "a rotation by 1e-12 rad", 1e-12 * _unit([1.0, 1.0, -1.0])),
    ("exp", "a rotation by 2.5 rad", 2.5 * _unit([-1.1, 0.4, 0.8])),
    ("exp", "a rotation by pi - 1e-4 rad", (np.pi - 1e-4) * _unit([0.3, -0.5, 0.8])),
    ("exp", "a rotation by pi - 1e-6 rad", (np.pi - 1e-6) * _unit([-0.6, 0.2, 0.7])),
    ("exp", "a rotation by pi - 1e-10 rad", (np.pi - 1e-10) * _unit([0.8, 0.1, -0.5])),
    ("pi", "an exact half-turn", np.array([0.0, 0.0, 1.0])),
    ("pi", "an exact half-turn", _unit([1.0, 1.0, 0.0])),
    ("pi", "an exact half-turn", _unit([1.0, 2.0, 3.0])),
    ("pi", "an exact half-turn", np.array([0.0, 0.6, -0.8])),
    ("noisy", "a computed half-turn, exp(pi n)", _unit([0.3, -0.5, 0.8])),
]


def _log_inputs():
    """(kind, label, R, phi or n) for each case: the label names the input, never its
    logarithm."""
    out = []
    for kind, what, p in _LOG_CASES:
        if kind == "pi":
            R = _halfturn(p)
        elif kind == "noisy":
            R = exp(np.pi * p)
        else:
            R = exp(p)
        shown = (np.round(R, 4) + 0.0).tolist()
        label = what if kind in ("exp", "id") else f"{what}, R = {shown}"
        out.append((kind, label, R, p))
    return out


@never_raises("principal_log")
def check_principal_log(func):
    r"""Exercise 4.5 (the whole logarithm): ``func(R)`` must return the principal
    logarithm of the rotation ``R``, a vector :math:`\varphi` with
    :math:`e^{\hat\varphi} = R` and :math:`\lVert\varphi\rVert \le \pi`, accurate at every
    angle, without calling a logarithm (so3lib's ``log`` or ``angle``, their helpers,
    SciPy's rotations or ``scipy.linalg.logm``: the checker watches the calls).

    Each test rotation is built from the rotation vector it must give back: ``exp(phi)``
    with :math:`\lVert\varphi\rVert < \pi` (from 1e-12 rad to :math:`\pi - 10^{-10}`), the
    identity, exact half-turns :math:`2nn^T - I` (either of :math:`\pm\pi n`) and a
    computed one, ``exp(pi n)`` (either sign: its skew part is rounding noise). The answer
    must be within :data:`LOG_TOL_45` times :math:`\min(1, \theta)` of that vector.
    Recognises the usual mistakes: 0/0 at the identity, the arccos angle that rounds to 0
    below about 2e-8 rad, the skew part's 0 (or NaN) at a half-turn, the axis from the
    skew part near pi, the arccos angle near pi, the missing sign test (4.16), a sign
    error and an answer longer than pi.
    """
    name = "principal_log"
    if func is None or func is Ellipsis or not callable(func):
        return check_function(func, None, [], name)
    for kind, label, R, p in _log_inputs():
        (got, fail), called = _logarithms_called(_call, func, name, label, R)
        if fail is not None:
            return fail
        if called:
            return Feedback(False, f"Not yet: {name}. It calls {called[0]}, a logarithm: the "
                                   "exercise asks you to write the logarithm yourself, from "
                                   "(4.9), (4.11) and (4.15)-(4.16).")
        a = _as_float(got)
        if a is None or a.shape != (3,):
            return _not_a_rotation_vector(name, label, a)
        if not np.isfinite(a).all():
            if kind == "id":
                hint = ("At R = I both s and theta are 0, so theta / (2 s) (or theta / (2 sin "
                        "theta)) is 0/0. Log I = 0 needs its own branch: return 0 when the "
                        "skew part is exactly 0 and c > 0.")
            elif kind == "exp" and np.linalg.norm(p) < 1e-7:
                hint = ("Below about 2e-8 rad, c = (tr R - 1)/2 rounds to exactly 1, so an "
                        "angle from arccos is 0 and theta / (2 sin theta) is 0/0. Take the "
                        "angle from atan2(s, c), (4.9): s is still accurate.")
            elif kind in ("pi", "noisy"):
                hint = ("At a half-turn the skew part is 0 (or rounding noise) and c can round "
                        "just below -1, where arccos is NaN: take the angle from atan2, (4.9), "
                        "and for c < 0 the axis from the symmetric part, (4.15), which is "
                        "large there.")
            else:
                hint = "Look for a division by a quantity that is 0 for this rotation."
            return Feedback(False, f"Not yet: {name}. For {label} it returned {_fmt_any(a)}, "
                                   f"with NaN or inf.\nHint: {hint}")
        length = float(np.linalg.norm(a))
        if kind == "id":
            if a.any():
                return Feedback(False, f"Not yet: {name}. For {label} it returned "
                                       f"{_fmt_any(a)}: the principal logarithm of I is the "
                                       "zero vector, (4.10).")
            continue
        if length > np.pi * (1 + 1e-15):
            return Feedback(False, f"Not yet: {name}. For {label} it returned {_fmt_any(a)}, "
                                   f"of length {length:.6g}, more than pi: not the principal "
                                   "logarithm.\nHint: with theta = atan2(s, c) and s >= 0, "
                                   "theta lies in [0, pi] and theta n is never longer.")
        if kind == "exp":
            theta = float(np.linalg.norm(p))
            scale = min(1.0, theta)
            err = float(np.abs(a - p).max())
            if err <= LOG_TOL_45 * scale:
                continue
            near_pi = theta > 3.0
            if not a.any():
                hint = ("A zero for a rotation that turns: below about 2e-8 rad c = (tr R - "
                        "1)/2 rounds to exactly 1, so an angle from arccos is 0. Take the "
                        "angle from atan2(s, c), (4.9).")
            elif np.abs(a + p).max() <= max(LOG_TOL_45 * scale, 1e-6 * scale) and near_pi:
                hint = ("The right axis, with the wrong sign: the symmetric part gives n only "
                        "up to its sign (n n^T is the same for -n). Fix it with (4.16): "
                        "n . (R - R^T)^vee = 2 sin theta >= 0.")
            elif np.abs(a + p).max() <= 1e-6 * scale:
                hint = ("It is off by a sign: (R - R^T)^vee = 2 sin theta n, with R[2, 1] - "
                        "R[1, 2] first, not R^T - R.")
            elif near_pi and err < 1e-3:
                hint = ("Close, but not accurate near pi. An axis from the skew part divides "
                        "a small R - R^T by a small 2 sin theta, and an angle from arccos is "
                        "ill-conditioned there, (4.8). For c < 0 take the axis from the "
                        "symmetric part, (4.15), the sign from (4.16), the angle from atan2.")
            elif err < 1e-3 * scale:
                hint = ("Close, but it has lost digits. Take the angle from atan2(s, c), "
                        "(4.9), and use the same s in theta / (2 s) of (4.11).")
            elif theta > np.pi / 2:
                hint = ("exp of your answer is not R. Here c < 0: the axis is the column with "
                        "the largest diagonal entry of (4.15), (1/2)(R + R^T) - c I = (1 - c) n "
                        "n^T (mind the - c I), normalised, with the sign of (4.16); the angle "
                        "is atan2(s, c).")
            else:
                hint = ("exp of your answer is not R. The logarithm is theta n: theta = "
                        "atan2(s, c) from (4.9), and theta / (2 s) (R - R^T)^vee, (4.11), for "
                        "c >= 0.")
            rel = " relative to the angle" if theta < 1 else ""
            return Feedback(False, f"Not yet: {name}. For {label} it returned {_fmt_any(a)}, "
                                   f"off by {err / scale:.1e}{rel} (allowed: "
                                   f"{LOG_TOL_45:g}).\nHint: {hint}")
        # a half-turn: +pi n or -pi n (for exp(pi n), +-fl(pi) n)
        size = np.pi if kind == "pi" else float(np.linalg.norm(np.pi * p))
        err = min(float(np.abs(a - size * p).max()), float(np.abs(a + size * p).max()))
        if err <= LOG_TOL_45:
            continue
        if not a.any():
            hint = ("A zero at a half-turn: there R - R^T (twice the skew part) is exactly 0 (and "
                    "the float pi's sine is 1.2e-16, not 0), so (4.11) returns 0 without a "
                    "warning. For c < 0 take the axis from the symmetric part, (4.15).")
        else:
            hint = ("At a half-turn the skew part holds no information (0, or rounding "
                    "noise): the axis must come from the symmetric part, (1/2)(R + R^T) - c I "
                    "= (1 - c) n n^T, (4.15): its column with the largest diagonal entry, "
                    "normalised.")
        return Feedback(False, f"Not yet: {name}. For {label} it returned {_fmt_any(a)}, "
                               "which is not a logarithm of it: +pi n and -pi n are, for its "
                               f"axis n.\nHint: {hint}")
    return Feedback(True, f"Correct: {name}. It gives the principal logarithm to within "
                          f"{LOG_TOL_45:g} (relative below 1 rad) on {len(_LOG_CASES)} "
                          "rotations, from 1e-12 rad to exact half-turns, without calling a "
                          "logarithm.")
