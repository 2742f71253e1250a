r"""Checkers for the notebooks' exercises.

A checker takes the learner's answer -- a value, or a function to call -- tests it, and
returns a :class:`Feedback`: it prints as a short message ("Correct" or what is wrong and
a hint) and is truthy only when the answer is right. A message names the learner's
answer and the mistake it recognises (a sign, a transpose, a shape), never the expected
value: the same exercises are graded as coursework (tools/assignments.py), where hidden
tests decide the grade and no function here may answer an exercise. A checker never raises: an answer that is missing (``None`` or ``...``), a
function that raises, returns ``None``, the wrong shape, NaN or a wrong number all get
a message, so that a notebook with unanswered exercises still runs top to bottom.

One module per notebook holds that notebook's checkers (``so3lib.exercises.hat_map``
for notebook 01, and so on); they are thin wrappers around :func:`check_value` and
:func:`check_function` defined here.
"""

import contextlib
import dis
import functools
import sys
import types

import numpy as np

__all__ = ["Feedback", "check_value", "check_function", "never_raises"]

_NOT_ANSWERED = "No answer yet: replace the `...` (or `None`) with your answer and run the cell again."


class Feedback:
    """Outcome of one check: truthy when correct; its repr is the message."""

    def __init__(self, passed, message):
        self.passed = bool(passed)
        self.message = message

    def __bool__(self):
        return self.passed

    def __repr__(self):
        return self.message

    __str__ = __repr__


def _ok(name, extra=""):
    return Feedback(True, f"Correct: {name}.{(' ' + extra) if extra else ''}")


def _fail(name, why, hint=None):
    text = f"Not yet: {name}. {why}"
    if hint:
        text += f"\nHint: {hint}"
    return Feedback(False, text)


def _fmt(x):
    arr = np.asarray(x)
    if arr.dtype.kind in "fc":
        arr = arr + 0.0          # -0.0 -> 0.0: a printed "-0." looks like a sign error
    if arr.ndim == 0:
        return f"{arr.item():.6g}"
    return np.array2string(arr, precision=4, suppress_small=True, separator=", ")


def _compare(got, expected, name, atol, rtol, hint, context=""):
    """Feedback for a computed answer ``got`` against ``expected`` (both array-like)."""
    where = f" for {context}" if context else ""
    if got is None or got is Ellipsis:
        return None
    try:
        got_arr = np.asarray(got, dtype=complex if np.iscomplexobj(expected) else float)
    except (TypeError, ValueError):
        return _fail(name, f"The answer{where} is a {type(got).__name__}, not a number or "
                           f"an array of numbers.", hint)
    exp_arr = np.asarray(expected)
    if got_arr.shape != exp_arr.shape:
        return _fail(name, f"The answer{where} has shape {got_arr.shape}; expected shape "
                           f"{exp_arr.shape}.", hint)
    if not np.isfinite(got_arr).all():
        return _fail(name, f"The answer{where} contains NaN or inf: {_fmt(got_arr)}. Look for a "
                           "division by zero (at a zero angle, or a half-turn?).", hint)
    if np.allclose(got_arr, exp_arr, atol=atol, rtol=rtol):
        return True
    # The expected value is never shown, nor the difference (with the learner's own answer
    # it would give the expected value away): only what the answer is and the mistake.
    why = f"The answer{where} is {_fmt(got_arr)}, which is not right."
    if np.any(exp_arr != 0) and np.allclose(got_arr, -exp_arr, atol=atol, rtol=rtol):
        why += " It is off by a sign."
    elif exp_arr.ndim >= 2 and exp_arr.shape[-1] == exp_arr.shape[-2] and \
            np.allclose(got_arr, np.swapaxes(exp_arr, -1, -2), atol=atol, rtol=rtol):
        why += " It is the transpose of the expected matrix."
    return _fail(name, why, hint)


def check_value(answer, expected, name, atol=1e-8, rtol=1e-8, hint=None):
    """Check a value the learner computed against the expected one.

    Parameters
    ----------
    answer : object
        The learner's answer; ``None`` or ``...`` means not answered yet.
    expected : array_like
        What the answer must equal; it is never shown in the message.
    name : str
        What the answer is, for the message ("the rotation reached in 1 s").
    atol, rtol : float
        Tolerances of ``np.allclose``.
    hint : str, optional
        Shown when the answer is wrong.
    """
    try:
        if answer is None or answer is Ellipsis:
            return _fail(name, _NOT_ANSWERED)
        result = _compare(answer, expected, name, atol, rtol, hint)
        return _ok(name) if result is True else result
    except Exception as err:  # a checker must never stop the notebook
        return _fail(name, f"The answer could not be checked ({type(err).__name__}: {err}).", hint)


def never_raises(name):
    """Decorate a checker so that any exception inside it becomes a "Not yet" message.

    A checker must never stop the notebook: a learner's answer can be anything, and an
    answer the checker did not foresee gets "could not be checked" and the reason.
    """
    def decorate(checker):
        @functools.wraps(checker)
        def safe(*args, **kwargs):
            try:
                return checker(*args, **kwargs)
            except Exception as err:
                return _fail(name, f"The answer could not be checked ({type(err).__name__}: {err}).")
        return safe
    return decorate


