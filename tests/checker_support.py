"""Helpers shared by the tests of the exercise checkers (tests/test_exercises_*.py)."""

import re

from so3lib.exercises import Feedback


def not_written(*args):
    """A learner's stub: the function is not written yet."""
    raise NotImplementedError


def says(fb, pattern):
    """The feedback is a failure ("Not yet: ...") whose message matches ``pattern``."""
    text = repr(fb)
    assert isinstance(fb, Feedback) and not fb, text
    assert text.startswith("Not yet:"), text
    assert re.search(pattern, text), text


def says_for(fb, name, pattern):
    """As :func:`says`, and the message names the exercise ``name`` first."""
    says(fb, pattern)
    assert repr(fb).startswith(f"Not yet: {name}"), repr(fb)
