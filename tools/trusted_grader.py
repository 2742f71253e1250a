"""The grade, decided in a process the learner's code never runs in.

nbgrader's `autograde` keeps its part (the source's test cells put back, the gradebook,
late penalties, the feedback), but its `Execute` step is replaced by `SandboxExecute`:

1. the learner's notebook runs cell by cell in a sandboxed kernel (tools/sandbox.py); a
   test cell runs there only with its visible part, the checker call, whose message goes
   to the feedback. The hidden tests never enter the sandbox.
2. the hidden tests run here, in nbgrader's own process, in a namespace built once per
   assignment from the instructor's source notebook (its set-up cells and solutions run
   here, never the learner's). The names the answer cells define are bound to stand-ins:
   a function calls the learner's function in the sandbox with plain data and gets plain
   numbers and arrays back; a value is fetched as plain data. So `np.allclose` is
   NumPy's own, a test cell cannot be blanked and a result cannot choose how it compares.
3. what the learner's code entered in the libraries during a call (recorded in the
   sandbox, in every thread) is replayed to the hidden test's own profile hook, and the
   names it entered join its code's names, so a check of "without so3lib's C" sees an
   alias, `functools.partial`, `getattr` or a thread. A library function the hidden test
   turns off (`so3lib.C = None`) is turned off in the sandbox too, for every way of
   reaching it.
4. the test cell's outputs are the checker's message and, when the hidden test failed,
   an error that says what happened (a hidden test failed, not answered, a time limit,
   what the learner's code raised). stderr never costs points.
"""

import ast
import contextlib
import functools
import hashlib
import hmac
import io
import itertools
import operator
import os
import socket
import sys
import time
import types
from pathlib import Path

from tools import sandbox

BEGIN_HIDDEN, END_HIDDEN = "### BEGIN HIDDEN TESTS", "### END HIDDEN TESTS"
BEGIN_SOLUTION = "### BEGIN SOLUTION"


def split_test(source):
    """(visible, hidden) code of a test cell."""
    visible, hidden, inside = [], [], False
    for line in source.splitlines():
        if line.strip() == BEGIN_HIDDEN:
            inside = True
        elif line.strip() == END_HIDDEN:
            inside = False
        else:
            (hidden if inside else visible).append(line)
    return "\n".join(visible), "\n".join(hidden)


def _by_source(fn):
    """FN(source, ...) remembered for the cells every submission of an assignment shares
    (a warm grading worker reads the same handed-out cells in every notebook); long cells,
    which only a learner writes, are worked out each time."""
    cached = functools.lru_cache(maxsize=4096)(fn)

    def call(source, *rest):
        return cached(source, *rest) if len(source) < 20_000 else fn(source, *rest)
    call.__doc__, call.__name__ = fn.__doc__, fn.__name__
    return call


@_by_source
def _python(source):
    from IPython.core.inputtransformer2 import TransformerManager
    return TransformerManager().transform_cell(source)


def stub_names(source):
    """(functions, values) that an answer cell's stub defines."""
    stub = source.split(BEGIN_SOLUTION)[0]
    try:
        tree = ast.parse(_python(stub))
    except SyntaxError:
        return [], []
    funcs = [n.name for n in tree.body if isinstance(n, (ast.FunctionDef, ast.AsyncFunctionDef))]
    values = []
    for n in tree.body:
        targets = n.targets if isinstance(n, ast.Assign) else [n.target] if isinstance(n, ast.AnnAssign) else []
        for t in targets:
            for node in ast.walk(t):
                if isinstance(node, ast.Name):
                    values.append(node.id)
    return funcs, values


def _meta(cell):
    return cell.get("metadata", {}).get("nbgrader", {})


def is_test(cell):
    m = _meta(cell)
    return cell.get("cell_type") == "code" and m.get("grade") and not m.get("solution")


def is_answer(cell):
    m = _meta(cell)
    return cell.get("cell_type") == "code" and m.get("solution") and not m.get("grade")


# --- the instructor's namespace ---------------------------------------------------------

_REFERENCE = {}


