"""`make book` and `make pdf`: the course as a Jupyter Book (1.x, sphinx-book-theme).

`make book` writes the web site build/book/ (open build/book/index.html); `make pdf` prints
the same book, as one page, into build/course.pdf with Debian's Chromium.

The notebooks are not executed: the book shows their stored outputs. Each notebook in
notebooks/ (tools.common.course_notebooks, so a new one is picked up) is copied into
build/book-src/ as the learner reads it:

- speaker notes (slide type `notes`), grading asserts (tag `hidden-test`) and the checks the
  text rests on (tag `verify`) are left out;
- each run of worked-solution cells (tag `solution`, markdown and code) goes into one
  collapsed "Show solution" block;
- a cell tagged `hide-input` shows its output with the code collapsed (myst-nb), and a
  figure's alt text is the cell's `metadata.mystnb.image.alt` (myst-nb).

The site reads with no network: MathJax 3 comes from the npm registry (tools/vendor.py,
pinned), the theme's fonts and search index are local, and plotly.js (when plotly is
installed) is copied from its Python package. Launch buttons (Binder, and a JupyterHub
through nbgitpuller) and the repository link all come from one setting, the repository
URL (`--repository-url`, `make book BOOK_REPOSITORY=...`); the hub from `--jupyterhub-url`.

Usage: python -m tools.book [--pdf] [--repository-url URL] [--jupyterhub-url URL]
"""

import argparse
import contextlib
import copy
import fcntl
import json
import os
import re
import shutil
import sys
from pathlib import Path
from urllib.parse import unquote

import yaml
from bs4 import BeautifulSoup

from tools import vendor
from tools.common import BUILD, NOTEBOOKS, Stamps, course_notebooks, label, read, write_atomic

BOOK_TITLE = "The exponential and logarithm of SO(3)"
SOURCE = BUILD / "book-src"
OUT = BUILD / "book"
# The one-page book the PDF is printed from. In a folder of its own: myst-nb writes its
# files next to the output folder (OUT's parent/jupyter_execute), so the web build and this
# one can run at the same time (two test workers) without writing the same files.
PRINT_OUT = BUILD / "book-print" / "site"
PDF = BUILD / "course.pdf"
DOCTREES = BUILD / "book-doctrees"
STATIC = Path(__file__).resolve().parent / "book_static"

# The one setting the launch buttons and the repository link are made from: the course's
# public GitHub repository. Without it the book has no launch or repository button at all.
REPOSITORY_URL = os.environ.get("BOOK_REPOSITORY", "").strip()
BRANCH = os.environ.get("BOOK_BRANCH", "main")
# The JupyterHub that the nbgitpuller launch button opens (only with a repository too).
JUPYTERHUB_URL = os.environ.get("BOOK_JUPYTERHUB", "").strip()
BINDERHUB_URL = "https://mybinder.org"

ROOT = Path(__file__).resolve().parent.parent
LICENSE = ROOT / "LICENSE"
CITATION = ROOT / "CITATION.cff"
CC_BY = "https://creativecommons.org/licenses/by/4.0/"

MATHJAX = "vendor/mathjax3/es5/tex-chtml-full.js"  # inside the book's _static/
SOLUTION_BEGIN = '<div class="course-solution-begin"></div>'
SOLUTION_END = '<div class="course-solution-end"></div>'


# ---------------------------------------------------------------------------------------
# The learner's copy of a notebook


def _tags(cell):
    return set(cell.metadata.get("tags", []))


def is_speaker_note(cell):
    return cell.metadata.get("slideshow", {}).get("slide_type") == "notes"


def is_hidden_test(cell):
    return "hidden-test" in _tags(cell)


def is_verification(cell):
    """A cell of checks that the notebook's claims rest on (tag `verify`): strict nbval
    runs it, JupyterLab shows it collapsed, the book leaves it out."""
    return "verify" in _tags(cell)


def is_solution(cell):
    return "solution" in _tags(cell)


def is_left_out(cell):
    """A cell that the book leaves out: speaker notes, grading asserts, `verify` checks, and
    any other role that tools/roles.py leaves out of the book (the lecture's own cells)."""
    if is_speaker_note(cell) or is_hidden_test(cell) or is_verification(cell):
        return True
    try:
        from tools import roles
    except ImportError:
        return False
    return roles.left_out(cell, roles.BOOK)


def _marker(text):
    from nbformat.v4 import new_markdown_cell
    cell = new_markdown_cell(text)
    cell.id = None  # nbformat fills a fresh id below
    return cell


_HEADING_ANCHOR = re.compile(r'^(#{1,6})\s*<a\s+(?:id|name)="([^"]+)"\s*>\s*</a>\s*', re.M)

_NB_FRAGMENT = re.compile(r"\]\(([^()\s#]+\.ipynb)#((?:[^()\s]|\([^()\s]*\))+)\)")


def heading_anchors(nbs):
    """The anchors that headings carry as raw HTML ('### <a id="N15"></a>N15. ...')."""
    return {m.group(2) for nb in nbs for cell in nb.cells if cell.cell_type == "markdown"
            for m in _HEADING_ANCHOR.finditer(cell.source)}


_HEADING = re.compile(r"^#{1,6}\s+(.+?)\s*$", re.M)


def heading_slugs(paths, nbs):
    """{notebook file: {JupyterLab's anchor of a heading: MyST's anchor of it}}: JupyterLab
    names '## 2. Integrating' '#2.-Integrating', MyST '#2-integrating'."""
    from myst_parser.mdit_to_docutils.base import default_slugify
    found = {}
    for p, nb in zip(paths, nbs):
        found[p.name] = {}
        for cell in nb.cells:
            if cell.cell_type == "markdown":
                for m in _HEADING.finditer(_HEADING_ANCHOR.sub(r"\1 ", cell.source)):
                    found[p.name][m.group(1).replace(" ", "-")] = default_slugify(m.group(1))
    return found


def fix_links(source, anchors=(), slugs=None):
    """'### <a id="N15"></a>N15. ...' becomes a MyST target '(N15)=' above the heading, so
    that the anchor does not nest inside the page's contents and links to it resolve; a
    link to it from another notebook ('A1_errata.ipynb#N15') becomes a reference to the
    target (Sphinx keeps targets in lower case: the page's anchor is '#n15'). A link to a
    heading by its JupyterLab anchor ('05_x.ipynb#2.-Integrating') gets MyST's anchor."""
    source = _HEADING_ANCHOR.sub(lambda m: f"({m.group(2)})=\n{m.group(1)} ", source)

    def relink(m):
        target, frag = m.group(1), m.group(2)
        if frag in anchors:
            return f"](#{frag.lower()})"
        slug = (slugs or {}).get(target, {}).get(unquote(frag))
        return f"]({target}#{slug})" if slug else m.group(0)
    return _NB_FRAGMENT.sub(relink, source)


def learner_copy(nb, anchors=(), slugs=None):
    """NB as the book shows it: no speaker notes, no hidden tests, each run of solution
    cells between two marker cells that the HTML pass turns into one collapsed block."""
    import nbformat
    cells, in_solution = [], False
    for cell in nb.cells:
        if is_left_out(cell):
            continue
        if is_solution(cell) != in_solution:
            cells.append(_marker(SOLUTION_END if in_solution else SOLUTION_BEGIN))
            in_solution = not in_solution
        if cell.cell_type == "markdown":
            cell = copy.deepcopy(cell)
            cell.source = fix_links(cell.source, anchors, slugs)
        cells.append(cell)
    if in_solution:
        cells.append(_marker(SOLUTION_END))
    for i, cell in enumerate(cells):
        if not cell.get("id"):
            cell.id = f"course-marker-{i}"
    nb = nbformat.from_dict({**nb, "cells": cells})
    return nb


def download_copy(nb, name, repository_url=REPOSITORY_URL):
    """The notebook behind a page's .ipynb download: a first cell that says how to run it,
    then the notebook as a learner works it, without the worked solutions (the book shows
    them), the speaker notes, the grading asserts and the `verify` checks."""
    import nbformat
    from nbformat.v4 import new_markdown_cell
    keep = [copy.deepcopy(c) for c in nb.cells
            if not (is_left_out(c) or is_solution(c))]
    repository_url = (repository_url or "").strip().rstrip("/")
    where = "the course folder"
    binder = ""
    if repository_url:
        where = f"the course folder ([{repository_url}]({repository_url}))"
        if "github.com/" in repository_url:
            slug = repository_url.split("github.com/", 1)[1]
            url = (f"{BINDERHUB_URL}/v2/gh/{slug}/{BRANCH}?urlpath=lab/tree/notebooks/{name}")
            binder = (f"\n\nWith nothing installed, open it on Binder instead: [{url}]({url}) "
                      "(a temporary session: keep your work with *File > Download*).")
    first = new_markdown_cell(
        "**How to run this notebook.** It imports `so3lib`, the course's own library, so it runs "
        f"inside the course, not on its own. Get {where}, and in it run\n\n"
        "```\nmake lab     # the first time: installs the pinned packages into .venv\n"
        "make test    # optional: checks the library and the notebooks\n```\n\n"
        "(Python 3.11.5 or newer and `make`). `make lab` opens JupyterLab on the folder "
        f"`notebooks/`: open `{name}` there and run it top to bottom." + binder
        + "\n\nThe worked solutions are not in this file: each is under its exercise in the "
        "course's book (*Show solution*), or in the course folder's copy of this notebook.")
    first.metadata["tags"] = ["course-how-to-run"]
    first.id = "course-how-to-run"
    return nbformat.from_dict({**nb, "cells": [first] + keep})


def missing_alt(nb):
    """Indices (in the notebook) of the code cells that draw a picture without alt text."""
    found = []
    for i, cell in enumerate(nb.cells):
        if cell.cell_type != "code" or is_hidden_test(cell):
            continue
        draws = any(k.startswith("image/") for o in cell.get("outputs", []) for k in o.get("data", {}))
        alt = cell.metadata.get("mystnb", {}).get("image", {}).get("alt", "")
        if draws and not str(alt).strip():
            found.append(i)
    return found


# ---------------------------------------------------------------------------------------
# Jupyter Book's source folder: notebooks, landing page, _config.yml, _toc.yml


def _write_if_changed(path, data):
    """Write only when the content differs, so that Sphinx rebuilds only changed pages."""
    path = Path(path)
    data = data.encode() if isinstance(data, str) else data
    if path.exists() and path.read_bytes() == data:
        return
    path.parent.mkdir(parents=True, exist_ok=True)
    tmp = path.with_name(f".{path.name}.tmp")
    tmp.write_bytes(data)
    os.replace(tmp, path)


def _questions():
    """Each notebook's one-line question, from the course map table in notebook 00."""
    start = NOTEBOOKS / "00_start_here.ipynb"
    found = {}
    if not start.exists():
        return found
    row = re.compile(r"^\|\s*\[[^\]]*\]\(([^)#]+)\.ipynb\)\s*\|\s*(.+?)\s*\|")
    for cell in read(start).cells:
        if cell.cell_type == "markdown":
            for line in cell.source.splitlines():
                m = row.match(line)
                if m:
                    found[m.group(1)] = m.group(2)
    return found


