"""The course book (tools/book.py, Jupyter Book 1) and its PDF.

The book is built once per session into build/book/ (Sphinx rebuilds only changed pages,
and does not run when no input changed); the PDF once into build/course.pdf (reprinted
only when the book changed). The build's own checks read the HTML: a page per notebook,
no speaker notes or grading asserts, solutions and figure code collapsed, alt text carried
over, launch buttons and download, every local link and every loaded file present. Then Chromium, with every request outside
file:// blocked, opens every page once at a laptop size and once at a phone size: maths
typeset, code boxes that scroll rather than cut, no serious or critical axe-core finding
(light and dark), and on a phone the text first; on the pages of notebooks 01 to 05 each
figure a learner turns turns when dragged; the search finds "Rodrigues"; a plain static
server serves the book without a request elsewhere.
"""

import functools
import http.server
import os
import re
import shutil
import subprocess
import threading
from urllib.parse import unquote, urlsplit

import pytest
from bs4 import BeautifulSoup

from browser_support import (
    MATHJAX_ERRORS,
    ROOT,
    SCREENSHOTS,
    Offline,
    drag_turns,
    eye_moved,
    screenshot,
    screenshot_to,
)
from tools import book, vendor
from tools.common import course_notebooks, read

LAPTOP = {"width": 1366, "height": 768}
PHONE = {"width": 390, "height": 844}
MATHJAX_READY = "window.MathJax && MathJax.startup && MathJax.startup.promise"


def _skip_or_fail(why):
    if os.environ.get("CI"):
        pytest.fail(why)
    pytest.skip(why)


_BUILT = {}


@pytest.fixture(scope="session")
def pages():
    """The built book: index.html, then one page per notebook in course order. The pages
    and the notebook copies they were built from are read at once, in case someone else
    rebuilds the book while the tests run."""
    try:
        built = book.build(ROOT / "build" / "book")
    except SystemExit as e:  # npm missing or the registry unreachable
        _skip_or_fail(str(e))
    _BUILT["soups"] = {p.name: BeautifulSoup(p.read_text(encoding="utf-8"), "html.parser") for p in built}
    _BUILT["sources"] = {p.name: read(book.SOURCE / p.name) for p in course_notebooks(book.SOURCE)}
    return built


@pytest.fixture(scope="session")
def soups(pages):
    return _BUILT["soups"]


def _words(element):
    """The words (3 letters or more) of an element's text, formulas left out."""
    copy = BeautifulSoup(str(element), "html.parser")
    for math in copy.select(".math"):
        math.decompose()
    return " ".join(re.findall(r"[A-Za-z]{3,}", copy.get_text(" ")))


def _fingerprint(source, n=8):
    """The first N words of a cell (3 letters or more), as they read in the rendered page."""
    return " ".join(re.findall(r"[A-Za-z]{3,}", re.sub(r"\$[^$]*\$|<[^>]*>", " ", source))[:n])


# ---------------------------------------------------------------------------------------
# The learner's copy (no build needed)


def test_learner_copy_drops_notes_and_hidden_tests_and_brackets_solutions():
    from nbformat.v4 import new_code_cell, new_markdown_cell, new_notebook
    cells = [new_markdown_cell("# T"),
             new_markdown_cell("say this", metadata={"slideshow": {"slide_type": "notes"}}),
             new_code_cell("stub()", metadata={"tags": ["answer"]}),
             new_markdown_cell("**Solution.**", metadata={"tags": ["solution"]}),
             new_code_cell("def f(): pass", metadata={"tags": ["solution"]}),
             new_code_cell("assert f() is None", metadata={"tags": ["hidden-test"]}),
             new_markdown_cell("after")]
    out = book.learner_copy(new_notebook(cells=cells))
    sources = [c.source for c in out.cells]
    assert sources == ["# T", "stub()", book.SOLUTION_BEGIN, "**Solution.**", "def f(): pass",
                       book.SOLUTION_END, "after"]
    assert len({c.id for c in out.cells}) == len(out.cells)