def reference_namespace(source_path):
    """The namespace of the source notebook run here (set-up cells and solutions; no test
    cell), built once per file and process."""
    import nbformat
    path = Path(source_path).resolve()
    key = (str(path), path.stat().st_mtime)
    if key in _REFERENCE:
        return _REFERENCE[key]
    # figures drawn here go nowhere; set the backend in this process only (an MPLBACKEND in
    # os.environ would reach every kernel this process starts later, as nbval's do)
    import matplotlib
    matplotlib.use("agg")
    from IPython.core.interactiveshell import InteractiveShell
    shell = InteractiveShell.instance()
    shell.user_ns.clear()
    shell.init_user_ns()
    nb = nbformat.read(str(path), as_version=4)
    here = os.getcwd()
    os.chdir(path.parent)
    try:
        with contextlib.redirect_stdout(io.StringIO()), contextlib.redirect_stderr(io.StringIO()):
            for source in needed_cells(nb):
                shell.run_cell(source, store_history=False, silent=True)
    finally:
        os.chdir(here)
        try:
            import matplotlib.pyplot as plt
            plt.close("all")
        except Exception:
            pass
    ns = {k: v for k, v in shell.user_ns.items() if not k.startswith("_i") and k not in ("In", "Out", "exit", "quit")}
    _REFERENCE[key] = ns
    return ns


@_by_source
def _tree(source):
    """The syntax tree of a cell (IPython syntax turned into Python first); read, never changed."""
    return ast.parse(_python(source))


@_by_source
def _defines_uses(source):
    """(names a cell binds at top level, names it reads), or None when it cannot be read."""
    try:
        tree = _tree(source)
    except SyntaxError:
        return None
    defined, used = set(), set()
    for node in ast.walk(tree):
        if isinstance(node, ast.Name):
            (defined if isinstance(node.ctx, ast.Store) else used).add(node.id)
        elif isinstance(node, (ast.FunctionDef, ast.AsyncFunctionDef, ast.ClassDef)):
            defined.add(node.name)
        elif isinstance(node, ast.alias):
            defined.add((node.asname or node.name).split(".")[0])
        elif isinstance(node, ast.Attribute):
            pass
    return frozenset(defined), frozenset(used)


def needed_cells(nb):
    """The source cells the hidden tests need, in order: those that bind a name a hidden
    test reads, and, in turn, what those cells read (figures and prose cells are skipped:
    they cost most of a notebook's time). A cell that cannot be parsed is kept."""
    import builtins
    cells = [c for c in nb.cells if c.cell_type == "code" and not is_test(c)]
    learner = set()
    for c in nb.cells:
        if is_answer(c):
            f, v = stub_names(c.source)
            learner |= set(f) | set(v)
    needed = set()
    for c in nb.cells:
        if is_test(c):
            info = _defines_uses(split_test(c.source)[1])
            needed |= (info[1] - info[0]) if info else set()
    needed -= learner | set(dir(builtins))
    keep = [False] * len(cells)
    for i in range(len(cells) - 1, -1, -1):
        info = _defines_uses(cells[i].source)
        if info is None or info[0] & needed:
            keep[i] = True
            if info:
                needed |= info[1] - info[0] - set(dir(builtins))
    # a kept cell may read a name bound only later in the notebook's order: keep earlier
    # binders of everything the kept cells read
    for i in range(len(cells)):
        info = _defines_uses(cells[i].source)
        if info and not keep[i] and info[0] & needed and not info[1] - needed - info[0]:
            keep[i] = True
    return [c.source for c, k in zip(cells, keep) if k]


def figure_cells(cells, figures):
    """Indices of the code cells that only draw a figure: a `hide-input` cell exactly as
    handed out (its source is one of FIGURES), none of whose names a later cell reads. Their
    figures are not in the feedback, and drawing them costs a third of a notebook's time."""
    skip, needed = set(), set()
    for i in range(len(cells) - 1, -1, -1):
        cell = cells[i]
        if cell.get("cell_type") != "code":
            continue
        info = _defines_uses(cell.source)
        if info is None:            # a cell that cannot be read: keep every cell before it
            return skip
        if (cell.source in figures and "hide-input" in cell.get("metadata", {}).get("tags", [])
                and not info[0] & needed):
            skip.add(i)
            continue
        # live before this cell: what it reads that it did not bind, and what later cells
        # read that it does not bind again
        needed = (needed - info[0]) | (info[1] - info[0])
    return skip


# Calls and statements after which a handed-out cell always runs in full: what they change
# cannot be read off the names in the code.
_OPAQUE_CALLS = {"exec", "eval", "compile", "globals", "locals", "vars", "setattr", "delattr",
                 "__import__", "get_ipython", "open", "input", "breakpoint"}


def _root(node):
    """The name at the root of an attribute or subscript chain (x in x.a[0].b), or None."""
    while isinstance(node, (ast.Attribute, ast.Subscript, ast.Starred)):
        node = node.value
    return node.id if isinstance(node, ast.Name) else None


