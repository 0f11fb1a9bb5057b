//! JSON output of a [`Table`]: an array of objects, one per row, keyed by column name, one
//! row per line. Also the nested JSON of a lookup table ([`lookup_json`]).
//!
//! Non-finite numbers (which JSON cannot hold) are written as `null`. Rows are written
//! straight into one byte buffer (keys escaped once), numbers by serde_json (Ryu).

use serde_json::json;

use super::lookup::TableUnits;
use super::table::{Cell, Table};
use crate::amax::AmaxTable;
use crate::export::c::{element_lines, physical, rule_lines};

/// The table as JSON bytes: `[\n{"col":value,...},\n...\n]\n`, or `[]\n` when empty.
pub fn to_json_bytes(table: &Table) -> Vec<u8> {
    let columns: Vec<&str> = table.columns.iter().map(String::as_str).collect();
    let mut w = JsonRows::new(&columns);
    let mut out = Vec::with_capacity(32 * table.columns.len() * (table.len() + 1));
    for row in table.rows() {
        w.begin_row(&mut out);
        for (i, cell) in row.iter().enumerate() {
            match cell {
                Cell::Num(x) => w.num(&mut out, i, *x),
                Cell::Text(s) => w.text(&mut out, i, s),
                Cell::Static(s) => w.text(&mut out, i, s),
            }
        }
        w.end_row(&mut out);
    }
    w.finish(&mut out);
    out
}

/// Writes the JSON of [`to_json_bytes`] row by row into a buffer of the caller's, so that a
/// long array streams through one buffer: [`JsonRows::begin_row`], one call per cell in
/// column order, [`JsonRows::end_row`], and [`JsonRows::finish`] after the last row.
///
/// ```
/// use stabound::export::json::JsonRows;
///
/// let mut w = JsonRows::new(&["x", "piece"]);
/// let mut out = Vec::new();
/// w.begin_row(&mut out);
/// w.num(&mut out, 0, 0.5);
/// w.text(&mut out, 1, "curve");
/// w.end_row(&mut out);
/// w.finish(&mut out);
/// assert_eq!(out, b"[\n{\"x\":0.5,\"piece\":\"curve\"}\n]\n");
/// ```
#[derive(Debug, Clone)]
pub struct JsonRows {
    /// Each column's `"name":`, escaped once.
    keys: Vec<Vec<u8>>,
    rows: usize,
}

impl JsonRows {
    /// A writer for rows with these columns.
    pub fn new(columns: &[&str]) -> Self {
        let keys = columns
            .iter()
            .map(|c| {
                let mut k = serde_json::to_vec(c).unwrap_or_else(|_| b"\"\"".to_vec());
                k.push(b':');
                k
            })
            .collect();
        Self { keys, rows: 0 }
    }

    /// Opens the next row (the array itself before the first).
    pub fn begin_row(&mut self, out: &mut Vec<u8>) {
        out.extend_from_slice(if self.rows == 0 { b"[\n{" } else { b",\n{" });
    }

    fn key(&self, out: &mut Vec<u8>, col: usize) {
        if col > 0 {
            out.push(b',');
        }
        out.extend_from_slice(self.keys.get(col).map_or(&b"\"\":"[..], |k| &k[..]));
    }

    /// The cell of column `col`, a number: shortest round-trip form (zmij, as serde_json
    /// writes it), `null` when not finite, and a zero as `0.0` whatever its sign (JSON
    /// readers differ on `-0.0`; no quantity here has a meaningful signed zero).
    pub fn num(&self, out: &mut Vec<u8>, col: usize, x: f64) {
        self.key(out, col);
        if x.is_finite() {
            // -0.0 + 0.0 is +0.0 in round-to-nearest; every other value is unchanged
            let x = x + 0.0;
            out.extend_from_slice(zmij::Buffer::new().format_finite(x).as_bytes());
        } else {
            out.extend_from_slice(b"null");
        }
    }

    /// The cell of column `col`, text (escaped as JSON requires).
    pub fn text(&self, out: &mut Vec<u8>, col: usize, s: &str) {
        self.key(out, col);
        // writing to a Vec cannot fail
        let _ = serde_json::to_writer(&mut *out, s);
    }

    /// Closes the row.
    pub fn end_row(&mut self, out: &mut Vec<u8>) {
        out.push(b'}');
        self.rows += 1;
    }

