"""The slide build and JupyterLab in a real browser (Chromium, driven by Playwright).

A small deck made here, opened from file:// with every network request blocked, shows what
the slide types and tags do, and S opens its speaker view (every course deck is tested in
tests/test_slides.py). JupyterLab is started the way `make lab` starts it, opens notebook
01, runs every cell and must show no error output. Screenshots go to build/screenshots/.
Without Chromium these tests are skipped (see browser_support.py).
"""

import hashlib
import json
import os
import re
import secrets
import signal
import socket
import subprocess
import threading
import time
import urllib.request

import nbformat
import pytest
from browser_support import (
    ROOT,
    Offline,
    chromium_executable,
    require_chromium,
    screenshot,
)
from nbformat.v4 import new_code_cell, new_markdown_cell, new_notebook

from tools import slides
from tools.common import course_notebooks, read

pytestmark = pytest.mark.browser

NOTEBOOKS = course_notebooks()
SLIDE_TYPES = {"slide", "subslide", "fragment", "skip", "notes", "-"}
DECK_MATH_ERRORS = "mjx-merror, [data-mjx-error]"  # MathJax 3, the decks' SVG output


def _build(what, *args):
    try:
        return what(*args)
    except SystemExit as e:  # npm missing or the registry unreachable
        if os.environ.get("CI"):
            pytest.fail(str(e))
        pytest.skip(str(e))


def _open_deck(browser, path):
    """Start loading a deck in its own offline context; returns (offline, page) at once."""
    offline = Offline(browser)
    page = offline.new_page()
    page.set_default_timeout(30_000)
    page.goto(path.as_uri(), wait_until="commit")
    return offline, page


def _ready(page):
    # the deck's start-up script sets this once reveal.js is up, MathJax has typeset every
    # formula and the figures are sized (tools/templates/course_slides/index.html.j2)
    page.wait_for_function("window.Reveal && Reveal.isReady()")
    page.wait_for_function("document.documentElement.dataset.deckReady === '1'")
    page.bring_to_front()


def _indices(page):
    return page.evaluate("JSON.stringify(Reveal.getIndices())")


def _press(page, key):
    before = _indices(page)
    page.keyboard.press(key)
    page.wait_for_function(f"JSON.stringify(Reveal.getIndices()) !== {json.dumps(before)}")
    return _indices(page)


def test_every_cell_has_a_slide_type():
    """The decks are cut by the cells' slideshow metadata, so every cell needs one."""
    missing = [f"{p.name} cell {i}: {c.metadata.get('slideshow')}"
               for p in NOTEBOOKS for i, c in enumerate(read(p).cells)
               if c.metadata.get("slideshow", {}).get("slide_type") not in SLIDE_TYPES]
    assert not missing, "cells without a valid slide_type:\n" + "\n".join(missing)


def _meta(cell, slide_type):
    cell.metadata["slideshow"] = {"slide_type": slide_type}
    return cell


def test_slide_types_and_speaker_notes(browser, tmp_path):
    """skip, notes, fragment, subslide and the hide-input tag do what the lecturer expects;
    S opens the speaker view with the notes."""
    nb = new_notebook(cells=[
        _meta(new_markdown_cell("# A deck\n\nEuler: $e^{i\\pi} + 1 = 0$"), "slide"),
        _meta(new_markdown_cell("Say that it links five constants."), "notes"),
        _meta(new_code_cell("hidden = 'SETUP-CELL-NOT-ON-A-SLIDE'"), "skip"),
        _meta(new_markdown_cell("## Second idea\n\n$$a^2 + b^2 = c^2$$"), "subslide"),
        _meta(new_markdown_cell("A step that appears on a key press."), "fragment"),
        _meta(new_code_cell("draw_the_figure()", metadata={"tags": ["hide-input"]},
                            outputs=[nbformat.v4.new_output("stream", text="FIGURE-ONLY\n")]), "-"),
        _meta(new_markdown_cell("## A new section"), "slide"),
    ])
    path = tmp_path / "99_deck.ipynb"
    nbformat.write(nb, str(path))
    (deck,) = _build(slides.build, tmp_path / "out", [path])
    html = deck.read_text()
    assert "SETUP-CELL-NOT-ON-A-SLIDE" not in html
    assert "FIGURE-ONLY" in html and "draw_the_figure" not in html, "hide-input shows the output only"
    offline, page = _open_deck(browser, deck)
    _ready(page)
    assert page.evaluate("Reveal.getTotalSlides()") == 3
    assert "five constants" in page.locator("aside.notes").inner_text()
    assert page.locator(".fragment").count() == 1
    with offline.context.expect_page() as popup:
        page.keyboard.press("s")
    speaker = popup.value
    speaker.wait_for_function("document.body && document.body.innerText.includes('five constants')")
    page.bring_to_front()
    # arrow keys walk through sub-slides and fragments in reading order
    assert json.loads(_press(page, "ArrowRight"))["v"] == 1
    assert json.loads(_press(page, "ArrowRight")).get("f") == 0
    assert json.loads(_press(page, "ArrowRight"))["h"] == 1
    page.evaluate("Reveal.slide(0, 0)")
    speaker.wait_for_function("document.body.innerText.includes('five constants')")
    screenshot(speaker, "slides_speaker_view")
    assert not offline.problems(), offline.problems()
    offline.close()


