"""The claims of notebook 04 (The logarithm) that the notebook states without printing a
check: each was a printed check line in an earlier edition, and is proved here against an
independent reference (sympy, 50-digit mpmath, SciPy's dense expm). The comment on each
test names the notebook's equation or section."""

import numpy as np
import pytest
import sympy as sp
from reference import exp_ref, expm_ref, log_ref
from scipy.linalg import expm

from so3lib import angle, exp, hat, log, random_rotation, vee

EPS = np.finfo(float).eps


def _unit(v):
    v = np.asarray(v, dtype=float)
    return v / np.linalg.norm(v)


def _err(got, ref, scale=None):
    """Largest difference in units of eps * max(1, |ref|) (or eps * scale)."""
    got, ref = np.asarray(got, dtype=float), np.asarray(ref, dtype=float)
    assert np.isfinite(got).all() and np.isfinite(ref).all()
    s = max(1.0, float(np.abs(ref).max())) if scale is None else scale
    return float(np.abs(got - ref).max()) / (EPS * s)


def _recipe(R, tau=1.0):
    """The notes' recipe (4.5)-(4.7), arccos not clipped, written out here."""
    with np.errstate(all="ignore"):
        sigma = np.arccos((np.trace(R) - 1) / 2) / tau
        if sigma == 0:
            return np.zeros(3)
        return sigma * vee(R - R.T) / (2 * np.sin(sigma * tau))


def _acos_angle(R):
    return float(np.arccos(np.clip((np.trace(R) - 1) / 2, -1.0, 1.0)))


# ------------------------------------------------------------------ sections 2 and 3: sympy

TH = sp.symbols("theta", real=True)
N1, N2, N3 = sp.symbols("n1 n2 n3", real=True)
NHAT = sp.Matrix([[0, -N3, N2], [N3, 0, -N1], [-N2, N1, 0]])
NN = sp.Matrix([N1, N2, N3])
RS = sp.eye(3) + sp.sin(TH) * NHAT + (1 - sp.cos(TH)) * NHAT**2            # (4.1)
UNIT = {N3**2: 1 - N1**2 - N2**2}


def _zero_on_sphere(expr):
    return sp.simplify(sp.expand(expr).subs(UNIT)) == 0


def test_trace_identity_4_2_symbolic():
    assert _zero_on_sphere(RS.trace() - (1 + 2 * sp.cos(TH)))


def test_symmetric_part_4_4_and_half_turn_4_13_symbolic():
    d44 = RS + RS.T - (2 * sp.cos(TH) * sp.eye(3) + 2 * (1 - sp.cos(TH)) * NN * NN.T)
    assert all(_zero_on_sphere(x) for x in d44)
    d413 = RS.subs(TH, sp.pi) + sp.eye(3) - 2 * NN * NN.T
    assert all(_zero_on_sphere(x) for x in d413)


def test_arccos_slope_4_8_symbolic():
    c = sp.symbols("c", real=True)
    assert sp.simplify(sp.diff(sp.acos(c), c) + 1 / sp.sin(sp.acos(c))) == 0


# ------------------------------------------------------------------ sections 2 and 3: floats

def test_4_2_to_4_4_on_a_50_digit_rotation_and_scipy_expm_against_it():
    theta, n = 2.2, np.array([2.0, -1.0, 2.0]) / 3.0
    R = expm_ref(theta * n)
    assert _err(np.trace(R), 1 + 2 * np.cos(theta)) <= 4
    assert _err(vee(R - R.T), 2 * np.sin(theta) * n) <= 4
    assert _err(R + R.T, 2 * np.cos(theta) * np.eye(3)
                + 2 * (1 - np.cos(theta)) * np.outer(n, n)) <= 4
    # the notebook uses SciPy's expm as an independent exponential: a few eps off
    assert _err(expm(hat(theta * n)), R) <= 16


def test_skew_part_of_a_computed_half_turn_is_rounding():
    n = np.array([2.0, -1.0, 2.0]) / 3.0
    H = expm(hat(np.pi * n))
    assert _err(H - H.T, np.zeros((3, 3))) <= 8


# ------------------------------------------------------------------ section 4: the recipe