def _chain(node):
    """The attribute names along a call's function (np.random.seed: random, seed)."""
    names = []
    while isinstance(node, (ast.Attribute, ast.Subscript)):
        if isinstance(node, ast.Attribute):
            names.append(node.attr)
        node = node.value
    return names


def _rebinds(node):
    """The names a top-level statement always binds to a new object (x = ..., def x,
    import x): what it held before is not seen after."""
    targets = []
    if isinstance(node, ast.Assign):
        targets = node.targets
    elif isinstance(node, ast.AnnAssign) and node.value is not None:
        targets = [node.target]
    elif isinstance(node, (ast.FunctionDef, ast.AsyncFunctionDef, ast.ClassDef)):
        return {node.name}
    elif isinstance(node, (ast.Import, ast.ImportFrom)):
        return {(a.asname or a.name).split(".")[0] for a in node.names if a.name != "*"}
    names = set()
    for t in targets:
        parts = t.elts if isinstance(t, (ast.Tuple, ast.List)) else [t]
        for part in parts:
            part = part.value if isinstance(part, ast.Starred) else part
            if isinstance(part, ast.Name):
                names.add(part.id)
    return names


def _scopes(code):
    """(global names CODE binds, global names it reads): at its top level, and inside its
    functions, classes and comprehensions (their parameters and locals left out)."""
    binds, top, inner = _scopes3(code)
    return binds, top | inner


def _scopes3(code):
    """(global names CODE binds, reads at its top level, reads inside its functions,
    classes and comprehensions)."""
    import symtable
    binds, top_reads, inner_reads = set(), set(), set()
    todo = [symtable.symtable(code, "<cell>", "exec")]
    while todo:
        table = todo.pop()
        top = table.get_type() == "module"
        for sym in table.get_symbols():
            if top or sym.is_global():
                if sym.is_referenced():
                    (top_reads if top else inner_reads).add(sym.get_name())
                if top and (sym.is_assigned() or sym.is_imported()):
                    binds.add(sym.get_name())
        todo += table.get_children()
    return binds, top_reads, inner_reads


def _changes(node, modules, statement):
    """The names whose objects running NODE may change in place: x in x.a = .., x[i] = ..,
    x.method(..) (a module's only through np.random or as a statement of its own, such as
    plt.show()), and f(x) (a callee may change its argument). Function bodies run later,
    when called: their changes belong to the call."""
    changed, todo = set(), [node]
    while todo:
        sub = todo.pop()
        if isinstance(sub, (ast.FunctionDef, ast.AsyncFunctionDef, ast.Lambda)):
            todo += [d for d in getattr(sub, "decorator_list", [])]
            todo += [d for d in sub.args.defaults + sub.args.kw_defaults if d is not None]
            continue
        if isinstance(sub, (ast.Attribute, ast.Subscript)) and isinstance(sub.ctx, (ast.Store, ast.Del)):
            if (r := _root(sub)) is not None:
                changed.add(r)
        elif isinstance(sub, ast.Call):
            if isinstance(sub.func, ast.Attribute) and (r := _root(sub.func)) is not None and (
                    r not in modules or "random" in _chain(sub.func) or statement is sub):
                changed.add(r)
            for arg in [*sub.args, *(k.value for k in sub.keywords)]:
                if (r := _root(arg)) is not None and r not in modules:
                    changed.add(r)
        todo += list(ast.iter_child_nodes(sub))
    return changed


def _statement(node, modules):
    """(names STATEMENT may bind or change, names it reads), or None when it must run
    whatever is needed (it reaches state the names do not show)."""
    if isinstance(node, (ast.Global, ast.Nonlocal, ast.Delete)):
        return None
    for sub in ast.walk(node):
        if isinstance(sub, (ast.Global, ast.Nonlocal)):
            return None
        if isinstance(sub, ast.Call) and isinstance(sub.func, ast.Name) and sub.func.id in _OPAQUE_CALLS:
            return None
    try:
        binds, reads = _scopes(ast.unparse(node))
    except SyntaxError:
        return None
    expr = node.value if isinstance(node, ast.Expr) else None
    return binds | _changes(node, modules, expr), reads


