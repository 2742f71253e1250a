"""The exercise checkers: helpful feedback, and never an exception (so3lib.exercises)."""

import re

import numpy as np
import pytest

import so3lib
from so3lib.exercises import Feedback, check_function, check_value

INPUTS = [([1.0, 2.0, 3.0],), ([0.0, 0.0, 0.0],)]


def check_hat(func):
    return check_function(func, so3lib.hat, INPUTS, "hat")


def test_correct_function_passes():
    fb = check_hat(lambda a: so3lib.hat(a))
    assert fb and isinstance(fb, Feedback) and repr(fb).startswith("Correct: hat")


@pytest.mark.parametrize("student, says", [
    (None, "No answer yet"),
    (..., "No answer yet"),
    (42, "Expected a function"),
    (lambda a: (_ for _ in ()).throw(NotImplementedError()), "Not written yet"),
    (lambda a: None, "returned None"),
    (lambda a: 1 / 0, "raised ZeroDivisionError"),
    (lambda a: np.zeros(3), r"has shape \(3,\); expected shape \(3, 3\)"),
    (lambda a: np.full((3, 3), np.nan), "NaN or inf"),
    (lambda a: -so3lib.hat(a), "off by a sign"),
    (lambda a: "hat", "not a number"),
    (lambda a: np.eye(3), "is not right"),
])
def test_wrong_functions_get_a_message_not_an_exception(student, says):
    fb = check_hat(student)
    assert not fb
    assert repr(fb).startswith("Not yet: hat.")
    assert re.search(says, repr(fb)), repr(fb)


def test_transposed_matrix_is_recognised():
    R = so3lib.exp([0.1, 0.2, 0.3])
    fb = check_value(R.T, R, "the rotation")
    assert not fb and "transpose" in repr(fb)


def test_values():
    assert check_value(np.pi, np.pi, "the angle")
    assert "No answer yet" in repr(check_value(None, 1.0, "x"))
    assert "No answer yet" in repr(check_value(..., 1.0, "x"))
    fb = check_value(3.0, np.pi, "the angle", hint="Use atan2.")
    assert not fb and "Hint: Use atan2." in repr(fb)
    assert not check_value([1.0, 2.0], [1.0, 2.0, 3.0], "v")
    assert check_value(1 + 1j, 1 + 1j, "z")
    assert not check_value(object(), 1.0, "x")


def test_labelled_inputs_diagnosis_and_reference_name():
    cases = [("the zero vector", ([0.0, 0.0, 0.0],)), ("a = (1, 2, 3)", ([1.0, 2.0, 3.0],))]

    def diagnose(got, args):
        return "You returned hat(a) squared." if np.allclose(got, so3lib.hat(args[0]) @ so3lib.hat(args[0])) else None

    fb = check_function(lambda a: so3lib.hat(a) @ so3lib.hat(a), so3lib.hat, cases, "hat",
                        diagnose=diagnose, hint="Build the matrix entry by entry.")
    assert not fb
    text = repr(fb)
    assert "for a = (1, 2, 3)" in text and "You returned hat(a) squared." in text
    assert text.endswith("Hint: Build the matrix entry by entry.")
    ok = check_function(so3lib.hat, so3lib.hat, cases, "hat", reference_name="the reference")
    assert ok and "agrees with the reference on 2 test inputs" in repr(ok)
    raised = check_function(lambda a: a[5], so3lib.hat, cases, "hat")
    assert "Calling it on the zero vector raised IndexError" in repr(raised)


def test_diagnose_is_not_called_on_malformed_results():
    def diagnose(got, args):
        raise AssertionError("must not be called")

    assert "shape" in repr(check_function(lambda a: np.zeros(2), so3lib.hat, INPUTS, "hat", diagnose=diagnose))
    assert "NaN" in repr(check_function(lambda a: np.full((3, 3), np.nan), so3lib.hat, INPUTS, "hat",
                                        diagnose=diagnose))


def test_messages_show_no_negative_zeros():
    fb = check_value(np.array([[-0.0, 1.0], [0.0, 2.0]]), np.eye(2), "M")
    assert "-0." not in repr(fb)


def test_diagnose_is_not_called_on_text():
    def diagnose(got, args):
        raise AssertionError("must not be called")

    fb = check_function(lambda a: "text", so3lib.hat, INPUTS, "hat", diagnose=diagnose)
    assert "not a number" in repr(fb)


def test_never_raises_turns_an_unforeseen_error_into_a_message():
    from so3lib.exercises import never_raises

    @never_raises("the answer")
    def checker(answer):
        return Feedback(True, "Correct") if answer[7] else Feedback(False, "Not yet")

    fb = checker([1.0])
    assert not fb and repr(fb).startswith("Not yet: the answer. The answer could not be checked (IndexError")
    assert checker.__name__ == "checker"


