"""The coursework (tools/assignments.py, tools/grade.py): nbgrader from the notebooks' tags.

One session fixture builds the course folder for two assignments (notebooks 01 and 04
once their exercises are tagged, else a small fixture notebook that follows the README's
convention), makes up submissions and grades them all in one run. The made-up students
cover, exercise by exercise, every row of issue 11's table: a right answer, a wrong one,
the stub left as it is, a checker redefined to print "Correct", a test cell deleted, a
test cell edited, a function that loops forever, one that raises, and a file that is not
JSON. Each score in build/grades.csv (and per exercise) is checked against what it must be.
"""

import ast
import csv
import html
import json
import re
from pathlib import Path

import nbformat
import pytest

from tools import assignments, grade
from tools.common import NOTEBOOKS, read

FIXTURE = Path(__file__).parent / "fixtures" / "09_fixture_exercises.ipynb"
REAL = [NOTEBOOKS / "01_hat_map_and_lemma.ipynb", NOTEBOOKS / "04_logarithm.ipynb"]
TIMEOUT = 10     # seconds a cell may run while grading the made-up submissions

RIGHT, WRONG, STUB, TAMPERED = "right", "wrong", "stub", "tampered"
DELETED, EDITED, LOOP, RAISES = "test-deleted", "test-edited", "loops", "raises"
FULL_MARKS = {RIGHT, DELETED}            # every other case scores 0 for that exercise
MIXED = [WRONG, STUB, TAMPERED, DELETED, EDITED, LOOP, RAISES]


def tagged(path):
    return any(assignments.ANSWER in assignments.tags(c) for c in read(path).cells)


def graded_notebooks():
    """The notebooks the whole loop runs on: 01 and 04 when tagged, else the fixture."""
    real = [p for p in REAL if p.exists() and tagged(p)]
    return real if len(real) == 2 else [FIXTURE]


def released_notebooks():
    """Every course notebook with exercises (release/ is checked for leaks in all of them)."""
    from tools.common import course_notebooks
    return sorted(set(graded_notebooks()) | {p for p in course_notebooks() if tagged(p)})


# --- made-up submissions --------------------------------------------------------------

def _bound_names(source):
    """(functions, values) that the stub defines."""
    tree = ast.parse(assignments._python(source))
    funcs = [n.name for n in tree.body if isinstance(n, ast.FunctionDef)]
    values = [t.id for n in tree.body if isinstance(n, ast.Assign) for t in n.targets
              if isinstance(t, ast.Name)]
    return funcs, values


def _checkers(check_source):
    tree = ast.parse(assignments._python(check_source))
    return sorted({n.func.id for n in ast.walk(tree) if isinstance(n, ast.Call)
                   and isinstance(n.func, ast.Name) and n.func.id not in {"print", "display"}})


def _wrong(ex):
    funcs, values = _bound_names(ex.answer.source)
    lines = [assignments._solution(ex), "import numpy as _np"]
    for f in funcs:
        lines += [f"_right_{f} = {f}", f"def {f}(*args, **kwargs):",
                  f"    return _np.asarray(_right_{f}(*args, **kwargs), dtype=float) * 2 + 1"]
    for v in values:
        lines.append(f"{v} = _np.asarray({v}, dtype=float) * 2 + 1")
    return "\n".join(lines)


def _answer(ex, case):
    funcs, values = _bound_names(ex.answer.source)
    if case in (RIGHT, DELETED):
        return assignments._solution(ex)
    if case in (WRONG, EDITED):
        return _wrong(ex)
    if case == TAMPERED:
        fake = [f"def {name}(*args, **kwargs):\n    print('Correct')\n    return True"
                for name in _checkers(ex.check.source)]
        return "\n\n".join([ex.answer.source, *fake, "print('Correct')"])
    if case == LOOP:
        body = [f"def {f}(*args, **kwargs):\n    while True:\n        pass" for f in funcs]
        return "\n".join(body or ["while True:\n    pass"])
    if case == RAISES:
        body = [f"def {f}(*args, **kwargs):\n    raise ZeroDivisionError('made up')" for f in funcs]
        return "\n".join(body + [f"{v} = 1 / 0" for v in values if not funcs])
    return ex.answer.source                       # STUB


