r"""Checkers for the exercises of notebook 05 (applications of exp and log).

=========================  ===============================================================
checker                    the exercise
=========================  ===============================================================
``check_keyframes``        5.1 ``keyframe_path(Rs, times, t)``: the orientation at time
                           ``t`` on the path through keyframes ``Rs`` at ``times``, one
                           geodesic (5.2) per segment
``check_steps_needed``     5.2 ``steps_needed(speed, T, tol)``: the fewest Euler steps
                           (5.7) that keep the body within a factor ``1 + tol`` of its size
``check_velocity_jump``    5.3 ``velocity_jump(Rs, times)``: how much the body angular
                           velocity jumps at the middle of three keyframes
``check_smooth_path``      5.4 ``smooth_path(Rs, times, ws, t)``: a path through the
                           keyframes whose body angular velocity is ``ws[i]`` on both sides
                           of keyframe ``i`` (a geodesic cubic, by De Casteljau): no kink
``check_rotation_mean``    5.5 ``rotation_mean(Rs, weights)``, the weighted geodesic
                           (Karcher) mean of rotations
=========================  ===============================================================

Each checker returns a :class:`so3lib.exercises.Feedback` and never raises. It tests the
property that defines a right answer (the path passes through every keyframe and turns at
a constant rate about one axis between two of them; the weighted attitude errors about
the mean sum to zero), names the usual mistakes (the entrywise blend, one geodesic for the
whole path, times taken as equally spaced, the relative rotation on the wrong side or
measured in the wrong frame, the projected blend, the chordal mean) and never prints the
expected answer. The graded answers live in the notebook's hidden tests, not here.
"""

import numpy as np

from ..so3 import exp, log
from ..validation import rotation_defects
from . import Feedback

__all__ = ["check_keyframes", "check_rotation_mean", "check_smooth_path", "check_steps_needed",
           "check_velocity_jump"]

_NOT_ANSWERED = ("No answer yet: replace the `...` (or `None`) with your answer and run the "
                 "cell again.")


def _ok(name, extra=""):
    return Feedback(True, f"Correct: {name}.{(' ' + extra) if extra else ''}")


def _fail(name, why, hint=None):
    return Feedback(False, f"Not yet: {name}. {why}" + (f"\nHint: {hint}" if hint else ""))


def _as_array(got, shape):
    """(array, None) for a finite float array of ``shape``, else (None, the reason)."""
    try:
        arr = np.asarray(got, dtype=float)
    except (TypeError, ValueError):
        return None, f"The answer is a {type(got).__name__}, not a number or an array of numbers."
    if arr.shape != shape:
        return None, f"The answer has shape {arr.shape}; expected shape {shape}."
    if not np.isfinite(arr).all():
        return None, ("The answer contains NaN or inf. Look for a division by zero (a zero "
                      "angle, a zero time step?).")
    return arr, None


def _not_a_rotation(M):
    """A sentence if ``M`` (finite, 3x3) is not a rotation, else None."""
    orth, det = rotation_defects(M)
    if orth > 1e-6 or abs(det - 1.0) > 1e-6:
        return (f"It is not a rotation: for your matrix M, max|M^T M - I| = {float(orth):.2g} "
                f"and det M = {float(det):.4g}.")
    return None


def _close(a, b, atol):
    with np.errstate(all="ignore"):
        return np.shape(a) == np.shape(b) and bool(np.allclose(a, b, atol=atol, rtol=0))


def _run(func, cases, name, shape, judge, hint):
    """Call ``func`` on each ``(label, args)`` case; ``judge(got, args)`` returns None when
    the result has the defining property, else a sentence saying what is wrong."""
    if func is None or func is Ellipsis:
        return _fail(name, _NOT_ANSWERED)
    if not callable(func):
        return _fail(name, f"Expected a function, got a {type(func).__name__}.")
    for label, args in cases:
        try:
            got = func(*[np.array(a, copy=True) if isinstance(a, np.ndarray) else a
                         for a in args])
        except NotImplementedError:
            return _fail(name, "Not written yet: the function still raises NotImplementedError.")
        except Exception as err:  # noqa: BLE001 -- a checker never raises
            return _fail(name, f"Calling it on {label} raised {type(err).__name__}: {err}", hint)
        if got is None:
            return _fail(name, f"It returned None on {label}: is the `return` missing?")
        arr, why = _as_array(got, shape)
        if why is None:
            try:
                why = judge(arr, args)
            except Exception as err:  # noqa: BLE001 -- a checker never raises
                why = f"The result could not be checked ({type(err).__name__}: {err})."
        if why:
            return _fail(name, f"On {label}: {why}", hint)
    return _ok(name, f"It has the defining property on {len(cases)} test inputs.")


