"""`make grade SUBMITTED=DIR`: grade the students' notebooks with nbgrader.

DIR holds nbgrader's layout, ``DIR/STUDENT_ID/ASSIGNMENT/NOTEBOOK.ipynb``, for the
assignments that `make assignments` wrote into build/coursework/. A relative DIR that is
not a folder here is looked up in build/coursework/: ``submitted`` is where ``nbgrader
collect`` puts the students' work, build/coursework/submitted/. For every student and
assignment on its own (so that one broken notebook never stops the others):

1. a notebook that is not a readable notebook (not JSON, not nbformat) scores 0, and the
   reason is recorded; it is not run;
2. ``nbgrader autograde`` runs the rest in a fresh kernel. nbgrader first puts back the
   test cells from the source (edited or deleted ones included), so the source's hidden
   tests decide the grade, whatever the notebook redefined or printed. A cell that runs
   longer than ``--timeout`` seconds is interrupted and scores 0; the next cells still run.
   A whole notebook that takes longer than ``--notebook-timeout`` is stopped and scores 0;
3. ``nbgrader generate_feedback`` writes one HTML page per notebook, with the checkers'
   messages, into build/coursework/feedback/STUDENT/ASSIGNMENT/;
4. ``nbgrader export`` writes build/grades.csv: one row per student and assignment with
   ``score`` and ``max_score``, plus a ``problem`` column saying why a notebook could
   not be graded. build/grades_by_exercise.csv has one row per exercise, with the reason a
   test failed (the hidden test's assertion, the error raised, the time limit).

Usage: python -m tools.grade SUBMITTED [--course DIR] [--timeout S] [--jobs N] [--out CSV]
"""

import argparse
import csv
import html
import json
import os
import re
import select
import shutil
import subprocess
import sys
import time
from concurrent.futures import ThreadPoolExecutor
from pathlib import Path

import nbformat

from tools.assignments import COURSE, DEFAULT_TIMEOUT, nbgrader
from tools.common import BUILD

NOT_RUN = "not graded"


def submitted_folder(submitted, course=COURSE):
    """The folder to grade: SUBMITTED itself, or, when that is no folder and the path is
    relative, the course's folder of that name (build/coursework/SUBMITTED)."""
    submitted, course = Path(submitted), Path(course)
    if submitted.is_dir():
        return submitted
    if not submitted.is_absolute() and (course / submitted).is_dir():
        return course / submitted
    looked = f"{submitted}" if submitted.is_absolute() else f"{submitted} or {_shown(course / submitted)}"
    raise SystemExit(f"no folder {looked}: it should hold STUDENT_ID/ASSIGNMENT/NOTEBOOK.ipynb "
                     "(`nbgrader collect` puts them in build/coursework/submitted/)")


def _shown(path):
    """PATH relative to the current folder when it lies under it."""
    path = Path(path).resolve()
    return path.relative_to(Path.cwd()) if path.is_relative_to(Path.cwd()) else path


def _gradebook(course):
    os.environ["PATH"] = os.pathsep.join([str(Path(sys.executable).parent), os.environ.get("PATH", "")])
    from nbgrader.api import Gradebook
    return Gradebook(f"sqlite:///{Path(course).resolve() / 'gradebook.db'}")


def unreadable(path):
    """Why the notebook at PATH cannot be graded, or None when it can be read."""
    try:
        nb = nbformat.read(str(path), as_version=4)
    except Exception as err:  # not JSON, not a notebook, unreadable bytes
        first = str(err).strip().splitlines()[0] if str(err).strip() else ""
        return f"not a valid notebook file ({type(err).__name__}: {first[:200]})"
    if not isinstance(nb.get("cells"), list):
        return "not a valid notebook file (it has no list of cells)"
    return None


def _first_line(text, limit=300):
    lines = [ln for ln in str(text).strip().splitlines() if ln.strip()]
    return lines[0][:limit] if lines else ""


