"""A learner's notebook, run in a bubblewrap sandbox (Debian's package `bubblewrap`).

The kernel that runs the learner's code sees only the system's programs, Python and its
packages (read-only), so3lib (read-only) and one scratch folder of its own, which it may
write. It has no network (a network namespace of its own), no view of the course folder
(source/, other submissions, the gradebook), of the repository, of /root or of /tmp, and
runs as the unprivileged user `nobody` when grading runs as root. Limits: time (each
cell, and the whole notebook), memory (address space), processes (per user), the size
of a file it writes, and the output kept from each cell (lines, characters per line,
bytes in all). Every process it starts lives in the sandbox's own PID namespace and is
killed with it when its grading ends (`close()`), background and detached ones too.

The grader talks to the kernel through Unix sockets in the scratch folder (Jupyter's
`ipc` transport), which cross the network namespace; the trusted side of grading
(tools/trusted_grader.py) reaches the learner's functions through one more socket and
gets back plain numbers, strings and arrays (`encode`/`decode`): never an object of the
learner's, so nothing the learner wrote decides how a result compares.
"""

import base64
import json
import os
import re
import shutil
import signal
import subprocess
import sys
import tempfile
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
NOBODY = 65534

#: limits of one graded notebook
MEMORY = 3 << 30            # bytes of address space
PROCESSES = 256             # processes and threads of the sandbox user
FILE_SIZE = 64 << 20        # bytes in one written file
OUTPUT_LINES = 200          # lines kept of one cell's output
OUTPUT_LINE_CHARS = 400     # characters kept of one line
OUTPUT_BYTES = 20_000       # characters kept of one cell's output in all


def bwrap():
    return shutil.which("bwrap")


def missing():
    """Why the sandbox cannot run here, or None."""
    if not bwrap():
        return "bubblewrap is not installed (Debian: apt-get install bubblewrap)"
    probe = subprocess.run(_bwrap_args(Path("/tmp")) + ["true"], capture_output=True, text=True)
    if probe.returncode != 0:
        return f"bwrap cannot make a sandbox here: {probe.stderr.strip()[:300]}"
    return None


def _python_homes():
    """Folders the sandbox needs read-only: the interpreter, the environment, so3lib."""
    import so3lib
    homes = {Path(sys.base_prefix), Path(sys.prefix), Path(so3lib.__file__).resolve().parent}
    return sorted(h for h in homes if not str(h).startswith(("/usr/", "/etc/")) and str(h) != "/usr")


def _bwrap_args(scratch):
    args = [bwrap(), "--die-with-parent", "--new-session",
            "--unshare-ipc", "--unshare-pid", "--unshare-net", "--unshare-uts", "--unshare-cgroup-try"]
    if os.geteuid() != 0:
        args.append("--unshare-user")
    args += ["--ro-bind", "/usr", "/usr", "--ro-bind", "/etc", "/etc"]
    for link in ("bin", "lib", "lib64", "sbin"):
        target = Path("/" + link)
        if target.is_symlink():
            args += ["--symlink", os.readlink(target), str(target)]
        elif target.is_dir():
            args += ["--ro-bind", str(target), str(target)]
    # /tmp first, then the folders that lead to the homes: a course cloned under /tmp (as
    # CI does) has its venv there, and the user the kernel runs as must be able to walk in
    args += ["--proc", "/proc", "--dev", "/dev", "--tmpfs", "/tmp"]
    made = set()
    for home in _python_homes() + [Path(scratch)]:
        for parent in reversed(home.parents):
            if str(parent) not in ("/", "/tmp") and parent not in made:
                args += ["--perms", "0755", "--dir", str(parent)]
                made.add(parent)
    for home in _python_homes():
        args += ["--ro-bind", str(home), str(home)]
    args += ["--bind", str(scratch), str(scratch), "--chdir", str(scratch)]
    return args


