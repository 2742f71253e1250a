"""Every notebook is marked the way README's "One source, three editions" table says.

The book, the decks, the student edition and the coursework are all built from
notebooks/ by reading these marks, so a cell marked wrongly leaks an answer or loses an
exercise in some edition. These tests read the committed notebooks only (fast, no
kernel) and cover any notebook added later.
"""

import ast
import functools
import importlib
import re

import pytest

from tools.common import course_notebooks, read

NOTEBOOKS = course_notebooks()
IDS = [p.stem for p in NOTEBOOKS]
POINTS = re.compile(r"^points-([1-9][0-9]*)$")
HIDDEN = ("notes", "solution", "hidden-test")


def _tags(cell):
    return set(cell.metadata.get("tags", []))


def _slide_type(cell):
    return cell.metadata.get("slideshow", {}).get("slide_type", "-")


def _kind(cell):
    """'notes', 'solution', 'hidden-test', 'answer', 'check', or None."""
    if _slide_type(cell) == "notes":
        return "notes"
    for tag in ("solution", "hidden-test", "answer", "check"):
        if tag in _tags(cell):
            return tag
    return None


@pytest.fixture(scope="module", params=NOTEBOOKS, ids=IDS)
def nb(request):
    return read(request.param)


def test_notes_solutions_and_hidden_tests_start_collapsed(nb):
    open_cells = [i for i, c in enumerate(nb.cells)
                  if _kind(c) in HIDDEN and not c.metadata.get("jupyter", {}).get("source_hidden")]
    assert not open_cells, f"cells {open_cells} should carry jupyter.source_hidden: true"


def test_speaker_notes_only_in_notes_cells(nb):
    stray = [i for i, c in enumerate(nb.cells)
             if _kind(c) != "notes" and c.source.lstrip().lower().startswith("speaker notes")]
    assert not stray, f"cells {stray} read as speaker notes but are not slide_type 'notes'"


def _exercises(nb):
    """Yield (answer index, [cells up to the next answer]) for each exercise."""
    starts = [i for i, c in enumerate(nb.cells) if _kind(c) == "answer"]
    for k, i in enumerate(starts):
        end = starts[k + 1] if k + 1 < len(starts) else len(nb.cells)
        yield i, nb.cells[i:end]


def test_each_exercise_has_answer_check_solution_hidden_test_in_order(nb):
    for i, cells in _exercises(nb):
        kinds = [_kind(c) for c in cells]
        assert cells[0].cell_type == "code", f"answer cell {i} must be a code cell"
        assert kinds[1] == "check", f"the cell after answer {i} must be its check cell"
        points = [POINTS.match(t) for t in _tags(cells[1])]
        assert sum(1 for m in points if m) == 1, f"check cell {i + 1} needs one points-N tag"
        assert "solution" in kinds, f"exercise at cell {i} has no solution cells"
        assert "hidden-test" in kinds, f"exercise at cell {i} has no hidden-test cell"
        assert kinds.index("solution") < kinds.index("hidden-test"), (
            f"exercise at cell {i}: the hidden test must run after the solution")
        assert kinds.count("hidden-test") == 1, f"exercise at cell {i}: one hidden-test cell"


def test_every_check_and_hidden_test_belongs_to_an_exercise(nb):
    answers = [i for i, c in enumerate(nb.cells) if _kind(c) == "answer"]
    first = answers[0] if answers else len(nb.cells)
    orphans = [i for i, c in enumerate(nb.cells[:first]) if _kind(c) in ("check", "hidden-test")]
    assert not orphans, f"cells {orphans} are check/hidden-test cells before any answer cell"


@functools.cache
def _checker_names():
    """Every public name that the modules of so3lib.exercises define."""
    import pkgutil

    import so3lib.exercises as ex
    names = set()
    for info in pkgutil.iter_modules(ex.__path__):
        module = importlib.import_module(f"so3lib.exercises.{info.name}")
        names |= {n for n, v in vars(module).items()
                  if not n.startswith("_") and getattr(v, "__module__", None) == module.__name__}
    return names


