"""What the book's tests share: the built book (once per test process, the build itself
once per machine: tools/book.py takes a lock, so a second worker waits and finds it
built), Chromium at a laptop's and a phone's size with every request outside file://
blocked, and the measures taken in a page.
"""

import os
import re
from pathlib import Path

import pytest
from bs4 import BeautifulSoup

from browser_support import (
    ROOT,
    SCREENSHOTS,
    Offline,
    drag_turns,
    eye_moved,
    screenshot_to,
)
from tools import book, vendor
from tools.common import course_notebooks, read

LAPTOP = {"width": 1366, "height": 768}
PHONE = {"width": 390, "height": 844}
MATHJAX_READY = "window.MathJax && MathJax.startup && MathJax.startup.promise"
# the pages of notebooks 01 to 05 each have a figure the learner turns (so3lib.plot.show_3d)
TURNABLE = [p for p in course_notebooks() if p.name[:2] in {"01", "02", "03", "04", "05"}]


def remembered(request, name, visit):
    """What VISIT() saw in the book (a dict, from one visit of every page), or what it saw
    last time, when that visit passed every test of its module and nothing it looked at has
    changed since: the built book, the test files and Chromium (tests/pass_record.py; a
    fresh clone, CI and `make test FRESH=1` always visit). The tests read it either way."""
    from pass_record import PassRecord, digest
    from browser_support import chromium_executable

    site = built()[0][0].parent
    axe_path()                      # the axe-core the laptop's visit runs, fetched once
    here = ROOT / "tests"
    browser = [Path(p) for p in (chromium_executable(), "/usr/lib/chromium/chromium") if p]
    extra = " ".join(f"{p}:{p.stat().st_size}:{p.stat().st_mtime_ns}" for p in browser if p.is_file())
    key = digest([site, Path(request.module.__file__), here / "book_support.py",
                  here / "browser_support.py", ROOT / "build" / "book-test"], ROOT, extra)
    record = PassRecord(name)
    if record.fresh("key", key) and isinstance(record.passed.get("found"), dict):
        return record.passed["found"]
    found = visit()
    failed = request.session.testsfailed

    def keep():
        if request.session.testsfailed == failed:
            record.record({"key": key, "found": found})
    request.addfinalizer(keep)
    return found


def skip_or_fail(why):
    if os.environ.get("CI"):
        pytest.fail(why)
    pytest.skip(why)


_BUILT = {}


def built():
    """(pages, soups, sources): the built book's pages, index.html first, then one per
    notebook in course order; their parsed HTML by name; and the notebook copies they were
    built from. Read at once, in case someone else rebuilds the book while the tests run."""
    if "pages" not in _BUILT:
        try:
            pages = book.build(ROOT / "build" / "book")
        except SystemExit as e:  # npm missing or the registry unreachable
            skip_or_fail(str(e))
        _BUILT["soups"] = {p.name: BeautifulSoup(p.read_text(encoding="utf-8"), "html.parser")
                           for p in pages}
        _BUILT["sources"] = {p.name: read(book.SOURCE / p.name) for p in course_notebooks(book.SOURCE)}
        _BUILT["pages"] = pages
    return _BUILT["pages"], _BUILT["soups"], _BUILT["sources"]


