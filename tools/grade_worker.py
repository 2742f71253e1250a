"""One warm grading worker: nbgrader's autograde for many submissions in one process.

`make grade` starts JOBS of these (tools/grade.py). Each reads ``STUDENT<TAB>ASSIGNMENT``
lines on stdin and answers each with one JSON line on stdout (``{"ok": true}`` or
``{"ok": false, "why": ...}``). Python, NumPy, nbgrader and the instructor's reference
namespace (tools/trusted_grader.py) are loaded once per worker, not once per notebook;
each notebook still runs in a sandboxed kernel of its own.

Usage: python -m tools.grade_worker COURSE TIMEOUT NOTEBOOK_TIMEOUT
"""

import json
import os
import sys
from pathlib import Path


def main(argv=None):
    course, timeout, notebook_timeout = (argv or sys.argv[1:])[:3]
    course = Path(course).resolve()
    os.chdir(course)
    os.environ["PATH"] = os.pathsep.join([str(Path(sys.executable).parent), os.environ.get("PATH", "")])
    out = sys.stdout
    sys.stdout = sys.stderr                  # nothing but the answers on the real stdout
    from nbgrader.apps import NbGraderAPI
    from traitlets.config.loader import PyFileConfigLoader
    config = PyFileConfigLoader("nbgrader_config.py", path=str(course)).load_config()
    config.SandboxExecute.timeout = int(timeout)
    config.SandboxExecute.notebook_timeout = int(notebook_timeout)
    config.Application.log_level = "ERROR"
    api = NbGraderAPI(config=config)
    for line in sys.stdin:
        student, _, assignment = line.rstrip("\n").partition("\t")
        try:
            result = api.autograde(assignment, student, force=True, create=True)
            reply = {"ok": bool(result.get("success"))}
            if not reply["ok"]:
                text = (result.get("error") or "") + (result.get("log") or "")
                errors = [ln for ln in text.splitlines() if "Error" in ln or "ERROR" in ln]
                reply["why"] = (errors[-1] if errors else text[-300:]).strip()[:500]
        except Exception as err:  # noqa: BLE001 -- one submission never stops the worker
            reply = {"ok": False, "why": f"{type(err).__name__}: {err}"[:500]}
        out.write(json.dumps(reply) + "\n")
        out.flush()


if __name__ == "__main__":
    sys.exit(main())
