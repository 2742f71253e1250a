"""The checker of the errata appendix A1 (so3lib.exercises.errata): right answers pass,
wrong ones get a message that names the mistake, no message gives the answer away, and
nothing raises."""

import inspect
import re

import numpy as np
import pytest

from so3lib import exp, log
from so3lib.exercises import Feedback, errata
from so3lib.exercises.errata import check_breaking_input, check_wrapped_velocity


def _assert_not_yet(fb, says):
    assert isinstance(fb, Feedback) and not fb
    text = repr(fb)
    assert text.startswith("Not yet: wrapped_velocity"), text
    assert re.search(says, text), text


def _wrapped(omega, tau):
    phi = np.asarray(omega, float) * tau
    theta = np.linalg.norm(phi)
    if theta == 0:
        return np.zeros(3)
    r = theta % (2 * np.pi)
    scale = r / theta if r <= np.pi else -(2 * np.pi - r) / theta
    return scale * phi / tau


def _no_zero_case(omega, tau):
    phi = np.asarray(omega, float) * tau
    theta = np.linalg.norm(phi)
    r = theta % (2 * np.pi)
    scale = r / theta if r <= np.pi else -(2 * np.pi - r) / theta
    return scale * phi / tau


def _pi_rounded(omega, tau):
    # pi typed as 3.14: right in form, a thousandth off past half a turn
    phi = np.asarray(omega, float) * tau
    theta = np.linalg.norm(phi)
    if theta == 0:
        return np.zeros(3)
    r = theta % 6.28
    scale = r / theta if r <= 3.14 else -(6.28 - r) / theta
    return scale * phi / tau


def _raise(exc):
    def f(omega, tau):
        raise exc
    return f


def test_right_answers_pass():
    fb = check_wrapped_velocity(_wrapped)
    assert fb and repr(fb).startswith("Correct: wrapped_velocity")


def test_calling_log_is_noticed():
    # The exercise forbids calling log: the library's way, directly, through the package or
    # from a helper defined inside, is refused with a message that says so.
    import so3lib

    def nested(w, t):
        def inner(R):
            return log(R, t)
        return inner(exp(w, t))

    for student in (lambda w, t: log(exp(w, t), t), lambda w, t: so3lib.log(exp(w, t), t),
                    nested):
        _assert_not_yet(check_wrapped_velocity(student), "calls log")


def test_calling_log_by_any_road_is_noticed():
    # A local import, an attribute chain through so3lib.so3, a name built at run time, and
    # SciPy's logarithms (Rotation.as_rotvec, logm) are refused too.
    import scipy.linalg
    from scipy.spatial.transform import Rotation

    import so3lib

    def local_import(w, t):
        from so3lib import exp, log
        return log(exp(w, t), t)

    def module_alias(w, t):
        import so3lib.so3 as m
        return m.log(exp(w, t), t)

    def built_name(w, t):
        return getattr(so3lib, "lo" + "g")(exp(w, t), t)

    for student in (local_import, module_alias, built_name,
                    lambda w, t: so3lib.so3.log(exp(w, t), t),
                    lambda w, t: Rotation.from_matrix(exp(w, t)).as_rotvec() / t,
                    lambda w, t: so3lib.vee(scipy.linalg.logm(exp(w, t)).real) / t):
        _assert_not_yet(check_wrapped_velocity(student), "calls log")
    # the library and SciPy are left as they were
    assert so3lib.log is so3lib.so3.log and so3lib.so3.log.__name__ == "log"
    assert Rotation.as_rotvec.__name__ == "as_rotvec" and scipy.linalg.logm.__name__ == "logm"
    # np.log, or a local variable named log, is not so3lib's log
    assert check_wrapped_velocity(lambda w, t, log=None: _wrapped(w, t))


