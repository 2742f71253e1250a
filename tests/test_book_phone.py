"""The book at a phone's size (390x844) in Chromium, with every request outside file://
blocked: each page once. The text comes first (the contents do not cover it), nothing
needs sideways scrolling (a wide table scrolls in its own box), and each 3-D figure lets
a swipe scroll the page, keeps its title inside it, draws all of its scene inside the
scene's frame (nothing runs off its sides), and has no toolbar or "Back to top" button
over it.
"""

import pytest
from book_support import (
    CUT_OFF,
    PHONE,
    PHONE_FIGURES,
    PREV_NEXT,
    SCENE_FRAMES,
    SHRUNK_PICTURES,
    SMALL_TARGETS,
    TEXT_FIRST,
    BookOffline,
    drawn_at_edges,
    open_page,
    remembered,
)
from browser_support import screenshot

pytestmark = pytest.mark.browser


@pytest.fixture(scope="module")
def phone(request, pages):
    """What each check needs, from one visit of every page (or the last one's, when nothing
    it looked at changed: book_support.remembered)."""
    return remembered(request, "book-phone", lambda: _visit(request.getfixturevalue("browser"), pages))


def _visit(browser, pages):
    found = {}
    offline = BookOffline(browser, viewport=PHONE)
    page = offline.new_page()
    page.set_default_timeout(60_000)
    try:
        for path in pages:
            open_page(page, path)
            page.wait_for_function("""() => [...document.querySelectorAll('.plotly-graph-div')]
                .every(f => f._fullLayout && f.dataset.courseSceneFitted)""")
            page.wait_for_timeout(300)  # the titles are refitted once drawn
            found[path.name] = {"cut": page.evaluate(CUT_OFF), "layout": page.evaluate(TEXT_FIRST),
                                "figures": page.evaluate(PHONE_FIGURES), "small": page.evaluate(SMALL_TARGETS),
                                "prevnext": page.evaluate(PREV_NEXT),
                                "shrunk": page.evaluate(SHRUNK_PICTURES),
                                "scenes": _scene_edges(page)}
            if path in (pages[0], pages[2]):
                screenshot(page, f"book_{path.stem}_phone")
        found["_problems"] = offline.problems()
    finally:
        offline.close()
    return found


def _scene_edges(page):
    """Each 3-D scene's frame photographed with its shield lifted (its button sits on the
    frame): the sides where something drawn reaches the frame's edge, cut off there."""
    frames = page.evaluate(SCENE_FRAMES)
    if not frames:
        return []
    page.evaluate("""() => document.querySelectorAll('.course-figure-shield, .course-figure-done')
                            .forEach(el => el.style.visibility = 'hidden')""")
    seen = []
    try:
        for f in frames:
            page.evaluate("y => window.scrollTo(0, y)", max(0, f["y"] - 100))
            page.wait_for_timeout(300)  # plotly draws the scene once it is in view
            clip = {"x": f["x"] + 1, "y": f["y"] + 1, "width": f["width"] - 2, "height": f["height"] - 2}
            png = page.screenshot(clip=clip, full_page=True)
            seen.append({"id": f["id"], "scene": f["scene"], "size": [round(f["width"]), round(f["height"])],
                         "edges": drawn_at_edges(png, f["background"])})
    finally:
        page.evaluate("""() => document.querySelectorAll('.course-figure-shield, .course-figure-done')
                                .forEach(el => el.style.visibility = '')""")
        page.evaluate("window.scrollTo(0, 0)")
    return seen


def test_every_page_reads_offline(phone):
    assert not phone["_problems"], phone["_problems"]


def test_nothing_needs_sideways_scrolling_on_a_phone(phone, pages):
    cut = [f"{path.name}: {c}" for path in pages for c in phone[path.name]["cut"]]
    assert not cut, "\n".join(cut)


def test_on_a_phone_3d_figures_let_the_page_scroll_and_show_their_title(phone, pages):
    problems = []
    for path in pages:
        for fig in phone[path.name]["figures"]:
            if not (fig["shield"] and fig["turn"]):
                problems.append(f"{path.name} #{fig['id']}: a swipe over it does not scroll the page")
            if not fig["titleInside"]:
                problems.append(f"{path.name} #{fig['id']}: its title is cut off")
            if not fig.get("sceneWide"):
                problems.append(f"{path.name} #{fig['id']}: its scene leaves part of the width empty")
            if not fig.get("legendClear"):
                problems.append(f"{path.name} #{fig['id']}: its legend covers the scene")
            if fig["toolbar"] or fig["backToTop"]:
                problems.append(f"{path.name} #{fig['id']}: a toolbar or 'Back to top' covers it")
    assert not problems, "\n".join(problems)


def test_on_a_phone_each_3d_scene_lies_inside_its_frame(phone, pages):
    """Nothing a 3-D scene draws (a sphere, an arrow, its axis box and labels) reaches the
    side of its frame on a phone: a slide's camera, placed for a wide frame, would leave
    part of the drawing off the narrow one."""
    cut = [f"{path.name} #{s['id']} ({s['scene']}, {s['size'][0]}x{s['size'][1]}): drawn up to its "
           + ", ".join(f"{side} edge ({n} px)" for side, n in s["edges"].items())
           for path in pages for s in phone[path.name].get("scenes", [{"id": "not measured", "scene": "",
                                                                      "size": [0, 0], "edges": {"all": 0}}])
           if s["edges"]]
    assert not cut, "\n".join(cut)


def test_on_a_phone_the_text_comes_first(phone, pages):
    for path in pages:
        layout = phone[path.name]["layout"]
        assert not layout["navShown"], f"{path.name}: the contents cover the text on a phone"
        assert layout["headingTop"] is not None and layout["headingTop"] < PHONE["height"] / 3, \
            f"{path.name}: the title starts {layout['headingTop']} px down"


def test_on_a_phone_the_header_buttons_are_big_enough_to_touch(phone, pages):
    small = [f"{path.name}: {b}" for path in pages for b in phone[path.name]["small"]]
    assert not small, "touch targets under 44 px:\n" + "\n".join(small[:12])


def test_on_a_phone_the_previous_and_next_links_fit(phone, pages):
    bad = [f"{path.name}: {b}" for path in pages for b in phone[path.name].get("prevnext", ["not measured"])]
    assert not bad, "\n".join(bad)


def test_on_a_phone_a_shrunk_picture_opens_full_size(phone, pages):
    """A picture a phone shows at under 4/5 of its width (its ticks a few pixels tall) opens
    at full size when tapped."""
    bad = [f"{path.name}: {p['src']} shown {p['width']} px wide" for path in pages
           for p in phone[path.name].get("shrunk", [{"src": "not measured", "width": 0, "opens": False}])
           if not p["opens"]]
    assert not bad, "\n".join(bad[:12])