# --- 5.1 a path through keyframes ------------------------------------------------------

def _keyframe_cases():
    Rz = exp([0.0, 0.0, np.pi / 2])
    Rzx = Rz @ exp([np.pi / 2, 0.0, 0.0])
    three = np.stack([np.eye(3), Rz, Rzx])
    gen = np.stack([exp([0.3, -0.5, 0.2]), exp([-0.4, 0.9, 1.1]), exp([1.0, 0.6, -0.5]),
                    exp([0.2, 0.1, 0.3])])
    uneven = np.array([0.0, 1.0, 3.0])
    return [
        ("three quarter-turn keyframes at times (0, 1, 2), t = 0.5",
         (three, np.array([0.0, 1.0, 2.0]), 0.5)),
        ("the same keyframes, t = 1 (the middle keyframe)", (three, np.array([0.0, 1.0, 2.0]), 1.0)),
        ("the same keyframes, t = 1.5", (three, np.array([0.0, 1.0, 2.0]), 1.5)),
        ("the same keyframes at uneven times (0, 1, 3), t = 2", (three, uneven, 2.0)),
        ("the same keyframes at uneven times (0, 1, 3), t = 3 (the last keyframe)",
         (three, uneven, 3.0)),
        ("four general keyframes at times (0, 0.5, 2, 2.5), t = 0", (gen, np.array([0.0, 0.5, 2.0, 2.5]), 0.0)),
        ("four general keyframes at times (0, 0.5, 2, 2.5), t = 1.1",
         (gen, np.array([0.0, 0.5, 2.0, 2.5]), 1.1)),
        ("four general keyframes at times (0, 0.5, 2, 2.5), t = 2.3",
         (gen, np.array([0.0, 0.5, 2.0, 2.5]), 2.3)),
    ]


def _segment(times, t):
    """Index i of the segment [times[i], times[i+1]] that holds t, and the fraction u."""
    i = int(np.clip(np.searchsorted(times, t, side="right") - 1, 0, len(times) - 2))
    return i, (t - times[i]) / (times[i + 1] - times[i])


