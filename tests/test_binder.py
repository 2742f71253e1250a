"""binder/: the image repo2docker builds for Binder and JupyterHub, followed without Docker.

repo2docker checks runtime.txt, installs binder/requirements.txt into the image's Python,
copies the repository into the learner's home and runs binder/postBuild there. The slow
test below does the same in a fresh venv, from a clean copy of the repository (the files
git knows), then runs a notebook from another folder, as a student on a JupyterHub whose
persistent home hides the checkout would. The packages come from a wheelhouse in
build/wheelhouse/, filled from PyPI the first time (pip's cache makes that quick), so the
install itself needs no network and takes the time a real one would minus the downloads.
Once it has passed, it is not done again until one of the files the image is made from
changes (tests/pass_record.py; a fresh clone, and CI, always does it).
"""

import json
import os
import re
import shutil
import subprocess
import sys
from pathlib import Path

import pytest
from packaging.utils import canonicalize_name, parse_wheel_filename
from pass_record import PassRecord, digest

ROOT = Path(__file__).resolve().parent.parent
BINDER = ROOT / "binder"
WHEELHOUSE = ROOT / "build" / "wheelhouse"
NOTEBOOK = ROOT / "notebooks" / "00_start_here.ipynb"
# so3lib's build backend (pyproject.toml), which pip fetches for postBuild's install
BUILD_BACKEND = "setuptools>=77"

if str(ROOT) not in sys.path:
    sys.path.insert(0, str(ROOT))


def _skip_or_fail(why):
    if os.environ.get("CI"):
        pytest.fail(why)
    pytest.skip(why)


def _requirements():
    """(canonical name, version) of every pin in binder/requirements.txt."""
    pins = []
    for line in (BINDER / "requirements.txt").read_text().splitlines():
        line = line.split("#", 1)[0].strip()
        if line:
            name, sep, version = line.partition("==")
            assert sep, f"binder/requirements.txt: {line!r} is not pinned with =="
            pins.append((canonicalize_name(name), version.strip()))
    return pins


# --- fast: the learner's list and environment.txt agree ----------------------------------

def test_binder_requirements_are_environment_txt_pins():
    from tools import binder_requirements as br
    environment = br.pins()
    for name, version in _requirements():
        if name in br.IMAGE_ONLY:
            assert version == br.IMAGE_ONLY[name]
            continue
        assert name in environment, f"{name} is in binder/requirements.txt, not in environment.txt"
        assert version == environment[name][1], \
            f"{name}: binder/requirements.txt pins {version}, environment.txt {environment[name][1]}"
    assert (BINDER / "requirements.txt").read_text() == br.render(), (
        "binder/requirements.txt is not what environment.txt gives: run "
        "`.venv/bin/python -m tools.binder_requirements`")


def test_binder_requirements_name_no_file_of_the_repository():
    """No -r ../environment.txt, -e . or path: repo2docker can then install the packages
    before it copies the repository, and an edited notebook does not rebuild them."""
    text = (BINDER / "requirements.txt").read_text()
    lines = [ln.strip() for ln in text.splitlines() if ln.strip() and not ln.startswith("#")]
    assert all(re.fullmatch(r"[A-Za-z0-9_.\-]+==[^\s/]+", ln) for ln in lines), lines
    names = {n for n, _ in _requirements()}
    assert "nbgitpuller" in names
    assert not names & {"pytest", "nbval", "playwright", "jupyter-book", "ruff", "hypothesis"}


# --- slow: repo2docker's steps in a fresh venv -------------------------------------------

def _wheelhouse():
    """build/wheelhouse/ with a wheel for every pin (and the build backend), fetched with pip
    download only when one is missing."""
    WHEELHOUSE.mkdir(parents=True, exist_ok=True)
    have, backend = set(), False
    for whl in WHEELHOUSE.glob("*.whl"):
        name, version, _, _ = parse_wheel_filename(whl.name)
        have.add((name, str(version)))
        backend |= name == "setuptools" and version.major >= 77
    if set(_requirements()) <= have and backend:
        return WHEELHOUSE
    run = subprocess.run([sys.executable, "-m", "pip", "download", "--quiet", "--only-binary=:all:",
                          "--dest", str(WHEELHOUSE), "-r", str(BINDER / "requirements.txt"),
                          BUILD_BACKEND], capture_output=True, text=True)
    if run.returncode != 0:
        _skip_or_fail("could not fetch the image's wheels from PyPI into build/wheelhouse/:\n"
                      + run.stderr[-2000:])
    return WHEELHOUSE


def _clean_checkout(dest):
    """The repository as repo2docker receives it: the files git knows, as they are now."""
    try:
        listed = subprocess.run(["git", "ls-files", "-z", "--cached", "--others", "--exclude-standard"],
                                cwd=ROOT, capture_output=True, check=True).stdout
    except (OSError, subprocess.CalledProcessError) as err:
        _skip_or_fail(f"git cannot list the repository's files: {err}")
    for rel in filter(None, listed.decode().split("\0")):
        src = ROOT / rel
        if src.is_file():
            (dest / rel).parent.mkdir(parents=True, exist_ok=True)
            shutil.copy2(src, dest / rel)
    return dest


def _files(folder):
    return sorted(str(p.relative_to(folder)) for p in folder.rglob("*"))


