"""The course book (tools/book.py, Jupyter Book 1): what its build writes.

The book is built once per session into build/book/ (Sphinx rebuilds only changed pages,
and does not run when no input changed). These tests read the HTML: a page per notebook,
no speaker notes or grading asserts, solutions and figure code collapsed, alt text carried
over, launch buttons and download, licence, every local link and every loaded file
present. In Chromium, offline: the search finds sections with an excerpt, and a plain
static server serves the book without a request elsewhere. The pages in Chromium at a
laptop's and a phone's size are tests/test_book_laptop.py and test_book_phone.py; the PDF
is test_book_pdf.py. tests/conftest.py gives the fixtures `pages` and `soups`
(tests/book_support.py).
"""

import functools
import http.server
import re
import threading
from urllib.parse import unquote, urlsplit

import pytest
from book_support import MATHJAX_READY, built, words
from browser_support import ROOT, Offline, screenshot

from tools import book
from tools.common import course_notebooks, read


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
        text = words(soups[f"{nb_path.stem}.html"].select_one("article"))
        for i, cell in enumerate(read(nb_path).cells):
            if book.is_speaker_note(cell) or book.is_hidden_test(cell):
                probe = _fingerprint(cell.source)
                if len(probe.split()) >= 5 and probe in text:
                    leaked.append(f"{nb_path.name} cell {i}: {probe!r}")
    assert not leaked, "\n".join(leaked)


def _built_from(nb_path):
    """The learner's copy the book was built from (the notebook itself may have moved on)."""
    return built()[2][nb_path.name]


def test_solutions_are_collapsed_and_figure_code_folded(pages, soups):
    problems = []
    for nb_path in course_notebooks():
        soup = soups[f"{nb_path.stem}.html"]
        nb = _built_from(nb_path)
        blocks = [words(d) for d in soup.select("details.course-solution")]
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


def _minutes(text):
    m = re.search(r"(?:(\d+)\s*h)?\s*(?:(\d+)\s*min)?", text.strip())
    return int(m.group(1) or 0) * 60 + int(m.group(2) or 0)


def test_the_start_page_gives_each_chapter_the_time_its_own_page_gives(pages, soups):
    """One source for a chapter's time: the start page's table (and its total) says what
    the "Time:" line at the top of the chapter's page says."""
    rows = soups["index.html"].select_one("article table").select("tbody tr")
    listed = [_minutes(row.find_all("td")[-1].get_text(" ").replace("*", "")) for row in rows]
    own = []
    for nb_path in course_notebooks():
        text = soups[f"{nb_path.stem}.html"].select_one("article").get_text(" ")
        m = re.search(r"Time:\s+about ((?:\d+ h)?\s*(?:\d+ min)?)", text)
        assert m, f"{nb_path.name}: no time at the top"
        own.append(_minutes(m.group(1)))
    assert listed == own, f"the start page lists {listed} minutes, the chapters say {own}"
    landing = re.sub(r"\s+", " ", soups["index.html"].select_one("article").get_text(" "))
    m = re.search(r"In all, about ((?:\d+ h)?\s*(?:\d+ min)?) of reading", landing)
    assert m and _minutes(m.group(1)) == sum(own), f"the total is not the chapters' sum {sum(own)}"


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
        if "rocket" in words(soup.select_one("article")).lower() and page.name == "index.html":
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
def test_search_keeps_maths_as_text_and_leaves_folded_code_out(browser, pages):
    """The index keeps maths as Unicode (a title reads "Near π: ...", not "Near :"), "pi"
    finds π, and the code of a folded figure cell is not quoted as an excerpt."""
    import json
    out = pages[0].parent
    index = json.loads((out / "_static" / "course-search.js").read_text(encoding="utf-8")
                       .removeprefix("window.COURSE_SEARCH = ").rstrip().rstrip(";"))
    titles = [e["t"] for e in index]
    assert any("π" in t for t in titles), "no section title keeps its π"
    assert not [t for t in titles if re.search(r"\\[a-zA-Z]+|\s[:,]", t)], \
        [t for t in titles if re.search(r"\\[a-zA-Z]+|\s[:,]", t)][:5]
    assert not [e["t"] for e in index if "plt.subplots" in e["x"]], "folded figure code in the index"
    # an equation's number is not text ("tag2.6"); a letter subscript keeps its "_"
    tagged = [e["x"][max(0, m.start() - 30):m.end() + 10] for e in index
              for m in re.finditer(r"\btag\s*\(?\d", e["x"] + " " + e["t"])]
    assert not tagged, tagged[:5]
    assert any("e_z" in e["x"] for e in index), "e_z is not in the index as e_z"
    offline = Offline(browser)
    page = offline.new_page()
    page.set_default_timeout(60_000)
    try:
        page.goto((out / "search.html").as_uri() + "?q=logarithm near pi")
        page.wait_for_function("document.querySelectorAll('#search-results ul.search li').length > 0")
        hits = page.evaluate(SEARCH_RESULTS)
        assert any(h["href"].startswith("04_") and "π" in h["title"] for h in hits), \
            [h["title"] for h in hits][:10]
    finally:
        offline.close()


