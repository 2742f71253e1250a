"""`make book`: the course as a static web site, build/book/index.html and one page per notebook.

The landing page says what the course is, lists the notebooks in order with their
sections, and how to run them. Each notebook is rendered with its stored outputs, a
contents sidebar and previous / next links; links between notebooks point at the pages.
MathJax and require.js are unpacked into build/book/vendor/ from the npm registry
(tools/vendor.py), so the book reads offline: open build/book/index.html in a browser.

Usage: python -m tools.book [--out DIR]
"""

import argparse
import html
import re
import sys
from pathlib import Path

from bs4 import BeautifulSoup
from nbconvert.exporters import HTMLExporter
from nbformat.v4 import new_markdown_cell, new_notebook
from traitlets.config import Config

from tools import vendor
from tools.common import (BUILD, NOTEBOOKS, TEMPLATES, Stamps, copy_assets, course_notebooks, label,
                          read, relink, tooling_key, write_atomic)

VENDOR_DIR = "vendor"
BOOK_TITLE = "The exponential and logarithm of SO(3)"
TOC_MARK = "<!--COURSE-PAGE-TOC-->"


def exporter():
    c = Config()
    c.HTMLExporter.mathjax_url = f"{VENDOR_DIR}/{vendor.MATHJAX_JS}"
    c.HTMLExporter.require_js_url = f"{VENDOR_DIR}/{vendor.REQUIRE_JS}"
    c.HTMLExporter.extra_template_basedirs = [str(TEMPLATES)]
    c.HTMLExporter.extra_template_paths = [str(TEMPLATES)]
    c.HTMLExporter.template_name = "course_book"
    return HTMLExporter(config=c)


def sections(page_html):
    """(id, text) of each section heading (h2) of a rendered page, in order."""
    soup = BeautifulSoup(page_html, "html.parser")
    found = []
    for h in soup.select(".jp-MarkdownOutput h2[id]"):
        for a in h.select("a.anchor-link"):
            a.decompose()
        found.append((h["id"], h.get_text(" ", strip=True)))
    return found


def _questions():
    """Each notebook's one-line question, from the course map table in notebook 00."""
    start = NOTEBOOKS / "00_start_here.ipynb"
    found = {}
    if not start.exists():
        return found
    row = re.compile(r"^\|\s*\[[^\]]*\]\(([^)#]+)\.ipynb\)\s*\|\s*(.+?)\s*\|\s*$")
    for cell in read(start).cells:
        if cell.cell_type == "markdown":
            for line in cell.source.splitlines():
                m = row.match(line)
                if m:
                    found[m.group(1)] = m.group(2)
    return found


def landing_notebook(pages):
    """The landing page, as a notebook of markdown cells (rendered like every other page)."""
    questions = _questions()
    # Raw HTML rather than markdown links: markdown would percent-encode the section ids
    # differently from nbconvert's headings, and the links would miss their anchors.
    esc = html.escape
    contents = ['<ol class="course-contents">']
    for page in pages:
        contents.append(f'<li><strong><a href="{esc(page["href"])}">{esc(page["title"])}</a></strong>')
        if page["stem"] in questions:
            contents.append(f'<br>{esc(questions[page["stem"]])}')
        contents.append("<ul>")
        contents += [f'<li><a href="{esc(page["href"])}#{esc(sid)}">{esc(text)}</a></li>'
                     for sid, text in page["sections"]]
        contents.append("</ul></li>")
    contents.append("</ol>")
    intro = rf"""
# {BOOK_TITLE}

An open course on the two maps between angular velocities and rotation matrices. Spinning
at a constant angular velocity $\omega$ for a time $\tau$ gives the rotation
$$R(\omega, \tau) = e^{{\tau\hat\omega}} = I + \frac{{\sin\theta}}{{\theta}}\,\tau\hat\omega
  + \frac{{1-\cos\theta}}{{\theta^2}}\,(\tau\hat\omega)^2, \qquad \theta = \lVert\omega\rVert\,\lvert\tau\rvert,$$
and the logarithm goes back from $R$ to $\omega$. The course derives both from the power
series, computes them in floating point without losing digits, takes the logarithm at
exactly 180°, and shows where its two sources (a set of lecture notes and Gallier's
textbook) go wrong.

This book is the course read end to end: every notebook with its outputs, as it was last
run. To change the numbers and run the code, open the notebooks themselves (below).
"""
    order = """
## The notebooks, in order

Take them in order: each builds on the ones before it.

""" + "\n".join(contents)
    how = """
## How to run them

- **On your own machine** (Python 3.11 or newer, and `make`): in the course folder, run
  `make lab`. The first time it installs the pinned packages into `.venv`; then JupyterLab
  opens `notebooks/00_start_here.ipynb`. Run each notebook top to bottom
  (*Run → Run All Cells*), then change the numbers and run it again.
- **With nothing installed**: open the course on Binder or on your institution's
  JupyterHub; the README of the course folder says how.
- **Exercises** check themselves: write your answer in the empty cell, run the checker
  below it, and read what it says.
- **Other editions**: `make slides` writes a slide deck per notebook for lectures, and
  `make student` writes the notebooks without the worked solutions, for coursework.
"""
    nb = new_notebook(cells=[new_markdown_cell(intro.strip()), new_markdown_cell(order.strip()),
                             new_markdown_cell(how.strip())])
    nb.metadata["title"] = BOOK_TITLE
    return nb


