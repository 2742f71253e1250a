"""What each edition of the course does with each kind of cell: the README's table "One
source, three editions" in code. Every builder reads it (tools/slides.py for the decks,
tools/student.py for the student edition; tools/book.py and tools/assignments.py spell the
same roles for the book and the coursework), so a new kind of cell is one entry of ROLES.

A cell's role comes from its metadata: a tag (`solution`, `lecture`, ...) or its
`slideshow.slide_type` (`skip`, `notes`). An edition does one of a few things with it:
shows it (SHOW), collapses it (COLLAPSE), leaves it out (DROP), puts it in the speaker
view (NOTES), shows only its output (OUTPUT), or something of its own (SPECIAL: the
coursework's answer and test cells, the student edition's "your turn" cell, the book's
"show solution" block). Each cell of the table also has its words for the README.

`python -m tools.roles` prints the table's rows as they stand in the README; the tests
hold the README to them (tests/test_student_edition.py).
"""

import sys
from dataclasses import dataclass, field

# The editions, in the README's order: the notebook in JupyterLab, the book (and the course
# PDF printed from it), the deck (and its handout), the nbgrader coursework, the student
# edition. The deck with the worked solutions (`make slides-solutions`) is the deck but for
# the cells whose role says otherwise (Role.solutions_deck).
NOTEBOOK, BOOK, DECK, COURSEWORK, STUDENT = "notebook", "book", "deck", "coursework", "student"
EDITIONS = (NOTEBOOK, BOOK, DECK, COURSEWORK, STUDENT)
DECK_SOLUTIONS = "deck-solutions"
HEADERS = {NOTEBOOK: "notebook (JupyterLab)", BOOK: "book", DECK: "deck",
           COURSEWORK: "coursework", STUDENT: "student edition"}

SHOW, COLLAPSE, DROP, NOTES, OUTPUT, SPECIAL = "show", "collapse", "drop", "notes", "output", "special"


@dataclass(frozen=True)
class Role:
    name: str                      # short name, used by the builders
    what: str                      # the README's first column
    mark: str                      # the README's "marked with"
    does: dict                     # edition -> (action, the README's words)
    tag: str = None                # the tag that gives the role, or
    slide_type: str = None         # the slide type that gives it
    solutions_deck: tuple = None   # (action, words) in the deck with the worked solutions
    notes: str = field(default="", compare=False)

    def applies(self, cell):
        if self.tag is not None:
            return self.tag in cell.get("metadata", {}).get("tags", [])
        if self.slide_type is not None:
            return cell.get("metadata", {}).get("slideshow", {}).get("slide_type") == self.slide_type
        return False  # a row of the table that no builder acts on (e.g. alt text)

    def action(self, edition):
        if edition == DECK_SOLUTIONS:
            return (self.solutions_deck or self.does[DECK])[0]
        return self.does[edition][0]


def _r(name, what, mark, notebook, book, deck, coursework, student, **kw):
    return Role(name, what, mark, {NOTEBOOK: notebook, BOOK: book, DECK: deck,
                                   COURSEWORK: coursework, STUDENT: student}, **kw)


_SHOWN = (SHOW, "shown")
_COLLAPSED = (COLLAPSE, "collapsed")
_LEFT_OUT = (DROP, "left out")

