"""Checkers of notebook 02 (so3lib.exercises.rodrigues): right answers pass; missing,
raising, wrong-shape, NaN and typical wrong answers get a helpful message, never an
exception, and no message gives the answer away."""

import inspect
import math
import warnings

import numpy as np
import pytest
from checker_support import not_written as _not_written
from checker_support import says_for as _says

import so3lib
from so3lib.exercises import rodrigues
from so3lib.exercises.rodrigues import check_B, check_naive_B_digits, check_partial_sum, check_printed_ex


def test_module_holds_no_answer():
    public = [n for n, f in inspect.getmembers(rodrigues, inspect.isfunction)
              if f.__module__ == rodrigues.__name__ and not n.startswith("_")]
    assert sorted(public) == sorted(rodrigues.__all__), public
    assert all(n.startswith("check_") for n in public), public


# ------------------------------------------------------------------ 2.1 partial sums

def _by_hand(omega, tau, terms):
    K = tau * so3lib.hat(omega)
    term, total = np.eye(3), np.eye(3)
    for m in range(1, terms):
        term = term @ K / m
        total = total + term
    return total


def test_partial_sum_right_answers_pass():
    fb = check_partial_sum(_by_hand)
    assert fb and repr(fb).startswith("Correct: partial_sum"), repr(fb)


def _wraps_exp_series(omega, tau, terms):
    return so3lib.exp_series(omega, tau, terms)


@pytest.mark.parametrize("student, pattern", [
    (so3lib.exp_series, "so3lib's own exp_series"),
    (_wraps_exp_series, "calls exp_series"),
    (lambda w, t, n: (lambda: so3lib.exp_series(w, t, n))(), "calls exp_series"),
])
def test_partial_sum_notices_the_forbidden_exp_series(student, pattern):
    _says(check_partial_sum(student), "partial_sum", pattern)


_series_alias = so3lib.exp_series             # a learner's `from so3lib import exp_series as es`


def _calls_an_alias(omega, tau, terms):
    return _series_alias(omega, tau, terms)


def _calls_through_getattr(omega, tau, terms):
    return getattr(so3lib, "exp_" + "series")(omega, tau, terms)


@pytest.mark.parametrize("student", [_calls_an_alias, _calls_through_getattr])
def test_partial_sum_notices_exp_series_under_another_name(student):
    _says(check_partial_sum(student), "partial_sum", "calls exp_series")


def test_partial_sum_watch_leaves_no_profile_hook_behind():
    import sys
    check_partial_sum(_calls_an_alias)
    check_partial_sum(_by_hand)
    assert sys.getprofile() is None


def _elementwise(omega, tau, terms):
    K = tau * so3lib.hat(omega)
    return sum(K ** m / math.factorial(m) for m in range(terms))


@pytest.mark.parametrize("student, pattern", [
    (None, "No answer yet"),
    (..., "No answer yet"),
    (_not_written, "Not written yet"),
    (lambda w, t, n: np.linalg.inv(np.zeros((3, 3))), "raised LinAlgError"),
    (lambda w, t, n: np.eye(2), r"shape \(2, 2\); it should have shape \(3, 3\)"),
    (lambda w, t, n: np.full((3, 3), np.nan), "NaN or inf"),
    (lambda w, t, n: _by_hand(w, t, n + 1), "You summed 2 terms instead of 1"),
    (lambda w, t, n: _by_hand(w, t, n - 1) if n > 1 else np.eye(3), "summed 1 terms instead of 2"),
    (_elementwise, r"raises each ENTRY"),
    (lambda w, t, n: sum(np.linalg.matrix_power(t * so3lib.hat(w), m) for m in range(n)),
     r"divided by m!"),
    (lambda w, t, n: _by_hand(w, 1.0, n), r"multiply hat\(omega\) by tau"),
    (lambda w, t, n: so3lib.exp(w, t), r"off by(.|\n)*Hint: partial_sum\(omega, tau, N\) is the sum"),
])
def test_partial_sum_wrong_answers_get_a_message(student, pattern):
    _says(check_partial_sum(student), "partial_sum", pattern)


def test_partial_sum_message_shows_no_matrix():
    text = repr(check_partial_sum(lambda w, t, n: so3lib.exp(w, t)))
    assert "[[" not in text and "expected" not in text, text


