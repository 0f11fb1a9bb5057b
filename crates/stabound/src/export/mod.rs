//! Writing results: one file per output format, each producing bytes in memory.

pub mod boundary;
pub mod c;
pub mod csv;
pub mod json;
pub mod lookup;
pub mod report;
pub mod rust;
pub mod table;
pub mod text;

pub use boundary::{BOUNDARY_COLUMNS, boundaries_table};
pub use lookup::{DeviceScale, TableUnits, lookup_header, lookup_rows};
pub use table::{Cell, Table};
