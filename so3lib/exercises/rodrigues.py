r"""Checkers for the exercises of notebook 02, "Rodrigues' formula from the series".

=============  ==========================================  ============================
exercise       the learner writes                          checker
=============  ==========================================  ============================
2.1            ``partial_sum(omega, tau, terms)``: the     :func:`check_partial_sum`
               first ``terms`` terms of the series
2.2            ``printed_ex``: where the notes' printed    :func:`check_printed_ex`
               last line sends ``e_x`` (by hand)
2.3            ``x_8_digits``: the ``x`` at which the      :func:`check_naive_B_digits`
               naive ``(1 - cos x)/x^2`` keeps only 8
               correct digits (predicted, then measured)
2.4            ``B_stable(x) = (1 - cos x)/x^2``,          :func:`check_B`
               accurate for ``|x| <= 1e10``,
               ``B(0) = 1/2``
=============  ==========================================  ============================

Every checker returns a :class:`~so3lib.exercises.Feedback` and never raises, and none
prints the value it is looking for. 2.1 and 2.4 compare with the library's own
``exp_series`` and ``B`` (the course's library, not an answer key); 2.2 evaluates the
notes' printed line itself (the property asked for); 2.3 measures the
property asked for (the naive formula's error near the learner's ``x``, against a
high-precision reference). When an answer is wrong, the checker compares it with the
usual mistakes (one term too many, an element-by-element power, the naive ``1 - cos``,
a Taylor polynomial used too far out) and names the one it matches. 2.1 and 2.4 rule out
calling ``exp_series`` and ``B``: the checkers notice such a call by name, and under any
other name (an alias, ``getattr``) while they run the learner's function.
"""

import math

import mpmath
import numpy as np

from ..series import B, exp_series
from ..so3 import hat
from . import Feedback, _calls_watched, never_raises
from .hat_map import _NOT_ANSWERED, _call, _fail, _shape_problem

__all__ = ["check_B", "check_naive_B_digits", "check_partial_sum", "check_printed_ex"]


def _close(got, alt, atol=1e-9, rtol=1e-9):
    """Whether ``got`` equals the alternative ``alt`` (False for anything unreadable)."""
    try:
        g = np.asarray(got, dtype=float)
        a = np.asarray(alt, dtype=float)
        return g.shape == a.shape and bool(np.isfinite(g).all()) and \
            bool(np.allclose(g, a, atol=atol, rtol=rtol))
    except Exception:  # noqa: BLE001 -- a checker never raises
        return False


def _global_names(func):
    """Every global or attribute name the code of ``func`` refers to, nested functions
    included (empty for an object without Python code)."""
    names, stack = set(), [getattr(func, "__code__", None)]
    while stack:
        code = stack.pop()
        if code is None:
            continue
        names.update(code.co_names)
        stack.extend(c for c in code.co_consts if hasattr(c, "co_names"))
    return names


def _forbidden(func, reference, name, what):
    """A "Not yet" Feedback when ``func`` is, or names, the library function the exercise
    asks the learner not to use (``what``, e.g. ``"exp_series"``); else None. A call under
    another name is caught while the checker runs the function (:func:`_watch`)."""
    if func is reference:
        return _fail(name, f"That is so3lib's own {what}; the exercise asks you to write it.")
    if what in _global_names(func):
        return _called(name, what)
    return None


def _called(name, what):
    return _fail(name, f"Your function calls {what}, which the exercise asks you not to "
                       "use: write the computation yourself.")


def _watch(reference):
    """While inside, a list that gets an entry each time ``reference`` is entered, under
    whatever name the learner's code called it (an alias, ``getattr``, a module attribute)."""
    return _calls_watched({reference.__code__: reference.__name__}.get)


# ---------------------------------------------------------------- exercise 2.1

_SUM_INPUTS = [
    (np.array([0.0, 0.0, 1.0]), 1.0, 1),
    (np.array([0.0, 0.0, 1.0]), 1.0, 2),
    (np.array([0.3, -0.4, 1.2]), 0.7, 6),
    (np.array([1.0, 2.0, 3.0]), 0.5, 6),
    (np.array([1.0, 2.0, 3.0]), -0.25, 9),
]

