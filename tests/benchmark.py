"""`make bench`: so3lib's exp and log side by side with scipy's Rotation.

First the goal of the library issue: for N = 1, 10, 100, 10^3 ... 10^6 rotations, the
ratio so3lib / scipy of exp and of the validated log, each the median of interleaved
pairs (so3lib then scipy, scipy then so3lib, in turn, each timed over the same number of
calls), with every ratio above 1 flagged. Then, for N = 1 to 10^6, the time per rotation
of each library (best of several rounds); the fixed cost of a call and the cost of one
more rotation; the targets of the performance issue, each with its measured value; and a
plot in build/benchmark.png (the README shows a copy, notebooks/images/benchmark.png).

Timings are the best of several repeats, taken in rounds that go through every size and
both libraries in turn, so that other work on the machine, or a slow spell of it, slows
both alike and cannot spoil every repeat of one measurement. Memory is the peak that tracemalloc sees
during one call (NumPy reports its allocations to it), result included, divided by the
size of the result. Not a test: speed targets live here, never in the test suite (the
memory bound, which does not depend on the machine, is tested in tests/test_memory.py).

    python tests/benchmark.py [--quick] [--ratios-only] [--plot PATH]
"""

import argparse
import os
import platform
import statistics
import sys
import time
import timeit
import tracemalloc
from pathlib import Path

import numpy as np
import scipy
from scipy.spatial.transform import Rotation

import so3lib

SIZES = (1, 3, 10, 30, 100, 300, 1_000, 3_000, 10_000, 30_000, 100_000, 300_000, 1_000_000)
RATIO_SIZES = (1, 10, 100, 1_000, 10_000, 100_000, 1_000_000)
TARGET_N = 100_000
ROOT = Path(__file__).resolve().parent.parent
PLOT = ROOT / "build" / "benchmark.png"


def machine():
    """One line naming the processor, the cores and the versions, for the README."""
    cpu = platform.processor() or platform.machine()
    try:
        with open("/proc/cpuinfo") as f:
            info = dict(line.split(":", 1) for line in f.read().split("\n\n")[0].splitlines()
                        if ":" in line)
        info = {k.strip(): v.strip() for k, v in info.items()}
        cpu = f"{info['model name']} (family {info['cpu family']}, model {info['model']})"
    except (OSError, KeyError):
        pass
    blas = os.environ.get("OPENBLAS_CORETYPE")
    blas = f"; OPENBLAS_CORETYPE={blas} (no BLAS call is timed)" if blas else ""
    return (f"{cpu}, {os.cpu_count()} cores; Python {platform.python_version()}, "
            f"numpy {np.__version__}, scipy {scipy.__version__}{blas}")


def calls(phi, R):
    """The four timed calls on one batch: so3lib's and scipy's exp, then their log."""
    return [lambda: so3lib.exp(phi),
            lambda: Rotation.from_rotvec(phi).as_matrix(),
            lambda: so3lib.log(R),
            lambda: Rotation.from_matrix(R).as_rotvec()]


def best_times(sizes, rounds, budget):
    """Best time in seconds of one call, for each size and each of the four calls.

    Timed in rounds: each round times every call at every size once (a short call several
    times), so the repeats of one measurement are spread over the whole run and a burst
    of other work, or a slow spell of the machine, cannot spoil all of them.
    """
    rng = np.random.default_rng(0)
    cases = []
    for n in sizes:
        phi, R = inputs(n, rng)
        for k, func in enumerate(calls(phi, R)):
            timer = timeit.Timer(func)
            one = min(timer.repeat(repeat=3, number=1))      # also warms up
            inner, seconds = (7, budget / 50) if n <= 1_000 else (1, budget)
            cases.append((n, k, timer, max(1, int(seconds / max(one, 1e-7))), inner))
    best = {n: [float("inf")] * 4 for n in sizes}
    progress = sys.stderr.isatty()
    for r in range(rounds):
        if progress:
            print(f"\rround {r + 1} of {rounds}", end="", file=sys.stderr, flush=True)
        for n, k, timer, number, inner in cases:
            for _ in range(inner):
                best[n][k] = min(best[n][k], timer.timeit(number) / number)
    if progress:
        print("\r" + " " * 20 + "\r", end="", file=sys.stderr)
    return best


