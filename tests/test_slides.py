"""Every lecture deck, as a lecturer would project it (issue 10), in a real Chromium with the
network blocked.

Each deck is built once per session (tools/slides.py, into build/slides/) and measured once,
every slide at 1280x720 (and where it lies at 1024x768 and 1920x1080); the tests below read
that measure against the shape of a lecture deck (tools.slides: SLIDES_MIN.., README "Adding
a notebook"). In the decks of notebooks 01 to 05 each figure a learner turns is dragged and
must turn (issue 13). The decks are the course's notebooks (tools.common.course_notebooks),
so a new notebook is covered without touching this file. `python -m tools.slides --report NOTEBOOK`
prints the same measure slide by slide, with screenshots.
"""

import html as htmllib
import os
import re
import shutil
import statistics
import subprocess

import nbformat
import pytest
from nbformat.v4 import new_code_cell, new_markdown_cell, new_notebook, new_output

from browser_support import SCREENSHOTS, screenshot, turn_deck_figures
from tools import roles, slides, student
from tools.common import course_notebooks, read

pytestmark = pytest.mark.browser

NOTEBOOKS = course_notebooks()
NAMES = [p.stem for p in NOTEBOOKS]
PATHS = dict(zip(NAMES, NOTEBOOKS, strict=True))


def _build(what, *args, **kwargs):
    try:
        return what(*args, **kwargs)
    except SystemExit as e:  # npm missing or the registry unreachable
        if os.environ.get("CI"):
            pytest.fail(str(e))
        pytest.skip(str(e))


@pytest.fixture(scope="session")
def decks():
    """name -> built deck; `make slides` output, only changed decks are rebuilt."""
    return {p.name.removesuffix(".slides.html"): p for p in _build(slides.build, slides.OUT)}


@pytest.fixture(scope="session")
def opened(browser, decks):
    """name -> the deck open offline at 1280x720; every deck starts loading at once (most of
    a load is MathJax, and two cores share the decks), and stays open for the tests below."""
    pages = {name: slides.OfflineDeck(browser, path) for name, path in decks.items()}
    yield pages
    for d in pages.values():
        d.close()


@pytest.fixture(scope="session")
def measured(opened):
    """name -> the deck's measure (tools.slides.measure), taken once per session."""
    cache = {}

    def get(name):
        if name not in cache:
            shots = slides.SCREENSHOTS / name if os.environ.get("DECK_SCREENSHOTS") else None
            cache[name] = slides.measure_open(opened[name], screenshots=shots)
        return cache[name]
    return get


def _where(m):
    return f"slide {m['h']}.{m['v']} {m['headline'][:40]!r}"


def _fail_list(name, what, lines):
    return f"{name}: {what}:\n  " + "\n  ".join(lines)


@pytest.mark.parametrize("name", NAMES)
def test_slide_count(measured, name):
    n = len(measured(name)["slides"])
    low = slides.min_slides(name)
    assert low <= n <= slides.SLIDES_MAX, \
        f"{name}: {n} slides; a 50-minute lecture is {low} to {slides.SLIDES_MAX} (mark detail 'skip')"


@pytest.mark.parametrize("name", NAMES)
def test_fonts_readable_from_the_back_row(measured, name):
    bad = []
    for m in measured(name)["slides"]:
        if m["prose_px"] is not None and m["prose_px"] < slides.PROSE_PX - 0.05:
            bad.append(f"{_where(m)}: prose {m['prose_px']} px ({m['prose_at']})")
        if m["code_px"] is not None and m["code_px"] < slides.CODE_PX - 0.05:
            bad.append(f"{_where(m)}: code {m['code_px']} px ({m['code_at']})")
    assert not bad, _fail_list(name, f"text under {slides.PROSE_PX} px (prose) or "
                               f"{slides.CODE_PX} px (code) at 1280x720", bad)


@pytest.mark.parametrize("name", NAMES)
def test_nothing_outside_the_slide(measured, name):
    bad = [f"{_where(m)} at {screen}: {p}" for m in measured(name)["slides"]
           for screen, problems in m["problems_at"].items() for p in problems]
    assert not bad, _fail_list(name, "content outside the slide or cut off (split the slide, "
                               "or mark a cell 'skip')", bad)


