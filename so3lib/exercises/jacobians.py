r"""Checkers for the exercises of notebook 06 (derivatives of exp: the Jacobians).

==========================  ==============================================================
checker                     the exercise
==========================  ==============================================================
``check_right_jacobian``    6.1 ``right_jacobian_formula(phi)``, :math:`J_r(\varphi)` from
                            the closed form, for :math:`\varphi \ne 0`
``check_C_stable``          6.2 ``C_stable(t)``, :math:`(t - \sin t)/t^3` to 1e-12
                            relative at every ``t``, 0 included
``check_body_jacobian``     6.3 ``body_jacobian(phi, b)``, the 3x3 derivative of
                            :math:`e^{-\hat\varphi} b` with respect to :math:`\varphi`
==========================  ==============================================================

Each checker returns a :class:`so3lib.exercises.Feedback` and never raises. The function
exercises are checked through their defining property -- a centred finite difference of
:func:`so3lib.exp` -- not against a stored answer, and a message names the mistake it
recognises (the left Jacobian in place of the right one, a missing term, a cancellation)
without printing the expected value.
"""

import math

import numpy as np

from ..jacobians import C as _C_lib
from ..so3 import exp, hat
from . import _NOT_ANSWERED, Feedback, _fail, _fmt, _ok, never_raises

__all__ = ["check_C_stable", "check_body_jacobian", "check_right_jacobian"]

_H = 1e-5           # step of the centred differences: truncation ~h^2, rounding ~eps/h


def _vee(M):
    return np.array([M[2, 1] - M[1, 2], M[0, 2] - M[2, 0], M[1, 0] - M[0, 1]]) / 2


def _fd_jacobian(phi, side):
    """Column j: the rotation vector, per unit step, of moving phi along e_j, seen on the
    right (``exp(phi)^T dR``) or on the left (``dR exp(phi)^T``)."""
    R = exp(phi)
    cols = []
    for e in np.eye(3):
        dR = (exp(phi + _H * e) - exp(phi - _H * e)) / (2 * _H)
        cols.append(_vee(R.T @ dR if side == "right" else dR @ R.T))
    return np.column_stack(cols)


def _call(func, name, args, shown, shape):
    """(result as float array, None) or (None, Feedback) for one call of the learner's
    function."""
    try:
        got = func(*[np.array(x, copy=True) if isinstance(x, np.ndarray) else x
                     for x in args])
    except NotImplementedError:
        return None, _fail(name, "Not written yet: the function still raises "
                                 "NotImplementedError.")
    except Exception as err:  # noqa: BLE001 -- a learner's function may raise anything
        return None, _fail(name, f"Calling it on {shown} raised {type(err).__name__}: {err}")
    if got is None:
        return None, _fail(name, f"It returned None on {shown}: is the `return` missing?")
    try:
        arr = np.asarray(got, dtype=float)
    except (TypeError, ValueError):
        return None, _fail(name, f"On {shown} it returned a {type(got).__name__}, not a "
                                 "number or an array of numbers.")
    if arr.shape != shape:
        return None, _fail(name, f"On {shown} the result has shape {arr.shape}; expected "
                                 f"shape {shape}.")
    if not np.isfinite(arr).all():
        return None, _fail(name, f"On {shown} the result contains NaN or inf. Look for a "
                                 "division by zero.")
    return arr, None


def _start(func, name):
    if func is None or func is Ellipsis:
        return _fail(name, _NOT_ANSWERED)
    if not callable(func):
        return _fail(name, f"Expected a function, got a {type(func).__name__}.")
    return None


def _close(a, b, tol):
    return float(np.abs(a - b).max()) <= tol


# --- 6.1 the right Jacobian ----------------------------------------------------------

_PHIS_61 = [
    ("a quarter turn about z, phi = (0, 0, pi/2)", np.array([0.0, 0.0, math.pi / 2])),
    ("phi = (0.3, -0.4, 1.2)", np.array([0.3, -0.4, 1.2])),
    ("phi = (1e-3, 2e-3, -1e-3), a small angle", np.array([1e-3, 2e-3, -1e-3])),
    ("phi = (2, -1, 2), an angle of 3 rad", np.array([2.0, -1.0, 2.0])),
    ("phi = (0, 4, 3), an angle of 5 rad, beyond pi", np.array([0.0, 4.0, 3.0])),
]


