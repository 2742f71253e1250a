r"""so3lib: the exponential and logarithm maps of SO(3), for the course in ``notebooks/``.

>>> import numpy as np, so3lib
>>> R = so3lib.exp([0.0, 0.0, np.pi / 2])          # a quarter turn about z
>>> np.allclose(R @ [1, 0, 0], [0, 1, 0])
True
>>> np.allclose(so3lib.log(R), [0, 0, np.pi / 2])
True

Modules: :mod:`so3lib.so3` (hat, vee, exp, log and friends), :mod:`so3lib.so2` (the
plane and complex numbers), :mod:`so3lib.series` (the power series, for teaching),
:mod:`so3lib.jacobians` (the Jacobians of exp, oplus and ominus),
:mod:`so3lib.validation` (input checks and the rotation tolerance),
:mod:`so3lib.measure` (errors in whole eps, for the notebooks' checks),
:mod:`so3lib.plot` (figure helpers; imports matplotlib) and :mod:`so3lib.exercises`
(checkers for the notebooks' exercises).

Docstrings and comments cite "spec Sn": the numbered statements of the course's
specification, which the notebooks teach in order (S1-S5 in notebook 01, S6-S11 in 02,
S24-S28 in 03, S12-S23 in 04; S29 is the 50-digit reference in ``tests/reference.py``).
"""

from . import so2
from .jacobians import (C, D, left_jacobian, left_jacobian_inv, ominus, oplus,
                        right_jacobian, right_jacobian_inv)
from .series import A, B, exp_series
from .so3 import angle, exp, hat, is_rotation, log, random_rotation, vee
from .validation import ROTATION_TOL

__version__ = "0.1.0"

__all__ = [
    "hat", "vee", "exp", "log", "angle", "is_rotation", "random_rotation",
    "exp_series", "A", "B", "so2", "ROTATION_TOL",
    "right_jacobian", "left_jacobian", "right_jacobian_inv", "left_jacobian_inv",
    "C", "D", "oplus", "ominus",
]