_NUMBER_WORDS = {"an": 1, "a": 1, "one": 1, "two": 2, "three": 3, "four": 4, "five": 5}


def _number(word):
    word = word.lower()
    return float(word) if re.fullmatch(r"\d+(\.\d+)?", word) else _NUMBER_WORDS.get(word)


def _prose(nb):
    """The markdown a learner reads: no speaker notes, solutions, grading or checks, nor
    anything else the book leaves out (is_left_out) or adds (its solution markers)."""
    return [c for c in nb.cells if c.cell_type == "markdown" and not (
        is_left_out(c) or is_solution(c) or c.source in (SOLUTION_BEGIN, SOLUTION_END))]


def chapter_time(nb):
    """(minutes, how it is known) for a notebook. Its own text first ("two lessons of about
    an hour each", "about 90 minutes"); else an estimate from its length: 60 words of
    mathematical prose a minute, half a minute per code cell, 10 minutes per exercise."""
    text = "\n".join(c.source for c in _prose(nb))
    m = re.search(r"\b(\w+) (?:lessons|parts|sessions) of about (an?|one|two|\d+) (hours?|minutes) each",
                  text, re.I)
    if m and _number(m.group(1)) and _number(m.group(2)):
        unit = 60 if m.group(3).startswith("hour") else 1
        return int(_number(m.group(1)) * _number(m.group(2)) * unit), "its own text"
    m = re.search(r"\b(?:takes|take|lasts|is) about (an?|one|two|three|\d+(?:\.\d+)?) (hours?|minutes)\b",
                  text, re.I)
    if m and _number(m.group(1)):
        return int(_number(m.group(1)) * (60 if m.group(2).startswith("hour") else 1)), "its own text"
    words = sum(len(re.findall(r"[A-Za-z]+", c.source)) for c in _prose(nb))
    code = sum(1 for c in nb.cells if c.cell_type == "code" and not (
        is_solution(c) or is_left_out(c)))
    exercises = sum(1 for c in nb.cells if "answer" in _tags(c) and not is_left_out(c))
    minutes = words / 60 + code / 2 + 10 * exercises
    return max(15, int(round(minutes / 15)) * 15), "estimated"


def format_time(minutes):
    h, m = divmod(int(minutes), 60)
    if not h:
        return f"{m} min"
    return f"{h} h" + (f" {m} min" if m else "")


_GOALS = re.compile(r"^#{2,4}\s+What you will learn", re.I)
_NEEDS = re.compile(r"^#{2,4}\s+What you need first|\*\*You need first:?\*\*", re.I | re.M)


def chapter_front(nb, time=None):
    """The book's copy of a chapter begins with its time and its goals: a line with the time
    goes after the title cell, followed by the notebook's own "What you will learn" and
    "What you need first" cells (moved up when other text stood before them). TIME: the
    chapter's (minutes, how it is known), as the start page's table gives it (prepare
    works it out once, from the notebook, for both)."""
    from nbformat.v4 import new_markdown_cell
    cells = list(nb.cells)
    if not cells:
        return nb
    minutes, how = time or chapter_time(nb)
    front = [c for c in cells[1:6] if c.cell_type == "markdown" and (
        _GOALS.match(c.source) or _NEEDS.search(c.source))]
    rest = [c for c in cells[1:] if not any(c is f for f in front)]
    note = " (estimated from its length)" if how == "estimated" else ""
    card = new_markdown_cell(f"**Time:** about {format_time(minutes)}{note}.")
    card.metadata["tags"] = ["course-chapter-time"]
    card.id = "course-chapter-time"
    nb = copy.copy(nb)
    nb.cells = [cells[0], card] + front + rest
    return nb


def _who_for():
    """The bullets of notebook 00's "Who it is for"."""
    start = NOTEBOOKS / "00_start_here.ipynb"
    if start.exists():
        for c in _prose(read(start)):
            if re.match(r"^#{1,4}\s+Who it is for", c.source):
                return "\n".join(l for l in c.source.splitlines()[1:] if l.strip())
    return "- You know matrices, the cross product, Taylor series and a little NumPy."


def landing_page(paths, nbs, repository_url=REPOSITORY_URL, times=None):
    """The start page. TIMES: each chapter's (minutes, how it is known), the same that its
    own page shows (prepare); by default worked out from NBS."""
    times = list(times) if times is not None else [chapter_time(nb) for nb in nbs]
    questions = _questions()
    c = citation()
    rows = ["| | chapter | the question it answers | time |", "|---|---|---|---|"]
    total = 0
    estimated = False
    for n, (p, nb) in enumerate(zip(paths, nbs), 1):
        q = questions.get(p.stem, "Start here: the course in one page, the set-up, the notation."
                          if p.stem.startswith("00") else "")
        minutes, how = times[n - 1]
        total += minutes
        estimated = estimated or how == "estimated"
        star = "*" if how == "estimated" else ""
        rows.append(f"| {n} | [{label(nb, p)}]({p.name}) | {q} | {format_time(minutes)}{star} |")
    path = "\n".join(rows)
    footnote = ("\n\n\\* estimated from the chapter's length (60 words of prose a minute, half a "
                "minute per code cell, 10 minutes per exercise); the other times are the "
                "chapter's own.") if estimated else ""
    first = next((p for p in paths if p.name.startswith("00")), paths[0] if paths else None)
    one = next((p for p in paths if p.name.startswith("01")), first)
    log = next((p for p in paths if p.name.startswith("04")), one)
    errata = next((p for p in paths if not p.name[0].isdigit()), None)
    launch = ("- **With nothing installed**: the rocket button at the top of a notebook's page "
              "opens it on Binder.\n" if (repository_url or "").strip() else "")
    edition = (f"Version {c['version']}, {_long_date(c['date'])}. " if c["version"] else "")
    return rf"""# {BOOK_TITLE}

{edition}By {re.sub(r"^The ", "the ", c['authors'])}. The text and figures are under [CC BY 4.0]({CC_BY}), the code under
BSD-3-Clause (<a href="LICENSE.txt">LICENSE</a>; to cite the course: <a href="CITATION.cff">CITATION.cff</a>).

An open course on the two maps between angular velocities and rotation matrices. Spinning
at a constant angular velocity $\omega$ for a time $\tau$ gives the rotation

$$
R(\omega, \tau) = e^{{\tau\hat\omega}} = I + \frac{{\sin\theta}}{{\theta}}\,\tau\hat\omega
  + \frac{{1-\cos\theta}}{{\theta^2}}\,(\tau\hat\omega)^2,
$$

where $\theta = \lVert\omega\rVert\,\lvert\tau\rvert$ is the angle turned, and the logarithm goes back from $R$ to $\omega$.

## What you will learn

- why every power of a cross-product matrix reduces to two, and how that turns the power
  series of $e^{{\tau\hat\omega}}$ into Rodrigues' formula;
- how to evaluate it in floating point without losing digits near $0$, and what the plane
  (complex numbers) says about it;
- how to take the logarithm of a rotation at every angle, a half-turn (180°) included, and
  check it against a 50-digit reference;
- how to interpolate, integrate and average rotations, and differentiate $\exp$ and $\log$;
- where the course's two sources (a set of lecture notes and Gallier's textbook) go wrong.

## What you need first

{_who_for()}

## The path, with the time each chapter takes

Take the chapters in order: each builds on the ones before it. In all, about
{format_time(total)} of reading, running and exercises.

{path}{footnote}

## Where to start

- **New to the course**: [{label(nbs[paths.index(first)], first) if first else ''}]({first.name if first else ''}),
  then [{label(nbs[paths.index(one)], one) if one else ''}]({one.name if one else ''}) and onwards.
- **You know the hat map and Rodrigues' formula** and want the logarithm at 180°:
  [{label(nbs[paths.index(log)], log) if log else ''}]({log.name if log else ''}).
""" + (f"""- **You teach from the sources** and want their mistakes:
  [{label(nbs[paths.index(errata)], errata)}]({errata.name}).
""" if errata else "") + rf"""
Each chapter begins with its time, its goals and what it needs first.
<span class="course-web-only">Worked solutions sit folded under each exercise (*Show solution*): try the exercise first.</span><span class="course-print-only">Worked solutions are printed at the end of each chapter, with the page given under each exercise: try the exercise first.</span>

## How to run the notebooks

{launch}- **On your own machine** (Python 3.11.5 or newer, and `make`): in the course folder, run
  `make lab`. The first time it installs the pinned packages into `.venv`; then JupyterLab
  opens `notebooks/00_start_here.ipynb`. Run each notebook top to bottom, then change the
  numbers and run it again.
- <span class="course-web-only">**A single notebook**: the download menu at the top of its page gives the `.ipynb`; its
  first cell says how to run it (it needs the course's library, `so3lib`). The same menu
  gives the whole course as one PDF for paper, <a href="course.pdf">course.pdf</a>.</span><span class="course-print-only">**The notebooks themselves** are in the course folder's `notebooks/`; the web edition of this book (`make book`) reads offline, with figures that turn.</span>
- **Exercises** check themselves: write your answer in the empty cell, run the checker
  below it, and read what it says.
"""


def _plotly_js():
    """plotly.js from the plotly package, when it is installed (its figures need it)."""
    try:
        import plotly
    except ImportError:
        return None
    js = Path(plotly.__file__).parent / "package_data" / "plotly.min.js"
    return js if js.is_file() else None


def citation():
    """The course's version, release date and authors, from CITATION.cff."""
    data = yaml.safe_load(CITATION.read_text()) if CITATION.exists() else {}
    authors = ", ".join(a.get("name") or " ".join(filter(None, [a.get("given-names"),
                                                                a.get("family-names")]))
                        for a in data.get("authors", [])) or "the course authors"
    return {"version": str(data.get("version", "")), "date": str(data.get("date-released", "")),
            "authors": authors}


def _long_date(iso):
    import datetime
    try:
        d = datetime.date.fromisoformat(iso)
    except ValueError:
        return iso
    return f"{d.day} {d.strftime('%B')} {d.year}"


def footer_html():
    """The licence line under every page."""
    c = citation()
    edition = f"Version {c['version']}, {_long_date(c['date'])}. " if c["version"] else ""
    return (f'<p class="course-licence">{edition}The course text and figures are under '
            f'<a href="{CC_BY}">CC BY 4.0</a>, the code (so3lib, the notebooks\' code cells, the '
            f'tools) under BSD-3-Clause: see <a href="LICENSE.txt">LICENSE</a>; to cite it, '
            f'<a href="CITATION.cff">CITATION.cff</a>. '
            f'The whole course as one PDF: <a href="course.pdf">course.pdf</a>.</p>')


