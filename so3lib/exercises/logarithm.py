r"""Checkers for the exercises of notebook 04, "The logarithm".

=============  ==========================================  ==============================
exercise       the learner writes                          checker
=============  ==========================================  ==============================
4.1            ``sigma`` and ``n`` for the rotation        :func:`check_sigma_and_axis`
               ``R41`` reached in ``TAU41`` seconds, by
               the lecture notes' method
4.2            ``all_logs(R, bound)``, every rotation      :func:`check_all_logs`
               vector of length below ``bound`` whose
               exponential is ``R``, one per row
4.3            ``halfturn_axis(R)``, the unit axis of a    :func:`check_halfturn_axis`
               rotation by pi (either sign)
4.4            ``log_at_pi(n)``, the logarithm that        :func:`check_log_at_pi`
               ``so3lib.log`` returns for the half-turn
               ``2 n n^T - I``
=============  ==========================================  ==============================

Every checker returns a :class:`~so3lib.exercises.Feedback` and never raises.
"""

import numpy as np

from ..so3 import angle, exp, log, random_rotation
from . import Feedback, check_function, check_value, never_raises

__all__ = ["check_sigma_and_axis", "check_halfturn_axis", "check_all_logs",
           "check_log_at_pi", "all_logs", "R41", "TAU41"]

#: Exercise 4.1: a rotation (angle about 1.85 rad) ...
R41 = random_rotation(40)
R41.setflags(write=False)
#: ... reached in this time (s).
TAU41 = 2.0



def _unanswered(fb):
    """True for the messages that need no extra hint (nothing written yet)."""
    return any(s in fb.message for s in ("No answer yet", "Not written yet",
                                         "Expected a function"))


def _as_float(x):
    try:
        return np.asarray(x, dtype=float)
    except Exception:
        return None


def _try_call(func, *args):
    """``func(*args)`` as a finite float array, or None if that fails."""
    try:
        out = np.asarray(func(*[np.array(a, copy=True) if isinstance(a, np.ndarray) else a
                                for a in args]), dtype=float)
        return out if np.isfinite(out).all() else None
    except Exception:
        return None


# --------------------------------------------------------------------------- 4.1

@never_raises("sigma and n")
def check_sigma_and_axis(sigma, n):
    r"""Exercise 4.1: the angular speed ``sigma`` and unit axis ``n`` of ``R41`` reached in
    ``TAU41`` seconds, by the lecture notes' method (notebook 04, (4.5) and (4.6)):

    .. math:: \sigma = \frac1\tau\arccos\frac{\operatorname{tr}R - 1}{2},\qquad
              n = \frac{(R - R^T)^\vee}{2\sin(\sigma\tau)}

    Recognises ``sigma`` not divided by ``tau``, ``n`` not divided by ``2 sin``, and ``n``
    with the opposite sign.
    """
    theta = float(angle(R41))
    v = np.array([R41[2, 1] - R41[1, 2], R41[0, 2] - R41[2, 0], R41[1, 0] - R41[0, 1]])
    sigma_ref, n_ref = theta / TAU41, v / (2 * np.sin(theta))
    s_hint = "sigma = arccos((trace(R) - 1) / 2) / tau: the angle divided by the time."
    s = _as_float(sigma)
    if s is not None and s.shape == () and np.isfinite(s):
        if np.isclose(float(s), theta):
            s_hint = ("That is the angle theta = sigma tau in radians; sigma is an angular "
                      "speed, so divide by tau.")
        elif np.isclose(float(s), theta * TAU41):
            s_hint = "You multiplied by tau; sigma = theta / tau."
    fb_s = check_value(sigma, sigma_ref, "sigma", atol=1e-9, rtol=1e-9, hint=s_hint)
    n_hint = "n = vee(R - R^T) / (2 sin(sigma tau)), a unit vector."
    a = _as_float(n)
    if a is not None and a.shape == (3,) and np.isfinite(a).all():
        if np.allclose(a, v, atol=1e-9):
            n_hint = ("That is vee(R - R^T) = 2 sin(theta) n; divide by 2 sin(sigma tau) "
                      "to get the unit axis.")
        elif np.allclose(a, n_ref * TAU41, atol=1e-9) or np.allclose(a, TAU41 * v, atol=1e-9):
            n_hint = "n is unitless: it should not contain tau."
        elif not np.isclose(np.linalg.norm(a), 1.0, atol=1e-6):
            n_hint = (f"Your n has length {np.linalg.norm(a):.4g}; an axis has length 1. "
                      "Check the factor 2 sin(sigma tau).")
    fb_n = check_value(n, n_ref, "the axis n", atol=1e-9, rtol=1e-9, hint=n_hint)
    if fb_s and fb_n:
        return Feedback(True, "Correct: sigma and n. Then omega = sigma n, and "
                              "exp(omega, tau) gives R back.")
    parts = [fb.message for fb in (fb_s, fb_n) if not fb]
    return Feedback(False, "\n".join(parts))