def command(scratch, argv):
    """ARGV run in the sandbox whose writable folder is SCRATCH."""
    env = {"HOME": scratch, "PATH": f"{Path(sys.executable).parent}:/usr/bin:/bin", "LANG": "C.UTF-8",
           "MPLCONFIGDIR": f"{scratch}/.matplotlib", "IPYTHONDIR": f"{scratch}/.ipython",
           "JUPYTER_RUNTIME_DIR": f"{scratch}/.jupyter", "JUPYTER_PLATFORM_DIRS": "1",
           "OPENBLAS_NUM_THREADS": "1", "OMP_NUM_THREADS": "1", "MKL_NUM_THREADS": "1",
           "PYTHONDONTWRITEBYTECODE": "1", "TMPDIR": scratch, "MPLBACKEND": "agg"}
    args = _bwrap_args(scratch) + ["--clearenv"]
    for key, value in env.items():
        args += ["--setenv", key, value]
    limits = ["prlimit", f"--as={MEMORY}", f"--nproc={PROCESSES}", f"--fsize={FILE_SIZE}", "--core=0"]
    if os.geteuid() == 0:
        drop = ["setpriv", f"--reuid={NOBODY}", f"--regid={NOBODY}", "--clear-groups",
                "--no-new-privs", "--inh-caps=-all", "--bounding-set=-all"]
    else:
        drop = ["setpriv", "--no-new-privs"]
    return args + ["--"] + limits + ["--"] + drop + list(argv)


# --- plain data across the sandbox's wall ------------------------------------------------

_DTYPES = {"b": "bool", "i": "int64", "u": "int64", "f": "float64", "c": "complex128"}


def encode(obj, depth=0):
    """OBJ as JSON-able plain data: numbers, strings, None, lists, dicts, arrays of numbers.
    Runs inside the sandbox on the learner's results (their __array__ or __float__ may run
    there); raises TypeError for anything else."""
    import numpy as np
    if depth > 20:
        raise TypeError("nested too deep")
    if obj is None or type(obj) in (bool, str):
        return obj
    if type(obj) is int:
        return obj if abs(obj) < 2**63 else float(obj)
    if type(obj) is float:
        return {"f": repr(obj)}
    if type(obj) is complex:
        return {"c": [repr(obj.real), repr(obj.imag)]}
    if obj is Ellipsis:
        return {"ellipsis": True}
    if type(obj) in (list, tuple):
        return {"list" if type(obj) is list else "tuple": [encode(x, depth + 1) for x in obj]}
    if type(obj) is dict:
        return {"dict": [[encode(k, depth + 1), encode(v, depth + 1)] for k, v in obj.items()]}
    if isinstance(obj, np.generic):
        return encode(obj.item(), depth + 1)
    arr = np.asarray(obj)
    kind = arr.dtype.kind
    if kind not in _DTYPES:
        raise TypeError(f"an object of type {type(obj).__name__}, not numbers")
    if arr.ndim == 0:
        return encode(arr.item(), depth + 1)
    arr = np.ascontiguousarray(arr, dtype=_DTYPES[kind])
    return {"array": base64.b64encode(arr.tobytes()).decode(), "dtype": _DTYPES[kind],
            "shape": list(arr.shape)}


def decode(data, depth=0):
    """The plain data ENCODE wrote; never builds anything but numbers, strings, lists,
    tuples, dicts and NumPy arrays of numbers."""
    import numpy as np
    if depth > 25:
        raise ValueError("nested too deep")
    if data is None or type(data) in (bool, int, str):
        return data
    if type(data) is float:
        return data
    if type(data) is dict:
        if "f" in data:
            return float(data["f"])
        if "c" in data:
            return complex(float(data["c"][0]), float(data["c"][1]))
        if "ellipsis" in data:
            return Ellipsis
        if "list" in data:
            return [decode(x, depth + 1) for x in data["list"]]
        if "tuple" in data:
            return tuple(decode(x, depth + 1) for x in data["tuple"])
        if "dict" in data:
            return {decode(k, depth + 1): decode(v, depth + 1) for k, v in data["dict"]}
        if "array" in data and data.get("dtype") in _DTYPES.values():
            shape = [int(n) for n in data["shape"]]
            raw = base64.b64decode(data["array"])
            arr = np.frombuffer(raw, dtype=data["dtype"]).copy()
            return arr.reshape(shape)
    raise ValueError("not plain data")