# ------------------------------------------------------------------ 2.2 eight digits

def test_naive_B_digits_predicted_and_measured_answers_pass():
    eps = np.finfo(float).eps
    predicted = math.sqrt((eps / 4) / (1e-8 / 2))      # (eps/4) / (x^2/2) = 1e-8
    for x in (predicted, 1e-4, 1.2e-4):
        fb = check_naive_B_digits(x)
        assert fb and repr(fb).startswith("Correct: x_8_digits"), repr(fb)


def test_naive_B_digits_verdict_does_not_use_the_machines_cos(monkeypatch):
    """The checker rounds cos x itself: a maths library whose cos is only faithful (one
    float off) changes neither the measured errors nor the verdict."""
    xs = np.geomspace(1e-4 / 1.25, 1.25e-4, 201)
    before = rodrigues._naive_B_error(xs)
    real_cos = np.cos
    monkeypatch.setattr(np, "cos", lambda x: np.nextafter(real_cos(x), 0.0))   # one float low
    assert np.array_equal(rodrigues._naive_B_error(xs), before)
    assert repr(check_naive_B_digits(1.05e-4)).startswith("Correct: x_8_digits")


@pytest.mark.parametrize("answer, pattern", [
    (None, "No answer yet"),
    (..., "No answer yet"),
    ("small", "one number"),
    (-1e-4, "positive angle"),
    (float("nan"), "positive angle"),
    ("1e-4", "one number"),
    (2.0, "accurate to about 16 digits"),
    (1e-12, "returns 0"),
    (1e-8, "returns 0|too small"),
    (1e-5, "too small"),
    (1e-3, "too large"),
])
def test_naive_B_digits_wrong_answers_get_a_message(answer, pattern):
    _says(check_naive_B_digits(answer), "x_8_digits", pattern)


def test_naive_B_digits_never_says_minus_zero_digits():
    text = repr(check_naive_B_digits(1e-8))
    assert "about 0.0 correct digits" in text and "-0.0" not in text, text


def test_naive_B_digits_message_does_not_give_the_t():
    for answer in (1e-5, 1e-3, 2.0):
        text = repr(check_naive_B_digits(answer))
        assert "1e-04" not in text and "0.0001" not in text and "1.05e-04" not in text, text


# ------------------------------------------------------------------ 2.3 stable B

def test_B_right_answers_pass():
    def half_angle(x):
        return 0.5 if x == 0 else 2 * (math.sin(x / 2) / x) ** 2

    def three_terms_then_half_angle(x):
        return 0.5 - x * x / 24 + x ** 4 / 720 if abs(x) < 1e-2 \
            else 2 * (math.sin(x / 2) / x) ** 2
    for func in (half_angle, three_terms_then_half_angle):
        fb = check_B(func)
        assert fb and repr(fb).startswith("Correct: B_stable"), repr(fb)


@pytest.mark.parametrize("student, pattern", [
    (so3lib.B, "so3lib's own B"),
    (lambda x: so3lib.B(x), "calls B"),
    (lambda x: float(so3lib.B(x)) + 0.0, "calls B"),
])
def test_B_notices_the_forbidden_library_B(student, pattern):
    _says(check_B(student), "B_stable", pattern)


_B_alias = so3lib.B                           # a learner's `from so3lib import B as B_lib`


@pytest.mark.parametrize("student", [
    lambda x: float(_B_alias(x)),
    lambda x: float(getattr(so3lib.series, "".join("B"))(x)),
])
def test_B_notices_the_library_B_under_another_name(student):
    _says(check_B(student), "B_stable", r"calls so3lib\.B")


def test_B_may_call_other_library_functions():
    def via_sin_only(x):                     # so3lib.A is not ruled out
        return 0.5 if x == 0 else float(so3lib.A(x / 2)) ** 2 / 2
    fb = check_B(via_sin_only)
    assert fb and repr(fb).startswith("Correct: B_stable"), repr(fb)


def _naive(x):
    return (1 - math.cos(x)) / x ** 2


def _naive_numpy(x):
    with np.errstate(all="ignore"):
        return (1 - np.cos(np.float64(x))) / np.float64(x) ** 2