_SUM_HINT = ("partial_sum(omega, tau, N) is the sum over m = 0, 1, ..., N-1 of "
             "(tau hat(omega))^m / m!: N terms, the first one I. Build each term from the "
             "previous one: term = term @ (tau * hat(omega)) / m.")


def _diagnose_sum(got, args):
    omega, tau, terms = args
    K = tau * hat(omega)
    if _close(got, exp_series(omega, tau, terms + 1)):
        return (f"You summed {terms + 1} terms instead of {terms}: terms = N means the powers "
                "m = 0, ..., N-1, as in range(N).")
    if terms > 1 and _close(got, exp_series(omega, tau, terms - 1)):
        return (f"You summed {terms - 1} terms instead of {terms}: terms = N means the powers "
                "m = 0, ..., N-1, as in range(N), starting with the identity.")
    if _close(got, sum(np.linalg.matrix_power(K, m) for m in range(terms))):
        return "Each power must be divided by m! (math.factorial(m))."
    if _close(got, sum(K ** m / math.factorial(m) for m in range(terms))):
        return ("`K ** m` on a NumPy array raises each ENTRY to the power m. The matrix power is "
                "np.linalg.matrix_power(K, m), or build it with K @ K @ ...")
    if tau != 1.0 and _close(got, exp_series(omega, 1.0, terms)):
        return "The series is in tau * hat(omega): multiply hat(omega) by tau."
    return None


@never_raises("partial_sum")
def check_partial_sum(func):
    r"""Exercise 2.1: ``func(omega, tau, terms)`` must equal :func:`so3lib.exp_series`.

    .. math:: S_N = \sum_{m=0}^{N-1} \frac{(\tau\hat\omega)^m}{m!}

    A wrong sum gets the size of its difference and, where it matches one, the usual
    mistake; never the right matrix. A function that is, or calls, ``exp_series`` (which
    the exercise rules out), under any name, is turned down.
    """
    name = "partial_sum"
    if callable(func):
        fb = _forbidden(func, exp_series, name, "exp_series")
        if fb is not None:
            return fb
    for omega, tau, terms in _SUM_INPUTS:
        shown = f"partial_sum({np.array2string(omega, separator=', ')}, {tau:g}, {terms})"
        with _watch(exp_series) as entered:
            got, fb = _call(func, name, (omega, tau, terms), shown, _SUM_HINT)
        if entered:
            return _called(name, "exp_series")
        if fb is not None:
            return fb
        problem = _shape_problem(got, (3, 3), f"On {shown}, the answer")
        if problem:
            return _fail(name, problem, _SUM_HINT)
        off = float(np.abs(np.asarray(got, dtype=float) - exp_series(omega, tau, terms)).max())
        if off > 1e-10:
            specific = _diagnose_sum(got, (omega, tau, terms))
            return _fail(name, f"On {shown}, the sum is off by {off:.2g} in its largest entry.",
                         specific or _SUM_HINT)
    return Feedback(True, f"Correct: {name}. It agrees with so3lib.exp_series on "
                          f"{len(_SUM_INPUTS)} test inputs, from 1 term to 9.")


# ---------------------------------------------------------------- exercise 2.3

def _naive_B_error(xs):
    """Relative error of the naive float64 ``(1 - cos x)/x^2`` at each ``x`` of ``xs``.

    ``cos x`` is rounded to the nearest float here, not taken from ``np.cos``: IEEE 754
    leaves ``cos`` to the maths library, and one that is only faithful (off by less than a
    spacing, not half) may double the error, so the verdict would move with the machine.
    The subtraction, square and division are IEEE operations, the same everywhere. The
    reference is the same formula in mpmath, with 30 digits beyond the ones the subtraction
    cancels (about ``-2 log10 x``), rounded once.
    """
    xs = np.asarray(xs, dtype=float)
    errors = np.empty_like(xs)
    for i, x in enumerate(xs):
        x = float(x)
        digits = 30 + max(0, int(-2 * math.log10(x)))
        with mpmath.workdps(digits):
            m = mpmath.mpf(x)
            cos_m = mpmath.cos(m)
            ref = float((1 - cos_m) / m ** 2)
            cos_rounded = float(cos_m)           # to nearest (mpmath's default rounding)
        naive = (1.0 - cos_rounded) / (x * x)
        errors[i] = abs(naive - ref) / ref
    return errors


