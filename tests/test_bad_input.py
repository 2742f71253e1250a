"""Every public function refuses bad input with a ValueError that says what and why."""

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
    (lambda: so3lib.random_rotation(rng="seed"), r"Generator, an int seed or None"),
    (lambda: so3lib.random_rotation(0, size=-2), r"nonnegative int"),
    (lambda: so3lib.random_rotation(0, size=(2, "x")), r"size as None"),
    (lambda: so3lib.exp_series([1.0, 0.0, 0.0], terms=0), r"terms as an int >= 1"),
    (lambda: so3lib.exp_series([1.0, 0.0, 0.0], terms=2.5), r"terms as an int >= 1"),
    (lambda: so3lib.exp_series([1.0, 0.0], terms=3), r"exp_series expects omega of shape"),
    (lambda: so3lib.A(np.nan), r"A expects finite numbers; t has NaN"),
    (lambda: so3lib.B([1.0, np.inf]), r"B expects finite numbers; t has an infinite value at index \[1\]"),
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