def _no_limit(x):
    return 2 * (math.sin(x / 2) / x) ** 2


def _taylor_below(limit, terms=2):
    def B_(x):
        if abs(x) < limit:
            return 0.5 - x * x / 24 + (x ** 4 / 720 if terms == 3 else 0.0)
        return 2 * (math.sin(x / 2) / x) ** 2
    return B_


@pytest.mark.parametrize("student, pattern", [
    (None, "No answer yet"),
    (..., "No answer yet"),
    (_not_written, "Not written yet"),
    (lambda x: math.log(-1), "raised ValueError"),
    (lambda x: np.array([x, x]), r"shape \(2,\); it should have shape \(\)"),
    (lambda x: float("nan"), "NaN or inf"),
    (_naive, r"B_stable\(1e-08\)(.|\n)*naive \(1 - cos x\)/x\^2"),
    (_naive_numpy, r"naive"),
    (_no_limit, r"B_stable\(0\) raised ZeroDivisionError(.|\n)*limit 1/2"),
    (lambda x: 0.5 - x * x / 24, r"B_stable\(1\)(.|\n)*Taylor polynomial"),
    (lambda x: math.sin(x) / x, r"That is A\(x\)"),
    (lambda x: (1 - math.cos(x)) / x, r"denominator is x\^2"),
    # the middle range: a Taylor branch kept too far out (issue: 7e-5 relative at x = 0.4)
    (_taylor_below(0.45), r"relative error(.|\n)*Taylor polynomial"),
    (_taylor_below(0.45, terms=3), r"relative error(.|\n)*Taylor polynomial"),
    (_taylor_below(0.02), r"B_stable\(0.01\)(.|\n)*Taylor polynomial"),
])
def test_B_wrong_answers_get_a_message(student, pattern):
    with warnings.catch_warnings():
        warnings.simplefilter("error")          # and the checker itself warns about nothing
        fb = check_B(student)
    _says(fb, "B_stable", pattern)


@pytest.mark.parametrize("student, x_shown", [
    (_taylor_below(1e-2), r"0\.0049"),            # 2.7e-11 relative at x = 0.0099
    (_taylor_below(0.1, terms=3), r"0\.099"),     # 4.9e-11 relative at x = 0.0999
])
def test_B_refuses_a_Taylor_branch_kept_just_too_long(student, x_shown):
    fb = check_B(student)
    _says(fb, "B_stable", r"B_stable\(-?" + x_shown + r"\)(.|\n)*Taylor polynomial")
    text = repr(fb)
    assert "expected" not in text and "0.49" not in text, text


@pytest.mark.parametrize("student", [_taylor_below(4.5e-3), _taylor_below(0.055, terms=3)])
def test_B_refuses_a_Taylor_branch_kept_a_little_too_long(student):
    """Off by 1.1e-12 (2 terms up to 4.5e-3) and 1.4e-12 (3 terms up to 0.055) at their
    worst: the sweep every 1% finds more than the 1e-12 asked, and says so in words that
    do not read "1.0e-12, asked 1e-12"."""
    _says(check_B(student), "B_stable",
          r"relative error just above the 1e-12(.|\n)*Taylor polynomial")


def _naive_far_from_0(x):
    """The half-angle form near 0 and the naive one beyond 0.5: it cancels again next to
    every multiple of 2 pi (at 2 pi itself cos x rounds to 1 and it returns 0)."""
    if abs(x) > 0.5:
        return (1 - math.cos(x)) / x ** 2
    return 0.5 if x == 0 else 2 * (math.sin(x / 2) / x) ** 2


def test_B_refuses_the_naive_form_next_to_multiples_of_2pi():
    _says(check_B(_naive_far_from_0), "B_stable",
          r"B_stable\(6\.28319\)(.|\n)*naive(.|\n)*multiple of 2 pi")

    def spares_2pi(x):                      # right at the float 2 pi only: refused nearby
        return 2 * (math.sin(x / 2) / x) ** 2 if x == 2 * math.pi else _naive_far_from_0(x)
    _says(check_B(spares_2pi), "B_stable", r"B_stable\(-6\.28719\) has a relative error")


