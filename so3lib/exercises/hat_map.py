r"""Checkers for the exercises of notebook 01, "The hat map and the Lemma".

=============  =========================================  ===================================
exercise       the learner writes                         checker
=============  =========================================  ===================================
1.1            ``split(M) -> (S, K)``: the symmetric and  :func:`check_split`
               skew parts of a 3x3 matrix, ``M = S + K``
1.2            ``c = (c0, c1, c2)`` with                  :func:`check_power_of_i_plus_hat`
               ``(I + hat(a))^4 = c0 I + c1 hat(a)
               + c2 hat(a)^2`` for ``a = (1, 2, 3)``
1.3            ``power_coefficients(a, p)``               :func:`check_power_coefficients`
               ``-> (c0, c1, c2)`` with
               ``hat(a)^p = c0 I + c1 hat(a) + c2 hat(a)^2``
=============  =========================================  ===================================

Every checker returns a :class:`~so3lib.exercises.Feedback` and never raises. A checker
holds no answer: it tests the defining property of what the learner hands in (``S`` is
symmetric, ``K`` skew and ``S + K = M``; ``c0 I + c1 hat(a) + c2 hat(a)^2`` equals
``(I + hat(a))^4`` multiplied out with a matrix power) and never prints the value it is
looking for. The checker of 1.3
also refuses code that calls a matrix route (``matrix_power``, ``funm``, ``eig``, a fit
with ``lstsq``, ``solve`` or ``pinv``, ...), directly, through a function of the learner's
own or under another name, since the exercise asks for the formula. When an answer is wrong it names
the usual mistake it matches, with a hint; a wrong answer is never measured against the
right one in the message (the size of the difference would give the answer away).
"""

import numpy as np

from ..so3 import hat
from . import Feedback, never_raises

__all__ = ["check_power_coefficients", "check_power_of_i_plus_hat", "check_split"]

_NOT_ANSWERED = ("No answer yet: replace the `...` (or `None`) with your answer and run "
                 "the cell again.")


def _fail(name, why, hint=None):
    """A "Not yet" Feedback: what is wrong, then the hint."""
    return Feedback(False, f"Not yet: {name}. {why}" + (f"\nHint: {hint}" if hint else ""))


#: The vector of exercise 1.2.
A_12 = np.array([1.0, 2.0, 3.0])

def _floats(x, shape=None):
    """``x`` as a finite float array (of ``shape``, if given), or None."""
    try:
        arr = np.asarray(x, dtype=float)
    except Exception:  # noqa: BLE001 -- a checker never raises
        return None
    if shape is not None and arr.shape != shape:
        return None
    return arr if np.isfinite(arr).all() else None


def _call(func, name, args, shown, hint=None):
    """Call the learner's ``func(*args)`` (on copies). Returns ``(result, None)``, or
    ``(None, feedback)`` when there is nothing to compare yet or the call failed."""
    if func is None or func is Ellipsis:
        return None, _fail(name, _NOT_ANSWERED)
    if not callable(func):
        return None, _fail(name, f"Expected a function, got a {type(func).__name__}.")
    try:
        got = func(*[np.array(a, copy=True) if isinstance(a, np.ndarray) else a for a in args])
    except NotImplementedError:
        return None, _fail(name, "Not written yet: the function still raises NotImplementedError.")
    except Exception as err:  # noqa: BLE001 -- a checker never raises
        return None, _fail(name, f"Calling it on {shown} raised {type(err).__name__}: {err}", hint)
    if got is None:
        return None, _fail(name, f"It returned None on {shown}: is the `return` missing?")
    return got, None


def _shape_problem(got, shape, what):
    """A sentence when ``got`` is not a finite float array of ``shape``, else None."""
    try:
        if np.iscomplexobj(np.asarray(got)):            # e.g. (-1)**k with k = 0.5
            return f"{what} contains a complex number; it should be real."
    except Exception:  # noqa: BLE001 -- a checker never raises
        pass
    try:
        arr = np.asarray(got, dtype=float)
    except Exception:  # noqa: BLE001 -- a checker never raises
        return f"{what} is a {type(got).__name__}, not a number or an array of numbers."
    if arr.shape != shape:
        return f"{what} has shape {arr.shape}; it should have shape {shape}."
    if not np.isfinite(arr).all():
        return f"{what} contains NaN or inf."
    return None