def closing_page(repository_url=REPOSITORY_URL):
    """The PDF's last page: the edition, the licence, how to cite the course, and where its
    notebooks are (the print appends it after the last chapter: print_pdf)."""
    from html import escape
    c = citation()
    edition = f"Version {c['version']}, {_long_date(c['date'])}." if c["version"] else ""
    year = c["date"][:4] if c["date"] else ""
    cite = (f"{c['authors']} ({year}). {BOOK_TITLE}: an open course."
            + (f" Version {c['version']}." if c["version"] else "")
            + (f" {repository_url}" if repository_url else ""))
    where = (f'The notebooks, so3lib and the tools that build this book are at '
             f'<a href="{escape(repository_url)}">{escape(repository_url)}</a>.' if repository_url else
             "The notebooks (notebooks/), so3lib and the tools that build this book come with "
             "the course's folder; the web book's download menu gives each notebook, ready to run.")
    return (f'<section id="course-print-close" class="course-close">'
            f'<h2>About this course</h2>'
            f'<p><strong>{escape(BOOK_TITLE)}</strong>. {escape(edition)} By {escape(re.sub(r"^The ", "the ", c["authors"]))}.</p>'
            f'<p>The course text and figures are under the Creative Commons Attribution 4.0 licence '
            f'(CC BY 4.0, {CC_BY}); the code (so3lib, the notebooks\' code cells, the tools) under '
            f'the BSD 3-Clause licence. The full terms are in the file LICENSE.</p>'
            f'<p>To cite the course: {escape(cite)} (CITATION.cff holds the same in a form '
            f'reference managers read.)</p>'
            f'<p>{where} Each chapter runs in JupyterLab as it is; the worked solutions, printed '
            f'here at the end of each chapter, are folded under their exercises there.</p>'
            f'</section>')


def book_config(repository_url=REPOSITORY_URL, jupyterhub_url=JUPYTERHUB_URL):
    """Jupyter Book's _config.yml, as a dict. Without a repository URL the book carries no
    launch buttons and no repository link (a button that goes nowhere is worse than none)."""
    repository_url = (repository_url or "").strip()
    launch = {"notebook_interface": "jupyterlab", "binderhub_url": "", "jupyterhub_url": "",
              "thebe": False, "colab_url": "", "deepnote_url": ""}
    if repository_url:
        launch["binderhub_url"] = BINDERHUB_URL
        launch["jupyterhub_url"] = (jupyterhub_url or "").strip()
    return {
        "title": BOOK_TITLE,
        # the theme's footer says "By <author>": "By the so3-course authors"
        "author": re.sub(r"^The ", "the ", citation()["authors"]),
        "copyright": citation()["date"][:4] or "2026",
        "only_build_toc_files": True,
        "exclude_patterns": ["_build", "**.ipynb_checkpoints", "course_static", "course_extra"],
        "execute": {"execute_notebooks": "off"},
        "parse": {
            # a bare https:// address in the text is a link (only with its scheme: "README.md"
            # is no web address)
            "myst_enable_extensions": ["dollarmath", "amsmath", "colon_fence", "linkify"],
            "myst_dmath_double_inline": True,
        },
        "html": {
            "use_repository_button": bool(repository_url),
            "use_issues_button": False,
            "use_edit_page_button": False,
            "use_download_button": True,
            "home_page_in_navbar": False,  # the book's title above the contents leads home
            "use_multitoc_numbering": False,
            "extra_footer": footer_html(),
        },
        "launch_buttons": launch,
        "repository": {"url": repository_url, "path_to_book": "notebooks", "branch": BRANCH},
        "latex": {"use_jupyterbook_latex": False},
        "sphinx": {
            "recursive_update": True,  # add to Jupyter Book's theme options, not replace them
            "config": {
                "html_context": {"default_mode": "auto"},
                "mathjax_path": MATHJAX,
                "mathjax3_config": {
                    "tex": {"tags": "ams"},
                    "options": {"menuOptions": {"settings": {"assistiveMml": True}}},
                },
                "html_static_path": ["course_static"],
                "html_extra_path": ["course_extra"],
                "html_css_files": ["course.css"],
                "html_favicon": "course_static/favicon.svg",
                "myst_linkify_fuzzy_links": False,
                "html_js_files": ["course.js"],
                "html_sourcelink_suffix": "",
                "html_show_search_summary": False,  # summaries fetch each page: not from file://
                "html_last_updated_fmt": None,
                "myst_heading_anchors": 3,
                "nb_render_markdown_format": "myst",
                "suppress_warnings": ["myst.header", "mystnb.unknown_mime_type",
                                      "myst.xref_missing"],  # links to raw <a id> anchors: tested
                "html_theme_options": {
                    "show_toc_level": 2,
                    "navbar_persistent": [],  # search sits above the contents, not in a header too
                    "use_download_button": True,
                    "pygments_light_style": "a11y-high-contrast-light",
                    "pygments_dark_style": "a11y-high-contrast-dark",
                },
            },
        },
    }


def book_toc(paths):
    """Jupyter Book's _toc.yml: the landing page, the numbered notebooks, the appendices."""
    main = [{"file": p.stem} for p in paths if p.name[0].isdigit()]
    appendix = [{"file": p.stem} for p in paths if not p.name[0].isdigit()]
    parts = [{"caption": "The course", "chapters": main}]
    if appendix:
        parts.append({"caption": "Appendix", "chapters": appendix})
    return {"format": "jb-book", "root": "index", "parts": parts}


def prepare(src=SOURCE, repository_url=REPOSITORY_URL, jupyterhub_url=JUPYTERHUB_URL):
    """Write Jupyter Book's source folder; returns the notebooks' paths in order."""
    import nbformat
    src = Path(src)
    paths = course_notebooks()
    nbs = [read(p) for p in paths]
    keep = {"index.md", "_config.yml", "_toc.yml"} | {p.name for p in paths}
    for old in src.glob("*"):
        if old.is_file() and old.name not in keep:
            old.unlink()  # a notebook renamed or removed
    anchors, slugs = heading_anchors(nbs), heading_slugs(paths, nbs)
    # each chapter's time, worked out once: its page and the start page's table show it
    times = [chapter_time(nb) for nb in nbs]
    for p, nb, time in zip(paths, nbs, times):
        _write_if_changed(src / p.name, nbformat.writes(
            chapter_front(learner_copy(nb, anchors, slugs), time)) + "\n")
    _write_if_changed(src / "index.md", landing_page(paths, nbs, repository_url, times))
    plotly = _plotly_js()
    # Not "_static": Jupyter Book would load every .js file in that folder into every page.
    static = src / "course_static"
    if (src / "_static").exists():
        shutil.rmtree(src / "_static")
    static.mkdir(parents=True, exist_ok=True)
    for f in ("course.css", "course.js", "favicon.svg"):
        _write_if_changed(static / f, (STATIC / f).read_bytes())
    # copied as they are to the book's top folder: the licence and the citation, which the
    # footer links
    extra = src / "course_extra"
    for f, name in ((LICENSE, "LICENSE.txt"), (CITATION, "CITATION.cff")):
        if f.exists():
            _write_if_changed(extra / name, f.read_bytes())
    vendor.install(static / "vendor", ["mathjax3"])
    svg = static / "vendor" / "mathjax3" / "es5" / "tex-svg-full.js"  # the decks' renderer
    if svg.exists():
        svg.unlink()
    if plotly:
        _write_if_changed(static / "vendor" / "plotly.min.js", plotly.read_bytes())
    for f in sorted((NOTEBOOKS / "images").rglob("*")) if (NOTEBOOKS / "images").is_dir() else []:
        if f.is_file():
            _write_if_changed(src / "images" / f.relative_to(NOTEBOOKS / "images"), f.read_bytes())
    config = book_config(repository_url, jupyterhub_url)
    _write_if_changed(src / "_config.yml", yaml.safe_dump(config, sort_keys=False))
    _write_if_changed(src / "_toc.yml", yaml.safe_dump(book_toc(paths), sort_keys=False))
    return paths


# ---------------------------------------------------------------------------------------
# Sphinx, then a pass over the HTML


def inputs_key(src=SOURCE):
    """A digest of everything a build of SRC reads: each file under SRC (the notebooks'
    copies, the landing page, the configuration, the vendored scripts and pictures), the
    notebooks themselves (the HTML pass puts them behind the download button), this
    script (its Sphinx settings and its HTML pass), and the versions of the packages that
    render the book. The same key, the same book."""
    import hashlib
    from importlib.metadata import PackageNotFoundError, version
    src = Path(src)
    digest = hashlib.sha256(Path(__file__).read_bytes())
    for name in ("jupyter-book", "sphinx", "myst-nb", "myst-parser", "sphinx-book-theme",
                 "pydata-sphinx-theme", "beautifulsoup4"):
        try:
            digest.update(f"\0{name} {version(name)}".encode())
        except PackageNotFoundError:
            digest.update(f"\0{name} absent".encode())
    for f in sorted(f for f in src.rglob("*") if f.is_file()):
        digest.update(f"\0{f.relative_to(src).as_posix()}\0".encode())
        digest.update(f.read_bytes())
    for nb in course_notebooks():
        digest.update(f"\0notebooks/{nb.name}\0".encode())
        digest.update(nb.read_bytes())
    return digest.hexdigest()


@contextlib.contextmanager
def _locked(name):
    """Hold BUILD/.NAME.lock: two builds at once (`make book` and `make pdf`, or two test
    workers) take turns at what they share; the second then finds the work done."""
    BUILD.mkdir(parents=True, exist_ok=True)
    with open(BUILD / f".{name}.lock", "w") as f:
        fcntl.flock(f, fcntl.LOCK_EX)
        try:
            yield
        finally:
            fcntl.flock(f, fcntl.LOCK_UN)


def _built(out, builder, key):
    """True when OUT holds the BUILDER build, HTML pass included, of the inputs KEY (see
    inputs_key): Sphinx and the pass can be skipped. A build that stopped half way has
    recorded nothing, so it runs again."""
    return Stamps(out).fresh("index.html", f"{builder} {key}")


def _record_built(out, builder, key):
    stamps = Stamps(out)
    stamps.record("index.html", f"{builder} {key}")
    stamps.save()


def sphinx(src, out, builder):
    """Run Jupyter Book's Sphinx build; raises SystemExit on failure."""
    from jupyter_book.sphinx import build_sphinx
    src = Path(src)
    overrides = {"external_toc_path": (src / "_toc.yml").as_posix(), "latex_individualpages": False}
    result = build_sphinx(str(src), str(out), noconfig=True, path_config=str(src / "_config.yml"),
                          confoverrides=overrides, doctreedir=str(DOCTREES / builder),
                          builder=builder, quiet=True, keep_going=True)
    if result:
        raise SystemExit(f"the {builder} build of the book failed ({result})")
    # when no page changed, Sphinx may finish without copying its static files again: the
    # course's own script and style are brought up to date here
    for f in ("course.css", "course.js"):
        _write_if_changed(Path(out) / "_static" / f, (src / "course_static" / f).read_bytes())


