"""The batched kernels give the same bits as one-rotation calls, on the hard cases too.

``exp``, ``log`` and ``angle`` run one kernel each over blocks of ``so3lib.so3._BLOCK``
rotations (one rotation is a block of one); the accuracy tests (test_accuracy.py) call
them one rotation at a time. Here the hard cases, and rotation vectors too long to square
(|phi| > 1e154), go through the blocks, mixed with ordinary rotations and placed on both
sides of a block boundary, and must come out identical.
"""

import doctest
import math
import re
from pathlib import Path

import numpy as np
import pytest

import so3lib
from cases import half_turns, hard_cases
from reference import exp_ref
from so3lib import so3

HUGE = [s * np.array(n) for s in (1e146, 1e200, 1e300)
        for n in ([1.0, 0.0, 0.0], [0.3, -0.5, 0.8], [-1.0, 2.0, 3.0])]
PHIS = np.array([phi for _, phi in hard_cases()] + HUGE)
ROTATIONS = np.array([exp_ref(phi) for _, phi in hard_cases()] + [R for *_, R in half_turns()])


def scatter(cases, ordinary):
    """``cases`` placed among ``ordinary`` rows, the first two on a block boundary."""
    n = len(ordinary)
    rng = np.random.default_rng(7)
    others = np.setdiff1d(np.arange(n), [so3._BLOCK - 1, so3._BLOCK])
    where = np.concatenate([[so3._BLOCK - 1, so3._BLOCK],
                            rng.choice(others, len(cases) - 2, replace=False)])
    batch = ordinary.copy()
    batch[where] = cases
    return batch, where


@pytest.mark.parametrize("tau", [1.0, 0.5, -3.0])
def test_exp_batch_equals_single_calls(rng, tau):
    phi, where = scatter(PHIS, rng.standard_normal((2 * so3._BLOCK + 37, 3)) * 2)
    R = so3lib.exp(phi, tau)
    assert not np.isnan(R).any()
    for k in np.concatenate([where, [0, len(phi) - 1]]):
        assert np.array_equal(R[k], so3lib.exp(phi[k], tau)), k


def test_exp_of_huge_vectors_is_a_rotation():
    R = so3lib.exp(np.array(HUGE))
    assert so3lib.is_rotation(R, tol=8 * np.finfo(float).eps).all()


@pytest.mark.parametrize("tau", [1.0, -2.5])
def test_log_and_angle_batch_equal_single_calls(rng, tau):
    R, where = scatter(ROTATIONS, so3lib.random_rotation(rng, 2 * so3._BLOCK + 37))
    L, theta = so3lib.log(R, tau), so3lib.angle(R)
    assert not np.isnan(L).any() and not np.isnan(theta).any()
    for k in np.concatenate([where, [0, len(R) - 1]]):
        assert np.array_equal(L[k], so3lib.log(R[k], tau)), k
        assert theta[k] == so3lib.angle(R[k]), k


@pytest.mark.parametrize("n", [1, 2, 9, 100])
def test_few_rotations_equal_their_batch(rng, n):
    """A short batch gives the same bits as a longer one and as one rotation at a time."""
    phi = rng.standard_normal((n + 1, 3)) * 2
    assert np.array_equal(so3lib.exp(phi[:-1]), so3lib.exp(phi)[:-1])
    R = so3lib.exp(phi)
    assert np.array_equal(so3lib.log(R[:-1]), so3lib.log(R)[:-1])
    assert np.array_equal(so3lib.angle(R[:-1]), so3lib.angle(R)[:-1])
    assert all(np.array_equal(so3lib.exp(phi[k]), so3lib.exp(phi)[k]) for k in range(n))
    assert all(np.array_equal(so3lib.log(R[k]), so3lib.log(R)[k]) for k in range(n))


def test_rotation_check_names_the_first_bad_matrix_in_a_later_block(rng):
    R = so3lib.random_rotation(rng, 2 * so3._BLOCK + 5)
    R[so3._BLOCK + 3] = np.diag([1.0, 1.0, -1.0])
    R[2 * so3._BLOCK + 1] = 2 * np.eye(3)
    with pytest.raises(ValueError, match=rf"R\[{so3._BLOCK + 3}\] has det = -1"):
        so3lib.log(R)
    ok = so3lib.is_rotation(R)
    assert np.flatnonzero(~ok).tolist() == [so3._BLOCK + 3, 2 * so3._BLOCK + 1]


