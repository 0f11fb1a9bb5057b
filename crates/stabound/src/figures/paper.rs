//! The recipes of the paper's Figs. 5 to 10: which curves, in which plane, with which
//! labels, and the CSV rows behind them.

use crate::amax::{AmaxOptions, amax_series};
use crate::boundary::{self, Axis, BisectOptions, ExactOptions, Piece, Plane, Vertex};
use crate::error::Result;
use crate::params::{Normalized, Plant};
use crate::passivity;
use crate::plot::{Figure, Legend, LineStyle};

use super::FigureData;

/// Axis labels of the `(alpha, beta)` plane.
pub(crate) const AB_X: &str = "virtual stiffness α";
/// See [`AB_X`].
pub(crate) const AB_Y: &str = "virtual damping β";
/// Axis labels of the `(delta, beta)` plane.
pub(crate) const DB_X: &str = "physical damping δ";
/// See [`DB_X`].
pub(crate) const DB_Y: &str = AB_Y;
/// The legend key of the dash-dotted passive region (a series without points).
pub(crate) const PASSIVE_KEY: &str = "passive region";

/// Physical dampings of the paper's Figs. 5 and 8.
pub const FIG5_DELTAS: [f64; 5] = [0.0, 0.25, 0.5, 0.75, 1.0];
/// Delay factors of the paper's Fig. 5 (one panel each).
pub const FIG5_DELAYS: [f64; 4] = [0.0, 1.0, 2.0, 4.0];
/// Delay factors of the paper's Fig. 6.
pub const FIG6_DELAYS: [f64; 6] = [0.0, 0.25, 0.5, 1.0, 2.0, 4.0];
/// Physical dampings of Fig. 7 (`d = 0`, large `delta`): around and above 2.3, where the
/// line of walls with the root `z = -1` (slope `-1/2`) starts to bound the region from above.
pub const FIG7_DELTAS: [f64; 5] = [1.5, 2.3, 3.0, 4.0, 5.0];
/// Stiffnesses of the paper's Fig. 9.
pub const FIG9_ALPHAS: [f64; 4] = [0.0, 1.0, 2.0, 4.0];
/// The `delta` range of the `(delta, beta)` figures 6 and 9.
pub const DELTA_BETA_RANGE: f64 = 4.0;

pub(crate) fn columns(names: &[&str]) -> Vec<String> {
    names.iter().map(|s| s.to_string()).collect()
}

/// CSV rows `(kind, a, b, x, y)` of one polyline with the two fixed parameters `a`, `b`.
fn rows_of(kind: &str, a: f64, b: f64, pts: &[(f64, f64)]) -> Vec<(String, Vec<f64>)> {
    pts.iter()
        .map(|&(x, y)| (kind.to_string(), vec![a, b, x, y]))
        .collect()
}

/// Paper Fig. 5: stability boundaries in the `(alpha, beta)` plane for `d` in
/// [`FIG5_DELAYS`] (one panel each) and `delta` in [`FIG5_DELTAS`], with the path of maximum
/// stiffness (dashed) for `delta` from 0 to 1. Rows: `(series, d, delta, alpha, beta)` with
/// series `boundary` or `path`.
pub fn fig05() -> Result<FigureData> {
    let mut panels = Vec::new();
    let mut rows = Vec::new();
    // 41 points, so that the figure's deltas (multiples of 1/4) are on the path exactly.
    let path_deltas: Vec<f64> = (0..=40).map(|i| i as f64 / 40.0).collect();
    for &d in &FIG5_DELAYS {
        let mut fig = Figure::new(
            &format!("Fig. 5: stability boundaries, d = {d}"),
            AB_X,
            AB_Y,
        );
        for (ci, &delta) in FIG5_DELTAS.iter().enumerate() {
            let pts = ab_curve(delta, d)?;
            let legend = format!("δ = {delta}");
            rows.extend(rows_of("boundary", d, delta, &pts));
            fig.push(legend, pts, LineStyle::Solid, ci);
        }
        let path = amax_series(&path_deltas, d, &AmaxOptions::default())?;
        for p in &path {
            rows.push(("path".into(), vec![d, p.delta, p.alpha_max, p.beta_at_max]));
        }
        fig.push(
            "max. stiffness path",
            path.iter().map(|p| (p.alpha_max, p.beta_at_max)).collect(),
            LineStyle::Dashed,
            7,
        );
        panels.push(fig);
    }
    Ok(FigureData {
        name: "fig05".into(),
        panels,
        columns_of_panels: 2,
        columns: columns(&["series", "d", "delta", "alpha", "beta"]),
        rows,
    })
}