def test_calling_a_logarithm_the_reading_cannot_see_is_noticed():
    # so3lib's private kernel, and log reached through globals() (a binding the checker
    # cannot replace), are caught while the function runs; the watch is removed after.
    import sys

    import so3lib.so3 as so3

    def private(w, t):
        return np.array(so3._log_one(exp(w, t).ravel().tolist(), t))

    def through_globals(w, t):
        return globals()["lo" + "g"](exp(w, t), t)

    for student in (private, through_globals):
        _assert_not_yet(check_wrapped_velocity(student), "calls log")
    assert sys.getprofile() is None
    # exp, angle and SciPy's expm are no logarithms: an answer that uses them passes
    from scipy.linalg import expm

    from so3lib import angle, hat

    def with_exp_and_angle(w, t):
        angle(expm(hat(np.asarray(w, float) * t)))
        return _wrapped(w, t)
    assert check_wrapped_velocity(with_exp_and_angle)


def test_sign_message_fits_the_mistake():
    # Past half a turn about +n instead of -n (tau > 0): the message speaks of the axis,
    # not of tau; dividing by |tau| (tau < 0): it speaks of tau.
    def wrong_way(w, t):
        phi = np.asarray(w, float) * t
        theta = np.linalg.norm(phi)
        if theta == 0:
            return np.zeros(3)
        r = theta % (2 * np.pi)
        return (r if r <= np.pi else 2 * np.pi - r) / theta * phi / t

    fb = check_wrapped_velocity(wrong_way)
    _assert_not_yet(fb, "off by a sign: it turns the wrong way")
    assert "sign of tau" not in repr(fb)
    _assert_not_yet(check_wrapped_velocity(lambda w, t: _wrapped(w, t) * t / abs(t)),
                    "sign of tau")


@pytest.mark.parametrize("student, says", [
    (None, "No answer yet"),
    (..., "No answer yet"),
    ("w", "Expected a function"),
    (_raise(NotImplementedError()), "Not written yet"),
    (_raise(ZeroDivisionError("division by zero")), "raised ZeroDivisionError"),
    (lambda w, t: None, "returned None"),
    (lambda w, t: np.zeros((3, 3)), r"has shape \(3, 3\); expected shape \(3,\)"),
    (lambda w, t: "x", "not a number"),
    (lambda w, t: np.full(3, np.nan), "NaN or inf"),
    (lambda w, t: w, "notes' claim.*other way"),
    (lambda w, t: (np.linalg.norm(w * t) % (2 * np.pi)) / np.linalg.norm(w * t) * w
     if np.linalg.norm(w * t) > 0 else np.zeros(3), "at most pi"),
    (lambda w, t: -_wrapped(w, t) if t < 0 else _wrapped(w, t), "off by a sign"),
    (lambda w, t: 0.5 * _wrapped(w, t), "is not the rotation"),
    (lambda w, t: (1 + 1e-6) * _wrapped(w, t), r"close, but not accurate.*misses exp\(omega, tau\) by \d\.\de-07"),
    (_pi_rounded, "close, but not accurate"),
])
def test_wrong_answers_get_a_message(student, says):
    with np.errstate(invalid="ignore", divide="ignore"):
        fb = check_wrapped_velocity(student)
    _assert_not_yet(fb, says)


def test_an_inaccurate_answer_is_not_called_omega_itself():
    # Below half a turn omega is the right answer: an answer near it but not accurate
    # must not be told it is "omega itself" (the message about the notes' N15 claim).
    fb = check_wrapped_velocity(lambda w, t: (1 + 1e-6) * _wrapped(w, t))
    _assert_not_yet(fb, "omega = \\(0, 0, 1\\)")
    assert "omega itself" not in repr(fb) and "notes' claim" not in repr(fb)


def test_zero_rotation_nan_is_reported():
    with np.errstate(invalid="ignore", divide="ignore"):
        fb = check_wrapped_velocity(_no_zero_case)
    _assert_not_yet(fb, "NaN or inf")