@pytest.mark.parametrize("name", NAMES)
def test_words_of_prose(measured, name):
    ms = measured(name)["slides"]
    bad = [f"{_where(m)}: {m['words']} words" for m in ms if m["words"] > slides.WORDS_MAX]
    median = statistics.median(m["words"] for m in ms)
    if median > slides.WORDS_MEDIAN:
        bad.append(f"median {median:g} words per slide > {slides.WORDS_MEDIAN}")
    assert not bad, _fail_list(name, f"more than {slides.WORDS_MAX} words of prose", bad)


@pytest.mark.parametrize("name", NAMES)
def test_lines_of_code(measured, name):
    bad = [f"{_where(m)}: {m['code_lines']} lines" for m in measured(name)["slides"]
           if m["code_lines"] > slides.CODE_LINES_MAX]
    assert not bad, _fail_list(name, f"more than {slides.CODE_LINES_MAX} lines of code", bad)


@pytest.mark.parametrize("name", NAMES)
def test_one_headline_per_slide(measured, name):
    bad = [f"slide {m['h']}.{m['v']}" for m in measured(name)["slides"] if not m["headline"]]
    assert not bad, _fail_list(name, "slides without a headline (## or ###)", bad)


@pytest.mark.parametrize("name", NAMES)
def test_figures_fill_the_slide_and_have_alt_text(measured, name):
    bad = []
    for m in measured(name)["slides"]:
        for f in m["figures"]:
            if not f["big"]:
                bad.append(f"{_where(m)}: figure {f['w']}x{f['h']} px, under half the slide")
            if f["alt"] == "":
                bad.append(f"{_where(m)}: figure without alt text (metadata.mystnb.image.alt)")
    assert not bad, _fail_list(name, "figures", bad)


@pytest.mark.parametrize("name", NAMES)
def test_maths_typesets(measured, name):
    bad = [f"{_where(m)}: {m['math_errors']} TeX errors" for m in measured(name)["slides"]
           if m["math_errors"]]
    assert not bad, _fail_list(name, "MathJax errors", bad)


@pytest.mark.parametrize("name", NAMES)
def test_no_network_requests_and_no_errors(measured, name):
    result = measured(name)
    problems = [f"network request: {u}" for u in result["blocked"]] + result["errors"]
    assert not problems, _fail_list(name, "the deck is not self-contained", problems)


@pytest.mark.parametrize("name", NAMES)
def test_deck_presents_offline(opened, measured, name):
    """The deck starts with no network, typesets every formula, and the arrow keys step
    through it; a screenshot of its first slide goes to build/screenshots/."""
    measured(name)
    page = opened[name].ready()
    jax = page.evaluate("Array.from(MathJax.startup.document.math).length")
    drawn = page.locator("mjx-container > svg").count()
    assert jax > 0 and drawn == jax, f"{name}: {drawn} of {jax} formulas typeset"
    page.bring_to_front()
    page.evaluate("Reveal.slide(0, 0)")
    before = page.evaluate("JSON.stringify(Reveal.getIndices())")
    page.keyboard.press("ArrowRight")
    page.wait_for_function(f"JSON.stringify(Reveal.getIndices()) !== {before!r}")
    page.keyboard.press("ArrowLeft")
    page.wait_for_function(f"JSON.stringify(Reveal.getIndices()) === {before!r}")
    screenshot(page, f"slides_{name}")


# Issue 23: each deck a 50-minute lecture (tools.slides.LIMITS; `python -m tools.slides --report
# NOTEBOOK` prints every slide against them). A deck is held to each limit it met when the
# limit came in; the pairs below did not meet theirs yet, and are expected to fail until the
# decks' content work makes them pass (then take the deck off the list, so it stays met).
NOT_YET = {
    "slides": "",
    "questions": "",
    "notes": "",
    "time": "",
    "code": "",
    "checks": "",
    "coursework": "",
    "references": "",
    "figures": "",
    "labels": "",
    "builds": "",
    "summary": "",
}