@_by_source
def _readable(source, modules):
    """(statements, their (binds, reads)) of a code cell, or None when what it reads or
    changes cannot be told from its names: IPython syntax (magics, !shell), exec, eval,
    globals(), open, global, del. A cell with two statements on one line or a decorator
    is one statement here (it runs whole or not at all)."""
    try:
        transformed = _python(source)
        tree = ast.parse(transformed)
    except SyntaxError:
        return None
    if transformed.rstrip("\n") != source.rstrip("\n"):
        return None
    body = tree.body
    infos = [_statement(node, modules) for node in body]
    if any(info is None for info in infos):
        return None
    if any(a.end_lineno >= b.lineno for a, b in zip(body, body[1:])) or \
            any(getattr(n, "decorator_list", None) for n in body):
        whole = ast.Module(body=[ast.Pass(lineno=1, col_offset=0, end_lineno=len(source.splitlines()) or 1,
                                          end_col_offset=0)], type_ignores=[])
        binds = set().union(*(b for b, _ in infos))
        reads = set().union(*(r for _, r in infos))
        return whole.body, [(binds, reads)]
    return body, infos


def run_plan(cells, handed_out, learner):
    """What of each code cell to run when grading: {index: code}; a cell not in it is not
    run. Answer and test cells, and the cells the learner wrote or changed, run in full.
    A cell handed out unchanged (its source in HANDED_OUT) runs only the statements that
    the grade may depend on. Going back from the last test: at each test, the names its
    visible part reads, the learner's names (LEARNER) and what the learner's functions
    read when called are needed; a statement is kept when it may bind or change a needed
    name (x = .., def x, import x, x.a = .., x[i] = .., x.method(..), f(x), a draw from
    a random generator), and then what it reads is needed, what it binds anew no longer.
    A cell whose effects its names cannot show (magics, exec, global, open, ...) runs in
    full, with every cell before it. So drawing the figures and the notebook's own checks,
    most of a notebook's time, is left out when nothing graded depends on them."""
    import builtins
    safe_builtins = set(dir(builtins)) - _OPAQUE_CALLS
    code = {i: c for i, c in enumerate(cells) if c.get("cell_type") == "code"}
    modules, answer_reads = set(), set()
    for c in code.values():
        try:
            tree = _tree(c.source)
        except SyntaxError:
            continue
        modules |= {(a.asname or a.name).split(".")[0] for sub in ast.walk(tree)
                    if isinstance(sub, ast.Import) for a in sub.names}
        if is_answer(c):            # what the learner's functions read when called
            answer_reads |= _scopes3(ast.unparse(tree))[2]
    plan, needed, everything = {}, set(), False
    for i in sorted(code, reverse=True):
        cell = code[i]
        if everything:
            plan[i] = cell.source
            continue
        if is_test(cell):
            visible = _readable(split_test(cell.source)[0], frozenset(modules))
            if visible is None:
                everything = True
            else:
                needed |= {n for _, reads in visible[1] for n in reads}
            needed |= set(learner) | answer_reads
            plan[i] = cell.source
            continue
        readable = _readable(cell.source, frozenset(modules))
        if readable is None:
            plan[i] = cell.source
            everything = True
            continue
        body, infos = readable
        if is_answer(cell) or cell.source not in handed_out:
            plan[i] = cell.source
            for node, (binds, reads) in zip(reversed(body), reversed(infos)):
                needed = (needed - _rebinds(node)) | (reads - safe_builtins)
            continue
        kept = []
        for node, (binds, reads) in zip(reversed(body), reversed(infos)):
            if binds & needed:
                kept.append(node)
                needed = (needed - _rebinds(node)) | (reads - safe_builtins)
        if kept:
            lines = cell.source.splitlines()
            plan[i] = "\n".join("\n".join(lines[n.lineno - 1:n.end_lineno]) for n in reversed(kept))
    return plan


# --- stand-ins for the learner's names ---------------------------------------------------

class StudentError(Exception):
    """The learner's code raised, or returned something that is not plain data."""

    def __init__(self, name, message):
        super().__init__(message)
        self.ename = name


class TimeLimit(Exception):
    pass


class NotAnswered(Exception):
    pass


class Unanswered:
    """The value of a stub left as handed out (`c = ...`): any use of it fails."""

    def __init__(self, name):
        self._name = name

    def _fail(self, *args, **kwargs):
        raise NotAnswered(f"{self._name} is still `...`")

    __float__ = __int__ = __index__ = __complex__ = __array__ = __iter__ = __len__ = _fail
    __getitem__ = __bool__ = __add__ = __mul__ = __sub__ = __truediv__ = __eq__ = _fail
    __hash__ = object.__hash__

    def __repr__(self):
        return "Ellipsis"