def test_exp_overflow_is_reported_from_a_batch(rng):
    omega = rng.standard_normal((so3._BLOCK + 10, 3))
    omega[so3._BLOCK + 4] = [1e200, 0.0, 0.0]
    with pytest.raises(ValueError, match="rotation vector omega \\* tau overflows"):
        so3lib.exp(omega, 1e200)
    omega[so3._BLOCK + 4] = [1.5e308, 1.5e308, 1.5e308]
    with pytest.raises(ValueError, match="rotation angle .* overflows"):
        so3lib.exp(omega)


@pytest.mark.parametrize("omega, tau", [([1e258, 1e258, -1e258], 3.2e-259),
                                        ([1e-250, 2e-250, 0.0], 1e250),
                                        ([3.0, -1.0, 2.0], 1e-300)])
def test_exp_forms_omega_times_tau_first(omega, tau):
    """|omega|^2 may overflow or underflow where phi = omega * tau is ordinary: exp takes
    the product first, so exp(omega, tau) is exp(omega * tau), bit for bit."""
    omega = np.array(omega)
    R = so3lib.exp(omega, tau)
    assert np.isfinite(R).all()
    assert np.array_equal(R, so3lib.exp(omega * tau))
    assert np.array_equal(so3lib.exp(np.stack([omega] * 3), tau)[1], R)


# --- The docstrings and the README say what the kernels do --------------------------------

README = Path(__file__).resolve().parent.parent / "README.md"


def _readme_section(title):
    text = README.read_text(encoding="utf-8")
    start = text.index(f"\n## {title}\n")
    end = text.find("\n## ", start + 1)
    return text[start:end if end > 0 else None]


def test_exp_docstring_example_is_what_exp_computes():
    """exp's Notes show the one-tangent formula as an example; it runs here, bit for bit,
    from 1e-200 (no Taylor branch) to 1e140 (just below the unit-axis form)."""
    result = doctest.testmod(so3, optionflags=doctest.ELLIPSIS)
    assert result.failed == 0 and result.attempted >= 5


def test_docs_state_the_kernels_own_bound():
    """The one bound of exp's method, theta = 1e145, is the code's, in the docstrings and
    in the README; no Taylor branch is claimed for exp."""
    bound = f"{math.sqrt(so3._SQ_HI):.0e}".replace("e+", "e")            # '1e145'
    assert f"up to ``theta = {bound}``" in " ".join(so3lib.exp.__doc__.split())
    assert f"up to ``theta = {bound}``" in " ".join(so3lib.series.__doc__.split())
    lib = " ".join(_readme_section("The library in one screen").split())
    assert f"One tangent gives the whole matrix, for every angle from 0 up to θ = {bound}" in lib
    assert "There is no Taylor branch" in lib
    assert "Taylor" not in " ".join(so3lib.exp.__doc__.split()).replace("no Taylor branch", "")


def test_readme_performance_table_lists_every_size_of_the_goal():
    """The Performance section carries the goal's ratio table for every N of the bench."""
    perf = _readme_section("Performance")
    from benchmark import RATIO_SIZES
    for n in RATIO_SIZES:
        assert re.search(rf"^\| {n} \|", perf, re.M), n


def test_exp_never_returns_negative_zero():
    """Signed zeros in, no -0.0 out (printed as '-0.' it would unsettle notebooks)."""
    phi = np.array([[-0.0, 0.0, -1.0], [0.0, -0.0, 2.0], [-1.0, -0.0, 0.0], [-0.0, -0.0, -0.0],
                    [0.0, 0.0, -np.pi], [-3.0, 0.0, -0.0]])
    for R in (so3lib.exp(phi), *map(so3lib.exp, phi), so3lib.exp(phi, -1.0)):
        assert not (np.signbit(R) & (R == 0)).any()


def test_rotation_check_of_one_matrix_equals_its_batch(rng):
    """One matrix is checked in plain floats, a batch on arrays: the same defects, bit
    for bit, so log(R) and is_rotation (arrays) agree on every matrix, also near tol."""
    from so3lib.validation import _defects_one, rotation_defects
    R = so3lib.random_rotation(rng, 200) + 1e-7 * rng.standard_normal((200, 3, 3))
    R[:5] *= 1 + 1e-6 * np.arange(5)[:, None, None]
    R[7] = -R[7]
    orth, det = rotation_defects(R)
    for k in range(len(R)):
        assert _defects_one(R[k].ravel().tolist()) == (orth[k], det[k]), k
