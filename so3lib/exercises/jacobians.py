r"""Checkers for the exercises of notebook 06 (derivatives of exp: the Jacobians).

==========================  ==============================================================
checker                     the exercise
==========================  ==============================================================
``check_ominus_jacobians``  6.1 ``ominus_jacobians(R1, R0)``, the derivatives of
                            :math:`R_1 \ominus R_0` in :math:`R_1` and in :math:`R_0`
``check_C_stable``          6.2 ``C_stable(t)``, :math:`(t - \sin t)/t^3` to 1e-12
                            relative at every ``t``, 0 included, without ``so3lib.C``
``check_body_jacobian``     6.3 ``body_jacobian(phi, b)``, the 3x3 derivative of
                            :math:`e^{-\hat\varphi} b` with respect to :math:`\varphi`
``check_gauss_newton_step`` 6.4 ``gauss_newton_step(phi, a, b)``, one Gauss-Newton step
                            (6.14) with :math:`J_r` for Wahba's problem
==========================  ==============================================================

Each checker returns a :class:`so3lib.exercises.Feedback` and never raises. The function
exercises are checked through their defining property -- 50-digit (mpmath) centred
differences of the exponential or the logarithm, to 1e-12, which differences in floats
do not reach; for ``C_stable``, :math:`(t - \sin t)/t^3` itself in 80-digit mpmath, not
the library's ``C`` -- not against a stored answer, and a message names the mistake it
recognises (a wrong side or sign, a Jacobian of exp for one of log, a missing factor, a
cancellation, a series kept too far) without printing the expected value.
"""

import contextlib
import math

import mpmath as _mp
import numpy as np

from .. import jacobians as _jacobians
from ..jacobians import C as _C_lib
from ..jacobians import ominus as _ominus
from ..jacobians import right_jacobian as _right_jacobian
from ..so3 import angle as _angle
from ..so3 import exp, hat
from ..so3 import log as _log
from . import _NOT_ANSWERED, Feedback, _code_names, _fail, _fmt, _ok, never_raises

__all__ = ["check_C_stable", "check_body_jacobian", "check_gauss_newton_step",
           "check_ominus_jacobians"]

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


# --- 6.1 the derivatives of ominus ---------------------------------------------------

#: turns |R1 (-) R0| between the named pairs, 5 % apart from 1e-3 to 3.1 rad, then up to
#: 1e-7 below a half-turn: a coefficient D that keeps a Taylor series too far, or cancels
#: (as written, 0/0 at R1 = R0 and 1 + cos near pi), is wrong somewhere along them
_TURNS_61 = tuple(float(t) for t in np.geomspace(1e-3, 3.1, 166)) + \
    tuple(math.pi - 10.0**-k for k in range(2, 8))
_AXES_61 = ((1.0, 2.0, -2.0), (-2.0, 1.0, 2.0), (2.0, 2.0, 1.0))


def _pairs_61():
    """(shown, R1, R0, phi) with R1 = R0 exp(phi): turns |phi| from 0 (R1 = R0) and
    3e-200 to pi - 1e-7."""
    R0 = exp(np.array([0.4, -0.9, 1.3]))
    phis = [("|R1 (-) R0| = 0 (R1 = R0)", np.zeros(3)),
            ("|R1 (-) R0| = 0.0024 rad", np.array([1e-3, 2e-3, -1e-3])),
            ("|R1 (-) R0| = 1.3 rad", np.array([0.3, -0.4, 1.2])),
            ("|R1 (-) R0| = 2.4 rad", np.array([-1.2, 2.0, 0.6])),
            ("|R1 (-) R0| = 3 rad, near a half-turn", np.array([2.0, -1.0, 2.0]))]
    phis += [(f"|R1 (-) R0| = {t:.10g} rad", t / 3 * np.array(_AXES_61[i % 3]))
             for i, t in enumerate(_TURNS_61)]
    pairs = [(shown, R0 @ exp(phi), R0, phi) for shown, phi in phis]
    # R0 = I keeps a tiny turn exact (next to another R0 it would round away): a D that
    # divides by theta^2 is 0/0 there though theta is not 0
    tiny = np.array([1e-200, 2e-200, -2e-200])
    return pairs + [("R0 = I and |R1 (-) R0| = 3e-200 rad", exp(tiny), np.eye(3), tiny)]


