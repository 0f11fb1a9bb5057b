"""Cost of one scalar call from Python against the compiled core's cost per element.

    pip install ./python
    RAYON_NUM_THREADS=1 python python/bench_call.py

Each scalar call is timed as the median of many single calls (``time.perf_counter`` around
each); the core's cost per element is the median, over repeats, of one array call of 20,000
elements on one thread divided by its length (no per-call overhead left in it). The array
call runs on worker threads: on a busy machine they compete for the cores and that column
reads high; the scalar column is the one to compare between builds. The last line times an
empty lambda the same way: the share of the scalar column that is the timer's and the
lambda's, not the call's.
"""

import os
import statistics
import sys
import time

if sys.path and os.path.abspath(sys.path[0]) == os.path.dirname(os.path.abspath(__file__)):
    sys.path.pop(0)  # import the installed package, not the source directory beside this file

import numpy as np  # noqa: E402

import stabound  # noqa: E402


def per_call(f, n=20_000):
    for _ in range(200):
        f()
    times = []
    for _ in range(n):
        t = time.perf_counter()
        f()
        times.append(time.perf_counter() - t)
    return statistics.median(times)


def per_element(f, n, repeats=7):
    f()
    return statistics.median(timed(f) for _ in range(repeats)) / n


def timed(f):
    t = time.perf_counter()
    f()
    return time.perf_counter() - t


def main():
    us = 1e6
    n = 20_000
    ones = np.ones(n)
    # the wall of the criterion bench `elements` (crates/stabound/benches/stability.rs):
    # half of alpha_max at its beta, delta = 0.5, d = 1; its `build/bare` plus
    # `checker/bare` is the core's cost of this call
    a = stabound.alpha_max(0.5, 1.0)
    wall = (0.5 * a.alpha_max, a.beta_at_max)
    rows = [
        ("check(bench wall, 0.5, 1.0, radius=False)",
         lambda: stabound.check(*wall, 0.5, 1.0, radius=False),
         lambda: stabound.check(wall[0] * ones, wall[1], 0.5, 1.0, radius=False)),
        ("check(0.1, 0.3, 0.5, 1.0)",
         lambda: stabound.check(0.1, 0.3, 0.5, 1.0),
         lambda: stabound.check(0.1 * ones, 0.3, 0.5, 1.0)),
        ("check(..., radius=False)",
         lambda: stabound.check(0.1, 0.3, 0.5, 1.0, radius=False),
         lambda: stabound.check(0.1 * ones, 0.3, 0.5, 1.0, radius=False)),
        ("alpha_max(0.5, 1.0)",
         lambda: stabound.alpha_max(0.5, 1.0),
         lambda: stabound.alpha_max(0.5 * ones, 1.0)),
        ("alpha_max(mass=, period=, damping=, delay_samples=)",
         lambda: stabound.alpha_max(mass=0.1, period=1e-3, damping=50.0, delay_samples=1),
         lambda: stabound.alpha_max(mass=0.1, period=1e-3, damping=50.0 * ones, delay_samples=1)),
    ]
    print(f"{'call':55} {'scalar call':>12} {'core/element':>13} {'ratio':>6}")
    for name, scalar, array in rows:
        s = per_call(scalar)
        c = per_element(array, n)
        print(f"{name:55} {s * us:9.2f} us {c * us:10.2f} us {s / c:6.2f}")
    print(f"{'(an empty lambda, timed the same way)':55} {per_call(lambda: None) * us:9.2f} us")


if __name__ == "__main__":
    main()