def test_messages_never_print_the_expected_value():
    # A wrong answer on the 4-rad case: the right answer there is (0, 0, 4 - 2 pi).
    fb = check_wrapped_velocity(lambda w, t: w)
    assert "2.28" not in repr(fb) and "-2.283" not in repr(fb) and "expected" not in repr(fb).lower()


def test_the_module_holds_no_answer():
    # Only the checker is public, and no function of the module returns a velocity.
    public = [n for n, f in inspect.getmembers(errata, inspect.isfunction)
              if f.__module__ == errata.__name__]
    assert sorted(public) == ["_break_fail", "_call_logging", "_calls_log", "_fail",
                              "_forbidden", "_judge", "_logarithm_codes", "_notes_ln",
                              "_package", "check_breaking_input", "check_wrapped_velocity"]
    assert errata.__all__ == ["check_breaking_input", "check_wrapped_velocity"]


# --- A1.2: an input that breaks the notes' logarithm -------------------------------------

_N = np.array([1.0, 2.0, 2.0]) / 3.0


def _raise_no_arg(exc):
    def g():
        raise exc
    return g


@pytest.mark.parametrize("inputs, says", [
    ((np.diag([1.0, -1.0, -1.0]), 1.0), "returns 0 on your input, silently"),   # a half-turn
    ((exp([1e-9, 0.0, 0.0]), 1.0), "returns 0 on your input, silently"),        # arccos -> 0
    ((exp((np.pi - 1e-12) * _N), 2.0), "off by a relative"),                      # near pi
    ((exp((np.pi - 1e-7) * _N), -1.0), "off by a relative"),
])
def test_breaking_inputs_pass_and_say_how_the_notes_fail(inputs, says):
    fb = check_breaking_input(lambda: inputs)
    assert fb and repr(fb).startswith("Correct: breaking_input"), repr(fb)
    assert re.search(says, repr(fb)), repr(fb)


def test_an_arccos_past_one_is_a_nan():
    E = exp(np.random.default_rng(0).standard_normal((2000, 3)))
    P = E @ np.swapaxes(E, -1, -2)                    # rotations to rounding, some c > 1
    c = (np.trace(P, axis1=1, axis2=2) - 1) / 2
    assert c.max() > 1
    fb = check_breaking_input(lambda: (P[np.argmax(c)], 1.0))
    assert fb and "NaN or inf" in repr(fb)


def _assert_break_not_yet(fb, says):
    assert isinstance(fb, Feedback) and not fb
    assert repr(fb).startswith("Not yet: breaking_input"), repr(fb)
    assert re.search(says, repr(fb)), repr(fb)


@pytest.mark.parametrize("student, says", [
    (None, "No answer yet"),
    (7, "Expected a function"),
    (_raise_no_arg(NotImplementedError()), "Not written yet"),
    (_raise_no_arg(ValueError("boom")), "raised ValueError: boom"),
    (lambda: None, "returned None"),
    (lambda: 3, r"Expected a pair \(R, tau\)"),
    (lambda: (np.eye(2), 1.0), "finite 3x3 matrix"),
    (lambda: (exp([0.3, 0.2, 0.1]), 0.0), "tau = 0.*errata N10"),
    (lambda: (exp([0.3, 0.2, 0.1]), float("nan")), "finite number"),
    (lambda: (2 * np.eye(3), 1.0), "not a rotation"),
    (lambda: (-np.eye(3), 1.0), "not a rotation"),
    (lambda: (exp([0.3, 0.2, 0.1]), 1.0), "gets this input right"),
    (lambda: (exp([0.0, 0.0, 3.0]), -2.0), "gets this input right"),   # tau < 0 is fine
    (lambda: (np.eye(3), 1.0), "gets this input right"),               # their sigma = 0 rule
])
def test_inputs_the_notes_handle_are_not_accepted(student, says):
    _assert_break_not_yet(check_breaking_input(student), says)