# 3x3 matrices of mpmath numbers as lists of rows: mpmath's matrix class spends most of
# its time on bookkeeping, and these checks take thousands of products.
def _mul(A, B):
    return [[A[i][0] * B[0][j] + A[i][1] * B[1][j] + A[i][2] * B[2][j] for j in range(3)]
            for i in range(3)]


def _transpose(A):
    return [[A[j][i] for j in range(3)] for i in range(3)]


def _log_mp(M):
    """Log of a 3x3 mpmath matrix (rows) near a rotation with angle in (0, pi), as a list."""
    v = [(M[2][1] - M[1][2]) / 2, (M[0][2] - M[2][0]) / 2, (M[1][0] - M[0][1]) / 2]
    s = _mp.sqrt(sum(x * x for x in v))
    theta = _mp.atan2(s, (M[0][0] + M[1][1] + M[2][2] - 1) / 2)
    return [theta / s * x for x in v]


def _exp_mp(p):
    """exp of the rotation vector p (mpmath numbers) by Rodrigues' formula, as rows."""
    one, zero = _mp.mpf(1), _mp.mpf(0)
    th = _mp.sqrt(sum(x * x for x in p))
    if th == 0:
        return [[one if i == j else zero for j in range(3)] for i in range(3)]
    K = [[zero, -p[2], p[1]], [p[2], zero, -p[0]], [-p[1], p[0], zero]]
    K2 = _mul(K, K)
    a, b = _mp.sin(th) / th, 2 * (_mp.sin(th / 2) / th)**2
    return [[(one if i == j else zero) + a * K[i][j] + b * K2[i][j] for j in range(3)]
            for i in range(3)]


def _judge_61(phi, g1, g0):
    """(ok1, ok0, diff, note) for the learner's (J1, J0) = (g1, g0): within 1e-12 of the
    derivatives that define them, and what a miss looks like. The derivatives are 50-digit
    centred differences of Log(exp(phi) exp(delta)) and of Log(exp(-delta) exp(phi)) in
    delta, rounded to floats, used here and never returned (no helper hands out an
    answer). These are
    R0^T (R1 exp(delta)) and (R0 exp(delta))^T R1 for R1 = R0 exp(phi), built from the
    exact rotation exp(phi) (the float product R0^T R1 is a rotation only to rounding,
    and near a half-turn the logarithm of the difference would swamp 1e-12)."""
    with _mp.workdps(50):
        h = _mp.mpf("1e-20")
        E_phi = _exp_mp([_mp.mpf(float(x)) for x in phi])
        out = []
        for side in (1, 0):
            cols = []
            for j in range(3):
                steps = []
                for sign in (1, -1):
                    E = _exp_mp([sign * h if i == j else _mp.mpf(0) for i in range(3)])
                    M = _mul(E_phi, E) if side == 1 else _mul(_transpose(E), E_phi)
                    steps.append(_log_mp(M))
                cols.append([float((u - d) / (2 * h)) for u, d in zip(*steps)])
            out.append(np.array(cols).T)
    j1, j0 = out
    ok1, ok0 = _close(g1, j1, 1e-12), _close(g0, j0, 1e-12)
    if ok1 and ok0:
        return True, True, 0.0, None
    diff = max(float(np.abs(g1 - j1).max()), float(np.abs(g0 - j0).max()))
    return ok1, ok0, diff, _diagnose_61(g1, g0, j1, j0, phi)


def _pair(got):
    """The learner's result as a (2, 3, 3) float array, or a reason why it is not one."""
    try:
        arr = np.asarray(got, dtype=float)
    except (TypeError, ValueError):
        return None, (f"it returned a {type(got).__name__}, not a number or an array "
                      "of numbers: a pair (J1, J0) of (3, 3) arrays")
    if arr.shape != (2, 3, 3):
        return None, (f"the result has shape {arr.shape}; expected a pair (J1, J0) of "
                      "(3, 3) arrays, shape (2, 3, 3)")
    if not np.isfinite(arr).all():
        return None, "the result contains NaN or inf; look for a division by zero"
    return arr, None


