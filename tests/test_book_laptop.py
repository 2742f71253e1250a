"""The book at a laptop's size (1366x768) in Chromium, with every request outside file://
blocked: each page once, in light mode (maths typeset, no block that needs sideways
scrolling, the chapter's contents in view, no serious or critical axe-core finding), then
switched to dark mode as a reader does with the theme button, where axe-core checks the
colours again (the layout does not change with the theme, so only the colour rules run).
On the pages of notebooks 01 to 05 each figure a learner turns is dragged.
"""

import pytest
from book_support import (
    CUT_OFF,
    LAPTOP,
    TOC_IN_VIEW,
    TURNABLE,
    BookOffline,
    axe,
    axe_path,
    open_page,
    remembered,
    turn_figures,
)
from browser_support import MATHJAX_ERRORS, screenshot

pytestmark = pytest.mark.browser

# axe-core's rules that depend on colour: the ones to run again in dark mode
COLOUR_RULES = ("color-contrast", "link-in-text-block")
DARK = """() => {
  const root = document.documentElement;
  root.dataset.mode = 'dark';
  root.dataset.theme = 'dark';
  return getComputedStyle(document.body).backgroundColor;
}"""


@pytest.fixture(scope="module")
def laptop(request, pages):
    """What each check needs, from one visit of every page (or the last one's, when nothing
    it looked at changed: book_support.remembered)."""
    return remembered(request, "book-laptop", lambda: _visit(request.getfixturevalue("browser"), pages))


def _visit(browser, pages):
    script = axe_path()
    turnable = {f"{p.stem}.html" for p in TURNABLE}
    found = {}
    offline = BookOffline(browser, viewport=LAPTOP)
    page = offline.new_page()
    page.set_default_timeout(60_000)
    try:
        for path in pages:
            page.emulate_media(color_scheme="light")
            open_page(page, path)
            light = page.evaluate("getComputedStyle(document.body).backgroundColor")
            seen = found[path.name] = {
                "typeset": page.locator("mjx-container").count(),
                "errors": page.locator(MATHJAX_ERRORS).count(),
                "cut": page.evaluate(CUT_OFF),
                "axe": axe(page, script),
            }
            if path != pages[0]:
                seen["toc"] = page.evaluate(TOC_IN_VIEW)
            if path in (pages[0], pages[2]):
                screenshot(page, f"book_{path.stem}_laptop")
            if path.name in turnable:
                seen["turned"] = turn_figures(page, path)
                seen["plotly"] = page.evaluate("() => !!window.Plotly")
            page.emulate_media(color_scheme="dark")
            seen["dark"] = page.evaluate(DARK) != light
            # the theme's colours fade over a quarter of a second: measure them once settled
            page.evaluate("() => Promise.all(document.getAnimations().map(a => a.finished))")
            seen["axe"] += [f"(dark) {v}" for v in axe(page, script, COLOUR_RULES)]
            if path == pages[2]:
                screenshot(page, f"book_{path.stem}_laptop_dark")
        found["_problems"] = offline.problems()
    finally:
        offline.close()
    return found


def test_every_page_reads_offline_with_its_maths_typeset(laptop, pages):
    assert not laptop["_problems"], laptop["_problems"]
    for path in pages:
        seen = laptop[path.name]
        assert seen["typeset"] > 0, f"{path.name}: no formula typeset"
        assert seen["errors"] == 0, f"{path.name}: {seen['errors']} formulas failed to typeset"


def test_nothing_needs_sideways_scrolling_on_a_laptop(laptop, pages):
    cut = [f"{path.name}: {c}" for path in pages for c in laptop[path.name]["cut"]]
    assert not cut, "\n".join(cut)


def test_on_a_laptop_a_chapter_keeps_its_contents_in_view(laptop, pages):
    for path in pages[1:]:
        toc = laptop[path.name]["toc"]
        assert toc["shown"] and toc["links"] >= 3, f"{path.name}: no contents in view half way down"
        assert not toc.get("hidden", ["not measured"]), \
            f"{path.name}: the contents do not show the section being read: {toc.get('hidden')}"
        assert not toc.get("wrong", ["not measured"]), \
            f"{path.name}: after a jump the contents mark another section: {toc.get('wrong')}"


def test_axe_finds_nothing_serious_in_light_or_dark(laptop, pages):
    assert all(laptop[p.name]["dark"] for p in pages), "the theme did not switch to dark"
    found = [f"{path.name}: {v}" for path in pages for v in laptop[path.name]["axe"]]
    assert not found, "\n".join(found)


@pytest.mark.parametrize("path", TURNABLE, ids=lambda p: p.stem)
def test_figures_turn_with_the_mouse(laptop, path):
    """Each figure a learner turns draws on the page (with the book's one plotly.js) and
    turns when dragged; screenshots to build/screenshots/interactive/book-NAME/."""
    seen = laptop[f"{path.stem}.html"]
    assert seen["turned"], f"{path.stem}.html: no plotly figure on the page"
    for i, moved in seen["turned"].items():
        assert moved > 0.05, f"{path.stem}.html #{i}: dragging did not turn it"
    assert seen["plotly"], f"{path.stem}.html: plotly.js is not loaded"
