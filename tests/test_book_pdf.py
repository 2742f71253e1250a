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
    # the authors as a sentence names them ("By the so3-course authors"), not a capital "The"
    assert not re.search(r"\bBy The\b", last), last[:400]


def _page_texts(pdf):
    text = subprocess.run(["pdftotext", "-layout", str(pdf), "-"], capture_output=True,
                          text=True, check=True).stdout
    return text.split("\f")


@pytest.mark.browser
def test_the_contents_list_every_chapter_with_its_page(pdf):
    """The Contents pages list every chapter, each with the page it starts on."""
    pages = _page_texts(pdf)
    first = next((n for n, p in enumerate(pages)
                  if [ln.strip() for ln in p.splitlines() if ln.strip()][1:2] == ["Contents"]), None)
    assert first is not None, "no page opens with the heading Contents"
    listing = "\n".join(pages[first:first + 4])
    flat = _squash(listing)
    for nb_path in course_notebooks():
        # a chapter's entry is its title, as its first heading gives it
        first = next(c.source for c in read(nb_path).cells if c.cell_type == "markdown")
        m = re.search(r"^#\s+(.+)$", first, re.M)
        title = re.sub(r"\$[^$]*\$", "", m.group(1)) if m else book.label(read(nb_path), nb_path)
        assert _squash(title)[:20] in flat, f"the Contents do not list {title}"
        line = next((ln for ln in listing.splitlines() if _squash(title)[:20] in _squash(ln)
                     and ln.strip() != book.BOOK_TITLE), "")
        m = re.search(r"(\d+)\s*$", line)
        assert m, f"no page number for {title} in the Contents: {line!r}"
        start = int(m.group(1))
        # (the running header holds the book's title, which 00's title starts with)
        assert _squash(title)[:12] in _squash(book._without_running_lines(pages[start - 1])), \
            f"the Contents send {title} to page {start}, which does not hold it"


@pytest.mark.browser
def test_every_contents_entry_is_on_its_page(pdf):
    """Each line of the Contents (a chapter or one of its sections) gives the page its
    heading is on: not a page of the Contents itself, nor one that only shows the running
    header, and the pages never go back."""
    pages = _page_texts(pdf)
    first = next(n for n, p in enumerate(pages)
                 if [ln.strip() for ln in p.splitlines() if ln.strip()][1:2] == ["Contents"])
    entries, n = [], first
    while n < len(pages):
        lines = book._without_running_lines(pages[n]).splitlines()
        found = [(m.group(1), int(m.group(2))) for m in
                 (re.match(r"^\s*(\S.*?)\s{2,}(\d+)\s*$", ln) for ln in lines) if m]
        if n > first and not found:
            break
        entries += found
        n += 1
    last_contents = n   # 1-based number of the Contents' last page
    assert len(entries) > 50, entries[:5]
    wrong, previous = [], 0
    for title, page in entries:
        key = _squash(title)[:12]
        if page <= last_contents or page < previous or page > len(pages) or (
                len(key) > 3 and key not in _squash(book._without_running_lines(pages[page - 1]))):
            wrong.append(f"{title!r}: page {page}")
        previous = max(previous, page)
    assert not wrong, "Contents entries not on their page:\n" + "\n".join(wrong)


def _grey_runs(column, shade=247, slack=3):
    """The runs [top, bottom) of rows whose pixels in COLUMN are all the code box's grey."""
    runs, top = [], None
    for y, row in enumerate(column + [None]):
        grey = row is not None and all(abs(v - shade) <= slack for v in row)
        if grey and top is None:
            top = y
        elif not grey and top is not None:
            runs.append((top, y))
            top = None
    return runs


