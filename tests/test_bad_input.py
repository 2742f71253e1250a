"""Every public function refuses bad input with a ValueError that says what and why.

The first table holds single cases; the tables after it hold classes of bad input (the
library issue's list): each class is tried on every argument of every public function
that takes numbers, in the manner of Sophus's tables of hard cases.
"""

import warnings

import numpy as np
import pytest

import so3lib
from so3lib import so2

NAN_VEC = [0.1, np.nan, 0.3]
INF_MAT = np.eye(3)
INF_MAT[1, 2] = np.inf
REFLECTION = np.diag([1.0, 1.0, -1.0])
SCALED = 1.01 * so3lib.exp([0.1, 0.2, 0.3])
SHEARED = np.array([[1.0, 0.1, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]])

BAD = [
    # (call, regex the message must match)
    (lambda: so3lib.hat([1.0, 2.0]), r"hat expects v of shape \(\.\.\., 3\).*got shape \(2,\)"),
    (lambda: so3lib.hat(np.ones((4, 2))), r"got shape \(4, 2\)"),
    (lambda: so3lib.hat(5.0), r"got shape \(\)"),
    (lambda: so3lib.hat(NAN_VEC), r"finite.*NaN at index \[1\]"),
    (lambda: so3lib.hat([1j, 0, 0]), r"real numbers; got complex"),
    (lambda: so3lib.hat(["a", "b", "c"]), r"real numbers"),
    (lambda: so3lib.hat([[1, 2, 3], [4, 5]]), r"could not read"),
    (lambda: so3lib.vee(np.ones((3, 4))), r"vee expects M of shape \(\.\.\., 3, 3\).*\(3, 4\)"),
    (lambda: so3lib.vee(np.eye(3)), r"skew-symmetric"),
    (lambda: so3lib.vee(INF_MAT), r"infinite value at index \[1, 2\]"),
    (lambda: so3lib.exp([1.0, 2.0]), r"exp expects omega of shape \(\.\.\., 3\)"),
    (lambda: so3lib.exp(np.ones((5, 2))), r"batch of them; got shape \(5, 2\)"),
    (lambda: so3lib.exp(NAN_VEC), r"NaN"),
    (lambda: so3lib.exp([1.0, 0, 0], np.nan), r"tau has NaN"),
    (lambda: so3lib.exp([1.0, 0, 0], np.inf), r"tau has an infinite value"),
    (lambda: so3lib.exp([1e200, 0, 0], 1e200), r"overflows"),
    (lambda: so3lib.exp([1.5e308, 1.5e308, 1.5e308]), r"overflows"),
    (lambda: so3lib.log(np.ones((3, 4))), r"log expects R of shape \(\.\.\., 3, 3\).*\(3, 4\)"),
    (lambda: so3lib.log([1.0, 2.0, 3.0]), r"got shape \(3,\)"),
    (lambda: so3lib.log(REFLECTION), r"det = -1: a reflection"),
    (lambda: so3lib.log(SCALED), r"not orthogonal.*rotation scaled by 1\.01"),
    (lambda: so3lib.log(np.zeros((3, 3))), r"zero matrix"),
    (lambda: so3lib.log(SHEARED), r"not orthogonal: max\|R\^T R - I\| = 1\.00e-01"),
    (lambda: so3lib.log(np.stack([np.eye(3), np.eye(3), REFLECTION])), r"R\[2\] has det = -1"),
    (lambda: so3lib.log(np.stack([[np.eye(3)], [SCALED]])), r"R\[1, 0\] is not orthogonal"),
    (lambda: so3lib.log(np.eye(3), 0.0), r"tau must be nonzero; got tau = 0"),
    (lambda: so3lib.log(np.eye(3), [1.0, 0.0]), r"tau = 0 \(at index \[1\]\)"),
    (lambda: so3lib.log(np.eye(3), tol=-1), r"tol as a finite nonnegative number"),
    (lambda: so3lib.log(np.full((3, 3), np.nan)), r"NaN at index \[0, 0\]"),
    (lambda: so3lib.angle(REFLECTION), r"angle expects rotation matrices"),
    (lambda: so3lib.angle(np.ones((2, 2))), r"angle expects R of shape"),
    (lambda: so3lib.is_rotation(np.ones((3, 4))), r"is_rotation expects R of shape"),
    (lambda: so3lib.is_rotation(np.eye(3), tol="small"), r"tol as a nonnegative number"),
    (lambda: so3lib.random_rotation(rng="seed"), r"Generator, a nonnegative int seed or None"),
    (lambda: so3lib.random_rotation(0, size=-2), r"nonnegative int"),
    (lambda: so3lib.random_rotation(0, size=(2, "x")), r"size as None"),
    (lambda: so3lib.exp_series([1.0, 0.0, 0.0], terms=0), r"terms as an int >= 1"),
    (lambda: so3lib.exp_series([1.0, 0.0, 0.0], terms=2.5), r"terms as an int >= 1"),
    (lambda: so3lib.exp_series([1.0, 0.0], terms=3), r"exp_series expects omega of shape"),
    (lambda: so3lib.A(np.nan), r"A expects finite numbers; x has NaN"),
    (lambda: so3lib.B([1.0, np.inf]), r"B expects finite numbers; x has an infinite value at index \[1\]"),
    (lambda: so2.hat([np.nan]), r"so2.hat expects finite numbers; w has NaN"),
    (lambda: so2.vee(np.ones((3, 3))), r"so2.vee expects W of shape \(\.\.\., 2, 2\)"),
    (lambda: so2.vee(np.eye(2)), r"skew-symmetric"),
    (lambda: so2.exp(np.inf), r"so2.exp expects finite numbers; theta"),
    (lambda: so2.exp(1e300, 1e300), r"overflows"),
    (lambda: so2.log(np.eye(3)), r"so2.log expects R of shape \(\.\.\., 2, 2\)"),
    (lambda: so2.log(np.diag([1.0, -1.0])), r"reflection"),
    (lambda: so2.log(2 * np.eye(2)), r"scaled by 2"),
    (lambda: so2.log(np.eye(2), 0), r"tau must be nonzero"),
    (lambda: so2.to_complex(np.array([[1.0, 2.0], [3.0, 4.0]])), r"form a I \+ b J"),
    (lambda: so2.to_complex(np.ones(2)), r"shape \(\.\.\., 2, 2\)"),
    (lambda: so2.from_complex(complex(np.nan, 0)), r"finite complex"),
    (lambda: so2.from_complex("1+2j"), r"complex numbers"),
]