# ---------------------------------------------------------------- exercise 1.1

_SPLIT_INPUTS = [
    ("the integer matrix [[1, 2, 3], [4, 5, 6], [7, 8, 10]]",
     np.array([[1.0, 2.0, 3.0], [4.0, 5.0, 6.0], [7.0, 8.0, 10.0]])),
    ("hat((1, 2, 3)), which is skew already", hat([1.0, 2.0, 3.0])),
    ("the symmetric matrix diag(1, 2, 3) + 1", np.diag([1.0, 2.0, 3.0]) + 1.0),
    ("a random 3x3 matrix", np.random.default_rng(101).standard_normal((3, 3))),
]

_SPLIT_HINT = ("Transposing swaps the roles: if M = S + K then M^T = S - K. Two equations, "
               "two unknowns: solve them for S and K.")


@never_raises("split")
def check_split(func):
    r"""Exercise 1.1: ``func(M)`` returns ``(S, K)`` with :math:`S^T = S`, :math:`K^T = -K`
    and :math:`S + K = M`.

    Tests those three properties on four matrices (a skew one and a symmetric one among
    them), and reports the inner product :math:`\operatorname{tr}(S^T K)` of the result.
    Recognises the missing halves (``S + K = 2M``) and ``S`` and ``K`` swapped.
    """
    name = "split"
    worst_inner = 0.0
    for label, M in _SPLIT_INPUTS:
        got, fb = _call(func, name, (M,), f"split({label})", _SPLIT_HINT)
        if fb is not None:
            return fb
        try:
            S, K = got
        except Exception:  # noqa: BLE001 -- a checker never raises
            return _fail(name, f"On {label} it returned a {type(got).__name__} that does not "
                               "unpack into two matrices.", "Return a pair: `return S, K`.")
        for what, X in (("S", S), ("K", K)):
            problem = _shape_problem(X, (3, 3), f"On {label}, {what}")
            if problem:
                return _fail(name, problem, "S and K are 3x3 arrays, like M.")
        S, K = np.asarray(S, dtype=float), np.asarray(K, dtype=float)
        scale = 1e-12 * max(1.0, float(np.abs(M).max()))
        sym = float(np.abs(S - S.T).max())
        skew = float(np.abs(K + K.T).max())
        total = float(np.abs(S + K - M).max())
        if sym <= scale and skew <= scale and total <= scale:
            worst_inner = max(worst_inner, abs(float(np.sum(S * K))))
            if worst_inner > scale:                     # cannot happen: the proof
                return _fail(name, f"On {label}, tr(S^T K) = {worst_inner:.2g}, not 0.")
            continue
        if np.abs(S + S.T).max() <= scale and np.abs(K - K.T).max() <= scale:
            why = f"On {label}, your S is skew and your K symmetric: they are swapped."
            return _fail(name, why, "S is the symmetric part (S^T = S), K the skew part (K^T = -K).")
        if sym <= scale and skew <= scale and np.abs(S + K - 2 * M).max() <= 2 * scale:
            why = (f"On {label}, S is symmetric and K is skew, but S + K is 2M, not M.")
            return _fail(name, why, "M + M^T = 2S: divide by two.")
        parts = []
        if sym > scale:
            parts.append(f"S is not symmetric (S - S^T is {sym:.2g} in its largest entry)")
        if skew > scale:
            parts.append(f"K is not skew (K + K^T is {skew:.2g} in its largest entry)")
        if total > scale:
            parts.append(f"S + K differs from M by {total:.2g}")
        return _fail(name, f"On {label}: " + "; ".join(parts) + ".", _SPLIT_HINT)
    inner = "0 on each" if worst_inner == 0 else "below 1e-12 on each (0 up to rounding)"
    return Feedback(True, f"Correct: {name}. S is symmetric, K is skew and S + K = M for "
                          f"{len(_SPLIT_INPUTS)} matrices; and tr(S^T K) is {inner}, as your "
                          "proof says.")


# ---------------------------------------------------------------- exercise 1.2

_I_PLUS_HAT_HINT = ("I and hat(a) commute, so the binomial theorem expands (I + hat(a))^4 into "
                    "powers hat(a)^0 to hat(a)^4, each with its binomial coefficient. Then "
                    "the Lemma, hat(a)^3 = -|a|^2 hat(a), and the same times hat(a), bring "
                    "the third and fourth powers down to hat(a) and hat(a)^2. Here "
                    "|a|^2 = 1 + 4 + 9 = 14.")


