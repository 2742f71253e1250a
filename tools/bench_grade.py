"""`make bench-grade`: how long `make grade` takes per notebook, on a made-up class.

Builds a course of its own (every course notebook with exercises) in a temporary folder,
hands in STUDENTS honest notebooks per assignment (the instructor's solutions, and every
third student a wrong answer to one exercise, so that both paths of the hidden tests run),
grades them all as `make grade JOBS=...` does, in the sandbox, and prints the seconds per
notebook and what a class of 200 handing in all seven assignments (1,400 notebooks) would
take at that rate. Nothing in build/ is touched.

Usage: python -m tools.bench_grade [--students N] [--jobs J] [--timeout S]
"""

import argparse
import tempfile
import time
from pathlib import Path

import nbformat

from tools import assignments, grade
from tools.common import course_notebooks, read

CLASS = 200 * 7


def honest(released, found, wrong_one):
    """RELEASED answered with the solutions; with WRONG_ONE, the first exercise's answer
    is off by a factor (an honest mistake)."""
    nb = nbformat.from_dict(released)
    by_id = {ex.grade_id: ex for ex in found}
    for cell in nb.cells:
        gid = cell.metadata.get("nbgrader", {}).get("grade_id", "")
        ex_id, _, kind = gid.rpartition("-")
        if ex_id in by_id and kind == "answer":
            cell.source = assignments._solution(by_id[ex_id])
            if wrong_one and ex_id == found[0].grade_id:
                cell.source += "\n\n# an honest slip: a wrong answer\n" + _slip(cell.source)
    return nb


def _slip(source):
    """Code that, run after the answer SOURCE, makes each name it defines off by half."""
    from tools.trusted_grader import stub_names
    funcs, values = stub_names(source)
    lines = ["import numpy as _np"]
    for f in funcs:
        lines += [f"_right_{f} = {f}", f"def {f}(*args, **kwargs):",
                  f"    return _np.asarray(_right_{f}(*args, **kwargs), dtype=float) * 1.5"]
    lines += [f"{v} = _np.asarray({v}, dtype=float) * 1.5" for v in values]
    return "\n".join(lines)


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--students", type=int, default=3)
    ap.add_argument("--jobs", type=int, default=2)
    ap.add_argument("--timeout", type=int, default=60)
    ap.add_argument("--verbose", action="store_true", help="print each notebook's time")
    args = ap.parse_args(argv)
    notebooks = [p for p in course_notebooks()
                 if any(assignments.ANSWER in assignments.tags(c) for c in read(p).cells)]
    with tempfile.TemporaryDirectory(prefix="bench-grade-") as tmp:
        root = Path(tmp)
        course, submitted = root / "course", root / "submitted"
        t0 = time.monotonic()
        made = assignments.build(course, notebooks, log=lambda *a: None)
        print(f"course built in {time.monotonic() - t0:.0f} s: {', '.join(sorted(made))}")
        count = 0
        for name, found in made.items():
            released = read(course / "release" / name / f"{name}.ipynb")
            for k in range(args.students):
                folder = submitted / f"student{k:03d}" / name
                folder.mkdir(parents=True)
                nbformat.write(honest(released, found, k % 3 == 2), str(folder / f"{name}.ipynb"))
                count += 1
        t0 = time.monotonic()
        rows = grade.grade(submitted, course, timeout=args.timeout, out=root / "grades.csv",
                           log=print if args.verbose else (lambda *a: None), jobs_at_once=args.jobs)
        spent = time.monotonic() - t0
    problems = [r for r in rows if r.get("problem")]
    per = spent / count
    print(f"{count} notebooks graded in {spent:.0f} s with {args.jobs} jobs: {per:.2f} s per notebook")
    print(f"a class of 200, seven assignments ({CLASS} notebooks): about {per * CLASS / 60:.0f} minutes "
          f"(target 60)")
    if problems:
        print(f"{len(problems)} notebooks with a problem, e.g. {problems[0]}")
    return 1 if problems else 0


if __name__ == "__main__":
    raise SystemExit(main())
