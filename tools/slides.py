"""`make slides`: a reveal.js deck per notebook, in build/slides/, that presents offline.

Each cell's slideshow metadata decides where it goes: "slide" starts a new slide,
"subslide" a new slide below it (down arrow), "fragment" appears on the next key press,
"skip" leaves the cell out, "notes" goes to the speaker view (press S), "-" continues
the current slide. A code cell tagged "hide-input" shows only its output (a figure
without the code that draws it). reveal.js, MathJax, jQuery and require.js are unpacked into
build/slides/vendor/ from the npm registry (tools/vendor.py), so the decks load nothing
from the network: copy the whole build/slides/ folder to the lecture-hall machine and
open NN_name.slides.html in a browser.

Usage: python -m tools.slides [--out DIR] [NOTEBOOK ...]
"""

import argparse
import sys
from pathlib import Path

from nbconvert.exporters import SlidesExporter
from traitlets.config import Config

from tools import vendor
from tools.common import (BUILD, TEMPLATES, Stamps, copy_assets, course_notebooks, read, relink,
                          tooling_key, write_atomic)

VENDOR_DIR = "vendor"


def exporter():
    c = Config()
    c.SlidesExporter.reveal_url_prefix = f"{VENDOR_DIR}/{vendor.REVEAL_PREFIX}"
    c.SlidesExporter.mathjax_url = f"{VENDOR_DIR}/{vendor.MATHJAX_JS}"
    c.SlidesExporter.require_js_url = f"{VENDOR_DIR}/{vendor.REQUIRE_JS}"
    c.SlidesExporter.jquery_url = f"{VENDOR_DIR}/{vendor.JQUERY_JS}"
    c.SlidesExporter.reveal_theme = "white"
    c.SlidesExporter.reveal_transition = "none"  # crisp on a projector
    c.SlidesExporter.reveal_number = "c/t"
    c.SlidesExporter.reveal_scroll = True
    c.SlidesExporter.reveal_width = "1280"
    c.SlidesExporter.reveal_height = "800"
    c.SlidesExporter.exclude_input_prompt = True
    c.SlidesExporter.exclude_output_prompt = True
    # A cell tagged "hide-input" shows only its output on the slide (a figure without the
    # plotting code); the notebook and the book still show the code.
    c.TagRemovePreprocessor.remove_input_tags = {"hide-input"}
    c.SlidesExporter.extra_template_basedirs = [str(TEMPLATES)]
    c.SlidesExporter.extra_template_paths = [str(TEMPLATES)]  # for course_mathjax.html.j2
    c.SlidesExporter.template_name = "course_slides"
    return SlidesExporter(config=c)


def build(out=BUILD / "slides", notebooks=None):
    """Write OUT/NN_name.slides.html for each notebook and the assets; returns the paths."""
    out = Path(out)
    out.mkdir(parents=True, exist_ok=True)
    vendor.install(out / VENDOR_DIR, ["reveal.js", "mathjax", "jquery", "requirejs"])
    copy_assets(out)
    exp, stamps, tooling = exporter(), Stamps(out), tooling_key()
    written = []
    for path in notebooks or course_notebooks():
        path = Path(path)
        target = out / f"{path.stem}.slides.html"
        key = stamps.key(tooling, path.read_bytes())
        if not stamps.fresh(target.name, key):  # unchanged since the last build: keep it
            body, _ = exp.from_notebook_node(read(path), resources={"metadata": {"name": path.stem}})
            write_atomic(target, relink(body, ".slides.html"))
            stamps.record(target.name, key)
        written.append(target)
    for old in set(out.glob("*.slides.html")) - set(written):  # a notebook renamed or removed
        old.unlink()
    stamps.save()
    return written


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--out", type=Path, default=BUILD / "slides")
    parser.add_argument("notebooks", nargs="*", type=Path)
    args = parser.parse_args(argv)
    for target in build(args.out, args.notebooks or None):
        print(target.relative_to(Path.cwd()) if target.is_relative_to(Path.cwd()) else target)


if __name__ == "__main__":
    sys.exit(main())
