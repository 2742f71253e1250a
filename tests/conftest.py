"""Shared fixtures and the hypothesis profile of the test suite."""

import os

import numpy as np
import pytest
from hypothesis import HealthCheck, settings

# Derandomized: the same examples on every run, so CI never flakes; no example database
# is written into the working tree. HYPOTHESIS_PROFILE=thorough searches harder.
settings.register_profile("ci", derandomize=True, max_examples=80, deadline=None,
                          database=None, suppress_health_check=[HealthCheck.too_slow])
settings.register_profile("thorough", max_examples=5000, deadline=None, database=None)
settings.load_profile(os.environ.get("HYPOTHESIS_PROFILE", "ci"))

EPS = np.finfo(float).eps


@pytest.fixture(scope="session")
def browser():
    """The one Chromium of this test process, shared by the book and browser tests and
    closed after all of them (skipped, or failed under CI, when there is none)."""
    from browser_support import close_shared_browser, shared_browser
    yield shared_browser()
    close_shared_browser()


@pytest.fixture
def rng():
    """One seeded generator per test: the same numbers on every run."""
    return np.random.default_rng(20261121)