def test_recipe_and_log_give_omega_at_1_23_rad():
    omega, tau = np.array([0.3, -0.2, 0.5]), 2.0
    R = expm_ref(omega, tau)
    assert _err(_recipe(R, tau), omega) <= 8
    assert _err(log(R, tau), omega) <= 8
    n = vee(R - R.T) / (2 * np.sin(np.arccos((np.trace(R) - 1) / 2)))
    assert _err(tau * n, omega) > 1e14                  # the notes' printed tau n (N13)


def test_four_rad_comes_back_as_the_shorter_turn():
    R = exp_ref([0.0, 0.0, 4.0])
    sigma = np.arccos((np.trace(R) - 1) / 2) / 2.0
    assert _err(sigma, (2 * np.pi - 4) / 2) <= 8
    assert _err(log(R, 2.0), [0.0, 0.0, (4 - 2 * np.pi) / 2]) <= 8
    assert _err(log(exp(np.array([0.0, 0.0, 4.0])), 2.0), [0.0, 0.0, (4 - 2 * np.pi) / 2]) <= 8


# ------------------------------------------------------------------ section 5: the angle

def test_angles_against_50_digits():
    n = np.array([2.0, -1.0, 2.0]) / 3.0
    for th in (1e-6, 2.2, np.pi - 1e-6):
        R = exp(th * n)
        ref = float(np.linalg.norm(log_ref(R)))
        scale = min(1.0, th)
        assert _err(angle(R), ref, scale) <= 4
        c = (np.trace(R) - 1) / 2
        s = np.linalg.norm(vee(R - R.T)) / 2
        assert _err(np.arctan2(s, c), ref, scale) <= 4
        if th == 2.2:
            assert _err(_acos_angle(R), ref) <= 4


@pytest.mark.parametrize("d, near0, nearpi", [
    (1e-1, (0, 1e-14), (0, 1e-14)),
    (1e-4, (1e-13, 1e-12), (1e-13, 1e-11)),
    (1e-6, (1e-11, 1e-10), (1e-11, 1e-9)),
])
def test_arccos_angle_error_table_of_section_5(d, near0, nearpi):
    rng = np.random.default_rng(1)
    axes = rng.standard_normal((100, 3))
    axes /= np.linalg.norm(axes, axis=1, keepdims=True)
    e0 = [abs(_acos_angle(exp(d * a)) - float(np.linalg.norm(log_ref(exp(d * a)))))
          for a in axes]
    epi = [abs(_acos_angle(exp((np.pi - d) * a))
               - float(np.linalg.norm(log_ref(exp((np.pi - d) * a))))) for a in axes]
    assert near0[0] <= min(e0) and max(e0) <= near0[1], (min(e0), max(e0))
    assert nearpi[0] <= min(epi) and max(epi) <= nearpi[1], (min(epi), max(epi))


def test_arccos_angle_is_lost_at_1e_8_and_more_than_d_near_pi():
    rng = np.random.default_rng(1)
    for a in rng.standard_normal((100, 3)):
        a = _unit(a)
        assert _acos_angle(exp(1e-8 * a)) == 0.0
    errs = [abs(_acos_angle(R) - np.linalg.norm(log_ref(R)))
            for R in (exp((np.pi - 1e-8) * _unit(a)) for a in rng.standard_normal((100, 3)))]
    assert max(errs) > 1e-8 and max(errs) < 1e-7


def test_the_angle_of_a_product_is_limited_by_its_input():
    # section 5, "The limit is in the input": angle(Ra^T Rb) agrees with the 50-digit angle
    # of the same matrix, while against the angle put in it has only absolute accuracy
    rng = np.random.default_rng(5)
    Ra = random_rotation(rng, 20)
    a = rng.standard_normal((20, 3))
    a /= np.linalg.norm(a, axis=1, keepdims=True)
    for th, lo, hi in ((1e-4, 1e-14, 1e-12), (1e-8, 1e-10, 1e-8)):
        M = np.swapaxes(Ra, 1, 2) @ (Ra @ exp(th * a))
        ours = angle(M)
        ref = np.array([np.linalg.norm(log_ref(m)) for m in M])
        assert _err(ours, ref, th) <= 4
        rel = np.median(np.abs(ours - th)) / th
        assert lo < rel < hi, rel
        direct = angle(exp(th * a))                    # made by exp: relative accuracy
        assert _err(direct, np.full(20, th), th) <= 4


# ------------------------------------------------------------------ section 6: the cases