def wrap_solutions(soup):
    """Move everything between a pair of solution markers into one collapsed <details>."""
    changed = False
    for begin in soup.select("div.course-solution-begin"):
        # the markers sit inside their cell's wrapper; climb to the children of the section
        start = begin
        while start.parent is not None and start.parent.name not in ("section", "article", "main"):
            start = start.parent
        run, node = [], start.next_sibling
        end = None
        while node is not None:
            if getattr(node, "select_one", None) and (
                    "course-solution-end" in (node.get("class") or []) or node.select_one("div.course-solution-end")):
                end = node
                break
            run.append(node)
            node = node.next_sibling
        details = soup.new_tag("details", attrs={"class": "course-solution"})
        summary = soup.new_tag("summary")
        summary.string = "Show solution"
        details.append(summary)
        start.insert_before(details)
        for n in run:
            details.append(n.extract())
        start.decompose()
        if end is not None:
            end.decompose()
        changed = True
    for stray in soup.select("div.course-solution-end"):
        stray.decompose()
        changed = True
    return changed


# Sphinx wraps a display formula that has a line break ("\\", also inside a matrix) in
# \begin{split}...\end{split}, where MathJax refuses \tag: the tag moves after the split.
_SPLIT_TAG = re.compile(r"\\begin\{split\}((?:(?!\\end\{split\}).)*?)\s*\\tag\{([^{}]*)\}"
                        r"((?:(?!\\end\{split\}).)*?)\\end\{split\}", re.S)


_TOKEN = re.compile(r"(<[^>]+>)|([^<]+)")


def line_spans(html):
    """The inner HTML of a <pre> with each line in its own <span class="cl" style="--i:N">
    (N: its leading spaces), so that a long line wraps with a hanging indent (course.css).
    Pygments' spans that run over a line end are closed and opened again around it."""
    out, stack, line = [], [], []

    def end_line(newline):
        text = "".join(line)
        plain = re.sub(r"<[^>]+>", "", text)
        indent = len(plain) - len(plain.lstrip(" "))
        out.append(f'<span class="cl" style="--i:{indent}">{text}{"".join("</span>" for _ in stack)}'
                   f'{newline}</span>')
        line.clear()
        line.extend(stack)

    for m in _TOKEN.finditer(html):
        tag, text = m.group(1), m.group(2)
        if tag:
            line.append(tag)
            if tag.startswith("</"):
                if stack:
                    stack.pop()
            elif not tag.endswith("/>"):
                stack.append(tag)
            continue
        parts = text.split("\n")
        for i, part in enumerate(parts):
            line.append(part)
            if i < len(parts) - 1:
                end_line("\n")
    if re.sub(r"<[^>]+>", "", "".join(line)):
        end_line("")
    return "".join(out)


_CLOSING = re.compile(r"^[.,:;!?)\]\u2019\u201d]+")
_OPENING = re.compile(r"[(\[\u2018\u201c]+$")


def join_maths_punctuation(soup):
    """Inline maths and the punctuation that touches it ("$[0,\\pi]$." or "($e^x$") go in
    one span that does not wrap (course.css), so that a line never starts with the full
    stop or colon after a formula, nor ends with the bracket before one."""
    from bs4 import NavigableString
    changed = False
    for math in soup.select("article span.math"):
        if math.find_parent(class_="course-nowrap"):
            continue
        after, before = math.next_sibling, math.previous_sibling
        close = _CLOSING.match(after) if isinstance(after, NavigableString) else None
        open_ = _OPENING.search(before) if isinstance(before, NavigableString) else None
        if not (close or open_):
            continue
        box = soup.new_tag("span", attrs={"class": "course-nowrap"})
        math.insert_before(box)
        if open_:
            before.replace_with(NavigableString(before[:open_.start()]))
            box.append(NavigableString(open_.group(0)))
        box.append(math.extract())
        if close:
            after.replace_with(NavigableString(after[close.end():]))
            box.append(NavigableString(close.group(0)))
        changed = True
    return changed


def wrap_code_lines(soup):
    """Every code and output block of the article gets line_spans (once)."""
    changed = False
    for pre in soup.select("article pre"):
        if pre.select_one("span.cl") or pre.find_parent(class_="math"):
            continue
        spans = line_spans(pre.decode_contents())
        pre.clear()
        # parsed inside a <pre>: outside one, the parser folds a run of spaces between two
        # tags (a line's indent) into one space
        for node in list(BeautifulSoup(f"<pre>{spans}</pre>", "html.parser").pre.contents):
            pre.append(node.extract())
        pre["class"] = list(pre.get("class", [])) + ["course-lines"]
        changed = True
    return changed


_TEX_SYMBOLS = {
    "alpha": "α", "beta": "β", "gamma": "γ", "delta": "δ", "Delta": "Δ", "epsilon": "ε",
    "varepsilon": "ε", "theta": "θ", "vartheta": "θ", "Theta": "Θ", "lambda": "λ", "mu": "μ",
    "pi": "π", "Pi": "Π", "rho": "ρ", "sigma": "σ", "Sigma": "Σ", "tau": "τ", "phi": "φ",
    "varphi": "φ", "Phi": "Φ", "psi": "ψ", "omega": "ω", "Omega": "Ω", "eta": "η", "xi": "ξ",
    "kappa": "κ", "nu": "ν", "zeta": "ζ", "chi": "χ",
    "cdot": "·", "times": "×", "le": "≤", "leq": "≤", "ge": "≥", "geq": "≥", "ne": "≠",
    "neq": "≠", "approx": "≈", "to": "→", "mapsto": "↦", "infty": "∞", "in": "∈",
    "lVert": "‖", "rVert": "‖", "Vert": "‖", "|": "‖", "lvert": "|", "rvert": "|", "vert": "|",
    "pm": "±", "mp": "∓", "partial": "∂", "nabla": "∇", "sum": "Σ", "prod": "Π", "circ": "∘",
    "ldots": "…", "dots": "…", "cdots": "⋯", "sim": "∼", "equiv": "≡", "perp": "⊥",
    "parallel": "∥", "subset": "⊂", "top": "ᵀ", "dagger": "†", "ell": "ℓ", "hbar": "ħ",
    "sqrt": "√", "int": "∫", "oplus": "⊕", "otimes": "⊗", "langle": "⟨", "rangle": "⟩",
    "quad": " ", "qquad": " ", ",": " ", ";": " ", ":": " ", "!": "", " ": " ",
    "{": "{", "}": "}", "lbrace": "{", "rbrace": "}",
}
_SUPERSCRIPT = str.maketrans("0123456789+-=()nT", "⁰¹²³⁴⁵⁶⁷⁸⁹⁺⁻⁼⁽⁾ⁿᵀ")
_SUBSCRIPT = str.maketrans("0123456789+-=()", "₀₁₂₃₄₅₆₇₈₉₊₋₌₍₎")


def tex_to_text(tex):
    """TeX maths as plain Unicode text, for places that show no typeset maths (a table's
    column label on a phone, the search's titles and excerpts): "\\theta = d" -> "θ = d"."""
    t = tex.strip()
    if t.startswith(("\\(", "\\[")):
        t = t[2:-2] if t.endswith(("\\)", "\\]")) else t[2:]
    t = t.strip("$")
    t = re.sub(r"\\(?:begin|end)\{[a-z*]+\}", " ", t)
    # an equation's number is not part of its text ("tag2.6"); nor its label
    t = re.sub(r"\\(?:tag\*?|label)\s*\{[^{}]*\}|\\(?:notag|nonumber)\b", " ", t)
    t = re.sub(r"\\(?:left|right|big|Big|bigg|Bigg)[lr]?\b\.?", "", t)
    t = re.sub(r"\\(?:operatorname|mathrm|mathbf|mathit|mathsf|mathcal|mathbb|text|textrm|textit|boldsymbol|bm)\s*\{([^{}]*)\}", r"\1 ", t)
    for _ in range(3):  # nested fractions
        t = re.sub(r"\\[dt]?frac\s*\{([^{}]*)\}\s*\{([^{}]*)\}", lambda m: (
            f"{m.group(1)}/{m.group(2)}" if len(m.group(1)) < 2 and len(m.group(2)) < 2
            else f"({m.group(1)})/({m.group(2)})"), t)
    t = re.sub(r"\\(?:hat|widehat)\s*\{\\([A-Za-z]+)\}", lambda m: _TEX_SYMBOLS.get(m.group(1), m.group(1)) + "\u0302", t)
    t = re.sub(r"\\(?:hat|widehat)\s*\\([A-Za-z]+)", lambda m: _TEX_SYMBOLS.get(m.group(1), m.group(1)) + "\u0302", t)
    t = re.sub(r"\\(?:hat|widehat)\s*([A-Za-z])", "\\1\u0302", t)
    t = re.sub(r"\\(?:hat|widehat)\s*\{([^{}]*)\}", lambda m: "".join(c + "\u0302" for c in m.group(1)) if len(m.group(1)) == 1 else f"({m.group(1)})^", t)
    t = re.sub(r"\\(?:tilde|widetilde)\s*\{?([A-Za-z])\}?", "\\1\u0303", t)
    t = re.sub(r"\\(?:bar|overline)\s*\{?([A-Za-z])\}?", "\\1\u0304", t)
    t = re.sub(r"\\(?:dot)\s*\{?([A-Za-z])\}?", "\\1\u0307", t)
    t = re.sub(r"\\sqrt\s*\{([^{}]*)\}", r"√(\1)", t)
    t = re.sub(r"\\([A-Za-z]+|.)", lambda m: _TEX_SYMBOLS.get(m.group(1), m.group(1)), t)
    # hats over a Greek letter that was a command: "\hat\omega" became "\hat ω"
    t = re.sub(r"\^\{([^{}]*)\}", lambda m: m.group(1).translate(_SUPERSCRIPT)
               if all(c in "0123456789+-=()nT" for c in m.group(1))
               else "^" + m.group(1) if len(m.group(1).replace("\u0302", "")) == 1 else "^(" + m.group(1) + ")", t)
    t = re.sub(r"\^([0-9nT])", lambda m: m.group(1).translate(_SUPERSCRIPT), t)
    # a digit sets as a subscript; a letter keeps its "_" ("e_z", not "ez": few letters
    # have a subscript form, and "e_z" is how one types it into the search)
    t = re.sub(r"_\{([^{}]*)\}", lambda m: m.group(1).translate(_SUBSCRIPT)
               if m.group(1).isdigit() else "_" + m.group(1), t)
    t = re.sub(r"_([0-9])", lambda m: m.group(1).translate(_SUBSCRIPT), t)
    t = t.replace("{", "").replace("}", "").replace("&", " ").replace("~", " ")
    return re.sub(r"\s+", " ", t).strip()


def plain_text(element):
    """An element's text with its maths as Unicode (tex_to_text), in a copy."""
    copy = BeautifulSoup(str(element), "html.parser")
    for math in copy.select(".math"):
        math.replace_with(" " + tex_to_text(math.get_text("")) + " ")
    text = re.sub(r"\s+", " ", copy.get_text(" ")).strip()
    return re.sub(r"\s+([,.;:)])", r"\1", re.sub(r"\(\s+", "(", text))


