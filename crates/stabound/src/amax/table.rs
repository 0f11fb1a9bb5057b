//! Lookup tables of `alpha_max` over a grid of `delta` by `d`, for firmware.

use rayon::prelude::*;

use super::series::check_rows;
use super::{Amax, AmaxOptions, alpha_max};
use crate::error::{Error, Result};
use crate::params::Plant;

/// A lookup table of `alpha_max` and `beta_at_max` over a grid of `delta` by `d`, for
/// firmware (see [`amax_table`]).
#[derive(Debug, Clone, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize))]
pub struct AmaxTable {
    /// The `delta` axis (ascending).
    pub delta: Vec<f64>,
    /// The `d` axis (ascending).
    pub d: Vec<f64>,
    /// `alpha_max[i_d][i_delta]`; with `conservative`, the lowered values.
    pub alpha_max: Vec<Vec<f64>>,
    /// `beta_at_max[i_d][i_delta]` (never lowered).
    pub beta_at_max: Vec<Vec<f64>>,
    /// Whether `alpha_max` was lowered for safe interpolation.
    pub conservative: bool,
    /// The options the values were computed with.
    #[cfg_attr(feature = "serde", serde(skip))]
    pub options: AmaxOptions,
    /// The refinement tolerance in theta used (copy of `options.theta_tol()`, for the record).
    pub tol: f64,
}

fn check_axis(name: &str, v: &[f64]) -> Result<()> {
    if v.is_empty() {
        return Err(Error::InvalidRequest(format!(
            "the {name} axis is empty; give at least one value"
        )));
    }
    if v.windows(2)
        .any(|w| w[1].partial_cmp(&w[0]) != Some(std::cmp::Ordering::Greater))
    {
        return Err(Error::InvalidRequest(format!(
            "the {name} axis must be strictly increasing for a lookup table"
        )));
    }
    Ok(())
}

/// Evaluates `alpha_max` on every `(d, delta)` of `points` in parallel, in order.
fn eval_points(points: &[(f64, f64)], opts: &AmaxOptions) -> Result<Vec<Amax>> {
    points
        .par_iter()
        .map(|&(d, delta)| alpha_max(&Plant::new(delta, d)?, opts))
        .collect()
}

