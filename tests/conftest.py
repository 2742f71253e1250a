"""Shared fixtures and the hypothesis profile of the test suite."""

import json
import os
from pathlib import Path

import numpy as np
import pytest
from hypothesis import HealthCheck, settings
from pass_record import REMEMBERED, PassRecord, tree_digest

# Derandomized: the same examples on every run, so CI never flakes; no example database
# is written into the working tree. HYPOTHESIS_PROFILE=thorough searches harder.
settings.register_profile("ci", derandomize=True, max_examples=80, deadline=None,
                          database=None, suppress_health_check=[HealthCheck.too_slow])
settings.register_profile("thorough", max_examples=5000, deadline=None, database=None)
settings.load_profile(os.environ.get("HYPOTHESIS_PROFILE", "ci"))

EPS = np.finfo(float).eps


# --- `make test`'s workers: the longest files first -------------------------------------
#
# `pytest -n N --dist loadfile` hands out whole files (a notebook under nbval is one too).
# xdist starts them in order of their number of tests, which put the few-test files with
# the long session fixtures (the book and its visits, the nbgrader runs, the student
# edition, the Binder venv) last, where one of them ran alone at the end while the other
# worker had finished. Here each file's time in the last such run (build/
# test-durations.json, written at the end of the run) decides instead: the longest goes
# first. In a fresh clone nothing is timed yet: then the files that build or drive an
# edition (FIRST_GUESS, seconds on a 2-core machine) and the notebooks go first. Which
# tests run, and where a file's tests run together, is unchanged.

DURATIONS = Path(__file__).resolve().parent.parent / "build" / "test-durations.json"
FIRST_GUESS = {"test_book_laptop.py": 180, "test_book_pdf.py": 140, "test_book_phone.py": 55,
               "test_book.py": 30, "test_assignments.py": 100, "test_slides.py": 80,
               "test_student_edition.py": 65, "test_binder.py": 55, "test_grading_sandbox.py": 50,
               "test_newcomer.py": 30, "test_browser.py": 35, "test_interactive.py": 25}
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
    name = Path(scope).name
    if name in REMEMBERED:
        _outcomes.setdefault(name, set()).add("failed" if report.failed else
                                              "skipped" if report.skipped else "passed")


# --- the slow edition files that passed on the same files (tests/pass_record.py) -----------
#
# The controller (or the only process) works out once which of REMEMBERED passed last time
# on the course's files as they are now, and hands its answer to xdist's workers, so that
# every process deselects the same tests. At the end of a run of whole files that passed,
# each such file that ran, with no test failed or skipped, is recorded.

ROOT = Path(__file__).resolve().parent.parent
_outcomes = {}
_remember = {}


def _whole_files(config):
    """Whether this run takes whole test files: no -k, -m, --deselect, --lf or node ids."""
    o = config.option
    return not (getattr(o, "keyword", "") or getattr(o, "markexpr", "") or getattr(o, "deselect", None)
                or getattr(o, "lf", False) or any("::" in str(a) for a in config.args))


def _remembered(config):
    """(key, files): the digest of the course's files now, and which REMEMBERED files need
    not run again (none under CI, TEST_FRESH or a selection of tests)."""
    if "files" not in _remember:
        if hasattr(config, "workerinput"):
            _remember["key"] = config.workerinput.get("remember_key")
            _remember["files"] = set(config.workerinput.get("remember_files", ()))
        else:
            fresh = os.environ.get("TEST_FRESH") or os.environ.get("CI")
            key = None if fresh else tree_digest(ROOT)
            record = PassRecord("test-files")
            _remember["key"] = key
            _remember["files"] = {f for f in REMEMBERED
                                  if key and _whole_files(config) and record.fresh(f, key)}
    return _remember["key"], _remember["files"]


@pytest.hookimpl(optionalhook=True)
def pytest_configure_node(node):
    key, files = _remembered(node.config)
    node.workerinput["remember_key"] = key
    node.workerinput["remember_files"] = sorted(files)


def pytest_collection_modifyitems(config, items):
    _, files = _remembered(config)
    drop = [item for item in items if item.path.name in files]
    if drop:
        config.hook.pytest_deselected(items=drop)
        items[:] = [item for item in items if item.path.name not in files]


def pytest_terminal_summary(terminalreporter, config):
    _, files = _remembered(config)
    if files:
        terminalreporter.write_line(
            "not run again, passed before on these same files (tests/pass_record.py; "
            "make test FRESH=1 runs them): " + ", ".join(sorted(files)))


def _record_passed_files(session):
    key, files = _remembered(session.config)
    if hasattr(session.config, "workerinput") or not key or session.exitstatus != 0 \
            or not _whole_files(session.config):
        return
    passed = {f: key for f, seen in _outcomes.items() if seen == {"passed"}}
    if passed:
        PassRecord("test-files").record(passed)


def pytest_sessionfinish(session):
    _record_passed_files(session)
    if session.exitstatus == pytest.ExitCode.NO_TESTS_COLLECTED and _remembered(session.config)[1]:
        session.exitstatus = pytest.ExitCode.OK    # all of it passed before on these files
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