@pytest.mark.browser
def test_no_empty_piece_of_a_code_box(pdf, tmp_path):
    """A code box split by a page break has code on both sides: no page ends in a grey box
    with no text in it (its code moved whole to the next page). (A grey band with no words
    higher up the page is a blank line of code.)"""
    from PIL import Image
    dpi = 40
    subprocess.run(["pdftoppm", "-r", str(dpi), "-gray", str(pdf), str(tmp_path / "p")], check=True)
    html = subprocess.run(["pdftotext", "-bbox", str(pdf), "-"], capture_output=True,
                          text=True, check=True).stdout
    words = [[(float(a) * dpi / 72, float(b) * dpi / 72) for a, b in re.findall(
        r'<word xMin="[\d.]+" yMin="([\d.]+)" xMax="[\d.]+" yMax="([\d.]+)">', page)]
        for page in re.findall(r"<page [^>]*>(.*?)</page>", html, re.S)]
    images = sorted(tmp_path.glob("p-*.pgm"))
    assert len(images) == len(words)
    empty = []
    for number, (image, found) in enumerate(zip(images, words), 1):
        im = Image.open(image)
        w, h = im.size
        px = im.load()
        column = [[px[int(w * f), y] for f in (0.3, 0.5, 0.7)] for y in range(h)]
        for top, bottom in _grey_runs(column):
            # (a box that may break draws its grey with its lines: no top edge is left alone
            # at a page's foot; thinner than 6 pt is a rule, not a box)
            if bottom - top < 6 * dpi / 72:
                continue
            foot = h - 16 / 25.4 * dpi   # the foot of the printed area
            below = [y0 for y0, y1 in found if y0 >= bottom and y1 < foot]
            if not below and bottom >= foot - 8 * dpi / 72 and not any(y0 < bottom and y1 > top for y0, y1 in found):
                empty.append(f"page {number}: an empty grey box {round((bottom - top) * 72 / dpi)} pt tall")
    assert not empty, "a code box's empty piece:\n" + "\n".join(empty)


def _scene_stills(pdf, folder):
    """Each 3-D figure's still in the PDF: (page, picture) with the picture laid on white.
    Chromium prints a scene's WebGL canvas, the size of the scene's frame, as an image with
    a soft mask (its transparency); the other pictures (matplotlib's PNGs) have none."""
    from PIL import Image
    listing = subprocess.run(["pdfimages", "-list", str(pdf)], capture_output=True, text=True,
                             check=True).stdout.splitlines()[2:]
    rows = [ln.split() for ln in listing if ln.strip()]
    subprocess.run(["pdfimages", "-png", "-p", str(pdf), str(folder / "i")], check=True)
    files = {int(f.stem.split("-")[-1]): f for f in folder.glob("i-*.png")}
    stills = []
    for row, next_row in zip(rows, rows[1:]):
        # an image followed by its soft mask (the same object)
        if row[2] == "image" and next_row[2] == "smask" and next_row[10] == row[10]:
            rgb = Image.open(files[int(row[1])]).convert("RGB")
            alpha = Image.open(files[int(next_row[1])]).convert("L").resize(rgb.size)
            white = Image.new("RGB", rgb.size, "white")
            stills.append((int(row[0]), Image.composite(rgb, white, alpha)))
    return stills


@pytest.mark.browser
def test_every_3d_still_fits_its_frame(pdf, tmp_path):
    """A 3-D figure's still shows all its scene draws: nothing drawn (the axis box, its
    tick labels and titles, a trace) reaches a side of the scene's frame, where the print
    would cut it off (course.js moves each scene's camera back until it fits: FIT_SCENES in
    tools/book.py)."""
    import io

    from book_support import drawn_at_edges
    if not shutil.which("pdfimages"):
        skip_or_fail("pdfimages (poppler-utils) is needed to read the PDF's pictures")
    stills = _scene_stills(pdf, tmp_path)
    assert stills, "no 3-D figure's still found in the PDF"
    cut = []
    for page, still in stills:
        png = io.BytesIO()
        still.save(png, "PNG")
        # at the print's 2 pixels a CSS pixel: a band 3 CSS pixels wide, 2 in from the side
        sides = drawn_at_edges(png.getvalue(), "white", band=6, inset=2)
        if sides:
            cut.append(f"page {page}: the still ({still.width}x{still.height}) is drawn up to "
                       f"its frame's " + ", ".join(f"{s} ({n} px)" for s, n in sides.items()))
    assert not cut, "3-D pictures cut by their frame:\n" + "\n".join(cut)