@pytest.mark.parametrize("limit", list(slides.LIMITS))
@pytest.mark.parametrize("name", NAMES)
def test_a_fifty_minute_lecture(measured, name, limit):
    found = slides.lecture_faults(name, measured(name)["slides"])[limit]
    if name[:2] in NOT_YET[limit].split():
        if found:
            pytest.xfail(f"issue 23, not met yet: {slides.LIMITS[limit]} ({len(found)} short)")
        return  # met now: take the deck off NOT_YET
    assert not found, _fail_list(name, slides.LIMITS[limit], found)


def test_label_estimate_is_the_house_style():
    """The report estimates a matplotlib figure's labels from so3lib.plot's house style."""
    from so3lib.plot import SLIDE_STYLE
    smallest = min(SLIDE_STYLE[k] for k in ("xtick.labelsize", "ytick.labelsize", "legend.fontsize"))
    assert slides.LABEL_PX_DRAWN == pytest.approx(smallest * SLIDE_STYLE["savefig.dpi"] / 72)


def test_lecture_measures_on_made_up_slides():
    """The lecture limits read what they should from a slide's texts."""
    base = {"headline": "A slide", "notes_words": 5, "notes_text": "[12 min] Ask the hall.",
            "code_lines": 2, "code_text": "x = 1\ny = 2", "output_text": "", "prose_text":
            "The error stays below 8 eps, as (4.9) says.", "math_text": "(4.9)", "pictures": [],
            "list_items": 0, "display_math": 1, "fragments": 0, "tables": 0, "questions": 0}
    assert slides.lecture_slide_faults(base) == []
    assert slides.time_mark("[12 min] go") == 12 and slides.time_mark("give them 2 min") is None
    bad = dict(base, notes_text="Ask the hall.", code_lines=8,
               code_text='report("x", a, b, tol=8)', output_text="x: within 8 eps: ok\nNot yet",
               prose_text="As shown above, (4.15) fixes N15; the checker gives 3 points.")
    kinds = {k for k, _ in slides.lecture_slide_faults(bad)}
    assert kinds == {"time", "code", "checks", "coursework", "references"}, kinds
    x = slides.lecture_measure(bad)
    assert x["checks"] == 3 and sorted(x["references"]) == ['"above"', "(4.15)", "N15"]


# notebooks 01 to 05 each have a figure the learner turns (tests/test_interactive.py); 05's deck
# shows the still picture of its frame instead (the 3-D scene is too small to read in a hall)
TURNABLE = [n for n in NAMES if n[:2] in {"01", "02", "03", "04"}]


@pytest.mark.parametrize("name", TURNABLE)
def test_figures_turn_with_the_mouse(opened, measured, name):
    """Each figure a learner turns (so3lib.plot.show_3d) draws in the deck, fits its slide
    and turns when dragged; screenshots to build/screenshots/interactive/NAME/. The deck is
    measured first, so that the measure sees it as it opened."""
    measured(name)
    turn_deck_figures(opened[name], name, SCREENSHOTS / "interactive" / name)


def _kept_notes_cells(path):
    return [c for c in read(path).cells
            if c.metadata.get("slideshow", {}).get("slide_type") == "notes"
            and not slides.DECK_DROPS & set(c.metadata.get("tags", []))]


@pytest.mark.parametrize("name", NAMES)
def test_speaker_notes_reach_the_deck(measured, decks, name):
    """Every notes cell of the notebook is in the deck's speaker view, and the deck has notes."""
    cells = _kept_notes_cells(PATHS[name])
    in_deck = decks[name].read_text().count('<aside class="notes">')
    assert in_deck == len(cells), f"{name}: {len(cells)} notes cells, {in_deck} in the deck"
    with_notes = sum(1 for m in measured(name)["slides"] if m["notes_words"])
    assert with_notes > 0, f"{name}: no slide has speaker notes (slide_type 'notes')"