@never_raises("(c0, c1, c2) for (I + hat(a))^4")
def check_power_of_i_plus_hat(answer):
    r"""Exercise 1.2: ``(c0, c1, c2)`` with
    :math:`(I + \hat a)^4 = c_0 I + c_1\hat a + c_2\hat a^2` for ``a = (1, 2, 3)``.

    Compares ``c0 I + c1 hat(a) + c2 hat(a)^2`` with ``(I + hat(a))^4`` multiplied out by a
    matrix power (exact in floats: integers below 2^53). Recognises the usual slips by
    what the learner's combination is: ``I + hat(a)^4`` (the binomial coefficients
    dropped), ``I + hat(a) + ... + hat(a)^4`` (all coefficients 1), the Lemma used with the
    wrong sign, ``|a|`` in place of ``|a|^2``, and the fourth power left out; and handing in
    a matrix, one number or text. A wrong combination is not measured against the right
    one (the size of the difference would give the answer away).
    """
    name = "(c0, c1, c2) for (I + hat(a))^4"
    if answer is None or answer is Ellipsis:
        return _fail(name, _NOT_ANSWERED)
    if isinstance(answer, (str, bytes)):
        return _fail(name, f"The answer is text ({type(answer).__name__}), not numbers: "
                           "write the three numbers themselves, without quotes.",
                     _I_PLUS_HAT_HINT)
    try:
        if any(x is Ellipsis for x in answer):
            return _fail(name, "Some of the three numbers are still `...`.", _I_PLUS_HAT_HINT)
    except TypeError:
        pass
    if np.iscomplexobj(answer):
        return _fail(name, "The answer contains a complex number; c0, c1, c2 are real.",
                     _I_PLUS_HAT_HINT)
    try:
        c = np.asarray(answer, dtype=float)
    except Exception:  # noqa: BLE001 -- a checker never raises
        return _fail(name, f"The answer is a {type(answer).__name__}, not three numbers.",
                     _I_PLUS_HAT_HINT)
    H = hat(A_12)
    H2 = H @ H
    target = np.linalg.matrix_power(np.eye(3) + H, 4)
    if c.shape == (3, 3):
        right = np.allclose(c, target, rtol=1e-12, atol=0)
        verdict = "and that matrix is right" if right else "but it is not (I + hat(a))^4"
        return _fail(name, f"You gave a 3x3 matrix, {verdict}. The exercise asks for the "
                           "three numbers c0, c1, c2 of I, hat(a) and hat(a)^2.",
                     _I_PLUS_HAT_HINT)
    if c.shape != (3,):
        return _fail(name, f"The answer has shape {c.shape}; it should be three numbers, "
                           "(c0, c1, c2).", _I_PLUS_HAT_HINT)
    if not np.isfinite(c).all():
        return _fail(name, "The answer contains NaN or inf.", _I_PLUS_HAT_HINT)

    def combo(k):
        return k[0] * np.eye(3) + k[1] * H + k[2] * H2

    got = combo(c)
    if np.allclose(got, target, rtol=1e-12, atol=0):
        return Feedback(True, f"Correct: {name}. c0 I + c1 hat(a) + c2 hat(a)^2 equals "
                              "(I + hat(a))^4 multiplied out.")
    H3, H4 = H2 @ H, H2 @ H2
    n2 = float(A_12 @ A_12)
    slips = [
        (np.eye(3) + H4, "It is I + hat(a)^4: the middle terms of the binomial expansion "
                         "are missing. (I + X)^4 is not I + X^4."),
        (np.eye(3) + H + H2 + H3 + H4, "It is I + hat(a) + hat(a)^2 + hat(a)^3 + hat(a)^4: "
                                       "the binomial coefficients are missing."),
        (np.eye(3) + 4 * H + 6 * H2 + 4 * (n2 * H) + n2 * H2,
         "The Lemma was used with the wrong sign: hat(a)^3 is MINUS |a|^2 hat(a)."),
        (np.eye(3) + 4 * H + 6 * H2 - 4 * np.sqrt(n2) * H - np.sqrt(n2) * H2,
         "The Lemma was used with |a| where it has |a|^2."),
        (np.eye(3) + 4 * H + 6 * H2 + 4 * H3,
         "The fourth power, hat(a)^4, is missing from the expansion."),
        (np.eye(3) + 4 * H + 6 * H2 + H4,
         "The third power, 4 hat(a)^3, is missing from the expansion."),
    ]
    for matrix, why in slips:
        if np.allclose(got, matrix, rtol=1e-12, atol=0):
            return _fail(name, why, _I_PLUS_HAT_HINT)
    why = "c0 I + c1 hat(a) + c2 hat(a)^2 is not (I + hat(a))^4 (multiplied out)."
    if np.allclose(got, target, rtol=1e-3, atol=0):
        why += (" It is close, but the Lemma gives whole numbers exactly: no rounding is "
                "needed.")
    return _fail(name, why, _I_PLUS_HAT_HINT)


