//! JSON output of a [`Table`]: an array of objects, one per row, keyed by column name, one
//! row per line. Also the nested JSON of a lookup table ([`lookup_json`]).
//!
//! Non-finite numbers (which JSON cannot hold) are written as `null`. Rows are written
//! straight into one byte buffer (keys escaped once), numbers by serde_json (Ryu).

use serde_json::json;

use super::table::{Cell, Table, TableUnits};
use crate::amax::AmaxTable;
use crate::export::c::{physical, rule_lines};

/// The table as JSON bytes: `[\n{"col":value,...},\n...\n]\n`, or `[]\n` when empty.
pub fn to_json_bytes(table: &Table) -> Vec<u8> {
    let keys: Vec<Vec<u8>> = table
        .columns
        .iter()
        .map(|c| {
            let mut k = serde_json::to_vec(c).unwrap_or_else(|_| b"\"\"".to_vec());
            k.push(b':');
            k
        })
        .collect();
    let mut out = Vec::with_capacity(32 * table.columns.len() * (table.len() + 1));
    if table.is_empty() {
        out.extend_from_slice(b"[]\n");
        return out;
    }
    out.extend_from_slice(b"[\n");
    for (r, row) in table.rows().enumerate() {
        if r > 0 {
            out.extend_from_slice(b",\n");
        }
        out.push(b'{');
        for (i, (key, cell)) in keys.iter().zip(row).enumerate() {
            if i > 0 {
                out.push(b',');
            }
            out.extend_from_slice(key);
            // writing to a Vec cannot fail
            let _ = match cell {
                Cell::Num(x) if x.is_finite() => serde_json::to_writer(&mut out, x),
                Cell::Num(_) => {
                    out.extend_from_slice(b"null");
                    Ok(())
                }
                Cell::Text(s) => serde_json::to_writer(&mut out, s),
                Cell::Static(s) => serde_json::to_writer(&mut out, s),
            };
        }
        out.push(b'}');
    }
    out.extend_from_slice(b"\n]\n");
    out
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
/// (`damping_Ns_per_m`, `K_max_N_per_m`, `B_Ns_per_m`) as the C header has them.
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
    if let Some(u) = units {
        let ph = physical(t, u);
        v["mass_kg"] = json!(u.mass);
        v["period_s"] = json!(u.period);
        v["damping_Ns_per_m"] = json!(ph.x);
        v["K_max_N_per_m"] = json!(ph.k);
        v["B_Ns_per_m"] = json!(ph.b);
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