@pytest.mark.parametrize("name", NAMES)
def test_speaker_notes_typeset_maths_once(opened, measured, name):
    """The speaker view (S) copies a slide's notes into a window without the deck's styles:
    each formula must show once there, drawn, with no second plain-text copy. Checked by doing
    what the speaker view does (the notes' HTML into an unstyled page) for every slide with
    notes; test_alt_text_hanging_indent_and_speaker_view presses S on a deck made here."""
    ms = [m for m in measured(name)["slides"] if m["notes_words"]]
    if not ms:
        pytest.skip(f"{name} has no speaker notes (test_speaker_notes_reach_the_deck fails)")
    d = opened[name]
    blank = d.context.new_page()
    try:
        notes = d.ready().evaluate("""() => Reveal.getSlides().map(s =>
          [...s.querySelectorAll('aside.notes')].map(a => a.innerHTML).join(''))""")
        bad = []
        for m in ms:
            k = next(i for i, x in enumerate(measured(name)["slides"]) if x is m)
            seen = blank.evaluate("""html => {
              document.body.innerHTML = '<div class="value">' + html + '</div>';
              const v = document.querySelector('.value');
              const boxes = [...v.querySelectorAll('mjx-container')];
              const plain = [...v.querySelectorAll('mjx-assistive-mml')].filter(e => {
                const cs = getComputedStyle(e);
                return !(cs.position === 'absolute' && cs.clip.startsWith('rect')); });
              return {n: boxes.length, drawn: boxes.filter(b => b.querySelector(':scope > svg')
                && b.querySelector(':scope > svg').getBoundingClientRect().width > 0).length,
                plain: plain.length}; }""", notes[k])
            if seen["n"] != m["notes_math"] or seen["drawn"] != seen["n"] or seen["plain"]:
                bad.append(f"{_where(m)}: {seen['drawn']} of {m['notes_math']} formulas drawn, "
                           f"{seen['plain']} shown twice")
        assert not bad, _fail_list(name, "speaker notes' maths", bad)
    finally:
        blank.close()


@pytest.mark.parametrize("name", NAMES)
def test_no_solution_in_the_default_deck(decks, name):
    """No line of a cell tagged solution / hidden-test / answer / check is in the deck."""
    text = htmllib.unescape(re.sub(r"<[^>]+>", "", decks[name].read_text()))
    lines = {ln.strip() for ln in text.splitlines()}
    leaked = [ln for ln in slides.solution_lines(PATHS[name]) if ln in lines]
    assert not leaked, _fail_list(name, "lines of worked solutions in the default deck", leaked[:10])


@pytest.mark.parametrize("name", NAMES)
def test_no_navigation_line_in_the_deck(decks, name):
    """The notebook's "Previous: ... Next: ..." line, for moving between files, is not
    projected (tools/slides.without_navigation)."""
    text = htmllib.unescape(re.sub(r"<[^>]+>", "", decks[name].read_text()))
    assert "Previous:" not in text and "of the course. Previous" not in text, name


def _pdf_pages(pdf):
    if shutil.which("pdfinfo"):
        out = subprocess.run(["pdfinfo", str(pdf)], capture_output=True, text=True, check=True)
        return int(re.search(r"^Pages:\s+(\d+)", out.stdout, re.MULTILINE).group(1))
    return len(re.findall(rb"/Type\s*/Page[^s]", pdf.read_bytes()))


@pytest.fixture(scope="session")
def handouts(browser, decks):
    """name -> the deck's handout PDF (`make handouts`), printed once per session."""
    pdfs = _build(slides.handouts, list(decks.values()), slides.OUT_HANDOUTS, browser=browser)
    return {p.stem: p for p in pdfs}


def _page_text(pdf, k):
    if not shutil.which("pdftotext"):
        if os.environ.get("CI"):
            pytest.fail("no pdftotext (Debian package poppler-utils)")
        pytest.skip("no pdftotext: apt-get install poppler-utils")
    return subprocess.run(["pdftotext", "-f", str(k), "-l", str(k), str(pdf), "-"],
                          capture_output=True, text=True, check=True).stdout


ANSWERS = "Answers to the questions"