def section_index(out, pages):
    """Every section of every page, with its own text (not its subsections'), for the
    course's search (course.js): [{p: page, i: anchor, c: chapter, t: title, x: text}]."""
    entries = []
    for page in pages:
        soup = BeautifulSoup(page.read_text(encoding="utf-8"), "html.parser")
        article = soup.select_one("article")
        if article is None:
            continue
        # a figure's folded code is not what a reader searches for; maths is kept as text
        # (nor is the code of a worked solution, folded under its exercise: its words stay)
        for bad in article.select("script, style, .headerlink, .copybtn, details.hide.above-input, "
                                  "details.course-solution div.cell_input, "
                                  ".course-figure-shield, .plotly-graph-div, mjx-container"):
            bad.decompose()
        for math in article.select(".math"):
            math.replace_with(" " + tex_to_text(math.get_text("")) + " ")
        h1 = article.select_one("h1")
        chapter = h1.get_text(" ", strip=True) if h1 else page.stem
        for section in article.select("section[id]"):
            heading = section.find(re.compile(r"^h[1-6]$"))
            title = re.sub(r"\s+([,.;:!?)])", r"\1", heading.get_text(" ", strip=True)) if heading else chapter
            own = BeautifulSoup(str(section), "html.parser").section
            for sub in own.find_all("section", recursive=False):
                sub.decompose()
            for pre in own.select("pre"):  # code reads as written, not token by token
                pre.replace_with(" " + pre.get_text("") + " ")
            if own.find(re.compile(r"^h[1-6]$")):
                own.find(re.compile(r"^h[1-6]$")).decompose()
            text = re.sub(r"\s+", " ", own.get_text(" ")).strip()
            entries.append({"p": page.name, "i": section["id"], "c": chapter, "t": title, "x": text})
    return entries


def write_search(out):
    """The course's search (course.js) on search.html: an index of sections in
    _static/course-search.js, in place of Sphinx's page-level search, which lists titles
    only (its excerpts fetch each page, which a file:// page may not) and ranks pages by
    stems of words they need not contain."""
    import json
    out = Path(out)
    search = out / "search.html"
    pages = [out / "index.html"] + sorted(p for p in out.glob("*.html")
                                          if p.name not in {"index.html", "search.html", "genindex.html"})
    data = "window.COURSE_SEARCH = " + json.dumps(section_index(out, pages), ensure_ascii=False) + ";\n"
    _write_if_changed(out / "_static" / "course-search.js", data)
    if not search.exists():
        return
    soup = BeautifulSoup(search.read_text(encoding="utf-8"), "html.parser")
    if soup.select_one("script[data-course-search]"):
        return
    for tag in soup.select("script[src]"):
        if any(k in tag["src"] for k in ("searchtools.js", "searchindex.js", "language_data.js")):
            tag.decompose()
    soup.head.append(soup.new_tag("script", attrs={"src": "_static/course-search.js",
                                                   "data-course-search": ""}))
    write_atomic(search, str(soup))


def postprocess(out, repository_url=REPOSITORY_URL):
    """The HTML pass: solution blocks; the download button gives the notebook (download_copy)
    and the course's PDF. A
    page this pass (the same script) already went over, and that Sphinx has not written
    since, is left as it is: OUT/.postprocessed.json holds each page's size and time."""
    import hashlib
    import json
    out = Path(out)
    plotly_js = out / "_static" / "vendor" / "plotly.min.js"
    script = hashlib.sha256(Path(__file__).read_bytes()
                            + str(plotly_js.exists()).encode()).hexdigest()
    record = out / ".postprocessed.json"
    try:
        done = json.loads(record.read_text())
    except (OSError, ValueError):
        done = {}
    if done.get("script") != script:
        done = {"script": script}
    for page in out.glob("*.html"):
        if done.get(page.name) == [page.stat().st_size, page.stat().st_mtime_ns]:
            continue
        text = page.read_text(encoding="utf-8")
        fixed = _SPLIT_TAG.sub(r"\\begin{split}\1\3\\end{split}\\tag{\2}", text)
        soup = BeautifulSoup(fixed, "html.parser")
        changed = wrap_solutions(soup) or fixed != text
        changed = wrap_code_lines(soup) or changed
        changed = join_maths_punctuation(soup) or changed
        # The search button's visible text ("Search Ctrl+K") is its accessible name; the
        # theme's aria-label "Search" would contradict it (axe: label-content-name-mismatch).
        for button in soup.select("button.search-button__button[aria-label]"):
            del button["aria-label"]
            changed = True
        # Live code (thebe) is off, yet sphinx-thebe declares its CDN URL twice per page, a
        # script error: its pieces go (the launch buttons run the notebooks instead).
        for tag in soup.select("script, link[href*=sphinx-thebe]"):
            if ("sphinx-thebe" in (tag.get("src") or tag.get("href") or "")
                    or tag.get("type") == "text/x-thebe-config"
                    or (tag.name == "script" and "THEBE_JS_URL" in (tag.string or ""))):
                tag.decompose()
                changed = True
        # A page with a figure the learner turns loads the one copy of plotly.js (4.8 MB):
        # the figure's own script draws it once the page has loaded (so3lib.plot.show_3d).
        if (soup.select_one("div.plotly-graph-div") and plotly_js.exists()
                and not soup.select_one("script[data-course-plotly]")):
            soup.head.append(soup.new_tag("script", attrs={
                "src": plotly_js.relative_to(out).as_posix(), "data-course-plotly": ""}))
            changed = True
        # The figure holds buttons and a slider, which role="img" would hide from a screen
        # reader (axe: nested-interactive); "figure" keeps its label and its controls.
        for div in soup.select('div.plotly-graph-div[role="img"]'):
            div["role"] = "figure"
            changed = True
        # The theme's ".pdf" prints the web page (window.print()): the course's PDF instead.
        for button in soup.select("button.btn-download-pdf-button"):
            link = soup.new_tag("a", attrs={
                "class": "btn btn-sm btn-download-pdf-button dropdown-item", "href": "course.pdf",
                "title": "The whole course as one PDF, for paper", "data-bs-toggle": "tooltip",
                "data-bs-placement": "left"})
            for child in list(button.children):
                link.append(child.extract())
            text = link.select_one(".btn__text-container")
            if text is not None:
                text.string = "course.pdf"
            button.replace_with(link)
            changed = True
        # A table's cells carry their column's heading, which a phone shows above each cell
        # when it stacks the rows (course.css).
        for table in soup.select("article table"):
            heads = [plain_text(th) for th in table.select("thead th")]
            for tr in table.select("tbody tr"):
                for head, td in zip(heads, tr.find_all("td", recursive=False)):
                    if td.get("data-label") != head:
                        td["data-label"] = head
                        changed = True
        # myst-nb's collapsed input: its summary's text ("Show code cell source") is its name.
        for summary in soup.select("summary[aria-label]"):
            del summary["aria-label"]
            changed = True
        # The colour-mode button is named "Color mode"; its icons' titles are not its text.
        for icon in soup.select(".theme-switch-button i[title]"):
            del icon["title"]
            icon["aria-hidden"] = "true"
            changed = True
        if changed:
            write_atomic(page, str(soup))
        done[page.name] = [page.stat().st_size, page.stat().st_mtime_ns]
    write_atomic(record, json.dumps(done, indent=1, sort_keys=True))
    write_search(out)
    import nbformat
    sources = out / "_sources"
    for p in course_notebooks():
        if (sources / p.name).exists():
            _write_if_changed(sources / p.name, nbformat.writes(
                download_copy(read(p), p.name, repository_url)) + "\n")


def build(out=OUT, repository_url=REPOSITORY_URL, jupyterhub_url=JUPYTERHUB_URL):
    """Build the web site into OUT; returns its pages, index.html first, then one per
    notebook. Sphinx and the HTML pass run only when an input changed since the last build
    into OUT (inputs_key)."""
    with _locked("book-src"):
        paths = prepare(SOURCE, repository_url, jupyterhub_url)
        key = inputs_key(SOURCE)
    pages = [Path(out) / "index.html"] + [Path(out) / f"{p.stem}.html" for p in paths]
    with _locked("book-html"):
        if not (_built(out, "html", key) and all(p.is_file() for p in pages)):
            sphinx(SOURCE, out, "html")
            postprocess(out, repository_url)
            _record_built(out, "html", key)
        publish_pdf(out)
    return pages


def publish_pdf(out=OUT, pdf=PDF):
    """Every page's download menu links course.pdf, next to the pages: `make pdf` prints it
    and puts a copy there (so the folder travels whole); a later `make book` keeps it."""
    pdf = Path(pdf)
    if pdf.exists() and Path(out).is_dir():
        _write_if_changed(Path(out) / "course.pdf", pdf.read_bytes())


# ---------------------------------------------------------------------------------------
# The whole course as one PDF, printed by Chromium from the one-page build of the book

CHROMIUM_ARGS = ["--no-sandbox", "--disable-background-networking", "--disable-component-update",
                 "--disable-sync", "--disable-quic", "--no-first-run", "--disable-dev-shm-usage"]

