"""Issue 24: a made-up class graded in the sandbox, where the learner's code cannot reach
the grade.

The fixture notebook's three exercises (a function, a value, and a function "without
NumPy's norm") are answered right, wrong, left as stubs, and by students who attack the
grading: patching what the hidden tests use, taking over the kernel, a fake numpy,
reading the answer key from disk, a process left behind, and every route around the
forbidden function. Each notebook runs as `make grade` runs it (tools/trusted_grader.py:
the notebook in a bubblewrap sandbox, the hidden tests in this process).
"""

import os
import time
from pathlib import Path

import nbformat
import pytest

from tools import assignments, sandbox
from tools.trusted_grader import NotebookRun, is_answer, is_test

FIXTURE = Path(__file__).parent / "fixtures" / "09_fixture_exercises.ipynb"
MARKER = "so3-grading-left-behind-4242"

pytestmark = pytest.mark.skipif(bool(sandbox.missing()), reason=str(sandbox.missing()))

RIGHT = {
    "ex9_1": "def twice(x):\n    return 2.0 * np.asarray(x)",
    "ex9_2": "n2 = 14",
    "ex9_3": "def length(v):\n    return float(np.sqrt(np.sum(np.asarray(v, dtype=float) ** 2)))",
}
WRONG = {
    "ex9_1": "def twice(x):\n    return 3.0 * np.asarray(x)",
    "ex9_2": "n2 = 13",
    "ex9_3": "def length(v):\n    return float(np.sum(np.abs(v)))",
}

ATTACKS = {
    # patching what the hidden tests use
    "allclose": {"ex9_1": "import numpy\nnumpy.allclose = lambda *a, **k: True\n"
                          "numpy.isclose = lambda *a, **k: True\n" + WRONG["ex9_1"],
                 "ex9_2": WRONG["ex9_2"], "ex9_3": WRONG["ex9_3"]},
    # blanking the test cells, and a displayhook that prints a score
    "transformer": {"ex9_1": "get_ipython().input_transformers_cleanup.append(lambda lines: ['pass\\n'])\n"
                             + WRONG["ex9_1"],
                    "ex9_2": "get_ipython().displayhook('ok')\nn2 = 13",
                    "ex9_3": WRONG["ex9_3"]},
    # objects that choose how they compare; a fake numpy
    "liar": {"ex9_1": "class Liar(float):\n    def __eq__(self, other):\n        return True\n"
                      "    def __array__(self, *a, **k):\n        get_ipython().displayhook('ok')\n"
                      "        return np.array(1.0)\n"
                      "def twice(x):\n    return Liar(0.0)",
             "ex9_2": "class Big(float):\n    def __eq__(self, other):\n        return True\n"
                      "n2 = Big(13.0)",
             "ex9_3": "import sys, types\nfake = types.ModuleType('numpy')\n"
                      "fake.allclose = fake.isclose = lambda *a, **k: True\n"
                      "fake.abs = lambda x: 0.0\nsys.modules['numpy'] = fake\n" + WRONG["ex9_3"]},
    # the answer key and the hidden tests from disk; a process that outlives grading
    "reader": {"ex9_1": "import glob, os, subprocess, sys\n"
                        "found = []\n"
                        "for pattern in KEYS + ['/work/*/notebooks/*.ipynb', '/tmp/*/*/*/*/*.ipynb',\n"
                        "                '../../../source/*/*.ipynb', '/root/*.ipynb', '../*/*.ipynb']:\n"
                        "    for path in glob.glob(pattern):\n"
                        "        try:\n"
                        "            if 'SOLUTION-CODE-SECRET' in open(path).read():\n"
                        "                found.append(path)\n"
                        "        except OSError:\n"
                        "            pass\n"
                        "print('answer keys found:', len(found))\n"
                        "for pattern in KEYS + ['../../gradebook.db', '/tmp/*/gradebook.db']:\n"
                        "    for path in glob.glob(os.path.join(os.path.dirname(pattern), '*')):\n"
                        "        if os.path.abspath(path).startswith(os.getcwd()):\n"
                        "            continue              # its own scratch folder\n"
                        "        try:\n"
                        "            open(path, 'a').close()\n"
                        "            print('WROTE', path)\n"
                        "        except OSError:\n"
                        "            pass\n"
                        "subprocess.Popen([sys.executable, '-c', 'import time\\nwhile True: "
                        f"time.sleep(0.2)  # {MARKER}'], start_new_session=True)\n"
                        + WRONG["ex9_1"],
               "ex9_2": "print(get_ipython().user_ns.get('In'))\nn2 = 13",
               "ex9_3": WRONG["ex9_3"]},
}