# --- the code the grader puts into the sandboxed kernel before the learner's ------------
#
# It runs before any of the learner's code and leaves three things behind that the learner's
# Python cannot undo: a seccomp filter (no new process or thread, in any thread), an audit
# hook (sys.addaudithook: it cannot be removed) and, inside that hook's closure, the serving
# loop. The grader reaches it with sys.audit("so3grade.serve", PATH). While it serves, the
# hook refuses what would reach into it (frames, gc's object lists, setprofile/settrace,
# code swaps, ctypes, new functions from code objects); what it saw is signed with a key
# only the hook holds (read from a file it deletes), so a stand-in for it, written by the
# learner, cannot answer the grader. It uses only builtins and C functions captured before
# the learner's code ran: patching json, socket, hmac, numpy or builtins changes nothing
# the grader trusts.

HELPER = r"""
def _so3grade_setup():
    import builtins
    ns = {"__builtins__": dict(vars(builtins)), "__name__": "<grader>"}
    exec(compile(SOURCE, "<grader>", "exec"), ns)
    ns["install"](KEYPATH)
_so3grade_setup()
del _so3grade_setup
"""

HELPER_SOURCE = r"""
import sys, os, _socket, _thread, _functools

def _no_new_tasks():
    # seccomp, for every thread of the kernel: clone, clone3, fork and vfork fail (EAGAIN)
    import ctypes, platform, struct
    machine = platform.machine()
    table = {"x86_64": (0xC000003E, (56, 57, 58, 435), 317),
             "aarch64": (0xC00000B7, (220, 435), 277)}
    if machine not in table:
        return False
    arch, calls, nr_seccomp = table[machine]
    LD, JEQ, JGE, RET = 0x20, 0x15, 0x35, 0x06
    deny, allow = 0x00050000 | 11, 0x7FFF0000
    n = len(calls)                     # jumps count the instructions skipped
    prog = [(LD, 0, 0, 4), (JEQ, 0, n + 2, arch), (LD, 0, 0, 0), (JGE, n + 1, 0, 0x40000000)]
    prog += [(JEQ, n - i, 0, nr) for i, nr in enumerate(calls)]
    prog += [(RET, 0, 0, allow), (RET, 0, 0, deny)]
    raw = b"".join(struct.pack("HBBI", *ins) for ins in prog)
    buf = ctypes.create_string_buffer(raw, len(raw))
    class Fprog(ctypes.Structure):
        _fields_ = [("len", ctypes.c_ushort), ("filter", ctypes.c_void_p)]
    fprog = Fprog(len(prog), ctypes.addressof(buf))
    libc = ctypes.CDLL(None, use_errno=True)
    libc.prctl(38, 1, 0, 0, 0)                       # PR_SET_NO_NEW_PRIVS
    ok = libc.syscall(nr_seccomp, 1, 1, ctypes.byref(fprog)) == 0   # SET_MODE_FILTER, TSYNC
    return ok

def install(keypath):
    with open(keypath, "rb") as fh:
        key = fh.read()
    os.unlink(keypath)
    from _hashlib import openssl_sha256 as sha
    blocks = _no_new_tasks()
    real = {"setprofile": sys.setprofile, "getprofile": sys.getprofile, "audit": sys.audit,
            "partial": _functools.partial, "ident": _thread.get_ident, "main": _thread.get_ident(),
            "tb": BaseException.__dict__["__traceback__"], "modules": sys.modules}
    st = {"guard": False, "watch": False, "internal": 0, "entered": set(), "tampered": [],
          "serving": False}
    ipad = bytes(b ^ 0x36 for b in key.ljust(64, b"\0"))
    opad = bytes(b ^ 0x5C for b in key.ljust(64, b"\0"))
    del key
    def sign(data):
        return sha(opad + sha(ipad + data).digest()).hexdigest()
    always = {"gc.get_objects", "gc.get_referrers", "gc.get_referents", "sys.addaudithook"}
    guarded = {"sys.setprofile", "sys.settrace", "sys._getframe", "sys._current_frames",
               "function.__new__", "code.__new__", "object.__setattr__", "object.__delattr__",
               "sys.setrecursionlimit", "os.fork", "subprocess.Popen"}
    frames = {"tb_frame", "gi_frame", "cr_frame", "ag_frame", "f_back", "tb_next"}

    def hook(event, args):
        if st["internal"]:
            return
        if event == "so3grade.entered":
            if st["watch"] and len(args) == 3 and args[1] == "call" and len(st["entered"]) < 20000:
                try:
                    c = args[0].f_code
                    if c.co_filename != "<grader>":
                        st["entered"].add((str(c.co_filename), int(c.co_firstlineno), str(c.co_name)))
                except Exception:
                    pass
            return
        if event == "so3grade.serve":
            if st["serving"] or real["ident"]() != real["main"]:
                raise RuntimeError("the grader's helper is already serving")
            serve(args[0])
            return
        refuse = event in always
        if event in ("sys.setprofile", "sys.settrace") and real["ident"]() != real["main"]:
            refuse = True
        if st["guard"] and (event in guarded or event.startswith("ctypes.") or
                            (event == "object.__getattr__" and len(args) > 1 and args[1] in frames)):
            refuse = True
        if refuse:
            if st["guard"]:
                st["tampered"].append(event)
            raise RuntimeError(f"{event} is not available in graded code")

    def internal(fn, *args):
        st["internal"] += 1
        try:
            return fn(*args)
        finally:
            st["internal"] -= 1

    def literal(obj, depth=0):
        # the reply, written with builtins only (never json, which the learner may patch)
        if depth > 40:
            raise ValueError("nested too deep")
        t = type(obj)
        if obj is None or t is bool or t is int:
            return repr(obj)
        if t is float:
            return repr(obj) if obj - obj == 0 else repr(repr(obj))
        if t is str:
            return repr(obj)
        if t in (list, tuple):
            return "[" + ", ".join(literal(x, depth + 1) for x in obj) + "]"
        if t is dict:
            return "{" + ", ".join(literal(k, depth + 1) + ": " + literal(v, depth + 1)
                                   for k, v in obj.items()) + "}"
        raise ValueError("not plain data")

    def disable(targets):
        swapped = []
        def off(*args, **kwargs):
            raise RuntimeError("this function is not allowed in this exercise")
        for module, name in targets:
            fn = getattr(real["modules"].get(module), name, None)
            fn = getattr(fn, "_implementation", fn)
            if type(fn) is not type(off):
                continue
            code = fn.__code__
            if not code.co_freevars:
                internal(setattr, fn, "__code__", off.__code__)
                swapped.append((fn, code))
        return swapped

    def call(obj, args, targets):
        st["entered"], st["tampered"] = set(), []
        swapped = disable(targets)
        probe = real["partial"](real["audit"], "so3grade.entered")
        getprofile = sys.getprofile
        internal(real["setprofile"], probe)
        sys.getprofile = type(None)            # the learner's code cannot see the probe
        st["watch"] = True
        try:
            result = ENCODE(obj(*args))        # __array__ and __float__ run while watched
        finally:
            st["watch"] = False
            if real["getprofile"]() is not probe or probe.func is not real["audit"] \
                    or probe.args != ("so3grade.entered",):
                st["tampered"].append("profile")
            internal(real["setprofile"], None)
            sys.getprofile = getprofile
            for fn, code in swapped:
                internal(setattr, fn, "__code__", code)
        return result

    def serve(path):
        from IPython import get_ipython
        user_ns = get_ipython().user_ns
        sock = _socket.socket(_socket.AF_UNIX, _socket.SOCK_STREAM)
        st["serving"] = st["guard"] = True
        try:
            sock.connect(path)
            pending = b""
            while True:
                while b"\n" not in pending:
                    chunk = sock.recv(1 << 20)
                    if not chunk:
                        return
                    pending += chunk
                line, _, pending = pending.partition(b"\n")
                req = eval(line.decode(), {"__builtins__": {}})     # the grader's own literal
                if req.get("op") == "done":
                    return
                reply = {}
                try:
                    if req["name"] not in user_ns:
                        raise NameError(f"name {req['name']!r} is not defined")
                    obj = user_ns[req["name"]]
                    if req["op"] == "value":
                        reply["ok"] = ENCODE(obj)
                    elif req["op"] == "describe":
                        reply["ok"] = _describe(obj)
                    elif req["op"] == "call":
                        reply["ok"] = call(obj, DECODE(req["args"]), req.get("disabled", []))
                        reply["entered"] = sorted(st["entered"])
                        reply["tampered"] = list(st["tampered"])
                except BaseException as err:
                    st["watch"] = False
                    reply.pop("ok", None)
                    reply["entered"] = sorted(st["entered"])
                    reply["tampered"] = list(st["tampered"])
                    try:
                        real["tb"].__set__(err, None)      # no way back to this frame
                        text = BaseException.__str__(err)[:300]
                    except BaseException:
                        text = ""
                    name = type(err).__name__ if type(type(err).__name__) is str else "Error"
                    if isinstance(err, KeyboardInterrupt):
                        name = "KeyboardInterrupt"
                    reply["error"] = [name[:100], text]
                    err = None
                try:
                    body = literal(reply)
                except ValueError:
                    body = literal({"error": ["TypeError", "the answer is not plain data"]})
                data = body.encode()
                sock.sendall(sign(line + b"\n" + data).encode() + b" " + data + b"\n")
        finally:
            st["serving"] = st["guard"] = st["watch"] = False
            sock.close()

    def _code(code, depth=0):
        consts = [_code(k, depth + 1) for k in code.co_consts if type(k) is type(_code.__code__) and depth < 8]
        return {"name": str(code.co_name), "names": [str(n) for n in code.co_names], "consts": consts}

    def _describe(fn):
        code = getattr(fn, "__code__", None)
        if type(code) is not type(_code.__code__):
            return {"callable": bool(callable(fn)), "name": ""}
        space = getattr(fn, "__globals__", {})
        space = space if type(space) is dict else {}
        names, todo, seen = set(), [code], set()
        while todo:
            c = todo.pop()
            if id(c) in seen:
                continue
            seen.add(id(c))
            names |= set(c.co_names)
            todo += [k for k in c.co_consts if type(k) is type(code)]
            for n in c.co_names:
                g = space.get(n)
                if type(g) is type(_describe) and g.__globals__ is space:
                    todo.append(g.__code__)
        glob = {}
        for n in sorted(names):
            g = space.get(n)
            if g is None:
                continue
            if type(g) is type(_describe) and g.__globals__ is space:
                glob[str(n)] = {"own": _code(g.__code__), "name": str(g.__name__)}
            else:
                label = getattr(g, "__name__", None)
                if type(label) is str:
                    glob[str(n)] = {"name": label}
        return {"code": _code(code), "globals": glob, "name": str(getattr(fn, "__name__", ""))}

    hook.__cantrace__ = True     # the probe must see the calls made inside the serving hook
    sys.addaudithook(hook)
    return blocks
"""


