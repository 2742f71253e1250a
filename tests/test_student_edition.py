"""The student edition (tools/student.py): no solutions left, and it still runs.

It is built once per session into a temporary folder. Every cell tagged "solution" or
"hidden-test" must be gone, with its output, and none of its text may remain anywhere in
the edition; so must every speaker note; each exercise keeps its stub and its checker
call; and the edition runs top to bottom under nbval in lax mode (no cell raises) with
the checkers saying "not yet", not crashing (a notebook whose edition files are unchanged
since it last ran clean is not run again: tests/pass_record.py).
"""

import os
import subprocess
import sys

import nbformat
import pytest
from nbformat.v4 import new_code_cell, new_markdown_cell, new_notebook

from browser_support import ROOT
from pass_record import PassRecord, digest
from tools import roles, student
from tools.common import course_notebooks, read

NOTEBOOKS = course_notebooks()


@pytest.fixture(scope="session")
def edition(tmp_path_factory):
    out = tmp_path_factory.mktemp("edition") / "student"
    return out, {p.name: p for p in student.build(out)}


def _lines(text):
    return {ln.strip() for ln in text.splitlines() if len(ln.strip()) >= 20}


def _texts(cell):
    yield cell.source
    for out in cell.get("outputs", []):
        if "text" in out:
            yield out["text"]
        for value in out.get("data", {}).values():
            if isinstance(value, str):
                yield value


def test_strip_replaces_each_run_of_solution_cells_by_one_stub():
    nb = new_notebook(cells=[
        new_markdown_cell("### Exercise 9.1"),
        new_code_cell("answer = ..."),
        new_code_cell("check(answer)"),
        new_markdown_cell("**Solution.** it is FORTY-TWO", metadata={"tags": ["solution"]}),
        new_markdown_cell("Say: the answer is SECRET-NOTE", metadata={"slideshow": {"slide_type": "notes"}}),
        new_code_cell("answer = 42  # SECRET-ANSWER\ncheck(answer)", metadata={"tags": ["solution"]},
                      outputs=[nbformat.v4.new_output("stream", text="Correct: 42\n")]),
        new_code_cell("assert answer == 42  # SECRET-TEST", metadata={"tags": ["hidden-test"]}),
        new_markdown_cell("## Next section"),
        new_markdown_cell("Ask: why 42? SECRET-QUESTION", metadata={"slideshow": {"slide_type": "notes"}}),
    ])
    out = student.strip(nb)
    sources = [c.source for c in out.cells]
    assert sources[:3] == ["### Exercise 9.1", "answer = ...", "check(answer)"]
    assert sources[3] == student.STUB_TEXT and out.cells[3].metadata["tags"] == [student.STUB_TAG]
    assert sources[4:] == ["## Next section"]
    text = nbformat.writes(out)
    assert "FORTY-TWO" not in text and "SECRET-ANSWER" not in text and "Correct: 42" not in text
    assert "SECRET-NOTE" not in text and "SECRET-TEST" not in text and "SECRET-QUESTION" not in text
    assert len(nb.cells) == 9, "the original notebook is left as it was"


def test_readme_table_is_the_roles_module():
    """The README's table "One source, three editions" is tools/roles.py, row for row, so
    that what it documents is what the builders do."""
    text = (ROOT / "README.md").read_text(encoding="utf-8")
    missing = [line for line in roles.table() if line not in text.splitlines()]
    assert not missing, ("README.md's table differs from tools/roles.py (paste the output of "
                         "`python -m tools.roles`):\n" + "\n".join(missing))


def test_each_role_the_student_edition_drops_is_dropped():
    """Every role whose student-edition column says "left out" is left out by strip()."""
    for role in roles.ROLES:
        if role.action(roles.STUDENT) != roles.DROP or not (role.tag or role.slide_type):
            continue
        meta = {"tags": [role.tag]} if role.tag else {"slideshow": {"slide_type": role.slide_type}}
        nb = new_notebook(cells=[new_markdown_cell("kept"), new_markdown_cell(
            f"GONE-{role.name}", metadata=meta)])
        assert [c.source for c in student.strip(nb).cells] == ["kept"], role.name


def test_the_edition_has_every_notebook_and_what_it_needs(edition):
    out, notebooks = edition
    assert sorted(notebooks) == [p.name for p in NOTEBOOKS]
    for name in ["so3lib/exercises/__init__.py", "environment.txt", "pyproject.toml",
                 "README.md", "binder/requirements.txt", "binder/postBuild"]:
        assert (out / name).is_file(), name
    assert os.access(out / "binder/postBuild", os.X_OK), "repo2docker runs postBuild"


