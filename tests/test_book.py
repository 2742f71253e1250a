"""The course book (tools/book.py): every link resolves, and it reads offline in a browser.

The book is built once per session into build/book/ (incrementally: pages whose inputs
did not change are kept). Its links are checked in every page; the index is opened in
Chromium from file:// with every network request blocked, its math must be typeset and
its "next" link must lead to a page whose math is typeset too.
"""

import html
import os
import re
from pathlib import Path
from urllib.parse import unquote, urlsplit

import pytest

from browser_support import MATHJAX_ERRORS, MATHJAX_IDLE, ROOT, Offline, screenshot
from tools import book
from tools.common import course_notebooks


@pytest.fixture(scope="session")
def pages():
    try:
        return book.build(ROOT / "build" / "book")
    except SystemExit as e:  # npm missing or the registry unreachable
        if os.environ.get("CI"):
            pytest.fail(str(e))
        pytest.skip(str(e))


# nbconvert writes every attribute in double quotes, so regular expressions read the pages
# exactly (and twenty times faster than an HTML parser).
ANCHOR = re.compile(r'<[a-zA-Z][^>]*?\s(?:id|name)="([^"]*)"')
HREF = re.compile(r'<a\s[^>]*?href="([^"]*)"')
LOADS = re.compile(r'<(?:script|link|img)\s[^>]*?(?:src|href)="([^"]*)"')


def _ids(path, cache={}):
    if path not in cache:
        cache[path] = {html.unescape(m) for m in ANCHOR.findall(path.read_text(encoding="utf-8"))}
    return cache[path]


def test_book_has_a_page_per_notebook(pages):
    names = [p.name for p in pages]
    assert names[0] == "index.html"
    assert names[1:] == [f"{p.stem}.html" for p in course_notebooks()]


def test_every_link_in_the_book_resolves(pages):
    broken = []
    for page in pages:
        text = page.read_text(encoding="utf-8")
        for href in map(html.unescape, HREF.findall(text)):
            url = urlsplit(href)
            if url.scheme in ("http", "https", "mailto"):
                continue  # references to the web: they work when there is a network
            target = (page.parent / unquote(url.path)).resolve() if url.path else page
            if url.scheme or not target.is_file():
                broken.append(f"{page.name}: {href} (no such file)")
            elif url.fragment and not {url.fragment, unquote(url.fragment)} & _ids(target):
                broken.append(f"{page.name}: {href} (no such anchor in {target.name})")
        for src in map(html.unescape, LOADS.findall(text)):
            url = urlsplit(src)
            if url.scheme in ("http", "https") or src.startswith("//"):
                broken.append(f"{page.name}: loads {src} from the network")
            elif not url.scheme and not (page.parent / unquote(url.path)).is_file():
                broken.append(f"{page.name}: loads {src}, which is not there")
    assert not broken, "\n".join(broken)


@pytest.mark.browser
def test_book_reads_offline(browser, pages):
    offline = Offline(browser)
    page = offline.new_page()
    page.set_default_timeout(20_000)
    page.goto(pages[0].as_uri())
    page.wait_for_function(MATHJAX_IDLE)
    assert page.locator(".MathJax_CHTML").count() > 0, "the index's formula was not typeset"
    titles = page.locator(".course-contents > li > strong > a")
    assert titles.count() == len(pages) - 1, "the index lists every notebook in order"
    screenshot(page, "book_index")
    page.locator(".course-nav.top a[rel=next]").click()
    page.wait_for_url("**/" + pages[1].name)
    page.wait_for_function(MATHJAX_IDLE)
    assert page.locator(".MathJax_CHTML").count() > 0
    assert page.locator(MATHJAX_ERRORS).count() == 0
    screenshot(page, "book_" + Path(pages[1]).stem)
    assert not offline.problems(), offline.problems()
    offline.close()
