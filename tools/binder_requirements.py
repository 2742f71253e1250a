"""binder/requirements.txt: what a learner's image needs, with environment.txt's own pins.

environment.txt pins everything the course uses, the tests and the build tools included
(pytest, nbval, playwright, Jupyter Book and Sphinx, ruff...). A Binder or JupyterHub
image (repo2docker reads binder/) needs only what the notebooks and JupyterLab need. This
script writes that subset into binder/requirements.txt: the packages named in LEARNER
below and everything they require (read from the installed packages' metadata, for
Linux and the Python of binder/runtime.txt), each at the version environment.txt pins,
plus the image's own extras (IMAGE_ONLY, pinned here). It refuses a requirement that
environment.txt does not pin. tests/test_binder.py fails when the file is not what this
script writes, so the two lists cannot drift apart.

Usage: .venv/bin/python -m tools.binder_requirements [--check]
"""

import argparse
import re
import sys
from importlib import metadata
from pathlib import Path

from packaging.markers import default_environment
from packaging.requirements import Requirement
from packaging.utils import canonicalize_name

ROOT = Path(__file__).resolve().parent.parent
ENVIRONMENT = ROOT / "environment.txt"
BINDER = ROOT / "binder"
REQUIREMENTS = BINDER / "requirements.txt"
RUNTIME = BINDER / "runtime.txt"

# What the notebooks import, the kernel and JupyterLab they run in, and nbgrader for a hub
# whose students fetch and submit coursework through nbgrader's exchange (binder/postBuild
# turns its instructor tools off).
LEARNER = ["numpy", "scipy", "sympy", "mpmath", "matplotlib", "plotly",
           "jupyterlab", "ipykernel", "nbconvert", "nbclient", "nbformat", "nbgrader"]
# Not in environment.txt (no use outside an image): nbgitpuller, which pulls a course
# repository into a student's persistent home on a JupyterHub.
IMAGE_ONLY = {"nbgitpuller": "1.3.0"}
# Come with Python's own environment (a venv, repo2docker's), unpinned in environment.txt
# too: nbgrader asks for setuptools.
PROVIDED = {"pip", "setuptools", "wheel"}

HEADER = """\
# Written by `.venv/bin/python -m tools.binder_requirements` from ../environment.txt:
# do not edit; change environment.txt (or LEARNER in that script) and run it again.
# What repo2docker installs for Binder and JupyterHub images: the notebooks' packages,
# JupyterLab, nbgrader and nbgitpuller, at environment.txt's pins, without the tests'
# and build tools' (pytest, nbval, playwright, Jupyter Book, ruff). so3lib itself is
# installed by postBuild.
"""


def pins(path=ENVIRONMENT):
    """canonical name -> (name as written, version) for every `name==version` line."""
    out = {}
    for line in Path(path).read_text().splitlines():
        line = line.split("#", 1)[0].strip()
        m = re.fullmatch(r"([A-Za-z0-9_.\-]+)\s*==\s*([^\s;]+)", line)
        if m:
            out[canonicalize_name(m.group(1))] = (m.group(1), m.group(2))
    return out


def image_environment(runtime=RUNTIME):
    """Marker environment of the image: Linux, x86_64, the Python of runtime.txt."""
    env = default_environment()
    version = Path(runtime).read_text().strip().removeprefix("python-")
    env.update(python_version=version, python_full_version=version + ".0",
               sys_platform="linux", platform_system="Linux", os_name="posix",
               platform_machine="x86_64", implementation_name="cpython",
               platform_python_implementation="CPython")
    return env


def closure(names, env, pinned):
    """Every distribution NAMES need, with the extras asked for, read from the metadata of
    the installed distributions (which must be those environment.txt pins)."""
    todo = [(canonicalize_name(n), frozenset()) for n in names]
    seen = {}
    while todo:
        name, extras = todo.pop()
        if name in PROVIDED or (name in seen and extras <= seen[name]):
            continue
        seen[name] = seen.get(name, frozenset()) | extras
        if name not in pinned:
            raise SystemExit(f"{name} is needed by the learner's image but environment.txt "
                             "does not pin it")
        try:
            dist = metadata.distribution(name)
        except metadata.PackageNotFoundError:
            raise SystemExit(f"{name} is not installed here: run this script with the "
                             "course's .venv (`make test-lib` builds it)") from None
        if dist.version != pinned[name][1]:
            raise SystemExit(f"{name} {dist.version} is installed, environment.txt pins "
                             f"{pinned[name][1]}: rebuild .venv first")
        for text in dist.requires or []:
            req = Requirement(text)
            wanted = [""] + sorted(seen[name])
            if req.marker is None or any(req.marker.evaluate({**env, "extra": e}) for e in wanted):
                todo.append((canonicalize_name(req.name), frozenset(req.extras)))
    return set(seen)


def render():
    pinned = pins()
    names = closure(LEARNER, image_environment(), pinned)
    lines = [f"{pinned[n][0]}=={pinned[n][1]}" for n in sorted(names)]
    lines += [f"{name}=={version}" for name, version in sorted(IMAGE_ONLY.items())]
    return HEADER + "\n".join(lines) + "\n"


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--check", action="store_true",
                        help="only say whether binder/requirements.txt is up to date")
    args = parser.parse_args(argv)
    text = render()
    if args.check:
        if REQUIREMENTS.read_text() != text:
            raise SystemExit("binder/requirements.txt is out of date: run "
                             ".venv/bin/python -m tools.binder_requirements")
        print("binder/requirements.txt is up to date")
        return
    REQUIREMENTS.write_text(text)
    print(f"wrote {REQUIREMENTS.relative_to(ROOT)} ({text.count(chr(10)) - HEADER.count(chr(10))} packages)")


if __name__ == "__main__":
    sys.exit(main())