# ---------------------------------------------------------------- exercise 1.3

def _power_hint(p):
    """The hint for a wrong answer at ``p``: which formula applies, never its value there
    (with the vector shown, ``k`` and the formula written out would be the answer)."""
    if p == 0:
        return ("hat(a)^0 is the identity I, by the definition of a matrix power; it is "
                "not covered by the formula for even powers, which starts at p = 2 "
                "(p = 0 would need k = -1).")
    if p % 2:
        return (f"p = {p} is odd, so (1.7) applies: write p = 2k + 1 and find k. Which of "
                "c0, c1, c2 can be nonzero for an odd power? |a|^(2k) is (a @ a)**k: no "
                "square root is needed.")
    return (f"p = {p} is even and at least 2, so (1.8) applies: write p = 2k + 2 and find k. "
            "Which of c0, c1, c2 can be nonzero for an even power? |a|^(2k) is (a @ a)**k: "
            "no square root is needed.")


#: The hint for a wrong answer on the zero vector, where hat(a) = 0: the formulas hold as
#: they stand (``0.0 ** 0`` is 1), and an answer that divides by ``|a|`` breaks.
_ZERO_HINT = ("At a = 0, hat(a) is the zero matrix, and (1.7) and (1.8) hold as they stand "
              "(|a|^0 = (a @ a)**0 = 1): nothing needs dividing by |a|. And hat(a)^0 is "
              "still I.")


#: Names whose use means the matrix power is computed (or fitted), not the formula
#: (exercise 1.3): powers and functions of a matrix (``funm(H, lambda x: x**p)`` is the
#: power), the ways to fit three coefficients to one, and the ready-made hat (``hat``, or
#: ``cross`` with the identity).
_MATRIX_ROUTE = frozenset({"matrix_power", "fractional_matrix_power", "funm", "expm", "eig",
                           "lstsq", "solve", "pinv", "inv", "hat", "cross"})


def _matrix_route(func):
    """``(names, helpers)``: the names of :data:`_MATRIX_ROUTE` that ``func``'s code refers
    to, and the learner's own functions through which it does.

    Followed: code objects nested in it (inner functions, lambdas, comprehensions), the
    functions it closes over, and the functions of the learner's namespace (its
    ``__globals__``) that it names, recursively. A name bound there to a matrix route
    under another name (``mp = np.linalg.matrix_power``) counts by the function's own
    ``__name__``; a function of the learner's own is followed, never counted by its name
    (a helper called ``solve`` that computes the formula is fine). Both sets are empty when
    ``func`` has no code."""
    code = getattr(func, "__code__", None)
    if code is None:
        return set(), set()
    space = getattr(func, "__globals__", {})
    found, helpers, seen = set(), set(), set()
    todo = [(code, None)]

    def own(obj):
        """A function defined in the learner's namespace."""
        return getattr(obj, "__globals__", None) is space and hasattr(obj, "__code__")

    def follow(obj, name, via):
        """A function of the learner's is followed; a matrix route renamed is a hit."""
        if own(obj):
            todo.append((obj.__code__, name))
        elif getattr(obj, "__name__", None) in _MATRIX_ROUTE:
            found.add(obj.__name__)
            if via is not None:
                helpers.add(via)

    for cell in getattr(func, "__closure__", None) or ():
        try:
            inner = cell.cell_contents
        except ValueError:                                     # an empty cell
            continue
        follow(inner, getattr(inner, "__name__", "a closure"), None)
    while todo:
        c, via = todo.pop()
        if id(c) in seen:
            continue
        seen.add(id(c))
        hits = {n for n in _MATRIX_ROUTE & set(c.co_names) if not own(space.get(n))}
        if hits:
            found.update(hits)
            if via is not None:
                helpers.add(via)
        todo.extend((k, via) for k in c.co_consts if hasattr(k, "co_names"))
        for n in c.co_names:
            if n in space:
                follow(space[n], n, via)
    return found, helpers


