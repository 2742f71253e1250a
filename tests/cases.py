"""The table of hard cases for exp and log, in the manner of Sophus's tests (spec S29).

Each case is ``(label, phi)``: a rotation vector whose angle or axis is hard for some
naive formula -- zero and signed zeros, subnormal and tiny angles, the Taylor switch at
1e-4, the regime switch at 1, the branch switch at pi/2, angles within 1e-4 .. 1e-12 of
pi, exactly pi (the double nearest), just past pi, near 2 pi, and large angles -- along
coordinate axes, their negatives, diagonals, a near-axis and a generic direction.
"""

import math

import numpy as np

PI = math.pi

ANGLES = {
    "0": 0.0,
    "5e-324 (smallest subnormal)": 5e-324,
    "1e-310 (subnormal)": 1e-310,
    "1e-300": 1e-300,
    "1e-16": 1e-16,
    "1e-8": 1e-8,
    "just below 1e-4": math.nextafter(1e-4, 0.0),
    "1e-4": 1e-4,
    "1e-3": 1e-3,
    "0.5": 0.5,
    "just below 1": math.nextafter(1.0, 0.0),
    "1": 1.0,
    "pi/2": PI / 2,
    "3": 3.0,
    "pi - 1e-4": PI - 1e-4,
    "pi - 1e-6": PI - 1e-6,
    "pi - 1e-8": PI - 1e-8,
    "pi - 1e-10": PI - 1e-10,
    "pi - 1e-12": PI - 1e-12,
    "pi": PI,
    "pi + 1e-9": PI + 1e-9,
    "2 pi - 1e-3": 2 * PI - 1e-3,
    "2 pi": 2 * PI,
    "100": 100.0,
    "1e6": 1e6,
}


def _unit(v):
    v = np.asarray(v, dtype=float)
    return v / np.linalg.norm(v)


AXES = {
    "x": [1.0, 0.0, 0.0],
    "-y": [0.0, -1.0, 0.0],
    "z": [0.0, 0.0, 1.0],
    "(1,1,0)": _unit([1, 1, 0]),
    "(1,-1,0)": _unit([1, -1, 0]),
    "(1,1,1)": _unit([1, 1, 1]),
    "near x (1, 1e-9, -1e-12)": _unit([1, 1e-9, -1e-12]),
    "(0.3,-0.5,0.8)": _unit([0.3, -0.5, 0.8]),
    "(1,2,3)": _unit([1, 2, 3]),
}


def hard_cases():
    """All ``(label, phi)`` pairs: every angle along every axis, plus signed zeros."""
    cases = [(f"angle {a} about {x}", t * np.asarray(n, dtype=float))
             for a, t in ANGLES.items() for x, n in AXES.items()]
    cases += [("signed zero (-0, 0, -0)", np.array([-0.0, 0.0, -0.0])),
              ("signed zero (-0, -0, -0)", np.array([-0.0, -0.0, -0.0]))]
    return cases


def half_turns():
    """Exact half-turns ``R = 2 n n^T - I`` (symmetric, trace -1) about hard axes."""
    axes = [[1, 0, 0], [0, 1, 0], [0, 0, 1], [1, 1, 0], [1, -1, 0], [0, 1, 1], [1, 1, 1],
            [1, 2, 3], [-3, 1, 2]]
    out = []
    for a in axes:
        n = _unit(a)
        out.append((f"half-turn about {tuple(a)}", n, 2.0 * np.outer(n, n) - np.eye(3)))
    return out
