//! Rows of named columns: the shape every tabular output of the crate takes before it is
//! written as CSV ([`super::csv`]) or JSON ([`super::json`]).

/// One value of a table.
#[derive(Debug, Clone, PartialEq)]
pub enum Cell {
    /// A number.
    Num(f64),
    /// Text.
    Text(String),
    /// Text known at compile time (no allocation per row).
    Static(&'static str),
}

/// A table: column names and rows of cells (each row as long as `columns`).
#[derive(Debug, Clone, PartialEq, Default)]
pub struct Table {
    /// Column names.
    pub columns: Vec<String>,
    /// Rows.
    pub rows: Vec<Vec<Cell>>,
}

impl Table {
    /// An empty table with these columns.
    pub fn new(columns: &[&str]) -> Self {
        Self {
            columns: columns.iter().map(|c| c.to_string()).collect(),
            rows: Vec::new(),
        }
    }

    /// Appends a row.
    ///
    /// # Panics
    ///
    /// If the row's length differs from the number of columns (a caller bug).
    pub fn push(&mut self, row: Vec<Cell>) {
        assert_eq!(
            row.len(),
            self.columns.len(),
            "row length must match columns"
        );
        self.rows.push(row);
    }
}
