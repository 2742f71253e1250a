r"""Checkers for the exercises of notebook 01, "The hat map and the Lemma".

=============  ==================================  ====================================
exercise       the learner writes                  checker
=============  ==================================  ====================================
1.1            ``hat_matrix(a)``, shape (3, 3)     :func:`check_hat`
1.2            ``c``, with ``hat(a)^5 = c hat(a)``  :func:`check_fifth_power`
               for ``a = (1, 2, 3)``
1.3            ``power_coefficients(a, p)``         :func:`check_power_coefficients`
               ``-> (c0, c1, c2)`` with
               ``hat(a)^p = c0 I + c1 hat(a) + c2 hat(a)^2``
=============  ==================================  ====================================

Every checker returns a :class:`~so3lib.exercises.Feedback` and never raises.
"""

import numpy as np

from ..so3 import hat
from . import Feedback, check_function, check_value, never_raises

__all__ = ["check_hat", "check_fifth_power", "check_power_coefficients",
           "power_coefficients"]

#: The vector of exercise 1.2.
A_FIFTH = np.array([1.0, 2.0, 3.0])

_HAT_INPUTS = [
    (np.array([1.0, 0.0, 0.0]),),
    (np.array([0.0, 0.0, 1.0]),),
    (np.array([1.0, 2.0, 3.0]),),
    (np.array([-0.5, 0.25, 2.0]),),
]

_HAT_HINT = ("Row 1 of hat(a) is (0, -a3, a2), row 2 is (a3, 0, -a1), row 3 is (-a2, a1, 0). "
             "Test your matrix: hat_matrix(a) @ b should equal np.cross(a, b).")


def _sq(a):
    a = np.asarray(a, dtype=float)
    return float(a @ a)


def power_coefficients(a, p):
    r"""The three numbers with :math:`\hat a^p = c_0 I + c_1 \hat a + c_2 \hat a^2`.

    .. math:: \hat a^0 = I,\qquad
              \hat a^{2k+1} = (-1)^k \lVert a\rVert^{2k}\,\hat a,\qquad
              \hat a^{2k+2} = (-1)^k \lVert a\rVert^{2k}\,\hat a^2 \quad (k \ge 0)

    Notebook 01, equations (1.7) and (1.8); the reference answer of exercise 1.3.

    Parameters
    ----------
    a : array_like, shape (3,)
    p : int, p >= 0

    Returns
    -------
    c : ndarray, shape (3,)
        ``(c0, c1, c2)``.
    """
    if p == 0:
        return np.array([1.0, 0.0, 0.0])
    k = (p - 1) // 2
    c = (-1.0) ** k * _sq(a) ** k
    return np.array([0.0, c, 0.0]) if p % 2 else np.array([0.0, 0.0, c])


def _without_negative_zero(func):
    """``func`` with ``-0.0`` entries of its result shown as ``0.0``.

    ``hat`` writes ``-a3`` etc., so ``hat((1, 0, 0))`` holds ``-0.0``; printed in a message,
    ``[[0., -0., 0.], ...]`` reads like a sign error. Adding ``0.0`` changes nothing else.
    Results that are not numeric arrays (None, the wrong type) are passed on untouched,
    so that the checker's own messages for them still apply.
    """
    def wrapped(*args):
        result = func(*args)
        try:
            arr = np.asarray(result, dtype=float)
        except (TypeError, ValueError):
            return result
        return arr + 0.0 if result is not None and arr.ndim == 2 else result
    return wrapped


def check_hat(func):
    """Exercise 1.1: ``func(a)`` must return the 3x3 matrix ``hat(a)``.

    A matrix with the opposite sign (the transpose, since hat(a) is skew) gets a hint
    about the sign pattern. Matrices in the message never show ``-0.``.
    """
    if not callable(func):
        return check_function(func, hat, _HAT_INPUTS, "hat_matrix", hint=_HAT_HINT)
    return check_function(_without_negative_zero(func), _without_negative_zero(hat),
                          _HAT_INPUTS, "hat_matrix", hint=_HAT_HINT)