def _run(cmd, **kw):
    run = subprocess.run(cmd, capture_output=True, text=True, **kw)
    assert run.returncode == 0, f"{' '.join(map(str, cmd))} failed:\n{run.stdout[-3000:]}\n{run.stderr[-3000:]}"
    return run


def test_binder_image_runs_a_notebook_from_another_folder(tmp_path):
    runtime = (BINDER / "runtime.txt").read_text().strip()
    m = re.fullmatch(r"python-(\d+)\.(\d+)", runtime)
    assert m, f"binder/runtime.txt says {runtime!r}; repo2docker reads python-X.Y"
    if sys.version_info[:2] != tuple(map(int, m.groups())):
        _skip_or_fail(f"binder/runtime.txt asks for Python {m[1]}.{m[2]}; this is "
                      f"{sys.version.split()[0]}, so the image cannot be followed here")
    # what the image is made from: binder/, the package and its pins, the notebook it runs
    key = digest([BINDER, ROOT / "pyproject.toml", ROOT / "environment.txt", ROOT / "so3lib",
                  NOTEBOOK, Path(__file__)], ROOT)
    record = PassRecord("binder-image")
    if record.fresh("image", key):
        return
    wheels = _wheelhouse()
    repo = _clean_checkout(tmp_path / "repo")
    before = _files(repo)

    venv, home = tmp_path / "image", tmp_path / "home"
    home.mkdir()
    base = getattr(sys, "_base_executable", None) or sys.executable
    _run([base, "-m", "venv", str(venv)])
    # The image's Python first on PATH; pip offline from the wheelhouse, none of this
    # machine's pip settings; a new user's empty home.
    env = {k: v for k, v in os.environ.items()
           if not k.startswith(("PIP_", "PYTHON", "JUPYTER", "VIRTUAL_ENV", "CONDA"))}
    env.update(PATH=f"{venv / 'bin'}{os.pathsep}{env.get('PATH', '')}", HOME=str(home),
               PIP_CONFIG_FILE=os.devnull, PIP_NO_INDEX="1", PIP_FIND_LINKS=str(wheels),
               PIP_DISABLE_PIP_VERSION_CHECK="1")
    # repo2docker: pip install -r binder/requirements.txt from the repository's root
    # (--no-compile: byte-compiling some 20 000 files proves nothing about the image)
    _run([venv / "bin" / "python", "-m", "pip", "install", "--quiet", "--no-compile",
          "-r", "binder/requirements.txt"], cwd=repo, env=env)
    _run(["bash", "binder/postBuild"], cwd=repo, env=env)
    _run([venv / "bin" / "python", "-m", "pip", "check"], env=env)

    assert _files(repo) == before, (
        "binder/ left files in the learner's home: "
        f"{sorted(set(_files(repo)) - set(before))[:10]}")

    # the libraries, from the image's site-packages, not from the checkout
    elsewhere = tmp_path / "elsewhere"
    elsewhere.mkdir()
    probe = ("import json, nbgitpuller, so3lib, pathlib; "
             "print(json.dumps(str(pathlib.Path(so3lib.__file__).parent)))")
    where = Path(json.loads(_run([venv / "bin" / "python", "-c", probe], cwd=elsewhere, env=env).stdout))
    assert where.is_relative_to(venv), f"so3lib imported from {where}, not the image's site-packages"
    ours = sorted(p.relative_to(ROOT / "so3lib") for p in (ROOT / "so3lib").rglob("*.py"))
    assert sorted(p.relative_to(where) for p in where.rglob("*.py")) == ours
    assert all((where / p).read_bytes() == (ROOT / "so3lib" / p).read_bytes() for p in ours)
    etc = venv / "etc" / "jupyter"
    enabled = json.loads((etc / "jupyter_server_config.d" / "nbgitpuller.json").read_text())
    assert enabled["ServerApp"]["jpserver_extensions"]["nbgitpuller"] is True
    # nbgrader's instructor tools off for the learners, the exchange's Assignments on
    disabled = json.loads((etc / "labconfig" / "page_config.json").read_text())["disabledExtensions"]
    assert {"@jupyter/nbgrader:formgrader", "@jupyter/nbgrader:create-assignment"} <= set(disabled)
    assert "@jupyter/nbgrader:assignment-list" not in disabled
    formgrader = etc / "jupyter_server_config.d" / "nbgrader.server_extensions.formgrader.json"
    assert json.loads(formgrader.read_text())["ServerApp"]["jpserver_extensions"] == \
        {"nbgrader.server_extensions.formgrader": False}

    # a copy of the first notebook, run in another folder with the image's nbconvert
    shutil.copy2(NOTEBOOK, elsewhere / NOTEBOOK.name)
    _run([venv / "bin" / "jupyter", "nbconvert", "--to", "notebook", "--execute",
          "--output", "ran.ipynb", "--ExecutePreprocessor.timeout=300",
          "--KernelManager.transport_encryption=auto", NOTEBOOK.name], cwd=elsewhere, env=env)
    ran = json.loads((elsewhere / "ran.ipynb").read_text())
    errors = [o for c in ran["cells"] for o in c.get("outputs", []) if o.get("output_type") == "error"
              and "raises-exception" not in c.get("metadata", {}).get("tags", [])]
    assert not errors, errors[0]
    assert any(c.get("outputs") for c in ran["cells"] if c["cell_type"] == "code")
    record.record({"image": key})