#: What "keeps only 8 digits" means to the checker: the worst relative error of the naive
#: B over the window [x/1.25, 1.25 x] lies between 10^-8.5 and 10^-7.5.
DIGITS_WINDOW = 1.25
DIGITS_BAND = (10 ** -8.5, 10 ** -7.5)

_DIGITS_HINT = ("Predict first: cos x is rounded to a float, off by up to half a spacing "
                "(eps/4 just below 1), and 1 - cos x is about x^2/2. So the relative error "
                "of (1 - cos x)/x^2 is about (eps/4)/(x^2/2). Set that to 1e-8 and solve for x; "
                "then measure with B_ref around your x.")


@never_raises("x_8_digits")
def check_naive_B_digits(answer):
    r"""Exercise 2.3: the ``x`` near which the naive :math:`(1 - \cos x)/x^2` keeps 8 digits.

    Measures the property itself: the worst relative error of the naive formula in float64
    (with ``cos x`` correctly rounded, so that the verdict is the same on every machine) over
    201 points of ``[x/1.25, 1.25 x]``, against a high-precision reference, must lie
    within half a digit of ``1e-8`` (between ``10^-8.5`` and ``10^-7.5``). The message says
    how many digits the naive formula keeps at the learner's ``x``.
    """
    name = "x_8_digits"
    if answer is None or answer is Ellipsis:
        return _fail(name, _NOT_ANSWERED)
    if isinstance(answer, (str, bytes)):
        return _fail(name, f"The answer should be one number x; got a {type(answer).__name__}.",
                     _DIGITS_HINT)
    try:
        x = float(np.asarray(answer, dtype=float))
    except Exception:  # noqa: BLE001 -- a checker never raises
        return _fail(name, f"The answer should be one number x; got a {type(answer).__name__}.",
                     _DIGITS_HINT)
    if not math.isfinite(x) or x <= 0:
        return _fail(name, f"x should be a positive angle in radians; got {x!r}.", _DIGITS_HINT)
    if x > 1.0:
        return _fail(name, f"At x = {x:.3g} the naive formula is accurate to about 16 digits: "
                           "no cancellation there. Look at small x.", _DIGITS_HINT)
    if x < 1e-9:
        return _fail(name, f"At x = {x:.3g}, cos x rounds to exactly 1 and the naive formula "
                           "returns 0: no correct digit left. Look at larger x.", _DIGITS_HINT)
    worst = float(_naive_B_error(np.geomspace(x / DIGITS_WINDOW, x * DIGITS_WINDOW, 201)).max())
    digits = max(0.0, -math.log10(worst)) if worst > 0 else 17.0    # never "-0.0 digits"
    lo, hi = DIGITS_BAND
    if lo <= worst <= hi:
        # the verdict, not the measured size: a notebook prints this line under strict
        # nbval, and the learner's own measurement (with np.cos) may differ in the last digit
        return Feedback(True, f"Correct: {name}. Near x = {x:.3g} the naive B keeps about 8 "
                              "correct digits: its worst relative error there is within half a "
                              "digit of 1e-8.")
    side = ("more than 8 digits survive there: the x is too large"
            if worst < lo else "fewer than 8 digits survive there: the x is too small")
    return _fail(name, f"Near x = {x:.3g} the naive B's worst relative error is {worst:.1e} "
                       f"(about {digits:.1f} correct digits): {side}.", _DIGITS_HINT)


# ---------------------------------------------------------------- exercise 2.4