_FONTS = []


def _font_list():
    """(file name, bytes) of matplotlib's list of the fonts on this machine, made once per
    grading process. A kernel that finds none scans every font file before it draws (a
    second or more per notebook); this one lists the same fonts, which the sandbox can
    read (/usr and the environment). A font it cannot open makes matplotlib scan again."""
    if not _FONTS:
        try:
            from matplotlib import font_manager
            name = f"fontlist-v{font_manager.FontManager.__version__}.json"
            with tempfile.TemporaryDirectory() as tmp:
                font_manager.json_dump(font_manager.fontManager, Path(tmp) / name)
                _FONTS.append((name, (Path(tmp) / name).read_bytes()))
        except Exception:        # noqa: BLE001 -- without it the kernel only starts slower
            _FONTS.append(("", b""))
    return _FONTS[0]


class KernelDied(Exception):
    """The sandboxed kernel stopped (killed at a time limit, out of memory, crashed)."""


class Sandbox:
    """One sandboxed IPython kernel with its scratch folder; `close()` ends every process."""

    def __init__(self, files=None, startup_timeout=180):
        self.scratch = Path(tempfile.mkdtemp(prefix="so3grade-"))
        if files:
            for path in Path(files).iterdir():
                if path.suffix != ".ipynb" and not path.name.startswith("."):
                    (shutil.copytree if path.is_dir() else shutil.copy2)(path, self.scratch / path.name)
        self.startup_timeout = startup_timeout
        self.proc = self.client = None
        self.start()

    def start(self):
        from jupyter_client import BlockingKernelClient
        from jupyter_client.connect import write_connection_file
        self._close_kernel()
        for stale in self.scratch.glob("kernel*"):
            stale.unlink()
        self.starts = getattr(self, "starts", 0) + 1     # new socket paths for each start
        conn = self.scratch / f"kernel{self.starts}.json"
        write_connection_file(str(conn), transport="ipc", ip=str(self.scratch / f"kernel{self.starts}"))
        name, fonts = _font_list()
        if fonts:                        # matplotlib's font list, not rebuilt in every kernel
            (self.scratch / ".matplotlib").mkdir(exist_ok=True)
            (self.scratch / ".matplotlib" / name).write_bytes(fonts)
        if os.geteuid() == 0:
            for path in [self.scratch, *self.scratch.rglob("*")]:
                os.chown(path, NOBODY, NOBODY)
        argv = command(str(self.scratch), [sys.executable, "-m", "ipykernel_launcher", "-f", str(conn),
                                           "--HistoryManager.enabled=False", "--quiet"])
        self.log = open(self.scratch.parent / (self.scratch.name + ".log"), "wb")
        self.proc = subprocess.Popen(argv, stdin=subprocess.DEVNULL, stdout=self.log, stderr=self.log,
                                     start_new_session=True)
        self.client = BlockingKernelClient(connection_file=str(conn))
        self.client.load_connection_file()
        end = time.monotonic() + self.startup_timeout
        info = json.loads(conn.read_text())
        sockets = [Path(f"{info['ip']}-{info[k]}") for k in
                   ("shell_port", "iopub_port", "stdin_port", "control_port", "hb_port")]
        while not all(p.exists() for p in sockets) and self.alive() and time.monotonic() < end:
            time.sleep(0.05)             # ZMQ does not come back to an ipc path made later
        self.client.start_channels()
        while True:                      # kernel_info until it answers (no heartbeat check)
            if not self.alive() or time.monotonic() > end:
                self.log.flush()
                tail = Path(self.log.name).read_text(errors="replace")[-600:]
                self.kill()
                raise KernelDied(f"the sandboxed kernel did not start: {tail}")
            self.client.kernel_info()
            try:
                reply = self.client.get_shell_msg(timeout=2)
            except Exception:
                continue
            if reply.get("msg_type") == "kernel_info_reply":
                break
        while True:                      # and drain what the start put on iopub
            try:
                self.client.get_iopub_msg(timeout=0.2)
            except Exception:
                break
        keypath = self.scratch / f".grader-key{self.starts}"
        self.key = os.urandom(32)
        fd = os.open(keypath, os.O_WRONLY | os.O_CREAT | os.O_EXCL, 0o600)
        with os.fdopen(fd, "wb") as fh:
            fh.write(self.key)
        if os.geteuid() == 0:
            os.chown(keypath, NOBODY, NOBODY)
        source = HELPER_SOURCE.replace("ENCODE", "_encode").replace("DECODE", "_decode") + _codec_source()
        reply = self.run(HELPER.replace("KEYPATH", repr(str(keypath))).replace("SOURCE", repr(source)),
                         30, silent=True)
        if reply["status"] != "ok":
            raise KernelDied(f"the grader's helper did not load: {reply}")

    def alive(self):
        return self.proc is not None and self.proc.poll() is None

    def run(self, code, timeout, silent=False):
        """Run CODE as one cell; returns {"status": ok|error|timeout|died, "outputs": [...]}."""
        if not self.alive():
            return {"status": "died", "outputs": []}
        kc = self.client
        msg_id = kc.execute(code, silent=silent, store_history=not silent, allow_stdin=False,
                            stop_on_error=False)
        outputs, size, error = [], 0, None
        deadline = time.monotonic() + timeout
        interrupted = False
        while True:
            left = deadline - time.monotonic()
            if left <= 0 and not interrupted:
                interrupted = True
                self.interrupt()
                deadline = time.monotonic() + 3
                continue
            if left <= 0:
                self.kill()
                return {"status": "timeout", "outputs": outputs, "killed": True}
            try:
                msg = kc.get_iopub_msg(timeout=min(left, 1.0))
            except Exception:
                if not self.alive():
                    return {"status": "died", "outputs": outputs}
                continue
            if msg.get("parent_header", {}).get("msg_id") != msg_id:
                continue
            kind, content = msg["msg_type"], msg["content"]
            if kind == "status" and content.get("execution_state") == "idle":
                break
            if kind == "stream":
                text = _cap_text(content.get("text", ""), OUTPUT_BYTES - size)
                size += len(text)
                if text:
                    if outputs and outputs[-1].get("output_type") == "stream" and outputs[-1]["name"] == content["name"]:
                        outputs[-1]["text"] = _cap_text(outputs[-1]["text"] + text, OUTPUT_BYTES)
                    else:
                        outputs.append({"output_type": "stream", "name": content["name"], "text": text})
            elif kind in ("display_data", "execute_result"):
                data = {k: v for k, v in content.get("data", {}).items()
                        if k in ("text/plain", "image/png") and isinstance(v, str)}
                if "text/plain" in data:
                    data["text/plain"] = _cap_text(data["text/plain"], 2000)
                if data.get("image/png") and len(data["image/png"]) > 150_000:
                    data.pop("image/png")
                size += sum(len(v) for v in data.values()) // 10
                if size < OUTPUT_BYTES and data:
                    out = {"output_type": kind, "data": data, "metadata": {}}
                    if kind == "execute_result":
                        out["execution_count"] = content.get("execution_count")
                    outputs.append(out)
            elif kind == "error":
                error = {"output_type": "error", "ename": str(content.get("ename", ""))[:100],
                         "evalue": _cap_text(str(content.get("evalue", "")), 500),
                         "traceback": [_cap_text(str(t), 2000) for t in content.get("traceback", [])[-20:]]}
                outputs.append(error)
        if interrupted:
            return {"status": "timeout", "outputs": outputs}
        return {"status": "error" if error else "ok", "outputs": outputs, "error": error}

    def interrupt(self):
        try:
            msg = self.client.session.msg("interrupt_request", {})
            self.client.control_channel.send(msg)
        except Exception:
            pass

    def kill(self):
        """End the kernel and every process in its sandbox."""
        if self.proc is not None and self.proc.poll() is None:
            try:
                os.killpg(self.proc.pid, signal.SIGKILL)
            except ProcessLookupError:
                pass
            try:
                self.proc.wait(timeout=10)
            except subprocess.TimeoutExpired:
                pass

    def _close_kernel(self):
        if self.client is not None:
            try:
                self.client.stop_channels()
            except Exception:
                pass
        self.kill()
        if getattr(self, "log", None):
            self.log.close()

    def close(self):
        self._close_kernel()
        shutil.rmtree(self.scratch, ignore_errors=True)
        Path(str(self.scratch) + ".log").unlink(missing_ok=True)

    def __enter__(self):
        return self

    def __exit__(self, *exc):
        self.close()


def _cap_text(text, room):
    """TEXT with long lines cut and at most OUTPUT_LINES lines, in ROOM characters."""
    if room <= 0:
        return ""
    lines = text.split("\n")
    cut = [ln if len(ln) <= OUTPUT_LINE_CHARS else ln[:OUTPUT_LINE_CHARS] + " [... line cut]"
           for ln in lines[:OUTPUT_LINES]]
    if len(lines) > OUTPUT_LINES:
        cut.append(f"[... {len(lines) - OUTPUT_LINES} more lines cut]")
    out = "\n".join(cut)
    return out if len(out) <= room else out[:room] + "\n[... output cut]\n"


def _codec_source():
    import inspect
    return ("\nimport base64\n_DTYPES = " + repr(_DTYPES) + "\n"
            + re.sub(r"\bencode\(", "_encode(", inspect.getsource(encode)) + "\n"
            + re.sub(r"\bdecode\(", "_decode(", inspect.getsource(decode)))