@contextlib.contextmanager
def _calls_watched(name_of):
    """While inside, yield a list that gets a name each time the code entered a watched
    function: ``name_of(code)`` names the code objects that count and returns None for the
    rest. A profile hook (``sys.setprofile``) sees every Python function entered, however
    the learner's code reached it (an alias, ``getattr``, a private helper behind it); the
    previous hook is put back afterwards. Exercises that forbid a call use it."""
    seen = []

    def hook(frame, event, arg):
        if event == "call":
            name = name_of(frame.f_code)
            if name is not None:
                seen.append(name)

    previous = sys.getprofile()
    sys.setprofile(hook)
    try:
        yield seen
    finally:
        sys.setprofile(previous)


def _code_names(func, banned, imported):
    """True if the code of ``func`` (or of a function defined inside it) names one of the
    objects ``banned``: by a global or enclosing-scope name bound to it, or an attribute
    chain such as ``so3lib.so3.log`` that leads to it; or if it imports a name for which
    ``imported(module, name)`` is true (``from so3lib import log`` inside the function).
    Calls hidden from this reading are for :func:`_calls_watched` to catch."""
    code = getattr(func, "__code__", None)
    if not isinstance(code, types.CodeType):
        return False
    env = dict(getattr(func, "__globals__", {}))
    for name, cell in zip(code.co_freevars, getattr(func, "__closure__", None) or ()):
        try:
            env[name] = cell.cell_contents
        except ValueError:          # an empty cell
            pass
    todo = [code]
    while todo:
        c = todo.pop()
        todo += [k for k in c.co_consts if isinstance(k, types.CodeType)]
        obj, module = None, ""
        for ins in dis.get_instructions(c):
            if ins.opname == "IMPORT_NAME":
                module = str(ins.argval)
            elif ins.opname == "IMPORT_FROM" and imported(module, str(ins.argval)):
                return True
            if ins.opname in ("LOAD_GLOBAL", "LOAD_NAME", "LOAD_DEREF", "LOAD_CLOSURE"):
                obj = env.get(ins.argval)
            elif ins.opname in ("LOAD_ATTR", "LOAD_METHOD") and obj is not None:
                obj = getattr(obj, str(ins.argval), None)
            else:
                obj = None
            if obj is not None and any(obj is b for b in banned):
                return True
    return False


def _labelled(inputs):
    """Accept argument tuples, or ``(label, args)`` pairs that name the input in words."""
    for item in inputs:
        if isinstance(item, tuple) and len(item) == 2 and isinstance(item[0], str) \
                and isinstance(item[1], tuple):
            yield item
        else:
            yield None, tuple(item)


def check_function(func, reference, inputs, name, atol=1e-10, rtol=1e-10, hint=None,
                   diagnose=None, reference_name="so3lib"):
    """Call the learner's function on each input and compare with ``reference``.

    Parameters
    ----------
    func : callable or None
        The learner's function. ``None``, ``...``, a function that raises
        ``NotImplementedError`` or returns ``None`` count as not written yet.
    reference : callable
        The function with the same signature that gives the right answer, for an input
        where the course's library gives it (``so3lib.hat``, ``so3lib.log``). Keep a
        reference that answers an exercise out of the public names of
        ``so3lib.exercises``; its results are never shown in a message.
    inputs : list of tuple
        Argument tuples to try, simplest first, so the message names the simplest input
        on which the function goes wrong. An item may also be ``(label, args)``: the
        label ("a half-turn about z") then names the input instead of its numbers.
    name : str
        The function's name in the exercise, for the message.
    hint : str, optional
        Shown when the answer is wrong.
    diagnose : callable, optional
        ``diagnose(got, args)`` gets a wrong but well-formed result (a finite array of
        the right shape) and returns a sentence naming the mistake it recognises, or
        None.
    reference_name : str
        Whose answers the success message says it agrees with.
    """
    if func is None or func is Ellipsis:
        return _fail(name, _NOT_ANSWERED)
    if not callable(func):
        return _fail(name, f"Expected a function, got a {type(func).__name__}.")
    cases = list(_labelled(inputs))
    for label, args in cases:
        shown = label or f"{name}({', '.join(_fmt(a) for a in args)})"
        try:
            got = func(*[np.array(a, copy=True) if isinstance(a, np.ndarray) else a for a in args])
        except NotImplementedError:
            return _fail(name, "Not written yet: the function still raises NotImplementedError.")
        except Exception as err:
            return _fail(name, f"Calling it on {shown} raised {type(err).__name__}: {err}", hint)
        if got is None:
            return _fail(name, f"It returned None on {shown}: is the `return` missing, or is "
                               "the function not written yet?")
        try:
            expected = reference(*args)
            result = _compare(got, expected, name, atol, rtol, None, context=shown)
            if result is not True and diagnose is not None:
                try:
                    got_arr = np.asarray(got, dtype=float)
                except (TypeError, ValueError):    # not numbers: _compare has said so
                    got_arr = None
                extra = diagnose(got_arr, args) if got_arr is not None and \
                    np.shape(got_arr) == np.shape(expected) and np.isfinite(got_arr).all() else None
                if extra:
                    result = Feedback(False, f"{result.message} {extra.strip()}")
        except Exception as err:
            return _fail(name, f"The result on {shown} could not be checked "
                               f"({type(err).__name__}: {err}).", hint)
        if result is not True:
            return Feedback(False, result.message + (f"\nHint: {hint}" if hint else ""))
    count = f"{len(cases)} test input{'s' if len(cases) != 1 else ''}"
    return _ok(name, f"It agrees with {reference_name} on {count}.")
