"""`make slides`: a reveal.js deck per notebook, in build/slides/, that presents offline.

Each cell's slideshow metadata decides where it goes: "slide" starts a new slide,
"subslide" a new slide below it (down arrow), "fragment" appears on the next key press,
"skip" leaves the cell out, "notes" goes to the speaker view (press S), "-" continues
the current slide. A code cell tagged "hide-input" shows only its output (a figure
without the code that draws it); a figure's alt text is its cell's
metadata.mystnb.image.alt. Which cells the deck leaves out is tools/roles.py's (the README's
table): those tagged "solution", "hidden-test", "answer", "check" or "verify", among others;
an exercise slide shows the task and how it is checked. `--solutions`
(`make slides-solutions`) builds the decks with the worked solutions, for after the
deadline, into build/slides-solutions/. `--handouts` (`make handouts`) prints each deck
to build/handouts/NN_name.pdf, one page per slide, with Chromium (reveal's print view),
each page with its slide's figures (a figure the learner turns as a still of its scene),
and the answers to the questions to the hall gathered on the last page(s), each question's
page saying where (a handout is often given out before the lecture).

The slide is 1280x720 (a common projector) and scales as a whole to the screen: prose is
30 px and code 25 px at 1280x720. reveal.js, MathJax, jQuery and require.js are unpacked
into build/slides/vendor/ from the npm registry (tools/vendor.py), so the decks load
nothing from the network: copy the whole build/slides/ folder to the lecture-hall
machine and open NN_name.slides.html in a browser.

`--report NOTEBOOK` builds that deck and measures every slide in Chromium with the
network blocked (words, code lines, font sizes on screen, anything outside the slide at
1280x720, 1024x768 and 1920x1080, figure sizes and alt text), against the limits of a
lecture deck (README, "Adding a notebook"), with a screenshot of each slide in
build/screenshots/slides/NN_name/. A second table reads the deck as a 50-minute lecture
(issue 23): slides, questions to the hall, builds, notes with a time mark, code lines,
check and test-output lines, coursework words, references the hall cannot follow, figure
share of the slide and label size. With --handouts it also prints the handout and counts
the pictures on each page against the slide.

Usage: python -m tools.slides [--out DIR] [--solutions] [--handouts] [NOTEBOOK ...]
       python -m tools.slides --report [--handouts] NOTEBOOK [NOTEBOOK ...]
"""

import argparse
import html as htmllib
import re
import shutil
import statistics
import sys
from pathlib import Path

from nbconvert.exporters import SlidesExporter
from traitlets.config import Config

from tools import roles, vendor
from tools.common import (
    BUILD,
    TEMPLATES,
    Stamps,
    copy_assets,
    course_notebooks,
    read,
    relink,
    tooling_key,
    write_atomic,
)

VENDOR_DIR = "vendor"
WIDTH, HEIGHT = 1280, 720  # the slide's design size: one CSS pixel is one pixel at 1280x720

# The shape of a lecture deck (issue 10; README "Adding a notebook"). The tests hold every
# deck to these; --report prints them next to each slide's figures.
SLIDES_MIN, SLIDES_MAX = 20, 35          # slides per lecture deck (see min_slides)
WORDS_MAX, WORDS_MEDIAN = 60, 40         # words of prose on a slide; median over the deck
CODE_LINES_MAX = 12                      # source lines of code on a slide
PROSE_PX, CODE_PX = 28, 24               # smallest font on screen at 1280x720
FIGURE_FRACTION = 0.5                    # a figure spans half the slide's width or height
SCREENS = [(1280, 720), (1024, 768), (1920, 1080)]  # nothing outside the slide at any

# A lecture (issue 23, "Done when"): what the report measures for it. The opening 00 and the
# appendices A* are short references: the slide count and questions do not apply to them.
LECTURE_SLIDES = (22, 28)          # slides in a 50-minute lecture
LECTURE_MINUTES = 50
QUESTION_EVERY = 12                # minutes between questions to the hall, at most
LECTURE_CODE_LINES = 6             # code lines on a slide where the code is the point
FIGURE_SHARE = 0.6                 # a figure spans 60 % of the slide's width or height
PLOTLY_HEIGHT_SHARE = 0.8          # a 3-D scene: 80 % of the slide's height
LABEL_PX = 20                      # figure labels on a 1280x720 screen
SUMMARY_SENTENCES = 4              # take-home sentences on the summary slide
# A matplotlib figure's smallest label at its drawn size: so3lib.plot's house style (tick
# labels 16 pt at 100 dpi). A PNG does not say its font sizes, so the report estimates a
# figure's labels on screen as this times the figure's scale on the slide (drawn with
# another style, the estimate is off by that style's ratio).
LABEL_PX_DRAWN = 16 * 100 / 72

# The tags of the cells a deck leaves out (tools/roles.py, the README's table): the
# exercise's stub, checker call, worked solution and grading asserts, the checks the
# notebook's claims rest on (tag "verify"), ... The solutions deck keeps the worked solutions.
# Cells of slide type "skip" and "notes" are nbconvert's own to leave out or put in the notes.
DECK_DROPS = roles.tags_left_out(roles.DECK)
SOLUTION_DECK_DROPS = roles.tags_left_out(roles.DECK_SOLUTIONS)

OUT = BUILD / "slides"
OUT_SOLUTIONS = BUILD / "slides-solutions"
OUT_HANDOUTS = BUILD / "handouts"
SCREENSHOTS = BUILD / "screenshots" / "slides"


def exporter(solutions=False):
    c = Config()
    c.SlidesExporter.reveal_url_prefix = f"{VENDOR_DIR}/{vendor.REVEAL_PREFIX}"
    c.SlidesExporter.mathjax_url = f"{VENDOR_DIR}/{vendor.MATHJAX3_SVG_JS}"
    c.SlidesExporter.require_js_url = f"{VENDOR_DIR}/{vendor.REQUIRE_JS}"
    c.SlidesExporter.jquery_url = f"{VENDOR_DIR}/{vendor.JQUERY_JS}"
    c.SlidesExporter.reveal_theme = "white"
    c.SlidesExporter.reveal_transition = "none"  # crisp on a projector
    c.SlidesExporter.reveal_number = "c/t"
    c.SlidesExporter.reveal_scroll = False  # a slide that does not fit is split, not scrolled
    c.SlidesExporter.reveal_width = str(WIDTH)
    c.SlidesExporter.reveal_height = str(HEIGHT)
    c.SlidesExporter.exclude_input_prompt = True
    c.SlidesExporter.exclude_output_prompt = True
    # A cell whose deck shows only its output (tag "hide-input": a figure without the
    # plotting code); the notebook and the book still show the code.
    c.TagRemovePreprocessor.enabled = True
    c.TagRemovePreprocessor.remove_input_tags = {r.tag for r in roles.ROLES
                                                 if r.tag and r.action(roles.DECK) == roles.OUTPUT}
    c.TagRemovePreprocessor.remove_cell_tags = SOLUTION_DECK_DROPS if solutions else DECK_DROPS
    c.SlidesExporter.extra_template_basedirs = [str(TEMPLATES)]
    c.SlidesExporter.extra_template_paths = [str(TEMPLATES)]  # for course_mathjax.html.j2
    c.SlidesExporter.template_name = "course_slides"
    return SlidesExporter(config=c)


