"""Ctrl-C: a long call raises KeyboardInterrupt, never a panic, also when it is the first call
of the process that makes an array."""

import signal
import subprocess
import sys
import time

import pytest

# Each call runs far longer than the time limit below when nothing interrupts it.
CALLS = {
    "check": "stabound.check(np.full(10_000, 1e-6), 0.001, 0.5, 500.0, method='state-space')",
    "step": "stabound.step(mass=0.1, period=1e-3, damping=list(np.linspace(0, 100, 2000)), "
            "delay_samples=1, stiffness=1e3, duration=2.0, points_per_period=100)",
    "alpha_max": "stabound.alpha_max(np.linspace(0, 10, 1_000_000), 40.0)",
    "table": "stabound.table(mass=0.1, period=1e-3, damping=list(np.linspace(0, 2, 100)), "
             "delay_samples=[1, 2, 3, 4, 5, 6, 7, 8], hand_mass=0.05, hand_stiffness=200.0, "
             "conservative=True)",
    "passivity": "stabound.passivity(3.0, 20, plane='delta-beta', alpha=0.05, "
                 "velocity_filter_samples=4, columns=20000)",
}

SCRIPT = """
import sys, numpy as np, stabound
print("ready", flush=True)
try:
    {call}
except KeyboardInterrupt:
    print("interrupted", flush=True)
    sys.exit(3)
print("finished", flush=True)
"""


@pytest.mark.parametrize("name", sorted(CALLS))
def test_ctrl_c_raises_keyboard_interrupt(name, tmp_path):
    p = subprocess.Popen([sys.executable, "-c", SCRIPT.format(call=CALLS[name])],
                         stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True, cwd=tmp_path)
    try:
        assert p.stdout.readline().strip() == "ready"
        time.sleep(1.0)  # well inside the call
        p.send_signal(signal.SIGINT)
        # not a speed assertion: a call that ignored Ctrl-C would run on well past this limit
        out, err = p.communicate(timeout=20)
    finally:
        p.kill()
    assert "PanicException" not in err, err
    assert p.returncode == 3 and "interrupted" in out, (p.returncode, out, err)