def _along_hat2(err, phi):
    """True if ``err`` is (to 1 %) a multiple of hat(phi)^2: only the coefficient D is off."""
    K2 = hat(phi) @ hat(phi)
    size = float(np.abs(err).max())
    if not K2.any():                # phi = 0: D plays no part
        return False
    c = float(np.sum(err * K2) / np.sum(K2 * K2))
    return size > 0 and float(np.abs(err - c * K2).max()) <= 0.01 * size


def _diagnose_61(g1, g0, j1, j0, phi):
    tol = 1e-8
    if _close(g1, j0, tol) and _close(g0, j1, tol):
        return "The two are swapped: return (J1, J0), the derivative in R1 first."
    notes = []
    if not _close(g1, j1, tol):
        if _close(g1, np.linalg.inv(j1), tol):
            notes.append("J1 is J_r(phi), the derivative of exp; R1 (-) R0 is a logarithm, "
                         "so its derivative is an inverse.")
        elif _close(g1, j1.T, tol):
            notes.append("J1 has the perturbation on the wrong side: R0^T (R1 exp(delta)) = "
                         "exp(phi) exp(delta) puts delta on the right.")
        elif _close(g1, -j1, tol):
            notes.append("J1 has the wrong sign: moving R1 forward moves R1 (-) R0 forward.")
    if not _close(g0, j0, tol):
        if _close(g0, -j0, tol):
            notes.append("J0 has the wrong sign: (R0 exp(delta))^T = exp(-delta) R0^T.")
        elif _close(g0, j0.T, tol):
            notes.append("J0 has the perturbation on the wrong side: (R0 exp(delta))^T R1 "
                         "= exp(-delta) exp(phi) puts it on the left.")
        elif _close(g0, np.linalg.inv(j0), tol) or _close(g0, -np.linalg.inv(j0), tol):
            notes.append("J0 uses a Jacobian of exp; R1 (-) R0 is a logarithm, so its "
                         "derivative is an inverse.")
    if not notes and all(_close(g, j, 1e-12) or _along_hat2(g - j, phi)
                         for g, j in ((g1, j1), (g0, j0))):
        notes.append("The error lies along hat(phi)^2: the coefficient D of (6.9) is off "
                     "at this angle. Is a Taylor series kept too far, or does a form "
                     "cancel? so3lib's inverse Jacobians compute it stably.")
    if not notes and _close(g1, j1, 1e-6) and _close(g0, j0, 1e-6):
        notes.append("Close (within 1e-6) but not within 1e-12: finite differences "
                     "cannot reach the last digits. Use the closed forms of this section.")
    return " ".join(notes) if notes else None