def submission(released, found, cases):
    """The released notebook with exercise i answered as cases[i]."""
    nb = nbformat.from_dict(released)
    by_id = {ex.grade_id: (ex, case) for ex, case in zip(found, cases)}
    cells = []
    for cell in nb.cells:
        gid = cell.metadata.get("nbgrader", {}).get("grade_id", "")
        ex_id, _, kind = gid.rpartition("-")
        if ex_id in by_id:
            ex, case = by_id[ex_id]
            if kind == "answer":
                cell.source = _answer(ex, case)
            elif kind == "test" and case == DELETED:
                continue
            elif kind == "test" and case == EDITED:
                cell.source = "print('Correct')"
        cells.append(cell)
    nb.cells = cells
    return nb


def plan(found):
    """{student: cases, one per exercise}: every case at least once per assignment, in as
    few notebooks as the number of exercises allows (each one is a kernel run)."""
    students = {"s1-right": [RIGHT] * len(found)}
    rest, k = list(MIXED), 2
    while rest:
        students[f"s{k}-mixed"] = [rest.pop(0) if rest else RIGHT for _ in found]
        k += 1
    return students


# --- the one shared run -----------------------------------------------------------------

@pytest.fixture(scope="session")
def coursework(tmp_path_factory):
    root = tmp_path_factory.mktemp("coursework")
    course = root / "course"
    made = assignments.build(course, released_notebooks(), log=lambda *a: None)
    submitted = root / "submitted"
    expected = {}
    graded = {p.stem for p in graded_notebooks()}
    for name, found in made.items():
        if name not in graded:
            continue
        released = read(course / "release" / name / f"{name}.ipynb")
        for student, cases in plan(found).items():
            folder = submitted / student / name
            folder.mkdir(parents=True)
            nbformat.write(submission(released, found, cases), str(folder / f"{name}.ipynb"))
            expected[(student, name)] = {ex.grade_id: (ex.points if c in FULL_MARKS else 0, c)
                                         for ex, c in zip(found, cases)}
        bad = submitted / "s9-corrupt" / name
        bad.mkdir(parents=True)
        (bad / f"{name}.ipynb").write_text('{"cells": [{"cell_type": "code", "source": "x = ', encoding="utf-8")
        expected[("s9-corrupt", name)] = {ex.grade_id: (0, "corrupt") for ex in found}
    out = root / "grades.csv"
    grade.grade(submitted, course, timeout=TIMEOUT, notebook_timeout=300, out=out, log=lambda *a: None,
                jobs_at_once=2)
    with open(out, newline="") as fh:
        rows = list(csv.DictReader(fh))
    with open(root / "grades_by_exercise.csv", newline="") as fh:
        cells = list(csv.DictReader(fh))
    return {"course": course, "made": {k: v for k, v in made.items() if k in graded},
            "released": made, "rows": rows, "cells": cells, "expected": expected,
            "submitted": submitted}


def test_real_notebooks_are_tagged():
    """01 and 04 are the assignments the loop must run on (the fixture stands in until then)."""
    untagged = [p.name for p in REAL if not tagged(p)]
    assert not untagged, f"no cell tagged 'answer' yet in {untagged}: the loop ran on the fixture"


def _written_points(course, name):
    """The points of the written parts (graded by hand) of assignment NAME."""
    nb = read(course / "source" / name / f"{name}.ipynb")
    return sum(c.metadata["nbgrader"].get("points", 0) for c in nb.cells
               if c.metadata.get("nbgrader", {}).get("grade_id", "").endswith("-written"))


