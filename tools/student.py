"""`make student`: the course for self-study, in build/student/, without the worked solutions.

What happens to each cell is tools/roles.py's (the README's table, column "student
edition"): every run of consecutive cells tagged "solution" or "hidden-test" (the worked
answer to an exercise with its output, and the grading asserts) is replaced by one markdown
cell saying it is the learner's turn, and the speaker notes (slide type "notes", which
answer the lecturer's questions) are left out; everything else, the exercise stubs and the
checker calls with their hints included, stays as it is. Graded coursework is the other edition
of the same exercises (tools/assignments.py, `make assignments`). The folder is
self-contained, so an instructor can hand it out or publish it as its own repository:
notebooks/, the so3lib library the checkers live in, environment.txt, pyproject.toml,
binder/ and a short README.

It only reads notebooks/: it refuses to write there or anywhere in the course folder
except under build/, so a learner's own edits are never overwritten.

Usage: python -m tools.student [--out DIR]
"""

import argparse
import shutil
import sys
from pathlib import Path

import nbformat
from nbformat.v4 import new_markdown_cell

from tools import roles
from tools.common import BUILD, ROOT, build_target, course_notebooks, read

STUB_TAG = "your-turn"
STUB_TEXT = (
    "**Your turn.** Write your answer in the cell above the checker, run it, then run the "
    "checker: it says what is right and what is still wrong. (The worked solution is not "
    "part of this edition.)"
)
# What a learner needs besides the notebooks (paths relative to the course folder).
COPIED = ["so3lib", "environment.txt", "pyproject.toml", "binder"]

README = """# The exponential and logarithm of SO(3): student edition

The course's notebooks with the exercises left for you. Each exercise has a cell for
your answer and a checker below it: run the checker, and it tells you what is right and
what is still wrong.

## Start

- **On a JupyterHub or Binder** your instructor gave you: open `notebooks/00_start_here.ipynb`.
- **On your own machine** (Python 3.11.5 or newer), in this folder:

      python3 -m venv .venv
      .venv/bin/python -m pip install -r environment.txt
      .venv/bin/jupyter lab notebooks/00_start_here.ipynb

Work through the notebooks in order: 00, 01, ..., 06, then the appendix A1.
"""


def is_solution(cell):
    """A worked solution or a hidden test: what the learner must not see, in whose place
    the edition puts a "your turn" cell (roles: SPECIAL in the student edition)."""
    return roles.SPECIAL in roles.actions(cell, roles.STUDENT) and not left_out(cell)


def left_out(cell):
    """A cell the edition leaves out: speaker notes, ... (roles: DROP)."""
    return roles.left_out(cell, roles.STUDENT)


def is_notes(cell):
    return roles.has(cell, "notes")


def strip(nb):
    """A copy of NB without the cells the edition leaves out (speaker notes, ...), each run
    of solution (and hidden-test) cells replaced by one "your turn" stub."""
    nb = nbformat.from_dict(nb)
    cells, in_run = [], False
    for cell in nb.cells:
        if left_out(cell):
            continue
        if is_solution(cell):
            if not in_run:
                stub = new_markdown_cell(STUB_TEXT, metadata={
                    "slideshow": dict(cell.metadata.get("slideshow", {"slide_type": "-"})),
                    "tags": [STUB_TAG]})
                stub["id"] = f"{cell.get('id', 'cell')}-your-turn"
                cells.append(stub)
            in_run = True
        else:
            cells.append(cell)
            in_run = False
    nb.cells = cells
    nbformat.validate(nb)
    return nb


def build(out=BUILD / "student", notebooks=None):
    """Write the student edition into OUT (replacing an earlier one); returns its notebooks."""
    out = build_target(out, "the student edition")
    if out.exists():
        shutil.rmtree(out)
    (out / "notebooks").mkdir(parents=True)
    for name in COPIED:
        src = ROOT / name
        if src.is_dir():
            shutil.copytree(src, out / name, ignore=shutil.ignore_patterns(
                "__pycache__", "*.pyc", ".ipynb_checkpoints", "*.egg-info"))
        elif src.exists():
            shutil.copy2(src, out / name)
    (out / "README.md").write_text(README, encoding="utf-8")
    written = []
    for path in notebooks or course_notebooks():
        target = out / "notebooks" / Path(path).name
        nbformat.write(strip(read(path)), str(target))
        written.append(target)
    return written


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--out", type=Path, default=BUILD / "student")
    args = parser.parse_args(argv)
    for target in build(args.out):
        print(target.relative_to(Path.cwd()) if target.is_relative_to(Path.cwd()) else target)


if __name__ == "__main__":
    sys.exit(main())