@never_raises("ominus_jacobians")
def check_ominus_jacobians(func):
    r"""Exercise 6.1: ``ominus_jacobians(R1, R0)`` returns ``(J1, J0)`` with
    :math:`\mathrm{Log}(R_0^T R_1 e^{\hat\delta}) \approx \varphi + J_1\delta` and
    :math:`\mathrm{Log}((R_0e^{\hat\delta})^T R_1) \approx \varphi + J_0\delta`,
    :math:`\varphi = R_1 \ominus R_0`, checked against 50-digit centred differences of
    those logarithms (within 1e-12) at 178 pairs: R1 = R0, a turn of 3e-200 rad, turns
    5 % apart from 1e-3 to 3.1 rad, and up to 1e-7 below a half-turn (so a coefficient
    wrong in any range, or 0/0 at R1 = R0 or where theta^2 underflows, is caught)."""
    name = "ominus_jacobians"
    fb = _start(func, name)
    if fb is not None:
        return fb
    pairs = _pairs_61()
    for shown, R1, R0, phi in pairs:
        try:
            got = func(R1.copy(), R0.copy())
        except NotImplementedError:
            return _fail(name, "Not written yet: the function still raises "
                               "NotImplementedError.")
        except Exception as err:  # noqa: BLE001 -- a learner's function may raise anything
            return _fail(name, f"Calling it on the pair with {shown} raised "
                               f"{type(err).__name__}: {err}")
        if got is None:
            return _fail(name, f"It returned None on the pair with {shown}: is the "
                               "`return` missing?")
        arr, why = _pair(got)
        if arr is None:
            if not phi.any() and "NaN" in why:
                why += (": at R1 = R0, 1/theta^2 and (1 + cos theta)/(2 theta sin theta) "
                        "are both infinite (0/0 in D). so3lib's inverse Jacobians handle "
                        "theta = 0")
            elif "NaN" in why:
                why += ("; at so small a turn theta^2 underflows to 0 (below 1.5e-162), "
                        "so a form that divides by it is 0/0 even when theta is not 0")
            return _fail(name, f"On the pair with {shown}, {why}.")
        ok1, ok0, diff, extra = _judge_61(phi, arr[0], arr[1])
        if not (ok1 and ok0):
            wrong = " and ".join(n for n, ok in (("J1", ok1), ("J0", ok0)) if not ok)
            verb = "differ" if " and " in wrong else "differs"
            why = (f"On the pair with {shown}, {wrong} {verb} from the 50-digit "
                   f"derivative of R1 (-) R0 by up to {diff:.2g} (allowed: 1e-12).")
            return Feedback(False, f"Not yet: {name}. {why}" + (f" {extra}" if extra else "")
                            + "\nHint: write R0^T (R1 exp(delta)) and (R0 exp(delta))^T R1 "
                              "as exp(phi) times a small rotation, and use the derivatives "
                              "of Log after (6.9).")
    return _ok(name, f"(J1, J0) match 50-digit differences of R1 (-) R0 within 1e-12 on "
                     f"{len(pairs)} pairs, turns from 0 (R1 = R0) to pi - 1e-7 rad.")


# --- 6.2 a C without cancellation ----------------------------------------------------

_TS_62 = [1.0, 0.0, 1e-300, 1e-8, 1e-5, 1e-3, 0.1, 0.9, 1.7, 2.5, math.pi, 4.0, 10.0,
          100.0, -0.5, -1e-6]
# a dense log-spaced grid (2.5 % apart) from 1e-3 to 4.5, both signs: where a threshold
# between the series and the written form goes wrong (either form too far from home)
_TS_62 += [float(x) for g in np.geomspace(1e-3, 4.5, 341)[1:-1] for x in (g, -g)]
# and just above round thresholds, where the written form starts
_TS_62 += [1.02 * x for x in (0.002, 0.005, 0.01, 0.02, 0.03, 0.05, 0.2, 0.3, 0.5)]


def _forbidden_62():
    """The library's own C, however the learner's code reaches it."""
    import so3lib
    return [(so3lib, "C"), (_jacobians, "C")]


_PRIVATE_62 = ("_C_scaled", "_C_SERIES")     # the library's own C, as theta^2 C and its series


def _names_C(func):
    """True if the code of ``func`` (or of a function defined inside it) names so3lib's
    ``C`` or the private pieces it is built from (``_C_scaled``, ``_C_SERIES``): a global,
    enclosing or imported name bound to one, or an attribute chain such as
    ``so3lib.jacobians.C`` that leads to one."""
    banned = [_C_lib] + [getattr(_jacobians, name) for name in _PRIVATE_62]
    return _code_names(func, banned, lambda module, name: name in ("C", *_PRIVATE_62)
                       and module.split(".")[0] == "so3lib")


@contextlib.contextmanager
def _spy_C(calls):
    """While inside, a call of ``C`` through ``so3lib`` or ``so3lib.jacobians`` is
    appended to ``calls`` (and still answered)."""
    saved = []
    for owner, attr in _forbidden_62():
        orig = getattr(owner, attr)

        def spy(*args, _orig=orig, **kwargs):
            calls.append("C")
            return _orig(*args, **kwargs)
        saved.append((owner, attr, orig))
        setattr(owner, attr, spy)
    try:
        yield calls
    finally:
        for owner, attr, orig in reversed(saved):
            setattr(owner, attr, orig)