def _judge_keyframes(got, args):
    Rs, times, t = args
    i, u = _segment(times, t)
    Ra, Rb = Rs[i], Rs[i + 1]
    if _close(got, (1 - u) * Ra + u * Rb, 1e-8) and not _close(got, Ra, 1e-8) \
            and not _close(got, Rb, 1e-8):
        return ("this is the entrywise blend (1 - u) R_i + u R_(i+1): it leaves SO(3). Move "
                "along the rotation between the two keyframes instead.")
    bad = _not_a_rotation(got)
    if bad:
        return bad + " Every point of the path must be a rotation."
    step = log(Ra.T @ Rb)                              # the segment's rotation vector
    if _close(log(Ra.T @ got), u * step, 1e-9):
        return None
    T = times[-1] - times[0]
    if _close(got, Rs[0] @ exp(log(Rs[0].T @ Rs[-1]), (t - times[0]) / T), 1e-8):
        return ("this is one geodesic from the first keyframe to the last: it misses the "
                "keyframes in between. Find the segment [t_i, t_(i+1)] that holds t first.")
    k = len(times) - 1
    s = (t - times[0]) / T * k                         # as if the keyframes were equally spaced
    j = int(np.clip(np.floor(s), 0, k - 1))
    if _close(got, Rs[j] @ exp(log(Rs[j].T @ Rs[j + 1]), s - j), 1e-8):
        return ("your path treats the keyframes as equally spaced in time. Here they are "
                "not: use the fraction (t - t_i) / (t_(i+1) - t_i) of the segment that "
                "holds t.")
    if _close(got, exp(step, u) @ Ra, 1e-8):
        return ("you multiplied R_i on the right. log(R_i^T R_(i+1)) is the step seen from "
                "the body at R_i, so R_i goes on the left.")
    if _close(got, Ra @ exp(log(Rb @ Ra.T), u), 1e-8):
        return ("you turned R_i on the right by the step seen from the world frame, "
                "log(R_(i+1) R_i^T). On the right of R_i goes the step seen from the body, "
                "log(R_i^T R_(i+1)); the world-frame step goes on the left of R_i.")
    U, _, Vt = np.linalg.svd((1 - u) * Ra + u * Rb)
    if not _close(got, Ra @ exp(step, u), 1e-8) and _close(got, U @ Vt, 1e-8):
        return ("this is the entrywise blend pushed back onto SO(3) by an SVD: a rotation, "
                "but it does not turn at a constant rate (section 1). Move along the "
                "geodesic (5.2) of the segment instead.")
    if _close(got, Ra @ exp(step, 1 - u), 1e-8):
        return "the segment runs backwards: at t = t_i the path must be at R_i."
    if times[i + 1] - times[i] != 1 and _close(got, Ra @ exp(step, t - times[i]), 1e-8):
        return ("you used t - t_i as the fraction of the segment: divide it by the "
                "segment's duration t_(i+1) - t_i.")
    if _close(got, Ra, 1e-8) or _close(got, Rb, 1e-8):
        return ("your path jumps from keyframe to keyframe instead of turning between "
                "them.")
    if u in (0.0, 1.0):
        return "at a keyframe's time the path must be exactly at that keyframe."
    off = float(np.linalg.norm(log(got.T @ (Ra @ exp(step, u)))))
    return (f"your R(t) is {off:.2g} rad away from the point a fraction u = "
            f"(t - t_i)/(t_(i+1) - t_i) of the way along the geodesic of that segment.")


def check_keyframes(func):
    """Exercise 5.1: ``keyframe_path(Rs, times, t)`` lies on the geodesic (5.2) of the
    segment that holds ``t``, a fraction ``(t - t_i)/(t_(i+1) - t_i)`` of the way."""
    return _run(func, _keyframe_cases(), "keyframe_path", (3, 3), _judge_keyframes,
                "Find i with t_i <= t <= t_(i+1) (np.searchsorted helps), the fraction u of "
                "that segment, and use (5.2) between R_i and R_(i+1).")


# --- 5.2 how many Euler steps keep the body's size -------------------------------------

# (speed in rad/s, T in s, tol): each margin from 1 + tol is far above rounding (tests).
# In the second, the prediction theta^2 / (2 ln(1 + tol)) rounded up is one step too many.
_STEPS_CASES = [
    ("speed 2 rad/s for 10 s, tol = 0.01", (2.0, 10.0, 0.01)),
    ("speed 1 rad/s for 1 s, tol = 0.1", (1.0, 1.0, 0.1)),
    ("speed 1 rad/s for 3 s, tol = 0.5", (1.0, 3.0, 0.5)),
    ("speed pi rad/s for 2 s, tol = 0.001", (np.pi, 2.0, 0.001)),
    ("speed 0.5 rad/s for 4 s, tol = 0.5", (0.5, 4.0, 0.5)),
    ("speed 3 rad/s for 0.1 s, tol = 0.01", (3.0, 0.1, 0.01)),
    ("speed 1 rad/s for 0.1 s, tol = 0.01 (one step may be enough)", (1.0, 0.1, 0.01)),
]


def _euler_length(speed, T, N):
    """Length of R_N e_x after N Euler steps (5.7) from I with omega = (0, 0, speed) and
    dt = T / N. One step maps the xy-plane to itself, scaled by sqrt(1 + (dt speed)^2), and
    e_x stays in that plane, so the length is (1 + (dt speed)^2)^(N/2); log1p keeps it
    accurate to a few eps for large N."""
    return float(np.exp(N / 2 * np.log1p((speed * T / N) ** 2)))