class FakeCode:
    """What the hidden test may read of the learner's code: names and inner code."""

    def __init__(self, desc, extra=()):
        self.co_name = desc.get("name", "")
        self.co_names = tuple(desc.get("names", [])) + tuple(sorted(set(extra) - set(desc.get("names", []))))
        self.co_consts = tuple(FakeCode(d) for d in desc.get("consts", []))
        self.co_filename = "<learner>"
        self.co_firstlineno = 0
        self.co_freevars = ()


class FakeFrame:
    def __init__(self, code):
        self.f_code = code


class _Named:
    def __init__(self, name):
        self.__name__ = name


_CODE_INDEX = {}


def _trusted_code(filename, line, name):
    """This process's code object at FILENAME:LINE called NAME (for the profile hook's
    `frame.f_code is ...` and `in {...}`), or a stand-in with those three."""
    if filename not in _CODE_INDEX:
        index = {}
        for module in list(sys.modules.values()):
            if getattr(module, "__file__", None) and os.path.realpath(module.__file__) == os.path.realpath(filename):
                _index_module(module, index)
        _CODE_INDEX[filename] = index
    code = _CODE_INDEX[filename].get((line, name))
    if code is None:
        code = FakeCode({"name": name})
        code.co_filename, code.co_firstlineno = filename, line
    return code


def _index_module(module, index):
    import inspect
    seen, todo = set(), list(vars(module).values())
    while todo:
        obj = todo.pop()
        if id(obj) in seen or len(seen) > 20000:
            continue
        seen.add(id(obj))
        if isinstance(obj, types.CodeType):
            index.setdefault((obj.co_firstlineno, obj.co_name), obj)
            todo += [k for k in obj.co_consts if isinstance(k, types.CodeType)]
            continue
        for attr in ("__wrapped__", "_implementation", "__func__", "fget", "fset"):
            inner = getattr(obj, attr, None) if not isinstance(obj, types.ModuleType) else None
            if inner is not None:
                todo.append(inner)
        if inspect.isfunction(obj):
            todo.append(obj.__code__)
        elif inspect.isclass(obj) and getattr(obj, "__module__", None) == module.__name__:
            todo += list(vars(obj).values())


class Channel:
    """The socket between this process and the grader's helper in the sandboxed kernel."""

    def __init__(self, run):
        self.run = run
        self.sock = self.stream = None
        self.entered_names = {}

    def open(self, budget):
        box = self.run.box
        path = box.scratch / "grader.sock"
        path.unlink(missing_ok=True)
        listener = socket.socket(socket.AF_UNIX, socket.SOCK_STREAM)
        listener.bind(str(path))
        if os.geteuid() == 0:
            os.chown(path, sandbox.NOBODY, sandbox.NOBODY)
        listener.listen(1)
        listener.settimeout(min(budget, 20))
        # the helper's audit hook serves; a stand-in the learner put in its place cannot
        # sign its answers (Channel.request)
        self.msg_id = box.client.execute(f"__import__('sys').audit('so3grade.serve', {str(path)!r})",
                                         silent=True, store_history=False)
        try:
            self.sock, _ = listener.accept()
        except OSError:
            raise StudentError("GraderUnreachable", "the grader could not reach the notebook's "
                               "kernel (was the kernel changed or stopped?)") from None
        finally:
            listener.close()
        self.stream = self.sock.makefile("rwb")

    def request(self, req):
        if self.stream is None:
            self.open(self.run.left())
        self.sock.settimeout(max(0.1, self.run.left()))
        req = dict(req, nonce=os.urandom(16).hex())
        sent = repr(req).encode()          # a Python literal: the helper reads it without json
        try:
            self.stream.write(sent + b"\n")
            self.stream.flush()
            line = self.stream.readline(200_000_000)
        except (socket.timeout, TimeoutError):
            self.run.time_out()
            raise TimeLimit() from None
        except OSError:
            line = b""
        if not line:
            self.close()
            if not self.run.box.alive():
                raise StudentError("KernelDied", "the notebook's kernel stopped (memory or process "
                                   "limit, or it was ended)")
            raise StudentError("GraderUnreachable", "the kernel stopped answering the grader")
        sig, _, body = line.rstrip(b"\n").partition(b" ")
        expected = hmac.new(self.run.box.key, sent + b"\n" + body, hashlib.sha256).hexdigest().encode()
        if not hmac.compare_digest(sig, expected):
            raise StudentError("GraderTampered", "the kernel's answer to the grader was not written "
                               "by the grader's helper (was the kernel or the helper replaced?)")
        try:
            return ast.literal_eval(body.decode())
        except (ValueError, SyntaxError, UnicodeDecodeError):
            raise StudentError("TypeError", "the kernel answered with something that is not data") from None

    def close(self):
        if self.stream is not None:
            try:
                self.sock.settimeout(2)
                self.stream.write(repr({"op": "done"}).encode() + b"\n")
                self.stream.flush()
            except OSError:
                pass
            with contextlib.suppress(OSError):
                self.sock.close()
            self.stream = self.sock = None
            self.run.wait_idle(self.msg_id, 5)


