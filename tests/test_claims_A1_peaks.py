"""Claims of notebook A1 (errata) about the peaks of its N11 and N12 plots, as the alt text
and the speaker notes state them: each on the plots' own grids, with rotations rounded once
from mpmath's 50-digit matrix exponential (as the notebook builds them)."""

import math

import mpmath as mp
import numpy as np

from so3lib import hat

_N = np.array([0.3, -0.5, 0.8]) / np.linalg.norm([0.3, -0.5, 0.8])


def _exp50(phi):
    with mp.workdps(50):
        return np.array(mp.expm(mp.matrix(hat(phi).tolist())).tolist(), dtype=float)


def _vee(M):
    return np.array([M[2, 1], M[0, 2], M[1, 0]])


def _arccos_angle(R):
    return math.acos(max(-1.0, min(1.0, (np.trace(R) - 1) / 2)))


def test_n12_plot_peaks_at_1e_minus_8_with_an_axis_about_8e7_long():
    # Slide "The axis near a half-turn" (alt text and notes): the notes' axis (skew part,
    # arccos angle) is worst at pi - theta = 1e-8, an error near 1e8 (an axis about 8e7 long),
    # because from there on arccos returns the float pi, whose sine 1.2e-16 stands in for
    # sin theta; closer in it falls to an axis about 8000 long at 1e-12.
    grid = np.logspace(-12, 0, 25)
    errors, lengths = [], []
    for g in grid:
        R = _exp50((np.pi - g) * _N)
        th = _arccos_angle(R)
        if g <= 1e-8:
            assert th == np.pi
        axis = _vee(R - R.T) / (2 * np.sin(th))
        errors.append(np.abs(axis - _N).max())
        lengths.append(np.linalg.norm(axis))
    k = int(np.argmax(errors))
    assert abs(grid[k] - 1e-8) < 1e-20
    assert 3e7 < errors[k] < 3e8 and 7e7 < lengths[k] < 9e7
    assert abs(lengths[k] - 1e-8 / math.sin(math.pi)) < 0.01 * lengths[k]   # sin(fl(pi)) = 1.22e-16
    assert 7e3 < lengths[0] < 9e3 and 1e3 < errors[0] < 1e4
    assert all(a < b for a, b in zip(errors[:k], errors[1 : k + 1]))   # falls closer in


def test_n11_plot_near_pi_peaks_at_about_3e_minus_9():
    # Slide "The angle by arccos", right panel (alt text): the relative error of the arccos
    # angle peaks at about 3e-9 at pi - theta = 1e-8, an absolute error of about 1e-8 rad.
    grid = np.logspace(-12, -1, 23)
    rel = []
    for g in grid:
        th = np.pi - g
        rel.append(abs(_arccos_angle(_exp50(th * _N)) - th) / th)
    k = int(np.argmax(rel))
    assert abs(grid[k] - 1e-8) < 1e-20
    assert 2e-9 < rel[k] < 5e-9 and 0.5e-8 < rel[k] * (np.pi - 1e-8) < 2e-8
