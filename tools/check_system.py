"""The programs and fonts outside Python that `make test` and `make pdf` use, and the
Debian packages that provide them.

    python3 -m tools.check_system test    # before `make test`: says what is missing
    python3 -m tools.check_system pdf     # before `make pdf`: fails when something is
    python3 -m tools.check_system --debian-packages   # the packages to install (.ci/run)

For `make test`, outside CI a missing program is reported and the tests that need it are
skipped (they say why); under CI (the CI environment variable set, as .ci/run does) it is
an error, since CI installs every one. Only the standard library: this runs before .venv
exists, with any Python 3.
"""

import os
import shutil
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent


def chromium():
    """Path of the Chromium the tests and tools drive (tests/browser_support.py's rule)."""
    candidates = [os.environ.get("CHROMIUM"), "/usr/bin/chromium"]
    candidates += [shutil.which(n) for n in ("chromium", "chromium-browser", "google-chrome")]
    return next((c for c in candidates if c and os.path.isfile(c) and os.access(c, os.X_OK)), None)


def npm_or_cache():
    """npm, or every tarball it would fetch already in build/npm/ (copied from elsewhere)."""
    if shutil.which("npm"):
        return True
    try:
        sys.path.insert(0, str(ROOT))
        from tools.vendor import CACHE, PACKAGES
    except Exception:
        return False
    return all((CACHE / f"{name}-{version}.tgz").is_file() for name, (version, _) in PACKAGES.items())


FONT_DIRS = ["/usr/share/fonts", "/usr/local/share/fonts", "~/.local/share/fonts", "~/.fonts"]


def font(family, filename):
    """Whether FAMILY is installed: fontconfig's list when there is one, else its file."""
    if shutil.which("fc-list"):
        import subprocess
        out = subprocess.run(["fc-list", ":", "family", "style"], capture_output=True, text=True)
        if out.returncode == 0:
            name, _, style = family.partition(":")
            return any(name in line.split(":")[0].split(",") and (not style or style in line)
                       for line in out.stdout.splitlines())
    return any(any(Path(d).expanduser().rglob(filename)) for d in FONT_DIRS if Path(d).expanduser().is_dir())


# (what, Debian package, how to find it, what needs it)
WHAT = {
    "chromium": ("chromium", chromium,
                 "the browser tests (decks, book, JupyterLab), make handouts and make pdf"),
    "npm": ("npm", npm_or_cache, "make slides and make book fetch reveal.js and MathJax with it, once"),
    "bwrap": ("bubblewrap", lambda: shutil.which("bwrap"),
              "make grade runs each learner's notebook in its sandbox (no network, no view of "
              "the answer key or the gradebook); the grading tests"),
    "setpriv": ("util-linux", lambda: shutil.which("setpriv") and shutil.which("prlimit"),
                "make grade: the sandbox's user and limits (setpriv, prlimit)"),
    "pdftotext": ("poppler-utils", lambda: shutil.which("pdftotext"),
                  "make pdf (page numbers of the contents) and the test of the course's PDF"),
    "pdfinfo": ("poppler-utils", lambda: shutil.which("pdfinfo"), "the handouts' page counts"),
    "pdftoppm": ("poppler-utils", lambda: shutil.which("pdftoppm"), "pictures of PDF pages"),
    "font Liberation Sans": ("fonts-liberation",
                             lambda: font("Liberation Sans", "LiberationSans-Regular.ttf"),
                             "the decks' text (reveal's Helvetica) and the book's Arial, "
                             "whose sizes the tests measure"),
    "font DejaVu Sans Mono": ("fonts-dejavu-core",
                              lambda: font("DejaVu Sans Mono", "DejaVuSansMono.ttf"),
                              "code in the decks and JupyterLab; Chromium's sans-serif"),
    "font DejaVu Sans Mono Oblique": ("fonts-dejavu-extra",
                                      lambda: font("DejaVu Sans Mono:Oblique",
                                                   "DejaVuSansMono-Oblique.ttf"),
                                      "the decks' comments in code (italic)"),
}
NEEDED = {
    "test": list(WHAT),
    "grade": ["bwrap", "setpriv"],
    "pdf": ["chromium", "npm", "pdftotext", "font Liberation Sans", "font DejaVu Sans Mono",
            "font DejaVu Sans Mono Oblique"],
}


def missing(names):
    return [name for name in names if not WHAT[name][1]()]


def require(names, purpose):
    """Stop (SystemExit) naming each of NAMES that is missing, with its Debian package, as
    `make pdf` does; tools/book.py calls it before printing the PDF."""
    gone = missing(names)
    if gone:
        lines = [f"missing: {n} (Debian package {WHAT[n][0]}): apt-get install {WHAT[n][0]}  [{WHAT[n][2]}]"
                 for n in gone]
        raise SystemExit("\n".join(lines) + f"\n{purpose} needs them: apt-get install "
                         + " ".join(sorted({WHAT[n][0] for n in gone})))


def main(argv=None):
    args = sys.argv[1:] if argv is None else argv
    if args == ["--debian-packages"]:
        print(" ".join(sorted({WHAT[n][0] for n in missing(WHAT)})))
        return 0
    if len(args) != 1 or args[0] not in NEEDED:
        print(__doc__, file=sys.stderr)
        return 2
    target = args[0]
    gone = missing(NEEDED[target])
    if not gone:
        return 0
    for name in gone:
        package, _, why = WHAT[name]
        print(f"missing: {name} (Debian package {package}): apt-get install {package}  [{why}]",
              file=sys.stderr)
    packages = " ".join(sorted({WHAT[n][0] for n in gone}))
    if target == "pdf":
        print(f"make pdf needs them: apt-get install {packages}"
              + (" (or set CHROMIUM=/path/to/chrome)" if "chromium" in gone else ""), file=sys.stderr)
        return 1
    if os.environ.get("CI"):
        print(f"CI runs every test: apt-get install {packages} (.ci/run does)", file=sys.stderr)
        return 1
    fonts = any(name.startswith("font ") for name in gone)
    print("the tests that need a missing program are skipped, with the reason"
          + ("; without the fonts, the decks' and the book's layout is measured in others" if fonts else "")
          + f". To run them all: apt-get install {packages}", file=sys.stderr)
    return 0


if __name__ == "__main__":
    sys.exit(main())