def _disabled(ns):
    """(module, name) of library functions the hidden test has set to None."""
    out = []
    for mod_name, (pristine, values) in _PRISTINE_NAMES.items():   # asked at every call: quick
        space = getattr(sys.modules.get(mod_name), "__dict__", None)
        if space is None:
            continue
        try:
            if not any(map(operator.is_, values(space), itertools.repeat(None))):
                continue
        except KeyError:                     # a name deleted: look at each one
            pass
        out += [(mod_name, name) for name in pristine if name in space and space[name] is None]
    return out


_PRISTINE = {}
_PRISTINE_NAMES = {}      # module: (its callables' names, a getter of their values now)


def _snapshot():
    for mod_name, module in list(sys.modules.items()):
        if mod_name.startswith(("so3lib", "numpy.linalg", "scipy.linalg")) and mod_name not in _PRISTINE:
            _PRISTINE[mod_name] = {n: v for n, v in vars(module).items() if callable(v)}
            names = tuple(_PRISTINE[mod_name])
            if names:
                getter = operator.itemgetter(*names)
                _PRISTINE_NAMES[mod_name] = (names, (lambda space, g=getter: (g(space),)) if len(names) == 1
                                             else getter)


def _code_key(fn):
    """(file, first line, name) of a library function's code, as the sandbox reports it."""
    for attr in ("_implementation", "__wrapped__"):
        fn = getattr(fn, attr, fn)
    code = getattr(fn, "__code__", None)
    if not isinstance(code, types.CodeType):
        return None
    return (code.co_filename, code.co_firstlineno, code.co_name)


class StudentFunction:
    """Calls the learner's function NAME in the sandbox with plain data."""

    def __init__(self, channel, name):
        self._channel, self.__name__, self.__qualname__ = channel, name, name

    def __call__(self, *args, **kwargs):
        if kwargs:
            raise TypeError("keyword arguments are not passed to the sandbox")
        ch = self._channel
        disabled = _disabled(None)
        reply = ch.request({"op": "call", "name": self.__name__, "args": sandbox.encode(list(args)),
                            "disabled": disabled})
        entered = [tuple(e) for e in reply.get("entered", [])]
        # a function the hidden test turned off, entered all the same (rebuilt from its code
        # object, reloaded): the code swap in the sandbox missed it, the record did not
        ruled_out = {_code_key(_PRISTINE[m][n]): n for m, n in disabled}
        reached = sorted({ruled_out[e] for e in entered if e in ruled_out})
        if reached:
            raise StudentError("RuntimeError", f"{self.__name__} used {', '.join(reached)}, "
                               "which this exercise rules out")
        ch.entered_names.setdefault(self.__name__, set()).update(e[2] for e in entered)
        hook = sys.getprofile()
        if hook is not None and entered:
            sys.setprofile(None)
            try:
                for filename, line, name in entered:
                    hook(FakeFrame(_trusted_code(filename, line, name)), "call", None)
            finally:
                sys.setprofile(hook)
        if reply.get("tampered"):
            raise StudentError("RuntimeError", f"{self.__name__} reached into the grader's watch "
                               f"({', '.join(map(str, reply['tampered']))[:200]})")
        if "error" in reply:
            raise StudentError(*reply["error"])
        try:
            return sandbox.decode(reply["ok"])
        except (KeyError, ValueError):
            raise StudentError("TypeError", f"{self.__name__} returned something that is not numbers") from None

    def _describe(self):
        reply = self._channel.request({"op": "describe", "name": self.__name__})
        return reply.get("ok") or {}

    @property
    def __code__(self):
        desc = self._describe()
        return FakeCode(desc.get("code", {}), self._channel.entered_names.get(self.__name__, ()))

    @property
    def __globals__(self):
        desc = self._describe()
        space = {}
        for name, g in desc.get("globals", {}).items():
            if "own" in g:
                fn = _Named(g.get("name", name))
                fn.__code__ = FakeCode(g["own"], self._channel.entered_names.get(name, ()))
                fn.__globals__ = space
                space[name] = fn
            else:
                space[name] = _Named(g.get("name", ""))
        return space