# Simplest first; the small angles come before x = 0 so that the naive formula is caught
# by its visible failure (0 instead of 0.5 at 1e-8) before its division by zero; the
# middle range (1e-3 to 0.45) catches a Taylor polynomial used too far out.
_B_INPUTS = [1.0, 2.5, -0.5, 1e-8, 1e-5, 1e-3, 0.0, 0.01, 0.05, 0.1, 0.2, 0.3, 0.4, 0.45,
             -0.7, 1e-300, 30.0]
# next to the nonzero multiples of 2 pi, where cos x is again next to 1 and 1 - cos x
# cancels: the naive form kept for large x is off by 1 at 2 pi (the float), 2.3e-12 at
# 2 pi + 0.004, 1.5e-12 at 4 pi - 0.003 and 1.9e-11 at 6 pi + 0.002; and the floats
# nearest 8 pi, 2000 pi, 2e6 pi and 2e9 pi, so that a naive branch kept only above 20 (or
# 1e3, 1e6) is caught too: off by 1 at the first three and 7e-3 at the last
_B_INPUTS += [2 * math.pi, -2 * math.pi - 0.004, 4 * math.pi - 0.003, 6 * math.pi + 0.002]
_B_INPUTS += [2 * math.pi * k for k in (4, 10**3, 10**6, 10**9)]
# then a dense sweep of both signs, 1e-4 to 1 (steps of 17%), and the points just below
# the round switch-overs: a Taylor branch kept up to 0.01 or 0.1 is off by 3e-11 or 5e-11
# just below it, which the coarse list above misses
_B_INPUTS += [0.0049, 0.0099, 0.049, 0.099, -0.0049, -0.0099, -0.049, -0.099]
_B_INPUTS += [float(s * x) for x in np.geomspace(1e-4, 1.0, 60) for s in (1, -1)]
# and every 1% from 1e-3 to 0.5, where a Taylor branch of 2 to 5 terms passes 1e-12: a
# branch kept a little too long (2 terms to 4.5e-3, 3 to 0.055) is off by up to 1.4e-12
# between the points above, but by at most 1.06e-12 below the next point here
_B_INPUTS += [float(s * x) for x in np.geomspace(1e-3, 0.5, 626) for s in (1, -1)]
_B_RTOL = 1e-12

_B_HINT = ("Avoid the subtraction 1 - cos(x), which cancels wherever cos(x) is near 1: use "
           "the half-angle form 2 sin(x/2)^2 / x^2, and return the limit 1/2 at x = 0 (a Taylor polynomial "
           "is fine too, but only where its first left-out term is below 1e-12 of B).")


_TINY_HINT = ("At so small an x, 1 - cos(x) cancels every digit, and the squares x**2 and "
              "sin(x/2)**2 are subnormal floats below |x| = 1e-154 (they lose digits) and "
              "round to 0 below about 1e-162. Divide before you square, or use a Taylor "
              "branch for small |x|.")


