r"""so3lib: the exponential and logarithm maps of SO(3), for the course in ``notebooks/``.

>>> import numpy as np, so3lib
>>> R = so3lib.exp([0.0, 0.0, np.pi / 2])          # a quarter turn about z
>>> np.allclose(R @ [1, 0, 0], [0, 1, 0])
True
>>> np.allclose(so3lib.log(R), [0, 0, np.pi / 2])
True

Modules: :mod:`so3lib.so3` (hat, vee, exp, log and friends), :mod:`so3lib.so2` (the
plane and complex numbers), :mod:`so3lib.series` (the power series, for teaching),
:mod:`so3lib.validation` (input checks and the rotation tolerance),
:mod:`so3lib.plot` (figure helpers; imports matplotlib) and :mod:`so3lib.exercises`
(checkers for the notebooks' exercises).
"""

from . import so2
from .series import A, B, exp_series
from .so3 import angle, exp, hat, is_rotation, log, random_rotation, vee
from .validation import ROTATION_TOL

__version__ = "0.1.0"

__all__ = [
    "hat", "vee", "exp", "log", "angle", "is_rotation", "random_rotation",
    "exp_series", "A", "B", "so2", "ROTATION_TOL",
]
