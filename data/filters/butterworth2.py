"""Writes butterworth2.csv: the second-order Butterworth low-pass coefficients that
scipy.signal.butter(2, 2 f_c T) returns, for the cutoffs f_c T the tests use.

Bless (regenerate) explicitly, with scipy installed:

    python3 data/filters/butterworth2.py > data/filters/butterworth2.csv

Each row: f_c T, then b0, b1, b2 (numerator) and a0, a1, a2 (denominator, a0 = 1), highest
power of z first, every float written with repr (round-trips exactly).
"""

import scipy
import scipy.signal

CUTOFFS = [0.001, 0.01, 0.03, 0.04, 0.1, 0.2, 0.25, 0.3, 0.45, 0.499]

print(f"# scipy {scipy.__version__}: scipy.signal.butter(2, 2 * fcT)")
print("fcT,b0,b1,b2,a0,a1,a2")
for fct in CUTOFFS:
    b, a = scipy.signal.butter(2, 2 * fct)
    print(",".join(repr(float(x)) for x in [fct, *b, *a]))
