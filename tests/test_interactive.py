"""Figures the learner turns with the mouse (issue 13, "Interactive 3-D"): plotly figures
shown with so3lib.plot.show_3d.

- The output bundle: the plotly JSON for JupyterLab's renderer (a "safe" renderer, so it
  draws in a notebook that is not trusted, with no kernel), an HTML part with a fixed div
  id that draws with the page's own plotly.js, and the alt text; no plotly.js and no CDN
  inside a notebook, and every notebook file under 1.5 MB.
- In Chromium with every request outside file:// blocked: the fixture notebook
  (tests/fixtures/10_fixture_interactive.ipynb) as a deck: the figure
  draws (WebGL), fits its slide, and a mouse drag turns it (plotly's
  _fullLayout.scene.camera changes). The course's notebooks 01 to 05 get the same checks
  in their decks (tests/test_slides.py) and book pages (tests/test_book_laptop.py), where those
  are open already.
- Each interactive figure's cell carries the same alt text in metadata.mystnb.image.alt as
  its figure's aria-label, and starts or sits on a slide of the deck.
"""

import html as htmllib
import re
import shutil
from unittest import mock

import nbformat
import pytest

from browser_support import (
    ROOT,
    SCREENSHOTS,
    Offline,
    drag_turns,
    eye_moved,
    screenshot_to,
    turn_deck_figures,
)
from tools import slides, vendor
from tools.common import course_notebooks, read

FIXTURE = ROOT / "tests" / "fixtures" / "10_fixture_interactive.ipynb"
PLOTLY_MIME = "application/vnd.plotly.v1+json"
MAX_NOTEBOOK_BYTES = 1_500_000
# notebooks 01 to 05 each have at least one figure the learner turns
TURNABLE = [p for p in course_notebooks() if p.name[:2] in {"01", "02", "03", "04", "05"}]


def _plotly_cells(nb):
    """(index, cell, output) of every show_3d output of a notebook."""
    return [(i, c, o) for i, c in enumerate(nb.cells) if c.cell_type == "code"
            for o in c.get("outputs", []) if PLOTLY_MIME in o.get("data", {})]


def _aria_label(html):
    m = re.search(r'class="plotly-graph-div course-plotly" role="figure" aria-label="([^"]*)"', html)
    return m and m.group(1)


# --- the output bundle ------------------------------------------------------------------------

def _bundle(fig, name, alt):
    from so3lib import plot
    out = {}
    with mock.patch("IPython.display.display", lambda b, raw: out.update(b)):
        plot.show_3d(fig, name, alt)
    return out


def _small_figure():
    import numpy as np

    from so3lib import plot
    fig = plot.new_3d_figure("The identity frame")
    for t in plot.frame_traces(np.eye(3), name="I"):
        fig.add_trace(t)
    return fig


ALT = "The identity's body frame: a red, a green and a blue arrow along x, y and z."


def test_bundle_has_json_html_and_words_and_no_plotly_js():
    out = _bundle(_small_figure(), "identity", ALT)
    assert set(out) == {PLOTLY_MIME, "text/html", "text/plain"}
    assert {"data", "layout", "config"} <= set(out[PLOTLY_MIME])
    html = out["text/html"]
    assert 'id="so3-identity"' in html and _aria_label(html) == ALT.replace("'", "&#x27;")
    assert ALT in out["text/plain"]
    assert len(html) < 50_000, "plotly.js itself went into the notebook"
    assert "https://" not in html and "cdn" not in html.lower()
    # byte-stable: the same figure twice gives the same output (strict nbval)
    assert _bundle(_small_figure(), "identity", ALT) == out


@pytest.mark.parametrize("name, alt, what", [
    ("Bad Name", ALT, "name"), ("x" * 80, ALT, "name"), ("ok", "", "alt"),
    ("ok", "a frame", "alt"), ("ok", None, "alt"),
])
def test_bad_input_says_what_was_expected(name, alt, what):
    from so3lib import plot
    with pytest.raises(ValueError, match=what):
        plot.show_3d(_small_figure(), name, alt)
    with pytest.raises(ValueError, match="plotly figure"):
        plot.show_3d({"data": []}, "ok", ALT)