def fetch_value(channel, name):
    reply = channel.request({"op": "value", "name": name})
    if "error" in reply:
        raise StudentError(*reply["error"])
    value = sandbox.decode(reply["ok"])
    return Unanswered(name) if value is Ellipsis else value


# --- one notebook ------------------------------------------------------------------------

class NotebookRun:
    """The learner's notebook in its sandbox, cell by cell, with the hidden tests here."""

    def __init__(self, nb, source_path, files=None, timeout=60, notebook_timeout=900):
        self.nb, self.source_path, self.files = nb, Path(source_path), files
        self.timeout, self.notebook_timeout = timeout, notebook_timeout
        self.box, self.done = None, []           # cells run so far (re-run after a restart)
        self.deadline = None

    def left(self):
        return self.deadline - time.monotonic()

    def time_out(self):
        """A call into the sandbox ran out of time: interrupt, or end and restart it."""
        self.box.interrupt()
        self.box.kill()
        self.restart()

    def restart(self):
        self.box.start()
        for code in self.done:
            if self.box.run(code, self.timeout)["status"] in ("timeout", "died"):
                break

    def wait_idle(self, msg_id, timeout):
        end = time.monotonic() + timeout
        while time.monotonic() < end:
            try:
                msg = self.box.client.get_iopub_msg(timeout=0.5)
            except Exception:
                if not self.box.alive():
                    return
                continue
            if (msg.get("parent_header", {}).get("msg_id") == msg_id and msg["msg_type"] == "status"
                    and msg["content"].get("execution_state") == "idle"):
                return
        self.box.interrupt()

    def grade(self):
        from nbformat import from_dict
        _snapshot()
        reference = reference_namespace(self.source_path)
        _snapshot()
        source = __import__("nbformat").read(str(self.source_path), as_version=4)
        stubs = {c.metadata.get("nbgrader", {}).get("grade_id"): c.source.split(BEGIN_SOLUTION)[0].rstrip()
                 for c in source.cells if is_answer(c)}
        funcs, values = set(), set()
        for c in source.cells:
            if is_answer(c):
                f, v = stub_names(c.source)
                funcs |= set(f)
                values |= set(v)
        figures = {c.source for c in source.cells
                   if c.cell_type == "code" and "hide-input" in c.metadata.get("tags", [])}
        handed_out = {c.source for c in source.cells
                      if c.cell_type == "code" and not is_answer(c) and not is_test(c)}
        skip = figure_cells(self.nb.cells, figures)
        full = {i: c.source for i, c in enumerate(self.nb.cells)
                if c.cell_type == "code" and i not in skip}
        # first only what the grade depends on (run_plan); a notebook that loses a point
        # that way, other than for a stub or a time limit, is graded again with every cell
        # run (but the figures nothing reads), and that run decides
        plan = run_plan(self.nb.cells, handed_out, funcs | values)
        cells = [from_dict(c) for c in self.nb.cells]
        failed = self._run(plan, reference, stubs, funcs, values)
        if failed and plan != full:
            self.nb.cells = cells
            self.done = []
            self._run(full, reference, stubs, funcs, values)
        return self.nb

    def _run(self, plan, reference, stubs, funcs, values):
        """Run the code cells of PLAN ({index: code}) in a new sandbox, the hidden tests
        here; the outputs go into self.nb. True when a hidden test failed for a reason
        other than a stub or a time limit."""
        from nbformat import from_dict
        failed = False
        end = time.monotonic() + self.notebook_timeout
        self.box = sandbox.Sandbox(self.files)
        try:
            answers = {}
            for index, cell in enumerate(self.nb.cells):
                if cell.cell_type != "code":
                    continue
                if index not in plan:
                    cell.outputs = []
                    continue
                if time.monotonic() > end:
                    cell.outputs = [_error("CellTimeoutError", f"time limit: the notebook ran "
                                           f"longer than {self.notebook_timeout} s in all; this cell was not run")] \
                        if is_test(cell) else []
                    continue
                if is_answer(cell):
                    answers[_meta(cell).get("grade_id")] = cell.source
                if not is_test(cell):
                    result = self.box.run(plan[index], self.timeout)
                    cell.outputs = [from_dict(o) for o in result["outputs"]]
                    if result["status"] == "timeout":
                        cell.outputs.append(from_dict(_error("CellTimeoutError", f"time limit: the cell ran "
                                                             f"longer than {self.timeout} s and was stopped")))
                    if result.get("killed") or result["status"] == "died":
                        self.restart()
                    elif result["status"] != "timeout":
                        self.done.append(plan[index])
                    continue
                visible, hidden = split_test(cell.source)
                result = self.box.run(visible, self.timeout)
                if result.get("killed") or result["status"] == "died":
                    self.restart()
                outputs = [_as_stdout(o) for o in result["outputs"] if o.get("output_type") != "error"]
                gid = _meta(cell).get("grade_id", "")
                answer_id = gid.rsplit("-", 1)[0] + "-answer"
                stub = answer_id in stubs and answers.get(answer_id, "").strip() == stubs[answer_id].strip()
                failure = self.hidden_test(hidden, reference, funcs, values, stub)
                if failure:
                    outputs.append(failure)
                    # a stub or a time limit is the same whatever else ran
                    failed = failed or failure["ename"] not in ("NotAnswered", "CellTimeoutError")
                cell.outputs = [from_dict(o) for o in outputs]
        finally:
            self.box.close()
        return failed

    def hidden_test(self, hidden, reference, funcs, values, stub):
        """None when the hidden test passes, else the error output that says why."""
        self.deadline = time.monotonic() + self.timeout
        channel = Channel(self)
        ns = dict(reference)
        try:
            code = compile(_python(hidden), "<hidden test>", "exec")
            used = _names_in(code)
            for name in funcs & used:
                ns[name] = StudentFunction(channel, name)
            for name in values & used:
                ns[name] = fetch_value(channel, name)
            hook = sys.getprofile()
            try:
                with contextlib.redirect_stdout(io.StringIO()), contextlib.redirect_stderr(io.StringIO()):
                    exec(code, ns)
            finally:
                sys.setprofile(hook)
            return None
        except TimeLimit:
            return _error("CellTimeoutError", f"time limit: the learner's code ran longer than "
                          f"{self.timeout} s and was stopped")
        except NotAnswered as err:
            return _error("NotAnswered", f"not answered: {err}")
        except StudentError as err:
            if stub and err.ename in ("NotImplementedError", "NameError"):
                return _error("NotAnswered", "not answered: the answer cell is the stub as handed out")
            if err.ename == "KeyboardInterrupt":
                return _error("KeyboardInterrupt", "your code raised KeyboardInterrupt itself "
                              "(this is not a time limit)")
            return _error(err.ename, f"your code raised {err.ename}: {err}")
        except AssertionError as err:
            if stub:
                return _error("NotAnswered", "not answered: the answer cell is the stub as handed out")
            return _error("AssertionError", str(err)[:300])
        except Exception as err:
            if stub:
                return _error("NotAnswered", "not answered: the answer cell is the stub as handed out")
            return _error(type(err).__name__, f"the hidden test stopped: {type(err).__name__}: "
                          f"{str(err)[:200]}")
        finally:
            channel.close()


