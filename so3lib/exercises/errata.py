r"""Checkers for the exercise of the errata appendix (notebook A1).

=========================  ===============================================================
checker                    the exercise
=========================  ===============================================================
``check_wrapped_velocity`` A1.1 ``wrapped_velocity(omega, tau)``: what
                           :math:`\ln_\tau(e^{\tau\hat\omega})` really returns, predicted
                           without ``log`` (errata N15)
``check_breaking_input``   A1.2 ``breaking_input()``: a rotation and a time on which the
                           notes' logarithm fails (errata N11, N12)
=========================  ===============================================================

The checker returns a :class:`so3lib.exercises.Feedback` and never raises. It tests the
property that defines the answer, without computing it: the velocity ``v`` returned must
reach the same rotation in the same time, ``exp(v, tau) = exp(omega, tau)``, with the
principal angle, ``|v| |tau| <= pi``. It names the usual mistakes and never prints the
expected answer.
"""

import contextlib
import inspect
import math
import types

import numpy as np

from .. import so3
from ..so3 import exp
from . import Feedback, _calls_watched, _code_names

__all__ = ["check_breaking_input", "check_wrapped_velocity"]

_NOT_ANSWERED = ("No answer yet: replace the `...` (or `None`) with your answer and run the "
                 "cell again.")

_WRAP_CASES = [
    ("omega = (0, 0, 1) rad/s, tau = 1 s (less than half a turn)",
     (np.array([0.0, 0.0, 1.0]), 1.0)),
    ("omega = (0, 0, 4) rad/s, tau = 1 s (4 rad: more than half a turn)",
     (np.array([0.0, 0.0, 4.0]), 1.0)),
    ("omega = (5/3)(1, 2, 2) rad/s, tau = 1 s (5 rad about a general axis)",
     (np.array([1.0, 2.0, 2.0]) * 5.0 / 3.0, 1.0)),
    ("omega = (0.3, -0.4, 1.2) rad/s, tau = 6 s (7.8 rad: more than a full turn)",
     (np.array([0.3, -0.4, 1.2]), 6.0)),
    ("omega = (0, 0, 5.5) rad/s, tau = 2 s (11 rad: nearly two turns)",
     (np.array([0.0, 0.0, 5.5]), 2.0)),
    ("omega = (0, 0, 2) rad/s, tau = -0.5 s (a negative time)",
     (np.array([0.0, 0.0, 2.0]), -0.5)),
    ("omega = (0, 0, 0), tau = 1 s (no rotation at all)",
     (np.array([0.0, 0.0, 0.0]), 1.0)),
]

_HINT = ("phi = omega tau has angle theta = |phi|. Reduce theta modulo 2 pi to r; if r > pi, "
         "the shortest turn is 2 pi - r the other way. Divide the resulting rotation vector by "
         "tau, and treat omega = 0 separately.")


def _fail(why, hint=_HINT):
    return Feedback(False, f"Not yet: wrapped_velocity. {why}" + (f"\nHint: {hint}" if hint else ""))


def _forbidden():
    """The logarithms the exercise asks not to call: so3lib's ``log`` (however it is
    reached), SciPy's ``Rotation.as_rotvec`` and ``scipy.linalg.logm``."""
    import scipy.linalg
    from scipy.spatial.transform import Rotation
    return [(so3, "log"), (_package(), "log"), (Rotation, "as_rotvec"), (scipy.linalg, "logm")]


def _package():
    import so3lib
    return so3lib


def _calls_log(func):
    """True if the code of ``func`` names a logarithm it must not call (one of
    :func:`_forbidden`, or ``log``, ``logm`` or ``as_rotvec`` imported inside it). Calls
    that the code hides from this reading (``as_rotvec`` on a SciPy rotation, ``getattr``)
    are caught by :func:`_call_logging` while the function runs."""
    def imported(module, name):
        return (name in ("log", "logm") and module.split(".")[0] in ("so3lib", "scipy")
                or name == "as_rotvec")
    return _code_names(func, [getattr(owner, name) for owner, name in _forbidden()], imported)


def _logarithm_codes():
    """{code object: name} of every function whose call counts as calling a logarithm:
    the functions of ``so3lib.so3`` that compute one (``log``, its private kernels
    ``_log_one``, ``_log_block``, ``_near_pi``, and any later function with "log" in its
    name), SciPy's ``Rotation.as_rotvec`` and the body of ``scipy.linalg.logm``. Watching
    code objects catches a call however the function was reached: a name bound before the
    checker ran, ``globals()``, a private helper."""
    import scipy.linalg
    from scipy.spatial.transform import Rotation
    codes = {}
    for fname, f in vars(so3).items():
        if (inspect.isfunction(f) and f.__module__ == so3.__name__
                and ("log" in fname or fname == "_near_pi")):
            codes[f.__code__] = "log" if fname == "log" else f"so3lib.so3.{fname}"
    for f, name in ((Rotation.as_rotvec, "as_rotvec"), (scipy.linalg.logm, "logm")):
        code = getattr(inspect.unwrap(f), "__code__", None)
        if isinstance(code, types.CodeType):
            codes[code] = name
    return codes


