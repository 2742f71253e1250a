"""Issue 24: honest work handed in under the wrong name is found and graded, and
grades.csv's problem column says what was done (tools/grade.py's staging; no kernel runs)."""

import shutil
from pathlib import Path

import nbformat
import pytest

from tools import assignments, grade

FIXTURE = Path(__file__).parent / "fixtures" / "09_fixture_exercises.ipynb"
NAME = FIXTURE.stem


@pytest.fixture(scope="module")
def course(tmp_path_factory):
    out = tmp_path_factory.mktemp("course")
    assignments.build(out, [FIXTURE], release=False, log=lambda *a: None)
    return out


def _notebook(path):
    path.parent.mkdir(parents=True, exist_ok=True)
    shutil.copy(FIXTURE, path)


@pytest.mark.parametrize("layout, said", [
    ({f"{NAME}/{NAME} (1).ipynb"}, f"graded {NAME} (1).ipynb as {NAME}.ipynb"),
    ({f"{NAME}/{NAME}-Copy1.ipynb", f"{NAME}/Untitled.ipynb"},
     f"graded {NAME}-Copy1.ipynb as {NAME}.ipynb; also found Untitled.ipynb (not graded)"),
    ({f"{NAME}_final/{NAME}.ipynb"}, f"graded the folder {NAME}_final as {NAME}"),
    ({f"{NAME}.ipynb"}, f"graded {NAME}.ipynb, found loose in the student's folder"),
    ({f"{NAME}/Untitled.ipynb", f"{NAME}/notes.ipynb"},
     f"also found Untitled.ipynb (not graded); also found notes.ipynb (not graded); missing {NAME}.ipynb"),
])
def test_misnamed_copies_are_found_or_named(course, tmp_path, layout, said):
    submitted = tmp_path / "submitted"
    for rel in layout:
        _notebook(submitted / "s1" / rel)
    shutil.rmtree(course / "submitted", ignore_errors=True)
    jobs, problems = grade._stage(submitted, course, {NAME}, log=lambda *a: None)
    assert problems[("s1", NAME)] == said
    graded = (course / "submitted" / "s1" / NAME / f"{NAME}.ipynb").exists()
    assert graded == ("missing" not in said)
    assert (("s1", NAME) in jobs) == graded
    if graded:
        nbformat.read(str(course / "submitted" / "s1" / NAME / f"{NAME}.ipynb"), as_version=4)


def test_the_right_name_is_not_a_problem(course, tmp_path):
    submitted = tmp_path / "submitted"
    _notebook(submitted / "s1" / NAME / f"{NAME}.ipynb")
    shutil.rmtree(course / "submitted", ignore_errors=True)
    jobs, problems = grade._stage(submitted, course, {NAME}, log=lambda *a: None)
    assert jobs == [("s1", NAME)] and not problems


def test_grading_skips_only_figures_nothing_later_reads():
    """A hide-input cell as handed out is not run when grading, unless a later cell reads a
    name it binds; a learner's own cell, or an edited figure, always runs."""
    from nbformat.v4 import new_code_cell

    from tools.trusted_grader import figure_cells
    figure = {"tags": ["hide-input"]}
    cells = [new_code_cell("import numpy as np"),
             new_code_cell("fig, ax = plt.subplots()\nax.plot([1, 2])", metadata=figure),
             new_code_cell("xs = np.linspace(0, 1)\nfig, ax = plt.subplots()", metadata=figure),
             new_code_cell("fig, ax = plt.subplots()\nax.plot(xs)", metadata=figure),
             new_code_cell("ys = 2 * xs\nfig, ax = plt.subplots()", metadata=figure),
             new_code_cell("def f():\n    return ys")]
    handed_out = {c.source for c in cells[1:5]} - {cells[4].source}
    assert figure_cells(cells, handed_out) == {1, 3}


def _plan(sources, answer_at, test_at, learner, changed=()):
    """run_plan over code cells SOURCES, cell ANSWER_AT an answer and TEST_AT its test;
    the cells in CHANGED are not as handed out."""
    from nbformat.v4 import new_code_cell

    from tools.trusted_grader import run_plan
    cells = [new_code_cell(s) for s in sources]
    cells[answer_at].metadata["nbgrader"] = {"solution": True, "grade": False, "grade_id": "ex-answer"}
    cells[test_at].metadata["nbgrader"] = {"solution": False, "grade": True, "grade_id": "ex-test"}
    handed_out = {s for i, s in enumerate(sources) if i not in (answer_at, test_at, *changed)}
    return run_plan(cells, handed_out, set(learner))


def test_grading_runs_what_the_grade_reads_and_what_changes_it():
    """A cell handed out unchanged runs only the statements the answer, its test or the
    learner's function (when the test calls it) depend on: figures, the notebook's own
    checks and imports nothing reads are left out; a random generator's earlier draws,
    an object changed in place and a name bound again are followed."""
    sources = [
        "import numpy as np\nimport matplotlib.pyplot as plt\nimport sympy as sp",   # 0
        "rng = np.random.default_rng(1)\nscale = 2.0",                                  # 1
        "a = rng.normal(size=3)\nfig, ax = plt.subplots()\nax.plot(a)\nplt.show()",     # 2
        "x = sp.symbols('x')\nprint(sp.diff(x**2, x))",                                 # 3
        "table = []\ntable.append(scale)\nunused = 5",                                  # 4
        "scale = 3.0",                                                                   # 5
        "def f(v):\n    return scale * np.asarray(v) + table[0] + rng.normal()",        # 6 answer
        "print(check(f))",                                                               # 7 test
        "fig, ax = plt.subplots()\nax.plot([f(1)])",                                     # 8
    ]
    plan = _plan(sources, 6, 7, {"f"})
    assert set(plan) == {0, 1, 2, 4, 5, 6, 7}
    assert plan[0] == "import numpy as np"
    assert plan[1] == sources[1]
    assert plan[2] == "a = rng.normal(size=3)"          # rng's state: its draws still run
    assert plan[4] == "table = []\ntable.append(scale)"
    assert plan[5] == "scale = 3.0"


def test_grading_runs_in_full_what_it_cannot_read():
    """A cell the learner changed, one with IPython syntax, exec, global or open runs in
    full, and so does every statement before it that binds what it reads."""
    sources = ["import numpy as np\nk = 2\nj = 3",
               "%time y = k",
               "exec('z = j')",
               "def f(v):\n    return v",
               "print(check(f))",
               "w = 1\nfig = None"]
    plan = _plan(sources, 3, 4, {"f"})
    assert plan[1] == sources[1] and plan[2] == sources[2]
    assert plan[0] == sources[0]
    assert 5 not in plan
    changed = _plan(sources, 3, 4, {"f"}, changed=(5,))
    assert changed[5] == sources[5]                    # the learner's own: always run
