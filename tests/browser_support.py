"""Driving a real Chromium from the tests (Playwright with Debian's chromium package).

Playwright's own browser download does not work everywhere, so the tests launch an
installed Chromium by path: $CHROMIUM, else /usr/bin/chromium, else chromium or
google-chrome on PATH. Without one the browser tests are skipped with the reason; under
CI (the CI environment variable is set) they fail instead, since .ci/run installs it.
"""

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
