r"""Checkers for the exercises of notebook 05 (applications of exp and log).

=========================  ===============================================================
checker                    the exercise
=========================  ===============================================================
``check_interpolate``      5.1 ``interpolate(R0, R1, s) = R0 exp(s log(R0^T R1))``
``check_euler_stretch``    5.2 the length of ``e_x`` after N Euler steps,
                           ``(1 + dt^2 |omega|^2)^(N/2)``
``check_angular_velocity`` 5.3 ``angular_velocity(R0, R1, dt) = log(R0^T R1) / dt``
``check_rotation_mean``    5.4 ``rotation_mean(Rs, weights)``, the weighted geodesic
                           (Karcher) mean of rotations
=========================  ===============================================================

Each checker returns a :class:`so3lib.exercises.Feedback` and never raises. Beyond
"right" or "wrong" it recognises the usual mistakes (interpolating the entries, the
relative rotation on the wrong side, forgetting ``dt``, the chordal mean) and says so.
"""

import numpy as np

from ..so3 import exp, log
from ..validation import rotation_defects
from . import (_NOT_ANSWERED, Feedback, _compare, _fail, _fmt, _ok, check_function,
               never_raises)

__all__ = ["check_interpolate", "check_euler_stretch", "check_angular_velocity",
           "check_rotation_mean", "interpolate_reference", "rotation_mean_reference"]


# --- references ----------------------------------------------------------------------

def interpolate_reference(R0, R1, s):
    r"""The geodesic from ``R0`` to ``R1``: :math:`R(s) = R_0 \exp(s \log(R_0^T R_1))`."""
    R0, R1 = np.asarray(R0, float), np.asarray(R1, float)
    return R0 @ exp(log(R0.T @ R1), s)


def rotation_mean_reference(Rs, weights=None, iterations=100, tol=1e-14):
    r"""The weighted geodesic (Karcher) mean of rotations ``Rs`` (shape (N, 3, 3)).

    Repeats :math:`\bar R \leftarrow \bar R \exp\big(\sum_i w_i \log(\bar R^T R_i)
    / \sum_i w_i\big)` from ``Rs[0]`` until the step is below ``tol`` (notebook 05,
    equation (5.9)); ``weights=None`` means equal weights.
    """
    Rs = np.asarray(Rs, float)
    w = np.ones(len(Rs)) if weights is None else np.asarray(weights, float)
    w = w / w.sum()
    mean = Rs[0]
    for _ in range(iterations):
        step = np.einsum("i,ij->j", w, log(np.swapaxes(mean, -1, -2) @ Rs))
        mean = mean @ exp(step)
        if np.linalg.norm(step) < tol:
            break
    return mean


def _chordal_mean(Rs, w=None):
    """The (weighted) entrywise mean projected onto SO(3) by an SVD: close to, but not,
    the geodesic mean."""
    w = np.ones(len(Rs)) / len(Rs) if w is None else w
    U, _, Vt = np.linalg.svd(np.einsum("i,ijk->jk", w, Rs))
    D = np.diag([1.0, 1.0, np.sign(np.linalg.det(U @ Vt))])
    return U @ D @ Vt


# --- the shared loop ------------------------------------------------------------------

def _not_a_rotation(M):
    """A sentence if ``M`` (finite, 3x3) is not a rotation, else None."""
    orth, det = rotation_defects(M)
    if orth > 1e-6 or abs(det - 1.0) > 1e-6:
        return (f" It is not a rotation: for your matrix M, max|M^T M - I| = "
                f"{float(orth):.2g} and det M = {float(det):.4g}.")
    return None


def _close(a, b, atol):
    with np.errstate(all="ignore"):
        return np.shape(a) == np.shape(b) and np.allclose(a, b, atol=atol, rtol=0)


def _run_cases(func, reference, cases, name, atol, diagnose, hint):
    """:func:`check_function` with labelled cases, absolute tolerance ``atol`` and the
    diagnosis of this notebook's usual mistakes."""
    return check_function(func, reference, cases, name, atol=atol, rtol=0.0, hint=hint,
                          diagnose=diagnose, reference_name="the reference")


# --- 5.1 interpolation ----------------------------------------------------------------

def _interpolation_cases():
    Rz = exp([0.0, 0.0, np.pi / 2])                      # a quarter turn about z
    R0 = exp([0.3, -0.5, 0.2])
    R1 = exp([-0.4, 0.9, 1.1])
    R2 = exp([1.0, 1.0, -0.5])
    return [
        ("R0 = I, R1 = a quarter turn about z and s = 0.5", (np.eye(3), Rz, 0.5)),
        ("s = 0 (the path must start at R0)", (R0, R1, 0.0)),
        ("s = 1 (the path must end at R1)", (R0, R1, 1.0)),
        ("two general rotations and s = 0.3", (R0, R1, 0.3)),
        ("two other rotations and s = 0.8", (R2, R0, 0.8)),
    ]