/// Paper Fig. 6: stability boundaries in the `(delta, beta)` plane at `alpha = 0` (the limit
/// `alpha -> 0+`) for `d` in [`FIG6_DELAYS`]. Rows: `(series, d, alpha, delta, beta)`.
pub fn fig06() -> Result<FigureData> {
    let mut fig = Figure::new("Fig. 6: stability boundaries at α = 0", DB_X, DB_Y);
    let mut rows = Vec::new();
    for (ci, &d) in FIG6_DELAYS.iter().enumerate() {
        let pts = db_curve(0.0, d, DELTA_BETA_RANGE)?;
        rows.extend(
            pts.iter()
                .map(|&(dl, b)| ("boundary".to_string(), vec![d, 0.0, dl, b])),
        );
        fig.push(format!("d = {d}"), pts, LineStyle::Solid, ci);
    }
    // the floor beta = -delta (eq. 19), which every boundary of the plane follows
    fig.push(
        "floor β = −δ",
        vec![(0.0, 0.0), (DELTA_BETA_RANGE, -DELTA_BETA_RANGE)],
        LineStyle::Band,
        7,
    );
    fig.x_range = Some((0.0, DELTA_BETA_RANGE));
    fig.legend = Legend::LowerLeft;
    Ok(FigureData {
        name: "fig06".into(),
        panels: vec![fig],
        columns_of_panels: 1,
        columns: columns(&["series", "d", "alpha", "delta", "beta"]),
        rows,
    })
}

/// Paper Fig. 7: `d = 0` and large `delta` ([`FIG7_DELTAS`]); above `delta = 2.3` a line
/// with slope `-1/2` (walls with the root `z = -1`) bounds the stable region from above.
/// Rows: `(series, d, delta, alpha, beta)`.
pub fn fig07() -> Result<FigureData> {
    let mut fig = Figure::new("Fig. 7: stability boundaries, d = 0, large δ", AB_X, AB_Y);
    let mut rows = Vec::new();
    for (ci, &delta) in FIG7_DELTAS.iter().enumerate() {
        let pts = ab_curve(delta, 0.0)?;
        let legend = format!("δ = {delta}");
        rows.extend(rows_of("boundary", 0.0, delta, &pts));
        fig.push(legend, pts, LineStyle::Solid, ci);
    }
    Ok(FigureData {
        name: "fig07".into(),
        panels: vec![fig],
        columns_of_panels: 1,
        columns: columns(&["series", "d", "delta", "alpha", "beta"]),
        rows,
    })
}

/// Paper Fig. 8: `d = 0`, `delta` in [`FIG5_DELTAS`], with Colgate's passive region
/// (eq. 21) dash-dotted in the same colour. Rows: `(series, d, delta, alpha, beta)` with
/// series `boundary` or `passivity`.
pub fn fig08() -> Result<FigureData> {
    let mut fig = Figure::new("Fig. 8: stability and passivity, d = 0", AB_X, AB_Y);
    let mut rows = Vec::new();
    for (ci, &delta) in FIG5_DELTAS.iter().enumerate() {
        let pts = ab_curve(delta, 0.0)?;
        let legend = format!("δ = {delta}");
        rows.extend(rows_of("boundary", 0.0, delta, &pts));
        fig.push(legend, pts, LineStyle::Solid, ci);
        let pass = passivity::boundary_alpha_beta(delta);
        rows.extend(rows_of("passivity", 0.0, delta, &pass));
        fig.push(String::new(), pass, LineStyle::DashDot, ci);
    }
    fig.push(PASSIVE_KEY, Vec::new(), LineStyle::DashDot, 0);
    Ok(FigureData {
        name: "fig08".into(),
        panels: vec![fig],
        columns_of_panels: 1,
        columns: columns(&["series", "d", "delta", "alpha", "beta"]),
        rows,
    })
}