# --- HTML touches the template cannot make ------------------------------------------------

_HIGHLIGHT = re.compile(r'(<div class="highlight[^"]*"><pre>)(.*?)(</pre></div>)', re.DOTALL)
_TAG = re.compile(r"(<[^>]+>)")


def _hang(inner):
    """One span.cl per source line of Pygments' HTML, with the line's indentation as --ind,
    so that a wrapped line continues 4 characters right of its own indentation."""
    lines, current, text, stack = [], [], [], []
    for token in _TAG.split(inner):
        if not token:
            continue
        if token.startswith("<"):
            if token.startswith("</"):
                if stack:
                    stack.pop()
            elif not token.endswith("/>"):
                stack.append(token)
            current.append(token)
            continue
        parts = token.split("\n")
        for k, part in enumerate(parts):
            if k:  # a newline: close the open spans, end the line, reopen them
                current.append("</span>" * len(stack))
                lines.append(("".join(current), "".join(text)))
                current, text = list(stack), []
            current.append(part)
            text.append(part)
    if "".join(text):  # the last line, unless the code ended with a newline
        current.append("</span>" * len(stack))
        lines.append(("".join(current), "".join(text)))
    out = []
    for body, plain in lines:
        plain = htmllib.unescape(plain)
        indent = len(plain) - len(plain.lstrip(" "))
        # the newline stays in the text (copying code from a slide keeps its lines); at the
        # end of a block it adds no blank line
        out.append(f'<span class="cl" style="--ind:{indent}ch">{body}\n</span>')
    return "".join(out)


def hang_code(page):
    return _HIGHLIGHT.sub(lambda m: m.group(1) + _hang(m.group(2)) + m.group(3), page)


# The speaker view copies a note's HTML into its own window, without this page's styles:
# each note carries the one rule that keeps MathJax's hidden MathML copy hidden there.
NOTES_STYLE = ("<style>mjx-assistive-mml{position:absolute!important;top:0;left:0;"
               "clip:rect(1px,1px,1px,1px);padding:1px 0 0 0!important;border:0!important;"
               "display:block!important;width:auto!important;overflow:hidden!important;"
               "user-select:none}mjx-container[display=\"true\"]{display:block;"
               "text-align:center;margin:0.5em 0}mjx-container{position:relative}</style>")


# The solutions deck says so on every slide, so that it is never projected by mistake
# before the coursework is due.
SOLUTIONS_MARK = ('<div class="course-solutions-mark" style="position:fixed;top:6px;left:10px;'
                  'z-index:40;font:bold 16px sans-serif;color:#b00020">with worked solutions</div>')


def finish(page, solutions=False):
    page = hang_code(page)
    page = page.replace('<aside class="notes">', '<aside class="notes">' + NOTES_STYLE)
    if solutions:
        page = page.replace('<div class="reveal">', SOLUTIONS_MARK + '<div class="reveal">', 1)
        page = page.replace(" slides</title>", " slides, with worked solutions</title>", 1)
    return relink(page, ".slides.html")


# --- build ----------------------------------------------------------------------------------

PLOTLY_MIME = "application/vnd.plotly.v1+json"


def has_plotly(nb):
    """Whether a notebook shows a figure the learner turns (so3lib.plot.show_3d)."""
    return any(PLOTLY_MIME in out.get("data", {})
               for cell in nb.cells if cell.cell_type == "code" for out in cell.get("outputs", []))


# A notebook's navigation line ("**Notebook 04** of the course. Previous: [...](...). Next:
# [...](...).", at its top and foot) is for the reader who moves between files; a projected
# deck has no use for it.
_NAVIGATION = re.compile(r"^(\*\*Notebook \w+\*\* of the course\. )?Previous: \[[^\]]*\]\([^)]*\)\. "
                         r"Next: \[[^\]]*\]\([^)]*\)\.[ \t]*\n?", re.MULTILINE)


def without_navigation(nb):
    """NB with the navigation lines taken out of its markdown cells (in place)."""
    for cell in nb.cells:
        if cell.cell_type == "markdown":
            source, n = _NAVIGATION.subn("", cell.source)
            if n:
                cell.source = re.sub(r"\n{3,}", "\n\n", source).strip("\n")
    return nb


def build(out=OUT, notebooks=None, solutions=False):
    """Write OUT/NN_name.slides.html for each notebook and the assets; returns the paths.
    With solutions=True the decks keep the worked solutions (for after the deadline)."""
    out = Path(out)
    out.mkdir(parents=True, exist_ok=True)
    vendor.install(out / VENDOR_DIR, ["reveal.js", "mathjax3", "jquery", "requirejs"])
    vendor.install_plotly(out / VENDOR_DIR)
    copy_assets(out)
    exp, stamps = exporter(solutions), Stamps(out)
    tooling = tooling_key() + ("+solutions" if solutions else "")
    written = []
    for path in notebooks or course_notebooks():
        path = Path(path)
        target = out / f"{path.stem}.slides.html"
        key = stamps.key(tooling, path.read_bytes())
        if not stamps.fresh(target.name, key):  # unchanged since the last build: keep it
            nb = without_navigation(read(path))
            resources = {"metadata": {"name": path.stem}}
            if has_plotly(nb):  # a figure the learner turns: load the one vendored plotly.js
                resources["plotly_js"] = f"{VENDOR_DIR}/{vendor.PLOTLY_JS}"
            body, _ = exp.from_notebook_node(nb, resources=resources)
            write_atomic(target, finish(body, solutions))
            stamps.record(target.name, key)
        written.append(target)
    if notebooks is None:  # a notebook renamed or removed: its deck goes too
        for old in set(out.glob("*.slides.html")) - set(written):
            old.unlink()
    stamps.save()
    return written


# --- in Chromium: measuring a deck, printing it -----------------------------------------------

def launch():
    """(playwright, browser): Debian's Chromium through Playwright (tests/browser_support.py)."""
    sys.path.insert(0, str(BUILD.parent / "tests"))
    from browser_support import CHROMIUM_ARGS, chromium_executable
    from playwright.sync_api import sync_playwright
    exe = chromium_executable()
    if exe is None:
        raise SystemExit("no Chromium: apt-get install chromium, or set CHROMIUM=/path/to/chrome")
    pw = sync_playwright().start()
    return pw, pw.chromium.launch(executable_path=exe, args=CHROMIUM_ARGS)


class OfflineDeck:
    """A deck open in its own browser context at a screen size, every request that is not a
    local file aborted and counted."""

    def __init__(self, browser, deck, width=WIDTH, height=HEIGHT, query=""):
        self.blocked, self.errors = [], []
        self.context = browser.new_context(viewport={"width": width, "height": height})
        self.context.route("**/*", self._route)
        self.page = self.context.new_page()
        self.page.on("pageerror", lambda e: self.errors.append(f"page error: {e}"))
        self.page.on("console", lambda m: self.errors.append(f"console {m.type}: {m.text}")
                     if m.type == "error" else None)
        self.page.set_default_timeout(180_000)  # a loaded machine takes minutes to lay out
        self.page.goto(Path(deck).resolve().as_uri() + query, wait_until="commit")

    def _route(self, route):
        url = route.request.url
        if url.startswith(("file:", "data:", "about:", "blob:")):
            route.continue_()
        else:
            self.blocked.append(url)
            route.abort()

    def ready(self, timeout=None):
        # polled by a timer: a background tab runs no animation frames to poll with
        self.page.wait_for_function("document.documentElement.dataset.deckReady === '1'",
                                    polling=250, timeout=timeout)
        return self.page

    def close(self):
        self.context.close()