@never_raises("the coefficient c of hat(a)^5 = c hat(a)")
def check_fifth_power(answer):
    r"""Exercise 1.2: the number ``c`` with :math:`\hat a^5 = c\,\hat a` for ``a = (1, 2, 3)``.

    Recognises the usual slips: the sign, the exponent of ``|a|``, and handing in the
    matrix :math:`\hat a^5` instead of the number.
    """
    name = "the coefficient c of hat(a)^5 = c hat(a)"
    n2 = _sq(A_FIFTH)                                  # |a|^2 = 14
    expected = n2 ** 2                                 # (-1)^2 |a|^4 = 196
    try:
        arr = None if answer is None or answer is Ellipsis else np.asarray(answer, dtype=float)
    except Exception:  # not a number: check_value writes the message
        arr = None
    if arr is not None and arr.shape == (3, 3) and np.isfinite(arr).all():
        H = hat(A_FIFTH)
        c = float(np.sum(arr * H) / np.sum(H * H))   # the best c with arr ~ c hat(a)
        if np.allclose(arr, c * H, atol=1e-8, rtol=1e-10):
            verdict = ("and that matrix is right" if np.isclose(c, expected)
                       else "but it is not hat(a)^5")
            return Feedback(False, f"Not yet: {name}. You gave a 3x3 matrix, equal to "
                                   f"{c:.6g} hat(a), {verdict}. The exercise asks for the "
                                   "number c itself.")
    hint = ("Start from the Lemma, hat(a)^3 = -|a|^2 hat(a), and write "
            "hat(a)^5 = hat(a)^3 hat(a)^2 = -|a|^2 hat(a)^3. Here |a|^2 = 1 + 4 + 9 = 14.")
    if arr is not None and arr.shape == () and np.isfinite(arr):
        x = float(arr)
        if np.isclose(x, -expected):
            hint = ("Right size, wrong sign: each use of the Lemma brings a factor "
                    "-|a|^2, and you used it twice, so the two minus signs cancel.")
        elif np.isclose(abs(x), n2):
            hint = ("That is (up to sign) the factor of hat(a)^3 = -|a|^2 hat(a). Apply "
                    "the Lemma once more: hat(a)^5 = hat(a)^3 hat(a)^2.")
        elif any(np.isclose(abs(x), v) for v in (n2 ** 1.5, n2 ** 2.5, n2 ** 4, n2 ** 5)):
            hint = ("Check the power of |a|: hat(a)^(2k+1) = (-1)^k |a|^(2k) hat(a), and "
                    "5 = 2k + 1 gives k = 2, so the factor is |a|^4 = (|a|^2)^2.")
    return check_value(answer, expected, name, atol=1e-9, rtol=1e-9, hint=hint)


def _power_hint(p):
    if p == 0:
        return ("hat(a)^0 is the identity I, so (c0, c1, c2) = (1, 0, 0). The formula for "
                "even powers starts at p = 2; p = 0 would need k = -1.")
    k = (p - 1) // 2
    if p % 2:
        return (f"p = {p} is odd: p = 2k + 1 with k = {k}, so hat(a)^p = (-1)^k |a|^(2k) hat(a), "
                "a multiple of hat(a) only (c0 = c2 = 0). Note |a|^(2k) = (a @ a)**k.")
    return (f"p = {p} is even: p = 2k + 2 with k = {k}, so hat(a)^p = (-1)^k |a|^(2k) hat(a)^2, "
            "a multiple of hat(a)^2 only (c0 = c1 = 0). Note |a|^(2k) = (a @ a)**k.")


@never_raises("power_coefficients")
def check_power_coefficients(func):
    r"""Exercise 1.3: ``func(a, p)`` must return ``(c0, c1, c2)`` with
    :math:`\hat a^p = c_0 I + c_1\hat a + c_2\hat a^2`.

    Tries ``p = 1, 2, ..., 9`` and then ``p = 0`` for two vectors of different length,
    and stops at the first wrong answer with a hint for that ``p``.
    """
    name = "power_coefficients"
    vectors = (np.array([1.0, 2.0, 3.0]), np.array([0.5, -1.0, 0.25]))
    order = list(range(1, 10)) + [0]
    for p in order:
        for a in vectors:
            fb = check_function(func, power_coefficients, [(a, p)], name,
                                atol=1e-9, rtol=1e-9, hint=_power_hint(p))
            if not fb:
                return fb
    return Feedback(True, f"Correct: {name}. It gives the right (c0, c1, c2) for "
                          "p = 0, ..., 9 and two vectors a.")
