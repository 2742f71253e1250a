"""What the build scripts share: where things are, and which notebooks make the course."""

import hashlib
import json
import os
import re
from pathlib import Path

import nbformat

ROOT = Path(__file__).resolve().parent.parent
NOTEBOOKS = ROOT / "notebooks"
BUILD = ROOT / "build"
TEMPLATES = Path(__file__).resolve().parent / "templates"

_NAME = re.compile(r"^[0-9A-Z][0-9]_[A-Za-z0-9_]+\.ipynb$")


def course_notebooks(directory=NOTEBOOKS):
    """The course's notebooks in reading order: 00, 01, ..., then the appendices A1, ..."""
    paths = [p for p in Path(directory).glob("*.ipynb") if _NAME.match(p.name)]
    return sorted(paths, key=lambda p: (p.name[0].isalpha(), p.name))


def read(path):
    return nbformat.read(str(path), as_version=4)


def title(nb, path):
    """The notebook's title: its first '# ' heading, else its file name."""
    for cell in nb.cells:
        if cell.cell_type == "markdown":
            for line in cell.source.splitlines():
                if line.startswith("# "):
                    return line[2:].strip()
    return Path(path).stem


def inside(path, directory):
    """True when PATH is DIRECTORY or lies under it (after resolving links)."""
    path, directory = Path(path).resolve(), Path(directory).resolve()
    return path == directory or directory in path.parents


def build_target(out, what):
    """OUT resolved, after refusing a folder that would overwrite the course's notebooks or
    scatter WHAT (e.g. "the student edition") through the course folder outside build/."""
    out = Path(out).resolve()
    if inside(NOTEBOOKS, out) or inside(out, NOTEBOOKS):
        raise SystemExit(f"refusing to write {what} into or over {NOTEBOOKS}")
    if inside(out, ROOT) and not inside(out, BUILD):
        raise SystemExit(f"{what} goes under {BUILD}, or outside the course folder")
    return out


_NB_LINK = re.compile(r'href="([0-9A-Z][0-9]_[A-Za-z0-9_]+)\.ipynb(#[^"]*)?"')


def relink(html, suffix):
    """Point links between notebooks (href="01_x.ipynb#a") at their rendered pages (01_x<suffix>#a)."""
    return _NB_LINK.sub(lambda m: f'href="{m.group(1)}{suffix}{m.group(2) or ""}"', html)


def label(nb, path):
    """A short name for menus: '01 The hat map and the Lemma', '00 Start here'."""
    prefix = Path(path).name[:2]
    text = nb.metadata.get("title") or title(nb, path)
    return text if text.startswith(prefix) else f"{prefix} {text}"


def _digest(*parts):
    h = hashlib.sha256()
    for part in parts:
        h.update(part if isinstance(part, bytes) else str(part).encode())
        h.update(b"\0")
    return h.hexdigest()


def tooling_key():
    """A digest of everything besides the notebooks that shapes the output: the build
    scripts and templates, and the nbconvert that renders."""
    import nbconvert
    here = Path(__file__).resolve().parent
    files = sorted(p for p in here.rglob("*") if p.is_file() and "__pycache__" not in p.parts)
    return _digest(nbconvert.__version__, *(f"{p.relative_to(here)}" for p in files),
                   *(p.read_bytes() for p in files))


class Stamps:
    """Which outputs in a folder are up to date: a JSON file of output name -> input digest.
    A build skips an output whose digest is unchanged and whose file still exists."""

    def __init__(self, folder):
        self.folder = Path(folder)
        self.path = self.folder / ".build-stamps.json"
        try:
            self.stamps = json.loads(self.path.read_text())
        except (OSError, ValueError):
            self.stamps = {}

    def key(self, *parts):
        return _digest(*parts)

    def fresh(self, name, key):
        return self.stamps.get(name) == key and (self.folder / name).exists()

    def record(self, name, key):
        self.stamps[name] = key

    def save(self):
        tmp = self.path.with_suffix(".tmp")
        tmp.write_text(json.dumps(self.stamps, indent=1, sort_keys=True))
        os.replace(tmp, self.path)


def write_atomic(path, text):
    """Write a file so that a reader never sees it half written."""
    path = Path(path)
    tmp = path.with_name(f".{path.name}.{os.getpid()}.tmp")
    tmp.write_text(text, encoding="utf-8")
    os.replace(tmp, path)


def copy_assets(out):
    """Copy the notebooks' own pictures (notebooks/images/) next to the rendered pages, so
    that a markdown image link like images/x.png works there too."""
    import shutil
    src = NOTEBOOKS / "images"
    if src.is_dir():
        shutil.copytree(src, Path(out) / "images", dirs_exist_ok=True)