# Runs in the page: every slide measured where it lies (the deck keeps every slide laid out,
# viewDistance 99; fragments not yet shown are laid out too), in Reveal.getSlides() order.
MEASURE_JS = r"""
() => {
  const LABEL_PX_DRAWN = %LABEL_PX_DRAWN%;
  const slidesEl = document.querySelector('.reveal .slides');
  const deckBox = slidesEl.getBoundingClientRect();
  const scale = deckBox.width / slidesEl.offsetWidth;        // screen px per design px
  const W = slidesEl.offsetWidth * scale, H = slidesEl.offsetHeight * scale;
  const inNotes = el => !!el.closest('aside.notes');
  const laidOut = el => { const r = el.getBoundingClientRect(); return r.width > 0 && r.height > 0; };
  const label = el => { let s = el.tagName.toLowerCase();
    if (el.className && typeof el.className === 'string') s += '.' + el.className.trim().split(/\s+/)[0];
    const t = (el.innerText || el.textContent || el.getAttribute('alt') || '').trim().replace(/\s+/g, ' ');
    return t ? `${s} "${[...t].slice(0, 40).join('')}"` : s; };
  return Reveal.getSlides().map(slide => {
    const idx = Reveal.getIndices(slide);
    const sr = slide.getBoundingClientRect();
    const box = {left: sr.left, top: sr.top, right: sr.left + W, bottom: sr.top + H};
    const heading = slide.querySelector('h1, h2, h3, h4');
    // prose: rendered markdown, each inline formula one word, display formulas none
    let words = 0;
    slide.querySelectorAll('.jp-RenderedMarkdown').forEach(md => {
      if (inNotes(md)) return;
      const c = md.cloneNode(true);
      c.querySelectorAll('mjx-container').forEach(m =>
        m.replaceWith(m.getAttribute('display') === 'true' ? ' ' : ' x '));
      c.querySelectorAll('style, script, a.anchor-link').forEach(e => e.remove());
      words += (c.textContent.match(/[\p{L}\p{N}][\p{L}\p{N}'’\-.]*/gu) || []).length;
    });
    const codes = [...slide.querySelectorAll('.jp-InputArea pre')].filter(e => !inNotes(e));
    const codeLines = codes.map(p => p.querySelectorAll('.cl').length
      || p.textContent.replace(/\n+$/, '').split('\n').length).reduce((a, b) => a + b, 0);
    const longest = Math.max(0, ...codes.flatMap(p => p.textContent.split('\n').map(l => l.length)));
    const outs = [...slide.querySelectorAll('.jp-OutputArea-output pre')].filter(e => !inNotes(e));
    const outLines = outs.map(p => p.textContent.replace(/\n+$/, '').split('\n').length)
      .reduce((a, b) => a + b, 0);
    // smallest font on screen, prose and code, over elements that hold text themselves
    let prosePx = null, codePx = null, proseAt = '', codeAt = '';
    const problems = [], seen = [];
    for (const el of slide.querySelectorAll('*')) {
      if (inNotes(el) || el.closest('mjx-container svg *, mjx-assistive-mml, style, script')) continue;
      if (!laidOut(el)) continue;
      if (!el.closest('mjx-container, svg, sup, sub')
          && [...el.childNodes].some(n => n.nodeType === 3 && n.textContent.trim())) {
        const px = parseFloat(getComputedStyle(el).fontSize) * scale;
        if (el.closest('pre, code, .jp-OutputArea-output')) {
          if (codePx === null || px < codePx) { codePx = px; codeAt = label(el); }
        } else if (prosePx === null || px < prosePx) { prosePx = px; proseAt = label(el); }
      }
      // anything outside the slide, or clipped inside a box that would scroll
      if (seen.some(p => p.contains(el))) continue;
      const r = el.getBoundingClientRect();
      const by = Math.max(r.bottom - box.bottom, r.right - box.right, box.left - r.left, box.top - r.top);
      if (by > 1) {
        problems.push(`outside the slide by ${Math.round(by)} px: ${label(el)}`); seen.push(el); continue;
      }
      const cs = getComputedStyle(el);
      if ((el.scrollHeight > el.clientHeight + 2 && /auto|scroll|hidden/.test(cs.overflowY)) ||
          (el.scrollWidth > el.clientWidth + 2 && /auto|scroll|hidden/.test(cs.overflowX))) {
        problems.push(`cut off inside its box (needs a scroll): ${label(el)}`); seen.push(el);
      }
    }
    const figures = [...slide.querySelectorAll('img, .jp-RenderedSVG svg, .plotly-graph-div, canvas')]
      .filter(e => !inNotes(e) && laidOut(e) && !(e.tagName !== 'DIV' && e.closest('.plotly-graph-div')))
      .map(e => { const r = e.getBoundingClientRect();
        return {w: Math.round(r.width), h: Math.round(r.height),
                big: r.width >= 0.5 * W - 1 || r.height >= 0.5 * H - 1,
                alt: e.tagName === 'IMG' ? (e.getAttribute('alt') || '') : (e.getAttribute('aria-label') || '-')}; });
    // the notes' own text, without the <style> that the build puts at the start of each
    const notes = [...slide.querySelectorAll('aside.notes')].map(n => {
      const copy = n.cloneNode(true);
      copy.querySelectorAll('style').forEach(s => s.remove());
      return copy;
    });
    // --- what a lecture needs (issue 23): the texts, read against the limits in Python
    const mine = sel => [...slide.querySelectorAll(sel)].filter(e => !inNotes(e));
    const mmlText = m => { const a = m.querySelector('mjx-assistive-mml'); return a ? a.textContent : ''; };
    let prose = '';
    mine('.jp-RenderedMarkdown').forEach(md => {
      const c = md.cloneNode(true);
      c.querySelectorAll('mjx-container').forEach(m =>
        m.replaceWith(m.getAttribute('display') === 'true' ? ' ' : ' ' + mmlText(m) + ' '));
      c.querySelectorAll('style, script, a.anchor-link').forEach(e => e.remove());
      c.querySelectorAll('p, li, h1, h2, h3, h4, td, th').forEach(e => e.append('\n'));
      prose += c.textContent + '\n';
    });
    const pictures = [...slide.querySelectorAll('img, .plotly-graph-div')]
      .filter(e => !inNotes(e) && laidOut(e)).map(e => {
        const r = e.getBoundingClientRect();
        let label = null;
        if (e.tagName === 'IMG' && e.classList.contains('course-figure') && e.naturalWidth) {
          label = LABEL_PX_DRAWN * (r.width / scale) / e.naturalWidth;   // estimate, see Python
        } else if (e.tagName === 'DIV' && e._fullLayout) {
          const sizes = [...e.querySelectorAll('svg text')].filter(t => t.textContent.trim())
            .map(t => parseFloat(getComputedStyle(t).fontSize));
          const sc = e._fullLayout.scene;
          if (sc) ['xaxis', 'yaxis', 'zaxis'].forEach(a => sizes.push(sc[a].tickfont.size));
          label = sizes.length ? Math.min(...sizes) : null;
        }
        return {plotly: e.tagName === 'DIV', w: r.width / W, h: r.height / H,
                label_px: label && Math.round(label * 10) / 10};
      });
    return {
      h: idx.h, v: idx.v || 0,
      headline: heading ? heading.textContent.replace(/¶/g, '').trim() : '',
      words, code_lines: codeLines, longest_code_line: longest, output_lines: outLines,
      prose_px: prosePx && Math.round(prosePx * 10) / 10, prose_at: proseAt,
      code_px: codePx && Math.round(codePx * 10) / 10, code_at: codeAt,
      problems, figures,
      math: slide.querySelectorAll('mjx-container').length,
      math_errors: slide.querySelectorAll('mjx-merror, [data-mjx-error]').length,
      notes_words: notes.map(n => n.textContent.trim().split(/\s+/).filter(Boolean).length)
        .reduce((a, b) => a + b, 0),
      notes_math: notes.reduce((a, n) => a + n.querySelectorAll('mjx-container').length, 0),
      notes_text: notes.map(n => n.textContent.trim()).join('\n'),
      prose_text: prose, code_text: codes.map(p => p.textContent).join('\n'),
      output_text: outs.map(p => p.textContent).join('\n'),
      math_text: mine('mjx-container[display="true"]').map(mmlText).join(' '),
      questions: mine('.celltag_question').length,
      fragments: mine('.fragment').length,
      list_items: mine('.jp-RenderedMarkdown li').length,
      display_math: mine('mjx-container[display="true"]').length,
      tables: mine('.jp-RenderedMarkdown table').length,
      pictures,
      scale: Math.round(scale * 1000) / 1000,
    };
  });
}
"""