/// `alpha_max` and `beta_at_max` on the grid `deltas x ds` (rayon; identical for any thread
/// count since every value is computed independently and collected in order).
///
/// With `conservative`, each `alpha_max` node is lowered just enough that linear
/// interpolation never exceeds the true `alpha_max` at the test points: in `delta` along
/// each row at 1/4, 1/2 and 3/4 of every interval, in `d` along each column at the midpoint,
/// and bilinearly at every cell centre. For each test point the excess of the interpolated
/// value over the true one is taken off every node that enters the interpolation there, and
/// every node is lowered by the largest excess it takes part in. Between test points the
/// guarantee is not proven (it holds when `alpha_max` is smooth on the scale of the grid).
pub fn amax_table(
    deltas: &[f64],
    ds: &[f64],
    opts: &AmaxOptions,
    conservative: bool,
) -> Result<AmaxTable> {
    check_axis("delta", deltas)?;
    check_axis("d", ds)?;
    check_rows(deltas.len().saturating_mul(ds.len()))?;
    for &d in ds {
        Plant::new(0.0, d)?;
    }
    for &delta in deltas {
        Plant::new(delta, 0.0)?;
    }
    let nx = deltas.len();
    let grid: Vec<(f64, f64)> = ds
        .iter()
        .flat_map(|&d| deltas.iter().map(move |&x| (d, x)))
        .collect();
    let vals = eval_points(&grid, opts)?;
    let mut alpha: Vec<Vec<f64>> = vals
        .chunks(nx)
        .map(|r| r.iter().map(|a| a.alpha_max).collect())
        .collect();
    let beta: Vec<Vec<f64>> = vals
        .chunks(nx)
        .map(|r| r.iter().map(|a| a.beta_at_max).collect())
        .collect();
    if conservative {
        // Each test: the point, and the nodes (row, col, weight) interpolated there.
        // (row, column, weight) of each node in one interpolation
        type Nodes = Vec<(usize, usize, f64)>;
        let mut tests: Vec<((f64, f64), Nodes)> = Vec::new();
        for (r, &d) in ds.iter().enumerate() {
            for c in 0..nx.saturating_sub(1) {
                for t in [0.25, 0.5, 0.75] {
                    let x = deltas[c] + t * (deltas[c + 1] - deltas[c]);
                    tests.push(((d, x), vec![(r, c, 1.0 - t), (r, c + 1, t)]));
                }
            }
        }
        for r in 0..ds.len().saturating_sub(1) {
            let dm = 0.5 * (ds[r] + ds[r + 1]);
            for c in 0..nx {
                tests.push(((dm, deltas[c]), vec![(r, c, 0.5), (r + 1, c, 0.5)]));
                if c + 1 < nx {
                    let xm = 0.5 * (deltas[c] + deltas[c + 1]);
                    tests.push((
                        (dm, xm),
                        vec![
                            (r, c, 0.25),
                            (r, c + 1, 0.25),
                            (r + 1, c, 0.25),
                            (r + 1, c + 1, 0.25),
                        ],
                    ));
                }
            }
        }
        let pts: Vec<(f64, f64)> = tests.iter().map(|t| t.0).collect();
        let truth = eval_points(&pts, opts)?;
        let mut lower = vec![vec![0.0f64; nx]; ds.len()];
        for ((_, nodes), t) in tests.iter().zip(&truth) {
            let interp: f64 = nodes.iter().map(|&(r, c, w)| w * alpha[r][c]).sum();
            // The weights sum to 1, so lowering every node by the excess lowers the
            // interpolated value by exactly the excess. A relative 1e-12 on top covers the
            // rounding of the interpolation itself and of alpha_max (DEFAULT_TOL).
            let excess = interp - t.alpha_max + 1e-12 * t.alpha_max.abs();
            if excess > 0.0 {
                for &(r, c, _) in nodes {
                    lower[r][c] = lower[r][c].max(excess);
                }
            }
        }
        for (row, low) in alpha.iter_mut().zip(&lower) {
            for (v, l) in row.iter_mut().zip(low) {
                // Never below 0: a coarse grid can ask for more lowering than the value has;
                // 0 is then the only safe value (every alpha in (0, alpha_max) is usable).
                *v = (*v - l).max(0.0);
            }
        }
    }
    Ok(AmaxTable {
        delta: deltas.to_vec(),
        d: ds.to_vec(),
        alpha_max: alpha,
        beta_at_max: beta,
        conservative,
        options: *opts,
        tol: opts.theta_tol(),
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Conservative tables: linear interpolation at fresh points (1/3 of each interval, not
    /// a point the lowering used) stays below the true alpha_max, and the lowering is small.
    #[test]
    fn conservative_interpolation_is_below_truth() {
        let deltas: Vec<f64> = (0..9).map(|i| i as f64 * 0.5).collect();
        let ds = [0.0, 0.5, 1.0];
        let opts = AmaxOptions::default();
        let plain = amax_table(&deltas, &ds, &opts, false).unwrap();
        let cons = amax_table(&deltas, &ds, &opts, true).unwrap();
        let mut any_excess = false;
        for (r, &d) in ds.iter().enumerate() {
            for c in 0..deltas.len() - 1 {
                let t = 1.0 / 3.0;
                let x = deltas[c] + t * (deltas[c + 1] - deltas[c]);
                let truth = alpha_max(&Plant::new(x, d).unwrap(), &opts)
                    .unwrap()
                    .alpha_max;
                let lin_plain = (1.0 - t) * plain.alpha_max[r][c] + t * plain.alpha_max[r][c + 1];
                any_excess |= lin_plain > truth;
                let lin = (1.0 - t) * cons.alpha_max[r][c] + t * cons.alpha_max[r][c + 1];
                assert!(lin <= truth, "d {d} delta {x}: {lin} > {truth}");
                // lowered, never raised (interpolation across the coarse d axis can take a lot)
                assert!(cons.alpha_max[r][c] <= plain.alpha_max[r][c]);
            }
        }
        // alpha_max is convex in delta somewhere here, so the plain table did overshoot:
        // the conservative lowering was needed, and this test exercises it.
        assert!(any_excess);
    }
}