@contextlib.contextmanager
def _call_logging(calls):
    """While inside, every call of a logarithm is appended to ``calls`` (and still
    answered): through its module or class (:func:`_forbidden`), or by any other road
    (its code object runs: :func:`_logarithm_codes`)."""
    saved = []
    for owner, name in _forbidden():
        orig = getattr(owner, name)

        def spy(*args, _orig=orig, _name=name, **kwargs):
            calls.append(_name)
            return _orig(*args, **kwargs)
        saved.append((owner, name, orig))
        setattr(owner, name, spy)
    try:
        with _calls_watched(_logarithm_codes().get) as seen:
            yield calls
    finally:
        calls.extend(seen)
        for owner, name, orig in reversed(saved):
            setattr(owner, name, orig)


def _judge(v, omega, tau):
    """None if ``v`` reaches exp(omega, tau) in time tau with the principal angle."""
    theta = float(np.linalg.norm(omega * tau))
    miss = float(np.abs(exp(v, tau) - exp(omega, tau)).max())
    same = miss < 1e-9
    principal = float(np.linalg.norm(v)) * abs(tau) <= np.pi + 1e-9
    if same and principal:
        return None
    if not principal and np.abs(v - omega).max() < 1e-9:   # omega itself, past half a turn
        return ("this is omega itself, the notes' claim that log undoes exp (errata N15). It "
                f"holds only while |omega| |tau| < pi; here the angle is {theta:.4g} rad, and "
                "the principal log turns at most pi, the shorter way round, which past half "
                "a turn is the other way.")
    if same:
        return (f"your velocity reaches the right rotation, but turns by "
                f"{float(np.linalg.norm(v)) * abs(tau):.4g} rad in |tau|: the principal "
                "logarithm turns by at most pi. Beyond half a turn the shorter way round is "
                "the other way, along -n, by 2 pi - r.")
    if np.allclose(exp(-np.asarray(v), tau), exp(omega, tau), atol=1e-9):
        if tau < 0:
            return "it is off by a sign (think of the sign of tau when you divide by it)."
        return ("it is off by a sign: it turns the wrong way round the axis. Past half a "
                "turn, the shorter turn is about -n, not n.")
    if miss < 1e-2:
        return (f"close, but not accurate: exp(v, tau) misses exp(omega, tau) by {miss:.1e} "
                "(the check allows 1e-9). Is a constant rounded, or a formula approximate?")
    return "exp(v, tau) with your v is not the rotation exp(omega, tau)."


def check_wrapped_velocity(func):
    r"""Exercise A1.1: ``wrapped_velocity(omega, tau)`` predicts
    :math:`\ln_\tau(e^{\tau\hat\omega})` without calling ``log``: the velocity ``v`` with
    :math:`e^{\tau\hat v} = e^{\tau\hat\omega}` and :math:`\lVert v\rVert\,|\tau| \le \pi`.
    """
    if func is None or func is Ellipsis:
        return _fail(_NOT_ANSWERED, None)
    if not callable(func):
        return _fail(f"Expected a function, got a {type(func).__name__}.", None)
    calls_log = _fail("It calls log (or another logarithm: SciPy's as_rotvec or logm): the "
                      "exercise asks you to predict what log returns from phi = omega tau "
                      "alone, without calling it.")
    if _calls_log(func):
        return calls_log
    for label, (omega, tau) in _WRAP_CASES:
        calls = []
        try:
            with _call_logging(calls):
                got = func(omega.copy(), tau)
        except NotImplementedError:
            return _fail("Not written yet: the function still raises NotImplementedError.", None)
        except Exception as err:  # noqa: BLE001 -- a checker never raises
            if calls:
                return calls_log
            return _fail(f"Calling it on {label} raised {type(err).__name__}: {err}")
        if calls:
            return calls_log
        if got is None:
            return _fail(f"It returned None on {label}: is the `return` missing?", None)
        try:
            v = np.asarray(got, dtype=float)
        except (TypeError, ValueError):
            return _fail(f"On {label} the answer is a {type(got).__name__}, not a number or "
                         "an array of numbers.")
        if v.shape != (3,):
            return _fail(f"On {label} the answer has shape {v.shape}; expected shape (3,).")
        if not np.isfinite(v).all():
            return _fail(f"On {label} the answer contains NaN or inf: a division by a zero "
                         "angle?")
        try:
            why = _judge(v, omega, tau)
        except Exception as err:  # noqa: BLE001 -- a checker never raises
            why = f"the result could not be checked ({type(err).__name__}: {err})."
        if why:
            return _fail(f"On {label}: {why}")
    return Feedback(True, f"Correct: wrapped_velocity. It predicts what log returns in "
                          f"{len(_WRAP_CASES)} cases: exp and log are inverses only below "
                          "half a turn.")