def interleaved_ratios(sizes, pairs, budget):
    """For each N: ``(t_exp, t_exp_scipy, ratio, t_log, t_log_scipy, ratio)``, times in
    seconds per call and each ratio the median over ``pairs`` interleaved pairs.

    A pair times so3lib and scipy back to back over the same number of calls (about
    ``budget`` seconds of scipy), alternating which goes first, so that a change in the
    machine's speed between pairs (other work, frequency) cancels in the ratio. Times are
    the CPU time of this process (``time.process_time``, every thread counted), so that
    other jobs on a shared machine do not count as so3lib's or scipy's time.
    """
    rng = np.random.default_rng(0)
    rows = {}
    for n in sizes:
        phi, R = inputs(n, rng)
        row = []
        for mine, theirs in zip(*[iter(calls(phi, R))] * 2):
            mine(), theirs()                                  # warm up
            number = max(1, int(budget / max(timeit.Timer(theirs).timeit(1), 1e-7)))
            number = max(number, 20 if n < 1_000 else 1)        # process_time ticks
            times = {mine: [], theirs: []}
            ratios = []
            for k in range(pairs if n < 1_000_000 else max(3, pairs // 3)):
                order = (mine, theirs) if k % 2 == 0 else (theirs, mine)
                for func in order:
                    timer = timeit.Timer(func, timer=time.process_time)
                    times[func].append(timer.timeit(number) / number)
                ratios.append(times[mine][-1] / times[theirs][-1])
            row += [statistics.median(times[mine]), statistics.median(times[theirs]),
                    statistics.median(ratios)]
        rows[n] = row
    return rows


def print_ratio_table(rows):
    """The goal's table: ratio so3lib / scipy per N, flagged where above 1."""
    print(f"{'N':>9} | {'exp us':>9} {'scipy us':>9} {'ratio':>6}   | "
          f"{'log us':>9} {'scipy us':>9} {'ratio':>6}")
    above = []
    for n, (te, tes, re, tl, tls, rl) in rows.items():
        flag = ["  ", "  "]
        for k, (name, r) in enumerate((("exp", re), ("log", rl))):
            if r > 1.0:
                flag[k] = " !"
                above.append(f"{name} at N = {n}")
        print(f"{n:>9} | {te * 1e6:>9.1f} {tes * 1e6:>9.1f} {re:>6.2f}{flag[0]} | "
              f"{tl * 1e6:>9.1f} {tls * 1e6:>9.1f} {rl:>6.2f}{flag[1]}")
    if above:
        print("ratio above 1 (!), goal not met: " + ", ".join(above))
    else:
        print("every ratio at most 1: goal met")
    return above


def peak_memory_ratio(func):
    """Peak memory allocated during ``func()``, its result included, over the result's size."""
    func()                                               # warm caches outside the count
    tracemalloc.start()
    try:
        tracemalloc.reset_peak()
        base = tracemalloc.get_traced_memory()[0]
        out = func()
        peak = tracemalloc.get_traced_memory()[1] - base
    finally:
        tracemalloc.stop()
    return peak / out.nbytes


def inputs(n, rng):
    phi = rng.standard_normal((n, 3)) * 1.5              # angles spread over 0 .. 2 pi
    return phi, so3lib.exp(phi)


def print_table(rows):
    print(f"{'N':>9} | {'exp':>9} {'scipy':>9} {'ratio':>6} | "
          f"{'log':>9} {'scipy':>9} {'ratio':>6}")
    for n, t in rows.items():
        ns = [x / n * 1e9 for x in t]
        print(f"{n:>9} | {ns[0]:>9.1f} {ns[1]:>9.1f} {t[0] / t[1]:>6.2f} | "
              f"{ns[2]:>9.1f} {ns[3]:>9.1f} {t[2] / t[3]:>6.2f}")


def fit_overhead(rows, k, n_min=10):
    """``(a, b)`` with time per call ~ ``a + b N`` for N >= n_min, fitted to relative error."""
    n = np.array([m for m in sorted(rows) if m >= n_min], dtype=float)
    t = np.array([rows[m][k] for m in sorted(rows) if m >= n_min])
    (a, b), *_ = np.linalg.lstsq(np.stack([1 / t, n / t], axis=1), np.ones_like(t), rcond=None)
    return a, b


def plot(rows, path, title):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    sizes = np.array(sorted(rows))
    t = np.array([rows[n] for n in sizes])
    labels = ["so3lib.exp", "scipy from_rotvec().as_matrix()",
              "so3lib.log (validated)", "scipy from_matrix().as_rotvec()"]
    styles = [dict(color="C0"), dict(color="C0", ls="--"),
              dict(color="C1"), dict(color="C1", ls="--")]
    fig, (ax1, ax2) = plt.subplots(1, 2, figsize=(11, 4.2))
    for k in range(4):
        ax1.loglog(sizes, t[:, k] * 1e6, marker="o", ms=3, label=labels[k], **styles[k])
        ax2.loglog(sizes, t[:, k] / sizes * 1e9, marker="o", ms=3, label=labels[k],
                   **styles[k])
    ax1.set(xlabel="rotations per call, N", ylabel="time per call (µs)",
            title="Time per call: flat = fixed overhead")
    ax2.set(xlabel="rotations per call, N", ylabel="time per rotation (ns)",
            title="Time per rotation: the floor is the cost of one more")
    for ax in (ax1, ax2):
        ax.grid(True, which="major", alpha=0.4)
    ax2.legend(fontsize=8)
    fig.suptitle(title, fontsize=9)
    fig.tight_layout()
    path.parent.mkdir(parents=True, exist_ok=True)
    fig.savefig(path, dpi=110)
    plt.close(fig)


def report_targets(ratios):
    """The issue's targets, each measured (the goal's interleaved CPU-time medians)."""
    rng = np.random.default_rng(1)
    phi, R = inputs(TARGET_N, rng)
    t = ratios[TARGET_N]
    checks = [
        ("exp time / scipy's, N = 1e5", t[2], 1.0, ""),
        ("log time (validated) / scipy's, N = 1e5", t[5], 0.25, ""),
        ("exp of one rotation (N = 1)", ratios[1][0] * 1e6, 10.0, " us"),
        ("log of one rotation (N = 1)", ratios[1][3] * 1e6, 10.0, " us"),
        ("exp peak memory / result size, N = 1e5",
         peak_memory_ratio(lambda: so3lib.exp(phi)), 2.0, ""),
        ("log peak memory / result size, N = 1e5",
         peak_memory_ratio(lambda: so3lib.log(R)), 2.0, ""),
    ]
    print("\nTargets (the performance issue)")
    for name, value, bound, unit in checks:
        verdict = "met" if value <= bound else "NOT MET"
        measured, target = f"{value:.2f}{unit}", f"<= {bound:g}{unit}"
        print(f"  {name:<42} {measured:>9}   target {target:<9} {verdict}")


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--quick", action="store_true", help="3 rounds instead of 7 (rougher)")
    parser.add_argument("--ratios-only", action="store_true",
                        help="only the goal's table of interleaved ratios")
    parser.add_argument("--plot", type=Path, default=PLOT, help=f"default {PLOT}")
    args = parser.parse_args(argv)
    rounds, budget = (3, 0.05) if args.quick else (7, 0.1)

    title = machine()
    print(f"so3lib {so3lib.__version__} against scipy.spatial.transform.Rotation")
    print(f"machine: {title}")
    pairs = 11 if args.quick else 21
    print(f"\nGoal: so3lib / scipy at most 1 at every N, exp and validated log; median of "
          f"{pairs} interleaved pairs (times: medians per call, CPU time of the process)\n")
    ratios = interleaved_ratios(RATIO_SIZES, pairs, budget / 10)
    print_ratio_table(ratios)
    if args.ratios_only:
        return 0

    rows = best_times(SIZES, rounds, budget)
    print(f"\nbest of {rounds} rounds (of 7 repeats each up to N = 1000); ns per rotation; "
          "ratio = so3lib / scipy (below 1: so3lib faster)\n")
    print_table(rows)

    print("\nCost of a call, fitted as  a + b N  over N >= 10 (relative least squares)")
    for k, name in enumerate(["so3lib.exp", "scipy exp", "so3lib.log", "scipy log"]):
        a, b = fit_overhead(rows, k)
        print(f"  {name:<11} a = {a * 1e6:6.1f} us fixed  + b = {b * 1e9:6.1f} ns per rotation;"
              f"  one rotation alone: {rows[1][k] * 1e6:5.1f} us")

    report_targets(ratios)
    plot(rows, args.plot, f"so3lib vs scipy — {title}")
    print(f"\nplot written to {args.plot}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
