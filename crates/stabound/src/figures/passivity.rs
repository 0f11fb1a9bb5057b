//! Companions of the paper's Figs. 8 and 9 for delayed loops: the stability boundaries of
//! `d = 1, 2, 4` with the passive region of the same delay (`delay`) dash-dotted in
//! the same colour. The paper draws only `d = 0`, where the passive region is Colgate's
//! triangle (eq. 21); these show how the passive region shrinks with the delay and stays
//! inside the stable region.

use super::FigureData;
use super::paper::{
    AB_X, AB_Y, DB_X, DB_Y, DELTA_BETA_RANGE, FIG5_DELTAS, FIG9_ALPHAS, FIGURE_TOL, PASSIVE_KEY,
    ab_curve, columns, db_curve,
};
use crate::error::{Error, Result};
use crate::filter::VelocityFilter;
use crate::passivity::Criterion;
use crate::plot::{Figure, Legend, LineStyle};

/// The delays of the companion figures.
pub const COMPANION_DELAYS: [f64; 3] = [1.0, 2.0, 4.0];

/// The names of every companion figure, in order: `fig08-d1`, `fig08-d2`, `fig08-d4`,
/// `fig09-d1`, `fig09-d2`, `fig09-d4`.
pub fn companion_names() -> Vec<String> {
    [8, 9]
        .iter()
        .flat_map(|f| {
            COMPANION_DELAYS
                .iter()
                .map(move |d| format!("fig{f:02}-d{d}"))
        })
        .collect()
}

/// The companion of the paper's figure `figure` (8 or 9) for delay `d` (a whole number of
/// samples).
///
/// Fig. 8's companion: the `(alpha, beta)` plane, `delta` in [`FIG5_DELTAS`]; rows
/// `(series, d, delta, alpha, beta)`. Fig. 9's: the `(delta, beta)` plane up to
/// [`DELTA_BETA_RANGE`], `alpha` in [`FIG9_ALPHAS`] divided by `1 + 2d` (Diolaiti's delay
/// scaling: the paper's stiffnesses have no stable wall below `delta = 4` at `d = 4`, and
/// scaled ones keep the passive wedges' apexes where Fig. 9 has them); rows
/// `(series, d, alpha, delta, beta)`.
/// Series `boundary` (stability, exact D-decomposition or bisection as in the paper's
/// figures) or `passivity` (the sandwich algorithm, [`Criterion`]), both to
/// [`FIGURE_TOL`]. The passive region's side on `alpha = 0` is left out, as in Fig. 8.
pub fn companion(figure: u32, d: f64) -> Result<FigureData> {
    let crit = Criterion::new(d, VelocityFilter::none())?;
    let mut rows = Vec::new();
    match figure {
        8 => {
            let mut fig = Figure::new(&format!("Stability and passivity, d = {d}"), AB_X, AB_Y);
            for (ci, &delta) in FIG5_DELTAS.iter().enumerate() {
                let pts = ab_curve(delta, d)?;
                rows.extend(
                    pts.iter()
                        .map(|&(a, b)| ("boundary".into(), vec![d, delta, a, b])),
                );
                fig.push(format!("δ = {delta}"), pts, LineStyle::Solid, ci);
                let mut pass = crit.region_alpha_beta(delta, FIGURE_TOL)?.xy();
                pass.pop(); // the closing side along alpha = 0
                rows.extend(
                    pass.iter()
                        .map(|&(a, b)| ("passivity".into(), vec![d, delta, a, b])),
                );
                fig.push(String::new(), pass, LineStyle::DashDot, ci);
            }
            fig.push(PASSIVE_KEY, Vec::new(), LineStyle::DashDot, 0);
            Ok(FigureData {
                name: format!("fig08-d{d}"),
                panels: vec![fig],
                columns_of_panels: 1,
                columns: columns(&["series", "d", "delta", "alpha", "beta"]),
                rows,
            })
        }
        9 => {
            let mut fig = Figure::new(&format!("Stability and passivity, d = {d}"), DB_X, DB_Y);
            for (ci, &alpha0) in FIG9_ALPHAS.iter().enumerate() {
                let alpha = alpha0 / (1.0 + 2.0 * d);
                let pts = db_curve(alpha, d, DELTA_BETA_RANGE)?;
                rows.extend(
                    pts.iter()
                        .map(|&(x, b)| ("boundary".into(), vec![d, alpha, x, b])),
                );
                // four decimals, without trailing zeros: 0.3333, 0.2 (not 0.2000)
                let shown = format!("{alpha:.4}");
                let shown = shown.trim_end_matches('0').trim_end_matches('.');
                fig.push(format!("α = {shown}"), pts, LineStyle::Solid, ci);
                let pass = crit
                    .region_delta_beta(alpha, DELTA_BETA_RANGE, FIGURE_TOL)?
                    .xy();
                rows.extend(
                    pass.iter()
                        .map(|&(x, b)| ("passivity".into(), vec![d, alpha, x, b])),
                );
                fig.push(String::new(), pass, LineStyle::DashDot, ci);
            }
            fig.push(PASSIVE_KEY, Vec::new(), LineStyle::DashDot, 0);
            fig.legend = Legend::LowerLeft;
            fig.x_range = Some((0.0, DELTA_BETA_RANGE));
            Ok(FigureData {
                name: format!("fig09-d{d}"),
                panels: vec![fig],
                columns_of_panels: 1,
                columns: columns(&["series", "d", "alpha", "delta", "beta"]),
                rows,
            })
        }
        _ => Err(Error::InvalidRequest(format!(
            "figure {figure} has no passivity companion; give 8 or 9"
        ))),
    }
}

/// Every companion figure, in the order of [`companion_names`].
pub fn companions() -> Result<Vec<FigureData>> {
    use rayon::prelude::*;
    let jobs: Vec<(u32, f64)> = [8u32, 9]
        .iter()
        .flat_map(|&f| COMPANION_DELAYS.iter().map(move |&d| (f, d)))
        .collect();
    jobs.par_iter().map(|&(f, d)| companion(f, d)).collect()
}

/// The stability boundary in the `(delta, beta)` plane for `(alpha, d)` and `delta` up to
/// `delta_max`, as the companions of Fig. 9 draw it (bisection engine at [`FIGURE_TOL`];
/// NaN pairs separate its pieces).
pub fn stable_delta_beta(alpha: f64, d: f64, delta_max: f64) -> Result<Vec<(f64, f64)>> {
    db_curve(alpha, d, delta_max)
}