# Runs in the one-page book before printing (twice: the second time with the page numbers
# the first print found). Paper is not a screen: each notebook starts a new page; the web's
# instructions ("Drag to turn", "move the slider", "the rocket button") give way to what the
# paper shows, and the "Previous / Next" links go; each chapter's worked solutions move to
# "Solutions" at its end, with a line under each exercise that gives the page; a contents
# list of every notebook and section leads (with page numbers once known).
PRINT_PREPARE = r"""(numbers) => {
  const toc = (numbers && numbers.toc) || [], sols = (numbers && numbers.sols) || [];
  // a heading's content, copied (typeset maths included), without its "#" link
  const headingCopy = h => {
    const c = h.cloneNode(true);
    c.querySelectorAll('a.headerlink').forEach(a => a.remove());
    c.querySelectorAll('[id]').forEach(e => e.removeAttribute('id'));
    c.querySelectorAll('mjx-container[data-course-size]').forEach(m => {
      m.style.fontSize = m.dataset.courseSize; });
    const nodes = [...c.childNodes];
    while (nodes.length && nodes[nodes.length - 1].nodeType === 3 && !nodes[nodes.length - 1].nodeValue.trim()) nodes.pop();
    while (nodes.length && nodes[0].nodeType === 3 && !nodes[0].nodeValue.trim()) nodes.shift();
    if (nodes.length && nodes[0].nodeType === 3) nodes[0].nodeValue = nodes[0].nodeValue.trimStart();
    return nodes;
  };
  const article = document.querySelector('.bd-article') || document.body;
  if (!document.body.dataset.coursePaper) {
    document.body.dataset.coursePaper = '1';
    // a picture is not a link to its own file on paper (a phone's tap to enlarge it)
    for (const a of document.querySelectorAll('a.course-figure-zoom')) a.replaceWith(...a.childNodes);
    // a heading that invites the reader to turn a figure ("Turn it: the box spinning")
    // names the figure on paper ("The box spinning"), in the contents list too
    for (const h of article.querySelectorAll('h1, h2, h3, h4')) {
      const w = document.createTreeWalker(h, NodeFilter.SHOW_TEXT);
      while (w.nextNode()) {
        const t = w.currentNode;
        if (!t.nodeValue.trim()) continue;
        if (/^\s*Turn it:\s*/.test(t.nodeValue)) {
          const rest = t.nodeValue.replace(/^\s*Turn it:\s*/, '');
          t.nodeValue = rest.charAt(0).toUpperCase() + rest.slice(1);
        }
        break;
      }
    }
    const starts = [...document.querySelectorAll('span[id^="document-"]')]
      .filter(s => s.nextElementSibling && s.nextElementSibling.tagName === 'SECTION');
    starts.forEach(s => s.nextElementSibling.classList.add('course-chapter'));
    const nav = document.createElement('nav');
    nav.id = 'course-print-toc';
    nav.setAttribute('aria-label', 'Contents');
    const first = starts.length ? starts[0] : document.querySelector('.bd-article section');
    first.parentNode.insertBefore(nav, first);
    // the web's navigation lines
    for (const p of article.querySelectorAll('p')) {
      const t = p.textContent.trim();
      if (/^(Previous|Next):/.test(t)) p.remove();
      else if (/^Notebook \w+ of the course\. (Previous|Next):/.test(t)) {
        const b = p.querySelector('strong');
        p.textContent = '';
        if (b) p.append(b, ' of the course.');
      }
    }
    // the web's instructions: a sentence that starts with one of these goes, with what
    // the paper shows in its place (the sentence may run over formulas and links)
    // phrases first, where the rest of the sentence still says something on paper
    const PHRASES = [
      [/Drag to turn the view; the slider runs /, 'On the screen a control runs '],
      [/Drag the slider: at /, 'At '],
      [/worked solutions behind\s*$/, 'worked solutions '],
      [/^Show solution$/, 'at the end of each chapter in print'],
      [/Drag to turn the ball; move the slider to walk the path\./,
       'The picture shows the path from one side (in the web book the ball turns, and a slider walks the path).'],
      [/Drag to look along the axis /, 'Seen along the axis '],
      [/Move the slider: the /, 'The '],
      [/the rocket button at the top of a\s+page of the book opens that notebook there/,
       "a Binder or JupyterHub link to the course's repository opens a notebook there"],
      [/stays folded until you click/, 'is printed at the end of its chapter'],
    ];
    // then any sentence that is still an instruction for the screen
    const SENTENCES = [
      [/Drag to [^.]*/, 'The picture shows the figure from one side (in the web book it turns).'],
      [/Drag the figure[^.]*/, ''],
      [/[Mm]ove the slider[^.]*/, ''],
      [/[Cc]lick the [^.]*button[^.]*/, ''],
    ];
    const walker = document.createTreeWalker(article, NodeFilter.SHOW_TEXT);
    const texts = [];
    while (walker.nextNode()) texts.push(walker.currentNode);
    const dropSentence = (node, at, replacement) => {
      // cut from AT in NODE to the end of the sentence, over formulas and links after it
      const text = node.nodeValue, head = text.slice(0, at), rest = text.slice(at);
      const end = rest.search(/[.](\s|$)/);
      const put = replacement ? replacement + ' ' : '';
      if (end >= 0) { node.nodeValue = head + put + rest.slice(end + 1).trimStart(); return; }
      node.nodeValue = head + put;
      let next = node.nextSibling;
      while (next) {
        const after = next.nextSibling;
        if (next.nodeType === 3) {
          const e = next.nodeValue.search(/[.](\s|$)/);
          if (e >= 0) { next.nodeValue = next.nodeValue.slice(e + 1).trimStart(); return; }
        }
        next.remove();
        next = after;
      }
    };
    for (const node of texts) {
      if (!node.parentNode || node.parentElement.closest('pre, code, mjx-container, .plotly-graph-div, script, style')) continue;
      for (const [re, put] of PHRASES) node.nodeValue = node.nodeValue.replace(re, put);
      for (const [re, put] of SENTENCES) {
        const m = node.parentNode ? node.nodeValue.match(re) : null;
        if (m) dropSentence(node, m.index, put);
      }
    }
    // each chapter's solutions, at its end
    let n = 0;
    for (const chapter of document.querySelectorAll('section.course-chapter')) {
      const found = [...chapter.querySelectorAll('details.course-solution')];
      if (!found.length) continue;
      const title = chapter.querySelector(':scope > h1, :scope > h2');
      const name = title ? title.textContent.replace('#', '').trim() : '';
      const end = document.createElement('section');
      end.className = 'course-solutions';
      const h = document.createElement('h2');
      h.textContent = 'Solutions: ' + name;
      end.appendChild(h);
      for (const d of found) {
        n += 1;
        let heading = null, el = d;
        while (el && !heading) {
          let prev = el.previousElementSibling;
          while (prev && !heading) {
            heading = prev.matches('h1, h2, h3, h4') ? prev : prev.querySelector('h2, h3, h4');
            prev = prev.previousElementSibling;
          }
          el = el.parentElement;
          if (el && el.matches('section') && !heading) heading = el.querySelector(':scope > h2, :scope > h3, :scope > h4');
        }
        const item = document.createElement('div');
        item.className = 'course-solution-printed';
        const h3 = document.createElement('h3');
        h3.id = 'course-solution-' + n;
        // the exercise's title as it reads above the exercise, its maths typeset
        h3.append('Solution to ', ...(heading ? headingCopy(heading) : ['the exercise above']));
        item.appendChild(h3);
        for (const child of [...d.childNodes]) if (child.nodeName !== 'SUMMARY') item.appendChild(child);
        end.appendChild(item);
        const ref = document.createElement('p');
        ref.className = 'course-solution-ref';
        ref.dataset.n = String(n);
        ref.innerHTML = '<em>Solution:</em> in “Solutions” at the end of this chapter' +
                        '<span class="course-solution-page"></span>.';
        d.replaceWith(ref);
      }
      chapter.appendChild(end);
    }
    document.body.dataset.courseSolutions = String(n);
    // a solution printed away from its exercise: "the figure below" is the one after the exercise
    for (const item of document.querySelectorAll('.course-solution-printed')) {
      const w = document.createTreeWalker(item, NodeFilter.SHOW_TEXT);
      while (w.nextNode()) {
        const t = w.currentNode;
        if (t.parentElement.closest('pre, code, mjx-container')) continue;
        t.nodeValue = t.nodeValue
          .replace(/\b([Tt])he figures\s+below\s+show\b/g, '$1he figures after the exercise show')
          .replace(/\b([Tt])he figure\s+below\s+shows\b/g, '$1he figure after the exercise shows')
          .replace(/\b([Tt])he figures?\s+below\b/g, '$1he figures after the exercise');
      }
    }
    // a code box with nothing to show (its input folded away on paper) leaves no empty frame
    for (const c of article.querySelectorAll('div.cell')) {
      const shown = [...c.querySelectorAll('pre, img, svg, table, .plotly-graph-div, p, mjx-container')]
        .some(e => !e.closest('details.hide.above-input') && (e.textContent.trim() || e.matches('img, svg, .plotly-graph-div')));
      if (!shown) c.classList.add('course-empty');
    }
    for (const pre of article.querySelectorAll('div.highlight')) {
      if (!pre.textContent.trim()) pre.classList.add('course-empty');
    }
    // a closing page: licence, how to cite, where the notebooks are
    const close = document.getElementById('course-print-close');
    if (close) article.appendChild(close);
  }
  // wide inline maths (in a table cell, say) is set smaller until it fits its box
  for (const m of article.querySelectorAll('mjx-container:not([display="true"])')) {
    // (the box is the block it sits in: not its span.math, which the theme makes a flex
    // box as wide as the formula, so that every formula seemed too wide for it)
    const box = m.closest('td, th, p, li, dd, dt, h1, h2, h3, h4, h5, h6, div') || m.parentElement;
    if (!box) continue;
    if (m.dataset.courseSize === undefined) m.dataset.courseSize = m.style.fontSize || '';
    m.style.fontSize = m.dataset.courseSize;
    const avail = box.clientWidth - 4, wide = m.getBoundingClientRect().width;
    if (avail > 0 && wide > avail) {
      m.style.fontSize = (100 * Math.max(0.55, avail / wide - 0.01)).toFixed(1) + '%';
    }
  }
  // what fits in a third of a page stays whole; what is longer may break across pages
  // (a long code block split, rather than a half-empty page and an empty frame)
  // (a box's inner block is never kept whole on its own: moved to the next page, it would
  // leave its box's frame empty on this one)
  for (const el of article.querySelectorAll('div.cell, div.cell_input, div.cell_output, div.math, mjx-container[display="true"], img, .plotly-graph-div, table')) {
    // a picture is never split: it and its output box stay whole when they fit on a page
    const picture = el.matches('img, .plotly-graph-div') || !!el.querySelector('img, .plotly-graph-div');
    el.classList.toggle('course-keep', el.getBoundingClientRect().height < (picture ? 900 : 380));
  }
  // a sentence that introduces what follows ("... doubles the middle one:") stays with
  // it: the paragraph and a formula, or a code box or table after a colon, in one box
  // not split
  for (const p of article.querySelectorAll('p')) {
    if (p.parentElement.classList.contains('course-intro-keep')) continue;
    const next = p.nextElementSibling;
    if (!next) continue;
    // (a display formula goes with the text before it, which often runs on after it)
    const introduces = /:\s*$/.test(p.textContent) && next.matches(
      'div.cell, div.highlight, div[class*=highlight-], .pst-scrollable-table-container, table, ul, ol');
    if (!introduces && !next.matches('div.math')) continue;
    if (next.getBoundingClientRect().height + p.getBoundingClientRect().height > 420) continue;
    const box = document.createElement('div');
    box.className = 'course-intro-keep';
    p.before(box);
    box.append(p, next);
  }
  // a heading stays with the start of what it heads: heading and next block kept together
  // (in one box that is not split), or with the first lines of a long one
  for (const h of article.querySelectorAll('h2, h3, h4')) {
    if (h.parentElement.classList.contains('course-head-keep')) continue;
    const next = h.nextElementSibling;
    if (!next || next.matches('section')) continue;
    if (next.getBoundingClientRect().height > 560) { next.classList.remove('course-keep'); continue; }
    const box = document.createElement('div');
    box.className = 'course-head-keep';
    h.before(box);
    box.append(h, next);
  }
  // (a chapter's title, like any heading, may sit in its course-head-keep box by now)
  const chapters = [...document.querySelectorAll('section.course-chapter')];
  const entries = [];
  for (const c of chapters) {
    const title = c.querySelector(':scope > h1, :scope > h2, :scope > .course-head-keep > h1, :scope > .course-head-keep > h2');
    if (!title) continue;
    entries.push({level: 1, id: c.id, text: title.textContent.replace('#', '').trim(), h: title});
    for (const s of c.querySelectorAll(':scope > section')) {
      const h = s.querySelector(':scope > h2, :scope > h3, :scope > .course-head-keep > h2, :scope > .course-head-keep > h3');
      if (h && s.id) entries.push({level: 2, id: s.id, text: h.textContent.replace('#', '').trim(), h});
    }
  }
  const nav = document.getElementById('course-print-toc');
  let html = '<h2>Contents</h2><ol class="course-print-toc">';
  entries.forEach((e, i) => {
    html += `<li class="toc-l${e.level}"><a href="#${e.id}"><span class="t"></span></a>` +
            `<span class="p">${toc[i] || ''}</span></li>`;
  });
  nav.innerHTML = html + '</ol>';
  // an entry reads as its heading does, its maths typeset
  nav.querySelectorAll('span.t').forEach((t, i) => { t.append(...headingCopy(entries[i].h)); });
  const solutionTitles = [...document.querySelectorAll('.course-solution-printed > h3, .course-solution-printed > .course-head-keep > h3')].map(h => h.textContent);
  document.querySelectorAll('p.course-solution-ref').forEach(p => {
    const i = Number(p.dataset.n) - 1;
    p.querySelector('.course-solution-page').textContent = sols[i] ? ', page ' + sols[i] : '';
  });
  return {toc: entries.map(e => e.text), sols: solutionTitles};
}"""

