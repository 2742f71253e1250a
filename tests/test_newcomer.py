"""A newcomer's path: the commands the README names, `make lab` as a learner sees it,
`make execute NB=...`, `make grade SUBMITTED=submitted`, and the check of the system
packages that `make test` and `make pdf` run first."""

import json
import os
import re
import secrets
import signal
import socket
import subprocess
import sys
import time
import urllib.request
import uuid
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parent.parent
if str(ROOT) not in sys.path:
    sys.path.insert(0, str(ROOT))

from tools import check_system  # noqa: E402
from tools.grade import submitted_folder  # noqa: E402

MAKE = ["make", "--no-print-directory", "-s", "-o", ".venv/.installed"]


def _make(*args, **kw):
    return subprocess.run(MAKE + list(args), cwd=ROOT, capture_output=True, text=True, **kw)


# --- the commands: make help, the README's table and the Makefile agree ------------------

def _help_targets():
    out = _make("help").stdout
    return {m.group(1) for m in re.finditer(r"^make ([a-z][\w-]*)", out, re.MULTILINE)}


def _readme_targets():
    text = (ROOT / "README.md").read_text()
    table = text[text.index("## All commands"):]
    table = table[:table.index("\n\n", table.index("| command |"))]
    return {m.group(1) for m in re.finditer(r"^\| `make ([a-z][\w-]*)", table, re.MULTILINE)}


def _makefile_targets():
    text = (ROOT / "Makefile").read_text()
    phony = set()
    for line in re.findall(r"^\.PHONY:(.*)$", text, re.MULTILINE):
        phony |= set(line.split())
    return phony - {"help", "check-test-system"}


def test_make_help_and_the_readme_list_the_same_commands():
    help_targets, readme = _help_targets(), _readme_targets()
    assert "lint" in readme and "test-portable" in readme
    assert help_targets == readme, (f"only in make help: {sorted(help_targets - readme)}; "
                                    f"only in the README's table: {sorted(readme - help_targets)}")
    assert _makefile_targets() == help_targets, \
        f"targets make help does not list: {sorted(_makefile_targets() - help_targets)}"


def test_make_test_runs_the_portable_nbval_after_the_main_run():
    recipe = _make("-n", "test").stdout
    main = recipe.index("pytest -n 2 --dist loadfile")
    portable = recipe.index("OPENBLAS_CORETYPE=Sandybridge")
    assert recipe.index("tools.check_system test") < recipe.index("ruff check") < main < portable
    assert 'NPY_DISABLE_CPU_FEATURES="X86_V3 X86_V4 AVX512_ICL AVX512_SPR"' in recipe
    # both portable runs drop the machine's own setting first
    assert recipe.count("env -u OPENBLAS_CORETYPE -u OPENBLAS_L2_SIZE") == 2


def test_make_execute_runs_one_notebook_or_all():
    one = "notebooks/01_hat_map_and_lemma.ipynb"
    recipe = _make("-n", "execute", f"NB={one}").stdout
    assert re.findall(r"notebooks/\S+\.ipynb", recipe) == [one]
    everything = re.findall(r"notebooks/\S+\.ipynb", _make("-n", "execute").stdout)
    assert everything == sorted(str(p.relative_to(ROOT)) for p in (ROOT / "notebooks").glob("*.ipynb"))


# --- make grade SUBMITTED=submitted --------------------------------------------------------

def test_grade_finds_a_relative_folder_in_the_course(tmp_path, monkeypatch):
    course, here = tmp_path / "coursework", tmp_path / "repo"
    (course / "submitted" / "alice" / "01_x").mkdir(parents=True)
    here.mkdir()
    monkeypatch.chdir(here)
    assert submitted_folder("submitted", course) == course / "submitted"
    (here / "submitted").mkdir()                     # a folder here comes first
    assert submitted_folder("submitted", course) == Path("submitted")
    with pytest.raises(SystemExit, match=r"no folder elsewhere or .*coursework/elsewhere"):
        submitted_folder("elsewhere", course)
    with pytest.raises(SystemExit, match=r"no folder /no/such/dir:"):
        submitted_folder("/no/such/dir", course)


# --- the system packages ----------------------------------------------------------------

def test_missing_system_packages_are_named_with_their_debian_package(monkeypatch, capsys):
    gone = {"pdftotext", "chromium", "font Liberation Sans"}
    monkeypatch.setattr(check_system, "missing", lambda names: [n for n in names if n in gone])
    monkeypatch.delenv("CI", raising=False)
    assert check_system.main(["test"]) == 0          # outside CI: the tests skip, with the reason
    err = capsys.readouterr().err
    assert ("missing: pdftotext (Debian package poppler-utils): apt-get install poppler-utils"
            in err)
    assert "missing: chromium (Debian package chromium): apt-get install chromium" in err
    assert "apt-get install chromium fonts-liberation poppler-utils" in err
    monkeypatch.setenv("CI", "true")
    assert check_system.main(["test"]) == 1          # CI installs them all: an error
    capsys.readouterr()
    monkeypatch.delenv("CI")
    assert check_system.main(["pdf"]) == 1           # make pdf cannot work without them
    assert "missing: pdftotext (Debian package poppler-utils)" in capsys.readouterr().err
    assert check_system.main(["--debian-packages"]) == 0
    assert capsys.readouterr().out.split() == ["chromium", "fonts-liberation", "poppler-utils"]


def test_the_readme_names_every_system_package_in_one_line():
    packages = {package for package, _, _ in check_system.WHAT.values()}
    lines = [ln for ln in (ROOT / "README.md").read_text().splitlines()
             if "apt-get install" in ln and all(p in ln.split() or f"{p}`" in ln for p in packages)]
    assert lines, f"no README line installs all of {sorted(packages)}"