MEASURE_JS = MEASURE_JS.replace("%LABEL_PX_DRAWN%", f"{LABEL_PX_DRAWN:.2f}")


def goto(page, h, v):
    """Show slide (h, v) with every fragment."""
    page.evaluate("([h, v]) => { Reveal.slide(h, v); while (Reveal.nextFragment()) {} }", [h, v])
    page.evaluate("() => new Promise(r => requestAnimationFrame(() => requestAnimationFrame(r)))")


def measure(deck, browser, screenshots=None, screens=SCREENS):
    """Every slide of DECK measured in Chromium: a list of dicts (see MEASURE_JS) with
    'problems_at' {"WxH": [...]} at each screen size (and 'shot', the screenshot's path,
    when SCREENSHOTS is a folder); and the deck's blocked requests and page errors."""
    d = OfflineDeck(browser, deck, *screens[0])
    try:
        return measure_open(d, screenshots, screens)
    finally:
        d.close()


def measure_open(d, screenshots=None, screens=SCREENS):
    """measure() on a deck already opened (an OfflineDeck at the first screen size), left
    open at that size."""
    page = d.ready()
    slides = page.evaluate(MEASURE_JS)
    for m in slides:
        m["problems_at"] = {f"{screens[0][0]}x{screens[0][1]}": m["problems"]}
    for w, h in screens[1:]:
        page.set_viewport_size({"width": w, "height": h})
        page.evaluate("() => new Promise(r => { Reveal.layout(); requestAnimationFrame(r); })")
        for m, again in zip(slides, page.evaluate(MEASURE_JS), strict=True):
            m["problems_at"][f"{w}x{h}"] = again["problems"]
    if screenshots:
        page.set_viewport_size({"width": screens[0][0], "height": screens[0][1]})
        page.evaluate("() => Reveal.layout()")
        Path(screenshots).mkdir(parents=True, exist_ok=True)
        for old in Path(screenshots).glob("*.png"):
            old.unlink()
        for k, m in enumerate(slides, 1):
            goto(page, m["h"], m["v"])
            # fragments fade in (a fifth of a second): the picture is taken once they are in
            page.evaluate("() => Promise.all(document.getAnimations().map(a => a.finished))")
            page.wait_for_function("() => [...document.querySelectorAll('.present .fragment.visible:not([class*=fade-out]):not([class*=highlight])')]"
                                   ".every(f => getComputedStyle(f).opacity === '1')")
            m["shot"] = str(Path(screenshots) / f"{k:02d}_{m['h']}-{m['v']}.png")
            page.screenshot(path=m["shot"])
    else:
        page.set_viewport_size({"width": screens[0][0], "height": screens[0][1]})
        page.evaluate("() => Reveal.layout()")
    return {"slides": slides, "blocked": list(d.blocked), "errors": list(d.errors)}


def slide_faults(m, deck_name=""):
    """What is wrong with one measured slide, as short phrases (empty when nothing is)."""
    faults = []
    if not m["headline"]:
        faults.append("no headline")
    if m["words"] > WORDS_MAX:
        faults.append(f"{m['words']} words > {WORDS_MAX}")
    if m["code_lines"] > CODE_LINES_MAX:
        faults.append(f"{m['code_lines']} code lines > {CODE_LINES_MAX}")
    if m["prose_px"] is not None and m["prose_px"] < PROSE_PX - 0.05:
        faults.append(f"prose {m['prose_px']} px < {PROSE_PX} ({m['prose_at']})")
    if m["code_px"] is not None and m["code_px"] < CODE_PX - 0.05:
        faults.append(f"code {m['code_px']} px < {CODE_PX} ({m['code_at']})")
    first = None
    for screen, problems in m["problems_at"].items():
        gist = [re.sub(r"by \d+ px", "", p) for p in problems]
        if first is not None and gist == first:
            continue  # the same as at the first screen size (the slide scales as a whole)
        first = gist if first is None else first
        for p in problems[:3]:
            faults.append(f"{screen}: {p}")
        if len(problems) > 3:
            faults.append(f"{screen}: {len(problems) - 3} more elements outside")
    for f in m["figures"]:
        if not f["big"]:
            faults.append(f"figure {f['w']}x{f['h']} px is under half the slide")
        if f["alt"] == "":
            faults.append("figure without alt text (cell metadata.mystnb.image.alt)")
    if m["math_errors"]:
        faults.append(f"{m['math_errors']} TeX errors")
    return faults


# --- a lecture, not a notebook poured into slides (issue 23) ---------------------------------

# A note's time mark: the minute into the lecture, first in the note: "[12 min]", "12'", "12:30".
TIME_MARK = re.compile(r"^\W{0,3}(\d{1,2})(?:[:.]\d{2})?\s*(?:min\b|minutes?\b|['′])", re.I)
# An output line that is a check or a test's verdict, not a number that teaches.
CHECK_OUTPUT = re.compile(r"\beps\b.*:\s*(?:ok|FAILS?)\b|:\s*ok\s*$|\bFAILS?\b|\bNot yet\b|"
                          r"\bCorrect\b|\btolerance\b|\berror \d+ eps\b", re.I | re.M)
CHECK_CODE = re.compile(r"^\s*(?:report\(|check_\w+\(|assert\b)", re.M)
# Words of the coursework, not of a lecture: points, checkers, stubs, grading.
COURSEWORK = re.compile(r"\b(?:\d+\s+points?|check_\w+|checkers?|autograd\w*|"
                        r"hidden tests?|stubs?|Not yet|nbgrader|graded?|submit\w*)\b", re.I)