# every way around "without np.linalg.norm" (exercise 9.3), each one right otherwise
ROUTES = {
    "alias": "_n = np.linalg.norm\ndef length(v):\n    return float(_n(v))",
    "partial": "import functools\n_n = functools.partial(np.linalg.norm, ord=None)\n"
               "def length(v):\n    return float(_n(v))",
    "getattr": "def length(v):\n    return float(getattr(np.linalg, 'no' + 'rm')(v))",
    "thread": "from concurrent.futures import ThreadPoolExecutor\n_pool = ThreadPoolExecutor(1)\n"
              "_pool.submit(int).result()\n"
              "def length(v):\n    return float(_pool.submit(np.linalg.norm, v).result())",
    "setprofile": "import sys\ndef length(v):\n    sys.setprofile(None)\n    import threading\n"
                  "    threading.setprofile(None)\n    return float(np.linalg.norm(v))",
    "_thread": "import _thread, time\ndef length(v):\n    out = []\n"
               "    _thread.start_new_thread(lambda: out.append(np.linalg.norm(v)), ())\n"
               "    for _ in range(100):\n        if out:\n            return float(out[0])\n"
               "        time.sleep(0.01)",
    # NumPy's norm rebuilt from its code object, which the code swap does not reach
    "rebuilt": "import types\n_impl = getattr(np.linalg.norm, '_implementation', np.linalg.norm)\n"
               "_n = types.FunctionType(_impl.__code__, _impl.__globals__, None, _impl.__defaults__)\n"
               "def length(v):\n    return float(_n(v))",
    # the helper's frame, reached from the call, to turn its watch off
    "frames": "import sys\ndef length(v):\n    try:\n        f = sys._getframe(1)\n"
              "    except RuntimeError:\n        try:\n            raise ValueError\n"
              "        except ValueError as e:\n            f = e.__traceback__.tb_frame.f_back\n"
              "    f.f_locals.clear()\n    return float(np.linalg.norm(v))",
    # a stand-in for the grader's helper: answers every call with the forbidden function
    "fake-helper": "import sys, socket, json\n_audit = sys.audit\n"
                   "def _fake(event, *args):\n    if event != 'so3grade.serve':\n"
                   "        return _audit(event, *args)\n"
                   "    s = socket.socket(socket.AF_UNIX); s.connect(args[0]); f = s.makefile('rwb')\n"
                   "    for line in f:\n        req = eval(line)\n        if req['op'] == 'done':\n"
                   "            return\n"
                   "        x = np.array(eval(repr(req['args'])), dtype=object)\n"
                   "        f.write((\"sig {'ok': {'f': '5.0'}, 'entered': []}\\n\").encode()); f.flush()\n"
                   "sys.audit = _fake\n"
                   "def length(v):\n    return float(np.linalg.norm(v))",
}


@pytest.fixture(scope="module")
def course(tmp_path_factory):
    out = tmp_path_factory.mktemp("course")
    assignments.build(out, [FIXTURE], log=lambda *a: None)
    name = FIXTURE.stem
    return (out / "source" / name / f"{name}.ipynb", out / "release" / name / f"{name}.ipynb")