def _diagnose_61(got, phi, right):
    K = hat(phi)
    theta = float(np.linalg.norm(phi))
    b = (1 - math.cos(theta)) / theta**2
    if _close(got, _fd_jacobian(phi, "left"), 1e-8):
        return ("It is the left Jacobian J_l = J_r^T: exp(phi + delta) = exp(J_l delta) "
                "exp(phi). For J_r the hat(phi) term has a minus sign.")
    if _close(got, right.T, 1e-8):
        return "It is the transpose of J_r (that is J_l): check the sign of the hat(phi) term."
    if _close(got, np.eye(3) - b * K, 1e-8):
        return "The hat(phi)^2 term, (theta - sin theta)/theta^3 hat(phi)^2, is missing."
    if _close(got, np.eye(3) - K / 2, 1e-8):
        return ("That is the first-order truncation I - hat(phi)/2; the closed form sums "
                "the whole series.")
    if _close(got, np.eye(3), 1e-8):
        return "That is the identity: J_r(phi) = I only at phi = 0."
    return None


@never_raises("right_jacobian_formula")
def check_right_jacobian(func):
    r"""Exercise 6.1: ``right_jacobian_formula(phi)`` satisfies
    :math:`e^{(\varphi + \delta)^\wedge} \approx e^{\hat\varphi} e^{(J\delta)^\wedge}`,
    column by column against a centred difference of ``exp`` (within 1e-8)."""
    name = "right_jacobian_formula"
    fb = _start(func, name)
    if fb is not None:
        return fb
    for shown, phi in _PHIS_61:
        got, fb = _call(func, name, (phi,), shown, (3, 3))
        if fb is not None:
            return fb
        right = _fd_jacobian(phi, "right")
        if not _close(got, right, 1e-8):
            diff = float(np.abs(got - right).max())
            why = (f"On {shown}, exp(phi) exp(J delta) does not match exp(phi + delta) to "
                   f"first order: your J differs from the finite-difference Jacobian by "
                   f"up to {diff:.2g}.")
            extra = _diagnose_61(got, phi, right)
            return Feedback(False, f"Not yet: {name}. {why}" + (f" {extra}" if extra else "")
                            + "\nHint: J_r = I - (1 - cos t)/t^2 hat(phi) + "
                              "(t - sin t)/t^3 hat(phi)^2 with t = |phi|.")
    return _ok(name, f"exp(phi) exp(J delta) matches exp(phi + delta) to first order on "
                     f"{len(_PHIS_61)} rotation vectors, from 2.4e-3 rad to 5 rad.")


# --- 6.2 a C without cancellation ----------------------------------------------------

_TS_62 = [1.0, 0.0, 1e-300, 1e-8, 1e-5, 1e-3, 0.1, 0.9, 1.7, 2.5, math.pi, 4.0, 10.0,
          100.0, -0.5, -1e-6]
# a log-spaced grid from 1e-3 to 0.1, both signs: where a threshold between the series
# and the written form goes wrong (either form too far from home)
_TS_62 += [float(x) for g in np.geomspace(1e-3, 0.1, 25)[1:-1] for x in (g, -g)]


def _written_62(t):
    try:
        return (t - math.sin(t)) / t**3
    except (ZeroDivisionError, OverflowError):
        return math.nan


@never_raises("C_stable")
def check_C_stable(func):
    r"""Exercise 6.2: ``C_stable(t)`` is :math:`(t - \sin t)/t^3` within 1e-12 relative
    at every ``t`` of a list from 0 through 1e-300, 1e-8, pi and 100 (negative ones too)."""
    name = "C_stable"
    fb = _start(func, name)
    if fb is not None:
        return fb
    bad = []
    for t in _TS_62:
        got, fb = _call(func, name, (t,), f"t = {t:g}", ())
        if fb is not None:
            if abs(t) < 1e-150 and ("NaN" in fb.message or "raised" in fb.message):
                return _fail(name, f"At t = {t:g} it gives 0/0 (NaN, inf or an error): "
                                   "t - sin t and t^3 are both 0 there (t^3 underflows "
                                   "below 1e-108). Use the Taylor series at small t.",
                             "C(t) = 1/6 - t^2/120 + t^4/5040 - ...")
            return fb
        ref = float(_C_lib(t))
        rel = abs(float(got) - ref) / ref
        if rel > 1e-12:
            bad.append((t, rel, float(got), ref))
    if not bad:
        return _ok(name, f"Within 1e-12 relative at all {len(_TS_62)} test angles, from 0 "
                         "to 100.")
    t, rel = bad[0][:2]
    # a wrong value equal to the written form in floats is cancellation; others are not
    small = [b for b in bad if abs(b[2] - _written_62(b[0])) <= 0.01 * abs(b[2] - b[3])]
    large = [b for b in bad if b not in small]
    where = ", ".join(f"{b[0]:g}" for b in bad[:4])
    why = f"Relative error {rel:.2g} at t = {t:g} (wrong at t = {where})."
    if any(b[0] < 0 for b in bad) and all(abs(b[0]) < 1e-7 or b[0] < 0 for b in bad) and \
            not any(b[0] > 0 for b in bad):
        extra = "Only negative t go wrong: C is even, C(-t) = C(t)."
    elif small and not large:
        extra = ("Only small t go wrong: t - sin t cancels there (at t = 1e-5 the two "
                 "agree in 10 digits). Switch to the Taylor series below a threshold.")
    elif large and not small:
        extra = ("Only larger t go wrong: is a truncated series used too far? Its error "
                 "grows like the first term left out.")
    else:
        extra = "Both small and large t go wrong."
    return _fail(name, f"{why} {extra}",
                 "Taylor 1/6 - t^2/120 + t^4/5040 - t^6/362880 below a threshold, "
                 "(t - sin t)/t^3 above it; check how many terms your threshold needs.")