def test_hidden_tests_are_silent_and_independent_of_the_checkers(nb):
    for i, c in enumerate(nb.cells):
        if _kind(c) != "hidden-test":
            continue
        assert c.cell_type == "code"
        assert "so3lib.exercises" not in c.source, f"hidden test {i} must not use the checkers"
        used = _checker_names() & set(re.findall(r"[A-Za-z_]\w*", c.source))
        assert not used, f"hidden test {i} calls a checker ({', '.join(sorted(used))})"
        assert "assert" in c.source, f"hidden test {i} asserts nothing"
        printed = c.get("outputs", [])
        assert not printed, f"hidden test {i} prints; it should be silent when the answer is right"


def test_every_figure_has_alt_text(nb):
    missing = []
    for i, c in enumerate(nb.cells):
        if c.cell_type != "code":
            continue
        has_image = any("image/png" in o.get("data", {}) or "image/svg+xml" in o.get("data", {})
                        for o in c.get("outputs", []))
        alt = c.metadata.get("mystnb", {}).get("image", {}).get("alt", "")
        if has_image and len(alt.split()) < 5:
            missing.append(i)
    assert not missing, f"figure cells {missing} need alt text (metadata.mystnb.image.alt)"


@pytest.mark.parametrize("path", NOTEBOOKS, ids=IDS)
def test_notebook_file_stays_small(path):
    size = path.stat().st_size
    assert size < 1.5e6, f"{path.name} is {size / 1e6:.2f} MB; keep each notebook under 1.5 MB"


def _has_picture(cell):
    return any(kind in o.get("data", {}) for o in cell.get("outputs", [])
               for kind in ("image/png", "image/svg+xml", "application/vnd.plotly.v1+json"))


def test_a_picture_every_dozen_cells(nb):
    """style.md: a learner meets a picture every few cells, never more than 12 without one.
    Speaker notes and cells for the lecture only (collapsed in JupyterLab, in no reading
    edition) are not cells a learner reads, so they do not count."""
    from tools import roles
    runs, start, count = [], 0, 0
    for i, cell in enumerate(list(nb.cells) + [None]):
        if cell is not None and (roles.has(cell, "notes") or roles.for_lecture_only(cell)):
            continue
        if cell is None or _has_picture(cell):
            if count > 12:
                runs.append(f"cells {start}-{i - 1}")
            start, count = i + 1, 0
        else:
            count += 1
    assert not runs, f"runs of more than 12 cells without a picture: {', '.join(runs)}"


# --- What a learner sees: a textbook, not a test log (README, "One source, three editions")

CHECK_LINE = re.compile(r"(:\s*ok|\bFAILS)\s*$")
CHECKS_SHOWN_MAX = 8
FIGURE_PX_MIN = 700


def _collapsed(cell):
    return (_kind(cell) in HIDDEN or "verify" in _tags(cell)
            or cell.metadata.get("jupyter", {}).get("outputs_hidden"))


def _printed_lines(cell):
    for o in cell.get("outputs", []):
        text = o.get("text") if o.get("output_type") == "stream" else o.get("data", {}).get("text/plain")
        if text and o.get("output_type") != "error":
            yield from (text if isinstance(text, str) else "".join(text)).splitlines()


def shown_check_lines(nb):
    """The printed check lines ('...: within 8 eps: ok', '...: FAILS') of the cells a learner
    sees: those not collapsed in JupyterLab (speaker notes, solutions, hidden tests and
    `verify` cells are) and so not in the book either."""
    return [(i, line) for i, c in enumerate(nb.cells)
            if c.cell_type == "code" and not _collapsed(c)
            for line in _printed_lines(c) if CHECK_LINE.search(line)]