@pytest.mark.parametrize("name", NAMES)
def test_handout_has_one_page_per_slide(handouts, measured, name):
    """One page per slide, then the page(s) of answers to the questions to the hall."""
    pdf = handouts[name]
    pages, n = _pdf_pages(pdf), len(measured(name)["slides"])
    extra = [k for k in range(n + 1, pages + 1) if _page_text(pdf, k).lstrip().startswith(ANSWERS)]
    assert pages == n + len(extra), f"{name}: the handout has {pages} pages for {n} slides"


@pytest.mark.parametrize("name", NAMES)
def test_handout_keeps_the_answers_for_the_last_pages(handouts, measured, name):
    """A handout may be given out before the lecture: a question's page says where its
    answer is printed, and that page lists it under the question's page number; the
    answer is not on the question's page."""
    pdf = handouts[name]
    slides_ = measured(name)["slides"]
    asked = [k for k, m in enumerate(slides_, 1) if m["questions"]]
    moved = {}
    for k in asked:
        text = _page_text(pdf, k)
        found = re.findall(r"Answer: page (\d+)\.", text)
        if found:
            moved[k] = int(found[0])
    # an answer that is a picture stays on its slide, with the figures the handout keeps
    kept = [k for k in asked if k not in moved and not slides_[k - 1]["figures"]]
    assert not kept, f"{name}: answers printed under their questions on pages {kept}"
    last = _pdf_pages(pdf)
    for k, at in moved.items():
        answers = "".join(_page_text(pdf, j) for j in range(at, last + 1))
        assert answers.lstrip().startswith(ANSWERS), f"{name}: page {k} sends to page {at}, which holds no answers"
        assert re.search(rf"^Page {k}\b", answers, re.MULTILINE), f"{name}: page {k}'s answer is not listed"


@pytest.mark.parametrize("name", NAMES)
def test_handout_prints_every_figure(handouts, measured, name):
    """Each page of the handout holds as many pictures as its slide shows figures (a figure
    the learner turns prints as a still of its scene): counted in the PDF by pdfimages."""
    if not shutil.which("pdfimages"):
        if os.environ.get("CI"):
            pytest.fail("no pdfimages (Debian package poppler-utils)")
        pytest.skip("no pdfimages: apt-get install poppler-utils")
    bad = slides.handout_faults(handouts[name], measured(name)["slides"])
    assert not bad, _fail_list(name, "handout pages without their slide's figure", bad)


# --- the build itself, on a small deck made here ------------------------------------------------

PNG_1x1 = ("iVBORw0KGgoAAAANSUhEUgAAAAEAAAABCAYAAAAfFcSJAAAADUlEQVR42mP8z8BQDwAEhQGAhKmMIQAAAABJ"
           "RU5ErkJggg==")


def _meta(cell, slide_type, **extra):
    cell.metadata["slideshow"] = {"slide_type": slide_type}
    cell.metadata.update(extra)
    return cell


@pytest.fixture(scope="module")
def small_deck(tmp_path_factory):
    tmp = tmp_path_factory.mktemp("deck")
    long_line = "    result = some_function(first_argument, second_argument, third_argument, fourth)"
    nb = new_notebook(cells=[
        _meta(new_markdown_cell("## A figure\n\nEuler: $e^{i\\pi} + 1 = 0$"), "slide"),
        _meta(new_markdown_cell("Say that $\\cos\\theta$ is the *x* part."), "notes"),
        _meta(new_code_cell("draw()", metadata={"tags": ["hide-input"],
                                                "mystnb": {"image": {"alt": "A red dot on a circle"}}},
                            outputs=[new_output("display_data", data={"image/png": PNG_1x1})]), "-"),
        _meta(new_markdown_cell("## Code\n\nA long line wraps under its own indentation."), "slide"),
        _meta(new_code_cell(f"def f():\n{long_line}\n    return result"), "-"),
        _meta(new_markdown_cell("### Exercise\n\nWrite `g`."), "subslide"),
        _meta(new_code_cell("def g():\n    ANSWER_STUB_LINE = 1", metadata={"tags": ["answer"]}), "-"),
        _meta(new_code_cell("check_g_exercise_call(g)", metadata={"tags": ["check"]}), "-"),
        _meta(new_code_cell("def g():\n    WORKED_SOLUTION_LINE = 2",
                            metadata={"tags": ["solution"], "jupyter": {"source_hidden": True}}), "-"),
        _meta(new_code_cell("assert HIDDEN_TEST_LINE", metadata={"tags": ["hidden-test"]}), "-"),
    ])
    path = tmp / "99_small.ipynb"
    nbformat.write(nb, str(path))
    (deck,) = _build(slides.build, tmp / "slides", [path])
    (solved,) = _build(slides.build, tmp / "slides-solutions", [path], solutions=True)
    return deck, solved


