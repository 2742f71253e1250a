"""Shared fixtures and the hypothesis profile of the test suite."""

import json
import os
from pathlib import Path

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


# --- `make test`'s two workers: the longest files first ----------------------------------
#
# `pytest -n 2 --dist loadfile` hands out whole files (a notebook under nbval is one too).
# xdist starts them in order of their number of tests, which put the few-test files with
# the long session fixtures (the book and its visits, the nbgrader runs, the student
# edition, the Binder venv) last, where one of them ran alone at the end while the other
# worker had finished. Here each file's time in the last such run (build/
# test-durations.json, written at the end of the run) decides instead: the longest goes
# first. In a fresh clone nothing is timed yet: then the files that build or drive an
# edition (FIRST_GUESS, seconds on a 2-core machine) and the notebooks go first. Which
# tests run, and where a file's tests run together, is unchanged.

DURATIONS = Path(__file__).resolve().parent.parent / "build" / "test-durations.json"
FIRST_GUESS = {"test_book_laptop.py": 130, "test_book_pdf.py": 120, "test_book_phone.py": 70,
               "test_book.py": 60, "test_assignments.py": 90, "test_slides.py": 90,
               "test_student_edition.py": 60, "test_binder.py": 60, "test_grading_sandbox.py": 40,
               "test_newcomer.py": 30, "test_browser.py": 30, "test_interactive.py": 30}
_spent = {}


def _loadfile(config):
    return config.getoption("dist", "no") == "loadfile" and not hasattr(config, "workerinput")


@pytest.hookimpl(tryfirst=True, optionalhook=True)
def pytest_xdist_make_scheduler(config, log):
    if not _loadfile(config):
        return None
    from xdist.scheduler import LoadFileScheduling
    try:
        last = json.loads(DURATIONS.read_text())
    except (OSError, ValueError):
        last = {}

    class LongestFirst(LoadFileScheduling):
        """LoadFileScheduling that gives a worker the longest file left, not the next."""

        def _assign_work_unit(self, node):
            scope = max(self.workqueue, key=lambda s: (_seconds(s, last), len(self.workqueue[s])))
            self.workqueue.move_to_end(scope, last=False)
            super()._assign_work_unit(node)

    return LongestFirst(config, log)


def _seconds(scope, last):
    """The seconds SCOPE (a test file or a notebook) took last time, or a first guess."""
    if scope in last:
        return last[scope]
    name = Path(scope).name
    return FIRST_GUESS.get(name, 20 if name.endswith(".ipynb") else 0)


def pytest_runtest_logreport(report):
    scope = report.nodeid.split("::", 1)[0]
    _spent[scope] = _spent.get(scope, 0.0) + report.duration


def pytest_sessionfinish(session):
    if not _loadfile(session.config) or not _spent:
        return
    try:
        times = json.loads(DURATIONS.read_text())
    except (OSError, ValueError):
        times = {}
    times.update({scope: round(t, 2) for scope, t in _spent.items()})
    DURATIONS.parent.mkdir(parents=True, exist_ok=True)
    tmp = DURATIONS.with_name(f".{DURATIONS.name}.{os.getpid()}")
    tmp.write_text(json.dumps(times, indent=1, sort_keys=True) + "\n")
    os.replace(tmp, DURATIONS)


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


@pytest.fixture(scope="session")
def pages():
    """The built book's pages, index.html first (tests/book_support.py)."""
    from book_support import built
    return built()[0]


@pytest.fixture(scope="session")
def soups(pages):
    """Each built page's parsed HTML, by file name."""
    from book_support import built
    return built()[1]