def _judge_62(t, got):
    """(relative error, like the written form) of the learner's C(t) = GOT, from the
    defining property t^3 C = t - sin t in 80-digit mpmath (the cancellation costs at most
    40 of the 80 digits for |t| >= 1e-20; below, C = 1/6, its limit, to within t^2/20 <
    1e-41 relative). The value of C is used here and never returned."""
    t = abs(float(t))
    if t < 1e-20:
        ref = 1 / 6
    else:
        with _mp.workdps(80):
            x = _mp.mpf(t)
            ref = float((x - _mp.sin(x)) / x**3)
    rel = abs(float(got) - ref) / ref
    return rel, abs(float(got) - _written_62(t)) <= 0.01 * abs(float(got) - ref)


def _written_62(t):
    try:
        return (t - math.sin(t)) / t**3
    except (ZeroDivisionError, OverflowError):
        return math.nan


@never_raises("C_stable")
def check_C_stable(func):
    r"""Exercise 6.2: ``C_stable(t)`` is :math:`(t - \sin t)/t^3` within 1e-12 relative
    at every ``t`` of a list from 0 through 1e-300, 1e-8, pi and 100 (negative ones too),
    without calling so3lib's ``C`` (read from the code, and watched while it runs)."""
    name = "C_stable"
    fb = _start(func, name)
    if fb is not None:
        return fb
    if func is _C_lib or _names_C(func):
        return _fail(name, "It calls so3lib's C (or reads the series inside it), which the "
                           "exercise asks you not to use: write the computation yourself.")
    bad, calls = [], []
    for t in _TS_62:
        with _spy_C(calls):
            got, fb = _call(func, name, (t,), f"t = {t:g}", ())
        if calls:
            return _fail(name, "It calls so3lib's C, which the exercise asks you not to "
                               "use: write the computation yourself.")
        if fb is not None:
            if abs(t) < 1e-150 and ("NaN" in fb.message or "raised" in fb.message):
                return _fail(name, f"At t = {t:g} it gives 0/0 (NaN, inf or an error): "
                                   "t - sin t and t^3 are both 0 there (t^3 underflows "
                                   "below 1e-108). Use the Taylor series at small t.",
                             "C(t) = 1/6 - t^2/120 + t^4/5040 - ...")
            return fb
        rel, like_written = _judge_62(t, got)
        if rel > 1e-12:
            bad.append((t, rel, like_written))
    if not bad:
        return _ok(name, f"Within 1e-12 relative at all {len(_TS_62)} test angles, from 0 "
                         "to 100.")
    t, rel = bad[0][:2]
    # a wrong value equal to the written form in floats is cancellation; others are not
    small = [b for b in bad if b[2]]
    # wrong below 0.01 but not as the written form is: too short a series, or t lost
    tiny = [b for b in bad if b not in small and abs(b[0]) < 0.01]
    large = [b for b in bad if b not in small and b not in tiny]
    # a series that is both too short and used from below 0.01 up past it is one fault,
    # a truncation error growing with t: not "both small and large t"
    if tiny and large:
        large, tiny = large + tiny, []
    # one or two points can match the written form by luck of rounding: go by the most
    if len(small) + len(tiny) < 0.1 * len(bad):
        small, tiny = [], []
    elif len(large) < 0.1 * len(bad):
        large = []
    where = ", ".join(f"{b[0]:g}" for b in bad[:4])
    why = f"Relative error {rel:.2g} at t = {t:g} (wrong at t = {where})."
    if any(b[0] < 0 for b in bad) and all(abs(b[0]) < 1e-7 or b[0] < 0 for b in bad) and \
            not any(b[0] > 0 for b in bad):
        extra = "Only negative t go wrong: C is even, C(-t) = C(t)."
    elif tiny and not small and not large:
        extra = ("Only small t go wrong (below 0.01), and not as the written form does: "
                 "is a series cut too short there, or is t lost (t^3 underflows below "
                 "1e-108; are there enough digits)?")
    elif (small or tiny) and not large:
        extra = ("Only small t go wrong: t - sin t cancels there (at t = 1e-5 the two "
                 "agree in 10 digits). Switch to the Taylor series below a threshold.")
    elif large and not small and not tiny:
        extra = ("Only larger t go wrong: is a truncated series used too far, or cut too "
                 "short? Its error grows like the first term left out.")
    else:
        extra = "Both small and large t go wrong."
    return _fail(name, f"{why} {extra}",
                 "the Taylor series of C below a threshold, (t - sin t)/t^3 above it. "
                 "At the threshold the first term left out must be below 1e-12 of C; "
                 "above it the written form's relative error is about 6 eps/t^2.")


