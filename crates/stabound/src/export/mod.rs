//! Writing results: one file per output format, each producing bytes in memory.

pub mod c;
pub mod csv;
pub mod json;
pub mod rust;
pub mod table;
pub mod text;

pub use table::{Cell, DeviceScale, Table, TableUnits};