/// Paper Fig. 9: the `(delta, beta)` plane for `d = 0` and `alpha` in [`FIG9_ALPHAS`], with
/// Colgate's passive wedge (eq. 21) dash-dotted. Rows: `(series, d, alpha, delta, beta)`.
pub fn fig09() -> Result<FigureData> {
    let mut fig = Figure::new("Fig. 9: stability and passivity, d = 0", DB_X, DB_Y);
    let mut rows = Vec::new();
    for (ci, &alpha) in FIG9_ALPHAS.iter().enumerate() {
        let pts = db_curve(alpha, 0.0, DELTA_BETA_RANGE)?;
        rows.extend(
            pts.iter()
                .map(|&(dl, b)| ("boundary".to_string(), vec![0.0, alpha, dl, b])),
        );
        fig.push(format!("α = {alpha}"), pts, LineStyle::Solid, ci);
        let pass = passivity::boundary_delta_beta(alpha, DELTA_BETA_RANGE);
        rows.extend(
            pass.iter()
                .map(|&(dl, b)| ("passivity".to_string(), vec![0.0, alpha, dl, b])),
        );
        fig.push(String::new(), pass, LineStyle::DashDot, ci);
    }
    fig.push(PASSIVE_KEY, Vec::new(), LineStyle::DashDot, 0);
    fig.x_range = Some((0.0, DELTA_BETA_RANGE));
    fig.legend = Legend::LowerLeft;
    Ok(FigureData {
        name: "fig09".into(),
        panels: vec![fig],
        columns_of_panels: 1,
        columns: columns(&["series", "d", "alpha", "delta", "beta"]),
        rows,
    })
}

/// The exact stability boundary in the `(alpha, beta)` plane for `(delta, d)` without the
/// axis `alpha = 0` (method: [`boundary::exact`], D-decomposition).
pub(crate) fn ab_curve(delta: f64, d: f64) -> Result<Vec<(f64, f64)>> {
    let b = boundary::exact(Plant::new(delta, d)?, &ExactOptions { tol: FIGURE_TOL })?;
    // The line alpha = 0 (root z = 1) bounds every region; like the paper, draw the curve
    // from its lower start (0, -delta) round to its upper end and leave the axis out.
    let mut out: Vec<(f64, f64)> = Vec::with_capacity(b.points.len());
    for w in b.points.windows(2) {
        if w[0].piece == Piece::AlphaZero {
            if out.last().is_some_and(|p| !p.0.is_nan()) {
                out.push((f64::NAN, f64::NAN));
            }
            continue;
        }
        if out.last().is_none_or(|p| p.0.is_nan()) {
            out.push((w[0].x, w[0].y));
        }
        out.push((w[1].x, w[1].y));
    }
    while out.last().is_some_and(|p| p.0.is_nan()) {
        out.pop();
    }
    Ok(out)
}

/// The stability boundary in the `(delta, beta)` plane for `(alpha, d)` and `delta` in
/// `[0, delta_hi]` (at `alpha = 0` the limit `alpha -> 0+`), by [`boundary::bisect`] (grid,
/// bisection and refinement), as drawn: the edges of the `delta` range are left out
/// ([`boundary_lines`]), NaN pairs separate the pieces.
pub(crate) fn db_curve(alpha: f64, d: f64, delta_hi: f64) -> Result<Vec<(f64, f64)>> {
    let plane = Plane {
        x: Axis::Delta,
        y: Axis::Beta,
        at: Normalized::new(alpha, 0.0, 0.0, d)?,
    };
    let contour = boundary::bisect(
        plane.at.plant(),
        &plane,
        &BisectOptions {
            tol: FIGURE_TOL,
            x_range: Some((0.0, delta_hi)),
            ..BisectOptions::default()
        },
    )?;
    let mut out = Vec::new();
    for lp in &contour.loops {
        for piece in boundary_lines(lp) {
            if !out.is_empty() {
                out.push((f64::NAN, f64::NAN));
            }
            out.extend(piece);
        }
    }
    Ok(out)
}