def _judge_steps(got, args):
    speed, T, tol = args
    if got != np.floor(got) or got < 1:
        return "a number of steps is a whole number, at least 1."
    N = int(got)
    length = _euler_length(speed, T, N)
    if length > 1 + tol:
        return (f"after your N = {N} Euler steps e_x has length 1 + tol + "
                f"{length - 1 - tol:.2g}, more than 1 + tol: N is too small.")
    if N > 1 and _euler_length(speed, T, N - 1) <= 1 + tol:
        if _euler_length(speed, T, N) ** 2 <= 1 + tol < _euler_length(speed, T, N - 1) ** 2:
            return ("this keeps the squared length within 1 + tol; the exercise asks for "
                    "the length.")
        if N == int(np.ceil((speed * T) ** 2 / (2 * np.log1p(tol)))):
            return ("this is the prediction theta^2 / (2 ln(1 + tol)) rounded up, and here "
                    "N - 1 steps already keep the length within 1 + tol. The prediction "
                    "is an approximation: measure the length after N - 1 steps too.")
        return ("fewer steps than your N already keep the length within 1 + tol: the "
                "smallest N is asked for.")
    return None


def check_steps_needed(func):
    r"""Exercise 5.2: ``steps_needed(speed, T, tol)`` is the smallest number N of Euler
    steps (5.7) of ``dt = T / N`` from ``I`` with :math:`\omega = (0, 0, \text{speed})`
    after which :math:`\lVert R_N e_x\rVert \le 1 + \text{tol}`: N steps stay within
    ``1 + tol`` and N - 1 do not."""
    return _run(func, _STEPS_CASES, "steps_needed", (), _judge_steps,
                "One Euler step stretches e_x by sqrt(1 + (dt |omega|)^2), and the stretches "
                "of N steps multiply. Predict N with ln(1 + x) ~ x, then measure N and its "
                "neighbours.")


# --- 5.3 the jump of the angular velocity at a keyframe ----------------------------------

def _jump_cases():
    Rz = exp([0.0, 0.0, np.pi / 2])
    R0, R1 = exp([0.3, -0.5, 0.2]), exp([-0.4, 0.9, 1.1])
    return [
        (("keyframes I, a quarter turn about z, then a quarter turn about the body's x, "
          "at times (0, 1, 2)"),
         (np.stack([np.eye(3), Rz, Rz @ exp([np.pi / 2, 0.0, 0.0])]), np.array([0.0, 1.0, 2.0]))),
        ("one axis, 0.5 rad in 1 s and then 0.5 rad in 2 s",
         (np.stack([np.eye(3), exp([0.0, 0.0, 0.5]), exp([0.0, 0.0, 1.0])]),
          np.array([0.0, 1.0, 3.0]))),
        ("three general keyframes at times (0, 0.4, 1.5)",
         (np.stack([R0, R1, R1 @ exp([0.7, 0.2, -0.6])]), np.array([0.0, 0.4, 1.5]))),
        ("a steady spin (no jump) at times (1, 2, 3)",
         (np.stack([R0, R0 @ exp([0.2, 0.4, -0.1]), R0 @ exp([0.4, 0.8, -0.2])]),
          np.array([1.0, 2.0, 3.0]))),
    ]


def _judge_jump(got, args):
    Rs, times = args
    d1, d2 = times[1] - times[0], times[2] - times[1]
    before = log(Rs[0].T @ Rs[1]) / d1                # body angular velocity on segment 1
    after = log(Rs[1].T @ Rs[2]) / d2                 # ... and on segment 2
    if _close(got, after - before, 1e-9):
        return None
    if np.any(np.abs(after - before) > 1e-9) and _close(got, before - after, 1e-9):
        return "it is off by a sign: the jump is (velocity after) - (velocity before)."
    if _close(got, Rs[1] @ (after - before), 1e-9):
        return ("this is the jump seen from the world frame (R_1 times the body-frame jump). "
                "The exercise asks for the body frame at the middle keyframe.")
    steps = log(Rs[1].T @ Rs[2]) - log(Rs[0].T @ Rs[1])
    if np.any(np.abs(steps) > 1e-9) and _close(got, steps, 1e-9):
        return ("this is the change of the rotation vectors of the steps; a velocity is a "
                "rotation vector divided by the time the step takes, and the two segments "
                "take different times.")
    if d1 != d2 and not np.any(np.abs(steps) > 1e-9) and _close(got, np.zeros(3), 1e-9):
        return ("the two steps have the same rotation vector, but the segments take "
                "different times: divide each step by its own segment's duration.")
    if _close(got, log(Rs[0].T @ Rs[2]) / (times[2] - times[0]) - before, 1e-9):
        return "the second segment runs from the middle keyframe to the last, not from the first."
    return ("that is not the difference of the body angular velocities of the two "
            "segments.")


