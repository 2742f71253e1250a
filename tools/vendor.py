"""The JavaScript that slides and book load, fetched from the npm registry at build time.

Slides and book must work in a lecture hall with no network, so everything they load sits
next to the HTML. Each package is fetched once with `npm pack NAME@VERSION` into a cache
(build/npm/), checked against the sha512 integrity pinned below, and only the files a page
needs are unpacked next to it. The browser never fetches anything.
"""

import base64
import hashlib
import json
import os
import shutil
import subprocess
import tarfile
import tempfile
from fnmatch import fnmatch
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
CACHE = ROOT / "build" / "npm"

# name: (version, npm integrity of the tarball). To upgrade: change both (`npm view
# NAME@VERSION dist.integrity`), run `make slides book`, then `make test`.
PACKAGES = {
    "reveal.js": ("6.0.2", "sha512-JYIg5D9aoxoaLeb84O+OvAwsKWdIavVgEDScxtYEXFCT6t6TQrhNtSgogcjdCpdLsWglhJn3zyE3fUOwiH5KEg=="),
    "mathjax": ("2.7.7", "sha512-OOl0B2/0tSJAtAZarXnQuLDBLgTNRqiI9VqHTQzPsxf4okT2iIpDrvaklK9x2QEMD1sDj4yRn11Ygci41DxMAQ=="),
    "jquery": ("3.7.1", "sha512-m4avr8yL8kmFN8psrbFFFmB/If14iN5o9nw/NgnnM+kybDJpRsAynV2BsfpTYrTRysYUdADVD7CkUUizgkpLfg=="),
    "requirejs": ("2.3.7", "sha512-DouTG8T1WanGok6Qjg2SXuCMzszOo0eHeH9hDZ5Y4x8Je+9JB38HdTLT4/VA8OaUhBa0JPVHJ0pyBkM1z+pDsw=="),
    # The book (Jupyter Book / Sphinx) needs MathJax 3; an npm alias lets it sit beside 2.7.7.
    "mathjax3": ("npm:mathjax@3.2.2", "sha512-Bt+SSVU8eBG27zChVewOicYs7Xsdt40qm4+UpHyX7k0/O9NliPc+x77k1/FEsPsjKPZGJvtRZM1vO+geW0OhGw=="),
    # Accessibility checks of the book in the tests (injected into each page, offline).
    "axe-core": ("4.14.1", "sha512-FHfa+lmNjQZfJz1q8wKqIDwC6DExcHt/pkjNQb09a3NPjCKg2rhu5qb2S4r76ASyFNNtuFooJpZe37OgudVGtQ=="),
}

# The files each page needs, as glob patterns inside the package. MathJax is trimmed to
# the TeX input, the CommonHTML output and its web fonts (about 4 MB instead of 70 MB).
FILES = {
    "reveal.js": ["LICENSE", "dist/reveal.js", "dist/reveal.css", "dist/theme/white.css",
                  "dist/plugin/notes.js"],
    "mathjax": [
        "LICENSE", "MathJax.js", "config/TeX-AMS_CHTML-full.js", "config/Safe.js",
        "extensions/*", "jax/input/TeX/*", "jax/element/*", "jax/output/CommonHTML/*",
        "fonts/HTML-CSS/TeX/woff/*",
    ],
    "jquery": ["LICENSE.txt", "dist/jquery.min.js"],
    "requirejs": ["README.md", "require.js"],
    # MathJax 3 as one file with every TeX extension built in, its fonts, menu and a11y.
    "mathjax3": ["LICENSE", "es5/tex-chtml-full.js", "es5/output/chtml/fonts/woff-v2/*",
                 "es5/a11y/*", "es5/ui/*",
                 "es5/tex-svg-full.js"],  # the decks
    "axe-core": ["LICENSE", "axe.min.js"],
}

# What a page's <script> and <link> point at, relative to the directory the assets go in.
MATHJAX_JS = "mathjax/MathJax.js?config=TeX-AMS_CHTML-full,Safe"
REQUIRE_JS = "requirejs/require.js"
JQUERY_JS = "jquery/dist/jquery.min.js"
REVEAL_PREFIX = "reveal.js"
# the decks: MathJax 3 SVG output, whose formulas draw without the page's style sheet
# (so that the speaker view shows each once)
MATHJAX3_SVG_JS = "mathjax3/es5/tex-svg-full.js"


def _sri(path):
    digest = hashlib.sha512(Path(path).read_bytes()).digest()
    return "sha512-" + base64.b64encode(digest).decode()