def test_at_most_eight_check_lines_in_sight(nb):
    shown = shown_check_lines(nb)
    assert len(shown) <= CHECKS_SHOWN_MAX, (
        f"{len(shown)} check lines in sight (at most {CHECKS_SHOWN_MAX}): keep those whose number "
        "is the lesson, move the others into a collapsed `verify` cell or tests/, drop those "
        "that cannot fail; " + "; ".join(f"cell {i}: {line.strip()[:60]}" for i, line in shown))


def test_verify_cells_are_collapsed_and_out_of_the_decks(nb):
    wrong = [i for i, c in enumerate(nb.cells) if "verify" in _tags(c) and (
        c.cell_type != "code" or _slide_type(c) not in ("skip", "-")
        or not c.metadata.get("jupyter", {}).get("source_hidden")
        or not c.metadata.get("jupyter", {}).get("outputs_hidden"))]
    assert not wrong, (f"verify cells {wrong}: code cells with slide_type skip and "
                       "jupyter.source_hidden and jupyter.outputs_hidden true")


def _defined(tree):
    names = set()
    for node in tree.body:
        if isinstance(node, (ast.FunctionDef, ast.ClassDef)):
            names.add(node.name)
        elif isinstance(node, (ast.Import, ast.ImportFrom)):
            names |= {(a.asname or a.name).split(".")[0] for a in node.names}
        else:
            for sub in ast.walk(node):
                if isinstance(sub, ast.Name) and isinstance(sub.ctx, ast.Store):
                    names.add(sub.id)
    return names


def _parse(cell):
    source = "\n".join(line for line in cell.source.splitlines()
                       if not line.lstrip().startswith(("%", "!")))
    try:
        return ast.parse(source)
    except SyntaxError:
        return ast.parse("")


def test_nothing_depends_on_a_verify_cell(nb):
    """The book, the decks and the coursework leave `verify` cells out, so a name they
    define must not be needed by a cell that those editions keep."""
    only_verify = set()
    code = [(i, c) for i, c in enumerate(nb.cells) if c.cell_type == "code"]
    for i, c in code:
        if "verify" in _tags(c):
            only_verify |= _defined(_parse(c))
    for i, c in code:
        if "verify" not in _tags(c):
            only_verify -= _defined(_parse(c))
    needed = []
    for i, c in code:
        if "verify" in _tags(c):
            continue
        used = {n.id for n in ast.walk(_parse(c)) if isinstance(n, ast.Name)} & only_verify
        needed += [f"cell {i} uses {n}" for n in sorted(used)]
    assert not needed, "names defined only in verify cells: " + "; ".join(needed)


def _png_width(b64):
    import base64
    import struct
    head = base64.b64decode(b64[:64] if isinstance(b64, str) else "".join(b64)[:64])
    return struct.unpack(">I", head[16:20])[0]


def test_figures_are_drawn_at_the_course_size(nb):
    """so3lib.plot.use_course_style() draws 10 x 5 inches at 100 dpi (1000 px): nothing a
    learner or a hall reads is narrower than 700 px."""
    small = []
    for i, c in enumerate(nb.cells):
        for o in c.get("outputs", []) if c.cell_type == "code" else []:
            png = o.get("data", {}).get("image/png")
            if png and _png_width(png) < FIGURE_PX_MIN:
                small.append(f"cell {i}: {_png_width(png)} px")
    assert not small, f"figures under {FIGURE_PX_MIN} px wide: {', '.join(small)}"


def test_figure_code_starts_collapsed(nb):
    """A `hide-input` cell's code is not the point: JupyterLab shows it folded, as the book
    does, so that a learner reads the figure, not 10 to 40 lines of plotting."""
    open_cells = [i for i, c in enumerate(nb.cells) if "hide-input" in _tags(c)
                  and not c.metadata.get("jupyter", {}).get("source_hidden")]
    assert not open_cells, f"hide-input cells {open_cells} should carry jupyter.source_hidden: true"