def test_links_to_raw_anchors_and_jupyterlab_headings_are_rewritten():
    src = ('### <a id="N15"></a>N15. Inverses\n'
           "see [N15](A1_errata.ipynb#N15) and [9](03_x.ipynb#9.-What-%22SU(2)%22-says)")
    out = book.fix_links(src, anchors={"N15"}, slugs={"03_x.ipynb": {'9.-What-"SU(2)"-says': "what-su-2-says"}})
    assert out.startswith("(N15)=\n### N15. Inverses")
    assert "[N15](#n15)" in out and "[9](03_x.ipynb#what-su-2-says)" in out


# ---------------------------------------------------------------------------------------
# The built pages


def test_book_has_a_page_per_notebook(pages):
    assert pages[0].name == "index.html"
    assert [p.name for p in pages[1:]] == [f"{p.stem}.html" for p in course_notebooks()]
    assert all(p.is_file() for p in pages)


def test_no_speaker_notes_or_hidden_tests(pages, soups):
    leaked = []
    for nb_path in course_notebooks():
        text = _words(soups[f"{nb_path.stem}.html"].select_one("article"))
        for i, cell in enumerate(read(nb_path).cells):
            if book.is_speaker_note(cell) or book.is_hidden_test(cell):
                probe = _fingerprint(cell.source)
                if len(probe.split()) >= 5 and probe in text:
                    leaked.append(f"{nb_path.name} cell {i}: {probe!r}")
    assert not leaked, "\n".join(leaked)


def _built_from(nb_path):
    """The learner's copy the book was built from (the notebook itself may have moved on)."""
    return _BUILT["sources"][nb_path.name]


def test_solutions_are_collapsed_and_figure_code_folded(pages, soups):
    problems = []
    for nb_path in course_notebooks():
        soup = soups[f"{nb_path.stem}.html"]
        nb = _built_from(nb_path)
        blocks = [_words(d) for d in soup.select("details.course-solution")]
        for i, cell in enumerate(nb.cells):
            if book.is_solution(cell) and not book.is_hidden_test(cell):
                probe = _fingerprint(cell.source, 6)
                if len(probe.split()) < 4:
                    continue
                inside = any(probe in words for words in blocks)
                if not inside:
                    problems.append(f"{nb_path.name} cell {i}: solution not in a 'Show solution' block")
        for d in soup.select("details.course-solution"):
            if d.has_attr("open") or d.summary.get_text(strip=True) != "Show solution":
                problems.append(f"{nb_path.name}: a solution block is open or mislabelled")
        for cell in soup.select("div.cell.tag_solution"):
            if not cell.find_parent("details", class_="course-solution"):
                problems.append(f"{nb_path.name}: solution code outside its block")
        for cell in soup.select("div.cell.tag_hide-input"):
            folded = cell.select_one("details.hide.above-input")
            if folded is None or folded.has_attr("open"):
                problems.append(f"{nb_path.name}: hide-input cell with its code open")
        if soup.select("div.course-solution-begin, div.course-solution-end"):
            problems.append(f"{nb_path.name}: a solution marker was left in the page")
    assert not problems, "\n".join(problems)


def test_figures_carry_their_alt_text(pages, soups):
    missing = []
    for nb_path in course_notebooks():
        alts = {img.get("alt", "") for img in soups[f"{nb_path.stem}.html"].select("article img")}
        for cell in _built_from(nb_path).cells:
            alt = cell.metadata.get("mystnb", {}).get("image", {}).get("alt")
            draws = any(k.startswith("image/") for o in cell.get("outputs", []) for k in o.get("data", {}))
            if alt and draws and alt not in alts:
                missing.append(f"{nb_path.name} cell {cell.id}")
    assert not missing, "alt text in the notebook but not in the book: " + ", ".join(missing)