# --- JupyterLab, started the way `make lab` starts it ---------------------------------

LAB_NOTEBOOK = next((p for p in NOTEBOOKS if p.name.startswith("01_")),
                    ROOT / "notebooks" / "00_start_here.ipynb")
LAB_SETTINGS = {
    # never write the notebook back: the test must leave notebooks/ exactly as it was
    "@jupyterlab/docmanager-extension/plugin.jupyterlab-settings": {"autosave": False},
    # every cell in the page, so every output can be inspected
    "@jupyterlab/notebook-extension/tracker.jupyterlab-settings": {"windowingMode": "none",
                                                                    "autoStartDefaultKernel": True},
    "@jupyterlab/apputils-extension/notification.jupyterlab-settings": {"fetchNews": "false",
                                                                         "checkForUpdates": False},
}


def _free_port():
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return s.getsockname()[1]


class LabServer:
    """`make lab` on a free port, with a known token and throwaway user settings. It boots
    in the background (a thread waits for it and starts the notebook's kernel), so that
    the decks are tested meanwhile."""

    def __init__(self, tmp):
        settings = tmp / "settings"
        for rel, value in LAB_SETTINGS.items():
            (settings / rel).parent.mkdir(parents=True, exist_ok=True)
            (settings / rel).write_text(json.dumps(value))
        port, self.token = _free_port(), secrets.token_hex(16)
        self.base, self.log = f"http://127.0.0.1:{port}", tmp / "lab.log"
        env = dict(os.environ, JUPYTERLAB_SETTINGS_DIR=str(settings),
                   JUPYTERLAB_WORKSPACES_DIR=str(tmp / "workspaces"),
                   JUPYTER_RUNTIME_DIR=str(tmp / "runtime"), JUPYTER_CONFIG_DIR=str(tmp / "config"))
        args = (f"--no-browser --port={port} --ServerApp.port_retries=0 "
                f"--IdentityProvider.token={self.token} "
                "--LabApp.check_for_updates_class=jupyterlab.NeverCheckForUpdate")
        # -o: take .venv as it is (a test never rebuilds it)
        with open(self.log, "w") as log:
            self.proc = subprocess.Popen(
                ["make", "-s", "-o", ".venv/.installed", "lab", f"LAB_ARGS={args}"],
                cwd=ROOT, env=env, stdout=subprocess.DEVNULL, stderr=log, start_new_session=True)
        self.error = None
        self.thread = threading.Thread(target=self._boot, daemon=True)
        self.thread.start()

    def _api(self, path, body=None):
        req = urllib.request.Request(f"{self.base}/api/{path}?token={self.token}",
                                     data=body and json.dumps(body).encode(),
                                     headers={"Content-Type": "application/json"})
        return urllib.request.urlopen(req, timeout=30)

    def _boot(self):
        deadline = time.monotonic() + 90
        while True:
            try:
                self._api("status")
                break
            except OSError:
                if self.proc.poll() is not None or time.monotonic() > deadline:
                    self.error = "JupyterLab did not start:\n" + self.log.read_text()
                    return
                time.sleep(0.2)
        # JupyterLab attaches to this session when it opens the notebook
        rel = LAB_NOTEBOOK.relative_to(ROOT / "notebooks").as_posix()
        try:
            self._api("sessions", {"path": rel, "name": LAB_NOTEBOOK.name, "type": "notebook",
                                   "kernel": {"name": "python3"}})
        except OSError as e:
            self.error = f"could not start a kernel: {e}\n" + self.log.read_text()

    def wait(self):
        self.thread.join(timeout=120)
        if self.error or self.thread.is_alive():
            pytest.fail(self.error or "JupyterLab took more than two minutes to start")
        return self.base, self.token

    def stop(self):
        os.killpg(self.proc.pid, signal.SIGTERM)
        try:
            self.proc.wait(timeout=15)
        except subprocess.TimeoutExpired:
            os.killpg(self.proc.pid, signal.SIGKILL)
            self.proc.wait()


