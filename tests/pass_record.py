"""A record of slow checks that passed, by a digest of everything they read.

Some tests build a whole edition and run it (the student edition's notebooks in a kernel,
the Binder image in a fresh venv): a minute each, on files that seldom change. Such a test
records, after it passes, a digest of its inputs in build/test-cache/NAME.json, and does
not redo the work while the digest is the same. A fresh clone, and so CI, has no record
and runs everything; `make test FRESH=1` (TEST_FRESH=1) ignores the records.
"""

import hashlib
import json
import os
import sys
from pathlib import Path

CACHE = Path(__file__).resolve().parent.parent / "build" / "test-cache"


def digest(paths, root, extra=""):
    """sha256 of the Python version, EXTRA and each file under PATHS (files or folders),
    named relative to ROOT; caches and byte code left out."""
    h = hashlib.sha256(f"{sys.version}\0{extra}".encode())
    files = set()
    for p in map(Path, paths):
        files |= {f for f in p.rglob("*") if f.is_file()} if p.is_dir() else {p} if p.is_file() else set()
    for f in sorted(files):
        rel = f.relative_to(root).as_posix()
        if "__pycache__" in rel or ".ipynb_checkpoints" in rel or rel.endswith(".pyc"):
            continue
        h.update(f"\0{rel}\0".encode())
        h.update(f.read_bytes())
    return h.hexdigest()


class PassRecord:
    def __init__(self, name):
        self.path = CACHE / f"{name}.json"
        try:
            self.passed = {} if os.environ.get("TEST_FRESH") else json.loads(self.path.read_text())
        except (OSError, ValueError):
            self.passed = {}

    def fresh(self, item, key):
        """True when ITEM passed with inputs KEY."""
        return self.passed.get(item) == key

    def record(self, items_keys):
        self.passed.update(items_keys)
        self.path.parent.mkdir(parents=True, exist_ok=True)
        tmp = self.path.with_name(f".{self.path.name}.{os.getpid()}")
        tmp.write_text(json.dumps(self.passed, indent=1, sort_keys=True) + "\n")
        os.replace(tmp, self.path)


# --- whole test files that passed on the same files -----------------------------------------
#
# The files that build and drive an edition (decks, book, coursework, JupyterLab: REMEMBERED)
# take most of `make test`. When every test of such a file passed in a run of the whole file
# and no file of the course has changed since (every file git knows of or would add, by
# content), the next `make test` does not run it again: conftest.py deselects its tests and
# says so. A fresh clone (CI), `make test FRESH=1` and any change to any file run it all.

REMEMBERED = ("test_slides.py", "test_book.py", "test_book_laptop.py", "test_book_phone.py",
              "test_book_pdf.py", "test_assignments.py", "test_grading_sandbox.py",
              "test_student_edition.py", "test_binder.py", "test_newcomer.py", "test_browser.py",
              "test_interactive.py")


def tree_digest(root):
    """sha256 of every file of the course under ROOT that git tracks or would add (content
    and name), the Python version and Chromium's binary; None outside a git checkout."""
    import subprocess
    try:
        listed = subprocess.run(["git", "ls-files", "-z", "--cached", "--others", "--exclude-standard"],
                                cwd=root, capture_output=True, check=True, timeout=60).stdout
    except (OSError, subprocess.SubprocessError):
        return None
    root = Path(root)
    h = hashlib.sha256(sys.version.encode())
    for rel in sorted(set(filter(None, listed.decode().split("\0")))):
        f = root / rel
        if f.is_file():
            h.update(f"\0{rel}\0".encode())
            h.update(f.read_bytes())
    for browser in ("/usr/lib/chromium/chromium", "/usr/bin/chromium"):
        p = Path(browser)
        if p.is_file():
            h.update(f"\0{browser}:{p.stat().st_size}:{p.stat().st_mtime_ns}".encode())
    return h.hexdigest()