def test_grades_csv_has_every_score(coursework):
    rows, expected, made = coursework["rows"], coursework["expected"], coursework["made"]
    got = {(r["student_id"], r["assignment"]): r for r in rows}
    students = {s for s, _ in expected}
    set_ = {a for _, a in expected}          # issue 24: only the assignments handed in
    assert len(rows) == len(got) == len(students) * len(set_), \
        "one row per student and assignment that was set"
    for key, row in got.items():
        if key not in expected:                 # fewer exercises, fewer made-up students
            assert float(row["score"]) == 0 and row["problem"] == "no submission", row
    for key, per_exercise in expected.items():
        row = got[key]
        want = sum(points for points, _ in per_exercise.values())
        # a written part left as handed out scores 0 until it is graded by hand; it still
        # counts in the assignment's maximum
        assert float(row["score"]) == want, (key, row, per_exercise)
        written = _written_points(coursework["course"], key[1])
        assert float(row["max_score"]) == sum(ex.points for ex in made[key[1]]) + written, row


def test_each_exercise_scores_what_it_must(coursework):
    got = {(c["student_id"], c["assignment"], c["exercise"]): c for c in coursework["cells"]}
    for (student, name), per_exercise in coursework["expected"].items():
        for gid, (points, case) in per_exercise.items():
            cell = got[(student, name, f"{gid}-test")]
            assert float(cell["score"]) == points, (student, name, gid, case, cell)
            if points == 0:
                assert cell["reason"], f"no reason recorded for {student} {name} {gid} ({case})"
            if case == LOOP:
                assert "time limit" in cell["reason"], cell
            if case == "corrupt":
                assert "not a valid notebook" in cell["reason"], cell


def test_corrupt_notebook_is_reported_and_others_still_graded(coursework):
    rows = {(r["student_id"], r["assignment"]): r for r in coursework["rows"]}
    for name in coursework["made"]:
        assert "not a valid notebook" in rows[("s9-corrupt", name)]["problem"]
        assert rows[("s1-right", name)]["problem"] == ""
        page = coursework["course"] / "feedback" / "s9-corrupt" / name / "problem.html"
        assert "not a valid notebook" in page.read_text()


def test_feedback_shows_the_checkers_message(coursework):
    course = coursework["course"]
    for (student, name), per_exercise in coursework["expected"].items():
        cases = {case for _, case in per_exercise.values()}
        page = course / "feedback" / student / name / f"{name}.html"
        if "corrupt" in cases:
            assert not page.exists()
            continue
        text = page.read_text()
        if RIGHT in cases:
            assert "Correct" in text, page
        if STUB in cases or WRONG in cases:
            assert "Not yet" in text, page
        if LOOP in cases:
            assert "CellTimeoutError" in text, page
        assert "HIDDEN TESTS" not in text and "hidden-test" not in text, page
        hidden = [ln.strip() for ex in coursework["made"][name] for c in ex.hidden
                  for ln in c.source.splitlines() if ln.strip().startswith("#") and len(ln.strip()) > 12]
        assert not [ln for ln in hidden if html.escape(ln, quote=False) in text], page


# --- nothing leaks into release/ ---------------------------------------------------------

def _lines(text):
    return {ln.strip() for ln in text.splitlines() if len(ln.strip()) >= 12}


def _secrets(nb):
    """Lines only solutions, hidden tests and speaker notes hold, and what they print."""
    def secret(c):
        return assignments.tags(c) & {assignments.SOLUTION, assignments.HIDDEN} or assignments.is_notes(c)

    def texts(c):
        yield c.source
        for out in c.get("outputs", []):
            yield out.get("text", "")
            for value in out.get("data", {}).values():
                if isinstance(value, str):
                    yield value

    public = {ln for c in nb.cells if not secret(c) for t in texts(c) for ln in _lines(t)}
    return {ln for c in nb.cells if secret(c) for t in texts(c) for ln in _lines(t)} - public