# References the hall cannot follow: "above", "below" as pointers (not "below 8 eps"), an
# errata code (N15, G3, P0, E1), an equation number not tagged on the slide.
POINTER = re.compile(r"(?:\b(?:see|as|shown|given|defined|details|discussed|computed|cell|"
                     r"code|figure|table|section|formula|equation)\s+|\)\s*)(above|below)\b|"
                     r"\b(above|below)\s*(?=[.,;:)]|$)", re.I | re.M)
ERRATA_CODE = re.compile(r"\b[NGPE]\d{1,2}\b")
EQUATION = re.compile(r"\((\d{1,2}\.\d{1,2}[a-z]?)\)")


def time_mark(notes_text):
    """The minute a slide's notes give (the time mark first in the note), or None."""
    m = TIME_MARK.match(notes_text or "")
    return int(m.group(1)) if m else None


def references(m):
    """The references on slide M that the hall cannot follow."""
    text = m["prose_text"]
    found = [f'"{(p.group(1) or p.group(2)).lower()}"' for p in POINTER.finditer(text)]
    found += [c for c in ERRATA_CODE.findall(text)]
    tagged = set(EQUATION.findall(m["math_text"]))
    found += [f"({n})" for n in EQUATION.findall(text) if n not in tagged]
    return found


def lecture_measure(m):
    """What issue 23 asks of one measured slide, as numbers."""
    out_lines = [ln for ln in m["output_text"].splitlines() if ln.strip()]
    return {
        "time": time_mark(m["notes_text"]),
        "checks": sum(1 for ln in out_lines if CHECK_OUTPUT.search(ln))
        + len(CHECK_CODE.findall(m["code_text"])),
        "coursework": COURSEWORK.findall(m["prose_text"] + "\n" + m["output_text"]),
        "references": references(m),
        "figure_share": [round(max(f["w"], f["h"]), 2) for f in m["pictures"]],
        "labels_px": [f["label_px"] for f in m["pictures"] if f["label_px"] is not None],
        "summary": bool(re.search(r"summary|take.home", m["headline"], re.I)),
        "sentences": len(re.findall(r"[.!?](?:\s|$)", m["prose_text"])),
    }


# The limits of issue 23 by name: the report prints them, tests/test_slides.py holds each
# deck to those it meets (LECTURE_LIMITS there).
LIMITS = {
    "slides": f"{LECTURE_SLIDES[0]} to {LECTURE_SLIDES[1]} slides (00 and A* excepted)",
    "questions": f"a question to the hall every {QUESTION_EVERY} minutes (tag question)",
    "notes": "speaker notes on every slide",
    "time": "a time mark first in every note ([12 min]), never going backwards",
    "code": f"at most {LECTURE_CODE_LINES} code lines on a slide",
    "checks": "no check or test output on a slide (report(...), ok, FAILS, Not yet)",
    "coursework": "no coursework on a slide (points, checkers, stubs, grading)",
    "references": "no 'above'/'below', untagged equation number or errata code",
    "figures": f"figures >= {FIGURE_SHARE:.0%} of the slide, 3-D >= {PLOTLY_HEIGHT_SHARE:.0%} high",
    "labels": f"figure labels >= {LABEL_PX} px (matplotlib: estimated)",
    "builds": "lists of 3+ items and derivations of 2+ formulas build (fragments)",
    "summary": f"a summary of at most {SUMMARY_SENTENCES} sentences and no table",
}


def lecture_slide_faults(m):
    """Where one slide falls short of a lecture's slide (issue 23, 3 to 8): a list of
    (limit, phrase), limit a key of LIMITS."""
    x, faults = lecture_measure(m), []
    if not m["notes_words"]:
        faults.append(("notes", "no speaker notes"))
    elif x["time"] is None:
        faults.append(("time", "notes without a time mark ([12 min] first)"))
    if m["code_lines"] > LECTURE_CODE_LINES:
        faults.append(("code", f"{m['code_lines']} code lines > {LECTURE_CODE_LINES}"))
    if x["checks"]:
        faults.append(("checks", f"{x['checks']} check/test lines (report(...), ok, FAILS, "
                                 "Not yet)"))
    if x["coursework"]:
        faults.append(("coursework", "coursework words: "
                       + ", ".join(sorted(set(x["coursework"]))[:4])))
    if x["references"]:
        faults.append(("references", "references the hall cannot follow: "
                       + ", ".join(x["references"][:4])))
    for f in m["pictures"]:
        if f["plotly"] and f["h"] < PLOTLY_HEIGHT_SHARE - 0.005:
            faults.append(("figures", f"3-D scene {f['h']:.0%} of the slide's height < "
                                      f"{PLOTLY_HEIGHT_SHARE:.0%}"))
        elif not f["plotly"] and max(f["w"], f["h"]) < FIGURE_SHARE - 0.005:
            faults.append(("figures", f"figure {max(f['w'], f['h']):.0%} of the slide < "
                                      f"{FIGURE_SHARE:.0%}"))
        if f["label_px"] is not None and f["label_px"] < LABEL_PX - 0.05:
            faults.append(("labels", f"figure labels about {f['label_px']:.0f} px < {LABEL_PX}"))
    if (m["list_items"] >= 3 or m["display_math"] >= 2) and not m["fragments"]:
        faults.append(("builds", "a list or derivation with no build (fragments)"))
    if x["summary"] and (m["tables"] or x["sentences"] > SUMMARY_SENTENCES):
        faults.append(("summary", f"summary: {m['tables']} tables, {x['sentences']} sentences "
                                  "(3-4 take-home sentences)"))
    return faults


def lecture_deck_faults(name, slides):
    """Where a deck falls short of a 50-minute lecture (issue 23, 2 and 4): a list of
    (limit, phrase)."""
    faults = []
    lecture = not name.startswith(("00", "A"))
    n = len(slides)
    if lecture and not LECTURE_SLIDES[0] <= n <= LECTURE_SLIDES[1]:
        faults.append(("slides", f"{n} slides, not {LECTURE_SLIDES[0]}..{LECTURE_SLIDES[1]}"))
    q = sum(m["questions"] for m in slides)
    want = LECTURE_MINUTES // QUESTION_EVERY
    if lecture and q < want:
        faults.append(("questions", f"{q} questions to the hall, fewer than {want} (one every "
                                    f"{QUESTION_EVERY} minutes)"))
    marked = [t for t in (time_mark(m["notes_text"]) for m in slides) if t is not None]
    if any(b < a for a, b in zip(marked, marked[1:])):
        faults.append(("time", "time marks go backwards"))
    if marked and lecture and marked[-1] > LECTURE_MINUTES:
        faults.append(("time", f"the last time mark is {marked[-1]} min > {LECTURE_MINUTES}"))
    return faults


def lecture_faults(name, slides):
    """{limit: [phrases]} for the whole deck, every key of LIMITS present."""
    out = {k: [] for k in LIMITS}
    for k, m in enumerate(slides, 1):
        for limit, phrase in lecture_slide_faults(m):
            out[limit].append(f"slide {k} {m['headline'][:40]!r}: {phrase}")
    for limit, phrase in lecture_deck_faults(name, slides):
        out[limit].append(phrase)
    return out


