#!/usr/bin/env python3
"""Reference spectral radii of walls near the alpha = 0 edge of a stiff transmission, at 40
digits with mpmath, independent of stabound's code: the device's continuous model
(docs/MODEL.md, section 8), its zero-order-hold discretization by mpmath's matrix
exponential of the augmented matrix (Van Loan 1978), the closed loop's state matrix for a
whole-sample delay without velocity filter, and its eigenvalues by mpmath's QR.

    python3 tools/stiff_reference.py > data/stiff/walls.csv

The walls: alpha from 1e-12 to 1e-10 on a geometric grid, beta spread over [0.001, 0.02]
by the golden-ratio sequence; on this device the root of the free integrator sits within
a few 1e-9 inside the unit circle, where double-precision discretization errs by more than
the default marginal band."""

import mpmath as mp

mp.mp.dps = 40

#: The device, normalized (mass 1 kg, period 1 s): delta, whole-sample delay, handle ratio,
#: coupling stiffness, coupling damping, handle-side damping, encoder side.
DEVICE = dict(delta="0.001", d=1, r="0.3", kappa_c="521140.08", delta_c="0", delta_2="0", encoder="handle")


def continuous(delta, r, kc, dc, d2, encoder):
    """A, b, c of a compliant transmission (states x1, v1, x2, v2)."""
    d1 = delta - d2
    m1, m2 = 1 - r, r
    a = mp.zeros(4, 4)
    a[0, 1] = 1
    a[1, 0], a[1, 1], a[1, 2], a[1, 3] = -kc / m1, -(d1 + dc) / m1, kc / m1, dc / m1
    a[2, 3] = 1
    a[3, 0], a[3, 1], a[3, 2], a[3, 3] = kc / m2, dc / m2, -kc / m2, -(d2 + dc) / m2
    b = [0, 1 / m1, 0, 0]
    c = [1, 0, 0, 0] if encoder == "motor" else [0, 0, 1, 0]
    return a, b, c


def radius(device, alpha, beta):
    """The closed loop's spectral radius for the wall (alpha, beta), at mp.dps digits."""
    a, b, c = continuous(*(mp.mpf(device[k]) for k in ("delta", "r", "kappa_c", "delta_c", "delta_2")), device["encoder"])
    return loop_radius(a, b, c, device["d"], alpha, beta)


def loop_radius(a, b, c, n, alpha, beta, pole=None):
    """The spectral radius of the closed loop of the device x' = A x + b u, y = c^T x, a
    whole-sample delay n and the wall u = -(alpha y + beta w): w the backward difference, or
    with a first-order low-pass of pole `pole`, w_k = pole w_{k-1} + (1 - pole)(y_k - y_{k-1})."""
    s = a.rows
    aug = mp.zeros(s + 1, s + 1)
    for i in range(s):
        for j in range(s):
            aug[i, j] = a[i, j]
        aug[i, s] = b[i]
    e = mp.expm(aug)
    # state [x_k, u_{k-1}, ..., u_{k-n}, memory]: y_{k-1} (w_k = y_k - y_{k-1}), or for the
    # low-pass p_k = pole w_{k-1} - (1 - pole) y_{k-1} (w_k = (1 - pole) y_k + p_k)
    dim = s + n + 1
    mem = s + n
    m = mp.zeros(dim, dim)
    y = [c[j] if j < s else 0 for j in range(dim)]
    if pole is None:
        w = [y[j] - (1 if j == mem else 0) for j in range(dim)]
        memory = y
    else:
        w = [(1 - pole) * y[j] + (1 if j == mem else 0) for j in range(dim)]
        memory = [-(1 - pole) ** 2 * y[j] + (pole if j == mem else 0) for j in range(dim)]
    u = [-(alpha * y[j] + beta * w[j]) for j in range(dim)]
    applied = u if n == 0 else [1 if col == s + n - 1 else 0 for col in range(dim)]
    for i in range(s):
        for j in range(s):
            m[i, j] = e[i, j]
        for col in range(dim):
            m[i, col] += e[i, s] * applied[col]
    if n > 0:
        for col in range(dim):
            m[s, col] = u[col]
        for j in range(1, n):
            m[s + j, s + j - 1] = 1
    for col in range(dim):
        m[mem, col] = memory[col]
    return max(abs(z) for z in mp.eig(m, left=False, right=False))


def walls(count=30):
    """The walls (alpha, beta) as exact decimal strings."""
    golden = (5 ** 0.5 - 1) / 2
    out = []
    for i in range(count):
        alpha = 10 ** (-12 + 2 * i / (count - 1))
        beta = 0.001 + 0.019 * ((i * golden) % 1)
        out.append((f"{alpha:.6e}", f"{beta:.6e}"))
    return out


def main():
    d = DEVICE
    print("delta,d,r,kappa_c,encoder,alpha,beta,radius")
    for alpha, beta in walls():
        rho = radius(d, mp.mpf(alpha), mp.mpf(beta))
        print(f"{d['delta']},{d['d']},{d['r']},{d['kappa_c']},{d['encoder']},{alpha},{beta},{mp.nstr(rho, 25)}")


if __name__ == "__main__":
    main()
