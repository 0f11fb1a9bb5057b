//! Speed against accuracy: prints a Markdown table of median time and
//! achieved error for every method over a ladder of tolerances.
//! Run with `cargo bench --bench tradeoff` (a few minutes on 2 cores).
//!
//! - Boundaries (exact D-decomposition, grid + bisection) at tol 1e-3 .. 1e-12: error is the
//!   Hausdorff distance to the reference, the exact boundary at 1e-12, away from the corner
//!   `(0, -delta)` (a double root at `z = 1` where point tests cannot resolve the region's thin
//!   wedge, see `tests/boundary_exact.rs`). The reference is checked by the bisection engine
//!   at 1e-12 (Hausdorff distance printed) and by the state-space spectral radius on its
//!   points (largest `|radius - 1|` printed).
//! - alpha_max at theta tolerance 1e-3 .. 1e-12: error against the run at 1e-15, which is
//!   checked against the closed form `12 - 8 sqrt 2` (delta = 0, d = 0), the exact boundary's
//!   rightmost vertex at 1e-12 and the state-space radius on both sides.
//! - Point tests (Schur-Cohn, guarded auto, companion eigenvalues, state-space eigenvalues)
//!   with marginal band `margin` = 1e-3 .. 1e-12: walls at known distances from the
//!   boundary (the D-decomposition wall of a root `e^{i theta}` on the boundary, its
//!   stiffness scaled by `1 +- s`, `s` from 1e-15 to 1e-2), reference radius by state-space
//!   eigenvalues. A verdict is wrong if it is confident (stable/unstable) and disagrees with
//!   the reference radius, or is marginal while the reference radius is more than `2 margin`
//!   from 1. "error" is the largest `|radius - 1|` of a wrong verdict (0: none): the verdict is
//!   right for every point farther from the boundary than that.

use std::hint::black_box;
use std::time::Instant;

use stabound::amax::{AmaxOptions, alpha_max};
use stabound::boundary::{
    BisectOptions, ExactOptions, Piece, bisect_alpha_beta, directed_distance, exact,
};
use stabound::params::{Plant, Wall};
use stabound::stability::{Checker, Method, Options, Verdict, spectral_radius};

/// Median seconds of `f` over repeated runs: at least 3 runs and about `budget` seconds.
fn median_time<R>(budget: f64, mut f: impl FnMut() -> R) -> f64 {
    let mut times = Vec::new();
    let start = Instant::now();
    while times.len() < 3 || (start.elapsed().as_secs_f64() < budget && times.len() < 1000) {
        let t = Instant::now();
        black_box(f());
        times.push(t.elapsed().as_secs_f64());
    }
    times.sort_by(f64::total_cmp);
    times[times.len() / 2]
}

/// Median seconds per call of `f`, each timing covering `batch` calls.
fn median_batched(budget: f64, batch: usize, mut f: impl FnMut(usize)) -> f64 {
    median_time(budget, || {
        for i in 0..batch {
            f(i)
        }
    }) / batch as f64
}

fn fmt_time(s: f64) -> String {
    if s < 1e-6 {
        format!("{:.0} ns", s * 1e9)
    } else if s < 1e-3 {
        format!("{:.1} us", s * 1e6)
    } else if s < 1.0 {
        format!("{:.1} ms", s * 1e3)
    } else {
        format!("{s:.2} s")
    }
}

/// Hausdorff distance between two closed polylines, ignoring vertices within 1e-4 of the
/// corner (0, -delta).
fn hausdorff(a: &[(f64, f64)], b: &[(f64, f64)], delta: f64) -> f64 {
    // At tight tolerances the polylines have up to ~1e6 vertices: the vertices checked are
    // subsampled to at most 20000 per side (evenly), the polylines themselves are complete.
    let keep = |p: &&(f64, f64)| p.0.hypot(p.1 + delta) > 1e-4;
    let sub = |v: &[(f64, f64)]| -> Vec<(f64, f64)> {
        let step = (v.len() / 20000).max(1);
        v.iter().step_by(step).filter(keep).copied().collect()
    };
    let (qa, qb) = (sub(a), sub(b));
    // cells of 1e-3: distances above 1e-3 are reported as 1e-3 (no tolerance in the ladder
    // comes near it)
    let h = 1e-3;
    directed_distance(&qa, b, h).max(directed_distance(&qb, a, h))
}

const TOLS: [f64; 6] = [1e-3, 1e-4, 1e-6, 1e-8, 1e-10, 1e-12];

/// Boundary tolerances: 1e-12 is the reference itself, so the ladder stops at 1e-11.
const BOUNDARY_TOLS: [f64; 7] = [1e-3, 1e-4, 1e-6, 1e-8, 1e-9, 1e-10, 1e-11];