def _names_in(code):
    names, todo = set(), [code]
    while todo:
        c = todo.pop()
        names |= set(c.co_names) | set(c.co_varnames) | set(c.co_freevars)
        todo += [k for k in c.co_consts if isinstance(k, types.CodeType)]
    return names


def _error(name, value):
    return {"output_type": "error", "ename": name, "evalue": value, "traceback": [f"{name}: {value}"]}


def _as_stdout(out):
    """stderr (a warning) shown in the test cell as text: it never costs the points."""
    if out.get("output_type") == "stream" and out.get("name") == "stderr":
        return {"output_type": "stream", "name": "stdout", "text": "(stderr) " + out.get("text", "")}
    if out.get("output_type") == "execute_result":      # a number here would set the points
        return {"output_type": "display_data", "data": out.get("data", {}), "metadata": {}}
    return out


# --- nbgrader's side ---------------------------------------------------------------------

try:
    from nbconvert.preprocessors import Preprocessor
    from traitlets import Integer, Unicode
except ImportError:          # pragma: no cover
    Preprocessor = object


class SandboxExecute(Preprocessor):
    """nbgrader's Execute, replaced: the learner's code in the sandbox, the verdicts here."""

    enabled = True          # nbconvert's preprocessors are off unless enabled
    course = Unicode("").tag(config=True)
    timeout = Integer(60).tag(config=True)
    notebook_timeout = Integer(900).tag(config=True)

    def preprocess(self, nb, resources):
        info = resources.get("nbgrader", {})
        assignment, notebook = info.get("assignment"), info.get("notebook")
        source = Path(self.course) / "source" / assignment / f"{notebook}.ipynb"
        files = Path(self.course) / "autograded" / info.get("student", "") / assignment
        run = NotebookRun(nb, source, files if files.is_dir() else None, self.timeout, self.notebook_timeout)
        return run.grade(), resources