# --- A1.2: an input on which the notes' logarithm fails ---------------------------------

def _notes_ln(R, tau):
    """The notes' ln_tau as printed, with N13 corrected (omega = sigma n) and their own
    rule at sigma = 0 (omega = 0): the recipe the exercise asks the learner to break."""
    with np.errstate(all="ignore"):
        c = (np.trace(R) - 1) / 2
        sigma = np.arccos(c) / tau
        if sigma == 0:
            return np.zeros(3)
        n = np.array([R[2, 1] - R[1, 2], R[0, 2] - R[2, 0], R[1, 0] - R[0, 1]]) / (
            2 * np.sin(sigma * tau))
        return sigma * n


def _break_fail(why, hint=True):
    text = f"Not yet: breaking_input. {why}"
    if hint:
        text += ("\nHint: the notes' log takes arccos((tr R - 1) / 2) and divides by "
                 "sin(sigma tau). Where is that sine zero, or tiny? Where does arccos lose "
                 "its digits (errata N11, N12)?")
    return Feedback(False, text)


def check_breaking_input(func):
    r"""Exercise A1.2: ``breaking_input()`` returns ``(R, tau)``, a rotation and a time
    :math:`\tau \ne 0` on which the notes' logarithm (N13 corrected) fails: it returns NaN
    or inf, or an :math:`\omega` more than a relative :math:`10^{-6}` from the principal
    :math:`\ln_\tau R` (either sign at a half-turn)."""
    if func is None or func is Ellipsis:
        return _break_fail(_NOT_ANSWERED, False)
    if not callable(func):
        return _break_fail(f"Expected a function, got a {type(func).__name__}.", False)
    try:
        got = func()
    except NotImplementedError:
        return _break_fail("Not written yet: the function still raises NotImplementedError.",
                           False)
    except Exception as err:  # noqa: BLE001 -- a checker never raises
        return _break_fail(f"Calling it raised {type(err).__name__}: {err}", False)
    if got is None:
        return _break_fail("It returned None: is the `return` missing?", False)
    try:
        R, tau = got
        R = np.asarray(R, dtype=float)
        tau = float(tau)
    except (TypeError, ValueError):
        return _break_fail("Expected a pair (R, tau): a 3x3 rotation matrix and a time.", False)
    if R.shape != (3, 3) or not np.isfinite(R).all():
        return _break_fail(f"R must be a finite 3x3 matrix; got shape {R.shape}.", False)
    if not math.isfinite(tau):
        return _break_fail("tau must be a finite number of seconds.", False)
    if tau == 0:
        return _break_fail("tau = 0: the notes never exclude it (errata N10), but no "
                           "angular velocity turns anything in no time, so there is no right "
                           "answer to miss. Choose tau != 0.", False)
    orth = float(np.abs(R.T @ R - np.eye(3)).max())
    if orth > 1e-9 or np.linalg.det(R) <= 0:
        return _break_fail(f"R is not a rotation (max|R^T R - I| = {orth:.2g}, det R = "
                           f"{float(np.linalg.det(R)):.4g}): the notes' log is meant for "
                           "rotations. Build one with so3lib's exp, for example.", False)
    try:
        true = so3.log(R, tau)
    except ValueError as err:
        return _break_fail(f"so3lib's log refuses R: {err}", False)
    w = _notes_ln(R, tau)
    if not np.isfinite(w).all():
        return Feedback(True, "Correct: breaking_input. The notes' log returns NaN or inf on "
                              "your input: it divides by a zero sine, or takes arccos of a "
                              "number past 1 (errata N11, N12).")
    size = float(np.linalg.norm(true))
    err = float(np.linalg.norm(w - true))
    if size * abs(tau) > np.pi - 1e-6:                     # a half-turn: either sign is right
        err = min(err, float(np.linalg.norm(w + true)))
    if err <= 1e-6 * size:
        return _break_fail("The notes' log gets this input right (relative error below "
                           "1e-6).")
    if not np.any(w):
        return Feedback(True, "Correct: breaking_input. The notes' log returns 0 on your "
                              "input, silently: a rotation that is not the identity gets no "
                              "angular velocity at all (errata N11, N12).")
    return Feedback(True, f"Correct: breaking_input. The notes' log is off by a relative "
                          f"{err / size:.1g} on your input, without a warning: its division "
                          "by a small sine, or its arccos, has lost the digits (errata N11, "
                          "N12).")