@pytest.fixture(scope="module", autouse=True)
def lab_server(request, tmp_path_factory):
    """Started with the module, if its JupyterLab test is going to run here."""
    wanted = any(item.name == "test_jupyterlab_runs_the_notebook" and item.module is request.module
                 for item in request.session.items)
    if not wanted or not chromium_executable() or not (ROOT / ".venv" / "bin" / "jupyter").exists():
        yield None
        return
    server = LabServer(tmp_path_factory.mktemp("lab"))
    yield server
    server.stop()


@pytest.fixture
def lab(lab_server):
    require_chromium()
    if lab_server is None:
        pytest.skip("`make lab` needs the course's .venv (run `make lab` or `make test` once)")
    return lab_server.wait()


def _menu(page, menu, item):
    page.locator(".lm-MenuBar-itemLabel", has_text=re.compile(f"^{menu}$")).click()
    page.locator(".lm-Menu-itemLabel", has_text=re.compile(f"^{item}$")).click()


def test_jupyterlab_runs_the_notebook(browser, lab):
    base, token = lab
    # `make lab` opens a notebook in notebooks/, so that folder is the server's root
    rel = LAB_NOTEBOOK.relative_to(ROOT / "notebooks").as_posix()
    before = hashlib.sha256(LAB_NOTEBOOK.read_bytes()).hexdigest()
    n_code = sum(1 for c in read(LAB_NOTEBOOK).cells if c.cell_type == "code" and c.source.strip())
    offline = Offline(browser, allowed=(base + "/", "data:", "blob:", "about:"))
    page = offline.new_page()
    page.set_default_timeout(60_000)
    page.goto(f"{base}/lab/tree/{rel}?token={token}")
    page.locator(".jp-NotebookPanel .jp-Cell").first.wait_for()
    # the kernel is up when the status bar says so
    page.locator(".jp-StatusBar-Widget", has_text=re.compile(r"\|\s*Idle")).first.wait_for()
    # folded cells (hide-input, verify) show no prompt: unfold them, as a curious learner would
    _menu(page, "View", "Expand All Code")
    _menu(page, "View", "Expand All Outputs")
    _menu(page, "Edit", "Clear Outputs of All Cells")
    page.wait_for_function("!document.querySelector('.jp-NotebookPanel .jp-OutputArea-output')")
    _menu(page, "Run", "Run All Cells")
    # every code cell ran, in order, in this kernel: the prompts read [1] ... [n]
    page.wait_for_function(
        """n => {
          const prompts = [...document.querySelectorAll('.jp-NotebookPanel .jp-CodeCell .jp-InputPrompt')]
            .map(p => p.textContent);
          if (prompts.some(t => t.includes('*'))) return false;
          const counts = prompts.map(t => parseInt((t.match(/\\[(\\d+)\\]/) || [])[1] || '0'));
          return Math.max(0, ...counts) === n;
        }""", arg=n_code)
    errors = page.locator(".jp-OutputArea-output[data-mime-type='application/vnd.jupyter.stderr']")
    texts = [errors.nth(i).inner_text() for i in range(errors.count())]
    figure = page.locator(".jp-NotebookPanel .jp-RenderedImage img").first
    if figure.count():
        figure.scroll_into_view_if_needed()
    screenshot(page, "jupyterlab_" + LAB_NOTEBOOK.stem)
    assert not texts, "error output in JupyterLab:\n" + "\n---\n".join(texts)
    assert not offline.problems(), offline.problems()
    offline.close()
    assert hashlib.sha256(LAB_NOTEBOOK.read_bytes()).hexdigest() == before, \
        f"{rel} was modified by the test"