# --------------------------------------------------------------------------- 4.3

def _halfturn(n):
    n = np.asarray(n, dtype=float)
    return 2.0 * np.outer(n, n) - np.eye(3)


# The third axis is e_z: column 0 (and 1) of R + I is then zero, which catches a
# solution that always normalises the first column.
_HALF_AXES = [
    np.array([1.0, 0.0, 0.0]),
    np.array([1.0, 1.0, 0.0]) / np.sqrt(2.0),
    np.array([0.0, 0.0, 1.0]),
    np.array([1.0, 2.0, 3.0]) / np.sqrt(14.0),
    np.array([0.3, -0.5, 0.8]) / np.linalg.norm([0.3, -0.5, 0.8]),
]


def _halfturn_inputs():
    cases = [(f"the half-turn about {np.round(n, 4).tolist()}", _halfturn(n), n)
             for n in _HALF_AXES]
    n = _HALF_AXES[-1]
    cases.append((f"exp(pi n) with n = {np.round(n, 4).tolist()} (rounding noise included)",
                  exp(np.pi * n), n))
    return cases


@never_raises("halfturn_axis")
def check_halfturn_axis(func):
    r"""Exercise 4.3: ``func(R)`` must return a unit axis ``n`` of a rotation by pi,
    ``R + I = 2 n n^T`` (notebook 04, (4.13) and (4.14)); either sign is accepted.

    Recognises a column that is not normalised, :math:`\pi n` in place of ``n``, and the
    zero column (NaN) that comes from always taking the first column.
    """
    name = "halfturn_axis"
    if func is None or func is Ellipsis or not callable(func):
        return check_function(func, None, [], name)
    for label, R, n0 in _halfturn_inputs():
        try:
            got = func(R.copy())
        except NotImplementedError:
            return Feedback(False, f"Not yet: {name}. Not written yet: the function still "
                                   "raises NotImplementedError.")
        except Exception as err:
            return Feedback(False, f"Not yet: {name}. For {label} it raised "
                                   f"{type(err).__name__}: {err}\nHint: the axis is a "
                                   "column of R + I, divided by its length.")
        if got is None:
            return Feedback(False, f"Not yet: {name}. It returned None for {label}: is the "
                                   "`return` missing?")
        a = _as_float(got)
        if a is None:
            return Feedback(False, f"Not yet: {name}. For {label} it returned a "
                                   f"{type(got).__name__}, not an array of numbers.")
        if a.shape != (3,):
            return Feedback(False, f"Not yet: {name}. For {label} it returned shape "
                                   f"{a.shape}; expected a vector of shape (3,).")
        if not np.isfinite(a).all():
            return Feedback(False, f"Not yet: {name}. For {label} it returned "
                                   f"{np.round(a, 4).tolist()}, with NaN or inf.\nHint: a "
                                   "column of R + I is 2 n_j n, which is zero when n_j = 0. "
                                   "Take the column j with the largest diagonal entry "
                                   "R[j, j]: then 2 n_j^2 = R[j, j] + 1 >= 2/3.")
        if min(np.abs(a - n0).max(), np.abs(a + n0).max()) <= 1e-8:
            continue
        length = np.linalg.norm(a)
        if np.isclose(length, np.pi, rtol=1e-8) and \
                min(np.abs(a / np.pi - n0).max(), np.abs(a / np.pi + n0).max()) <= 1e-8:
            hint = "That is the logarithm pi n; the exercise asks for the unit axis n."
        elif length > 0 and min(np.abs(a / length - n0).max(),
                                np.abs(a / length + n0).max()) <= 1e-8:
            hint = (f"Right direction, but length {length:.4g}: divide the column by its "
                    "length, sqrt(2 (R[j, j] + 1)).")
        else:
            hint = ("R + I = 2 n n^T, so every column of R + I is a multiple of n: take "
                    "the one with the largest diagonal entry and normalise it.")
        return Feedback(False, f"Not yet: {name}. For {label} it returned "
                               f"{np.round(a, 4).tolist()}; expected +-"
                               f"{np.round(n0, 4).tolist()}.\nHint: {hint}")
    return Feedback(True, f"Correct: {name}. It finds the axis (up to its sign, which is "
                          "free at a half-turn) of 6 half-turns.")