PLACEHOLDERS = re.compile(r"OWNER/|example\.(edu|com|org)|executablebooks/jupyter-book|jupyterhub\.example")


def test_landing_page_orients_and_each_chapter_begins_with_its_time_and_goals(pages, soups):
    landing = soups["index.html"].select_one("article")
    heads = [h.get_text(" ", strip=True).rstrip("#").strip() for h in landing.select("h2")]
    for wanted in ("What you will learn", "What you need first", "The path", "Where to start"):
        assert any(h.startswith(wanted) for h in heads), f"the landing page has no '{wanted}'"
    path_table = landing.select_one("table")
    rows = path_table.select("tbody tr")
    assert len(rows) == len(course_notebooks())
    for row in rows:
        assert re.search(r"\d+ (h|min)", row.get_text(" ")), f"no time in {row.get_text(' ', strip=True)}"
    for nb_path in course_notebooks():
        article = soups[f"{nb_path.stem}.html"].select_one("article")
        blocks = article.select("h1, h2, h3, p")[:12]
        text = " ".join(b.get_text(" ") for b in blocks)
        assert re.search(r"Time:\s+about \d+ (h|min)", text), f"{nb_path.name}: no time at the top"
        source = "\n".join(c.source for c in read(nb_path).cells if c.cell_type == "markdown")
        if "What you will learn" in source:
            assert "What you will learn" in text, f"{nb_path.name}: goals not at the top"


def test_without_a_repository_no_launch_or_repository_button(pages, soups):
    """The book in build/book is built without BOOK_REPOSITORY (as the tests run): no
    launch or repository button, no placeholder URL, and no promise of a rocket button."""
    if book.REPOSITORY_URL:
        pytest.skip("built with BOOK_REPOSITORY set")
    found = []
    for page in pages:
        soup = soups[page.name]
        if soup.select(".dropdown-launch-buttons, .btn-source-repository-button, a[href*='mybinder']"):
            found.append(f"{page.name}: a launch or repository button")
        if PLACEHOLDERS.search(str(soup)):
            found.append(f"{page.name}: a placeholder URL ({PLACEHOLDERS.search(str(soup)).group(0)})")
        if "rocket" in _words(soup.select_one("article")).lower() and page.name == "index.html":
            found.append("index.html promises a rocket button")
    assert not found, "\n".join(found)


def test_with_a_repository_the_launch_buttons_are_set_up():
    config = book.book_config("https://github.com/ORG/so3-course", "https://hub.uni.example")
    assert config["html"]["use_repository_button"] is True
    assert config["launch_buttons"]["binderhub_url"] == book.BINDERHUB_URL
    assert config["launch_buttons"]["jupyterhub_url"] == "https://hub.uni.example"
    assert config["repository"]["url"] == "https://github.com/ORG/so3-course"
    bare = book.book_config("", "https://hub.uni.example")
    assert bare["html"]["use_repository_button"] is False
    assert not bare["launch_buttons"]["binderhub_url"] and not bare["launch_buttons"]["jupyterhub_url"]
    assert "rocket" not in book.landing_page([], [], "")
    nb = read(course_notebooks()[1])
    first = book.download_copy(nb, "01_x.ipynb", "https://github.com/ORG/so3-course").cells[0].source
    assert "mybinder.org/v2/gh/ORG/so3-course/main?urlpath=lab/tree/notebooks/01_x.ipynb" in first