# --- 6.3 the Jacobian of the residual in the body frame --------------------------------

def _cases_63():
    b = np.array([1.0, -2.0, 0.5])
    return [
        ("phi = 0 and b = (1, -2, 0.5)", (np.zeros(3), b)),
        ("phi = (0.3, -0.4, 1.2) and b = (1, -2, 0.5)", (np.array([0.3, -0.4, 1.2]), b)),
        ("phi = (2, -1, 2) and b = (0, 1, 1)", (np.array([2.0, -1.0, 2.0]),
                                               np.array([0.0, 1.0, 1.0]))),
    ]


def _fd_body(phi, b):
    """Columns: d/dphi_j of exp(phi)^T b, by centred differences."""
    return np.column_stack([(exp(phi + _H * e).T @ b - exp(phi - _H * e).T @ b) / (2 * _H)
                            for e in np.eye(3)])


def _diagnose_63(got, phi, b):
    v = hat(exp(phi).T @ b)
    jr = _fd_jacobian(phi, "right")
    if _close(got, v, 1e-7) and not _close(v, v @ jr, 1e-7):
        return ("It is hat(exp(phi)^T b) alone: J_r(phi) is missing. exp(phi + delta) is "
                "not exp(phi) exp(delta); it is exp(phi) exp(J_r(phi) delta).")
    if _close(got, -v @ jr, 1e-7):
        return ("It is off by a sign: exp(-hat(u)) c = c - u x c = c + c x u "
                "= c + hat(c) u.")
    if _close(got, v @ jr.T, 1e-7):
        return "It uses J_l = J_r^T where the perturbation is on the right: J_r belongs here."
    if _close(got, jr @ v, 1e-7):
        return "The factors are in the wrong order: hat(exp(phi)^T b) J_r(phi)."
    if _close(got, hat(exp(phi) @ b) @ jr, 1e-7):
        return "That uses exp(phi) b; the residual has exp(phi)^T b (the body frame)."
    return None


@never_raises("body_jacobian")
def check_body_jacobian(func):
    r"""Exercise 6.3: ``body_jacobian(phi, b)`` is :math:`\partial(e^{-\hat\varphi}b)/
    \partial\varphi`, the derivative of the measured direction ``b`` seen in the body
    frame, checked against a centred difference of ``exp`` (within 1e-7)."""
    name = "body_jacobian"
    fb = _start(func, name)
    if fb is not None:
        return fb
    cases = _cases_63()
    for shown, (phi, b) in cases:
        got, fb = _call(func, name, (phi, b), shown, (3, 3))
        if fb is not None:
            return fb
        ref = _fd_body(phi, b)
        if not _close(got, ref, 1e-7):
            diff = float(np.abs(got - ref).max())
            why = (f"On {shown} it differs from the finite-difference derivative of "
                   f"exp(phi)^T b by up to {diff:.2g}; your result is {_fmt(got)}.")
            extra = _diagnose_63(got, phi, b)
            return Feedback(False, f"Not yet: {name}. {why}" + (f" {extra}" if extra else "")
                            + "\nHint: exp(phi + delta)^T ~ exp(J_r delta)^T exp(phi)^T "
                              "= exp(-J_r delta) exp(phi)^T; expand to first order.")
    return _ok(name, f"It matches the derivative of exp(phi)^T b by finite differences on "
                     f"{len(cases)} cases.")