# What a reader would have to scroll sideways: a code or output block wider than its box
# (they wrap: none may scroll), a display formula wider than its column with no scroll of
# its own (formulas are set smaller until they fit, course.js: down to 70% of the text's
# size when the whole formula then fits, else to 80% of MathJax's size), one set below 70%
# of the text, or one shrunk below 80% of MathJax's size that still scrolls, inline maths past its line with no scroll of its own, a table wider than the screen with no scroll of its
# own, or the page itself wider than the screen; a formula that opens with its start out
# of reach (left of its column). Collapsed blocks are skipped.
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
  // a formula wider than its column scrolls in its own box, which lies within the column
  const ownScroll = el => ['auto', 'scroll'].includes(getComputedStyle(el).overflowX);
  for (const el of document.querySelectorAll('article mjx-container[display="true"]')) {
    if (!shown(el)) continue;
    const avail = el.parentElement.clientWidth;
    const wide = Math.max(el.scrollWidth, el.offsetWidth) > avail + 1;
    const box = [el, el.parentElement].find(b => ownScroll(b) && b.clientWidth <= avail + 1
                                                && b.getBoundingClientRect().right <= innerWidth + 1);
    if (wide && !box)
      cut.push('formula wider than its column: ' + text(el));
    // it opens at its start: nothing of it lies left of its column, out of the scroll's reach
    const col = (el.closest('div.math') || el.parentElement).getBoundingClientRect();
    if (el.getBoundingClientRect().left < col.left - 1)
      cut.push(`formula opens with its start hidden (${Math.round(col.left - el.getBoundingClientRect().left)} px): ` + text(el));
    // an equation number that ends at its box's right edge has its closing parenthesis cut
    const label = el.querySelector('mjx-labels');
    if (label && label.getClientRects().length && el.scrollWidth <= el.clientWidth + 1 &&
        label.getBoundingClientRect().right > el.getBoundingClientRect().right - 2)
      cut.push('equation number cut at the right edge: ' + text(el));
    const size = parseFloat(getComputedStyle(el).fontSize);
    const body = parseFloat(getComputedStyle(el.closest('article')).fontSize);
    if (size < 0.695 * body) cut.push(`formula set at ${size.toFixed(1)} px: ` + text(el));
    // below 80% of MathJax's size (course.js) only when it then fits whole
    if (el.dataset.courseSize !== undefined && /%$/.test(el.style.fontSize) && wide &&
        parseFloat(el.style.fontSize) < 0.795 * (parseFloat(el.dataset.courseSize) || 100))
      cut.push('formula set below 80% of its size and still too wide: ' + text(el));
  }
  for (const el of document.querySelectorAll('article mjx-container:not([display="true"])')) {
    if (!shown(el) || el.closest('td, th, .pst-scrollable-table-container')) continue;
    const r = el.getBoundingClientRect();
    const box = (el.closest('p, li, dd, div') || el.parentElement).getBoundingClientRect();
    if ((r.right > box.right + 1 || r.right > innerWidth + 1) && !(ownScroll(el) && el.clientWidth <= box.width + 1))
      cut.push('inline formula runs past its line: ' + text(el));
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
# title lies inside it, its legend above the scene (not over it), and no toolbar or "Back to
# top" button sits on it.
PHONE_FIGURES = """() => [...document.querySelectorAll('.plotly-graph-div')].map(fig => {
  const r = fig.getBoundingClientRect();
  const cover = fig.parentElement.querySelector(':scope > .course-figure-shield');
  const turn = cover && cover.querySelector('button');
  const title = fig.querySelector('.gtitle');
  const t = title ? title.getBoundingClientRect() : null;
  const bar = fig.querySelector('.modebar-container');
  const top = document.querySelector('#pst-back-to-top');
  const legend = fig.querySelector('.legend');
  const size = fig._fullLayout && fig._fullLayout._size;
  const sceneTop = size ? r.top + size.t : r.top;
  // a lone scene takes the figure's width (not a slide's layout, kept clear of a legend
  // beside it, which leaves a third of a phone empty and cuts the scene)
  const scenes = fig._fullLayout ? Object.keys(fig._fullLayout).filter(k => /^scene\\d*$/.test(k)) : [];
  const box = scenes.length === 1 && fig._fullLayout[scenes[0]]._scene &&
              fig._fullLayout[scenes[0]]._scene.container;
  return {id: fig.id,
          sceneWide: !box || box.getBoundingClientRect().width >= 0.9 * r.width,
          legendClear: !legend || legend.getBoundingClientRect().bottom <= sceneTop + 2,
          shield: !!cover && !cover.hidden && cover.getBoundingClientRect().height > r.height / 2,
          turn: !!turn && turn.textContent.includes('Turn'),
          titleInside: !t || (t.left >= r.left - 1 && t.right <= r.right + 1),
          toolbar: !!bar && getComputedStyle(bar).display !== 'none',
          backToTop: !!top && getComputedStyle(top).display !== 'none'};
})"""

# On a phone, each 3-D scene's frame on the page (its container: the scene's share of the
# figure, under its legend and above its slider) and the figure's background colour.
SCENE_FRAMES = """() => [...document.querySelectorAll('.plotly-graph-div')].flatMap(fig => {
  const L = fig._fullLayout;
  if (!L) return [];
  return Object.keys(L).filter(k => /^scene\\d*$/.test(k) && L[k]._scene).map(k => {
    const r = L[k]._scene.container.getBoundingClientRect();
    return {id: fig.id, scene: k, x: r.left + scrollX, y: r.top + scrollY, width: r.width, height: r.height,
            background: L.paper_bgcolor};
  });
})"""


def drawn_at_edges(png, background, band=3, inset=1, tolerance=60):
    """The sides (left, right, top, bottom) of a picture of a 3-D scene's frame (PNG bytes)
    where something is drawn: pixels in a band along the side, INSET pixels in, that differ
    from the BACKGROUND colour ("#fff", "rgb(...)" or "white") by more than TOLERANCE (the
    sum over the three channels), with up to two stray pixels forgiven on each side."""
    import io
    from PIL import Image, ImageColor

    img = Image.open(io.BytesIO(png)).convert("RGB")
    bg = ImageColor.getrgb(background or "white")[:3]
    w, h = img.size
    px = img.load()
    sides = {"left": [(x, y) for x in range(inset, inset + band) for y in range(h)],
             "right": [(x, y) for x in range(w - inset - band, w - inset) for y in range(h)],
             "top": [(x, y) for y in range(inset, inset + band) for x in range(w)],
             "bottom": [(x, y) for y in range(h - inset - band, h - inset) for x in range(w)]}
    found = {}
    for side, points in sides.items():
        n = sum(1 for p in points if sum(abs(a - b) for a, b in zip(px[p], bg)) > tolerance)
        if n > 2:
            found[side] = n
    return found


# On a phone, each picture shrunk to under 4/5 of its own width: whether a tap opens it
# full size (a link to its own file).
SHRUNK_PICTURES = """() => [...document.querySelectorAll('.bd-article div.cell_output img')]
  .filter(img => img.getClientRects().length && img.naturalWidth && img.clientWidth < 0.8 * img.naturalWidth)
  .map(img => { const a = img.closest('a');
    return {src: img.getAttribute('src'), width: img.clientWidth, opens: !!a && a.href === img.src}; })"""

# On a phone, the header's buttons are touch targets of 44 px or more.
SMALL_TARGETS = """() => [...document.querySelectorAll('.bd-header-article button, .bd-header-article a.btn, .bd-header button, label.sidebar-toggle')]
  .filter(b => b.getClientRects().length && getComputedStyle(b).visibility !== 'hidden')
  .map(b => [b.getAttribute('aria-label') || b.title || b.textContent.trim() || b.className, b.getBoundingClientRect()])
  .filter(([, r]) => r.width > 0 && (r.width < 43.5 || r.height < 43.5))
  .map(([name, r]) => `${name}: ${Math.round(r.width)}x${Math.round(r.height)}`)"""

# On a phone, the links to the previous and next chapter at a page's foot: any that runs
# past the screen's right edge or whose title wraps to more than two lines.
PREV_NEXT = """() => [...document.querySelectorAll('.prev-next-area a')].flatMap(a => {
  const r = a.getBoundingClientRect(), t = a.querySelector('.prev-next-title');
  const lines = t ? Math.round(t.getBoundingClientRect().height / parseFloat(getComputedStyle(t).lineHeight)) : 1;
  const icon = a.querySelector('i');
  const out = [];
  if (r.right > innerWidth + 1 || (icon && icon.getBoundingClientRect().right > innerWidth + 1))
    out.push(`${a.className}: runs ${Math.round(r.right - innerWidth)} px past the screen`);
  if (lines > 2) out.push(`${a.className}: its title takes ${lines} lines`);
  return out;
})"""

# At a phone width, the first thing on the screen is the page's text, not the contents.
TEXT_FIRST = """() => {
  const h = document.querySelector('article h1');
  const nav = document.querySelector('#pst-primary-sidebar');
  const navShown = nav && nav.getBoundingClientRect().width > 0
                   && nav.getBoundingClientRect().left >= 0 && getComputedStyle(nav).visibility !== 'hidden';
  return {headingTop: h ? h.getBoundingClientRect().top : null, navShown};
}"""


# On a laptop, half way down a chapter, its contents ("Contents" beside the text) are in view;
# and down the chapter, the entry the theme marks as the section being read lies inside the
# contents' visible box (a list taller than the window scrolls to it): the places where not.
TOC_IN_VIEW = """async () => {
  // after a jump the course's script marks the entry and scrolls the contents to it (after
  // a short pause, and again when the theme changes its own marks): wait until both hold
  // still, not a fixed time, which a loaded machine overruns
  const sleep = ms => new Promise(done => setTimeout(done, ms));
  const state = () => {
    const panel = document.querySelector('.bd-sidebar-secondary');
    return panel ? panel.scrollTop + '|' + [...panel.querySelectorAll('a.active, a[aria-current]')]
      .map(a => a.getAttribute('href')).join(' ') : '';
  };
  const settle = async () => {
    await sleep(400);
    for (let last = state(), i = 0; i < 20; i++) {
      await sleep(150);
      const now = state();
      if (now === last) break;
      last = now;
    }
  };
  window.scrollTo(0, document.documentElement.scrollHeight / 2);
  await settle();
  const toc = document.querySelector('.bd-sidebar-secondary');
  const r = toc ? toc.getBoundingClientRect() : null;
  const links = toc ? toc.querySelectorAll('a').length : 0;
  const shown = !!r && r.width > 100 && r.top < innerHeight / 2 && r.bottom > innerHeight / 2
                && getComputedStyle(toc).visibility !== 'hidden';
  const hidden = [], wrong = [];
  // big jumps, as the wheel, End and Home make them: the marked entry is the section read
  // (the last whose heading is above the window's top third; at the page's foot, the last
  // whose heading shows), whatever the jump came from
  for (const at of [0.3, 0.6, 0.9, 0.2, 1, 0.45, 0]) {
    window.scrollTo(0, at * (document.documentElement.scrollHeight - innerHeight));
    await settle();
    if (toc) {
      const links = [...toc.querySelectorAll('a.nav-link[href^="#"]')];
      const foot = innerHeight + scrollY >= document.documentElement.scrollHeight - 2;
      let expected = null, best = -Infinity;
      for (const a of links) {
        const t = document.getElementById(decodeURIComponent(a.hash.slice(1)));
        const top = t ? t.getBoundingClientRect().top : Infinity;
        if ((top <= innerHeight / 3 || (foot && top < innerHeight)) && top >= best) { best = top; expected = a; }
      }
      const marked = links.filter(a => a.classList.contains('active'));
      const name = a => a ? a.textContent.trim().slice(0, 40) : 'none';
      if (expected ? !marked.includes(expected) : marked.length)
        wrong.push(`${Math.round(at * 100)}% down: marked "${name(marked.pop())}", reading "${name(expected)}"`);
      // one place marked: the entry read and the entries it sits under, by the link's
      // class, its aria-current or its list item's class (the theme's own marking), nothing else
      const chain = new Set();
      for (let li = expected && expected.closest('li'); li && toc.contains(li); li = li.parentElement.closest('li')) {
        const a = li.querySelector(':scope > a.nav-link');
        if (a) chain.add(a);
      }
      const shownMarked = links.filter(a => a.classList.contains('active') || a.hasAttribute('aria-current') ||
                                            (a.parentElement.matches('li') && a.parentElement.classList.contains('active')));
      for (const a of shownMarked.filter(a => !chain.has(a)))
        wrong.push(`${Math.round(at * 100)}% down: "${name(a)}" marked besides "${name(expected)}"`);
    }
    const active = toc && [...toc.querySelectorAll('a.active')].filter(a => a.getClientRects().length).pop();
    if (!active) continue;
    const box = toc.getBoundingClientRect(), a = active.getBoundingClientRect();
    if (a.top < box.top - 1 || a.bottom > Math.min(box.bottom, innerHeight) + 1)
      hidden.push(`${Math.round(at * 100)}% down: "${active.textContent.trim().slice(0, 40)}" out of view`);
  }
  window.scrollTo(0, 0);
  return {shown, links, hidden, wrong};
}"""


class BookOffline(Offline):
    """browser_support.Offline at a chosen window size and colour scheme."""

    def __init__(self, browser, viewport=LAPTOP, color_scheme="light",
                 allowed=("file:", "data:", "about:", "blob:")):
        self.allowed = tuple(allowed)
        self.blocked, self.failed, self.errors = [], [], []
        self.context = browser.new_context(viewport=viewport, color_scheme=color_scheme)
        self.context.route("**/*", self._route)
        self.context.on("page", self.watch)


def axe_path():
    return vendor.install(ROOT / "build" / "book-test", ["axe-core"]) / "axe-core" / "axe.min.js"


def axe(page, script, rules=None):
    """axe-core's serious and critical findings on PAGE (every rule, or only RULES)."""
    if not page.evaluate("() => !!window.axe"):
        page.add_script_tag(path=str(script))
    options = {"resultTypes": ["violations"], "preload": False}
    if rules:
        options["runOnly"] = {"type": "rule", "values": list(rules)}
    result = page.evaluate("options => axe.run(document, options)", options)
    return [f"{v['impact']} {v['id']}: {v['help']} ({len(v['nodes'])}x, e.g. {v['nodes'][0]['target']})"
            for v in result["violations"] if v["impact"] in ("serious", "critical")]


def open_page(page, path):
    page.goto(path.as_uri())
    page.wait_for_function(MATHJAX_READY)
    page.evaluate("MathJax.startup.promise")
    page.wait_for_function("document.documentElement.dataset.courseFitted === '1'")


def turn_figures(page, path):
    """Drag each figure a learner turns on PAGE: {figure id: how far the camera's eye
    moved}; a screenshot of each to build/screenshots/interactive/book-NAME/."""
    page.bring_to_front()
    turned = {}
    for i in page.evaluate("() => [...document.querySelectorAll('.plotly-graph-div')].map(g => g.id)"):
        before, after = drag_turns(page, f"#{i}")
        turned[i] = eye_moved(before, after)
        screenshot_to(page, SCREENSHOTS / "interactive" / f"book-{path.stem}" / f"{i}.png")
    return turned


def words(element):
    """The words (3 letters or more) of an element's text, formulas left out."""
    copy = BeautifulSoup(str(element), "html.parser")
    for math in copy.select(".math"):
        math.decompose()
    return " ".join(re.findall(r"[A-Za-z]{3,}", copy.get_text(" ")))