@pytest.mark.parametrize("start, x_shown", [(20.0, r"25\.1327"), (30.0, r"6283\.19"),
                                            (1e4, r"6\.28319e\+06"), (1e7, r"6\.28319e\+09")])
def test_B_refuses_a_naive_branch_kept_only_far_out(start, x_shown):
    """A naive branch only above 20 (beyond 6 pi + 0.002), 30 (the end of the plain
    range), 1e4 or 1e7 is wrong next to 8 pi, 2000 pi, 2e6 pi and 2e9 pi: refused there."""
    def far_naive(x):
        if abs(x) > start:
            return (1 - math.cos(x)) / x ** 2
        return 0.5 if x == 0 else 2 * (math.sin(x / 2) / x) ** 2
    _says(check_B(far_naive), "B_stable", rf"B_stable\({x_shown}\) has a relative error")


def test_B_typed_as_displayed_hears_about_the_squares_that_underflow():
    """2*sin(x/2)**2/x**2, with B(0) = 1/2 apart, divides 0 by 0 at 1e-300: the hint is
    about the squares, not the formula the learner already typed."""
    def as_displayed(x):
        return 0.5 if x == 0 else 2 * math.sin(x / 2) ** 2 / x ** 2
    _says(check_B(as_displayed), "B_stable",
          r"B_stable\(1e-300\) raised ZeroDivisionError(.|\n)*subnormal(.|\n)*Divide before")


def test_B_names_no_mistake_it_cannot_tell_apart():
    """At x = 1 a denominator x equals x^2, and a 0 returned at 1e-300 matches
    (1 - cos x)/x there: neither may be called "the denominator is x^2, not x"."""
    single = check_B(lambda x: float(np.float32(_taylor_below(1e-4)(x))))     # float32
    _says(single, "B_stable", r"B_stable\(1\) has a relative error")
    assert "denominator" not in repr(single), repr(single)

    def zero_at_tiny(x):
        return 0.0 if 0 < abs(x) < 1e-200 else _taylor_below(1e-4)(x)
    tiny = check_B(zero_at_tiny)
    _says(tiny, "B_stable", r"B_stable\(1e-300\) has a relative error")
    assert "denominator" not in repr(tiny), repr(tiny)


def test_B_refuses_a_string():
    _says(check_B(lambda x: str(_taylor_below(1e-4)(x))), "B_stable", "is a str, not a number")


def test_B_message_shows_no_expected_value():
    text = repr(check_B(_taylor_below(0.45)))
    assert "expected" not in text and "0.49" not in text, text


# ------------------------------------------------------------------ notebook 02 in step

def _notebook_02_prose():
    import json
    from pathlib import Path
    path = Path(__file__).resolve().parent.parent / "notebooks" / "02_rodrigues_from_the_series.ipynb"
    cells = json.loads(path.read_text(encoding="utf-8"))["cells"]
    return "\n".join("".join(c["source"]) for c in cells if c["cell_type"] == "markdown")


def test_notebook_02_describes_exp_as_the_library_computes_it():
    """Section 6 of notebook 02 teaches the one-tangent form of so3lib.exp; the docstring
    of exp and the constants of so3lib.series must say the same, or this test fails."""
    from so3lib import series
    prose = _notebook_02_prose()
    doc = so3lib.exp.__doc__
    # one tangent, no Taylor branch, up to 1e145: notebook and docstring
    assert r"t = \tan h" in prose and "t = tan(h)" in doc
    assert "10^{145}" in prose and "1e145" in doc
    assert "no Taylor branch" in prose.replace("No Taylor branch", "no Taylor branch")
    assert "no Taylor branch" in doc
    # so3lib.B keeps the textbook forms, with Taylor below 1e-4
    assert series._TAYLOR_BELOW == 1e-4
    assert r"Taylor below $10^{-4}$" in prose
    # words of the algorithm exp no longer uses, and of SciPy's expm as a plain series
    for stale in ("half-angle B up to", "unit-axis form", "sums a short series",
                  "no float method can promise"):
        assert stale not in prose, stale
    assert "Padé" in prose and "Al-Mohy" in prose