# --- 6.3 the Jacobian of the residual in the body frame --------------------------------

#: turns 5 % apart from 1e-4 to 3.1 rad: B and C kept as a Taylor series too far (or
#: taken as 1/2 and 1/6) are wrong somewhere along them
_TURNS_63 = tuple(float(t) for t in np.geomspace(1e-4, 3.1, 213))
#: and below 1e-4, a turn every half decade down to 1e-9, then 1e-200: the written B and
#: C, mended only at phi = 0 or below 1e-8, are off by more than 1e-12 there (the
#: rounding of cos theta divided by theta^2, about eps/theta; 0/0 where theta^2
#: underflows)
_TINY_63 = (1e-200,) + tuple(float(t) for t in np.geomspace(1e-9, 10**-4.5, 10))


def _cases_63():
    b = np.array([1.0, -2.0, 0.5])
    return [
        ("phi = 0 and b = (1, -2, 0.5)", (np.zeros(3), b)),
        ("phi = (0.01, 0.02, -0.02) and b = (1, -2, 0.5)", (np.array([0.01, 0.02, -0.02]), b)),
        ("phi = (0.1, -0.2, 0.2) and b = (1, -2, 0.5)", (np.array([0.1, -0.2, 0.2]), b)),
        ("phi = (0.2, 0.4, -0.4) and b = (0, 1, 1)", (np.array([0.2, 0.4, -0.4]),
                                                     np.array([0.0, 1.0, 1.0]))),
        ("phi = (0.3, -0.4, 1.2) and b = (1, -2, 0.5)", (np.array([0.3, -0.4, 1.2]), b)),
        ("phi = (2, -1, 2) and b = (0, 1, 1)", (np.array([2.0, -1.0, 2.0]),
                                               np.array([0.0, 1.0, 1.0]))),
    ] + [(f"|phi| = {t:.10g} rad along {_AXES_61[i % 3]} / 3 and b = (1, -2, 0.5)",
          (t / 3 * np.array(_AXES_61[i % 3]), b))
         for i, t in enumerate(_TINY_63 + _TURNS_63)]


def _judge_63(phi, b, got):
    """(ok, diff, note) for the learner's derivative GOT of exp(phi)^T b: within 1e-12 of
    its columns d/dphi_j by 50-digit centred differences (used here, never returned)."""
    with _mp.workdps(50):
        h = _mp.mpf("1e-20")
        p, v = [_mp.mpf(float(x)) for x in phi], [_mp.mpf(float(x)) for x in b]
        cols = []
        for j in range(3):
            up = _exp_mp([x + (h if i == j else 0) for i, x in enumerate(p)])
            down = _exp_mp([x - (h if i == j else 0) for i, x in enumerate(p)])
            # (up^T v - down^T v) / 2h, one component k at a time
            cols.append([float(sum((up[i][k] - down[i][k]) * v[i] for i in range(3)) / (2 * h))
                         for k in range(3)])
    ref = np.array(cols).T
    if _close(got, ref, 1e-12):
        return True, 0.0, None
    return False, float(np.abs(got - ref).max()), _diagnose_63(got, phi, b, ref)