def cell_reason(cell, timeout):
    """Why a test cell lost its points, read from its error output ("" when none)."""
    errors = [out for out in cell.get("outputs", []) if out.get("output_type") == "error"]
    # a cell stopped at the time limit (a KeyboardInterrupt the learner's code raised
    # itself is not one: the trusted grader names it)
    for out in errors:
        if out.get("ename") == "CellTimeoutError":
            return _first_line(out.get("evalue", "")) or f"time limit: the cell ran longer than {timeout} s"
    for out in errors:
        name, value = out.get("ename", ""), _first_line(out.get("evalue", ""))
        if name == "AssertionError":
            return "a hidden test failed" + (f": {value}" if value else "")
        if name == "NameError":
            return f"{name}: {value} (was the answer cell run, or deleted?)"
        return f"{name}: {value}" if value else name
    return ""


_COPY_SUFFIX = re.compile(r"(\s*\(\d+\)|[\s_-]*copy\d*|[\s_-]+(final|last|new|done|submitted?|"
                          r"submission|v\d+|version\s*\d+|\d+))+$", re.I)


def _plain(name):
    """NAME without the suffixes a download or a copy adds: "04_logarithm (1)",
    "04_logarithm-Copy1", "04_logarithm_final" are all "04_logarithm"."""
    return _COPY_SUFFIX.sub("", Path(name).stem if name.endswith(".ipynb") else name).strip().lower()


def match_name(name, candidates):
    """The one of CANDIDATES that NAME is a misnamed copy of, or None."""
    plain = _plain(name)
    found = [c for c in candidates if _plain(c) == plain]
    return found[0] if len(found) == 1 else None


def _stage(submitted, course, known, log):
    """Copy DIR into the course's submitted/ and sort out what cannot be graded.

    A misnamed copy is found and graded under its right name, and the problem column says
    so: a notebook renamed by a download or a copy ("04_logarithm (1).ipynb",
    "04_logarithm-Copy1.ipynb", beside an "Untitled.ipynb"), an assignment folder with a
    suffix ("04_logarithm_final"), a notebook loose in the student's folder. Anything
    else is named in the problem column as not graded. Returns (jobs, problems): jobs is a
    list of (student, assignment); problems maps (student, assignment) to what happened.
    """
    submitted, target = Path(submitted).resolve(), (Path(course) / "submitted").resolve()
    jobs, problems = [], {}
    same = submitted == target
    for student_dir in sorted(p for p in submitted.iterdir() if p.is_dir() and not p.name.startswith(".")):
        found = {}
        for child in sorted(student_dir.iterdir()):
            if child.name.startswith(".") or not (child.is_dir() or child.suffix == ".ipynb"):
                continue
            name = child.name if child.is_dir() and child.name in known else match_name(child.name, known)
            if name is None:
                log(f"warning: {student_dir.name}/{child.name}: no such assignment; skipped")
                continue
            found.setdefault(name, []).append(child)
        for assignment, sources in found.items():
            key = (student_dir.name, assignment)
            reasons = []
            exact = [p for p in sources if p.is_dir() and p.name == assignment]
            chosen = exact[0] if exact else max(sources, key=lambda p: (p.is_dir(), p.stat().st_mtime))
            for other in sources:
                if other is not chosen:
                    reasons.append(f"also found {other.name} (not graded)")
            dest = target / student_dir.name / assignment
            if chosen.is_dir() and chosen.name != assignment:
                reasons.append(f"graded the folder {chosen.name} as {assignment}")
            elif not chosen.is_dir():
                reasons.append(f"graded {chosen.name}, found loose in the student's folder")
            if not same or chosen != dest:
                if dest.exists() and not same:
                    shutil.rmtree(dest)
                if chosen.is_dir():
                    shutil.copytree(chosen, dest, ignore=shutil.ignore_patterns(".ipynb_checkpoints"),
                                    dirs_exist_ok=True)
                else:
                    dest.mkdir(parents=True, exist_ok=True)
                    shutil.copy2(chosen, dest / chosen.name)
            expected = sorted(p.name for p in (Path(course) / "source" / assignment).glob("*.ipynb"))
            notebooks = sorted(dest.glob("*.ipynb"))
            others = [p for p in notebooks if p.name not in expected]
            missing = [name for name in expected if not (dest / name).exists()]
            for name in list(missing):
                like = [p for p in others if match_name(p.name, [name])]
                if not like and len(missing) == 1 and len(others) == 1:
                    like = others            # the only other notebook: graded, and said so
                if like:
                    pick = max(like, key=lambda p: p.stat().st_mtime)
                    shutil.copy2(pick, dest / name)
                    if not same:
                        pick.unlink()
                    reasons.append(f"graded {pick.name} as {name}")
                    others.remove(pick)
                    missing.remove(name)
            for other in others:
                reasons.append(f"also found {other.name} (not graded)")
            if missing:
                reasons.append(f"missing {', '.join(missing)}")
            notebooks = [dest / name for name in expected if (dest / name).exists()]
            for nb in notebooks:
                why = unreadable(nb)
                if why:
                    reasons.append(f"{nb.name}: {why}")
                    if not same:
                        nb.unlink()          # keep the staged copy gradable; DIR is untouched
            if not any(dest.glob("*.ipynb")):
                reasons.append("no notebook submitted")
            if reasons:
                problems[key] = "; ".join(reasons)
            # a corrupt notebook left in place (DIR is the course's own submitted/) is not run
            unreadable_left = same and any("not a valid notebook" in r for r in reasons)
            if any(dest.glob("*.ipynb")) and not unreadable_left and notebooks:
                jobs.append(key)
    return jobs, problems