def test_messages_never_show_the_expected_value():
    """Neither the expected value nor the difference that would give it away."""
    fb = check_value(-14.0, 196.0, "c")
    assert not fb and "196" not in repr(fb) and "210" not in repr(fb)
    fb = check_value(197.0, 196.0, "c", hint="Use the Lemma twice.")
    assert "196" not in repr(fb) and "Hint: Use the Lemma twice." in repr(fb)
    assert "off by a sign" in repr(check_value(-196.0, 196.0, "c"))
    secret = np.array([[0.0, -3.125, 2.375], [3.125, 0.0, -1.5], [-2.375, 1.5, 0.0]])
    fb = check_function(lambda a: np.eye(3), lambda a: secret, INPUTS, "hat")
    assert not fb and "3.125" not in repr(fb) and "2.375" not in repr(fb)


# --- nothing in so3lib.exercises answers an exercise, no message shows an expected value --

def _public(module):
    names = getattr(module, "__all__", None)
    if names is None:
        names = [n for n in dir(module) if not n.startswith("_")]
    return {f"{module.__name__}.{n}": getattr(module, n) for n in names
            if callable(getattr(module, n, None)) and not isinstance(getattr(module, n), type(re))}


def _exercise_modules():
    import importlib
    import pkgutil

    import so3lib.exercises as package
    return [package] + [importlib.import_module(f"{package.__name__}.{m.name}")
                        for m in pkgutil.iter_modules(package.__path__)]


def _checkers():
    """Every public check_* of the per-notebook modules that takes one answer."""
    import inspect
    found = {}
    for module in _exercise_modules()[1:]:
        for name, obj in _public(module).items():
            if not name.rpartition(".")[2].startswith("check_"):
                continue
            try:
                params = inspect.signature(obj).parameters.values()
            except (TypeError, ValueError):
                continue
            required = [p for p in params if p.default is p.empty
                        and p.kind in (p.POSITIONAL_ONLY, p.POSITIONAL_OR_KEYWORD)]
            if len(required) == 1:
                found[name] = obj
    return found


def test_no_public_function_of_so3lib_exercises_answers_an_exercise():
    """Pass every public callable of so3lib.exercises to every checker: none may pass.
    (A reference answer the checkers need stays private, or lives in the hidden tests.)"""
    candidates = {}
    for module in _exercise_modules():
        candidates.update(_public(module))
    checkers = _checkers()
    assert checkers, "no checker found"
    accepted = []
    for cname, checker in sorted(checkers.items()):
        for name, candidate in sorted(candidates.items()):
            try:
                fb = checker(candidate)
            except Exception as err:            # a checker must never raise either
                accepted.append(f"{cname}({name}) raised {type(err).__name__}: {err}")
                continue
            if fb:
                accepted.append(f"{cname} accepts {name}")
    assert not accepted, "\n".join(accepted)


def _value_exercises():
    """(notebook, exercise, checker call, expected scalar) for every tagged exercise whose
    answer is a number, the number computed by running the worked solution."""
    import contextlib
    import io

    from tools import assignments
    from tools.common import course_notebooks, read
    found = []
    for path in course_notebooks():
        nb = read(path)
        try:
            exercises = assignments.exercises(nb, path)
        except assignments.ConventionError:
            continue                            # tests/test_assignments.py names it
        setup = [c for c in nb.cells if c.cell_type == "code" and not assignments.tags(c) & {
            assignments.ANSWER, assignments.CHECK, assignments.SOLUTION, assignments.HIDDEN}]
        imports = "\n".join(assignments._imports(setup))
        for ex in exercises:
            stub = assignments._python(ex.answer.source)
            if "def " in stub:
                continue
            space = {}
            try:
                with contextlib.redirect_stdout(io.StringIO()):
                    exec(imports, space)
                    exec(assignments._solution(ex), space)
            except Exception:
                continue                        # the solution needs the notebook's state
            names = [n for n in space if n in stub and not n.startswith("_")]
            values = [space[n] for n in names if np.ndim(space[n]) == 0 and
                      isinstance(space[n], (int, float, np.number)) and not isinstance(space[n], bool)]
            if len(values) == 1:
                found.append((path.name, ex.label, ex.check.source.strip(), float(values[0]), space))
    return found


def _shown(x):
    forms = {f"{x:.6g}", f"{x:.4g}", f"{x:g}", repr(x), str(x)}
    if float(x).is_integer():
        forms.add(str(int(x)))
    return forms


def test_no_checker_message_shows_the_expected_number():
    cases = _value_exercises()
    leaks = []
    for notebook, label, call, value, space in cases:
        name = call[call.index("(") + 1:call.rindex(")")].strip()
        checker = space[call[:call.index("(")].strip()]
        expected = {s for s in _shown(value) if len(s.lstrip("-").replace(".", "")) >= 3}
        for wrong in {value + 1, 2 * value + 1, -value, 0.5 * value + 0.25, 0.0}:
            if np.isclose(wrong, value):
                continue
            text = repr(checker(wrong))
            for form in sorted(_shown(wrong), key=len, reverse=True):
                text = text.replace(form, "#")
            shown = sorted(s for s in expected if s in text)
            if shown:
                leaks.append(f"{notebook} exercise {label}: {name} = {wrong:g} gets a message "
                             f"showing {shown}: {text!r}")
    assert not leaks, "\n".join(leaks)