def test_exercise_cells_left_out_and_solutions_deck(small_deck):
    deck, solved = (p.read_text() for p in small_deck)
    for line in ("ANSWER_STUB_LINE", "check_g_exercise_call", "WORKED_SOLUTION_LINE", "HIDDEN_TEST_LINE"):
        assert line not in deck, f"{line} is in the default deck"
    assert "WORKED_SOLUTION_LINE" in solved
    assert "with worked solutions" in solved and "with worked solutions" not in deck
    for line in ("ANSWER_STUB_LINE", "HIDDEN_TEST_LINE"):
        assert line not in solved, f"{line} is in the solutions deck"
    assert slides.OUT_SOLUTIONS != slides.OUT


def test_alt_text_hanging_indent_and_speaker_view(browser, small_deck):
    d = slides.OfflineDeck(browser, small_deck[0])
    try:
        page = d.ready()
        assert page.locator("img.course-figure").get_attribute("alt") == "A red dot on a circle"
        # the long line wraps, and its second screen line starts 4 characters right of the
        # line's own indentation (4 spaces): at 8 characters
        slides.goto(page, 1, 0)
        rows = page.evaluate("""() => {
          const l = [...Reveal.getCurrentSlide().querySelectorAll('pre .cl')][1];
          const r = document.createRange(); r.selectNodeContents(l);
          const boxes = [...r.getClientRects()].filter(b => b.width > 0);
          const tops = [...new Set(boxes.map(b => Math.round(b.top)))].sort((a, b) => a - b);
          const starts = tops.map(t => Math.min(...boxes.filter(b => Math.round(b.top) === t).map(b => b.left)));
          const s = document.createElement('span'); s.textContent = 'x'.repeat(10); l.appendChild(s);
          const ch = s.getBoundingClientRect().width / 10; s.remove();
          return {rows: tops.length, starts: starts.map(x => (x - l.getBoundingClientRect().left) / ch)}; }""")
        assert rows["rows"] >= 2, "the long code line did not wrap"
        assert all(abs(x - 8) < 0.6 for x in rows["starts"][1:]), \
            f"wrapped code continues at {rows['starts'][1:]} characters, not at indentation + 4 = 8"
        slides.goto(page, 0, 0)
        with d.context.expect_page() as popup:
            page.keyboard.press("s")
        speaker = popup.value
        speaker.wait_for_function("(document.querySelector('.speaker-controls-notes .value') || {}).textContent"
                                  " && document.querySelector('.speaker-controls-notes .value').textContent.includes('part')")
        assert speaker.locator(".speaker-controls-notes .value mjx-container svg").count() == 1
        plain = speaker.evaluate("""() => [...document.querySelectorAll('.speaker-controls-notes mjx-assistive-mml')]
          .filter(m => { const cs = getComputedStyle(m);
                         return !(cs.position === 'absolute' && cs.clip.startsWith('rect')); }).length""")
        assert plain == 0, "the speaker view shows the formula a second time, as text"
        assert not d.blocked and not d.errors, d.blocked + d.errors
    finally:
        d.close()


def _lecture(cell, slide_type, tag="lecture"):
    return _meta(cell, slide_type, tags=[tag], jupyter={"source_hidden": True})