def test_notebook_02_names_the_argument_of_A_and_B_x():
    """Section 5 and its exercises write A(x), B(x), keeping t for tan(theta/2) in
    section 6; the exercise names in the notebook are the ones the checkers report."""
    import json
    from pathlib import Path
    path = Path(__file__).resolve().parent.parent / "notebooks" / "02_rodrigues_from_the_series.ipynb"
    cells = json.loads(path.read_text(encoding="utf-8"))["cells"]
    code = "\n".join("".join(c["source"]) for c in cells if c["cell_type"] == "code")
    prose = _notebook_02_prose()
    assert r"$A(x) = \sin x/x$" in prose and r"$B(x) = (1 - \cos x)/x^2$" in prose
    assert "x_8_digits = ..." in code and "check_naive_B_digits(x_8_digits)" in code
    assert "t_8_digits" not in code and "def B_stable(x):" in code
    assert "x_8_digits" in repr(check_naive_B_digits(None))


def test_exercise_2_3_range_in_the_notebook_covers_the_checkers_points():
    """Exercise 2.3 asks for 1e-12 for |x| <= 1e10: every point the checker tries lies in
    that range, and there B is a normal float that the divide-first solution meets."""
    import mpmath

    from so3lib.exercises.rodrigues import _B_INPUTS
    assert r"for every $|x| \le 10^{10}$" in _notebook_02_prose()
    assert max(abs(x) for x in _B_INPUTS) <= 1e10
    rng = np.random.default_rng(23)
    for x in list(10 ** rng.uniform(-300, 10, 300)) + [2 * math.pi * 1e9, 1e10]:
        with mpmath.workdps(40 + max(0, int(-2 * math.log10(x)))):
            ref = (1 - mpmath.cos(mpmath.mpf(x))) / mpmath.mpf(x) ** 2
        got = 0.5 - x * x / 24 if x < 1e-4 else 2 * (math.sin(x / 2) / x) ** 2
        assert float(ref) > 2.2e-308
        assert abs(got - float(ref)) <= 4 * 2.2e-16 * float(ref), x


def test_exercise_2_3_says_how_many_points_the_checker_tries():
    """The statement of exercise 2.3 gives the number of x the checker tries, as its
    success message does: the notebook fails this test when the list changes."""
    from so3lib.exercises.rodrigues import _B_INPUTS
    n = len(_B_INPUTS)
    assert f"at {n} values of $x$" in _notebook_02_prose()
    assert f"at {n} values of x" in repr(check_B(lambda x: 0.5 - x * x / 24 if abs(x) < 1e-4
                                                 else 2 * (math.sin(x / 2) / x) ** 2))


# ------------------------------------------------------------- exercise 2.2: check_printed_ex

def _printed_ex_by_hand():
    """The notes' printed line on e_x for omega = (0, 0, pi/2), tau = 1, worked by hand:
    e_x + e_y + (2/pi) e_y."""
    return np.array([1.0, 1.0 + 2.0 / math.pi, 0.0])


def test_printed_ex_accepts_the_hand_computation():
    fb = check_printed_ex(_printed_ex_by_hand())
    assert fb.passed, fb.message
    assert fb.message.startswith("Correct")


@pytest.mark.parametrize("answer, words", [
    (np.array([0.0, 1.0, 0.0]), "corrected (2.6)"),
    (np.array([1.0, 2.0, 0.0]), "divided by |omega|^2"),
    (np.array([1.0, 1.0 + math.pi / 2, 0.0]), "division was left out"),
    (np.array([1.0, 1.0, 0.5]), "z component"),
    (np.array([0.5, 1.0, 0.0]), "x component"),
    (np.array([1.0, 1.2, 0.0]), "y component"),
])
def test_printed_ex_names_the_slip(answer, words):
    fb = check_printed_ex(answer)
    assert not fb.passed and words in fb.message, fb.message
    assert "1.63" not in fb.message and "0.636" not in fb.message   # never the value looked for


@pytest.mark.parametrize("answer", [..., None, "1, 1.6, 0", [1.0, 2.0], np.full(3, np.nan),
                                    [[1.0, 0.0, 0.0]], object()])
def test_printed_ex_never_raises(answer):
    fb = check_printed_ex(answer)
    assert not fb.passed and fb.message.startswith("Not yet")