def test_download_menu_gives_a_notebook_that_runs_and_the_course_pdf(pages, soups):
    for nb_path in course_notebooks():
        soup = soups[f"{nb_path.stem}.html"]
        menu = soup.select_one(".dropdown-download-buttons")
        assert menu is not None, f"{nb_path.name}: no download menu"
        hrefs = [a.get("href", "") for a in menu.select("a")]
        download = f"_sources/{nb_path.name}"
        assert download in hrefs, f"{nb_path.name}: no .ipynb download"
        assert "course.pdf" in hrefs, f"{nb_path.name}: the course PDF is not in the download menu"
        assert not menu.select("[onclick*='print']"), f"{nb_path.name}: '.pdf' prints the web page"
        given = read(pages[0].parent / download)
        first = given.cells[0]
        assert first.cell_type == "markdown" and "make lab" in first.source and "so3lib" in first.source
        for cell in given.cells:
            assert not (book.is_hidden_test(cell) or book.is_solution(cell)
                        or book.is_verification(cell) or book.is_speaker_note(cell)), \
                f"{download}: cell {cell.get('id')} should not be in the download"
        # every cell the learner works with is there, in the notebook's order
        source = read(nb_path)
        wanted = [c.id for c in source.cells if not (book.is_left_out(c) or book.is_solution(c))]
        assert [c.id for c in given.cells[1:]] == wanted, f"{download} is not {nb_path.name}"


def test_licence_version_and_citation(pages, soups):
    import tomllib
    import yaml
    licence = (ROOT / "LICENSE").read_text()
    assert "BSD 3-Clause License" in licence and "Attribution 4.0 International" in licence
    cff = yaml.safe_load((ROOT / "CITATION.cff").read_text())
    project = tomllib.loads((ROOT / "pyproject.toml").read_text())["project"]
    assert cff["version"] == project["version"], "CITATION.cff and pyproject.toml disagree"
    assert project["license"] == "BSD-3-Clause"
    readme = (ROOT / "README.md").read_text()
    assert "BSD 3-Clause" in readme and "CC BY 4.0" in readme
    landing = soups["index.html"].select_one("article").get_text(" ")
    assert f"Version {cff['version']}" in landing and str(cff["date-released"])[:4] in landing
    for page in pages:
        foot = soups[page.name].select_one("footer.bd-footer-content")
        text = foot.get_text(" ") if foot else ""
        assert "CC BY 4.0" in text and "BSD-3-Clause" in text, f"{page.name}: no licence in the footer"
    out = pages[0].parent
    assert (out / "LICENSE.txt").is_file() and (out / "CITATION.cff").is_file()


def test_every_link_in_the_book_resolves(pages, soups):
    out = pages[0].parent
    ids = {name: {t["id"] for t in soup.select("[id]")} for name, soup in soups.items()}
    broken = []
    for page in pages:
        soup = soups[page.name]
        for a in soup.select("a[href]"):
            url = urlsplit(a["href"])
            if url.scheme in ("http", "https", "mailto"):
                continue  # the web: launch buttons, the repository, references
            target = (page.parent / unquote(url.path)).resolve() if url.path else page
            if url.path == "course.pdf":
                continue  # printed by `make pdf` (test_the_pdf_holds_the_whole_course checks it)
            if url.scheme or not target.is_file():
                broken.append(f"{page.name}: {a['href']} (no such file)")
            elif url.fragment and target.suffix == ".html" and target.parent == out.resolve():
                if not {url.fragment, unquote(url.fragment)} & ids.get(target.name, set()):
                    broken.append(f"{page.name}: {a['href']} (no such anchor)")
        for tag in soup.select("script[src], link[href], img[src]"):
            src = tag.get("src") or tag.get("href")
            url = urlsplit(src)
            if url.scheme in ("http", "https") or src.startswith("//"):
                broken.append(f"{page.name}: loads {src} from the network")
            elif not url.scheme and not (page.parent / unquote(url.path)).is_file():
                broken.append(f"{page.name}: loads {src}, which is not there")
    assert not broken, "\n".join(broken)


# ---------------------------------------------------------------------------------------
# In Chromium, offline