    /// Closes the array (`[]` when no row was written).
    pub fn finish(&self, out: &mut Vec<u8>) {
        out.extend_from_slice(if self.rows == 0 { b"[]\n" } else { b"\n]\n" });
    }
}

/// Appends the JSON rows of `points`, consecutive points of `b`, as
/// `to_json_bytes(&boundaries_table(..))` writes them (the same bytes), through `w`.
pub fn push_boundary_rows(
    w: &mut JsonRows,
    out: &mut Vec<u8>,
    b: &crate::boundary::Boundary,
    points: &[crate::boundary::Vertex],
) {
    for p in points {
        w.begin_row(out);
        w.num(out, 0, b.delta);
        w.num(out, 1, b.d);
        w.num(out, 2, p.x);
        w.num(out, 3, p.y);
        w.text(out, 4, p.piece.name());
        w.end_row(out);
    }
}

/// The table as JSON text (see [`to_json_bytes`]).
pub fn to_json(table: &Table) -> String {
    // only UTF-8 is ever written
    String::from_utf8(to_json_bytes(table))
        .unwrap_or_else(|e| String::from_utf8_lossy(e.as_bytes()).into_owned())
}

/// A lookup table as one JSON object (pretty-printed): the axes, `alpha_max[d][delta]`,
/// `beta_at_max[d][delta]`, the exact `alpha_max` before lowering, the tolerance, the beta
/// limits, whether conservative, the `precision`, the `interpolation` (`rows` or
/// `bilinear`), the procedure in words (`lookup`, the same lines as the C header's), the
/// largest lowering per row (`lowering`), and with units the physical arrays
/// (`damping_Ns_per_m`, `K_max_N_per_m`, `B_Ns_per_m`) as the C header has them; for a
/// loop with elements, `elements`: the C header's lines naming them and their values.
pub fn lookup_json(t: &AmaxTable, units: &TableUnits) -> String {
    let lowering: Vec<serde_json::Value> = t
        .lowering()
        .iter()
        .map(|r| {
            json!({
                "d": r.d,
                "largest": r.largest,
                "at_delta": r.at_delta,
                "exact": r.exact,
                "largest_relative": r.largest_relative,
            })
        })
        .collect();
    let mut v = json!({
        "model": "Hulin et al. 2006, exact ZOH discretization; alpha = K T^2/m, beta = B T/m, delta = b T/m, d = delay/T",
        "tol": t.tol,
        "beta_min": t.options.beta_min(),
        "beta_max": t.options.beta_max(),
        "conservative": t.conservative,
        "precision": t.precision.name(),
        "interpolation": t.interpolation.name(),
        "lookup": rule_lines(t, units),
        "delta": t.delta,
        "d": t.d,
        "alpha_max": t.alpha_max,
        "beta_at_max": t.beta_at_max,
        "exact_alpha_max": t.exact_alpha_max,
        "lowering": lowering,
    });
    let elements = element_lines(t, units);
    if !elements.is_empty() {
        v["elements"] = json!(elements);
    }
    if let Some(u) = units {
        let ph = physical(t, u);
        v["mass_kg"] = json!(u.mass);
        v["period_s"] = json!(u.period);
        v["damping_Ns_per_m"] = json!(ph.x);
        v["K_max_N_per_m"] = json!(ph.k);
        v["B_at_max_Ns_per_m"] = json!(ph.b);
    }
    // serializing a Value to a string cannot fail
    format!("{}\n", serde_json::to_string_pretty(&v).unwrap_or_default())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn rows_become_objects() {
        let mut t = Table::new(&["x", "piece"]);
        t.push([Cell::Num(0.5), Cell::Static("curve")]);
        t.push([Cell::Num(f64::NAN), Cell::Text("li\"ne".into())]);
        let text = to_json(&t);
        assert_eq!(text.lines().count(), 4, "{text}");
        let v: serde_json::Value = serde_json::from_str(&text).unwrap();
        assert_eq!(v[0]["x"], 0.5);
        assert_eq!(v[0]["piece"], "curve");
        assert!(v[1]["x"].is_null());
        assert_eq!(v[1]["piece"], "li\"ne");
        assert_eq!(to_json(&Table::new(&["x"])), "[]\n");
    }
}