fn boundaries(out: &mut String) {
    out.push_str("\n### Boundaries\n\n| (delta, d) | method | tol | median time | points | Hausdorff error |\n| --- | --- | --- | --- | --- | --- |\n");
    for (delta, d) in [(0.5, 1.0), (1.0, 4.0)] {
        let plant = Plant::new(delta, d).unwrap();
        let t0 = Instant::now();
        let reference = exact(plant, &ExactOptions { tol: 1e-12 }).unwrap();
        eprintln!(
            "reference exact: {} points, {:.1} s",
            reference.points.len(),
            t0.elapsed().as_secs_f64()
        );
        let r_xy = reference.xy();
        // independent checks of the reference
        let bis = bisect_alpha_beta(
            plant,
            &BisectOptions {
                tol: 1e-12,
                ..Default::default()
            },
        )
        .unwrap();
        let h_bis = hausdorff(&bis.xy(), &r_xy, delta);
        let ss = Checker::new(
            plant,
            Options {
                method: Method::StateSpace,
                ..Default::default()
            },
        )
        .unwrap();
        let step = (reference.points.len() / 400).max(1);
        let worst_radius = reference
            .points
            .iter()
            .step_by(step)
            .filter(|p| p.x > 1e-6 && p.piece != Piece::AlphaZero)
            .map(|p| {
                let r = spectral_radius(
                    &ss.roots(&Wall::new(p.x, p.y).unwrap(), Method::StateSpace)
                        .unwrap(),
                );
                (r - 1.0).abs()
            })
            .fold(0.0, f64::max);
        eprintln!(
            "reference ({delta}, {d}): exact 1e-12, {} points; bisection 1e-12 Hausdorff {h_bis:.1e}; state-space |radius - 1| <= {worst_radius:.1e}",
            r_xy.len()
        );
        out.push_str(&format!(
            "| ({delta}, {d}) | reference: exact 1e-12 | | | {} | vs bisection 1e-12: {h_bis:.1e}; state-space \\|radius-1\\| <= {worst_radius:.1e} |\n",
            r_xy.len()
        ));
        let t0 = Instant::now();
        for &tol in &BOUNDARY_TOLS {
            let t = median_time(2.0, || exact(plant, &ExactOptions { tol }).unwrap());
            let b = exact(plant, &ExactOptions { tol }).unwrap();
            let e = hausdorff(&b.xy(), &r_xy, delta);
            out.push_str(&format!(
                "| ({delta}, {d}) | exact | {tol:.0e} | {} | {} | {e:.1e} |\n",
                fmt_time(t),
                b.points.len()
            ));
        }
        eprintln!("exact ladder {:.0} s", t0.elapsed().as_secs_f64());
        for &tol in &BOUNDARY_TOLS {
            let opts = BisectOptions {
                tol,
                ..Default::default()
            };
            let t = median_time(2.0, || bisect_alpha_beta(plant, &opts).unwrap());
            let b = bisect_alpha_beta(plant, &opts).unwrap();
            let e = hausdorff(&b.xy(), &r_xy, delta);
            out.push_str(&format!(
                "| ({delta}, {d}) | grid+bisection | {tol:.0e} | {} | {} | {e:.1e} |\n",
                fmt_time(t),
                b.points.len()
            ));
        }
        eprintln!("boundaries ({delta}, {d}) done");
    }
}

fn amax_table(out: &mut String) {
    out.push_str("\n### alpha_max\n\n| (delta, d) | theta tol | median time | error in alpha_max | error in beta |\n| --- | --- | --- | --- | --- |\n");
    for (delta, d) in [(0.0, 0.0), (0.5, 1.0), (1.0, 4.0), (1.0, 50.0)] {
        let plant = Plant::new(delta, d).unwrap();
        let r = alpha_max(plant, &AmaxOptions::new(1e-15).unwrap()).unwrap();
        // independent checks of the reference
        let mut checks = String::new();
        if delta == 0.0 && d == 0.0 {
            checks += &format!(
                "closed form 12 - 8 sqrt 2: {:.1e}; ",
                (r.alpha_max - (12.0 - 8.0 * 2f64.sqrt())).abs()
            );
        }
        if d < 10.0 {
            let (ea, _) = exact(plant, &ExactOptions { tol: 1e-12 })
                .unwrap()
                .rightmost();
            checks += &format!(
                "exact boundary 1e-12 rightmost: {:.1e}; ",
                (r.alpha_max - ea).abs()
            );
        }
        let ss = Checker::new(
            plant,
            Options {
                method: Method::StateSpace,
                ..Default::default()
            },
        )
        .unwrap();
        let rad = |f: f64| {
            spectral_radius(
                &ss.roots(
                    &Wall::new(r.alpha_max * f, r.beta_at_max).unwrap(),
                    Method::StateSpace,
                )
                .unwrap(),
            )
        };
        checks += &format!(
            "state-space radius at (1 -+ 1e-8) alpha_max: 1 {:+.1e}, 1 {:+.1e}",
            rad(1.0 - 1e-8) - 1.0,
            rad(1.0 + 1e-8) - 1.0
        );
        eprintln!(
            "alpha_max reference ({delta}, {d}) = {:.15} at beta {:.15}: {checks}",
            r.alpha_max, r.beta_at_max
        );
        out.push_str(&format!(
            "| ({delta}, {d}) | reference 1e-15: {:.12} | | {checks} | |\n",
            r.alpha_max
        ));
        for &tol in &TOLS {
            let opts = AmaxOptions::new(tol).unwrap();
            let t = median_time(1.0, || alpha_max(plant, &opts).unwrap());
            let a = alpha_max(plant, &opts).unwrap();
            out.push_str(&format!(
                "| ({delta}, {d}) | {tol:.0e} | {} | {:.1e} | {:.1e} |\n",
                fmt_time(t),
                (a.alpha_max - r.alpha_max).abs(),
                (a.beta_at_max - r.beta_at_max).abs()
            ));
        }
    }
}