ROLES = (
    _r("slide", "starts a slide",
       "`slideshow.slide_type` `slide` or `subslide`; first line a `##`/`###` headline",
       _SHOWN, _SHOWN, (SHOW, "a slide"), _SHOWN, _SHOWN),
    _r("skip", "detail for self-study", "`slide_type` `skip`",
       _SHOWN, _SHOWN, _LEFT_OUT, _SHOWN, _SHOWN, slide_type="skip"),
    _r("notes", "speaker notes: cues, the minute into the lecture (`[12 min]` first), the "
       "answers to the hall's questions and the exercises",
       "`slide_type` `notes`, and `jupyter.source_hidden: true`",
       _COLLAPSED, _LEFT_OUT, (NOTES, "speaker view"), _LEFT_OUT, _LEFT_OUT, slide_type="notes"),
    _r("lecture", "for the lecture only: a roadmap, a recap of the last lecture, a homework "
       "slide, the answer to a question (on the next fragment)",
       "tag `lecture`, and `jupyter.source_hidden: true`",
       _COLLAPSED, _LEFT_OUT, (SHOW, "shown"), _LEFT_OUT, _LEFT_OUT, tag="lecture"),
    _r("question", "a question to the hall (predict or vote), its answer in the next cell "
       "(tag `lecture`, `slide_type` `fragment`) and in the notes",
       "tag `question`, and `jupyter.source_hidden: true`",
       _COLLAPSED, _LEFT_OUT, (SHOW, "shown, counted by the deck report"), _LEFT_OUT,
       _LEFT_OUT, tag="question"),
    _r("notebook-only", "for reading only: what the lecture says otherwise (an equation "
       "table, a summary of errata codes)", "tag `notebook-only`",
       _SHOWN, _SHOWN, _LEFT_OUT, _SHOWN, _SHOWN, tag="notebook-only"),
    _r("hide-input", "figure whose code is not the point",
       "tag `hide-input`, and `jupyter.source_hidden: true`",
       (SHOW, "code collapsed"), (SHOW, "code collapsed"), (OUTPUT, "figure only"), _SHOWN, _SHOWN,
       tag="hide-input"),
    _r("alt", "figure's alt text", "`metadata.mystnb.image.alt` on the code cell",
       (SHOW, ""), (SHOW, "`alt`"), (SHOW, "`alt`"), (SHOW, ""), (SHOW, "")),
    _r("turn", "a 3-D figure to turn",
       "`so3lib.plot.show_3d(fig, name, alt)` (the same alt text in the metadata), tag "
       "`hide-input`, a `subslide` of its own",
       (SHOW, "turns (plotly, no kernel)"), (SHOW, "turns"),
       (SHOW, "turns; the handout prints a still of it"), _SHOWN, (SHOW, "turns")),
    _r("answer", "the stub the learner edits", "tag `answer`",
       _SHOWN, _SHOWN, _LEFT_OUT, (SPECIAL, "nbgrader answer cell"), _SHOWN, tag="answer"),
    _r("check", "the self-study checker call", "tags `check` and `points-N`",
       _SHOWN, _SHOWN, _LEFT_OUT, (SPECIAL, "autograded test cell worth N points"), _SHOWN,
       tag="check"),
    _r("written", "an exercise's written part (a proof on paper, a prediction), graded by hand",
       "tags `written` and `points-N` on the task's markdown cell",
       _SHOWN, _SHOWN, _SHOWN,
       (SPECIAL, "followed by a manually graded answer cell worth N points (formgrader)"),
       _SHOWN, tag="written"),
    _r("solution", "worked solution (markdown and code)",
       "tag `solution`, and `jupyter.source_hidden: true`",
       _COLLAPSED, (SPECIAL, '"show solution"'),
       (DROP, "left out (`make slides-solutions` keeps it)"),
       (SPECIAL, "the answer key, then removed"),
       (SPECIAL, 'one "your turn" cell per run of them'), tag="solution",
       solutions_deck=(SHOW, "shown")),
    _r("hidden-test", "grading asserts", "tag `hidden-test`, and `jupyter.source_hidden: true`",
       _COLLAPSED, _LEFT_OUT, _LEFT_OUT, (SPECIAL, "hidden tests of the test cell"),
       (SPECIAL, 'in the "your turn" cell\'s place'), tag="hidden-test"),
    _r("verify", "checks the text rests on (not the number that teaches)",
       "tag `verify`, `slide_type` `skip`, `jupyter.source_hidden` and `outputs_hidden: "
       "true`; defines nothing other cells use",
       (COLLAPSE, "collapsed, run by strict nbval"), _LEFT_OUT, _LEFT_OUT, _LEFT_OUT,
       _COLLAPSED, tag="verify"),
)
BY_NAME = {r.name: r for r in ROLES}


def roles_of(cell):
    """The roles a cell has (a cell may have several: `solution` and `notes`...)."""
    return [r for r in ROLES if r.applies(cell)]


def actions(cell, edition):
    """What EDITION does with CELL: the set of its roles' actions (empty: shown as it is)."""
    return {r.action(edition) for r in roles_of(cell)}


def left_out(cell, edition):
    """Whether EDITION leaves CELL out (any of its roles says so)."""
    return DROP in actions(cell, edition)


def has(cell, name):
    """Whether CELL has the role NAME ("solution", "lecture", ...)."""
    return BY_NAME[name].applies(cell)


def tags_left_out(edition):
    """The tags whose cells EDITION leaves out (for nbconvert's TagRemovePreprocessor)."""
    return {r.tag for r in ROLES if r.tag and r.action(edition) == DROP}


def for_lecture_only(cell):
    """A cell that is in the deck and in no reading edition (a roadmap, a question...)."""
    return not left_out(cell, DECK) and left_out(cell, BOOK) and left_out(cell, STUDENT) \
        and not has(cell, "notes")


def table():
    """The README's table "One source, three editions", as markdown lines."""
    head = "| cell | marked with | " + " | ".join(HEADERS[e] for e in EDITIONS) + " |"
    lines = [head, "|" + "---|" * (len(EDITIONS) + 2)]
    for r in ROLES:
        lines.append(f"| {r.what} | {r.mark} | " + " | ".join(r.does[e][1] for e in EDITIONS)
                     + " |")
    return lines


def lecture_faults(nb):
    """Where a notebook's lecture cells break the convention: a question to the hall whose
    next cell is not its answer (tag `lecture`, slide type `fragment`), a lecture-only cell
    without `jupyter.source_hidden` (it would stand open in JupyterLab)."""
    faults = []
    cells = nb["cells"]
    for k, cell in enumerate(cells):
        where = f"cell {k} ({cell.get('id', '?')})"
        if has(cell, "question"):
            nxt = cells[k + 1] if k + 1 < len(cells) else None
            if nxt is None or not has(nxt, "lecture") or \
                    nxt.get("metadata", {}).get("slideshow", {}).get("slide_type") != "fragment":
                faults.append(f"{where}: a question whose next cell is not its answer "
                              "(tag lecture, slide_type fragment)")
        if (has(cell, "question") or has(cell, "lecture")) and \
                not cell.get("metadata", {}).get("jupyter", {}).get("source_hidden"):
            faults.append(f"{where}: a lecture-only cell without jupyter.source_hidden: true")
    return faults


if __name__ == "__main__":
    print("\n".join(table()))
    sys.exit(0)