def check_velocity_jump(func):
    """Exercise 5.3: ``velocity_jump(Rs, times)``, the body angular velocity of the second
    segment minus that of the first, for three keyframes joined by geodesics."""
    return _run(func, _jump_cases(), "velocity_jump", (3,), _judge_jump,
                "On each segment the path of 5.1 spins at one constant body angular velocity: "
                "the rotation vector of the step divided by the time the step takes.")


# --- 5.5 the weighted mean of rotations -----------------------------------------------

def _mean_cases():
    c = exp([0.2, -0.3, 0.5])
    rng = np.random.default_rng(5)
    spread = exp(0.6 * rng.standard_normal((6, 3)))
    two = np.stack([c @ exp([0.0, 0.0, 0.4]), c @ exp([0.0, 0.0, -0.4])])
    return [
        ("two turns of +-0.4 rad about z around a centre C, equal weights", (two, np.array([1.0, 1.0]))),
        ("the same two turns with weights (1, 3)", (two, np.array([1.0, 3.0]))),
        ("six rotations spread about 0.6 rad around I, weights 1..6", (spread, np.arange(1.0, 7.0))),
        ("the same six rotations turned by C, weights 0.1, 0.2, 0.3, 0.4, 0.5, 0.5",
         (c @ spread, np.array([0.1, 0.2, 0.3, 0.4, 0.5, 0.5]))),
    ]


def _judge_mean(got, args):
    Rs, weights = args
    w = np.asarray(weights, float) / np.sum(weights)
    if _close(got, np.einsum("i,ijk->jk", w, Rs), 1e-8) or _close(got, Rs.mean(axis=0), 1e-8):
        return ("this is an entrywise mean of the matrices: it is not a rotation (averaging "
                "the entries shrinks the matrix, as the blend (5.4) does).")
    bad = _not_a_rotation(got)
    if bad:
        return bad
    residual = float(np.linalg.norm(w @ log(got.T @ Rs)))    # the defining property: 0
    if residual < 1e-9:
        return None
    if not np.allclose(w, w[0]) and np.linalg.norm(log(got.T @ Rs).mean(axis=0)) < 1e-9:
        return "this is the unweighted mean: the weights were ignored."
    U, _, Vt = np.linalg.svd(np.einsum("i,ijk->jk", w, Rs))
    if _close(got, U @ np.diag([1.0, 1.0, np.linalg.det(U @ Vt)]) @ Vt, 1e-8):
        return ("this is the chordal mean (the weighted entrywise mean moved to the nearest "
                "rotation). It is close, but the exercise asks for the geodesic mean, where "
                "the weighted attitude errors Log(R_bar^T R_i) sum to zero.")
    return (f"at your R_bar the weighted mean attitude error sum_i w_i Log(R_bar^T R_i) / "
            f"sum_i w_i has length {residual:.2g} rad, not zero: iterate (5.9) until the step "
            f"is below 1e-12 (and divide by the sum of the weights, or the steps overshoot).")


def check_rotation_mean(func):
    """Exercise 5.5: ``rotation_mean(Rs, weights)`` is a rotation at which the weighted
    attitude errors ``Log(R_bar^T R_i)`` sum to zero."""
    return _run(func, _mean_cases(), "rotation_mean", (3, 3), _judge_mean,
                "Start from R_bar = Rs[0]; repeat: step = sum_i w_i Log(R_bar^T R_i) / sum_i w_i, "
                "R_bar = R_bar exp(step), until |step| < 1e-12.")


