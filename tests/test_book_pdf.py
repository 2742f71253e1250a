"""The course as one PDF for paper (`make pdf`, tools/book.py): printed once into
build/course.pdf (again only when the book changed), and read back with pdftotext: the
whole course, no TeX source, no stray lines, no instruction for a screen, and the
solutions at the end of each chapter with each exercise pointing to its page.
"""

import re
import shutil
import subprocess

import pytest
from book_support import skip_or_fail

from tools import book
from tools.common import course_notebooks, read


@pytest.fixture(scope="module")
def pdf(browser):
    if not shutil.which("pdftotext"):
        skip_or_fail("pdftotext (poppler-utils) is needed to read the PDF")
    return book.build_pdf(browser=browser)


@pytest.mark.browser
def test_the_pdf_holds_the_whole_course(pdf, pages):
    """`pages` after `pdf`: the print does not wait for the web build (on a fresh clone
    another worker may be making it), and the web build puts the PDF next to its pages."""
    assert pdf.is_file() and pdf.stat().st_size > 100_000
    published = book.OUT / "course.pdf"
    assert published.is_file() and published.read_bytes() == pdf.read_bytes(), \
        "the download menus link build/book/course.pdf, which is not the printed PDF"
    text = subprocess.run(["pdftotext", "-layout", str(pdf), "-"], capture_output=True,
                          text=True, check=True).stdout
    assert "Rodrigues" in text
    assert "Contents" in text
    for nb_path in course_notebooks():
        title = book.label(read(nb_path), nb_path)
        assert re.sub(r"\W+", "", title)[:20] in re.sub(r"\W+", "", text), f"{title} not in the PDF"
    assert "code cell source" not in text, "a figure's folded code printed as a stray line"
    assert "\\frac" not in text and "\\begin{" not in text, "maths printed as TeX source"
    assert text.count("\f") > 50, "fewer pages than the course has"


@pytest.mark.browser
def test_the_pdf_is_made_for_paper(pdf):
    """No instruction for a screen, no figure controls, no "Next:" links; the solutions are
    gathered at the end of each chapter, each exercise pointing to its page."""
    text = subprocess.run(["pdftotext", "-layout", str(pdf), "-"], capture_output=True,
                          text=True, check=True).stdout
    flat = re.sub(r"\s+", " ", text)
    for word in ("button", "Drag", "drag to", "slider", "Next:", "Show solution", "▶ play", "pause",
                 "Turn it"):
        found = [m.start() for m in re.finditer(r"\b" + re.escape(word), flat)]  # not time_slider
        assert not found, f"the PDF says {word!r}: ...{flat[max(0, found[0] - 80):found[0] + 80]}..."
    refs = re.findall(r"Solution: in “Solutions” at the end of this chapter, page (\d+)", flat)
    assert refs, "no exercise points to its solution"
    assert len(refs) == flat.count("Solution: in “Solutions”"), "an exercise's solution has no page"
    pages = text.split("\f")
    for n in refs:
        assert "Solution to" in pages[int(n) - 1], f"page {n} holds no solution"
    assert "Solutions:" in flat


@pytest.mark.browser
def test_no_heading_ends_a_page(pdf):
    """A heading is printed with the start of what it heads: no page ends in a heading, or
    in the first line of one."""
    from bs4 import BeautifulSoup
    soup = BeautifulSoup((book.PRINT_OUT / "index.html").read_text(encoding="utf-8"), "html.parser")
    heads = {_squash(h.get_text(" ").replace("#", "").replace("Turn it:", ""))
             for h in soup.select(".bd-article h1, .bd-article h2, .bd-article h3, .bd-article h4")}
    heads.discard("")
    assert len(heads) > 50, "the one-page book's headings were not found"
    text = subprocess.run(["pdftotext", "-layout", str(pdf), "-"], capture_output=True,
                          text=True, check=True).stdout
    ending = []
    for number, page in enumerate(text.split("\f"), 1):
        lines = [ln.strip() for ln in page.splitlines() if ln.strip()
                 and not re.fullmatch(r"\d+ / \d+", ln.strip()) and ln.strip() != book.BOOK_TITLE]
        # a heading starts with a capital or a number and has no full stop at its end
        last = lines[-1] if lines else ""
        if re.match(r"[A-Z0-9]", last) and not re.search(r"[.,;:]$", last) \
                and len(_squash(last)) >= 6 and any(h.startswith(_squash(last)) for h in heads):
            ending.append(f"page {number}: {lines[-1]}")
    assert not ending, "a page ends in a heading:\n" + "\n".join(ending)


def _squash(text):
    return re.sub(r"\W+", "", text).lower()


@pytest.mark.browser
def test_no_text_past_the_margins(pdf):
    """Every word lies inside the page's printed area (A4, 14 mm side margins): a table or
    a formula wider than the column would run past the right margin and be lost. Chromium
    drops what lies past the paper's edge, so the print also lists, as it lays the page out,
    every cell, formula or line that ends past the column (tools/book.py, PAST_MARGIN)."""
    import json
    listed = json.loads(pdf.with_name(pdf.name + ".past-margin.json").read_text())
    assert not listed, "past the right margin:\n" + "\n".join(listed[:15])
    html = subprocess.run(["pdftotext", "-bbox", str(pdf), "-"], capture_output=True,
                          text=True, check=True).stdout
    past = []
    for number, page in enumerate(re.findall(r'<page width="([\d.]+)"[^>]*>(.*?)</page>', html, re.S), 1):
        width = float(page[0])
        right = width - 14 / 25.4 * 72 + 2   # the right margin, in points, and 2 pt to spare
        for x_max, word in re.findall(r'<word xMin="[\d.]+" yMin="[\d.]+" xMax="([\d.]+)" '
                                      r'yMax="[\d.]+">([^<]*)</word>', page[1]):
            if float(x_max) > right:
                past.append(f"page {number}: {word!r} ends at {float(x_max):.0f} pt of {width:.0f}")
    assert not past, f"{len(past)} words past the right margin, e.g.\n" + "\n".join(past[:15])


@pytest.mark.browser
def test_the_pdf_ends_with_a_closing_page(pdf):
    text = subprocess.run(["pdftotext", "-layout", str(pdf), "-"], capture_output=True,
                          text=True, check=True).stdout
    last = [p for p in text.split("\f") if p.strip()][-1]
    assert "About this course" in last and "CC BY 4.0" in last and "cite" in last, last[:400]