def lecture_summary(name, slides):
    """One line per measure of the issue's "Done when", for the deck report."""
    xs = [lecture_measure(m) for m in slides]
    shares = [s for x in xs for s in x["figure_share"]]
    labels = [v for x in xs for v in x["labels_px"]]
    return {
        "slides": len(slides),
        "questions": sum(m["questions"] for m in slides),
        "fragments": sum(m["fragments"] for m in slides),
        "slides with notes": sum(1 for m in slides if m["notes_words"]),
        "notes with a time mark": sum(1 for x in xs if x["time"] is not None),
        "slides with code": sum(1 for m in slides if m["code_lines"]),
        f"slides over {LECTURE_CODE_LINES} code lines": sum(
            1 for m in slides if m["code_lines"] > LECTURE_CODE_LINES),
        "check/test lines": sum(x["checks"] for x in xs),
        "coursework words": sum(len(x["coursework"]) for x in xs),
        "references": sum(len(x["references"]) for x in xs),
        "figures": len(shares),
        f"figures under {FIGURE_SHARE:.0%} (3-D: {PLOTLY_HEIGHT_SHARE:.0%} high)": sum(
            1 for m in slides for f in m["pictures"]
            if (f["h"] < PLOTLY_HEIGHT_SHARE - 0.005 if f["plotly"]
                else max(f["w"], f["h"]) < FIGURE_SHARE - 0.005)),
        "smallest figure share": min(shares, default=None),
        f"figures with labels under {LABEL_PX} px": sum(1 for v in labels if v < LABEL_PX - 0.05),
        "smallest label px": min(labels, default=None),
    }


def min_slides(name):
    """The fewest slides a deck may have: the opening (00) and the appendices (A1, ...)
    are short references rather than 50-minute lectures, so they may be shorter."""
    return 1 if name.startswith(("00", "A")) else SLIDES_MIN


def deck_faults(name, slides):
    """What is wrong with the deck as a whole."""
    faults = []
    n = len(slides)
    low = min_slides(name)
    if not low <= n <= SLIDES_MAX:
        faults.append(f"{n} slides, not {low}..{SLIDES_MAX}")
    med = statistics.median(m["words"] for m in slides) if slides else 0
    if med > WORDS_MEDIAN:
        faults.append(f"median {med:g} words > {WORDS_MEDIAN}")
    if not any(m["notes_words"] for m in slides):
        faults.append("no speaker notes at all")
    return faults


def solution_lines(notebook):
    """The lines of the cells the deck leaves out by their tags (DECK_DROPS: solutions,
    stubs, checker calls...) that no kept cell has too: none of them may appear in the
    default deck."""
    nb = read(notebook)
    kept = set()
    dropped = []
    for cell in nb.cells:
        lines = [ln.strip() for ln in cell.source.splitlines() if len(ln.strip()) >= 12]
        if DECK_DROPS & set(cell.metadata.get("tags", [])):
            dropped += lines
        elif not roles.left_out(cell, roles.DECK):
            kept.update(lines)
    return sorted({ln for ln in dropped if ln not in kept})


def report(notebook, browser, handout=False):
    """Build NOTEBOOK's deck, measure it and print the tables (legibility, then the deck as a
    lecture), with HANDOUT its handout's pictures per page; returns the number of faults."""
    notebook = Path(notebook)
    (deck,) = build(OUT, [notebook])
    name = notebook.stem
    shots = SCREENSHOTS / name
    result = measure(deck, browser, screenshots=shots)
    slides = result["slides"]
    print(f"\n{name}: {deck.relative_to(BUILD.parent)}  (Chromium {WIDTH}x{HEIGHT}, network "
          f"blocked; limits: {SLIDES_MIN}-{SLIDES_MAX} slides, <= {WORDS_MAX} words and median "
          f"<= {WORDS_MEDIAN}, <= {CODE_LINES_MAX} code lines, prose >= {PROSE_PX} px, code >= "
          f"{CODE_PX} px, figures >= half the slide, nothing outside at "
          + ", ".join(f"{w}x{h}" for w, h in SCREENS) + ")")
    print(f"{'#':>3} {'h.v':>5} {'words':>5} {'code':>4} {'out':>4} {'prose':>5} {'code':>5} "
          f"{'figure':>9} {'notes':>5}  headline")
    total = 0
    for k, m in enumerate(slides, 1):
        fig = ",".join(f"{f['w']}x{f['h']}" for f in m["figures"]) or "-"
        px = (lambda v: f"{v:.0f}" if v is not None else "-")
        print(f"{k:>3} {m['h']:>3}.{m['v']:<1} {m['words']:>5} {m['code_lines']:>4} "
              f"{m['output_lines']:>4} {px(m['prose_px']):>5} {px(m['code_px']):>5} {fig:>9} "
              f"{m['notes_words']:>5}  {m['headline'][:60]}")
        for f in slide_faults(m):
            print(f"{'':>10}! {f}")
            total += 1
    words = [m["words"] for m in slides]
    print(f"\nsummary: {len(slides)} slides, median {statistics.median(words) if words else 0:g} "
          f"words of prose (max {max(words, default=0)}), "
          f"{sum(1 for m in slides if m['notes_words'])} slides with speaker notes, "
          f"{sum(len(m['figures']) for m in slides)} figures, "
          f"{sum(1 for m in slides if slide_faults(m))} slides with a fault")
    for f in deck_faults(name, slides):
        print(f"! deck: {f}")
        total += 1
    html = deck.read_text()
    leaked = [ln for ln in solution_lines(notebook) if htmllib.escape(ln, quote=False) in html
              or ln in html]
    for ln in leaked[:5]:
        print(f"! a solution line is in the deck: {ln[:70]}")
    total += len(leaked)
    for u in result["blocked"]:
        print(f"! network request (blocked): {u}")
    for e in result["errors"]:
        print(f"! {e}")
    total += len(result["blocked"]) + len(result["errors"])
    total += lecture_report(name, slides)
    if handout:
        (pdf,) = handouts([deck], browser=browser)
        bad = handout_faults(pdf, slides)
        counts = pdf_images(pdf)
        print(f"\nhandout {pdf.relative_to(BUILD.parent)}: pictures per page "
              + " ".join(f"{k}:{counts[k]}/{len(m['figures'])}" for k, m in enumerate(slides, 1)
                         if m["figures"] or counts[k]))
        for f in bad:
            print(f"! handout: {f}")
        total += len(bad)
    print(f"screenshots: {shots.relative_to(BUILD.parent)}/NN_h-v.png")
    print("faults: " + (str(total) if total else "none"))
    return total


