//! CSV output of a [`Table`]: a header line of column names, then one line per row.
//!
//! Numbers are written in Rust's shortest round-trip form (reading them back gives the same
//! `f64`); text cells are quoted when they contain a comma, quote or line break (RFC 4180).

use std::fmt::Write;

use super::table::{Cell, Table};

/// The table as CSV text (header line first, `\n` line ends).
pub fn to_csv(table: &Table) -> String {
    let mut out = String::with_capacity(32 * (table.rows.len() + 1));
    let header: Vec<String> = table.columns.iter().map(|c| quote(c)).collect();
    out.push_str(&header.join(","));
    out.push('\n');
    for row in &table.rows {
        for (i, cell) in row.iter().enumerate() {
            if i > 0 {
                out.push(',');
            }
            match cell {
                Cell::Num(v) => push_num(&mut out, *v),
                Cell::Text(s) => out.push_str(&quote(s)),
                Cell::Static(s) => out.push_str(&quote(s)),
            }
        }
        out.push('\n');
    }
    out
}

/// Shortest round-trip form of `v` (serde_json's float writer, several times faster than
/// `Display` for the many-digit values of a boundary); `NaN`, `inf`, `-inf` otherwise.
fn push_num(out: &mut String, v: f64) {
    if v.is_finite() {
        let mut buf = Vec::with_capacity(24);
        if serde_json::to_writer(&mut buf, &v).is_ok()
            && let Ok(s) = std::str::from_utf8(&buf)
        {
            // integral values come out as `2.0`; keep CSV numbers plain: `2`
            out.push_str(s.strip_suffix(".0").unwrap_or(s));
            return;
        }
    }
    // writing to a String cannot fail
    let _ = write!(out, "{v}");
}

fn quote(s: &str) -> String {
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
    fn header_rows_and_quoting() {
        let mut t = Table::new(&["x", "label"]);
        t.push(vec![Cell::Num(0.1), Cell::Text("a,b".into())]);
        t.push(vec![Cell::Num(-2.0), Cell::Static("plain")]);

        t.push(vec![Cell::Num(3.3465615358663214e-5), Cell::Num(f64::NAN)]);
        let text = to_csv(&t);
        assert_eq!(
            text.lines().take(3).collect::<Vec<_>>().join("\n"),
            "x,label\n0.1,\"a,b\"\n-2,plain"
        );
        // numbers read back bit for bit
        let last: Vec<&str> = text.lines().nth(3).unwrap().split(',').collect();
        assert_eq!(
            last[0].parse::<f64>().unwrap().to_bits(),
            3.3465615358663214e-5f64.to_bits()
        );
        assert_eq!(last[1], "NaN");
    }
}
