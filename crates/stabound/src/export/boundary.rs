//! Stability boundaries in the `(alpha, beta)` plane ([`crate::boundary::Boundary`]) as
//! rows of a [`Table`].

use super::table::{Cell, Table};
use crate::boundary::Boundary;

/// The columns of boundaries in the `(alpha, beta)` plane: `delta,d,alpha,beta,piece`.
pub const BOUNDARY_COLUMNS: [&str; 5] = ["delta", "d", "alpha", "beta", "piece"];

/// Boundaries as rows `delta,d,alpha,beta,piece`, one closed polyline per boundary in the
/// given order (`piece` names what the segment leaving the point lies on).
pub fn boundaries_table(bs: &[Boundary]) -> Table {
    let mut t = Table::new(&BOUNDARY_COLUMNS);
    t.reserve(bs.iter().map(|b| b.points.len()).sum());
    for b in bs {
        for p in &b.points {
            t.push([
                Cell::Num(b.delta),
                Cell::Num(b.d),
                Cell::Num(p.x),
                Cell::Num(p.y),
                Cell::Static(p.piece.name()),
            ]);
        }
    }
    t
}