def _tail(run):
    text = (run.stdout or "") + (run.stderr or "")
    errors = [ln for ln in text.splitlines() if "ERROR" in ln or "Error" in ln]
    return _first_line("\n".join(errors[-3:]) or text[-500:], 500)


def _digest(course, student, assignment):
    """What a grade depends on: the submitted notebooks, their timestamp, the source."""
    import hashlib
    h = hashlib.sha256()
    for folder in (Path(course) / "submitted" / student / assignment, Path(course) / "source" / assignment):
        for path in sorted(folder.glob("*.ipynb")) + sorted(folder.glob("timestamp.txt")):
            h.update(path.name.encode() + b"\0" + path.read_bytes() + b"\0")
    return h.hexdigest()


def grade(submitted, course=COURSE, timeout=DEFAULT_TIMEOUT, notebook_timeout=None,
          out=BUILD / "grades.csv", log=print, jobs_at_once=1, force=False):
    """Grade every student and assignment in SUBMITTED; returns the rows of the CSV."""
    course = Path(course).resolve()
    if not (course / "gradebook.db").exists() or not (course / "source").is_dir():
        raise SystemExit(f"no coursework in {course}: run `make assignments` first")
    from tools import sandbox
    if sandbox.missing():           # never run a learner's code outside the sandbox
        raise SystemExit(f"make grade runs each notebook in a sandbox: {sandbox.missing()}")
    submitted = submitted_folder(submitted, course)
    notebook_timeout = notebook_timeout or max(900, 20 * timeout)
    with _gradebook(course) as gb:
        known = {a.name for a in gb.assignments}
    jobs, problems = _stage(submitted, course, known, log)
    staged = set(jobs) | set(problems)
    students = sorted({s for s, _ in jobs} | {s for s, _ in problems})

    # a submission graded before and unchanged since (the same notebooks, timestamp and
    # source) keeps its grades, hand grades included, and its feedback: it is not run again
    record_path = course / "grade-digests.json"
    try:
        digests = json.loads(record_path.read_text())
    except (OSError, ValueError):
        digests = {}
    now = {job: _digest(course, *job) for job in jobs}
    with _gradebook(course) as gb:
        unchanged = {job for job in jobs if not force and job not in problems
                     and digests.get("/".join(job)) == now[job] and _submitted(gb, *job)
                     and (course / "autograded" / job[0] / job[1]).is_dir()}
    if unchanged:
        log(f"{len(unchanged)} submissions unchanged since they were graded: kept as they are")
    jobs = [job for job in jobs if job not in unchanged]
    for job in set(jobs) | set(problems):
        digests.pop("/".join(job), None)

    for student, assignment in set(jobs) | set(problems):
        for stale in ("autograded", "feedback"):     # an earlier run's results for them
            shutil.rmtree(course / stale / student / assignment, ignore_errors=True)
    with _gradebook(course) as gb:
        for student in students:
            gb.update_or_create_student(student)
        for student, assignment in set(jobs) | set(problems):
            try:                        # an earlier run's grade must not outlive a new submission
                gb.remove_submission(assignment, student)
            except Exception:
                pass
    import threading
    workers, local = [], threading.local()     # warm worker processes, one per thread

    def worker():
        if getattr(local, "proc", None) is None or local.proc.poll() is not None:
            env = dict(os.environ, PYTHONPATH=str(Path(__file__).resolve().parent.parent))
            local.proc = subprocess.Popen(
                [sys.executable, "-m", "tools.grade_worker", str(course), str(int(timeout)),
                 str(int(notebook_timeout))], stdin=subprocess.PIPE, stdout=subprocess.PIPE,
                stderr=subprocess.DEVNULL, text=True, env=env)
            workers.append(local.proc)
        return local

    def autograde(job):
        student, assignment = job
        begin = time.monotonic()
        local = worker()
        proc = local.proc
        failed = ""
        try:
            proc.stdin.write(f"{student}\t{assignment}\n")
            proc.stdin.flush()
            # a notebook may be run twice (tools/trusted_grader.py: the full run after a pruned one)
            ready = select.select([proc.stdout], [], [], 2 * notebook_timeout + 120)[0]
            line = proc.stdout.readline() if ready else ""
            reply = json.loads(line) if line else {"ok": False, "why": f"grading stopped after "
                                                               f"{2 * notebook_timeout + 120} s"}
        except (OSError, ValueError) as err:
            reply = {"ok": False, "why": f"the grading worker stopped ({type(err).__name__})"}
        if not reply.get("ok"):
            failed = f"autograde failed: {reply.get('why', '')}"
            if "stopped" in reply.get("why", ""):
                proc.kill()
                local.proc = None
        log(f"autograde {student}/{assignment}: {'FAILED, ' + failed if failed else 'done'} "
            f"({time.monotonic() - begin:.0f} s)")
        return failed

    # Each student and assignment graded on its own, by JOBS warm workers; one that
    # fails beside others (the SQLite gradebook can be busy) is tried once more alone.
    failed_jobs = {}
    try:
        with ThreadPoolExecutor(max_workers=max(1, jobs_at_once)) as pool:
            for job, failed in zip(jobs, pool.map(autograde, jobs)):
                if failed:
                    failed_jobs[job] = failed
        if jobs_at_once > 1:
            failed_jobs = {job: why for job in list(failed_jobs) if (why := autograde(job))}
    finally:
        for proc in workers:
            if proc.poll() is None:
                proc.stdin.close()
                try:
                    proc.wait(timeout=30)
                except subprocess.TimeoutExpired:
                    proc.kill()
    for (student, assignment), failed in failed_jobs.items():
        problems[(student, assignment)] = "; ".join(filter(None, [problems.get((student, assignment)), failed]))
        with _gradebook(course) as gb:
            try:
                gb.remove_submission(assignment, student)
            except Exception:
                pass
    jobs = [job for job in jobs if job not in failed_jobs]
    digests.update({"/".join(job): now[job] for job in jobs})
    record_path.write_text(json.dumps(digests, indent=1, sort_keys=True))

    # feedback only for the submissions graded now (their old pages were removed above):
    # without --force, nbgrader leaves every other page as it is
    run = nbgrader(course, "generate_feedback", "*", "--log-level=ERROR", check=False) \
        if jobs else None
    if run is not None and run.returncode != 0:
        # one student's page must not cost the others theirs: again, one by one
        for student, assignment in jobs:
            nbgrader(course, "generate_feedback", assignment, f"--student={student}",
                     "--force", "--log-level=ERROR", check=False)
    for (student, assignment), why in problems.items():
        _problem_page(course, student, assignment, why)

    # what could not be graded, kept across runs (a later run grades other students)
    record = course / "grade-problems.json"
    try:
        kept = {tuple(k.split("/", 1)): v for k, v in json.loads(record.read_text()).items()}
    except (OSError, ValueError):
        kept = {}
    for key in staged:
        kept.pop(key, None)
    kept.update(problems)
    record.write_text(json.dumps({"/".join(k): v for k, v in sorted(kept.items())}, indent=1))
    problems = dict(kept)

    out = Path(out)
    out.parent.mkdir(parents=True, exist_ok=True)
    nbgrader(course, "export", f"--to={out.resolve()}", "--log-level=ERROR")
    with _gradebook(course) as gb:
        for row in _read_csv(out):
            key = (row["student_id"], row["assignment"])
            if key not in problems and not _submitted(gb, *key):
                problems[key] = "no submission"
    rows = _add_problems(out, problems, course)
    _by_exercise(course, out.with_name(out.stem + "_by_exercise.csv"), problems, timeout,
                 {row["assignment"] for row in rows})
    return rows