fn points(out: &mut String) {
    out.push_str("\n### Point tests\n\n| d (degree) | method | margin | median time per verdict | wrong verdicts | error: largest \\|radius - 1\\| of a wrong verdict | fallbacks |\n| --- | --- | --- | --- | --- | --- | --- |\n");
    let margins = [1e-3, 1e-6, 1e-9, 1e-12];
    for (delta, d) in [(0.5, 1.0), (1.0, 20.0), (1.0, 100.0)] {
        let plant = Plant::new(delta, d).unwrap();
        let ss = Checker::new(
            plant,
            Options {
                method: Method::StateSpace,
                ..Default::default()
            },
        )
        .unwrap();
        let b = exact(plant, &ExactOptions { tol: 1e-6 }).unwrap();
        // boundary walls of the curve, then scaled off the boundary
        let curve: Vec<Wall> = b
            .points
            .iter()
            .filter(|p| p.piece == Piece::Curve && p.x > 1e-3)
            .step_by((b.points.len() / 12).max(1))
            .map(|p| Wall::new(p.x, p.y).unwrap())
            .collect();
        let mut walls: Vec<(Wall, f64)> = Vec::new();
        for w0 in &curve {
            for e in [-15, -14, -13, -12, -11, -10, -9, -8, -7, -6, -5, -4, -3, -2] {
                for sgn in [-1.0, 1.0] {
                    let w = Wall::new(w0.alpha() * (1.0 + sgn * 10f64.powi(e)), w0.beta()).unwrap();
                    let r = spectral_radius(&ss.roots(&w, Method::StateSpace).unwrap());
                    walls.push((w, r));
                }
            }
        }
        let methods = [
            Method::SchurCohn,
            Method::Auto,
            Method::Eigen,
            Method::StateSpace,
            Method::ArgumentPrinciple,
        ];
        for &margin in &margins {
            for method in methods {
                let c = Checker::new(plant, Options { method, margin }).unwrap();
                let (mut wrong, mut err, mut fallbacks) = (0, 0.0f64, 0);
                for &(w, r) in &walls {
                    let dec = c.decide(&w).unwrap();
                    fallbacks += usize::from(dec.fallback);
                    let gap = (r - 1.0).abs();
                    let bad = match dec.verdict {
                        Verdict::Stable => r >= 1.0,
                        Verdict::Unstable => r <= 1.0,
                        Verdict::Marginal => gap > 2.0 * margin,
                    };
                    if bad {
                        wrong += 1;
                        err = err.max(gap);
                    }
                }
                let budget = if d > 50.0 { 0.5 } else { 0.3 };
                let n = walls.len();
                let t = median_batched(budget, if d > 50.0 { 4 } else { n.min(64) }, |i| {
                    black_box(c.verdict(&walls[i % n].0).unwrap());
                });
                out.push_str(&format!(
                    "| {d} ({}) | {} | {margin:.0e} | {} | {wrong} of {n} | {err:.1e} | {fallbacks} |\n",
                    plant.degree(),
                    method.name(),
                    fmt_time(t)
                ));
            }
        }
        eprintln!("points d = {d} done");
    }
}

fn main() {
    // `cargo bench` passes `--bench`; any other argument filters the sections.
    let args: Vec<String> = std::env::args()
        .skip(1)
        .filter(|a| !a.starts_with("--"))
        .collect();
    let want = |s: &str| args.is_empty() || args.iter().any(|a| s.contains(a.as_str()));
    let mut out = String::from("## Speed against accuracy\n");
    let start = Instant::now();
    if want("boundaries") {
        boundaries(&mut out);
    }
    if want("amax") {
        amax_table(&mut out);
    }
    if want("points") {
        points(&mut out);
    }
    println!("{out}");
    eprintln!("total {:.0} s", start.elapsed().as_secs_f64());
}