@pytest.mark.parametrize("call, message", BAD, ids=[m for _, m in BAD])
def test_bad_input_raises_value_error_with_message(call, message):
    with pytest.raises(ValueError, match=message):
        call()


def test_times_that_do_not_broadcast_are_refused_with_both_shapes():
    with pytest.raises(ValueError, match=r"exp expects tau .* batch shape \(4,\) of omega; got tau of shape \(3,\)"):
        so3lib.exp(np.ones((4, 3)), np.ones(3))
    with pytest.raises(ValueError, match=r"log expects tau .* batch shape \(2,\) of R; got tau of shape \(5,\)"):
        so3lib.log(np.stack([np.eye(3)] * 2), np.ones(5))


def test_rounding_noise_is_accepted():
    """A rotation carrying 1e-13 noise is a rotation; its log is the log of the clean one."""
    R = so3lib.exp([0.3, -0.2, 0.9])
    noisy = R + 1e-13 * np.random.default_rng(1).uniform(-1, 1, (3, 3))
    assert so3lib.is_rotation(noisy)
    assert np.allclose(so3lib.log(noisy), [0.3, -0.2, 0.9], rtol=0, atol=1e-12)
    assert so2.log(so2.exp(0.5) + 1e-13) == pytest.approx(0.5, abs=1e-12)


def test_tolerance_is_the_documented_one():
    """ROTATION_TOL separates float32-rounded rotations (kept) from typed decimals."""
    R = so3lib.exp([0.3, -0.2, 0.9])
    assert so3lib.ROTATION_TOL == 1e-6
    assert so3lib.is_rotation(R.astype(np.float32))
    typed = np.round(so3lib.exp([0.0, 0.0, np.pi / 4]), 4)       # 0.7071, four digits
    assert not so3lib.is_rotation(typed)
    assert so3lib.is_rotation(typed, tol=1e-3)
    assert np.allclose(so3lib.log(typed, tol=1e-3), [0, 0, np.pi / 4], atol=1e-4)


def test_check_false_skips_only_the_group_test():
    assert np.isfinite(so3lib.log(SCALED, check=False)).all()
    with pytest.raises(ValueError, match="shape"):
        so3lib.log(np.ones((3, 4)), check=False)
    with pytest.raises(ValueError, match="NaN"):
        so3lib.log(np.full((3, 3), np.nan), check=False)
    assert np.array_equal(so3lib.vee(np.eye(3), check=False), [0.0, 0.0, 0.0])


def test_is_rotation_answers_without_raising_for_non_rotations():
    batch = np.stack([np.eye(3), REFLECTION, SCALED, np.zeros((3, 3))])
    assert so3lib.is_rotation(batch).tolist() == [True, False, False, False]
    assert so3lib.is_rotation(np.eye(3)) is True