def _problem_page(course, student, assignment, why):
    folder = Path(course) / "feedback" / student / assignment
    folder.mkdir(parents=True, exist_ok=True)
    (folder / "problem.html").write_text(
        "<!DOCTYPE html><html lang='en'><head><meta charset='utf-8'><title>Not graded</title></head>"
        f"<body><h1>{html.escape(assignment)}: not graded</h1><p>{html.escape(why)}</p>"
        "<p>This part scores 0. Ask your instructor if you think this is wrong.</p></body></html>",
        encoding="utf-8")


def _read_csv(path):
    with open(path, newline="", encoding="utf-8") as fh:
        return list(csv.DictReader(fh))


def _submitted(gb, student, assignment):
    from nbgrader.api import MissingEntry
    try:
        gb.find_submission(assignment, student)
        return True
    except MissingEntry:
        return False


def _add_problems(path, problems, course=None):
    rows = _read_csv(path)
    fields = list(rows[0].keys()) if rows else ["assignment", "student_id", "score", "max_score"]
    late, due = {}, set()
    if course is not None:
        with _gradebook(course) as gb:
            for assignment in gb.assignments:
                if assignment.duedate is not None:
                    due.add(assignment.name)
                for sub in assignment.submissions:
                    late[(sub.student_id, assignment.name)] = sub.total_seconds_late
    fields += ["seconds_late", "problem"]
    # only the assignments that were set: those with a due date, and those someone handed
    # in (or tried to)
    handed_in = {row["assignment"] for row in rows if problems.get((row["student_id"], row["assignment"]))
                 != "no submission"} | {a for (_, a), why in problems.items() if why != "no submission"}
    rows = [row for row in rows if row["assignment"] in handed_in | due]
    for row in rows:
        key = (row["student_id"], row["assignment"])
        seconds = late.get(key)
        row["seconds_late"] = f"{seconds:.0f}" if seconds else ("0" if key in late else "")
        row["problem"] = problems.get(key, "")
    with open(path, "w", newline="", encoding="utf-8") as fh:
        writer = csv.DictWriter(fh, fieldnames=fields)
        writer.writeheader()
        writer.writerows(rows)
    return rows