def _diagnose_63(got, phi, b, ref):
    v = hat(exp(phi).T @ b)
    jr = _fd_jacobian(phi, "right")
    if _close(got, ref, 1e-6):
        return ("Close (within 1e-6) but not within 1e-12: finite differences cannot reach "
                "the last digits, nor can coefficients B, C kept as a Taylor series too far "
                "(or written in a form that cancels). Expand exp(phi + delta)^T b to first "
                "order, with a stable J_r.")
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
    frame, checked against 50-digit centred differences of the exponential (within
    1e-12, which differences in floats do not reach) at phi = 0, turns of 1e-200 and
    half a decade apart from 1e-9 to 1e-4.5, and turns 5 % apart from 1e-4 to 3.1 rad
    (230 cases)."""
    name = "body_jacobian"
    fb = _start(func, name)
    if fb is not None:
        return fb
    cases = _cases_63()
    for shown, (phi, b) in cases:
        got, fb = _call(func, name, (phi, b), shown, (3, 3))
        if fb is not None:
            return fb
        ok, diff, extra = _judge_63(phi, b, got)
        if not ok:
            why = (f"On {shown} it differs from the 50-digit derivative of exp(phi)^T b "
                   f"by up to {diff:.2g} (allowed: 1e-12); your result is {_fmt(got)}.")
            return Feedback(False, f"Not yet: {name}. {why}" + (f" {extra}" if extra else "")
                            + "\nHint: exp(phi + delta)^T ~ exp(J_r delta)^T exp(phi)^T "
                              "= exp(-J_r delta) exp(phi)^T; expand to first order.")
    return _ok(name, f"It matches 50-digit differences of exp(phi)^T b within 1e-12 on "
                     f"{len(cases)} cases.")


# --- 6.4 capstone: one Gauss-Newton step on SO(3) --------------------------------------

#: Wahba problems (turn of the answer, its axis): 1 rad, and three beyond 2.33 rad, where
#: the step without J_r is repelled by the answer (notebook 06, section 7)
_PROBLEMS_64 = ((1.0, (0.0, 1.0, 1.0)), (2.5, (1.0, 0.0, 1.0)), (2.8, (1.0, 2.0, -2.0)),
                (3.0, (-2.0, 1.0, 2.0)))
_STEPS_64 = 12      # Gauss-Newton from phi = 0: with J_r each run is at rounding level by 10


def _wahba_64(theta, axis):
    """(a, b, R_star): ten directions b in the world, a = R^T b + noise 1e-3 measured in
    the body, and the least-squares rotation R_star from one SVD (Kabsch, (6.15))."""
    rng = np.random.default_rng(64)
    n = np.array(axis) / np.linalg.norm(axis)
    b = rng.standard_normal((10, 3))
    a = b @ exp(theta * n) + 1e-3 * rng.standard_normal((10, 3))
    U, _, Vt = np.linalg.svd(b.T @ a)
    return a, b, U @ np.diag([1.0, 1.0, np.linalg.det(U @ Vt)]) @ Vt


def _residual_64(phi, a, b):
    return (a @ exp(phi).T - b).ravel()


def _solves_normal_equations(J, r, d, tol=1e-6):
    """True if ``d`` minimises |r + J d| to within ``tol`` of the size of a step:
    |J^T (r + J d)| small against |J^T J| (|d| + 1e-3)."""
    lhs = float(np.linalg.norm(J.T @ (r + J @ d)))
    return lhs <= tol * float(np.linalg.norm(J.T @ J, 2)) * (float(np.linalg.norm(d)) + 1e-3)


def _diagnose_64(phi, got, a, b):
    """What the learner's step ``got`` (from ``phi``) is, if it is a known slip."""
    R = exp(phi)
    r = _residual_64(phi, a, b)
    J_noJr = np.vstack([-R @ hat(x) for x in a])            # derivative at delta = 0
    J_Jr = J_noJr @ _right_jacobian(phi)
    if _solves_normal_equations(J_noJr, r, got - phi, 1e-8):
        return ("The step solves the normal equations with -exp(phi) hat(a_i) alone: J_r(phi) "
                "is missing from (6.13). Added to phi, that step is J_r Delta too short or "
                "turned, and near a turn of the answer above 2.33 rad it is repelled.")
    if _solves_normal_equations(J_Jr, r, phi - got, 1e-8):
        return ("The step has the wrong sign (or the Jacobian has: the derivative of "
                "exp(phi) a is -exp(phi) hat(a) J_r(phi)). Delta = -(J^T J)^-1 J^T r.")
    if _solves_normal_equations(J_Jr, r, got, 1e-8):
        return "It returned the step Delta itself; return the new phi, phi + Delta."
    with contextlib.suppress(ValueError):
        if _solves_normal_equations(J_noJr, r, _ominus(exp(got), R), 1e-8):
            return ("That is the step R (+) Delta of section 7, which needs no J_r; this "
                    "exercise asks for phi + Delta with the Jacobian (6.13), J_r included.")
    J_Jl = J_noJr @ _right_jacobian(phi).T
    if _solves_normal_equations(J_Jl, r, got - phi, 1e-8):
        return ("It uses J_l = J_r^T: the perturbation of (6.5) is on the right, "
                "exp(phi + d) ~ exp(phi) exp(J_r d), so J_r belongs here.")
    return None


