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
                Cell::Num(v) => {
                    // writing to a String cannot fail
                    let _ = write!(out, "{v}");
                }
                Cell::Text(s) => out.push_str(&quote(s)),
                Cell::Static(s) => out.push_str(&quote(s)),
            }
        }
        out.push('\n');
    }
    out
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
        assert_eq!(to_csv(&t), "x,label\n0.1,\"a,b\"\n-2,plain\n");
    }
}