def _by_exercise(course, path, problems, timeout, set_assignments=None):
    """One row per student, assignment (of those set) and exercise, with the reason for
    lost points."""
    from nbgrader.api import MissingEntry
    rows = []
    with _gradebook(course) as gb:
        for assignment in gb.assignments:
            if set_assignments is not None and assignment.name not in set_assignments:
                continue
            for notebook in assignment.notebooks:
                for cell in notebook.grade_cells:
                    for student in gb.students:
                        key = (student.id, assignment.name)
                        note = problems.get(key, "")
                        manual = False
                        try:            # this run's grade, or an earlier run's still in the book
                            g = gb.find_grade(cell.name, notebook.name, assignment.name, student.id)
                            manual = g.score is None and g.needs_manual_grade
                            score = None if g.score is None else float(g.score)
                        except MissingEntry:
                            score = None
                        if manual:      # a written part: formgrader's, by hand
                            score, reason = 0.0, "; ".join(filter(None, [note, "to be graded by hand "
                                                                          "(formgrader)"]))
                        elif score is None:
                            score, reason = 0.0, note or "no submission"
                        elif score < float(cell.max_score):
                            why = _reason_from_notebook(course, key, notebook.name, cell.name, timeout)
                            reason = "; ".join(filter(None, [note, why]))
                        else:
                            reason = note
                        rows.append({"student_id": student.id, "assignment": assignment.name,
                                     "notebook": notebook.name, "exercise": cell.name,
                                     "score": score, "max_score": float(cell.max_score),
                                     "reason": reason})
    with open(path, "w", newline="", encoding="utf-8") as fh:
        writer = csv.DictWriter(fh, fieldnames=["student_id", "assignment", "notebook", "exercise",
                                                "score", "max_score", "reason"])
        writer.writeheader()
        writer.writerows(rows)
    return rows


