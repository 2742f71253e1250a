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