def _diagnose_B(got, x, ref):
    """The usual mistake that ``got`` matches at ``x``, or None. A mistake is named only
    where its value differs from the true ``ref``: at ``x = 1`` a denominator ``x`` equals
    ``x^2``, and near 0 a Taylor polynomial is right, so neither can be told apart there."""
    with np.errstate(all="ignore"):
        x64 = np.float64(x)
        naive = (1.0 - np.cos(x64)) / x64 ** 2
        taylor = 0.5 - x64 ** 2 / 24.0
        taylor3 = taylor + x64 ** 4 / 720.0
        over_x = (1 - math.cos(x)) / x if x != 0 else ref

    def apart(alt):                 # the mistake gives a value the checker refuses
        return not _close(alt, ref, atol=0, rtol=_B_RTOL)

    if x != 0 and abs(x) > 1 and apart(naive) and _close(got, naive, atol=0, rtol=1e-15):
        return ("This is the naive (1 - cos x)/x^2, here far from 0: near every multiple "
                "of 2 pi, cos(x) is next to 1 again. " + _B_HINT)
    if x != 0 and apart(naive) and _close(got, naive, atol=0, rtol=1e-15):
        return ("This is the naive (1 - cos x)/x^2. Near x = 0, cos(x) rounds to a number "
                "next to 1 and the subtraction cancels almost every digit (at x = 1e-8 it "
                "gives 0). " + _B_HINT)
    if x != 0 and apart(taylor3) and _close(got, taylor3, atol=0, rtol=1e-15) \
            and taylor3 != taylor:
        return ("A Taylor polynomial here: its error is about its first left-out term, "
                "x^6/40320 for 1/2 - x^2/24 + x^4/720 (relative x^6/20160), which is above "
                "1e-12 once |x| > 0.05. Use it only below that, and the half-angle form "
                "elsewhere.")
    if x != 0 and apart(taylor) and _close(got, taylor, atol=0, rtol=1e-15):
        return ("A Taylor polynomial here: its error is about its first left-out term, "
                "x^4/720 for 1/2 - x^2/24 (relative x^4/360), which is above 1e-12 once "
                "|x| > 4e-3. Use it only below that, and the half-angle form elsewhere.")
    if x != 0 and apart(math.sin(x) / x) and _close(got, math.sin(x) / x):
        return "That is A(x) = sin(x)/x, the other coefficient. B(x) = (1 - cos x)/x^2."
    if x != 0 and over_x != 0 and apart(over_x) and _close(got, over_x):
        return "The denominator is x^2, not x."
    if 0 < abs(x) < 1e-150:
        return _TINY_HINT
    return None


@never_raises("B_stable")
def check_B(func):
    r"""Exercise 2.4: ``func(x)`` must give :math:`B(x) = (1 - \cos x)/x^2` to 1e-12 relative.

    Compares with the library's ``so3lib.B`` at ``x`` from 1 down to 1e-8, then ``x = 0``
    (where ``B = 1/2``), the middle range 0.01 to 0.45 (where a Taylor polynomial kept
    too long fails), ``1e-300`` and ``x = 30``, next to 2 pi, 4 pi, 6 pi and 8 pi and at
    the floats nearest ``2 pi k`` for ``k = 1e3, 1e6, 1e9`` (where the naive form cancels
    again), then just below the round switch-overs
    0.005, 0.01, 0.05, 0.1, at 60 values of each sign from 1e-4 to 1 and every 1% from
    1e-3 to 0.5. A wrong value gets its relative error and the usual mistake it matches
    (below ``|x| = 1e-150``: squares that underflow). A function that is, or calls, ``so3lib.B`` (which the
    exercise rules out), under any name, is turned down.
    """
    name = "B_stable"
    if callable(func):
        fb = _forbidden(func, B, name, "B")
        if fb is not None:
            return fb
    for x in _B_INPUTS:
        shown = f"B_stable({x:g})"
        hint = _TINY_HINT if 0 < abs(x) < 1e-150 else _B_HINT
        with _watch(B) as entered:
            got, fb = _call(func, name, (x,), shown, hint)
        if entered:
            return _called(name, "so3lib.B")
        if fb is not None:
            return fb
        problem = (f"{shown} is a {type(got).__name__}, not a number."
                   if isinstance(got, (str, bytes)) else _shape_problem(got, (), f"{shown}"))
        if problem:
            return _fail(name, problem, "Return one float.")
        ref = float(B(x))
        rel = abs(float(got) - ref) / ref
        if rel > _B_RTOL:
            if rel < 1.05 * _B_RTOL:        # printed, 1.0e-12 would read as 1e-12
                size = f"a relative error just above the {_B_RTOL:.0e} the exercise asks for"
            else:
                size = f"a relative error of {rel:.1e}; the exercise asks for {_B_RTOL:.0e}"
            return _fail(name, f"{shown} has {size}.", _diagnose_B(got, x, ref) or _B_HINT)
    return Feedback(True, f"Correct: {name}. It is accurate to 1e-12 (relative) at "
                          f"{len(_B_INPUTS)} values of x from 0 to 6.3e9, among them every 1% "
                          "where Taylor branches end and next to multiples of 2 pi.")