# --------------------------------------------------------------------------- 4.2

def all_logs(R, bound):
    r"""Every rotation vector :math:`\varphi` with :math:`e^{\hat\varphi} = R` and
    :math:`\lVert\varphi\rVert < \mathrm{bound}`, one per row, in increasing length.

    .. math:: \exp^{-1}(R) = \{(\theta + 2\pi k)\,n : k \in \mathbb Z\}

    for a rotation of principal angle :math:`0 < \theta < \pi` (notebook 04, (4.12));
    the reference answer of exercise 4.2. Rows with ``k < 0`` point along ``-n`` and
    have length :math:`2\pi|k| - \theta`.

    Parameters
    ----------
    R : array_like, shape (3, 3), with angle strictly between 0 and pi
    bound : float

    Returns
    -------
    phis : ndarray, shape (m, 3)
    """
    phi = log(R)
    theta = float(np.linalg.norm(phi))
    n = phi / theta
    kmax = int(np.ceil(bound / (2 * np.pi))) + 1
    lengths = [theta + 2 * np.pi * k for k in range(-kmax, kmax + 1)]
    lengths = sorted((t for t in lengths if abs(t) < bound), key=abs)
    return np.array([t * n for t in lengths]).reshape(-1, 3)


_ALL_LOG_INPUTS = [
    (exp([0.0, 0.0, 1.0]), 7.0),
    (exp([0.3, -0.4, 1.2]), 10.0),
    (exp(2.5 * np.array([2.0, -1.0, 2.0]) / 3.0), 20.0),
]


def _match_rows(got, expected, atol=1e-8):
    """True when the rows of ``got`` are those of ``expected`` in some order."""
    if got.shape != expected.shape:
        return False
    left = list(range(len(expected)))
    for row in got:
        hit = next((i for i in left if np.allclose(row, expected[i], atol=atol)), None)
        if hit is None:
            return False
        left.remove(hit)
    return True