# What a reader would have to scroll sideways: a code or output block wider than its box
# (they wrap: none may scroll), a display formula wider than its column (formulas are set
# smaller until they fit, course.js), a table wider than the screen with no scroll of its
# own, or the page itself wider than the screen. Collapsed blocks are skipped.
CUT_OFF = """() => {
  const cut = [];
  const shown = el => !el.closest('details:not([open])') && el.getClientRects().length > 0;
  const text = el => (el.textContent || '').trim().replace(/\\s+/g, ' ').slice(0, 60);
  for (const el of document.querySelectorAll('article pre')) {
    if (!shown(el)) continue;
    const r = el.getBoundingClientRect();
    if (el.scrollWidth > el.clientWidth + 1 || r.right > innerWidth + 1)
      cut.push('code or output scrolls sideways: ' + text(el));
  }
  for (const el of document.querySelectorAll('article mjx-container[display="true"]')) {
    if (!shown(el)) continue;
    const avail = el.parentElement.clientWidth;
    if (Math.max(el.scrollWidth, el.offsetWidth) > avail + 1)
      cut.push('formula wider than its column: ' + text(el));
  }
  for (const t of document.querySelectorAll('article table')) {
    if (!shown(t)) continue;
    let box = t.parentElement, scrolls = false;
    for (; box && box !== document.body; box = box.parentElement)
      if (['auto', 'scroll'].includes(getComputedStyle(box).overflowX) && box.clientWidth <= innerWidth) {
        scrolls = true; break;
      }
    if (t.getBoundingClientRect().width > innerWidth + 1 && !scrolls)
      cut.push('table wider than the screen: ' + text(t));
  }
  if (document.documentElement.scrollWidth > innerWidth + 1) cut.push('the page scrolls sideways');
  return cut;
}"""

# On a phone, each 3-D figure: a swipe over it scrolls the page (the shield, course.js), its
# title lies inside it, and no toolbar or "Back to top" button sits on it.
PHONE_FIGURES = """() => [...document.querySelectorAll('.plotly-graph-div')].map(fig => {
  const r = fig.getBoundingClientRect();
  const cover = fig.parentElement.querySelector(':scope > .course-figure-shield');
  const turn = cover && cover.querySelector('button');
  const title = fig.querySelector('.gtitle');
  const t = title ? title.getBoundingClientRect() : null;
  const bar = fig.querySelector('.modebar-container');
  const top = document.querySelector('#pst-back-to-top');
  return {id: fig.id,
          shield: !!cover && !cover.hidden && cover.getBoundingClientRect().height > r.height / 2,
          turn: !!turn && turn.textContent.includes('Turn'),
          titleInside: !t || (t.left >= r.left - 1 && t.right <= r.right + 1),
          toolbar: !!bar && getComputedStyle(bar).display !== 'none',
          backToTop: !!top && getComputedStyle(top).display !== 'none'};
})"""

# At a phone width, the first thing on the screen is the page's text, not the contents.
TEXT_FIRST = """() => {
  const h = document.querySelector('article h1');
  const nav = document.querySelector('#pst-primary-sidebar');
  const navShown = nav && nav.getBoundingClientRect().width > 0
                   && nav.getBoundingClientRect().left >= 0 && getComputedStyle(nav).visibility !== 'hidden';
  return {headingTop: h ? h.getBoundingClientRect().top : null, navShown};
}"""


# On a laptop, half way down a chapter, its contents ("Contents" beside the text) are in view.
TOC_IN_VIEW = """() => {
  window.scrollTo(0, document.documentElement.scrollHeight / 2);
  const toc = document.querySelector('.bd-sidebar-secondary');
  const r = toc ? toc.getBoundingClientRect() : null;
  const links = toc ? toc.querySelectorAll('a').length : 0;
  const shown = !!r && r.width > 100 && r.top < innerHeight / 2 && r.bottom > innerHeight / 2
                && getComputedStyle(toc).visibility !== 'hidden';
  window.scrollTo(0, 0);
  return {shown, links};
}"""