def _diagnose_interpolate(got, args):
    R0, R1, s = args
    R0, R1 = np.asarray(R0, float), np.asarray(R1, float)
    if _close(got, (1 - s) * R0 + s * R1, 1e-8):
        return (" This is the entrywise blend (1 - s) R0 + s R1: it leaves SO(3). Move along "
                "the rotation instead: R0 exp(s log(R0^T R1)).")
    bad = _not_a_rotation(got)
    if bad:
        return bad + " Every R(s) on the path should be a rotation."
    if _close(got, exp(log(R0.T @ R1), s) @ R0, 1e-8):
        return (" You multiplied R0 on the right. log(R0^T R1) is measured in R0's own "
                "frame, so R0 goes on the left: R0 exp(s log(R0^T R1)).")
    if _close(got, R0 @ exp(log(R1 @ R0.T), s), 1e-8):
        return (" You used log(R1 R0^T), the step measured in the fixed frame; with R0 on "
                "the left the step must be log(R0^T R1).")
    if _close(got, R0 @ exp(log(R0.T @ R1), 1 - s), 1e-8):
        return " It runs backwards: at s = 0 the path must be at R0."
    return None


def check_interpolate(func):
    """Exercise 5.1: ``interpolate(R0, R1, s)`` returns ``R0 exp(s log(R0^T R1))``."""
    return _run_cases(func, interpolate_reference, _interpolation_cases(), "interpolate",
                      1e-9, _diagnose_interpolate,
                      "R0^T R1 takes R0 to R1; take its log, scale it by s, exponentiate, "
                      "and multiply R0 on the left.")


# --- 5.2 Euler's stretch factor -------------------------------------------------------

#: The numbers of exercise 5.2.
EULER_OMEGA = np.array([0.0, 0.0, 2.0])     # rad/s
EULER_DT = 0.05                              # s
EULER_STEPS = 200


@never_raises("the length of R_N e_x after 200 Euler steps")
def check_euler_stretch(answer):
    r"""Exercise 5.2: the length of :math:`R_N e_x` after N Euler steps from ``I``.

    With :math:`\omega = (0, 0, 2)` rad/s, ``dt = 0.05`` s and ``N = 200``, each step
    multiplies the length of a vector perpendicular to :math:`\omega` by
    :math:`\sqrt{1 + dt^2\lVert\omega\rVert^2}`, so the answer is
    :math:`1.01^{100} \approx 2.7048`.
    """
    name = "the length of R_N e_x after 200 Euler steps"
    if answer is None or answer is Ellipsis:
        return _fail(name, _NOT_ANSWERED)
    w, dt, N = float(np.linalg.norm(EULER_OMEGA)), EULER_DT, EULER_STEPS
    expected = (1.0 + (dt * w) ** 2) ** (N / 2)
    hint = ("One Euler step multiplies a vector perpendicular to omega by "
            "(I + dt hat(omega)); compute the length of that product (Pythagoras), "
            "then repeat it N times.")
    result = _compare(answer, expected, name, 1e-6, 1e-6, None)
    if result is None:
        return _fail(name, _NOT_ANSWERED)
    if result is True:
        return _ok(name, "The body has grown to 2.7 times its size: Euler steps are "
                         "not rotations.")
    try:
        got = float(np.asarray(answer, dtype=float).reshape(()))
    except (TypeError, ValueError):
        got = None
    extra = ""
    if got is not None and np.isfinite(got):
        if np.isclose(got, 1.0):
            extra = (" A rotation would keep the length 1, but I + dt hat(omega) is "
                     "not a rotation.")
        elif np.isclose(got, (1 + (dt * w) ** 2) ** N, rtol=1e-4):
            extra = (" That is the squared length: the length grows by the square "
                     "root of 1 + dt^2 |omega|^2 per step.")
        elif np.isclose(got, (1 + dt * w) ** N, rtol=1e-4) or \
                np.isclose(got, (1 + dt * w) ** (N / 2), rtol=1e-4):
            extra = (" dt hat(omega) e_x is perpendicular to e_x, so the lengths add "
                     "like the sides of a right triangle, not along a line.")
        elif np.isclose(got, np.sqrt(1 + (dt * w) ** 2), rtol=1e-6):
            extra = " That is one step; the question asks for N = 200 steps."
    return Feedback(False, result.message + extra + f"\nHint: {hint}")


# --- 5.3 angular velocity from two orientations ---------------------------------------

def _angular_velocity_reference(R0, R1, dt):
    return log(np.asarray(R0, float).T @ np.asarray(R1, float), dt)


def _velocity_cases():
    R0 = exp([0.3, -0.5, 0.2])
    w = np.array([0.4, -1.5, 2.0])
    return [
        ("a quarter turn about z in 1 s from R0 = I",
         (np.eye(3), exp([0.0, 0.0, np.pi / 2]), 1.0)),
        ("a general R0, omega = (0.4, -1.5, 2.0) rad/s and dt = 0.1 s",
         (R0, R0 @ exp(w, 0.1), 0.1)),
        ("a general R0, omega = (0.4, -1.5, 2.0) rad/s and dt = 0.5 s",
         (R0, R0 @ exp(w, 0.5), 0.5)),
        ("no motion (R1 = R0) and dt = 0.01 s", (R0, R0.copy(), 0.01)),
    ]