def tarball(name):
    """Path of NAME's tarball in the cache, fetched with `npm pack` if it is not there yet."""
    version, integrity = PACKAGES[name]
    CACHE.mkdir(parents=True, exist_ok=True)
    target = CACHE / f"{name}-{version}.tgz"
    if target.exists() and _sri(target) == integrity:
        return target
    npm = shutil.which("npm")
    if npm is None:
        raise SystemExit("npm (Node.js) is needed once, to fetch reveal.js and MathJax from "
                         "the npm registry: install Node.js, or copy build/npm/ from a "
                         "machine that has built the slides.")
    # Fetch into a private directory and move into place: two builds running at once
    # (two test workers) never see a half-written tarball.
    with tempfile.TemporaryDirectory(dir=CACHE) as tmp:
        out = subprocess.run([npm, "pack", f"{name}@{version}", "--json", "--silent",
                              "--pack-destination", tmp],
                             capture_output=True, text=True, cwd=tmp)
        if out.returncode != 0:
            raise SystemExit(f"npm pack {name}@{version} failed:\n{out.stderr}")
        filename = json.loads(out.stdout)[0]["filename"]
        got = Path(tmp) / filename
        if _sri(got) != integrity:
            raise SystemExit(f"{name}@{version}: the tarball's sha512 is not the pinned one")
        os.replace(got, target)
    return target


def install(dest, names):
    """Unpack the needed files of each package into DEST/<name>/; returns DEST."""
    dest = Path(dest)
    for name in names:
        patterns = FILES[name]
        pkg_dir = dest / name
        stamp = pkg_dir / ".unpacked"
        wanted = f"{name}@{PACKAGES[name][0]} {PACKAGES[name][1]} {patterns}"
        if stamp.exists() and stamp.read_text() == wanted:
            continue
        if pkg_dir.exists():
            shutil.rmtree(pkg_dir)
        with tarfile.open(tarball(name)) as tar:
            for member in tar.getmembers():
                rel = member.name.removeprefix("package/")
                if not member.isfile() or not any(fnmatch(rel, p) for p in patterns):
                    continue
                out = pkg_dir / rel
                out.parent.mkdir(parents=True, exist_ok=True)
                with tar.extractfile(member) as src, open(out, "wb") as dst:
                    shutil.copyfileobj(src, dst)
        stamp.write_text(wanted)
    return dest


# plotly.js for the figures a learner turns (so3lib.plot.show_3d), taken from the pinned plotly
# Python package (environment.txt) rather than npm: it is the very plotly.js that package writes
# its figures for and that its JupyterLab renderer draws them with, it is on every machine that
# can run the notebooks, and it needs no download. Pinned by its sha512 below, so that a plotly
# upgrade is a deliberate change here (update both, then `make slides book`).
PLOTLY_JS_VERSION = "4.1.1"  # bundled by plotly 7.1.0
PLOTLY_JS_SHA512 = ("sha512-2SAjXeni/1+3u+HXGF7+CYi8nJ5WYF/2cBFcrgIv+4Ie9W5rpoXVnHGAM0tm0HBg+sKD"
                    "j8+CnFEQwCWxA4uqig==")
PLOTLY_JS = "plotly/plotly.min.js"  # relative to the directory the assets go in


def install_plotly(dest):
    """Copy the plotly Python package's plotly.min.js to DEST/plotly/ after checking its
    sha512; returns the path written."""
    from importlib.resources import files

    source = Path(str(files("plotly") / "package_data" / "plotly.min.js"))
    if not source.is_file():
        raise SystemExit("plotly.min.js is not in the plotly package: install the pinned plotly")
    if _sri(source) != PLOTLY_JS_SHA512:
        raise SystemExit(f"{source}: not the pinned plotly.js {PLOTLY_JS_VERSION} (sha512 differs);"
                         " install the plotly of environment.txt or update tools/vendor.py")
    target = Path(dest) / PLOTLY_JS
    if target.is_file() and target.stat().st_size == source.stat().st_size \
            and _sri(target) == PLOTLY_JS_SHA512:
        return target
    target.parent.mkdir(parents=True, exist_ok=True)
    tmp = target.with_name(f".plotly.min.js.{os.getpid()}.tmp")
    shutil.copyfile(source, tmp)
    os.replace(tmp, target)
    return target


if __name__ == "__main__":
    for n in PACKAGES:
        print(tarball(n))