# --- make lab, as a learner sees it ------------------------------------------------------

def test_lab_config_turns_off_every_nbgrader_extension_the_venv_enables():
    config = json.loads((ROOT / "tools/lab_config/jupyter_server_config.json").read_text())
    off = config["ServerApp"]["jpserver_extensions"]
    enabled = set()
    for path in (ROOT / ".venv/etc/jupyter/jupyter_server_config.d").glob("*.json"):
        enabled |= set(json.loads(path.read_text()).get("ServerApp", {}).get("jpserver_extensions", {}))
    assert {e for e in enabled if e.startswith("nbgrader")} <= {e for e, on in off.items() if on is False}
    page = json.loads((ROOT / "tools/lab_config/labconfig/page_config.json").read_text())
    assert page["disabledExtensions"] == {"@jupyter/nbgrader": True}


def _free_port():
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return s.getsockname()[1]


def _execute(ws_url, code):
    """Run CODE in the kernel behind WS_URL (JupyterLab's websocket); returns its stdout."""
    import websocket
    ws = websocket.create_connection(ws_url, timeout=60)
    try:
        msg_id, session = uuid.uuid4().hex, uuid.uuid4().hex
        ws.send(json.dumps({
            "header": {"msg_id": msg_id, "session": session, "username": "test", "version": "5.3",
                       "msg_type": "execute_request", "date": ""},
            "parent_header": {}, "metadata": {}, "buffers": [], "channel": "shell",
            "content": {"code": code, "silent": False, "store_history": False,
                        "user_expressions": {}, "allow_stdin": False, "stop_on_error": True}}))
        out, deadline = [], time.monotonic() + 60
        while time.monotonic() < deadline:
            msg = json.loads(ws.recv())
            if msg.get("parent_header", {}).get("msg_id") != msg_id:
                continue
            if msg["msg_type"] == "stream":
                out.append(msg["content"]["text"])
            if msg["msg_type"] == "status" and msg["content"]["execution_state"] == "idle":
                return "".join(out)
        raise AssertionError("the kernel did not answer within a minute")
    finally:
        ws.close()


def test_make_lab_is_a_learners_lab(tmp_path):
    """`make lab` prints a URL that opens notebooks/00_start_here.ipynb; nbgrader's menus
    and server extensions are off; a kernel runs code over an encrypted connection; and the
    terminal shows neither nbgrader's missing-config warning nor the kernel's plain-TCP one."""
    if not (ROOT / ".venv" / "bin" / "jupyter").exists():
        pytest.skip("`make lab` needs the course's .venv (run `make lab` or `make test` once)")
    port, token = _free_port(), secrets.token_hex(16)
    env = dict(os.environ, JUPYTERLAB_SETTINGS_DIR=str(tmp_path / "settings"),
               JUPYTERLAB_WORKSPACES_DIR=str(tmp_path / "workspaces"),
               JUPYTER_RUNTIME_DIR=str(tmp_path / "runtime"), JUPYTER_CONFIG_DIR=str(tmp_path / "config"))
    log = tmp_path / "lab.log"
    args = f"--no-browser --port={port} --ServerApp.port_retries=0 --IdentityProvider.token={token}"
    with open(log, "w") as err:
        proc = subprocess.Popen(MAKE + ["lab", f"LAB_ARGS={args}"], cwd=ROOT, env=env,
                                stdout=subprocess.DEVNULL, stderr=err, start_new_session=True)
    try:
        deadline, urls = time.monotonic() + 120, []
        while not urls:
            assert proc.poll() is None and time.monotonic() < deadline, \
                "JupyterLab did not start:\n" + log.read_text()
            time.sleep(0.5)
            urls = re.findall(rf"http://127\.0\.0\.1:{port}/\S+", log.read_text())
        # (a token given on the command line is printed as "...")
        assert urls[-1] in {f"http://127.0.0.1:{port}/lab/tree/00_start_here.ipynb?token={t}"
                            for t in (token, "...")}, urls[-1]
        url = f"http://127.0.0.1:{port}/lab/tree/00_start_here.ipynb?token={token}"
        page = urllib.request.urlopen(url, timeout=60).read().decode()
        config = json.loads(re.search(r'id="jupyter-config-data"[^>]*>(.*?)</script>', page, re.S).group(1))
        assert "@jupyter/nbgrader" in config["disabledExtensions"]
        assert config["news"] == {"disabled": True}

        api = f"http://127.0.0.1:{port}/api"
        listed = json.loads(urllib.request.urlopen(f"{api}/contents/00_start_here.ipynb?content=0&token={token}",
                                                   timeout=30).read())
        assert listed["type"] == "notebook"           # served from notebooks/
        request = urllib.request.Request(
            f"{api}/sessions?token={token}", method="POST", headers={"Content-Type": "application/json"},
            data=json.dumps({"path": "00_start_here.ipynb", "name": "00_start_here.ipynb",
                             "type": "notebook", "kernel": {"name": "python3"}}).encode())
        kernel = json.loads(urllib.request.urlopen(request, timeout=60).read())["kernel"]["id"]
        ws = f"ws://127.0.0.1:{port}/api/kernels/{kernel}/channels?token={token}"
        assert _execute(ws, "import so3lib; print(6 * 7)").strip() == "42"
        connection = json.loads(next((tmp_path / "runtime").glob(f"kernel-{kernel}.json")).read_text())
        assert connection.get("curve_publickey"), "the kernel's connection is not encrypted"
    finally:
        os.killpg(proc.pid, signal.SIGTERM)
        try:
            proc.wait(timeout=20)
        except subprocess.TimeoutExpired:
            os.killpg(proc.pid, signal.SIGKILL)
            proc.wait()
    text = log.read_text()
    assert "without encryption" not in text, text
    assert "nbgrader" not in text.lower(), text
