#!/usr/bin/env python3
"""The four main jobs of stabound against their physical floor and two Python peers, in one run.

Jobs:
  main    stabound boundary --delta 0.5 --d 1                    (tol 1e-9, 31,567 rows)
  family  stabound boundary --delta 0,0.25,0.5,0.75,1 --d 0,1,2,4  (Fig. 5, 20 curves)
  amax    stabound amax --delta 0:10:1001 --d 1                  (1001 rows)
  check   stabound check --batch walls.csv                       (100,000 walls at d = 1)

For each job, in every pass (passes alternate the jobs, so that the load of a shared machine
falls on all of them alike):
  * criterion: ours in-process and the floor in-process (benches/floor.rs, one run of the
    bench binary per job, warm-up 1 s, measurement 2 s; median of the passes' medians, and
    the ratio ours / floor as the median of the passes' ratios);
  * whole process: RUNS runs of our command alternating with RUNS runs of
    `stabound --version` (process start of a trivial run), output to /dev/null; medians over
    all passes. The process floor is the in-process floor plus the --version median (the
    process ratio likewise per pass, then the median);
  * numpy: column-wise bisection with batched companion-matrix `eigvals`
    (benches/numpy_boundary.py) for the boundaries; alpha_max by bisection in alpha inside a
    golden-section search in beta, batched over all rows; the point tests by batched `eigvals`;
  * python-control: the same column-wise bisection and alpha_max search, each evaluation a
    `control.tf([1], q, dt=1).poles()`, on fewer columns / rows (given in the output), and
    `poles()` per wall on a sample of the point tests, scaled to the whole job.

The load average is read before and after. Needs numpy, scipy and control:

    python3 -m venv /tmp/venv-peer && . /tmp/venv-peer/bin/activate && pip install numpy scipy control
    python3 crates/stabound/benches/compare.py [--passes 5] [--runs 8]

Builds the release binary and the floor bench first (cargo), then prints one table.
"""
import argparse
import json
import math
import os
import re
import statistics
import subprocess
import sys
import time
from pathlib import Path

import numpy as np

HERE = Path(__file__).resolve().parent
ROOT = HERE.parents[2]
sys.path.insert(0, str(HERE))
import numpy_boundary  # noqa: E402

FAMILY = [(x, d) for x in (0.0, 0.25, 0.5, 0.75, 1.0) for d in (0.0, 1.0, 2.0, 4.0)]
TOL = 1e-9
WALLS = 100_000


def build():
    subprocess.run(["cargo", "build", "--release", "-q"], cwd=ROOT, check=True)
    r = subprocess.run(["cargo", "bench", "-p", "stabound", "--bench", "floor", "--no-run"],
                       cwd=ROOT, check=True, capture_output=True, text=True)
    m = re.search(r"\((\S+floor-[0-9a-f]+)\)", r.stderr)
    if not m:
        sys.exit("could not find the floor bench binary in cargo's output:\n" + r.stderr)
    return ROOT / "target" / "release" / "stabound", ROOT / m.group(1)


def loadavg():
    return Path("/proc/loadavg").read_text().split()[:3]


def wall_of(i):
    """Wall i of the point tests, as benches/floor.rs builds it (a Weyl sequence)."""
    def frac(g):
        x = 0.5 + i * g
        return x - math.floor(x)
    return frac(0.7548776662466927), -0.2 + 1.2 * frac(0.5698402909980532), 2.0 * frac(0.6180339887498949)