def grade(course, answers, timeout=4):
    """{exercise: (passed, ename, evalue)} and the text of every output."""
    source_path, release_path = course
    nb = nbformat.read(str(release_path), as_version=4)
    source = nbformat.read(str(source_path), as_version=4)
    tests = {c.metadata["nbgrader"]["grade_id"]: c.source for c in source.cells if is_test(c)}
    for cell in nb.cells:
        gid = cell.metadata.get("nbgrader", {}).get("grade_id", "")
        ex = gid.rsplit("-", 1)[0]
        if is_answer(cell) and ex in answers:
            cell.source = answers[ex]
        elif is_test(cell):
            cell.source = tests[gid]          # as nbgrader puts them back
    NotebookRun(nb, source_path, timeout=timeout, notebook_timeout=120).grade()
    verdicts, text = {}, []
    for cell in nb.cells:
        for out in cell.get("outputs", []):
            text.append(str(out.get("text", "")) + str(out.get("data", "")) + str(out.get("evalue", "")))
        if is_test(cell):
            errors = [o for o in cell.outputs if o.output_type == "error"]
            stderr = [o for o in cell.outputs if o.output_type == "stream" and o.name == "stderr"]
            assert not stderr, "a test cell's stderr would cost the points in nbgrader"
            verdicts[cell.metadata["nbgrader"]["grade_id"].rsplit("-", 1)[0]] = (
                not errors, errors[0].ename if errors else "", errors[0].evalue if errors else "")
    return verdicts, "\n".join(text)


def test_right_wrong_and_stub(course):
    start = time.monotonic()
    right, _ = grade(course, RIGHT)
    assert all(ok for ok, _, _ in right.values()), right
    wrong, _ = grade(course, WRONG)
    assert not any(ok for ok, _, _ in wrong.values()), wrong
    assert {name for _, name, _ in wrong.values()} == {"AssertionError"}
    stub, _ = grade(course, {})
    assert {name for _, name, _ in stub.values()} == {"NotAnswered"}, stub
    assert all("not answered" in why for _, _, why in stub.values())
    assert time.monotonic() - start < 90


@pytest.mark.parametrize("attack", sorted(ATTACKS))
def test_attacks_score_nothing(course, attack):
    answers = dict(ATTACKS[attack])
    keys = [str(p) for p in course] + [str(Path(__file__).resolve().parent.parent / "notebooks" / "*.ipynb")]
    answers["ex9_1"] = f"KEYS = {keys!r}\n" + answers["ex9_1"]
    verdicts, text = grade(course, answers)
    assert not any(ok for ok, _, _ in verdicts.values()), verdicts
    assert "HIDDEN-TEST-SECRET" not in text and "HIDDEN-VALUE-SECRET" not in text
    if attack == "reader":
        assert "answer keys found: 0" in text and "WROTE" not in text
        time.sleep(0.5)
        left = []
        for pid in os.listdir("/proc"):
            try:
                if pid.isdigit() and MARKER in Path(f"/proc/{pid}/cmdline").read_text(errors="replace"):
                    left.append(pid)
            except OSError:
                pass
        assert not left, "a process outlived its grading"


@pytest.mark.parametrize("route", sorted(ROUTES))
def test_forbidden_routes_are_refused_by_the_grade(course, route):
    verdicts, _ = grade(course, dict(RIGHT, ex9_3=ROUTES[route]))
    assert verdicts["ex9_1"][0] and verdicts["ex9_2"][0]
    assert not verdicts["ex9_3"][0], verdicts["ex9_3"]


def test_honest_work_is_not_zeroed(course):
    """A warning on stderr costs nothing; a KeyboardInterrupt the code raises is not a
    time limit; a loop that swallows the interrupt costs only its own exercise."""
    warns = dict(RIGHT, ex9_1="import sys, warnings\ndef twice(x):\n"
                              "    warnings.warn('careful', RuntimeWarning)\n"
                              "    print('a note', file=sys.stderr)\n"
                              "    return 2.0 * np.asarray(x)")
    verdicts, _ = grade(course, warns)
    assert all(ok for ok, _, _ in verdicts.values()), verdicts
    stopped = dict(RIGHT, ex9_1="def twice(x):\n    raise KeyboardInterrupt",
                   ex9_3="import time\ndef length(v):\n    while True:\n        try:\n"
                         "            time.sleep(0.5)\n        except:\n            pass")
    verdicts, _ = grade(course, stopped, timeout=3)
    assert verdicts["ex9_1"][1] == "KeyboardInterrupt" and "not a time limit" in verdicts["ex9_1"][2]
    assert verdicts["ex9_2"][0]
    assert verdicts["ex9_3"][1] == "CellTimeoutError", verdicts["ex9_3"]