# ---------------------------------------------------------------- exercise 2.2

#: The quarter turn of exercise 2.2: omega = (0, 0, pi/2) rad/s for tau = 1 s.
QUARTER_OMEGA = np.array([0.0, 0.0, math.pi / 2])

_PRINTED_HINT = ("Work term by term on e_x: hat(omega) e_x = omega x e_x, |omega| = pi/2, "
                 "sin(pi/2) = 1 and 1 - cos(pi/2) = 1. The printed line has hat(omega) in "
                 "its third term where hat(omega)^2 belongs.")


def _printed_line(omega, tau):
    """The notes' printed last line, ``I + sin(|w| tau)/|w| W + (1 - cos(|w| tau))/|w|^2 W``
    (W = hat(omega): the square missing), as the learner is asked to evaluate it."""
    w, W = float(np.linalg.norm(omega)), hat(omega)
    return np.eye(3) + math.sin(w * tau) / w * W + (1 - math.cos(w * tau)) / w ** 2 * W


@never_raises("printed_ex")
def check_printed_ex(answer):
    r"""Exercise 2.2: where the notes' printed line sends :math:`e_x` for the quarter turn
    :math:`\omega = (0, 0, \pi/2)`, :math:`\tau = 1`.

    Evaluates the printed line (hat where the square belongs) on :math:`e_x`, the property
    asked for, and compares to 1e-9. A wrong answer is compared with the usual slips (the
    corrected formula's :math:`Re_x`, the square put back, a lost :math:`1/\lVert\omega\rVert`)
    and the message names the slip; it never prints the vector looked for.
    """
    name = "printed_ex"
    if answer is None or answer is Ellipsis:
        return _fail(name, _NOT_ANSWERED)
    problem = _shape_problem(answer, (3,), "printed_ex")
    if problem:
        return _fail(name, problem + " It should be a vector of 3 floats.", _PRINTED_HINT)
    got = np.asarray(answer, dtype=float)
    W = hat(QUARTER_OMEGA)
    w = float(np.linalg.norm(QUARTER_OMEGA))
    e_x = np.array([1.0, 0.0, 0.0])
    if _close(got, _printed_line(QUARTER_OMEGA, 1.0) @ e_x):
        return Feedback(True, f"Correct: {name}. The printed line sends e_x off the unit "
                              "circle: longer than 1, so it is not a rotation.")
    slips = [
        ((np.eye(3) + W / w + W @ W / w ** 2) @ e_x,
         "That is R e_x, where the corrected (2.6) sends it. The exercise asks for the "
         "printed line, whose third term has hat(omega), not hat(omega)^2."),
        ((np.eye(3) + W / w + W / w) @ e_x,
         "The third term is divided by |omega|^2, not by |omega|: hat(omega) carries one "
         "factor |omega| = pi/2, so one is left over in the denominator."),
        ((np.eye(3) + W / w + W) @ e_x,
         "The third term divides by |omega|^2 = (pi/2)^2: it looks as if that division "
         "was left out."),
        ((np.eye(3) + W + W / w ** 2) @ e_x,
         "The second term is sin(|omega| tau)/|omega| hat(omega): it looks as if the "
         "division by |omega| was left out there."),
    ]
    for alt, why in slips:
        if _close(got, alt):
            return _fail(name, why, _PRINTED_HINT)
    if abs(got[2]) > 1e-9:
        return _fail(name, "Every term maps e_x into the x-y plane (the turn is about z): "
                           "the z component is 0.", _PRINTED_HINT)
    if not math.isclose(got[0], 1.0, abs_tol=1e-9):
        return _fail(name, "The x component is wrong: only I sends e_x to something with an "
                           "x component; hat(omega) e_x points along y.", _PRINTED_HINT)
    return _fail(name, "The x and z components are right; the y component is not.",
                 _PRINTED_HINT)