def test_table_labels_read_as_maths(pages, soups):
    """A phone shows each table cell under its column's heading (data-label): no TeX there."""
    bad = [f"{p.name}: {td['data-label']}" for p in pages for td in soups[p.name].select("td[data-label]")
           if re.search(r"\\[(a-zA-Z]", td["data-label"])]
    assert not bad, bad[:10]


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


def test_code_keeps_its_indentation():
    """A code line keeps its leading spaces when it is put in its own span (a parser folds a
    run of spaces between two tags into one outside a <pre>), and copies as it was written."""
    from bs4 import BeautifulSoup
    html = ('<article><pre><span class="k">for</span> <span class="n">k</span>:\n'
            '        <span class="k">return</span>  <span class="n">k</span>   # two\n</pre></article>')
    soup = BeautifulSoup(html, "html.parser")
    book.wrap_code_lines(soup)
    assert soup.pre.get_text() == "for k:\n        return  k   # two\n"
    assert soup.select("span.cl")[1]["style"] == "--i:8"


def test_built_code_lines_start_with_their_indent(pages, soups):
    wrong = []
    for page in pages:
        for line in soups[page.name].select("article pre.course-lines > span.cl"):
            indent = int(re.search(r"--i:(\d+)", line.get("style", "")).group(1))
            text = line.get_text()
            if indent and not text.startswith(" " * indent):
                wrong.append(f"{page.name}: {text.strip()[:50]!r} lost its {indent} spaces")
    assert not wrong, "\n".join(wrong[:10])


def test_punctuation_stays_on_the_line_of_the_maths_it_touches(pages, soups):
    """A full stop, comma or colon right after inline maths (or a bracket right before it)
    shares an unbreakable span with it: no line starts with the "." after a formula."""
    from bs4 import NavigableString
    loose = []
    for page in pages:
        for math in soups[page.name].select("article span.math"):
            if math.find_parent(class_="course-nowrap"):
                continue
            after, before = math.next_sibling, math.previous_sibling
            if (isinstance(after, NavigableString) and re.match(r"[.,:;!?)\]]", after)) or \
                    (isinstance(before, NavigableString) and re.search(r"[(\[]$", before)):
                loose.append(f"{page.name}: {(before or '')[-10:]!s}{math.get_text()[:30]}{(after or '')[:5]!s}")
    assert not loose, "punctuation that can wrap away from its formula:\n" + "\n".join(loose[:10])


def test_web_addresses_are_links_and_the_footer_and_icon_are_right(pages, soups):
    """A bare https:// address in the text is a link; the theme's footer reads "By the
    so3-course authors" (not "By The"); every page names an icon that is there."""
    out = pages[0].parent
    for page in pages:
        soup = soups[page.name]
        article = soup.select_one("article")
        for text in article.find_all(string=re.compile(r"https?://")):
            if text.find_parent(["a", "code", "pre", "script"]) is None:
                pytest.fail(f"{page.name}: a web address that is not a link: {text.strip()[:80]}")
        foot = soup.select_one("footer")
        assert foot is None or "By The " not in foot.get_text(" "), f"{page.name}: footer says 'By The'"
        icon = soup.select_one('link[rel~="icon"]')
        assert icon is not None, f"{page.name}: no icon"
        assert (out / icon["href"]).is_file(), f"{page.name}: its icon {icon['href']} is missing"


def test_search_text_of_maths_drops_equation_numbers_and_keeps_subscripts():
    assert book.tex_to_text(r"\hat\omega^2 \tag{2.6}") == "ω̂²"
    assert book.tex_to_text(r"\theta \label{eq:x} \nonumber") == "θ"
    assert book.tex_to_text(r"e_z + e_{x}") == "e_z + e_x"
    assert book.tex_to_text(r"R_{12}") == "R₁₂"
