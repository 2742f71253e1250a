"""`make bench`: so3lib's batched exp and log side by side with scipy's Rotation.

Prints nanoseconds per rotation for each batch size and the ratio so3lib / scipy
(below 1 means so3lib is faster). Timings are the best of several repeats, so that other
work on the machine inflates them as little as possible. Not a test: speed targets live
here, never in the test suite.
"""

import sys
import timeit

import numpy as np
from scipy.spatial.transform import Rotation

import so3lib

SIZES = (1, 100, 10_000, 100_000)


def best_ns_per_item(func, n, budget=0.4, repeat=5):
    """Best time of ``func()`` over ``repeat`` runs, in ns per rotation."""
    timer = timeit.Timer(func)
    number, _ = timer.autorange()
    number = max(1, int(number * budget / 0.2))
    return min(timer.repeat(repeat=repeat, number=number)) / number / n * 1e9


def main():
    rng = np.random.default_rng(0)
    print(f"numpy {np.__version__}; times in ns per rotation (best of 5)")
    print(f"{'N':>8} | {'exp':>9} {'scipy':>9} {'ratio':>6} | {'log':>9} {'scipy':>9} {'ratio':>6}")
    for n in SIZES:
        phi = rng.standard_normal((n, 3)) * 1.5
        R = so3lib.exp(phi)
        t_exp = best_ns_per_item(lambda: so3lib.exp(phi), n)
        t_sexp = best_ns_per_item(lambda: Rotation.from_rotvec(phi).as_matrix(), n)
        t_log = best_ns_per_item(lambda: so3lib.log(R), n)
        t_slog = best_ns_per_item(lambda: Rotation.from_matrix(R).as_rotvec(), n)
        print(f"{n:>8} | {t_exp:>9.1f} {t_sexp:>9.1f} {t_exp / t_sexp:>6.2f} | "
              f"{t_log:>9.1f} {t_slog:>9.1f} {t_log / t_slog:>6.2f}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