PRINT_CSS = """
@page { size: A4; margin: 16mm 14mm 18mm 14mm; }
.course-chapter { break-before: page; }
#course-print-toc { break-before: page; }
#course-print-toc ol { list-style: none; padding: 0; }
#course-print-toc li { display: flex; gap: 0.5em; margin: 0.15em 0; }
#course-print-toc li a { flex: 1; text-decoration: none; color: inherit; }
#course-print-toc li.toc-l1 { font-weight: 600; margin-top: 0.6em; }
#course-print-toc li.toc-l2 { padding-left: 1.5em; font-size: 0.92em; }
#course-print-toc .p { min-width: 2.5em; text-align: right; }
.bd-article img { max-width: 100% !important; height: auto; }
/* what fits in a third of a page stays whole (course-keep, set when printed: PRINT_PREPARE);
   a longer code block or table breaks across pages rather than leave half a page empty */
.bd-article .course-keep, .bd-article tr, .course-head-keep, .course-intro-keep { break-inside: avoid; }
.bd-article h1, .bd-article h2, .bd-article h3, .bd-article h4 { break-after: avoid; break-inside: avoid; }
.bd-article pre.course-lines > span.cl { break-inside: avoid; }
/* a code box does not begin at a page's foot with no line of code in it: its padding
   belongs to its first and last lines, which are not split from them */
.bd-article pre.course-lines { padding-top: 0 !important; padding-bottom: 0 !important; }
.bd-article pre.course-lines > span.cl:first-child { padding-top: 1rem; }
.bd-article pre.course-lines > span.cl:last-child { padding-bottom: 1rem; }
/* a code box that may break across pages draws its grey and its green bar with its lines,
   not round them: when its first line goes to the next page, what is left at the foot of
   this one (the box's own top edge) shows nothing */
.bd-article div.cell_input:not(.course-keep) { background: none !important;
  border-color: transparent !important; }
.bd-article div.cell_input:not(.course-keep) div.highlight,
.bd-article div.cell_input:not(.course-keep) pre { background: none !important;
  overflow: visible !important; }
.bd-article div.cell_input:not(.course-keep) pre.course-lines {
  padding-left: 0 !important; padding-right: 0 !important; }
.bd-article div.cell_input:not(.course-keep) pre.course-lines > span.cl {
  background: #f7f7f7; box-shadow: -3px 0 0 #008000, 1px 0 0 #ccc;
  padding-left: calc((var(--i, 0) + 4) * 1ch + 1rem); padding-right: 1rem; }
.bd-article div.cell_input:not(.course-keep) pre.course-lines > span.cl:first-child {
  box-shadow: -3px 0 0 #008000, 1px 0 0 #ccc, 0 -1px 0 #ccc; }
.bd-article div.cell_input:not(.course-keep) pre.course-lines > span.cl:last-child {
  box-shadow: -3px 0 0 #008000, 1px 0 0 #ccc, 0 1px 0 #ccc; }
/* whether a code or output box stays whole is its own class's say (course-keep): the
   theme's wrappers inside it (div.highlight, div.highlight-ipython3: flex boxes that avoid
   a break) would move the code to the next page and leave the box's frame empty here */
.bd-article div.cell div.highlight, .bd-article div.cell div[class*=highlight-] {
  display: block !important; }
.bd-article div.cell_input:not(.course-keep) div.highlight, .bd-article div.cell_input:not(.course-keep) pre,
.bd-article div.cell_input:not(.course-keep) div[class*=highlight-],
.bd-article div.cell_output:not(.course-keep) div[class*=highlight-],
.bd-article div.cell_output:not(.course-keep) div.highlight, .bd-article div.cell_output:not(.course-keep) pre,
.bd-article div.cell_output:not(.course-keep) div.output { break-inside: auto !important; }
.bd-article .course-empty { display: none !important; }
#jb-print-docs-body #print-main-content { display: none !important; }  /* ours is below */
/* the figures' play buttons, slider and toolbar do nothing on paper */
.js-plotly-plot .updatemenu-container, .js-plotly-plot .slider-container,
.js-plotly-plot .modebar-container { display: none !important; }
/* a table keeps within the page: its columns share the width, its words wrap, its text a
   little smaller (wide inline maths is set smaller to fit: PRINT_PREPARE) */
.bd-article .pst-scrollable-table-container { overflow: visible !important; }
.bd-article table { width: 100% !important; max-width: 100% !important; table-layout: fixed;
  font-size: 0.86em; }
.bd-article table th, .bd-article table td { overflow-wrap: anywhere; white-space: normal !important;
  hyphens: auto; padding: 0.3em 0.4em !important; }
.bd-article table code { white-space: normal !important; overflow-wrap: anywhere; }
.bd-article table:has(th:nth-child(3)) th:first-child { width: 20%; }
section.course-close { break-before: page; }
section.course-solutions { break-before: page; }
.course-solution-printed { margin-bottom: 1.2em; }
p.course-solution-ref { font-size: 0.92em; border-left: 3px solid #999; padding-left: 0.5em; }
.course-web-only { display: none !important; }
.course-print-only { display: inline !important; }
/* a figure's code that is not the point stays out of print, as it stays folded on screen */
details.hide.above-input { display: none !important; }
"""


# Text that runs past the printed column's right edge: a table cell, a formula or a code
# line wider than the column (Chromium cuts it off at the paper's edge).
PAST_MARGIN = r"""() => {
  const article = document.querySelector('.bd-article') || document.body;
  const right = article.getBoundingClientRect().right + 2;
  const past = [];
  for (const el of article.querySelectorAll('td, th, mjx-container, pre, img, .plotly-graph-div, p, li')) {
    if (!el.getClientRects().length || el.closest('.course-empty, details.hide.above-input')) continue;
    const r = el.getBoundingClientRect();
    if (r.width > 0 && r.right > right && !el.querySelector('td, th, p, li'))
      past.push(`${el.tagName.toLowerCase()} ${Math.round(r.right - right + 2)} px past: ` +
                (el.textContent || '').trim().replace(/\s+/g, ' ').slice(0, 60));
  }
  return past;
}"""


# Each 3-D scene as it will be printed (the paper's fonts, the column's width): its camera
# moved back along its line of sight until all it draws (every trace, the axis box with
# its tick labels and titles) lies inside its frame, and the frame no taller than the
# drawing then needs: course.js's fitting for a phone (courseFitScenes), given the paper's
# text size. Plotly's perspective scales a scene to its frame's height, so a slide's camera
# in a frame narrower than the slide's cut the drawing at its sides.
FIT_SCENES = """async () => {
  const frame = () => new Promise(r => requestAnimationFrame(() => r()));
  for (const d of document.querySelectorAll('.plotly-graph-div')) {
    if (!window.courseFitScenes || !d._fullLayout) continue;
    await frame();
    await Promise.resolve(window.courseFitScenes(d, 16));
  }
  await frame();
}"""


# Each figure as laid out for print: its title, its height, and the height of the block
# that moves with it to the next page when it does not fit (the outermost box kept whole
# round it: its cell, or a heading or introducing sentence kept with it), and the space
# between that block and what is printed before it (margins).
FIGURE_BLOCKS = r"""() => [...document.querySelectorAll('.plotly-graph-div')].map(d => {
  let block = d;
  for (let e = d; e && !e.matches('.bd-article'); e = e.parentElement)
    if (e.matches('.course-keep, .course-head-keep, .course-intro-keep')) block = e;
  let prev = null;
  for (let e = block; e && !prev && !e.matches('.bd-article'); e = e.parentElement) {
    let s = e.previousElementSibling;
    while (s && !s.getClientRects().length) s = s.previousElementSibling;
    prev = s;
  }
  const top = block.getBoundingClientRect().top;
  const t = d._fullLayout && d._fullLayout.title && d._fullLayout.title.text;
  return {title: String(t || '').replace(/<[^>]+>/g, ' '), height: d.getBoundingClientRect().height,
          block: block.getBoundingClientRect().height,
          lead: prev ? Math.max(0, top - prev.getBoundingClientRect().bottom) : 0};
})"""

# Figures made shorter by the given number of pixels ({index: pixels}); a 3-D scene's
# drawing, scaled to its frame's height, shrinks with it and still fits across.
SHRINK_FIGURES = r"""async (shrink) => {
  const figs = [...document.querySelectorAll('.plotly-graph-div')];
  for (const [i, by] of Object.entries(shrink)) {
    const d = figs[Number(i)], h = Math.round(d._fullLayout.height - by);
    for (const b of [d, d.parentElement])
      if (b && b.style.height && !b.classList.contains('cell_output')) b.style.height = h + 'px';
    await Plotly.relayout(d, {height: h});
  }
  await new Promise(r => requestAnimationFrame(() => r()));
}"""


def _page_words(pdf):
    """Each page of PDF as (height, [(top, bottom, word)]) in points (pdftotext -bbox)."""
    import subprocess
    html = subprocess.run(["pdftotext", "-bbox", str(pdf), "-"], capture_output=True,
                          text=True, check=True).stdout
    return [(float(h), [(float(a), float(b), w) for a, b, w in re.findall(
        r'<word xMin="[\d.]+" yMin="([\d.]+)" xMax="[\d.]+" yMax="([\d.]+)">([^<]*)</word>', body)])
        for h, body in re.findall(r'<page width="[\d.]+" height="([\d.]+)">(.*?)</page>', html, re.S)]


def figures_to_shrink(pdf, figures, margin_mm=16, most=0.4, at_most=0.35):
    """The figures (FIGURE_BLOCKS) that opened a page of PDF when the page before has
    most of its printed area empty (more than MOST of it) and would hold the figure's block
    if the figure were shorter by at most AT_MOST of its height: {index: pixels shorter}.
    (Chromium prints a CSS pixel as 0.75 pt.)"""
    pages = _page_words(pdf)
    margin = margin_mm / 25.4 * 72
    shrink, start = {}, 1
    for i, fig in enumerate(figures):
        key = _squash(fig["title"])[:24]
        if len(key) < 8:
            continue
        for n in range(start, len(pages)):
            height, words = pages[n]
            inside = [(a, b, w) for a, b, w in words if a > margin and b < height - margin]
            if not key or key not in _squash(" ".join(w for _, _, w in inside)):
                continue
            start = n
            if not _squash(" ".join(w for _, _, w in inside)).startswith(key):
                break
            before = [b for a, b, _ in pages[n - 1][1] if a > margin and b < pages[n - 1][0] - margin]
            foot = pages[n - 1][0] - margin
            free = (foot - max(before, default=margin)) / 0.75
            # (and a little more: the last line's box reaches below its letters)
            need = fig["block"] + fig.get("lead", 0) - free + 16
            if free > most * (foot - margin) / 0.75 and 0 < need <= at_most * fig["height"]:
                shrink[i] = need
            break
    return shrink


