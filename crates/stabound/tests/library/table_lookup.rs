//! Lookup tables for firmware: a conservative table's lookup yields stable walls at queries
//! the construction never tested (the point test decides, not the construction); a table
//! that is not conservative is exact at its nodes (the point test finds the node on the
//! stability boundary); rows of whole delays are built alone (no lowering along `d`);
//! float tables round stiffness down.

use stabound::amax::{AmaxOptions, Interpolation, Precision, TableOptions, amax_table};
use stabound::{Checker, Plant, Verdict, Wall, alpha_max};

fn verdict(delta: f64, d: f64, alpha: f64, beta: f64) -> Verdict {
    Checker::new(Plant::new(delta, d).unwrap(), Default::default())
        .unwrap()
        .verdict(&Wall::new(alpha, beta).unwrap())
        .unwrap()
}

/// Queries at 29 steps per interval (the construction uses 16 and 8) and 1e-9 from nodes.
fn fresh(axis: &[f64], n: u32) -> Vec<f64> {
    if axis.len() == 1 {
        return axis.to_vec();
    }
    let mut out = Vec::new();
    for w in axis.windows(2) {
        let mut ts: Vec<f64> = (0..n).map(|k| f64::from(k) / f64::from(n)).collect();
        ts.extend([1e-9, 1.0 - 1e-9]);
        out.extend(ts.iter().map(|t| w[0] + t * (w[1] - w[0])));
    }
    out.extend(axis.last());
    out
}

fn assert_lookups_stable(deltas: &[f64], ds: &[f64], p: Precision) -> usize {
    let opts = AmaxOptions::default();
    let t = amax_table(
        deltas,
        ds,
        &TableOptions::new(opts)
            .with_conservative(true)
            .with_precision(p),
    )
    .unwrap();
    let dq = match t.interpolation {
        Interpolation::Rows => ds.to_vec(),
        _ => fresh(ds, 7),
    };
    let mut n = 0;
    for &d in &dq {
        for &x in &fresh(deltas, 29) {
            // the query as firmware of this precision holds it
            let (x, d) = match p {
                Precision::Float => (f64::from(x as f32), f64::from(d as f32)),
                _ => (x, d),
            };
            let (a, b) = t.lookup(x, d).unwrap();
            assert_eq!(
                verdict(x, d, a, b),
                Verdict::Stable,
                "{p:?} delta {x} d {d}: ({a}, {b})"
            );
            n += 1;
        }
    }
    n
}

#[test]
fn conservative_lookups_are_stable_between_test_points() {
    let deltas: Vec<f64> = (0..11).map(|i| f64::from(i) * 0.4).collect();
    for p in [Precision::Double, Precision::Float] {
        assert_eq!(
            assert_lookups_stable(&deltas, &[1.0, 2.0], p),
            2 * (10 * 31 + 1)
        );
        assert_eq!(
            assert_lookups_stable(&deltas[..5], &[0.0, 0.5, 1.0], p),
            (2 * 9 + 1) * (4 * 31 + 1)
        );
    }
}

#[test]
fn plain_table_is_exact_at_nodes() {
    let opts = AmaxOptions::default();
    let (deltas, ds) = ([0.0, 0.5, 2.0, 7.0], [0.0, 0.5, 1.0, 3.0]);
    let t = amax_table(
        &deltas,
        &ds,
        &TableOptions::new(opts).with_conservative(false),
    )
    .unwrap();
    for (i, &d) in ds.iter().enumerate() {
        for (j, &x) in deltas.iter().enumerate() {
            let a = alpha_max(Plant::new(x, d).unwrap(), &opts).unwrap();
            assert_eq!(t.alpha_max[i][j].to_bits(), a.alpha_max.to_bits());
            assert_eq!(t.beta_at_max[i][j].to_bits(), a.beta_at_max.to_bits());
            // exact: the point test finds the node on the boundary, stable just left of it
            // and unstable just right (1e-6 is far above alpha_max's 1e-10 accuracy)
            let (a, b) = (t.alpha_max[i][j], t.beta_at_max[i][j]);
            assert_eq!(verdict(x, d, a * (1.0 - 1e-6), b), Verdict::Stable);
            assert_eq!(verdict(x, d, a * (1.0 + 1e-6), b), Verdict::Unstable);
        }
    }
    // exact: a plain double table holds the exact values, so exact - value is exactly 0
    assert!(t.lowering().iter().all(|r| r.largest == 0.0));
}