def _diagnose_velocity(got, args):
    R0, R1, dt = args
    R0, R1 = np.asarray(R0, float), np.asarray(R1, float)
    if _close(got, log(R1 @ R0.T, dt), 1e-8):
        return (" This is log(R1 R0^T)/dt, the angular velocity in the fixed (world) "
                "frame, R0 omega. The exercise asks for the body frame: log(R0^T R1)/dt.")
    if _close(got, log(R0.T @ R1), 1e-8):
        return " It is the rotation vector of the step: divide by dt to get a velocity."
    if _close(got, dt * log(R0.T @ R1), 1e-8):
        return " You multiplied by dt: the velocity is the rotation vector divided by dt."
    approx = R0.T @ (R1 - R0) / dt
    if _close(got, np.array([approx[2, 1], approx[0, 2], approx[1, 0]]), 1e-8) or \
            _close(got, 0.5 * np.array([approx[2, 1] - approx[1, 2],
                                        approx[0, 2] - approx[2, 0],
                                        approx[1, 0] - approx[0, 1]]), 1e-8):
        return (" This is the finite difference vee(R0^T (R1 - R0))/dt: only a first-order "
                "approximation, wrong by a lot when the step turns far. Use the log.")
    return None


def check_angular_velocity(func):
    """Exercise 5.3: ``angular_velocity(R0, R1, dt)`` returns ``log(R0^T R1) / dt``."""
    return _run_cases(func, _angular_velocity_reference, _velocity_cases(),
                      "angular_velocity", 1e-9, _diagnose_velocity,
                      "R0^T R1 is the step seen from the body; its log is the rotation "
                      "vector of the step, and a velocity is that divided by the time.")


# --- 5.4 the weighted mean of rotations -----------------------------------------------

def _mean_cases():
    c = exp([0.2, -0.3, 0.5])
    rng = np.random.default_rng(5)
    spread = exp(0.6 * rng.standard_normal((6, 3)))
    two = np.stack([c @ exp([0.0, 0.0, 0.4]), c @ exp([0.0, 0.0, -0.4])])
    return [
        ("two turns of +-0.4 rad about z around a centre C, equal weights (the mean is C)",
         (two, np.array([1.0, 1.0]))),
        ("the same two turns with weights (1, 3) (the mean is C exp(-0.2 rad about z))",
         (two, np.array([1.0, 3.0]))),
        ("six rotations spread about 0.6 rad around I, weights 1..6",
         (spread, np.arange(1.0, 7.0))),
        ("the same six rotations turned by C, weights 0.1, 0.2, 0.3, 0.4, 0.5, 0.5",
         (c @ spread, np.array([0.1, 0.2, 0.3, 0.4, 0.5, 0.5]))),
    ]


def _diagnose_mean(got, args):
    Rs, weights = args
    Rs, w = np.asarray(Rs, float), np.asarray(weights, float) / np.sum(weights)
    if _close(got, np.einsum("i,ijk->jk", w, Rs), 1e-8) or _close(got, Rs.mean(axis=0), 1e-8):
        return (" This is an entrywise mean of the matrices: it is not a rotation "
                "(averaging the entries shrinks the matrix, as the blend (5.4) does).")
    bad = _not_a_rotation(got)
    if bad:
        return bad
    if not np.allclose(w, w[0]) and _close(got, rotation_mean_reference(Rs), 1e-8):
        return " This is the unweighted mean: the weights were ignored."
    if _close(got, _chordal_mean(Rs, w), 1e-8):
        return (" This is the chordal mean (the weighted entrywise mean projected onto "
                "SO(3)). It is close, but the exercise asks for the geodesic mean, where the "
                "weighted attitude errors Log(R_bar^T R_i) sum to zero.")
    step = np.einsum("i,ij->j", w, log(got.T @ Rs))
    return (f" At your answer R_bar the weighted mean attitude error "
            f"sum_i w_i Log(R_bar^T R_i) / sum_i w_i is {_fmt(step)}, not zero: iterate (5.9) until it is below 1e-12 "
            f"(and divide by the sum of the weights, or the steps overshoot).")


def check_rotation_mean(func):
    """Exercise 5.4: ``rotation_mean(Rs, weights)`` returns the weighted geodesic mean."""
    return _run_cases(func, rotation_mean_reference, _mean_cases(), "rotation_mean", 1e-8,
                      _diagnose_mean,
                      "Start from R_bar = Rs[0]; repeat: step = sum_i w_i Log(R_bar^T R_i) / "
                      "sum_i w_i, R_bar = R_bar exp(step), until |step| < 1e-12.")