def criterion(bench, job, seconds):
    """Criterion medians (s) of ours and the floor of `job`, from this run's estimates."""
    base = ROOT / "target" / "criterion" / job
    files = {who: base / who / "new" / "estimates.json" for who in ("ours", "floor")}
    for f in files.values():
        f.unlink(missing_ok=True)
    # criterion writes under target/criterion of the working directory
    subprocess.run([str(bench), "--bench", "--warm-up-time", "1", "--measurement-time", str(seconds),
                    f"^{job}/"], cwd=ROOT, check=True,
                   stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    return {who: json.loads(f.read_text())["median"]["point_estimate"] * 1e-9 for who, f in files.items()}


def run_time(cmd):
    t = time.perf_counter()
    subprocess.run(cmd, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL, check=True)
    return time.perf_counter() - t


# ---------------------------------------------------------------- the polynomial, d = 1

def parts_d1(delta):
    """Q0, QA, QB (highest power first, degree 4) of q at d = 1 for an array of delta
    (docs/MODEL.md section 3 with n = 1, eps = 0: M = m2 z^2 + m1 z, the factor z divided out)."""
    delta = np.asarray(delta, dtype=float)
    safe = np.where(delta == 0, 1.0, delta)
    p1 = np.where(delta == 0, 1.0, -np.expm1(-delta) / safe)
    g0x = np.where(delta == 0, 0.5, (1.0 - p1) / safe)
    c = np.exp(-delta)
    m2, m1 = g0x, p1 * p1 - c * g0x
    z, o = np.zeros_like(delta), np.ones_like(delta)
    q0 = np.stack([o, -(1 + c), c, z, z], axis=-1)
    qa = np.stack([z, z, m2, m1, z], axis=-1)
    qb = np.stack([z, z, m2, m1 - m2, -m1], axis=-1)
    return q0, qa, qb


def radius_batched(coef):
    """Largest root modulus of each row of monic `coef` (highest first), batched eigvals."""
    deg = coef.shape[-1] - 1
    comp = np.zeros(coef.shape[:-1] + (deg, deg))
    comp[..., 0, :] = -coef[..., 1:]
    comp[..., np.arange(1, deg), np.arange(0, deg - 1)] = 1.0
    return np.abs(np.linalg.eigvals(comp)).max(axis=-1)


def radius_control(coef):
    import control
    return float(np.abs(control.tf([1.0], list(coef), dt=1).poles()).max())


# ---------------------------------------------------------------- boundary peers

def control_boundary(delta, d, tol, window, columns, betas):
    """Column-wise bisection as numpy_boundary.boundary, one `poles()` per evaluation."""
    q0, qa, qb = numpy_boundary.char_poly_parts(delta, d)
    a_hi, b_lo, b_hi = window
    stable = lambda a, b: radius_control(q0 + a * qa + b * qb) < 1.0  # noqa: E731
    pts = []
    beta = np.linspace(b_lo, b_hi, betas)
    for a in np.linspace(1e-6, a_hi, columns):
        s = [stable(a, b) for b in beta]
        for j in range(betas - 1):
            if s[j] != s[j + 1]:
                lo, hi = beta[j], beta[j + 1]
                while hi - lo > tol:
                    mid = 0.5 * (lo + hi)
                    if stable(a, mid) == s[j]:
                        lo = mid
                    else:
                        hi = mid
                pts.append((a, 0.5 * (lo + hi)))
    return pts


def windows_from(stabound):
    """Plot windows per family curve (alpha up to 1.2 alpha_max, beta range plus 20 %),
    read from our own output once, untimed: the peers need a window and have no way to find one."""
    out = subprocess.run([str(stabound), "boundary", "--delta", "0,0.25,0.5,0.75,1", "--d", "0,1,2,4"],
                         check=True, capture_output=True, text=True).stdout.splitlines()[1:]
    acc = {}
    for line in out:
        x, d, a, b, _ = line.split(",")
        k = (float(x), float(d))
        a, b = float(a), float(b)
        lo = acc.setdefault(k, [0.0, math.inf, -math.inf])
        lo[0], lo[1], lo[2] = max(lo[0], a), min(lo[1], b), max(lo[2], b)
    win = {}
    for k, (amax, bmin, bmax) in acc.items():
        span = bmax - bmin
        win[k] = (1.2 * amax, bmin - 0.2 * span, bmax + 0.2 * span)
    return win


# ---------------------------------------------------------------- alpha_max peers

def amax_search(radius, deltas, coarse=12, steps=32, golden=20):
    """alpha_max per delta (d = 1): the largest stable alpha at a beta, by bisection in alpha
    (`steps` halvings of [0, 1 + 1.5 delta]), maximized over beta by a coarse grid of
    `coarse` betas in [-delta, 1.2 + 1.2 delta] and then golden-section search (`golden`
    steps) between the best grid point's neighbours. `radius` maps an (N, 5) array of
    polynomials to their spectral radii."""
    deltas = np.asarray(deltas, dtype=float)
    q0, qa, qb = parts_d1(deltas)

    def edge(beta):
        lo = np.zeros_like(deltas)
        hi = 1.0 + 1.5 * deltas
        for _ in range(steps):
            mid = 0.5 * (lo + hi)
            s = radius(q0 + mid[:, None] * qa + beta[:, None] * qb) < 1.0
            lo, hi = np.where(s, mid, lo), np.where(s, hi, mid)
        return lo

    b_lo, b_hi = -deltas, 1.2 + 1.2 * deltas
    grid = [b_lo + (b_hi - b_lo) * k / (coarse - 1) for k in range(coarse)]
    vals = np.stack([edge(b) for b in grid])
    j = np.clip(vals.argmax(axis=0), 1, coarse - 2)
    idx = np.arange(len(deltas))
    g = np.stack(grid)
    lo, hi = g[j - 1, idx], g[j + 1, idx]
    r = (math.sqrt(5) - 1) / 2
    x1, x2 = hi - r * (hi - lo), lo + r * (hi - lo)
    f1, f2 = edge(x1), edge(x2)
    for _ in range(golden):
        left = f1 > f2
        hi = np.where(left, x2, hi)
        lo = np.where(left, lo, x1)
        nx1 = np.where(left, hi - r * (hi - lo), x2)
        nx2 = np.where(left, x1, lo + r * (hi - lo))
        fn = edge(np.where(left, nx1, nx2))
        f2, f1 = np.where(left, f1, fn), np.where(left, fn, f2)
        x1, x2 = nx1, nx2
    return np.maximum(f1, f2)


def control_radius_rows(coef):
    return np.array([radius_control(c) for c in coef])


# ---------------------------------------------------------------- the run

def median(xs):
    return statistics.median(xs) if xs else float("nan")


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--passes", type=int, default=5)
    ap.add_argument("--runs", type=int, default=8, help="process runs per job and pass")
    ap.add_argument("--bench-time", type=float, default=2.0)
    ap.add_argument("--jobs", default="main,family,amax,check")
    args = ap.parse_args()
    jobs = args.jobs.split(",")

    stabound, bench = build()
    walls_csv = Path("/tmp/stabound-compare-walls.csv")
    walls = np.array([wall_of(i) for i in range(WALLS)])
    with walls_csv.open("w") as f:
        f.write("alpha,beta,delta,d\n")
        for i in range(WALLS):
            a, b, x = wall_of(i)
            f.write(f"{a!r},{b!r},{x!r},1\n")
    commands = {
        "main": [str(stabound), "boundary", "--delta", "0.5", "--d", "1"],
        "family": [str(stabound), "boundary", "--delta", "0,0.25,0.5,0.75,1", "--d", "0,1,2,4"],
        "amax": [str(stabound), "amax", "--delta", "0:10:1001", "--d", "1"],
        "check": [str(stabound), "check", "--batch", str(walls_csv)],
    }
    version = [str(stabound), "--version"]
    windows = windows_from(stabound)
    ours_amax = np.loadtxt(subprocess.run(commands["amax"], check=True, capture_output=True,
                                          text=True).stdout.splitlines()[1:], delimiter=",")
    # the radius column only with --radius (the timed command prints the verdicts)
    ours_check = subprocess.run(commands["check"] + ["--radius"], check=True, capture_output=True,
                                text=True).stdout.splitlines()[1:]
    ours_radius = np.array([float(line.split(",")[5]) for line in ours_check])
    deltas = np.linspace(0.0, 10.0, 1001)
    # control's rows and walls: the first few of each job, scaled to the whole job
    amax_ctrl_rows = [0, 500, 1000]
    check_ctrl = 1000
    ctrl_cols, ctrl_betas = 20, 100
    fam_ctrl_cols, fam_ctrl_betas = 5, 40

    res = {j: {"crit_ours": [], "crit_floor": [], "proc": [], "numpy": [], "control": []} for j in jobs}
    version_times = []
    pass_version = []
    notes = {}
    load_before = loadavg()
    t_start = time.time()
    for p in range(args.passes):
        for job in jobs:
            r = res[job]
            c = criterion(bench, job, args.bench_time)
            r["crit_ours"].append(c.get("ours", float("nan")))
            r["crit_floor"].append(c.get("floor", float("nan")))
            proc, start = [], []
            for _ in range(args.runs):
                proc.append(run_time(commands[job]))
                start.append(run_time(version))
            r["proc"] += proc
            version_times += start
            # this pass's ratios: ours against the floor measured minutes apart at most
            r.setdefault("ratio_in", []).append(c["ours"] / c["floor"])
            r.setdefault("ratio_proc", []).append(median(proc) / (c["floor"] + median(start)))
            if job == "main":
                t = time.perf_counter()
                pts = numpy_boundary.boundary(0.5, 1.0, TOL)
                r["numpy"].append(time.perf_counter() - t)
                notes["main_numpy"] = f"{len(pts)} points, alpha_max found {pts[:, 0].max():.6f}"
                t = time.perf_counter()
                cp = control_boundary(0.5, 1.0, TOL, (1.2, -1.0, 2.0), ctrl_cols, ctrl_betas)
                r["control"].append(time.perf_counter() - t)
                notes["main_control"] = f"{ctrl_cols} x {ctrl_betas} grid, {len(cp)} points"
            elif job == "family":
                t = time.perf_counter()
                n = sum(len(numpy_boundary.boundary(x, d, TOL, *windows[(x, d)])) for x, d in FAMILY)
                r["numpy"].append(time.perf_counter() - t)
                notes["family_numpy"] = f"{n} points"
                t = time.perf_counter()
                n = sum(len(control_boundary(x, d, TOL, windows[(x, d)], fam_ctrl_cols, fam_ctrl_betas))
                        for x, d in FAMILY)
                r["control"].append(time.perf_counter() - t)
                notes["family_control"] = f"{fam_ctrl_cols} x {fam_ctrl_betas} grid per curve, {n} points"
            elif job == "amax":
                t = time.perf_counter()
                am = amax_search(radius_batched, deltas)
                r["numpy"].append(time.perf_counter() - t)
                err = np.abs(am - ours_amax[:, 2]).max()
                notes["amax_numpy"] = f"largest |alpha_max - ours| {err:.1e}"
                t = time.perf_counter()
                ac = amax_search(control_radius_rows, deltas[amax_ctrl_rows])
                r["control"].append((time.perf_counter() - t) * len(deltas) / len(amax_ctrl_rows))
                err = np.abs(ac - ours_amax[amax_ctrl_rows, 2]).max()
                notes["amax_control"] = (f"{len(amax_ctrl_rows)} rows timed, scaled to 1001; "
                                         f"largest |alpha_max - ours| {err:.1e}")
            elif job == "check":
                t = time.perf_counter()
                q0, qa, qb = parts_d1(walls[:, 2])
                coef = q0 + walls[:, :1] * qa + walls[:, 1:2] * qb
                rho = radius_batched(coef)
                stable = rho < 1.0
                r["numpy"].append(time.perf_counter() - t)
                far = np.abs(ours_radius - 1) > 1e-6
                agree = np.mean(stable[far] == (ours_radius[far] < 1))
                notes["check_numpy"] = (f"verdicts agree with ours on {agree:.4f} of the walls away "
                                        f"from the circle; largest |radius - ours| "
                                        f"{np.abs(rho - ours_radius).max():.1e}")
                t = time.perf_counter()
                rc = control_radius_rows(coef[:check_ctrl])
                r["control"].append((time.perf_counter() - t) * WALLS / check_ctrl)
                notes["check_control"] = (f"{check_ctrl} walls timed, scaled to {WALLS}; largest "
                                          f"|radius - ours| {np.abs(rc - ours_radius[:check_ctrl]).max():.1e}")
        print(f"pass {p + 1} done, load {' '.join(loadavg())}", file=sys.stderr)
    load_after = loadavg()
    start = median(version_times)

    def fmt(s):
        if s != s:
            return "-"
        return f"{s * 1e3:.2f} ms" if s < 1 else f"{s:.2f} s"

    print(f"date {time.strftime('%Y-%m-%d %H:%M', time.gmtime(t_start))} UTC, {os.cpu_count()} cores, "
          f"load average before {' '.join(load_before)}, after {' '.join(load_after)}; "
          f"{args.passes} passes, {args.passes * args.runs} process runs per job")
    print(f"process start (`stabound --version`, median of {len(version_times)}): {fmt(start)}")
    print("| job | ours in-process | ours process | floor in-process | floor process | "
          "in-process ratio | process ratio | numpy | python-control |")
    print("| --- | --- | --- | --- | --- | --- | --- | --- | --- |")
    for job in jobs:
        r = res[job]
        oi, fi, op = median(r["crit_ours"]), median(r["crit_floor"]), median(r["proc"])
        fp = fi + start
        ri, rp = median(r["ratio_in"]), median(r["ratio_proc"])
        print(f"| {job} | {fmt(oi)} | {fmt(op)} | {fmt(fi)} | {fmt(fp)} | {ri:.1f} | {rp:.1f} | "
              f"{fmt(median(r['numpy']))} | {fmt(median(r['control']))} |")
    print("ratios are medians of the passes' ratios (each pass's ours against that pass's floor)")
    print("per pass: ours in-process / floor in-process (ms), in-process ratio, process ratio:")
    for job in jobs:
        r = res[job]
        print(f"  {job}: " + "; ".join(f"{o * 1e3:.2f} / {f * 1e3:.2f}, {a:.1f}, {b:.1f}" for o, f, a, b in
                                       zip(r["crit_ours"], r["crit_floor"], r["ratio_in"], r["ratio_proc"])))
    for k, v in notes.items():
        print(f"  {k}: {v}")


if __name__ == "__main__":
    main()