def test_case_1_log_of_identity_and_full_turns():
    assert np.array_equal(log(np.eye(3)), np.zeros(3))
    m = _unit([0.3, -1.2, 0.5])
    for k in (1, 2, 3):
        assert _err(exp_ref(2 * np.pi * k * m), np.eye(3)) <= 8
        assert _err(exp(2 * np.pi * k * m), np.eye(3)) <= 8 * k


def test_case_2_formula_4_11_and_tiny_angles():
    phi = np.array([0.3, -0.4, 1.2])
    R = expm(hat(phi))
    v = vee(R - R.T)
    theta = np.arctan2(np.linalg.norm(v) / 2, (np.trace(R) - 1) / 2)
    assert _err(theta / (2 * np.sin(theta)) * v, phi) <= 8
    assert np.array_equal(log(exp([1e-170, 0.0, 0.0])), [1e-170, 0.0, 0.0])


def test_gallier_set_4_12():
    phi = np.array([0.3, -0.4, 1.2])
    R = exp_ref(phi)
    v = vee(R - R.T)
    theta = np.linalg.norm(phi)
    for th in (theta, -theta, theta + 2 * np.pi, -theta + 2 * np.pi, theta - 4 * np.pi):
        p = th / (2 * np.sin(th)) * v      # (theta + 2 pi k) n, rounded: an ulp of |p|
        assert _err(exp_ref(p), R) <= 3 * max(1.0, abs(th))


def test_case_3_construction_4_14():
    n = np.array([1.0, 2.0, 3.0]) / np.sqrt(14.0)
    R = expm(hat(np.pi * n))
    assert _err(R + np.eye(3), 2 * np.outer(n, n)) <= 8
    j = int(np.argmax(np.diag(R)))
    n_found = (R + np.eye(3))[:, j] / np.sqrt(2 * (R[j, j] + 1))
    assert _err(n_found * np.sign(n_found @ n), n) <= 8
    for k in (1, -1, 3):
        assert _err(exp_ref(k * np.pi * n_found), R) <= 8


def test_exact_half_turns_silent_zero():
    # section 6, case 3: on exact half-turns the recipe returns exactly 0 or NaN, and
    # (4.11) with the atan2 angle exactly 0; so3lib.log returns +-pi n
    rng = np.random.default_rng(4)
    u = rng.standard_normal((400, 3))
    u /= np.sqrt(u[:, :1]**2 + u[:, 1:2]**2 + u[:, 2:]**2)
    for a in u:
        H = 2 * np.outer(a, a) - np.eye(3)
        r = _recipe(H)
        assert not r.any() or np.isnan(r).all()
        v = vee(H - H.T)
        assert not v.any()
        L = log(H)
        assert min(_err(L, np.pi * a), _err(L, -np.pi * a)) <= 8
    assert np.sin(np.pi) > 1e-16


def test_sign_rule_and_computed_half_turns():
    assert np.array_equal(log(np.diag([1.0, -1.0, -1.0])), [np.pi, 0.0, 0.0])
    rng = np.random.default_rng(7)
    for m in rng.standard_normal((20, 3)):
        m = _unit(m)
        R = expm(hat(np.pi * m))
        L = log(R)
        assert min(_err(L, np.pi * m), _err(L, -np.pi * m)) <= 8
        assert _err(exp_ref(L), R) <= 8


# ------------------------------------------------------------------ section 7: near pi

def _axis_skew(R):
    c = (np.trace(R) - 1) / 2
    s = np.linalg.norm(vee(R - R.T)) / 2
    return vee(R - R.T) / (2 * np.sin(np.arctan2(s, c)))


def test_near_pi_log_against_the_input_and_4_11_everywhere_fails():
    rng = np.random.default_rng(3)
    ths = np.concatenate([np.pi - np.logspace(-12, -1, 12), rng.uniform(0, np.pi, 200)])
    axes = rng.standard_normal((len(ths), 3))
    axes /= np.linalg.norm(axes, axis=1, keepdims=True)
    phi = ths[:, None] * axes
    Rs = np.array([expm(hat(p)) for p in phi])
    assert _err(log(Rs), phi) <= 8
    skew = np.array([np.arctan2(np.linalg.norm(vee(R - R.T)) / 2, (np.trace(R) - 1) / 2)
                     * _axis_skew(R) for R in Rs])
    assert _err(skew, phi) > 1e9