def chromium_executable():
    for c in (os.environ.get("CHROMIUM"), "/usr/bin/chromium", shutil.which("chromium"),
              shutil.which("chromium-browser"), shutil.which("google-chrome")):
        if c and os.path.isfile(c) and os.access(c, os.X_OK):
            return c
    raise SystemExit("the PDF is printed by Chromium: `apt-get install chromium`, or set "
                     "CHROMIUM=/path/to/chrome")


def _pdf_pages(pdf):
    """The text of each page of PDF, letters and digits only (pdftotext; line breaks fall
    anywhere and maths comes out scrambled)."""
    import subprocess
    text = subprocess.run(["pdftotext", "-layout", str(pdf), "-"], capture_output=True,
                          text=True, check=True).stdout
    return [_squash(_without_running_lines(p)) for p in text.split("\f")]


def _without_running_lines(page):
    """A printed page's text without its running header (the book's title, on every page:
    a title that starts as the book's does would be found on any page) and its footer."""
    lines = page.splitlines()
    while lines and not lines[0].strip():
        lines.pop(0)
    if lines and lines[0].strip() == BOOK_TITLE:
        lines.pop(0)
    while lines and not lines[-1].strip():
        lines.pop()
    if lines and re.fullmatch(r"\d+\s*/\s*\d+", lines[-1].strip()):
        lines.pop()
    return "\n".join(lines)


def _squash(t):
    return re.sub(r"[^A-Za-z0-9]+", "", t)


def _heading_pages(pages, titles, at=0):
    """Page (1-based) on which each title first appears from page AT on, in order."""
    found = []
    for title in titles:
        for key in (_squash(title)[:30], _squash(title)[:12]):
            n = next((n for n in range(at, len(pages)) if len(key) > 3 and key in pages[n]), None)
            if n is not None:
                found.append(str(n + 1))
                at = n
                break
        else:
            found.append("")
    return found


def _contents_end(pages, titles):
    """The page after the contents list: the first page after the Contents heading's that
    opens with the list's first title (each chapter starts a page of its own; a title found
    anywhere on a page could be its line in the contents list, or a short title such as
    "References" that stands higher up the list)."""
    if not titles:
        return 0
    start = next((n for n, p in enumerate(pages) if p.startswith("Contents")), 0)
    first = _squash(titles[0])[:30]
    return next((n for n in range(start + 1, len(pages)) if first and pages[n].startswith(first)),
                start + 1)


def print_pdf(site=PRINT_OUT, pdf=PDF, browser=None):
    """Print SITE/index.html (the one-page book) to PDF with Chromium, no network. Skipped
    when the page and this script are unchanged since the PDF was printed. BROWSER: a
    running Playwright Chromium to use (else one is started)."""
    import hashlib
    from playwright.sync_api import sync_playwright
    pdf = Path(pdf)
    stamp = pdf.with_name(pdf.name + ".stamp")
    script = Path(site) / "_static" / "course.js"   # it lays the 3-D figures out too
    key = hashlib.sha256(b"\0".join([(Path(site) / "index.html").read_bytes(),
                                       script.read_bytes() if script.exists() else b"",
                                       Path(__file__).read_bytes()])).hexdigest()
    if pdf.exists() and stamp.exists() and stamp.read_text() == key:
        return pdf
    footer = ('<div style="font-size:8px;width:100%;text-align:center;color:#444">'
              '<span class="pageNumber"></span> / <span class="totalPages"></span></div>')
    header = (f'<div style="font-size:8px;width:100%;text-align:center;color:#444">'
              f'{BOOK_TITLE}</div>')
    if browser is None:
        with sync_playwright() as pw:
            browser = pw.chromium.launch(executable_path=chromium_executable(), args=CHROMIUM_ARGS)
            try:
                return print_pdf(site, pdf, browser)
            finally:
                browser.close()
    # about the width of the printed column, so that figures are laid out for the paper
    context = browser.new_context(viewport={"width": 690, "height": 1000})
    try:
        context.route("**/*", lambda r: r.continue_() if r.request.url.startswith(
            ("file:", "data:", "about:", "blob:")) else r.abort())
        page = context.new_page()
        page.set_default_timeout(600_000)  # one page of the whole course: slow on a busy machine
        page.goto((Path(site) / "index.html").as_uri(), wait_until="domcontentloaded")
        page.wait_for_function("window.MathJax && MathJax.startup && MathJax.startup.promise")
        page.evaluate("MathJax.startup.promise")
        page.add_style_tag(content=PRINT_CSS)
        page.emulate_media(media="print")
        # the 3-D figures take the printed column's width (plotly lays them out on load)
        page.evaluate("""() => Promise.all([...document.querySelectorAll('.plotly-graph-div')]
                         .map(d => window.Plotly ? Plotly.Plots.resize(d) : null))""")
        page.wait_for_function("""() => [...document.querySelectorAll('.plotly-graph-div')]
                               .every(d => d._fullLayout)""")  # drawn once the page has loaded
        # (and laid out for the page's width by course.js, which would otherwise redo its
        # fonts after the paper's)
        page.wait_for_function("""() => !window.Plotly || [...document.querySelectorAll('.plotly-graph-div')]
                               .every(d => d.dataset.courseSceneFitted)""")
        page.evaluate("""() => Promise.all([...document.querySelectorAll('.plotly-graph-div')]
                         .map(d => window.Plotly ? Plotly.relayout(d, {sliders: [], updatemenus: [],
                           'title.text': (typeof d.layout.title === 'string' ? d.layout.title
                             : String((d.layout.title && d.layout.title.text) || ''))
                             .replace(/^Turn it:\\s*/, ''),
                           // a legend's title that tells the screen's reader to turn the
                           // figure ("on screen: drag to turn it") says nothing on paper
                           ...(/\\bdrag\\b|\\bon screen\\b/i.test(String((d.layout.legend && d.layout.legend.title
                               && (d.layout.legend.title.text || d.layout.legend.title)) || ''))
                               ? {'legend.title.text': ''} : {}),
                           // set for a projected slide; on a column of paper a third smaller
                           // and dark: plotly's grey is too light on paper
                           'title.font.size': 16, 'legend.font.size': 15, 'font.size': 15,
                           'font.color': '#111', 'title.font.color': '#111', 'legend.font.color': '#111',
                           'margin.b': 10, 'legend.bgcolor': 'rgba(255,255,255,0.85)',
                           ...Object.fromEntries(Object.keys(d._fullLayout).filter(k => /^scene\\d*$/.test(k))
                             .flatMap(sc => ['xaxis', 'yaxis', 'zaxis'].flatMap(a => [
                               [`${sc}.${a}.tickfont.size`, 14], [`${sc}.${a}.tickfont.color`, '#111'],
                               [`${sc}.${a}.title.font.size`, 16], [`${sc}.${a}.title.font.color`, '#111'],
                               [`${sc}.${a}.gridcolor`, '#bbb'], [`${sc}.${a}.nticks`, 4]])))}) : null))""")
        page.evaluate(FIT_SCENES)
        page.evaluate("html => { if (!document.getElementById('course-print-close')) "
                      "document.body.insertAdjacentHTML('beforeend', html); }", closing_page())
        titles = page.evaluate(PRINT_PREPARE, None)
        options = dict(format="A4", print_background=True, outline=True, tagged=True,
                       display_header_footer=True, header_template=header,
                       footer_template=footer,
                       margin={"top": "16mm", "bottom": "16mm", "left": "14mm", "right": "14mm"})
        tmp = Path(pdf).with_suffix(".tmp.pdf")
        page.pdf(path=str(tmp), **options)
        # a figure moved whole to the next page, leaving most of this one empty, is made
        # short enough to stay (a 3-D scene's drawing shrinks with its frame)
        shrink = figures_to_shrink(tmp, page.evaluate(FIGURE_BLOCKS))
        if shrink:
            page.evaluate(SHRINK_FIGURES, {str(i): by for i, by in shrink.items()})
            titles = page.evaluate(PRINT_PREPARE, None)
            page.pdf(path=str(tmp), **options)
        # second pass: the contents list gets the page numbers the first pass found
        pages = _pdf_pages(tmp)
        at = _contents_end(pages, titles["toc"])
        numbers = {"toc": _heading_pages(pages, titles["toc"], at),
                   "sols": _heading_pages(pages, titles["sols"], at)}
        page.evaluate(PRINT_PREPARE, numbers)
        # what would run past the right margin (and be cut off on paper), for the tests
        past = page.evaluate(PAST_MARGIN)
        page.pdf(path=str(tmp), **options)
        _write_if_changed(pdf.with_name(pdf.name + ".past-margin.json"), json.dumps(past, indent=1))
        os.replace(tmp, pdf)
        stamp.write_text(key)
    finally:
        context.close()
    return pdf


def build_pdf(pdf=PDF, repository_url=REPOSITORY_URL, jupyterhub_url=JUPYTERHUB_URL, browser=None):
    """The whole course as one PDF: the book built as one page, printed by Chromium. The
    one-page book is rebuilt only when an input changed (Sphinx's singlehtml builder
    rewrites the whole page every time), and printed only when the page changed."""
    with _locked("book-src"):
        prepare(SOURCE, repository_url, jupyterhub_url)
        key = inputs_key(SOURCE)
    from tools import check_system
    # the contents list's page numbers and the solutions' page references come from pdftotext
    check_system.require(["pdftotext"] + ([] if browser else ["chromium"]), "the course's PDF")
    with _locked("book-pdf"):
        if not _built(PRINT_OUT, "singlehtml", key):
            sphinx(SOURCE, PRINT_OUT, "singlehtml")
            postprocess(PRINT_OUT, repository_url)
            _record_built(PRINT_OUT, "singlehtml", key)
        printed = print_pdf(PRINT_OUT, pdf, browser)
    with _locked("book-html"):
        publish_pdf(OUT, printed)
    return printed


def report_missing_alt():
    lines = []
    for p in course_notebooks():
        cells = missing_alt(read(p))
        if cells:
            lines.append(f"{p.name}: figure without alt text in cell(s) {', '.join(map(str, cells))}")
    return lines


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--out", type=Path, default=OUT)
    parser.add_argument("--pdf", action="store_true", help="also print build/course.pdf")
    parser.add_argument("--repository-url", default=REPOSITORY_URL)
    parser.add_argument("--jupyterhub-url", default=JUPYTERHUB_URL)
    args = parser.parse_args(argv)
    pages = build(args.out, args.repository_url, args.jupyterhub_url)
    for line in report_missing_alt():
        print("warning:", line, file=sys.stderr)
    print(f"open {pages[0]}")
    if args.pdf:
        print(build_pdf(PDF, args.repository_url, args.jupyterhub_url))


if __name__ == "__main__":
    sys.exit(main())