def lecture_report(name, slides):
    """Print the deck against a 50-minute lecture (issue 23): per slide the time mark,
    questions, builds, code, check lines, coursework words, references, figure share and
    label size; then the deck's totals. Returns the number of faults."""
    print(f"\n{name} as a lecture (issue 23; limits: {LECTURE_SLIDES[0]}-{LECTURE_SLIDES[1]} "
          f"slides, a question every {QUESTION_EVERY} min, notes with a time mark on every "
          f"slide, <= {LECTURE_CODE_LINES} code lines, no check or coursework lines, figures "
          f">= {FIGURE_SHARE:.0%} (3-D >= {PLOTLY_HEIGHT_SHARE:.0%} high), labels >= {LABEL_PX} px "
          f"(matplotlib: estimated), no 'above'/'below', untagged equation numbers or errata codes)")
    print(f"{'#':>3} {'time':>4} {'q':>2} {'frag':>4} {'code':>4} {'chk':>3} {'cw':>3} {'ref':>3} "
          f"{'fig%':>7} {'label':>5}  headline")
    total = 0
    for k, m in enumerate(slides, 1):
        x = lecture_measure(m)
        fig = ",".join(f"{s * 100:.0f}" for s in x["figure_share"]) or "-"
        label = f"{min(x['labels_px']):.0f}" if x["labels_px"] else "-"
        t = "-" if x["time"] is None else str(x["time"])
        print(f"{k:>3} {t:>4} {m['questions']:>2} {m['fragments']:>4} {m['code_lines']:>4} "
              f"{x['checks']:>3} {len(x['coursework']):>3} {len(x['references']):>3} {fig:>7} "
              f"{label:>5}  {m['headline'][:50]}")
        for _, f in lecture_slide_faults(m):
            print(f"{'':>10}~ {f}")
            total += 1
    summary = lecture_summary(name, slides)
    print("lecture: " + "; ".join(f"{k} {v}" for k, v in summary.items()))
    for _, f in lecture_deck_faults(name, slides):
        print(f"~ deck: {f}")
        total += 1
    found = lecture_faults(name, slides)
    print("against issue 23: " + "; ".join(
        f"{k} {'ok' if not v else str(len(v)) + ' short'}" for k, v in found.items()))
    return total


# Before a deck is printed: each figure the learner turns (a plotly WebGL scene, which a
# printer may drop) becomes a still of the same scene at the same size and camera
# (Plotly.toImage), with the figure's alt text; every picture is decoded; and the figures
# of a slide taller than its page are shrunk until it fits.
STILLS_JS = r"""
async () => {
  const gds = [...document.querySelectorAll('.plotly-graph-div')].filter(gd => gd.layout);
  for (const gd of gds) {
    const w = Math.round(gd.offsetWidth), h = Math.round(gd.offsetHeight);
    if (!w || !h) continue;
    // Paper has no play button or slider: an animated scene is printed at the middle of its
    // slider, which the title names, and without the controls.
    const slider = (gd.layout.sliders || [])[0];
    const t = gd.layout.title;
    const title = typeof t === 'string' ? t : String((t && t.text) || '');
    let at = '';
    if (slider && slider.steps && slider.steps.length) {
      const step = slider.steps[Math.floor((slider.steps.length - 1) / 2)];
      await Plotly.animate(gd, step.args[0], {mode: 'immediate', frame: {duration: 0, redraw: true},
                                              transition: {duration: 0}});
      at = `${(slider.currentvalue && slider.currentvalue.prefix) || ''}${step.label}`;
    }
    await Plotly.relayout(gd, {sliders: [], updatemenus: [], 'margin.b': 10,
      'title.text': !at ? title : title ? `${title} (printed at ${at})` : `printed at ${at}`});
    const url = await Plotly.toImage(gd, {format: 'png', width: w, height: h, scale: 2});
    const img = document.createElement('img');
    img.src = url;
    img.alt = gd.getAttribute('aria-label') || '';
    img.className = 'course-figure course-plotly-still';
    img.style.cssText = `width:${w}px;height:${h}px;max-height:none;margin:4px 0 0 0`;
    gd.style.display = 'none';
    gd.parentNode.style.height = 'auto';  // the box fitted to the scene: now to the still
    gd.parentNode.insertBefore(img, gd);
  }
  await Promise.all([...document.images].map(i => i.decode().catch(() => null)));
  // The print view lays slides out anew, figures at their drawn size: a slide taller than
  // its page would push a figure, whole, onto the next page. Shrink its figures to fit.
  let shrunk = 0;
  for (const pg of document.querySelectorAll('.reveal .pdf-page')) {
    const section = pg.querySelector('section');
    if (!section) continue;
    for (let round = 0; round < 3; round++) {
      const over = section.scrollHeight - pg.clientHeight + 6;
      const imgs = [...section.querySelectorAll('img.course-figure, .jp-RenderedMarkdown img')]
        .filter(i => i.offsetHeight > 0);
      if (over <= 0 || !imgs.length) break;
      const share = over / imgs.length;
      imgs.forEach(i => { const h = i.offsetHeight, w = i.offsetWidth;
        const t = Math.max(120, h - share);
        i.style.maxHeight = 'none'; i.style.height = Math.floor(t) + 'px';
        i.style.width = Math.floor(w * t / h) + 'px'; });
      shrunk++;
    }
  }
  await new Promise(r => requestAnimationFrame(() => requestAnimationFrame(r)));
  return {stills: gds.length, shrunk};
}
"""


# A handout is given out before the lecture as often as after: the answer to each question
# to the hall (the fragment after a `question` cell) is not printed under its question but on
# the last page(s), "Answers to the questions", with the slide it answers; the question's page
# says where. An answer that holds a picture stays on its slide (the handout keeps every
# figure where the slide shows it).
ANSWERS_JS = r"""
async () => {
  const pages = [...document.querySelectorAll('.reveal .pdf-page')];
  if (!pages.length) return 0;
  const found = [];
  pages.forEach((pg, k) => {
    for (const q of pg.querySelectorAll('.jp-RenderedMarkdown.celltag_question')) {
      const cell = q.closest('.jp-Cell');
      if (!cell) continue;
      // a question shown as a fragment of its own: its answer is the next fragment
      const next = cell.nextElementSibling;
      const holder = cell.parentElement.classList.contains('fragment') &&
                     !(next && next.classList.contains('jp-Cell')) ? cell.parentElement : cell;
      const frag = holder.nextElementSibling;
      if (!frag || !frag.classList.contains('fragment')) continue;
      const cells = [...frag.children].filter(c => c.classList.contains('jp-Cell'));
      if (!cells.length || cells.some(c => c.querySelector('img, svg:not(mjx-container svg), .plotly-graph-div, canvas')))
        continue;
      const head = q.querySelector('h1, h2, h3, h4');
      let title = (head || q).textContent.replace(/¶/g, '').replace(/\s+/g, ' ').trim();
      if (!head && title.length > 70) title = title.slice(0, title.lastIndexOf(' ', 66)) + ' …';
      // a question with maths and no heading: its first paragraph, formulas and all
      const first = !head && q.querySelector('mjx-container') ? q.querySelector('p') : null;
      const shown = first && first.textContent.length < 160 ? first.cloneNode(true) : null;
      found.push({page: k + 1, title: head || !q.querySelector('mjx-container') ? title : '', shown,
                  cells: cells.map(c => c.querySelector('.jp-RenderedMarkdown') || c)});
      const ref = document.createElement('p');
      ref.className = 'course-answer-ref';
      ref.textContent = `Answer: page ${pages.length + 1}.`;
      ref.style.cssText = 'font-size: 0.6em; color: #555; font-style: italic';
      cells.forEach(c => c.remove());
      frag.insertBefore(ref, frag.firstChild);
    }
  });
  if (!found.length) return 0;
  const model = pages[pages.length - 1], modelSection = model.querySelector('section');
  const parent = model.parentNode;
  const newPage = () => {
    const pg = model.cloneNode(false);
    const sec = modelSection.cloneNode(false);
    sec.classList.remove('stack');
    sec.style.cssText = modelSection.style.cssText + ';display:block;text-align:left;font-size:0.62em';
    sec.style.height = 'auto';
    pg.appendChild(sec);
    parent.appendChild(pg);
    const h = document.createElement('h3');
    h.textContent = 'Answers to the questions';
    sec.appendChild(h);
    return [pg, sec];
  };
  let [pg, sec] = newPage(), count = 1;
  for (const f of found) {
    const item = document.createElement('div');
    item.className = 'course-answer';
    item.style.cssText = 'margin: 0 0 0.5em 0';
    const label = document.createElement('p');
    label.style.cssText = 'font-weight: bold; margin: 0';
    label.textContent = `Page ${f.page}` + (f.title ? `: ${f.title}` : '');
    if (f.shown) {
      label.textContent += ': ';
      f.shown.style.cssText = 'display: inline; font-size: inherit; margin: 0';
      label.appendChild(f.shown);
    }
    item.appendChild(label);
    f.cells.forEach(c => {
      c.classList.remove('fragment');
      for (const el of [c, ...c.querySelectorAll('[style]')]) el.style.removeProperty('font-size');
      c.style.fontSize = '26px';
      item.appendChild(c);
    });
    sec.appendChild(item);
    if (item.getBoundingClientRect().bottom > pg.getBoundingClientRect().bottom - 24 &&
        sec.children.length > 2) {
      item.remove();
      [pg, sec] = newPage();
      count++;
      sec.appendChild(item);
    }
  }
  return count;
}
"""