def _render(exp, nb, name, course):
    body, _ = exp.from_notebook_node(nb, resources={"metadata": {"name": name}, "course": course})
    return relink(body, ".html")


def _fill_toc(page_html, found):
    items = "".join(f'<li><a href="#{html.escape(sid, quote=True)}">{html.escape(text)}</a></li>'
                    for sid, text in found)
    return page_html.replace(TOC_MARK, items, 1)


def build(out=BUILD / "book", notebooks=None):
    """Write the book into OUT; returns the paths of its pages, index.html first."""
    out = Path(out)
    out.mkdir(parents=True, exist_ok=True)
    vendor.install(out / VENDOR_DIR, ["mathjax", "requirejs"])
    copy_assets(out)
    paths = [Path(p) for p in (notebooks or course_notebooks())]
    # every page lists every notebook, so the whole book is rebuilt when any input changes
    stamps = Stamps(out)
    key = stamps.key(tooling_key(), *(f"{p.name}" for p in paths), *(p.read_bytes() for p in paths))
    names = ["index.html"] + [f"{p.stem}.html" for p in paths]
    if all(stamps.fresh(n, key) for n in names):
        return [out / n for n in names]
    exp = exporter()
    nbs = [read(p) for p in paths]
    pages = [{"stem": p.stem, "href": f"{p.stem}.html", "title": label(nb, p), "sections": []}
             for p, nb in zip(paths, nbs)]
    nav = [{"href": pg["href"], "title": pg["title"]} for pg in pages]
    rendered = []
    for i, (nb, page) in enumerate(zip(nbs, pages)):
        course = {"book_title": BOOK_TITLE, "pages": nav, "current": page["href"],
                  "prev": nav[i - 1] if i > 0 else None,
                  "next": nav[i + 1] if i + 1 < len(nav) else None}
        body = _render(exp, nb, page["stem"], course)
        page["sections"] = sections(body)
        rendered.append((out / page["href"], _fill_toc(body, page["sections"])))
    course = {"book_title": BOOK_TITLE, "pages": nav, "current": "index.html", "prev": None,
              "next": nav[0] if nav else None}
    index = _render(exp, landing_notebook(pages), "index", course)
    rendered.insert(0, (out / "index.html", index))
    for target, body in rendered:
        write_atomic(target, body)
        stamps.record(target.name, key)
    for old in set(out.glob("*.html")) - {t for t, _ in rendered}:  # a notebook renamed or removed
        old.unlink()
    stamps.save()
    return [target for target, _ in rendered]


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--out", type=Path, default=BUILD / "book")
    args = parser.parse_args(argv)
    for target in build(args.out):
        print(target.relative_to(Path.cwd()) if target.is_relative_to(Path.cwd()) else target)


if __name__ == "__main__":
    sys.exit(main())
