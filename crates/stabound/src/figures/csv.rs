//! The CSV text of a figure's data, through the crate's one CSV writer
//! ([`crate::export::csv::CsvWriter`]: shortest round-trip numbers, no `-0`, an empty field
//! for a pen-up `NaN`).

use crate::export::csv::CsvWriter;

/// The table as CSV text: a header line and one line per row (label, then numbers).
pub(crate) fn to_csv(columns: &[String], rows: &[(String, Vec<f64>)]) -> String {
    let names: Vec<&str> = columns.iter().map(String::as_str).collect();
    let mut w = CsvWriter::new(&names, rows.len());
    for (label, values) in rows {
        w.text(label);
        values.iter().for_each(|&v| w.num(v));
    }
    // only UTF-8 is written: the column names and labels are `str`
    String::from_utf8(w.finish()).unwrap_or_default()
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