# --- 5.4 no kink: a cubic through the keyframes ----------------------------------------

def _smooth_cases():
    Rz = exp([0.0, 0.0, 1.0])
    three = np.stack([np.eye(3), Rz, Rz @ exp([1.0, 0.0, 0.0])])
    gen = np.stack([exp([0.3, -0.5, 0.2]), exp([-0.4, 0.9, 1.1]), exp([1.0, 0.6, -0.5]),
                    exp([0.2, 0.1, 0.3])])
    return [
        ("three keyframes (I, 1 rad about z, then 1 rad about the body's x) at times "
         "(0, 1, 2.5), velocities (0, 0, 1), (0.33, 0, 0.5), (0.67, 0, 0) rad/s",
         (three, np.array([0.0, 1.0, 2.5]),
          np.array([[0.0, 0.0, 1.0], [1.0 / 3.0, 0.0, 0.5], [2.0 / 3.0, 0.0, 0.0]]))),
        ("the same keyframes and times, every velocity zero (the body stops at each)",
         (three, np.array([0.0, 1.0, 2.5]), np.zeros((3, 3)))),
        ("four general keyframes at times (0, 0.5, 2, 2.5) with general velocities",
         (gen, np.array([0.0, 0.5, 2.0, 2.5]),
          np.array([[0.4, -0.2, 0.1], [-0.3, 0.5, 0.6], [0.2, 0.2, -0.7], [0.0, 0.3, 0.1]]))),
    ]


def _rate(func, Rs, times, ws, t, side):
    """Body angular velocity of ``func``'s path just after (side +1) or just before (side
    -1) time t: (5.8) over steps h and h/2 near t, combined by Richardson's rule (error
    O(h^2); h = 1e-4 s, so about 1e-8 rad/s on these paths)."""
    def path(s):
        M = np.asarray(func(Rs.copy(), times.copy(), ws.copy(), s), dtype=float)
        if M.shape != (3, 3) or not np.isfinite(M).all():
            raise ValueError("not a finite 3x3 matrix")
        return M

    def one_sided(h):
        a, b = (t, t + h) if side > 0 else (t - h, t)
        return log(path(a).T @ path(b)) / h
    h = 1e-4
    return 2 * one_sided(h / 2) - one_sided(h)


def _judge_velocity(v, w, R, h_seg, seg_phi, where):
    """None if the measured body velocity ``v`` is ``w``, else what went wrong."""
    if np.abs(v - w).max() < 1e-5:
        return None
    if np.abs(v - seg_phi / h_seg).max() < 1e-5 and np.abs(w - seg_phi / h_seg).max() > 1e-5:
        return (f"{where}, your path turns at the constant velocity of the geodesic (5.2) of "
                "the segment, as in 5.1, not at the velocity w_i given for the keyframe: "
                "that is the kink. Bend each segment with the control rotations A_i and B_i.")
    if np.abs(w).max() > 1e-9 and np.abs(v - 3 * w).max() < 1e-4:
        return (f"{where}, the body angular velocity is 3 times w_i: a cubic leaves its end "
                "3 times as fast as the step to its control point, so put the control "
                "rotation only a third of the way: exp of (h/3) w_i.")
    if np.abs(w).max() > 1e-9 and h_seg != 1 and np.abs(v - w / h_seg).max() < 1e-4:
        return (f"{where}, the velocity is w_i divided by the segment's duration h: the "
                "control step must turn by (h/3) w_i, the turn made in a third of the "
                "segment's time, not by w_i / 3.")
    if np.abs(w).max() > 1e-9 and np.abs(v - R.T @ w).max() < 1e-5:
        return (f"{where}, the velocity is w_i turned into another frame: w_i is a body "
                "velocity, so the control rotation multiplies R_i on the right, "
                "R_i exp((h/3) w_i).")
    if np.abs(w).max() > 1e-9 and np.abs(v + w).max() < 1e-5:
        return (f"{where}, the body turns the wrong way (-w_i): check the sign of the "
                "control step at that end. Arriving at R_(i+1) with velocity w_(i+1) means "
                "B_i = R_(i+1) exp(-(h/3) w_(i+1)).")
    off = float(np.abs(v - w).max())
    return (f"{where}, the body angular velocity differs from the w_i given for that "
            f"keyframe by up to {off:.2g} rad/s.")