class _Offline(Offline):
    """browser_support.Offline at a chosen window size and colour scheme."""

    def __init__(self, browser, viewport=LAPTOP, color_scheme="light",
                 allowed=("file:", "data:", "about:", "blob:")):
        self.allowed = tuple(allowed)
        self.blocked, self.failed, self.errors = [], [], []
        self.context = browser.new_context(viewport=viewport, color_scheme=color_scheme)
        self.context.route("**/*", self._route)
        self.context.on("page", self.watch)


def _axe_path():
    return vendor.install(ROOT / "build" / "book-test", ["axe-core"]) / "axe-core" / "axe.min.js"


def _axe(page, axe):
    page.add_script_tag(path=str(axe))
    result = page.evaluate("axe.run(document, {resultTypes: ['violations'], preload: false})")
    return [f"{v['impact']} {v['id']}: {v['help']} ({len(v['nodes'])}x, e.g. {v['nodes'][0]['target']})"
            for v in result["violations"] if v["impact"] in ("serious", "critical")]


def _open(page, path):
    page.goto(path.as_uri())
    page.wait_for_function(MATHJAX_READY)
    page.evaluate("MathJax.startup.promise")
    page.wait_for_function("document.documentElement.dataset.courseFitted === '1'")


# the pages of notebooks 01 to 05 each have a figure the learner turns (so3lib.plot.show_3d)
TURNABLE = [p for p in course_notebooks() if p.name[:2] in {"01", "02", "03", "04", "05"}]


def _turn_figures(page, path):
    """Drag each figure a learner turns on PAGE: {figure id: how far the camera's eye
    moved}; a screenshot of each to build/screenshots/interactive/book-NAME/."""
    page.bring_to_front()
    turned = {}
    for i in page.evaluate("() => [...document.querySelectorAll('.plotly-graph-div')].map(g => g.id)"):
        before, after = drag_turns(page, f"#{i}")
        turned[i] = eye_moved(before, after)
        screenshot_to(page, SCREENSHOTS / "interactive" / f"book-{path.stem}" / f"{i}.png")
    return turned


@pytest.fixture(scope="session")
def visits(browser, pages):
    """Every page opened once at a laptop size and once at a phone size (light, then dark
    for axe), with every request outside file:// blocked: what each check needs. On the
    laptop in light, once a page of notebooks 01 to 05 is measured, each figure a learner
    turns on it is dragged (test_figures_turn_with_the_mouse)."""
    axe = _axe_path()
    turnable = {f"{p.stem}.html" for p in TURNABLE}
    found = {}
    for size_name, size in (("laptop", LAPTOP), ("phone", PHONE)):
        for scheme in ("light", "dark"):
            if size_name == "phone" and scheme == "dark":
                continue
            offline = _Offline(browser, viewport=size, color_scheme=scheme)
            page = offline.new_page()
            page.set_default_timeout(60_000)
            for path in pages:
                _open(page, path)
                seen = found.setdefault(path.name, {})
                key = f"{size_name}-{scheme}"
                seen[key] = {
                    "typeset": page.locator("mjx-container").count(),
                    "errors": page.locator(MATHJAX_ERRORS).count(),
                    "cut": page.evaluate(CUT_OFF),
                    "layout": page.evaluate(TEXT_FIRST),
                    "axe": _axe(page, axe) if size_name == "laptop" else [],
                }
                if key == "laptop-light" and path != pages[0]:
                    seen[key]["toc"] = page.evaluate(TOC_IN_VIEW)
                if size_name == "phone":
                    page.wait_for_function("""() => [...document.querySelectorAll('.plotly-graph-div')]
                        .every(f => f._fullLayout)""")
                    page.wait_for_timeout(300)  # the titles are refitted once drawn
                    seen[key]["figures"] = page.evaluate(PHONE_FIGURES)
                if path in (pages[0], pages[2]) and scheme == "light":
                    screenshot(page, f"book_{path.stem}_{size_name}")
                if key == "laptop-light" and path.name in turnable:
                    seen[key]["turned"] = _turn_figures(page, path)
                    seen[key]["plotly"] = page.evaluate("() => !!window.Plotly")
            found.setdefault("_problems", []).append(offline.problems())
            offline.close()
    return found