def test_lecture_only_and_notebook_only_cells(tmp_path):
    """Cells for the lecture (a roadmap, a question to the hall and its answer on the next
    fragment) are in the deck and in no reading edition; a notebook-only cell is in every
    edition but the deck (tools/roles.py, README "One source, three editions")."""
    nb = new_notebook(cells=[
        _lecture(new_markdown_cell("## Roadmap\n\nLECTURE-ROADMAP"), "slide"),
        _lecture(new_markdown_cell("## Vote\n\nQUESTION-TO-THE-HALL?"), "slide", "question"),
        _lecture(new_markdown_cell("ANSWER-ON-THE-NEXT-FRAGMENT"), "fragment"),
        _meta(new_markdown_cell("## Table\n\nNOTEBOOK-ONLY-TABLE"), "slide", tags=["notebook-only"]),
        _meta(new_markdown_cell("## Read on\n\nFOR-EVERYONE"), "slide"),
    ])
    assert roles.lecture_faults(nb) == []
    path = tmp_path / "97_lecture.ipynb"
    nbformat.write(nb, str(path))
    (deck,) = _build(slides.build, tmp_path / "slides", [path])
    html = deck.read_text()
    for text in ("LECTURE-ROADMAP", "QUESTION-TO-THE-HALL", "ANSWER-ON-THE-NEXT-FRAGMENT", "FOR-EVERYONE"):
        assert text in html, f"{text} is not in the deck"
    assert "NOTEBOOK-ONLY-TABLE" not in html
    assert "celltag_question" in html
    answer = html.index("ANSWER-ON-THE-NEXT-FRAGMENT")
    assert html.rfind('class="fragment', 0, answer) > html.index("QUESTION-TO-THE-HALL"), \
        "the answer is not on a fragment after its question"
    kept = [c.source for c in student.strip(nb).cells]
    assert kept == ["## Table\n\nNOTEBOOK-ONLY-TABLE", "## Read on\n\nFOR-EVERYONE"]
    for cell in nb.cells[:3]:
        for edition in (roles.BOOK, roles.COURSEWORK, roles.STUDENT):
            assert roles.left_out(cell, edition), (cell.source, edition)
    # a question without its answer next is named
    nb.cells[2].metadata["slideshow"]["slide_type"] = "-"
    assert len(roles.lecture_faults(nb)) == 1


@pytest.mark.parametrize("name", NAMES)
def test_each_question_to_the_hall_has_its_answer_next(name):
    faults = roles.lecture_faults(read(PATHS[name]))
    assert not faults, _fail_list(name, "lecture cells (README, 'One source, three editions')", faults)


def test_hang_code_keeps_pygments_spans_per_line():
    html = ('<div class="highlight hl-ipython3"><pre><span></span><span class="k">def</span> f():\n'
            '    <span class="s2">"""two\nlines"""</span>\n</pre></div>')
    out = slides.hang_code(html)
    assert out.count('class="cl"') == 3
    assert '--ind:4ch' in out and '--ind:0ch' in out
    # a string token across a newline is closed and reopened on the next line
    assert out.count('<span class="s2">') == 2


def test_plotly_js_loaded_once_only_by_decks_with_a_turnable_figure(small_deck, tmp_path):
    """A deck with a so3lib.plot.show_3d figure loads the one vendored plotly.js, before
    require.js; a deck without one (the small deck) does not load it at all."""
    from tools import vendor
    assert "plotly.min.js" not in small_deck[0].read_text()
    nb = new_notebook(cells=[
        _meta(new_markdown_cell("## A figure to turn"), "slide"),
        _meta(new_code_cell("show_3d(fig, 'x', ALT)", outputs=[new_output("display_data", data={
            slides.PLOTLY_MIME: {"data": [], "layout": {}},
            "text/html": '<div id="so3-x" class="plotly-graph-div"></div>',
            "text/plain": "Interactive 3-D figure"})]), "-"),
    ])
    path = tmp_path / "98_plotly.ipynb"
    nbformat.write(nb, str(path))
    (deck,) = _build(slides.build, tmp_path / "slides", [path])
    page = deck.read_text()
    src = f'src="{slides.VENDOR_DIR}/{vendor.PLOTLY_JS}"'
    assert page.count(src) == 1
    assert page.index(src) < page.index("require.js")
    assert (deck.parent / slides.VENDOR_DIR / vendor.PLOTLY_JS).stat().st_size > 1_000_000
