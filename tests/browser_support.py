"""Driving a real Chromium from the tests (Playwright with Debian's chromium package).

Playwright's own browser download does not work everywhere, so the tests launch an
installed Chromium by path: $CHROMIUM, else /usr/bin/chromium, else chromium or
google-chrome on PATH. Without one the browser tests are skipped with the reason; under
CI (the CI environment variable is set) they fail instead, since .ci/run installs it.
"""

import json
import os
import shutil
import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parent.parent
SCREENSHOTS = ROOT / "build" / "screenshots"
if str(ROOT) not in sys.path:  # the build scripts in tools/
    sys.path.insert(0, str(ROOT))

# Root in a container needs --no-sandbox; the rest stop Chromium's own background traffic.
CHROMIUM_ARGS = ["--no-sandbox", "--disable-background-networking", "--disable-component-update",
                 "--disable-sync", "--disable-quic", "--no-first-run", "--disable-dev-shm-usage"]
VIEWPORT = {"width": 1280, "height": 800}
MATHJAX_IDLE = ("window.MathJax && MathJax.Hub && MathJax.Hub.queue"
                " && MathJax.Hub.queue.pending === 0 && MathJax.Hub.queue.running === 0")
MATHJAX_TYPESET = ".MathJax_CHTML, .MathJax, mjx-container"
MATHJAX_ERRORS = ".mjx-merror, .mjx-noError, .MathJax_Error, .noError"


def chromium_executable():
    """Path of an installed Chromium, or None."""
    candidates = [os.environ.get("CHROMIUM"), "/usr/bin/chromium"]
    candidates += [shutil.which(n) for n in ("chromium", "chromium-browser", "google-chrome")]
    for c in candidates:
        if c and os.path.isfile(c) and os.access(c, os.X_OK):
            return c
    return None


def require_chromium():
    """Skip (or under CI, fail) when there is no browser to drive."""
    try:
        import playwright.sync_api  # noqa: F401
    except ImportError:
        why = "playwright is not installed (it is pinned in environment.txt)"
    else:
        exe = chromium_executable()
        if exe:
            return exe
        why = ("no Chromium on this machine: `apt-get install chromium` (Debian/Ubuntu) or "
               "set CHROMIUM=/path/to/chrome; CI installs it")
    if os.environ.get("CI"):
        pytest.fail(f"browser tests cannot run under CI: {why}")
    pytest.skip(why)


_shared = {}


def shared_browser():
    """One Chromium per test process, shared by every test file that needs one (Playwright's
    sync API allows only one running instance per thread). Closed by close_shared_browser."""
    exe = require_chromium()
    if "browser" not in _shared:
        from playwright.sync_api import sync_playwright
        _shared["playwright"] = sync_playwright().start()
        _shared["browser"] = _shared["playwright"].chromium.launch(executable_path=exe,
                                                                   args=CHROMIUM_ARGS)
    return _shared["browser"]


def close_shared_browser():
    if "browser" in _shared:
        _shared.pop("browser").close()
        _shared.pop("playwright").stop()


class Offline:
    """A browser context in which every request outside ALLOWED is aborted and recorded,
    with the page errors, console errors and failed loads of its pages."""

    def __init__(self, browser, allowed=("file:", "data:", "about:", "blob:")):
        self.allowed = tuple(allowed)
        self.blocked, self.failed, self.errors = [], [], []
        self.context = browser.new_context(viewport=VIEWPORT)
        self.context.route("**/*", self._route)
        self.context.on("page", self.watch)

    def _route(self, route):
        url = route.request.url
        if url.startswith(self.allowed):
            route.continue_()
        else:
            self.blocked.append(url)
            route.abort()

    def watch(self, page):
        page.on("pageerror", lambda e: self.errors.append(f"page error: {e}"))
        page.on("console", lambda m: self.errors.append(f"console {m.type}: {m.text}")
                if m.type == "error" else None)
        page.on("requestfailed", lambda r: self.failed.append(f"{r.url} ({r.failure})")
                if r.url not in self.blocked else None)

    def new_page(self):
        return self.context.new_page()

    def problems(self):
        """Everything that went wrong, as text (empty when nothing did)."""
        lines = [f"blocked network request: {u}" for u in self.blocked]
        lines += [f"failed to load: {u}" for u in self.failed] + self.errors
        return "\n".join(lines)

    def close(self):
        self.context.close()


