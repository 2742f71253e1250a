"""Peak memory of batched calls: under twice the size of their result.

The performance issue's bound. tracemalloc sees NumPy's allocations, so the peak it
records during one call (the result included) is what the call costs in memory; the
kernels work in blocks of a few thousand rotations, so their temporaries stay small.
A memory test, not a timing test: it does not depend on the machine.
"""

import numpy as np
import pytest

import so3lib
from benchmark import peak_memory_ratio   # the bench reports the same measure

N = 100_000


@pytest.fixture(scope="module")
def batch():
    phi = np.random.default_rng(5).standard_normal((N, 3)) * 1.5
    return phi, so3lib.exp(phi)


@pytest.mark.parametrize("call", [
    lambda phi, R: so3lib.exp(phi),
    lambda phi, R: so3lib.exp(phi, 0.25),
    lambda phi, R: so3lib.log(R),
    lambda phi, R: so3lib.log(R, -2.0),
    lambda phi, R: so3lib.angle(R),
], ids=["exp", "exp tau", "log", "log tau", "angle"])
def test_peak_memory_is_under_twice_the_result(batch, call):
    ratio = peak_memory_ratio(lambda: call(*batch))
    assert ratio < 2.0, f"peak memory {ratio:.2f} x the result"