def _point(func, Rs, times, ws, t):
    """(R(t), None) from the learner's path, or (None, what is wrong with the result)."""
    got = func(Rs.copy(), times.copy(), ws.copy(), t)
    if got is None:
        return None, "it returned None: is the `return` missing?"
    return _as_array(got, (3, 3))


def _smooth_failure(func, Rs, times, ws):
    """None if ``func``'s path through (Rs, times) has body velocity ws[i] on both sides
    of each keyframe, else a sentence saying what is wrong."""
    K = len(times)
    for i in range(K):
        M, why = _point(func, Rs, times, ws, times[i])
        if why:
            return f"at t = t_{i}: {why}"
        if not _close(M, Rs[i], 1e-9):
            return (f"at the time t_{i} of keyframe {i} your path is not at R_{i}: it must "
                    "pass through every keyframe at its time.")
    for i in range(K - 1):
        for u in (0.3, 0.7):
            t = times[i] + u * (times[i + 1] - times[i])
            M, why = _point(func, Rs, times, ws, t)
            if why:
                return f"at t = {t:.3g}: {why}"
            bad = _not_a_rotation(M)
            if bad:
                return f"at t = {t:.3g}: {bad} Every point of the path must be a rotation."
    for i in range(K):
        for side in (+1, -1):
            if (side > 0 and i == K - 1) or (side < 0 and i == 0):
                continue
            j = i if side > 0 else i - 1                      # the segment on that side
            h_seg = times[j + 1] - times[j]
            v = _rate(func, Rs, times, ws, times[i], side)
            where = f"just {'after' if side > 0 else 'before'} keyframe {i}"
            why = _judge_velocity(v, ws[i], Rs[i], h_seg, log(Rs[j].T @ Rs[j + 1]),
                                  where)
            if why:
                return why
    for i in range(K - 1):                                    # no kink inside a segment
        t = times[i] + 0.5 * (times[i + 1] - times[i])
        gap = np.abs(_rate(func, Rs, times, ws, t, +1) - _rate(func, Rs, times, ws, t, -1)).max()
        if gap > 1e-5:
            return (f"half way through segment {i} the body angular velocity jumps by "
                    f"{gap:.2g} rad/s: the path has a kink inside the segment.")
    return None


def check_smooth_path(func):
    r"""Exercise 5.4: ``smooth_path(Rs, times, ws, t)`` passes through every keyframe
    ``Rs[i]`` at ``times[i]``, stays in SO(3), and has the body angular velocity
    ``ws[i]`` just before and just after each keyframe (measured by (5.8) over short steps),
    with no kink inside a segment: a path whose :math:`\omega(t)` is continuous."""
    name = "smooth_path"
    if func is None or func is Ellipsis:
        return _fail(name, _NOT_ANSWERED)
    if not callable(func):
        return _fail(name, f"Expected a function, got a {type(func).__name__}.")
    hint = ("On segment i, with h = t_(i+1) - t_i and u = (t - t_i) / h: A = R_i exp((h/3) w_i), "
            "B = R_(i+1) exp(-(h/3) w_(i+1)); then De Casteljau with the geodesic step "
            "g(P, Q, u) = P exp(u Log(P^T Q)): three points, then two, then one.")
    for label, (Rs, times, ws) in _smooth_cases():
        try:
            with np.errstate(all="ignore"):
                why = _smooth_failure(func, Rs, times, ws)
        except NotImplementedError:
            return _fail(name, "Not written yet: the function still raises NotImplementedError.")
        except Exception as err:  # noqa: BLE001 -- a checker never raises
            return _fail(name, f"Calling it on {label} raised {type(err).__name__}: {err}", hint)
        if why:
            return _fail(name, f"On {label}: {why}", hint)
    return _ok(name, f"On {len(_smooth_cases())} sets of keyframes it passes through each "
                     "at its time with the given body angular velocity on both sides: no kink.")
