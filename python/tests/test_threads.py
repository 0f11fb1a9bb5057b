"""The GIL is released while the library computes, and results do not depend on the number
of threads."""

import os
import subprocess
import sys
import threading
import time

import numpy as np

import stabound


def test_another_thread_runs_while_check_computes():
    # A long call in a worker thread; the main thread waits for the worker to be about to
    # call, then records when it gets to run again. With the GIL held for the whole call the
    # main thread could only run after the call returned; released, it runs right away.
    n = 20_000
    alpha = np.linspace(0.001, 0.2, n)
    entered = threading.Event()
    times = {}

    def work():
        times["enter"] = time.perf_counter()
        entered.set()
        stabound.check(alpha, 0.05, 0.1, 10.0)  # degree-13 polynomials: about a second
        times["exit"] = time.perf_counter()

    t = threading.Thread(target=work)
    t.start()
    entered.wait()
    times["main"] = time.perf_counter()
    t.join()
    call = times["exit"] - times["enter"]
    # ordering, not a time limit: the main thread ran during the first half of the call
    assert times["main"] - times["enter"] < 0.5 * call, times


SCRIPT = """
import numpy as np, stabound, sys
rng = np.random.default_rng(3)
a = rng.uniform(0, 2, 3000); b = rng.uniform(-0.5, 1.5, 3000)
x = rng.uniform(0, 3, 3000); d = rng.choice([0.0, 0.5, 1.0, 2.0, 7.25], 3000)
r = stabound.check(a, b, x, d)
m = stabound.alpha_max(x[:200], d[:200])
c = stabound.boundary([0.0, 0.5], [0.0, 1.5], tol=1e-6)
sys.stdout.write(r.spectral_radius.tobytes().hex() + r.code.tobytes().hex()
                 + m.alpha_max.tobytes().hex() + m.beta_at_max.tobytes().hex()
                 + "".join(k.alpha.tobytes().hex() + k.beta.tobytes().hex() for k in c))
"""


def test_results_do_not_depend_on_thread_count(tmp_path):
    outs = []
    for threads in ("1", "2", "3"):
        env = dict(os.environ, RAYON_NUM_THREADS=threads)
        p = subprocess.run([sys.executable, "-c", SCRIPT], env=env, capture_output=True,
                           text=True, cwd=tmp_path, check=True)
        outs.append(p.stdout)
    assert outs[0] and outs[0] == outs[1] == outs[2]