def test_symmetric_axis_bound_of_4_15():
    # the axis from the column of (4.15) errs by at most about 3 delta / (1 - c) in length
    # (the 2-norm), for a matrix off by at most delta in each entry
    rng = np.random.default_rng(2)
    for _ in range(200):
        n = _unit(rng.standard_normal(3))
        th = rng.uniform(np.pi / 2, np.pi)
        delta = 1e-9
        R = exp_ref(th * n) + delta * rng.uniform(-1, 1, (3, 3))
        c = (np.trace(R) - 1) / 2
        B = (R + R.T) / 2 - c * np.eye(3)
        j = int(np.argmax(np.diag(B)))
        m = B[:, j] / np.linalg.norm(B[:, j])
        err = min(np.linalg.norm(m - n), np.linalg.norm(m + n))
        assert err <= 3 * delta / (1 - np.cos(th))


def test_symmetric_axis_entry_bound_of_4_15():
    # one entry of that axis: off by at most about (4/3) sqrt(3) = 2.3 delta / (1 - c) when
    # each entry of the column errs by at most delta, reached for n = (1, 1, 1)/sqrt(3) and
    # the column error delta (1, 1, -1)
    rng = np.random.default_rng(12)
    delta, worst = 1e-9, 0.0
    for k in range(4000):
        n = _unit(rng.standard_normal(3)) if k else _unit([1.0, 1.0, 1.0])
        c = rng.uniform(-1, 0)
        j = int(np.argmax(np.abs(n)))
        e = delta * (rng.choice([-1.0, 1.0], 3) if k else np.array([1.0, 1.0, -1.0]))
        col = (1 - c) * n[j] * n + e
        m = col / np.linalg.norm(col)
        err = min(np.abs(m - n).max(), np.abs(m + n).max()) * (1 - c) / delta
        if k == 0:
            assert abs(err - 4 / np.sqrt(3)) < 1e-5
        worst = max(worst, err)
    assert worst <= 4 / np.sqrt(3) + 1e-5


# ------------------------------------------------------------------ section 8

def test_exp_of_log_4_17():
    rng = np.random.default_rng(8)
    Rs = random_rotation(rng, 200)
    for R in Rs:
        assert _err(exp_ref(log(R)), R) <= 8
    halves = [2 * np.outer(a, a) - np.eye(3) for a in np.eye(3)]
    halves.append(expm(hat(np.pi * np.array([0.6, 0.0, 0.8]))))
    for R in halves:
        assert _err(exp_ref(log(R)), R) <= 8


def test_log_of_exp_4_18_and_the_jump_at_pi():
    assert _err(log(expm(hat([0.0, 0.0, 3.0]))), [0.0, 0.0, 3.0]) <= 8
    R4 = expm(hat([0.0, 0.0, 4.0]))
    assert _err(log(R4), [0.0, 0.0, 4.0]) > 1e14
    assert _err(log(R4), [0.0, 0.0, 4.0 - 2 * np.pi]) <= 8
    n = np.array([1.0, 2.0, 2.0]) / 3.0
    a = log(expm(hat((np.pi - 1e-9) * n)))
    b = log(expm(hat((np.pi + 1e-9) * n)))
    assert _err(a, (np.pi - 1e-9) * n) <= 8
    assert _err(b, (1e-9 - np.pi) * n) <= 8


# ------------------------------------------------------------------ section 9: the recipe

def test_recipe_near_pi_1e_4_is_off_by_1e7_to_1e9_eps():
    rng = np.random.default_rng(1)
    errs = []
    for a in rng.standard_normal((100, 3)):
        R = exp((np.pi - 1e-4) * _unit(a))
        errs.append(_err(_recipe(R), log_ref(R)))
    assert 1e7 < min(errs) and max(errs) < 1e9, (min(errs), max(errs))


def test_section5_c_is_one_below_about_2e8_and_below_one_from_3e8():
    # Section 5: c = (tr R - 1)/2 of exp(theta n) comes out as 1 or above for most axes once
    # theta^2/2 is below about eps (theta below about 2e-8), and stays below 1 from about 3e-8.
    rng = np.random.default_rng(5)
    axes = rng.standard_normal((200, 3))
    axes /= np.linalg.norm(axes, axis=1)[:, None]
    def share_at_one(th):
        return np.mean([(np.trace(exp(th * a)) - 1) / 2 >= 1.0 for a in axes])
    assert share_at_one(1e-8) == 1.0 and share_at_one(2e-8) > 0.5
    assert share_at_one(3e-8) == 0.0 and share_at_one(5e-8) == 0.0