/// The pieces of one closed contour of [`boundary::bisect`] that are stability boundary, as
/// `(x, y)` polylines: segments along an edge of the requested box (both ends clipped, or one
/// clipped end and the other on the same vertical edge) are not boundary and are left out, so
/// that a drawing shows only where stability changes.
pub fn boundary_lines(contour: &[Vertex]) -> Vec<Vec<(f64, f64)>> {
    let mut out: Vec<Vec<(f64, f64)>> = Vec::new();
    let mut current: Vec<(f64, f64)> = Vec::new();
    for w in contour.windows(2) {
        let (a, b) = (w[0], w[1]);
        // exact comparison: edge points carry the range value itself
        let on_edge = (a.clipped() && b.clipped()) || ((a.clipped() || b.clipped()) && a.x == b.x);
        if on_edge {
            if current.len() > 1 {
                out.push(std::mem::take(&mut current));
            }
            current.clear();
            continue;
        }
        if current.is_empty() {
            current.push((a.x, a.y));
        }
        current.push((b.x, b.y));
    }
    if current.len() > 1 {
        out.push(current);
    }
    out
}

/// Tolerance of the figures' boundaries: `1e-5` in the normalized parameters, over fifty
/// times below a pixel of any of these plots at the default size (the smallest axis span,
/// 0.35 over some 380 px, is 9e-4 per pixel), and coarse enough to keep `figure all` fast and the CSVs small.
pub const FIGURE_TOL: f64 = 1e-5;

/// Delay factors of the paper's Fig. 10.
pub const FIG10_DELAYS: [f64; 7] = [0.0, 0.125, 0.25, 0.5, 1.0, 2.0, 4.0];

/// Paper Fig. 10: `alpha_max` against `delta` for `d` in [`FIG10_DELAYS`], in two scalings:
/// (a) `delta` in `[0, 1]` and (b) `delta` in `[0, 10]`, where the dependency becomes linear
/// (eq. 22). Rows: `(series, d, delta, alpha_max, beta_at_max)`; series `a` or `b`.
pub fn fig10() -> Result<FigureData> {
    let scalings = [("a", 1.0, 101usize), ("b", 10.0, 201usize)];
    let mut panels = Vec::new();
    let mut rows = Vec::new();
    for (tag, hi, count) in scalings {
        let deltas: Vec<f64> = (0..count)
            .map(|i| hi * i as f64 / (count - 1) as f64)
            .collect();
        let mut fig = Figure::new(
            &format!("Fig. 10 ({tag}): maximum stable stiffness, δ ≤ {hi}"),
            DB_X,
            "maximum stiffness α_{max}",
        );
        for (ci, &d) in FIG10_DELAYS.iter().enumerate() {
            let series = amax_series(&deltas, d, &AmaxOptions::default())?;
            fig.push(
                format!("d = {d}"),
                series.iter().map(|p| (p.delta, p.alpha_max)).collect(),
                LineStyle::Solid,
                ci,
            );
            rows.extend(series.iter().map(|p| {
                (
                    tag.to_string(),
                    vec![d, p.delta, p.alpha_max, p.beta_at_max],
                )
            }));
        }
        fig.x_range = Some((0.0, hi));
        fig.legend = Legend::UpperLeft;
        panels.push(fig);
    }
    Ok(FigureData {
        name: "fig10".into(),
        panels,
        columns_of_panels: 2,
        columns: ["series", "d", "delta", "alpha_max", "beta_at_max"]
            .map(String::from)
            .to_vec(),
        rows,
    })
}
