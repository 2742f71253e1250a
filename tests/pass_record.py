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