def test_frame_traces_and_slider_check_their_input():
    from so3lib import plot
    with pytest.raises(ValueError, match="3x3"):
        plot.frame_traces([1.0, 2.0, 3.0])
    with pytest.raises(ValueError, match="one label per frame"):
        plot.time_slider(_small_figure(), [[]], ["0", "1"], "t = ")


def test_jupyterlab_renderer_is_installed_and_safe():
    """JupyterLab draws the JSON part itself (its plotly renderer brings its own plotly.js),
    in a notebook opened without a kernel and not trusted: the renderer must be "safe"."""
    ext = ROOT / ".venv" / "share" / "jupyter" / "labextensions" / "jupyterlab-plotly"
    if not ext.is_dir():
        pytest.skip("no .venv/share/jupyter/labextensions/jupyterlab-plotly (plotly not in .venv)")
    js = "".join(p.read_text(errors="replace") for p in (ext / "static").glob("*.js"))
    assert PLOTLY_MIME in js
    assert re.search(r"safe:!0,mimeTypes:\[\w+\]", js), "the plotly renderer is not marked safe"


# --- the notebooks ------------------------------------------------------------------------------

@pytest.mark.parametrize("path", course_notebooks() + [FIXTURE], ids=lambda p: p.stem)
def test_notebook_size(path):
    size = path.stat().st_size
    assert size < MAX_NOTEBOOK_BYTES, f"{path.name} is {size / 1e6:.2f} MB (limit 1.5 MB)"
    text = path.read_text()
    assert "Copyright 2012-" not in text, f"{path.name} holds a copy of plotly.js"


@pytest.mark.parametrize("path", course_notebooks() + [FIXTURE], ids=lambda p: p.stem)
def test_interactive_figures_have_alt_text_and_a_slide(path):
    nb = read(path)
    for i, cell, out in _plotly_cells(nb):
        alt = ((cell.metadata.get("mystnb") or {}).get("image") or {}).get("alt")
        assert alt, f"{path.name} cell {i}: no metadata.mystnb.image.alt"
        label = _aria_label(out["data"].get("text/html", ""))
        assert label is not None and htmllib.unescape(label) == alt, \
            f"{path.name} cell {i}: the figure's aria-label differs from metadata.mystnb.image.alt"
        assert "slideshow" in cell.metadata, f"{path.name} cell {i}: no slideshow metadata"
        # a lecture may leave a figure to the notebook (slide type skip, or notebook-only):
        # the deck tests (tests/test_slides.py, TURNABLE) turn the ones it keeps


@pytest.mark.parametrize("path", TURNABLE, ids=lambda p: p.stem)
def test_notebook_has_a_figure_to_turn(path):
    assert _plotly_cells(read(path)), f"{path.name} has no figure the learner turns (show_3d)"


@pytest.mark.parametrize("path", course_notebooks() + [FIXTURE], ids=lambda p: p.stem)
def test_div_ids_are_fixed_and_unique(path):
    ids = [re.search(r'<div id="([^"]+)" class="plotly-graph-div', o["data"]["text/html"]).group(1)
           for _, _, o in _plotly_cells(read(path))]
    assert all(i.startswith("so3-") for i in ids), ids
    assert len(ids) == len(set(ids)), f"{path.name}: a div id is used twice: {ids}"


# --- in Chromium -------------------------------------------------------------------------------

SHOTS = SCREENSHOTS / "interactive"


@pytest.fixture(scope="module")
def fixture_deck(tmp_path_factory):
    try:
        (deck,) = slides.build(tmp_path_factory.mktemp("deck"), [FIXTURE])
    except SystemExit as e:
        pytest.skip(str(e))
    return deck


@pytest.fixture(scope="module")
def fixture_deck_open(browser, fixture_deck):
    """The fixture deck open offline (one load for the tests below), and its measure
    (tools.slides.measure_open) taken as soon as it is ready, before a figure is turned."""
    d = slides.OfflineDeck(browser, fixture_deck)
    try:
        d.ready()
        yield d, slides.measure_open(d)
    finally:
        d.close()