# ---------------------------------------------------------------------------------------
# Classes of input that are not real numbers, tried on every public function.
# Each argument kind has a valid value; a class turns it into a bad one of the same shape.

GOOD = {"vector": [0.1, 0.2, 0.3], "matrix": np.eye(3), "plane": np.eye(2), "scalar": 0.5,
        "complex": 1j}


def _shape(kind):
    return np.shape(GOOD[kind])


def _one_entry(kind, value):
    """The valid value of ``kind`` as a list (a 1-element list for a scalar), with its
    first entry replaced by ``value``."""
    good = np.array(GOOD[kind], dtype=object).reshape(-1)
    good[0] = value
    return good.reshape(_shape(kind) or (1,)).tolist()


NOT_NUMBERS = {   # class -> (builder from an argument kind, regex of the message)
    "datetime64": (lambda k: np.full(_shape(k), np.datetime64("2026-01-01")),
                   r"dates or times \(dtype datetime64\[D\]\)"),
    "timedelta64": (lambda k: np.full(_shape(k), np.timedelta64(3, "s")),
                    r"dates or times \(dtype timedelta64\[s\]\)"),
    "strings": (lambda k: np.full(_shape(k), "0.1").tolist(), r"got text \(dtype <U3\)"),
    "bytes": (lambda k: np.full(_shape(k), b"1"), r"got text \(dtype \|S1\)"),
    "structured dtype": (lambda k: np.zeros(_shape(k), dtype=[("x", float)]),
                         r"structured array with fields \('x',\)"),
    "string among numbers": (lambda k: _one_entry(k, "0.1"), r"got text \(dtype <U\d+\)"),
    "object of another kind": (lambda k: _one_entry(k, {"x": 1}), r"is a dict, not a number"),
    "masked array": (lambda k: np.ma.array(GOOD[k], mask=np.ones(_shape(k), bool)),
                     r"masked array, whose mask would be ignored"),
    "None": (lambda k: None, r"numbers; got None"),
    "None among numbers": (lambda k: _one_entry(k, None), r"\S+\[0(, 0)?\] is None"),
    "int too large for a float": (lambda k: _one_entry(k, 10**400),
                                  r"int with 401 digits, too large for a float"),
    "33 batch axes": (lambda k: np.reshape(GOOD[k], (1,) * 33 + _shape(k)),
                      r"at most 32 batch axes; \w+ has 33"),
}

ARGUMENTS = [   # (label, argument kind, call with the bad value in that argument)
    ("hat(v)", "vector", lambda x: so3lib.hat(x)),
    ("vee(M)", "matrix", lambda x: so3lib.vee(x)),
    ("exp(omega)", "vector", lambda x: so3lib.exp(x)),
    ("exp(omega, tau)", "scalar", lambda x: so3lib.exp([0.1, 0.2, 0.3], x)),
    ("log(R)", "matrix", lambda x: so3lib.log(x)),
    ("log(R, check=False)", "matrix", lambda x: so3lib.log(x, check=False)),
    ("log(R, tau)", "scalar", lambda x: so3lib.log(np.eye(3), x)),
    ("log(R, tol=)", "scalar", lambda x: so3lib.log(np.eye(3), tol=x)),
    ("angle(R)", "matrix", lambda x: so3lib.angle(x)),
    ("is_rotation(R)", "matrix", lambda x: so3lib.is_rotation(x)),
    ("exp_series(omega)", "vector", lambda x: so3lib.exp_series(x)),
    ("exp_series(omega, tau)", "scalar", lambda x: so3lib.exp_series([0.1, 0.2, 0.3], x)),
    ("A(t)", "scalar", lambda x: so3lib.A(x)),
    ("B(t)", "scalar", lambda x: so3lib.B(x)),
    ("so2.hat(w)", "scalar", lambda x: so2.hat(x)),
    ("so2.vee(W)", "plane", lambda x: so2.vee(x)),
    ("so2.exp(theta)", "scalar", lambda x: so2.exp(x)),
    ("so2.exp(theta, tau)", "scalar", lambda x: so2.exp(0.5, x)),
    ("so2.log(R)", "plane", lambda x: so2.log(x)),
    ("so2.log(R, tau)", "scalar", lambda x: so2.log(np.eye(2), x)),
    ("so2.to_complex(M)", "plane", lambda x: so2.to_complex(x)),
    ("so2.from_complex(z)", "complex", lambda x: so2.from_complex(x)),
]