@pytest.mark.browser
def test_every_page_reads_offline_with_its_maths_typeset(visits, pages):
    assert not any(visits["_problems"]), "\n".join(visits["_problems"])
    for path in pages:
        seen = visits[path.name]["laptop-light"]
        assert seen["typeset"] > 0, f"{path.name}: no formula typeset"
        assert seen["errors"] == 0, f"{path.name}: {seen['errors']} formulas failed to typeset"


@pytest.mark.browser
def test_nothing_needs_sideways_scrolling_on_a_laptop_or_a_phone(visits, pages):
    cut = [f"{path.name} at {key}: {c}" for path in pages
           for key, seen in visits[path.name].items() for c in seen["cut"]]
    assert not cut, "\n".join(cut)


@pytest.mark.browser
def test_on_a_phone_3d_figures_let_the_page_scroll_and_show_their_title(visits, pages):
    problems = []
    for path in pages:
        for fig in visits[path.name]["phone-light"].get("figures", []):
            if not (fig["shield"] and fig["turn"]):
                problems.append(f"{path.name} #{fig['id']}: a swipe over it does not scroll the page")
            if not fig["titleInside"]:
                problems.append(f"{path.name} #{fig['id']}: its title is cut off")
            if fig["toolbar"] or fig["backToTop"]:
                problems.append(f"{path.name} #{fig['id']}: a toolbar or 'Back to top' covers it")
    assert not problems, "\n".join(problems)


@pytest.mark.browser
def test_on_a_laptop_a_chapter_keeps_its_contents_in_view(visits, pages):
    for path in pages[1:]:
        toc = visits[path.name]["laptop-light"]["toc"]
        assert toc["shown"] and toc["links"] >= 3, f"{path.name}: no contents in view half way down"


@pytest.mark.browser
def test_axe_finds_nothing_serious(visits, pages):
    found = [f"{path.name} ({key}): {v}" for path in pages
             for key, seen in visits[path.name].items() for v in seen["axe"]]
    assert not found, "\n".join(found)


@pytest.mark.browser
def test_on_a_phone_the_text_comes_first(visits, pages):
    for path in pages:
        layout = visits[path.name]["phone-light"]["layout"]
        assert not layout["navShown"], f"{path.name}: the contents cover the text on a phone"
        assert layout["headingTop"] is not None and layout["headingTop"] < PHONE["height"] / 3, \
            f"{path.name}: the title starts {layout['headingTop']} px down"


@pytest.mark.browser
@pytest.mark.parametrize("path", TURNABLE, ids=lambda p: p.stem)
def test_figures_turn_with_the_mouse(visits, path):
    """Each figure a learner turns draws on the page (with the book's one plotly.js) and
    turns when dragged; screenshots to build/screenshots/interactive/book-NAME/."""
    seen = visits[f"{path.stem}.html"]["laptop-light"]
    assert seen["turned"], f"{path.stem}.html: no plotly figure on the page"
    for i, moved in seen["turned"].items():
        assert moved > 0.05, f"{path.stem}.html #{i}: dragging did not turn it"
    assert seen["plotly"], f"{path.stem}.html: plotly.js is not loaded"
    assert not any(visits["_problems"]), "\n".join(visits["_problems"])


SEARCH_RESULTS = """() => [...document.querySelectorAll('#search-results ul.search li')].map(li => {
  const a = li.querySelector('a');
  return {href: a ? a.getAttribute('href') : '', title: a ? a.textContent : '', excerpt: (li.querySelector('p.context') || {}).textContent || '',
          marked: li.querySelectorAll('mark').length};
})"""