@pytest.mark.browser
def test_fixture_deck_loads_plotly_once_and_turns(fixture_deck, fixture_deck_open):
    page = fixture_deck.read_text()
    assert page.count(f'src="{slides.VENDOR_DIR}/{vendor.PLOTLY_JS}"') == 1
    assert (fixture_deck.parent / slides.VENDOR_DIR / vendor.PLOTLY_JS).is_file()
    d, _ = fixture_deck_open
    turn_deck_figures(d, fixture_deck.name, SHOTS / "deck")


@pytest.mark.browser
def test_fixture_deck_report_counts_one_figure_with_alt(fixture_deck_open):
    _, m = fixture_deck_open
    first = m["slides"][0]
    assert len(first["figures"]) == 1, first["figures"]
    assert first["figures"][0]["alt"].startswith("A body frame"), first["figures"]


# The course's decks (notebooks 01 to 05) are turned in tests/test_slides.py, in the decks
# it opens and measures, and the book's pages in tests/test_book_laptop.py, on the pages it visits.


# --- the book -------------------------------------------------------------------------------
# The book's pages of notebooks 01 to 05 are opened offline and each of their figures turned
# in tests/test_book_laptop.py (with the book's one plotly.js, test_book.py checks that no
# page loads anything from the network): a one-page book of the fixture would only repeat it.


ALT_FIXTURE_START = "A body frame (red x, green y, blue z arrows)"


def test_fixture_notebook_is_executed_and_deterministic():
    nb = nbformat.read(str(FIXTURE), as_version=4)
    (i, cell, out), = _plotly_cells(nb)
    assert 'id="so3-fixture-rotating-frame"' in out["data"]["text/html"]
    assert len(out["data"][PLOTLY_MIME]["frames"]) == 21


# --- JupyterLab, with no kernel -----------------------------------------------------------

@pytest.fixture(scope="module")
def jupyterlab(tmp_path_factory):
    """JupyterLab serving a copy of the fixture notebook, with no kernel it could start
    (the only allowed kernelspec does not exist): yields its URL."""
    import socket
    import subprocess
    import sys
    import time
    import urllib.request
    root = tmp_path_factory.mktemp("lab")
    shutil.copy(FIXTURE, root / FIXTURE.name)
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        port = s.getsockname()[1]
    proc = subprocess.Popen(
        [sys.executable, "-m", "jupyterlab", "--allow-root", "--no-browser", f"--port={port}",
         "--ip=127.0.0.1", f"--ServerApp.root_dir={root}", "--ServerApp.token=",
         "--ServerApp.password=", "--LabApp.news_url=None",
         "--LabApp.check_for_updates_class=jupyterlab.NeverCheckForUpdate",
         "--KernelSpecManager.allowed_kernelspecs={'no-such-kernel'}"],
        stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL, cwd=root)
    url = f"http://127.0.0.1:{port}"
    try:
        for _ in range(120):
            try:
                urllib.request.urlopen(f"{url}/api/status", timeout=1)
                break
            except OSError:
                time.sleep(0.5)
        else:
            pytest.skip("JupyterLab did not start within a minute")
        yield url
    finally:
        proc.terminate()
        try:
            proc.wait(timeout=20)
        except subprocess.TimeoutExpired:
            proc.kill()


@pytest.mark.browser
def test_jupyterlab_draws_and_turns_with_no_kernel(browser, jupyterlab):
    """The notebook opened in JupyterLab with "No Kernel": the plotly renderer draws the
    stored figure (with its 21 animation frames) from the notebook alone, nothing is
    fetched from the network, and a drag turns it."""
    off = Offline(browser, allowed=(jupyterlab, jupyterlab.replace("http", "ws"), "data:",
                                    "about:", "blob:"))
    try:
        page = off.new_page()
        page.goto(f"{jupyterlab}/lab/tree/{FIXTURE.name}")
        page.locator("button:has-text('No Kernel')").first.click(timeout=90_000)
        page.wait_for_selector(".js-plotly-plot", timeout=60_000)
        before, after = drag_turns(page, ".js-plotly-plot")
        assert eye_moved(before, after) > 0.05, "dragging did not turn the figure in JupyterLab"
        frames = page.evaluate("() => document.querySelector('.js-plotly-plot')._transitionData._frames.length")
        assert frames == 21
        screenshot_to(page, SHOTS / "jupyterlab" / "fixture.png")
        assert not off.blocked, off.blocked
    finally:
        off.context.close()