@never_raises("all_logs")
def check_all_logs(func):
    r"""Exercise 4.2: ``func(R, bound)`` must return, one per row and in any order, every
    :math:`(\theta + 2\pi k)\,n` shorter than ``bound``.

    Recognises the usual slip: only ``k >= 0``, forgetting the logarithms that point along
    ``-n``.
    """
    name = "all_logs"
    if func is None or func is Ellipsis or not callable(func):
        return check_function(func, None, [], name)
    for R, bound in _ALL_LOG_INPUTS:
        expected = all_logs(R, bound)
        theta = float(angle(R))
        label = (f"all_logs(R, {bound:g}) with R a rotation by {theta:.4g} rad about "
                 f"{np.round(log(R) / theta, 4).tolist()}")
        try:
            got = func(R.copy(), bound)
        except NotImplementedError:
            return Feedback(False, f"Not yet: {name}. Not written yet: the function still "
                                   "raises NotImplementedError.")
        except Exception as err:
            return Feedback(False, f"Not yet: {name}. Calling {label} raised "
                                   f"{type(err).__name__}: {err}")
        if got is None:
            return Feedback(False, f"Not yet: {name}. {label} returned None: is the "
                                   "`return` missing?")
        a = _as_float(got)
        if a is None:
            return Feedback(False, f"Not yet: {name}. {label} returned something that is "
                                   "not an array of numbers (a list of 3-vectors is fine).")
        if a.ndim == 1 and a.shape == (3,):
            a = a[None, :]
        if a.ndim != 2 or a.shape[1] != 3:
            return Feedback(False, f"Not yet: {name}. {label} returned shape {a.shape}; "
                                   f"expected shape (m, 3), one rotation vector per row "
                                   f"(here m = {len(expected)}).")
        if not np.isfinite(a).all():
            return Feedback(False, f"Not yet: {name}. {label} returned NaN or inf.")
        if _match_rows(a, expected):
            continue
        lengths = np.sort(np.linalg.norm(a, axis=1))
        why = (f"{label} returned {len(a)} vectors of lengths "
               f"{np.round(lengths, 4).tolist()}; expected {len(expected)}, of lengths "
               f"{np.round(np.linalg.norm(expected, axis=1), 4).tolist()}.")
        forward = expected[expected @ log(R) > 0]
        if _match_rows(a, forward):
            hint = ("You have the k >= 0 ones. The k < 0 ones, (theta - 2 pi |k|) n, point "
                    "along -n and have length 2 pi |k| - theta: turning the other way round "
                    "reaches the same R.")
        elif len(a) == len(expected):
            hint = ("The count is right; check each vector: exp(phi) should equal R for "
                    "every row.")
        else:
            hint = ("The logarithms are (theta + 2 pi k) n for every integer k; keep those "
                    "with |theta + 2 pi k| < bound.")
        return Feedback(False, f"Not yet: {name}. {why}\nHint: {hint}")
    return Feedback(True, f"Correct: {name}. It finds every logarithm below the bound for "
                          f"{len(_ALL_LOG_INPUTS)} rotations.")


# --------------------------------------------------------------------------- 4.4

_PI_AXES = [
    np.array([1.0, 0.0, 0.0]),
    np.array([0.0, -1.0, 0.0]),
    np.array([-0.8, 0.6, 0.0]),
    np.array([0.0, 0.6, -0.8]),
    np.array([1.0, -2.0, 2.0]) / 3.0,      # two largest components of equal size
]


def _log_at_pi_ref(n):
    return log(_halfturn(n))


def _first_nonzero_positive(n):
    n = np.asarray(n, dtype=float)
    k = int(np.flatnonzero(np.abs(n) > 1e-12)[0])
    return np.pi * n * np.sign(n[k])


@never_raises("log_at_pi")
def check_log_at_pi(func):
    r"""Exercise 4.4: ``func(n)`` must predict ``so3lib.log(2 n n^T - I)``, the logarithm
    so3lib picks among :math:`\pm\pi n` for an exactly symmetric half-turn.

    Recognises :math:`\pi n` returned as given (ignoring the convention) and the other
    common convention, "first nonzero component positive".
    """
    name = "log_at_pi"
    fb = check_function(func, _log_at_pi_ref, [(n,) for n in _PI_AXES], name,
                        atol=1e-10, rtol=1e-10)
    if fb or _unanswered(fb):
        return fb
    hint = ("so3lib.log returns the one of +-pi n whose largest component (in absolute "
            "value; the first, if two are equally large) is positive.")
    probes = _PI_AXES + [np.array([-0.6, 0.0, 0.8]), np.array([0.6, 0.0, -0.8])]
    outs = [_try_call(func, n) for n in probes]
    if all(o is not None and o.shape == (3,) for o in outs):
        if all(np.allclose(o, np.pi * n, atol=1e-10) for o, n in zip(outs, probes)):
            hint = ("You returned pi n as given. Both +pi n and -pi n are logarithms of the "
                    "half-turn, and the matrix 2 n n^T - I does not know which n you started "
                    "from, so so3lib picks one by a rule. " + hint)
        elif all(np.allclose(o, _first_nonzero_positive(n), atol=1e-10)
                 for o, n in zip(outs, probes)):
            hint = ("You made the first nonzero component positive. That is a fine "
                    "convention, but so3lib looks at the largest component (in absolute "
                    "value; the first of equally large ones), the one the half-turn "
                    "construction divides by.")
    return Feedback(False, fb.message + "\nHint: " + hint)