@pytest.mark.browser
def test_search_finds_sections_with_an_excerpt_offline(browser, pages, soups):
    """Search lists sections, each with an excerpt that marks the word and a link to the
    section; a page that does not contain the word is not listed."""
    offline = Offline(browser)
    page = offline.new_page()
    page.set_default_timeout(60_000)
    out = pages[0].parent
    texts = {p.name: soups[p.name].select_one("article").get_text(" ").lower() for p in pages}
    try:
        for word in ("Rodrigues", "half-turn"):
            page.goto((out / "search.html").as_uri() + "?q=" + word)
            page.wait_for_function("document.querySelectorAll('#search-results ul.search li').length > 0")
            hits = page.evaluate(SEARCH_RESULTS)
            if word == "Rodrigues":
                screenshot(page, "book_search")
            assert len(hits) >= 3, f"only {len(hits)} hits for {word}"
            for hit in hits:
                name, _, anchor = hit["href"].partition("#")
                assert anchor and anchor in {t["id"] for t in soups[name].select("[id]")}, \
                    f"{word}: {hit['href']} is not a section"
                assert hit["excerpt"].strip(), f"{word}: {hit['href']} has no excerpt"
                assert (word.lower() in hit["excerpt"].lower() and hit["marked"]) or \
                    word.lower() in hit["title"].lower(), \
                    f"{word}: neither the excerpt nor the title of {hit['href']} shows the word"
                assert word.lower() in texts[name], f"{word}: {name} is listed but never says it"
            if word == "half-turn":
                assert hits[0]["href"].startswith("04_"), f"half-turn: first hit {hits[0]['href']}"
        assert not offline.problems(), offline.problems()
    finally:
        offline.close()


@pytest.mark.browser
def test_a_plain_static_server_serves_it_with_no_other_request(browser, pages):
    class Quiet(http.server.SimpleHTTPRequestHandler):
        def log_message(self, *args):
            pass

    handler = functools.partial(Quiet, directory=str(pages[0].parent))
    server = http.server.ThreadingHTTPServer(("127.0.0.1", 0), handler)
    threading.Thread(target=server.serve_forever, daemon=True).start()
    origin = f"http://127.0.0.1:{server.server_address[1]}/"
    offline = Offline(browser, allowed=(origin, "data:", "about:", "blob:"))
    try:
        page = offline.new_page()
        page.set_default_timeout(60_000)
        for path in (pages[0], pages[2]):
            page.goto(origin + path.name)
            page.wait_for_function(MATHJAX_READY)
            page.evaluate("MathJax.startup.promise")
            assert page.locator("mjx-container").count() > 0
        page.goto(origin + "search.html?q=Rodrigues")
        page.wait_for_function("document.querySelectorAll('#search-results ul.search li').length > 0")
        assert not offline.problems(), offline.problems()
    finally:
        offline.close()
        server.shutdown()


# ---------------------------------------------------------------------------------------
# The PDF


@pytest.fixture(scope="session")
def pdf(browser, pages):
    if not shutil.which("pdftotext"):
        _skip_or_fail("pdftotext (poppler-utils) is needed to read the PDF")
    return book.build_pdf(browser=browser)


@pytest.mark.browser
def test_the_pdf_holds_the_whole_course(pdf):
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
    for word in ("button", "Drag", "drag to", "slider", "Next:", "Show solution", "▶ play", "pause"):
        found = [m.start() for m in re.finditer(r"\b" + re.escape(word), flat)]  # not time_slider
        assert not found, f"the PDF says {word!r}: ...{flat[max(0, found[0] - 80):found[0] + 80]}..."
    refs = re.findall(r"Solution: in “Solutions” at the end of this chapter, page (\d+)", flat)
    assert refs, "no exercise points to its solution"
    assert len(refs) == flat.count("Solution: in “Solutions”"), "an exercise's solution has no page"
    pages = text.split("\f")
    for n in refs:
        assert "Solution to" in pages[int(n) - 1], f"page {n} holds no solution"
    assert "Solutions:" in flat
