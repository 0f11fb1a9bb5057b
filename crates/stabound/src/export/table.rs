//! Rows of named columns: the shape every tabular output of the crate takes before it is
//! written as CSV ([`super::csv`]) or JSON ([`super::json`]).
//!
//! Cells are stored in one flat vector (row after row), so a table of many rows costs one
//! allocation, not one per row or per cell.

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
    /// The cells, row after row.
    cells: Vec<Cell>,
}

impl Table {
    /// An empty table with these columns.
    pub fn new(columns: &[&str]) -> Self {
        Self {
            columns: columns.iter().map(|c| c.to_string()).collect(),
            cells: Vec::new(),
        }
    }

    /// Reserves room for `rows` more rows.
    pub fn reserve(&mut self, rows: usize) {
        self.cells.reserve(rows.saturating_mul(self.columns.len()));
    }

    /// Appends a row.
    ///
    /// # Panics
    ///
    /// If the row's length differs from the number of columns (a caller bug).
    pub fn push<const N: usize>(&mut self, row: [Cell; N]) {
        assert_eq!(N, self.columns.len(), "row length must match columns");
        self.cells.extend(row);
    }

    /// Appends a row whose length is known only at run time (columns chosen by options).
    ///
    /// ```
    /// use stabound::export::{Cell, Table};
    /// let mut t = Table::new(&["verdict", "spectral_radius"]);
    /// t.push_cells(vec![Cell::Static("stable"), Cell::Num(0.84)]);
    /// assert_eq!(t.len(), 1);
    /// ```
    ///
    /// # Panics
    ///
    /// If the row's length differs from the number of columns (a caller bug).
    pub fn push_cells(&mut self, row: impl IntoIterator<Item = Cell>) {
        let before = self.cells.len();
        self.cells.extend(row);
        assert_eq!(
            self.cells.len() - before,
            self.columns.len(),
            "row length must match columns"
        );
    }

    /// Appends a row of numbers.
    ///
    /// # Panics
    ///
    /// If the row's length differs from the number of columns (a caller bug).
    pub fn push_numbers(&mut self, row: &[f64]) {
        assert_eq!(
            row.len(),
            self.columns.len(),
            "row length must match columns"
        );
        self.cells.extend(row.iter().map(|&x| Cell::Num(x)));
    }

    /// The number of rows.
    pub fn len(&self) -> usize {
        self.cells.len() / self.columns.len().max(1)
    }

    /// Whether the table has no rows.
    pub fn is_empty(&self) -> bool {
        self.cells.is_empty()
    }

    /// The rows in order, each as long as `columns`.
    pub fn rows(&self) -> impl Iterator<Item = &[Cell]> {
        self.cells.chunks(self.columns.len().max(1))
    }
}