# tol is a single number: it is read with float(), so only its own classes apply.
_SCALAR_ONLY = {"log(R, tol=)"}


def _cases():
    for cls, (build, message) in NOT_NUMBERS.items():
        for label, kind, call in ARGUMENTS:
            if label in _SCALAR_ONLY:
                continue
            if cls == "33 batch axes" and label.startswith(("so2.exp(theta, tau)", "exp(omega, tau)",
                                                            "exp_series(omega, tau)")):
                message_here = r"at most 32 batch axes; tau has 33"
            else:
                message_here = message
            yield pytest.param(build, kind, call, message_here, id=f"{cls}: {label}")


@pytest.mark.parametrize("build, kind, call, message", list(_cases()))
def test_non_numbers_are_refused_everywhere(build, kind, call, message):
    """Each class of non-number, in each argument: a ValueError naming it, no warning."""
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        with pytest.raises(ValueError, match=message):
            call(build(kind))


def test_complex_is_welcome_in_from_complex_only():
    assert np.array_equal(so2.from_complex([1j, 2]), [so2.J, 2 * np.eye(2)])
    assert np.array_equal(so2.from_complex(np.array([1j, 2], dtype=object)),
                          [so2.J, 2 * np.eye(2)])
    with pytest.raises(ValueError, match=r"real numbers; got complex values"):
        so3lib.exp([1j, 0, 0])


def test_numbers_in_other_containers_are_accepted():
    """Not refused: ints, float32, big ints that fit a float, Fractions, object arrays of
    numbers; they give the same rotation as the float64 input."""
    from fractions import Fraction
    R = so3lib.exp([0.5, 0.25, 2.0])
    for omega in ([Fraction(1, 2), 0.25, 2], np.array([0.5, 0.25, 2.0], dtype=np.float32),
                  np.array([0.5, 0.25, 2], dtype=object)):
        assert np.array_equal(so3lib.exp(omega), R)
    assert so3lib.exp([10**30, 0, 0]).shape == (3, 3)          # fits a float: accepted


# ---------------------------------------------------------------------------------------
# The other classes of the issue, each a table.

ROT = so3lib.exp([1.0, 2.0, 0.0])
ROTS = so3lib.exp(np.random.default_rng(3).standard_normal((20, 3)))

TINY_TAU = [   # log divides by tau: a tau so small that the quotient overflows
    (lambda: so3lib.log(ROT, 1e-310), r"log divides Log\(R\) by tau.*overflows float64: "
                                      r"tau = 1e-310 is too small"),
    (lambda: so3lib.log(ROT, 5e-324), r"tau = 4\.94e-324 is too small"),
    (lambda: so3lib.log(ROT, -5e-324), r"tau = -4\.94e-324 is too small"),
    (lambda: so3lib.log(ROTS, 1e-310), r"overflows float64 at index \[0\]"),
    (lambda: so3lib.log(ROTS, np.r_[np.ones(7), 1e-310, np.ones(12)]),
     r"overflows float64 at index \[7\]: tau = 1e-310"),
    (lambda: so2.log(so2.exp(2.0), 1e-310), r"so2.log divides the angle by tau.*1e-310 is too small"),
    (lambda: so2.log(so2.exp([2.0, 1.0]), [1.0, 5e-324]), r"at index \[1\]: tau = 4\.94e-324"),
]

HIDDEN_DEFECT = [   # messages print enough digits to show what is wrong
    (lambda: so3lib.log((1 + 4.9e-7) * np.eye(3)), r"det = 1\.0000015, which differs from \+1 "
                                                   r"by 1\.5e-06"),
    (lambda: so3lib.log((1 + 6e-7) * ROT, tol=1e-7), r"a rotation scaled by 1\.0000006\)"),
    (lambda: so3lib.log((1 - 6e-7) * ROT, tol=1e-7), r"a rotation scaled by 0\.9999994\)"),
    (lambda: so2.log((1 + 6e-7) * np.eye(2), tol=1e-7), r"scaled by 1\.0000006"),
    (lambda: so3lib.log(2 * ROT), r"a rotation scaled by 2\)"),
    (lambda: so3lib.exp(None), r"got None"),
    (lambda: so3lib.log([[1, 0, 0], [0, 1, 0], [0, 0, None]]), r"R\[2, 2\] is None"),
]