def test_release_holds_no_solution_hidden_test_or_speaker_note(coursework):
    course = coursework["course"]
    assert sorted(coursework["released"]) == [p.stem for p in released_notebooks()]
    for path in released_notebooks():
        released = (course / "release" / path.stem / path.name).read_text()
        nb = read(course / "release" / path.stem / path.name)
        secrets = _secrets(read(path))
        shown = {ln for c in nb.cells for ln in _lines(c.source)}
        left = sorted(secrets & shown)
        assert not left, f"{path.name}: release shows {left[:5]}"
        assert "BEGIN SOLUTION" not in released and "HIDDEN TESTS" not in released
        assert not any(c.get("outputs") for c in nb.cells), "outputs could show an answer"
        assert not any(assignments.is_notes(c) for c in nb.cells)
        assert not any(assignments.tags(c) & {assignments.SOLUTION, assignments.HIDDEN} for c in nb.cells)
    # nothing else in release/ but the notebooks (and their pictures)
    for f in (course / "release").rglob("*"):
        assert f.is_dir() or f.suffix in {".ipynb", ".png", ".svg", ".jpg"}, f


def test_release_keeps_the_notebooks_own_stub(coursework):
    course = coursework["course"]
    for name, found in coursework["released"].items():
        nb = read(course / "release" / name / f"{name}.ipynb")
        answers = {c.metadata["nbgrader"]["grade_id"]: c for c in nb.cells
                   if c.metadata.get("nbgrader", {}).get("solution")}
        for ex in found:
            assert answers[f"{ex.grade_id}-answer"].source.strip() == ex.answer.source.strip()


# --- the conversion, without nbgrader (fast) ----------------------------------------------

def test_fixture_converts_as_the_readme_says():
    nb, found = assignments.source_notebook(read(FIXTURE), FIXTURE)
    assert [(ex.label, ex.points) for ex in found] == [("9.1", 2), ("9.2", 3), ("9.3", 2)]
    text = nbformat.writes(nb)
    assert "SPEAKER-NOTE-SECRET" not in text and "SOLUTION-PROSE-SECRET" not in text
    answer = next(c for c in nb.cells if c.metadata.get("nbgrader", {}).get("grade_id") == "ex9_1-answer")
    stub, solution = answer.source.split(assignments.BEGIN_SOLUTION)
    assert "raise NotImplementedError" in stub and "SOLUTION-CODE-SECRET" in solution
    assert "check_twice" not in solution, "the solution's trailing checker call is dropped"
    test = next(c for c in nb.cells if c.metadata.get("nbgrader", {}).get("grade_id") == "ex9_1-test")
    meta = test.metadata["nbgrader"]
    assert meta["grade"] and meta["locked"] and not meta["solution"] and meta["points"] == 2
    visible = re.sub(r"### BEGIN HIDDEN TESTS.*?### END HIDDEN TESTS\n?", "", test.source, flags=re.S)
    assert visible.strip() == "print(check_twice(twice))"
    assert "HIDDEN-TEST-SECRET" in test.source
    assert not any(c.get("outputs") for c in nb.cells)


@pytest.mark.parametrize("change, says", [
    (lambda cells: cells.pop(5), "no cell tagged 'check'"),
    (lambda cells: cells.pop(8), "no cell tagged 'hidden-test'"),
    (lambda cells: cells[5].metadata.update(tags=["check"]), "points-N"),
])
def test_a_broken_convention_is_named(change, says):
    nb = read(FIXTURE)
    change(nb.cells)
    with pytest.raises(assignments.ConventionError, match=re.escape(says)):
        assignments.source_notebook(nb, FIXTURE)


def test_every_tagged_course_notebook_converts():
    """Each course notebook with exercises follows the convention (no nbgrader run)."""
    from tools.common import course_notebooks
    for path in course_notebooks():
        nb = read(path)
        if tagged(path):
            _, found = assignments.source_notebook(nb, path)
            assert found, path.name