def _reason_from_notebook(course, key, notebook, grade_id, timeout):
    student, assignment = key
    path = Path(course) / "autograded" / student / assignment / f"{notebook}.ipynb"
    try:
        nb = nbformat.read(str(path), as_version=4)
    except Exception:
        return NOT_RUN
    cells = {cell.metadata.get("nbgrader", {}).get("grade_id"): cell for cell in nb.cells}
    if grade_id not in cells:
        return "the test cell was not found in the graded notebook"
    test = cell_reason(cells[grade_id], timeout) or "the test did not pass"
    answer = cells.get(grade_id.rsplit("-", 1)[0] + "-answer")
    if answer is not None and cell_reason(answer, timeout):
        return f"the answer cell: {cell_reason(answer, timeout)}; then the test: {test}"
    return test


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("submitted", type=Path,
                        help="DIR/STUDENT_ID/ASSIGNMENT/NOTEBOOK.ipynb (a relative DIR that is not "
                             "here: in the course folder, e.g. submitted)")
    parser.add_argument("--course", type=Path, default=COURSE)
    parser.add_argument("--timeout", type=int, default=DEFAULT_TIMEOUT,
                        help=f"seconds one cell may run (default {DEFAULT_TIMEOUT})")
    parser.add_argument("--notebook-timeout", type=int, default=None,
                        help="seconds one notebook may take in all (default max(900, 20 x timeout))")
    parser.add_argument("--out", type=Path, default=BUILD / "grades.csv")
    parser.add_argument("--jobs", type=int, default=1,
                        help="notebooks graded at once, each in its own kernel (default 1)")
    parser.add_argument("--force", action="store_true",
                        help="grade again submissions that have not changed since they were graded "
                             "(their hand grades are lost)")
    args = parser.parse_args(argv)
    rows = grade(args.submitted, args.course, args.timeout, args.notebook_timeout, args.out,
                 jobs_at_once=args.jobs, force=args.force)
    for row in rows:
        note = f"  ({row['problem']})" if row["problem"] else ""
        print(f"{row['student_id']:>16}  {row['assignment']:<32} {float(row['score']):6.1f} / "
              f"{float(row['max_score']):.1f}{note}")
    print(f"grades: {args.out}; per exercise: {args.out.with_name(args.out.stem + '_by_exercise.csv')}; "
          f"feedback: {args.course / 'feedback'}/STUDENT/ASSIGNMENT/")


if __name__ == "__main__":
    sys.exit(main())