@never_raises("gauss_newton_step")
def check_gauss_newton_step(func):
    r"""Exercise 6.4 (capstone): ``gauss_newton_step(phi, a, b)`` returns
    :math:`\varphi + \Delta`, with :math:`\Delta` the Gauss-Newton step (6.14) for the
    residuals :math:`r_i = e^{\hat\varphi}a_i - b_i` of Wahba's problem (6.12).

    Checked by its defining property, not against a stored step: from three points of
    each of four problems (answers turned by 1, 2.5, 2.8 and 3 rad), :math:`\Delta`
    solves the normal equations :math:`J^T(r + J\Delta) = 0` with :math:`J` from centred
    differences of the residuals in floats (to 1e-6 of a step); then twelve steps from
    :math:`\varphi = 0` reach the least-squares rotation (one SVD, Kabsch's (6.15)) to
    1e-9 rad on every problem, where the step without :math:`J_r` is repelled."""
    name = "gauss_newton_step"
    fb = _start(func, name)
    if fb is not None:
        return fb
    h = 1e-6            # centred differences of r in floats: error ~ h^2 + eps/h ~ 1e-10
    for theta, axis in _PROBLEMS_64:
        a, b, R_star = _wahba_64(theta, axis)
        phi_star = _log(R_star)
        for label, phi in (("phi = 0", np.zeros(3)), ("phi halfway to the answer", phi_star / 2),
                           ("phi near the answer", phi_star + np.array([0.02, -0.01, 0.03]))):
            shown = f"{label} (on the problem whose answer turns by {theta:g} rad)"
            got, fb = _call(func, name, (phi, a, b), shown, (3,))
            if fb is not None:
                return fb
            r = _residual_64(phi, a, b)
            J = np.column_stack([(_residual_64(phi + h * e, a, b)
                                  - _residual_64(phi - h * e, a, b)) / (2 * h) for e in np.eye(3)])
            if not _solves_normal_equations(J, r, got - phi):
                extra = _diagnose_64(phi, got, a, b)
                return _fail(name, f"From {shown}, the step got - phi does not minimise the "
                                   "linearised |r + J Delta|^2 (the normal equations "
                                   "J^T (r + J Delta) = 0 fail)."
                                   + (f" {extra}" if extra else ""),
                             "r stacks exp(phi) a_i - b_i (3N numbers), J stacks (6.13), "
                             "-exp(phi) hat(a_i) J_r(phi) (3N x 3); Delta = -(J^T J)^-1 J^T r.")
    for theta, axis in _PROBLEMS_64:
        a, b, R_star = _wahba_64(theta, axis)
        phi = np.zeros(3)
        for _ in range(_STEPS_64):
            phi, fb = _call(func, name, (phi, a, b), "one of its own iterates", (3,))
            if fb is not None:
                return fb
        if float(_angle(R_star.T @ exp(phi))) > 1e-9:
            return _fail(name, f"Each step solves the normal equations, but {_STEPS_64} steps "
                               f"from phi = 0 on the problem whose answer turns by {theta:g} "
                               "rad end more than 1e-9 rad from the least-squares rotation. "
                               "Is the step computed at a fixed phi rather than at the phi "
                               "it is given?")
    return _ok(name, f"Each step solves the normal equations of (6.14) from 12 points of "
                     f"four problems, and {_STEPS_64} steps from phi = 0 reach the least-"
                     "squares rotation within 1e-9 rad, also where the answer turns by 2.5 to "
                     "3 rad and the step without J_r is repelled.")