def screenshot(page, name):
    SCREENSHOTS.mkdir(parents=True, exist_ok=True)
    path = SCREENSHOTS / f"{name}.png"
    page.screenshot(path=str(path))
    return path


# --- the figures a learner turns (so3lib.plot.show_3d): plotly's 3-D scenes -------------------

PLOT_READY = """(sel) => { const g = document.querySelector(sel);
  return !!(g && g._fullLayout && g._fullLayout.scene && g._fullLayout.scene._scene
            && g.querySelector('canvas')); }"""
CAMERA = "(sel) => JSON.stringify(document.querySelector(sel)._fullLayout.scene.camera)"


def drag_turns(page, selector):
    """Drag the mouse across the 3-D scene of the plotly figure SELECTOR, 144 px right and
    36 px down with the button held; returns the camera before and after (plotly's
    _fullLayout.scene.camera). The drag moves in three steps of a third: each mouse move
    redraws the scene in software WebGL (0.3 to 1 s here), so 36 small moves cost 5 to 12
    s a figure for the same drag."""
    page.wait_for_function(PLOT_READY, arg=selector)
    page.wait_for_timeout(500)  # the scene's first frames, and any resize
    page.locator(selector).scroll_into_view_if_needed()
    before = page.evaluate(CAMERA, selector)
    box = page.evaluate("""(sel) => { const r = document.querySelector(sel).querySelector('canvas')
      .getBoundingClientRect(); return [r.left, r.top, r.width, r.height]; }""", selector)
    x, y, w, h = box
    after = before
    for fx, fy in ((0.3, 0.7), (0.5, 0.5), (0.7, 0.3)):  # away from the traces, then others
        x0, y0 = x + fx * w, y + fy * h
        page.mouse.move(x0, y0)
        page.mouse.down()
        for k in (4, 8, 12):
            page.mouse.move(x0 + 12 * k, y0 + 3 * k)
            page.wait_for_timeout(30)
        page.mouse.up()
        page.wait_for_timeout(300)
        after = page.evaluate(CAMERA, selector)
        if after != before:
            break
    return json.loads(before), json.loads(after)


def eye_moved(before, after):
    """How far the camera's eye moved between two cameras (drag_turns)."""
    b, a = before["eye"], after["eye"]
    return max(abs(a[k] - b[k]) for k in "xyz")


def screenshot_to(page, path):
    """A screenshot at PATH (its folder made)."""
    path.parent.mkdir(parents=True, exist_ok=True)
    page.screenshot(path=str(path))
    return path


DECK_FIGURES = """() => [...document.querySelectorAll('.plotly-graph-div')].map(g =>
  { const s = g.closest('.reveal .slides section:not(.stack)'); const i = Reveal.getIndices(s);
    return {id: g.id, h: i.h, v: i.v || 0}; })"""

FIGURE_FITS = """(sel) => { const g = document.querySelector(sel).getBoundingClientRect();
  const s = document.querySelector('.reveal .slides').getBoundingClientRect();
  return {w: g.width, h: g.height, inside: g.bottom <= s.bottom + 1 && g.right <= s.right + 1}; }"""


def turn_deck_figures(deck, name, shots):
    """Each figure a learner turns in an open deck (tools.slides.OfflineDeck DECK): on its
    slide a drag turns it, it fits the slide and takes at least half its width or height;
    a screenshot of each goes to SHOTS/ID.png. No request left the deck, and no error."""
    from tools import slides
    page = deck.ready()
    page.bring_to_front()
    plots = page.evaluate(DECK_FIGURES)
    assert plots, f"{name}: no plotly figure in the deck"
    for p in plots:
        slides.goto(page, p["h"], p["v"])
        sel = f'#{p["id"]}'
        before, after = drag_turns(page, sel)
        assert eye_moved(before, after) > 0.05, f"{name} {sel}: dragging did not turn it"
        fit = page.evaluate(FIGURE_FITS, sel)
        assert fit["inside"], f"{name} {sel}: the figure runs outside its slide: {fit}"
        assert fit["w"] >= 0.5 * slides.WIDTH or fit["h"] >= 0.5 * slides.HEIGHT, fit
        screenshot_to(page, shots / f"{p['id']}.png")
    assert not deck.blocked, deck.blocked
    assert not deck.errors, deck.errors