# How many pictures each page of the print view shows (what the PDF's page must hold).
PAGE_PICTURES_JS = r"""
() => [...document.querySelectorAll('.reveal .pdf-page')].map(pg =>
  [...pg.querySelectorAll('img')].filter(i => i.offsetWidth > 0 && i.offsetHeight > 0
    && !i.closest('aside.notes')).length)
"""
PAINTED_JS = r"""
async () => {
  await Promise.all([...document.images].map(i => i.decode().catch(() => null)));
  await new Promise(r => requestAnimationFrame(() => requestAnimationFrame(r)));
}
"""


# A deck's print view may take minutes to lay out on a loaded machine (a session of tests
# keeps every deck open meanwhile); nobody waits at the screen for a handout.
PRINT_TIMEOUT_MS = 300_000


def handouts(decks, out=OUT_HANDOUTS, browser=None):
    """Print each deck through reveal's print view (?print-pdf) to OUT/NN_name.pdf, one page
    per slide, with Chromium and no network; returns the PDF paths. Every page holds its
    slide's figures: a plotly scene prints as a still of itself (STILLS_JS), and each deck
    is brought to the front before it prints (Chromium left the pictures of a deck printed
    from a background tab out of about a third of its pages)."""
    out = Path(out)
    out.mkdir(parents=True, exist_ok=True)
    own = browser is None
    if own:
        pw, browser = launch()
    written, todo, opened = [], [], []
    stamps, tooling = Stamps(out), tooling_key()
    try:
        for deck in decks:
            deck = Path(deck)
            target = out / (deck.name.removesuffix(".slides.html") + ".pdf")
            written.append(target)
            key = stamps.key(tooling, deck.read_bytes())
            if not stamps.fresh(target.name, key):  # not printed since the deck or tools changed
                todo.append((deck, target, key))
        # one deck at a time, in front: a background tab is not painted for the printer
        for deck, target, key in todo:
            d = OfflineDeck(browser, deck, WIDTH, HEIGHT, query="?print-pdf")
            opened.append(d)
            d.page.bring_to_front()
            page = d.ready(timeout=PRINT_TIMEOUT_MS)
            page.wait_for_function("document.querySelectorAll('.reveal .pdf-page').length > 0",
                                   polling=250, timeout=PRINT_TIMEOUT_MS)
            page.evaluate(ANSWERS_JS)
            page.evaluate(STILLS_JS)
            page.emulate_media(media="print")
            want = page.evaluate(PAGE_PICTURES_JS)
            tmp = target.with_name(f".{target.name}.tmp")
            # Chromium now and then prints a page without a picture that is on it (seen on a
            # loaded machine): the PDF is checked page by page and printed again if so.
            for attempt in range(3):
                page.evaluate(PAINTED_JS)
                page.wait_for_timeout(500 * (attempt + 1))
                page.pdf(path=str(tmp), width=f"{WIDTH}px", height=f"{HEIGHT}px",
                         print_background=True, prefer_css_page_size=True)
                got = pdf_images(tmp) if shutil.which("pdfimages") else None
                missing = [k for k, n in enumerate(want, 1) if got is not None and got[k] < n]
                if not missing:
                    break
            else:
                tmp.unlink(missing_ok=True)
                raise SystemExit(f"{deck.name}: the handout's pages {missing} lack a figure "
                                 "after 3 prints")
            tmp.replace(target)
            problems = d.blocked + d.errors
            if problems:
                target.unlink(missing_ok=True)
                raise SystemExit(f"{deck.name}: " + "; ".join(problems))
            opened.remove(d)
            d.close()
            stamps.record(target.name, key)
            stamps.save()
    finally:
        for d in opened:
            d.close()
        if own:
            browser.close()
            pw.stop()
    return written


def pdf_images(pdf):
    """{page number (from 1): how many pictures it holds} of a PDF (poppler's pdfimages;
    a picture's transparency mask is not counted again)."""
    import subprocess
    from collections import Counter
    if not shutil.which("pdfimages"):
        raise SystemExit("no pdfimages: apt-get install poppler-utils")
    out = subprocess.run(["pdfimages", "-list", str(pdf)], capture_output=True, text=True,
                         check=True).stdout
    counts = Counter()
    for line in out.splitlines()[2:]:
        f = line.split()
        if len(f) > 2 and f[2] == "image":
            counts[int(f[0])] += 1
    return counts


def handout_faults(pdf, slides):
    """The pages of a deck's handout that hold fewer pictures than their slide shows
    (SLIDES: the deck's measure, in page order)."""
    counts = pdf_images(pdf)
    return [f"page {k} ({m['headline'][:40]!r}): {counts[k]} of {len(m['figures'])} figures printed"
            for k, m in enumerate(slides, 1) if counts[k] < len(m["figures"])]


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--out", type=Path, default=None)
    parser.add_argument("--solutions", action="store_true",
                        help="keep the worked solutions (default folder build/slides-solutions/)")
    parser.add_argument("--handouts", action="store_true",
                        help="also print each deck to a PDF in build/handouts/")
    parser.add_argument("--report", action="store_true",
                        help="build and measure the given notebooks' decks in Chromium")
    parser.add_argument("notebooks", nargs="*", type=Path)
    args = parser.parse_args(argv)
    if args.report:
        if not args.notebooks:
            parser.error("--report needs a notebook: python -m tools.slides --report notebooks/01_x.ipynb")
        pw, browser = launch()
        try:
            faults = sum(report(nb, browser, handout=args.handouts) for nb in args.notebooks)
        finally:
            browser.close()
            pw.stop()
        return 1 if faults else 0
    out = args.out or (OUT_SOLUTIONS if args.solutions else OUT)
    decks = build(out, args.notebooks or None, solutions=args.solutions)
    for target in decks:
        print(target.relative_to(Path.cwd()) if target.is_relative_to(Path.cwd()) else target)
    if args.handouts:
        for pdf in handouts(decks):
            print(pdf.relative_to(Path.cwd()) if pdf.is_relative_to(Path.cwd()) else pdf)
    return 0


if __name__ == "__main__":
    sys.exit(main())