@pytest.mark.parametrize("path", NOTEBOOKS, ids=lambda p: p.stem)
def test_no_solution_text_remains(edition, path):
    out, notebooks = edition
    full = read(path)
    full.cells = [c for c in full.cells if not student.is_notes(c)   # test_no_speaker_notes
                  and not roles.for_lecture_only(c)]                  # roadmap, questions: deck only
    solutions = [c for c in full.cells if student.is_solution(c)]
    kept = read(notebooks[path.name])
    assert not any(student.is_solution(c) for c in kept.cells)
    # a solution line that also appears outside the solutions (an import, a checker call)
    # gives nothing away; every other line of a solution must be gone
    elsewhere = {ln for c in full.cells if not student.is_solution(c) for t in _texts(c)
                 for ln in _lines(t)}
    secret = {ln for c in solutions for t in _texts(c) for ln in _lines(t)} - elsewhere
    left = {ln for c in kept.cells for t in _texts(c) for ln in _lines(t)} & secret
    assert not left, f"solution text left in the student edition: {sorted(left)[:5]}"
    stubs = [c for c in kept.cells if student.STUB_TAG in c.metadata.get("tags", [])]
    runs = sum(1 for i, c in enumerate(full.cells)
               if student.is_solution(c) and (i == 0 or not student.is_solution(full.cells[i - 1])))
    assert len(stubs) == runs
    # everything that is not a solution is kept, in order, outputs included
    assert [c for c in full.cells if not student.is_solution(c)] == \
           [c for c in kept.cells if student.STUB_TAG not in c.metadata.get("tags", [])]


@pytest.mark.parametrize("path", NOTEBOOKS, ids=lambda p: p.stem)
def test_no_speaker_notes(edition, path):
    """Speaker notes answer the lecturer's questions: none of them, nor their text, remains."""
    out, notebooks = edition
    full = read(path)
    notes = {ln for c in full.cells if student.is_notes(c) for ln in _lines(c.source)}
    elsewhere = {ln for c in full.cells if not student.is_notes(c) for t in _texts(c) for ln in _lines(t)}
    kept = read(notebooks[path.name])
    assert not any(student.is_notes(c) for c in kept.cells)
    left = {ln for c in kept.cells for t in _texts(c) for ln in _lines(t)} & (notes - elsewhere)
    assert not left, f"speaker notes left in the student edition: {sorted(left)[:5]}"


def test_the_build_never_writes_into_notebooks(tmp_path):
    before = {p: p.stat().st_mtime_ns for p in (ROOT / "notebooks").iterdir()}
    for bad in [ROOT / "notebooks", ROOT / "notebooks" / "student", ROOT, ROOT / "so3lib"]:
        with pytest.raises(SystemExit):
            student.build(bad)
    assert {p: p.stat().st_mtime_ns for p in (ROOT / "notebooks").iterdir()} == before


def _edition_key(out, notebook):
    """A digest of what running NOTEBOOK in the edition OUT depends on: the notebook, every
    other file of the edition except the other notebooks (so3lib, environment.txt, ...),
    and the Python that runs it."""
    return digest([p for p in out.rglob("*") if p.is_file()
                   and not (p.suffix == ".ipynb" and p != notebook)], out)


def test_edition_key_sees_the_library_and_the_notebook(tmp_path):
    (tmp_path / "so3lib").mkdir()
    (tmp_path / "so3lib" / "a.py").write_text("x = 1\n")
    nb, other = tmp_path / "n.ipynb", tmp_path / "m.ipynb"
    nb.write_text("{}")
    other.write_text("{}")
    key = _edition_key(tmp_path, nb)
    other.write_text('{"changed": 1}')
    assert _edition_key(tmp_path, nb) == key, "another notebook is not an input"
    (tmp_path / "so3lib" / "a.py").write_text("x = 2\n")
    assert _edition_key(tmp_path, nb) != key
    key = _edition_key(tmp_path, nb)
    nb.write_text('{"cells": []}')
    assert _edition_key(tmp_path, nb) != key


def test_the_edition_runs_under_nbval_lax(edition):
    """Each notebook that lost solution cells runs top to bottom with no error; the others
    are the course's notebooks unchanged, which strict nbval runs already."""
    out, notebooks = edition
    changed = [notebooks[p.name] for p in NOTEBOOKS if any(student.is_solution(c) for c in read(p).cells)]
    if not changed:
        pytest.skip("no notebook has solution cells yet")
    # a notebook that ran clean with the same files is not run again (tests/pass_record.py)
    record = PassRecord("student-edition")
    keys = {nb.name: _edition_key(out, nb) for nb in changed}
    to_run = [nb for nb in changed if not record.fresh(nb.name, keys[nb.name])]
    if to_run:
        env = dict(os.environ, PYTHONHASHSEED="0")
        env.pop("PYTEST_XDIST_WORKER", None)
        run = subprocess.run(
            [sys.executable, "-m", "pytest", "-q", "-p", "no:cacheprovider", "-p", "no:xdist",
             "--rootdir", str(out), "--nbval-lax", "--nbval-current-env", *map(str, to_run)],
            cwd=out, env=env, capture_output=True, text=True, timeout=600)
        assert run.returncode == 0, run.stdout[-4000:] + run.stderr[-2000:]
    record.record({nb.name: keys[nb.name] for nb in to_run})