HUGE = [   # entries near the float limit: the right ValueError, and no RuntimeWarning first
    (lambda: so3lib.log(np.full((3, 3), 1e200)), r"entries as large as 1e\+200, so R\^T R "
                                                 r"overflows float64"),
    (lambda: so3lib.log(np.full((20, 3, 3), 1e200)), r"R\[0\] has entries as large as 1e\+200"),
    (lambda: so3lib.angle(np.full((3, 3), -1e300)), r"entries as large as 1e\+300"),
    (lambda: so2.log(np.full((2, 2), 1e200)), r"entries as large as 1e\+200"),
    (lambda: so3lib.vee(np.full((3, 3), 1.7e308)), r"max\|M \+ M\^T\|/2 = 1\.70e\+308"),
    (lambda: so3lib.vee(np.full((20, 3, 3), 1.7e308)), r"M\[0\] has max\|M \+ M\^T\|/2"),
    (lambda: so2.vee(np.full((2, 2), 1.7e308)), r"max\|W \+ W\^T\|/2 = 1\.70e\+308"),
    (lambda: so3lib.exp([1e200, 0, 0], 1e200), r"omega \* tau overflows float64"),
    (lambda: so3lib.exp(np.full((20, 3), 1e200), 1e200), r"overflows float64 at index \[0\]"),
]

BROADCAST = [   # a tau that does not broadcast: so3lib's message in so2 as in so3
    (lambda: so2.exp(np.ones(3), np.ones(2)), r"so2.exp expects tau as a scalar or an array "
                                              r"that broadcasts against the batch shape \(3,\) "
                                              r"of theta; got tau of shape \(2,\)"),
    (lambda: so2.log(np.stack([np.eye(2)] * 3), np.ones(2)), r"so2.log expects tau .* batch "
                                                             r"shape \(3,\) of R; got tau of "
                                                             r"shape \(2,\)"),
]

RANDOM_ARGS = [   # random_rotation's size and rng: only the documented types
    (lambda: so3lib.random_rotation(0, size=True), r"size as None, a nonnegative int or a "
                                                   r"tuple of them; got True \(bool\)"),
    (lambda: so3lib.random_rotation(0, size=2.7), r"got 2\.7 \(float\)"),
    (lambda: so3lib.random_rotation(0, size="3"), r"got '3' \(str\)"),
    (lambda: so3lib.random_rotation(0, size=(2, 1.0)), r"got \(2, 1\.0\) \(tuple\)"),
    (lambda: so3lib.random_rotation(0, size=10**400), r"size as None"),
    (lambda: so3lib.random_rotation(0, size=(1,) * 33), r"at most 32 batch axes"),
    (lambda: so3lib.random_rotation(rng=True), r"rng as a numpy.random.Generator, a "
                                               r"nonnegative int seed or None; got True"),
    (lambda: so3lib.random_rotation(rng=1.5), r"got 1\.5 \(float\)"),
    (lambda: so3lib.random_rotation(rng=-1), r"got -1 \(int\)"),
]

CLASSES = {"tiny tau": TINY_TAU, "hidden defect": HIDDEN_DEFECT, "huge entries": HUGE,
           "tau broadcast": BROADCAST, "random_rotation arguments": RANDOM_ARGS}


@pytest.mark.parametrize("call, message", [
    pytest.param(call, message, id=f"{cls}: {message[:40]}")
    for cls, table in CLASSES.items() for call, message in table])
def test_classes_are_refused_with_what_was_wrong(call, message):
    with warnings.catch_warnings():
        warnings.simplefilter("error")          # no RuntimeWarning before the ValueError
        with pytest.raises(ValueError, match=message):
            call()


def test_tiny_tau_is_fine_where_nothing_overflows():
    """Refused only where the quotient overflows: Log(I) / 1e-310 is 0."""
    assert np.array_equal(so3lib.log(np.eye(3), 1e-310), [0.0, 0.0, 0.0])
    assert so2.log(np.eye(2), 1e-310) == 0.0
    assert np.isfinite(so3lib.log(so3lib.exp([1e-10, 0, 0]), 1e-300)).all()


def test_huge_entries_answer_false_without_warning():
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        assert so3lib.is_rotation(np.full((3, 3), 1e200)) is False
        assert not so3lib.is_rotation(np.full((20, 3, 3), 1e200)).any()


def test_log_of_minus_identity_without_check_is_documented():
    """-I is a reflection and has no logarithm; check=False returns (pi, 0, 0) silently,
    as log's docstring says in plain words."""
    assert "log(-np.eye(3), check=False)" in so3lib.log.__doc__
    assert "returns ``(pi, 0, 0)``" in so3lib.log.__doc__
    assert np.array_equal(so3lib.log(-np.eye(3), check=False), [np.pi, 0.0, 0.0])
    with pytest.raises(ValueError, match="det = -1: a reflection"):
        so3lib.log(-np.eye(3))