@never_raises("power_coefficients")
def check_power_coefficients(func):
    r"""Exercise 1.3: ``func(a, p)`` must return ``(c0, c1, c2)`` with
    :math:`\hat a^p = c_0 I + c_1\hat a + c_2\hat a^2`.

    The defining property is tested directly: ``c0 I + c1 hat(a) + c2 hat(a)^2`` against
    ``np.linalg.matrix_power(hat(a), p)``, relative to the size of the power, for
    ``p = 1, ..., 12`` and then ``p = 0``, on two vectors of different length and on the
    zero vector (an answer that divides by ``|a|`` gives NaN there), and then for
    ``p = 400`` on ``a = (0.6, 0, 0.8)``. It stops at the first wrong answer with a hint
    for that ``p`` (on the zero vector, a hint for ``a = 0``).

    The exercise asks for the formulas (1.7) and (1.8), so a function whose code names a
    matrix route (:data:`_MATRIX_ROUTE`: a matrix power or function (``funm`` too), ``eig``,
    a fit with ``lstsq``, ``solve``, ``pinv`` or ``inv``, ``hat``, ``cross``) is refused: in
    its own code, in a function defined inside it, in a function of the notebook it calls, or
    under another name (see :func:`_matrix_route`). A hand-written loop of ``@`` products
    is not seen, nor is ``matmul``: ``a @ a`` (or ``np.matmul(a, a)``) is also how the
    formula computes ``|a|^2``.

    A wrong answer is named (the sign, or simply "not the power") and followed by the hint
    for that ``p``; the size of the difference is not printed, since from it and the
    learner's own coefficient the right one could be worked out.
    """
    name = "power_coefficients"
    used, helpers = _matrix_route(func)
    if used:
        via = f" (inside {', '.join(sorted(helpers))})" if helpers else ""
        return _fail(name, f"Your code calls {', '.join(sorted(used))}{via}: that is the "
                           "matrix route (a matrix power, or a fit to one), and the exercise "
                           "asks for the formula.",
                     "Use (1.7) and (1.8): only the number |a|^2 = a @ a and the parity "
                     "of p are needed.")
    vectors = (np.array([1.0, 2.0, 3.0]), np.array([0.5, -1.0, 0.25]), np.zeros(3))
    cases = [(p, a) for p in list(range(1, 13)) + [0] for a in vectors]
    cases.append((400, np.array([0.6, 0.0, 0.8])))     # |a|^2 = 1 exactly in floats
    for p, a in cases:
        shown = f"power_coefficients({np.array2string(a, separator=', ')}, {p})"
        hint = _power_hint(p) if a.any() else _ZERO_HINT
        got, fb = _call(func, name, (a, p), shown, hint)
        if fb is not None:
            return fb
        problem = _shape_problem(got, (3,), f"On {shown}, the answer")
        if problem:
            if "complex" in problem:                    # (-1)**k or x**k with k = 0.5, ...
                return _fail(name, problem + " A power x**k with a non-integer k (such as "
                             "(-1)**0.5) gives a complex number.", hint)
            return _fail(name, problem,
                         "Return three numbers, (c0, c1, c2)." if a.any() else _ZERO_HINT)
        c = np.asarray(got, dtype=float)
        H = hat(a)
        power = np.linalg.matrix_power(H, p)
        combo = c[0] * np.eye(3) + c[1] * H + c[2] * (H @ H)
        size = max(1.0, float(np.abs(power).max()))
        if float(np.abs(combo - power).max()) > 1e-10 * size:
            if float(np.abs(combo + power).max()) <= 1e-10 * size:
                why = f"is minus hat(a)^{p} (multiplied out): the sign is wrong."
            else:
                why = f"is not hat(a)^{p} (multiplied out)."
            return _fail(name, f"On {shown}, c0 I + c1 hat(a) + c2 hat(a)^2 {why}", hint)
    return Feedback(True, f"Correct: {name}. c0 I + c1 hat(a) + c2 hat(a)^2 equals the matrix "
                          "power for p = 0, ..., 12 and three vectors a (one of them 0), and "
                          "for p = 400.")