#[test]
fn whole_delays_are_not_lowered_along_d() {
    let opts = AmaxOptions::default();
    let deltas: Vec<f64> = (0..9).map(|i| f64::from(i) * 0.25).collect();
    let one = amax_table(
        &deltas,
        &[1.0],
        &TableOptions::new(opts).with_conservative(true),
    )
    .unwrap();
    let three = amax_table(
        &deltas,
        &[1.0, 2.0, 4.0],
        &TableOptions::new(opts).with_conservative(true),
    )
    .unwrap();
    assert_eq!(one.interpolation, Interpolation::Rows);
    assert_eq!(three.interpolation, Interpolation::Rows);
    // the d = 1 row does not depend on the other rows
    assert_eq!(one.alpha_max[0], three.alpha_max[0]);
    assert_eq!(one.lowering()[0], three.lowering()[0]);
    // a fractional delay makes d interpolated, which lowers the d = 1 row further
    let frac = amax_table(
        &deltas,
        &[1.0, 1.5],
        &TableOptions::new(opts).with_conservative(true),
    )
    .unwrap();
    assert_eq!(frac.interpolation, Interpolation::Bilinear);
    assert!(frac.lowering()[0].largest > one.lowering()[0].largest);
    // A single node per row: nothing is interpolated, the node is lowered only off the
    // boundary (the point test's margin), far below a millionth of its value.
    let node = amax_table(
        &[0.5],
        &[1.0, 2.0],
        &TableOptions::new(opts).with_conservative(true),
    )
    .unwrap();
    for r in node.lowering() {
        assert!(r.largest > 0.0 && r.largest_relative < 1e-6, "{r:?}");
    }
}

#[test]
fn float_tables_round_stiffness_down() {
    let opts = AmaxOptions::default();
    let t = amax_table(
        &[0.0, 0.3, 0.6],
        &[1.0],
        &TableOptions::new(opts)
            .with_conservative(true)
            .with_precision(Precision::Float),
    )
    .unwrap();
    for (row, exact) in t.alpha_max.iter().zip(&t.exact_alpha_max) {
        for (&a, &e) in row.iter().zip(exact) {
            // exact: an f32 value survives the round trip through f32 unchanged
            assert_eq!(f64::from(a as f32), a, "representable in f32");
            assert!(a < e);
        }
    }
    for &b in t.beta_at_max.iter().flatten() {
        // exact, as above
        assert_eq!(f64::from(b as f32), b);
    }
}

/// The device of a trial by a firmware engineer (m = 0.25 kg, T = 0.5 ms, one and two
/// samples of delay, b every 2 N s/m): the old construction lowered the d = 2 node at
/// b = 2 N s/m to 50,951 N/m against an exact 63,740 N/m (-20 %).
#[test]
fn whole_delay_rows_lose_little() {
    let (m, period) = (0.25, 0.0005);
    let deltas: Vec<f64> = (0..11).map(|i| f64::from(i) * 2.0 * period / m).collect();
    let t = amax_table(
        &deltas,
        &[1.0, 2.0],
        &TableOptions::new(AmaxOptions::default()).with_conservative(true),
    )
    .unwrap();
    let k = |a: f64| a * m / (period * period);
    let exact = k(t.exact_alpha_max[1][1]);
    assert!((exact - 63_740.0).abs() < 1.0, "{exact}");
    let lowered = k(t.alpha_max[1][1]);
    assert!(
        lowered < exact && lowered > exact * (1.0 - 1e-4),
        "{lowered}"
    );
}