def test_unreadable_notebooks_are_named(tmp_path):
    bad = tmp_path / "x.ipynb"
    bad.write_text("{not json", encoding="utf-8")
    assert "not a valid notebook" in grade.unreadable(bad)
    good = tmp_path / "y.ipynb"
    good.write_text(json.dumps(nbformat.v4.new_notebook()), encoding="utf-8")
    assert grade.unreadable(good) is None


def test_the_build_never_writes_into_notebooks():
    for bad in [NOTEBOOKS, NOTEBOOKS / "x", NOTEBOOKS.parent]:
        with pytest.raises(SystemExit):
            assignments.build(bad, [FIXTURE], release=False)



def test_staging_sorts_out_what_cannot_be_graded(tmp_path):
    """Without nbgrader: a renamed download is graded under its name, an unreadable file
    is left out with its reason, a missing notebook and an unknown assignment are named."""
    course, dirs = tmp_path / "course", tmp_path / "in"
    (course / "source" / "A").mkdir(parents=True)
    nbformat.write(nbformat.v4.new_notebook(), str(course / "source" / "A" / "A.ipynb"))
    good = nbformat.writes(nbformat.v4.new_notebook())
    for student, name, text in [("ann", "A (1).ipynb", good), ("bo", "A.ipynb", "{oops"),
                                ("cy", "notes.txt", "x"), ("di", "A.ipynb", good)]:
        (dirs / student / "A").mkdir(parents=True)
        (dirs / student / "A" / name).write_text(text, encoding="utf-8")
    (dirs / "di" / "Z").mkdir()
    jobs, problems = grade._stage(dirs, course, {"A"}, log=lambda *a: None)
    assert sorted(jobs) == [("ann", "A"), ("di", "A")]
    assert (course / "submitted" / "ann" / "A" / "A.ipynb").exists()
    assert problems[("ann", "A")] == "graded A (1).ipynb as A.ipynb"
    assert "not a valid notebook" in problems[("bo", "A")]
    assert not (course / "submitted" / "bo" / "A" / "A.ipynb").exists()
    assert (dirs / "bo" / "A" / "A.ipynb").exists(), "the submitted folder is never changed"
    assert "missing A.ipynb" in problems[("cy", "A")]
    assert ("di", "Z") not in problems and ("di", "Z") not in jobs


def test_written_part_becomes_a_manually_graded_cell(tmp_path):
    """A task tagged `written` and `points-N` is followed by a markdown answer cell that
    nbgrader grades by hand (formgrader); the release keeps only its stub."""
    nb = read(FIXTURE)
    task = next(c for c in nb.cells if c.cell_type == "markdown" and "Exercise 9.1" in c.source)
    task.metadata["tags"] = sorted(set(task.metadata.get("tags", [])) | {"written", "points-2"})
    path = tmp_path / FIXTURE.name
    nbformat.write(nb, str(path))
    assignments.build(tmp_path / "course", [path], log=lambda *a: None)
    for edition in ("source", "release"):
        out = read(tmp_path / "course" / edition / path.stem / path.name)
        k = next(i for i, c in enumerate(out.cells) if "Exercise 9.1" in c.source)
        cell = out.cells[k + 1]
        meta = cell.metadata["nbgrader"]
        assert cell.cell_type == "markdown" and meta["grade_id"] == "ex9_1-written"
        assert meta["grade"] and meta["solution"] and meta["points"] == 2
        assert ("YOUR ANSWER HERE" in cell.source) == (edition == "release")
    from nbgrader.api import Gradebook
    with Gradebook(f"sqlite:///{tmp_path / 'course' / 'gradebook.db'}") as gb:
        cells = {c.name: (c.max_score, c.cell_type) for c in gb.find_notebook(path.stem, path.stem).grade_cells}
    assert cells["ex9_1-written"] == (2, "markdown")
