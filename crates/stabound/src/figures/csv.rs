//! The CSV text of a figure's data.

/// The table as CSV text: a header line and one line per row (label, then numbers).
pub(crate) fn to_csv(columns: &[String], rows: &[(String, Vec<f64>)]) -> String {
    let mut s = columns.join(",");
    s.push('\n');
    for (label, values) in rows {
        s.push_str(&csv_text(label));
        for v in values {
            s.push(',');
            s.push_str(&number(*v));
        }
        s.push('\n');
    }
    s
}

/// A number for CSV in the shortest form that reads back to the same `f64`: plain decimal for
/// magnitudes in `[1e-4, 1e15)` and zero, scientific notation (`5e-8`) otherwise, so that tiny
/// positions do not turn into long runs of zeros.
fn number(v: f64) -> String {
    let a = v.abs();
    // exact zero on purpose: 0 (and -0) print as `0`, not in exponent form
    if a == 0.0 || (1e-4..1e15).contains(&a) || !v.is_finite() {
        format!("{v}")
    } else {
        format!("{v:e}")
    }
}

/// Quotes a CSV text field when it contains a comma, quote or line break (RFC 4180).
fn csv_text(s: &str) -> String {
    if s.contains([',', '"', '\n', '\r']) {
        format!("\"{}\"", s.replace('"', "\"\""))
    } else {
        s.to_string()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn csv_quotes_and_round_trips() {
        let csv = to_csv(
            &["series".into(), "x".into()],
            &[("a, b".into(), vec![0.1]), ("c".into(), vec![1.0 / 3.0])],
        );
        assert_eq!(
            csv.lines().nth(1).unwrap(),
            "\"a, b\",0.1",
            "comma in a label must be quoted"
        );
        let third: f64 = csv.lines().nth(2).unwrap()[2..].parse().unwrap();
        assert_eq!(
            third,
            1.0 / 3.0,
            "shortest round-trip form reads back exactly"
        );
    }
}
