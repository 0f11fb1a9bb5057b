//! JSON output of a [`Table`]: an array of objects, one per row, keyed by column name.
//!
//! Non-finite numbers (which JSON cannot hold) are written as `null`.

use serde_json::{Map, Number, Value};

use super::table::{Cell, Table};

/// The table as a JSON value: `[{"col": value, ...}, ...]`.
pub fn to_json_value(table: &Table) -> Value {
    Value::Array(
        table
            .rows
            .iter()
            .map(|row| {
                let mut obj = Map::with_capacity(row.len());
                for (name, cell) in table.columns.iter().zip(row) {
                    let v = match cell {
                        Cell::Num(x) => Number::from_f64(*x).map_or(Value::Null, Value::Number),
                        Cell::Text(s) => Value::String(s.clone()),
                        Cell::Static(s) => Value::String((*s).to_string()),
                    };
                    obj.insert(name.clone(), v);
                }
                Value::Object(obj)
            })
            .collect(),
    )
}

/// The table as JSON text (compact, one trailing newline).
pub fn to_json(table: &Table) -> String {
    let mut s = to_json_value(table).to_string();
    s.push('\n');
    s
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn rows_become_objects() {
        let mut t = Table::new(&["x", "piece"]);
        t.push(vec![Cell::Num(0.5), Cell::Static("curve")]);
        t.push(vec![Cell::Num(f64::NAN), Cell::Text("line".into())]);
        let v: Value = serde_json::from_str(&to_json(&t)).unwrap();
        assert_eq!(v[0]["x"], 0.5);
        assert_eq!(v[0]["piece"], "curve");
        assert!(v[1]["x"].is_null());
    }
}
