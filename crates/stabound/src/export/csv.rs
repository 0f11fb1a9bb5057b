//! CSV output of a [`Table`]: a header line of column names, then one line per row.
//!
//! Numbers are written in the shortest form that reads back to the same `f64` (zmij, the
//! formatter serde_json uses), integral values without a trailing `.0` (`2`, not `2.0`);
//! an empty field where a value is missing or not finite (JSON writes `null` there). Text cells are quoted when they contain a
//! comma, quote or line break (RFC 4180). Everything is written straight into one byte
//! buffer: no allocation per row or per cell.

use super::boundary::BOUNDARY_COLUMNS;
use super::table::{Cell, Table};
use crate::boundary::{Boundary, Vertex};

/// The table as CSV bytes (header line first, `\n` line ends).
pub fn to_csv_bytes(table: &Table) -> Vec<u8> {
    let columns: Vec<&str> = table.columns.iter().map(String::as_str).collect();
    let mut w = CsvWriter::new(&columns, table.len());
    for row in table.rows() {
        for cell in row {
            match cell {
                Cell::Num(v) => w.num(*v),
                Cell::Text(s) => w.text(s),
                Cell::Static(s) => w.text(s),
            }
        }
    }
    w.finish()
}

/// Writes CSV row by row straight into one byte buffer, for outputs too large to be worth
/// building a [`Table`] first (a boundary at the default tolerance has tens of thousands of
/// rows). Cells are written in column order; a row ends after its last column.
///
/// A number repeated from the row above in the same column (a curve's `delta` and `d` on
/// each of its rows) is copied instead of formatted again; values are compared by bits, so
/// `-0.0` and `0.0` are never confused.
#[derive(Debug)]
pub struct CsvWriter {
    out: Vec<u8>,
    /// Per column: the last number written, and where its text sits in `out`.
    last: Vec<Option<(u64, usize, usize)>>,
    col: usize,
}

impl CsvWriter {
    /// A writer with the header line written; `rows` sizes the buffer (about 20 bytes a cell).
    pub fn new(columns: &[&str], rows: usize) -> Self {
        let mut out = Vec::with_capacity(20 * columns.len().max(1) * (rows + 1));
        for (i, c) in columns.iter().enumerate() {
            if i > 0 {
                out.push(b',');
            }
            push_text(&mut out, c);
        }
        out.push(b'\n');
        Self {
            out,
            last: vec![None; columns.len().max(1)],
            col: 0,
        }
    }

    /// A writer of rows that continue a CSV of `columns` columns whose header line is
    /// written elsewhere (rows formatted in parallel chunks and joined in order); `rows`
    /// sizes the buffer.
    ///
    /// ```
    /// use stabound::export::csv::CsvWriter;
    ///
    /// let mut head = CsvWriter::new(&["x", "label"], 1);
    /// head.num(0.5);
    /// head.text("a");
    /// let mut tail = CsvWriter::without_header(2, 1);
    /// tail.num(2.0);
    /// tail.text("b");
    /// let text = [head.finish(), tail.finish()].concat();
    /// assert_eq!(text, b"x,label\n0.5,a\n2,b\n");
    /// ```
    pub fn without_header(columns: usize, rows: usize) -> Self {
        Self {
            out: Vec::with_capacity(20 * columns.max(1) * rows),
            last: vec![None; columns.max(1)],
            col: 0,
        }
    }

    fn separate(&mut self) {
        if self.col > 0 {
            self.out.push(b',');
        }
    }

    fn advance(&mut self) {
        self.col += 1;
        if self.col == self.last.len() {
            self.out.push(b'\n');
            self.col = 0;
        }
    }

    /// The next cell, a number.
    pub fn num(&mut self, v: f64) {
        self.separate();
        let start = self.out.len();
        match self.last[self.col] {
            Some((bits, from, len)) if bits == v.to_bits() => {
                self.out.extend_from_within(from..from + len);
            }
            _ => push_num(&mut self.out, v),
        }
        self.last[self.col] = Some((v.to_bits(), start, self.out.len() - start));
        self.advance();
    }

    /// The next cell, text (quoted as RFC 4180 requires).
    pub fn text(&mut self, s: &str) {
        self.separate();
        push_text(&mut self.out, s);
        self.advance();
    }

    /// The CSV bytes.
    pub fn finish(self) -> Vec<u8> {
        self.out
    }

    /// Writes what has been formatted so far to `w` and empties the buffer (its capacity is
    /// kept), so that a long output streams through one buffer. Call between rows.
    ///
    /// # Errors
    ///
    /// The writer's error.
    pub fn write_to(&mut self, w: &mut impl std::io::Write) -> std::io::Result<()> {
        w.write_all(&self.out)?;
        self.out.clear();
        // positions of the last numbers pointed into what was just written
        self.last.iter_mut().for_each(|l| *l = None);
        Ok(())
    }
}

/// Rows per chunk of [`boundaries_csv`]: large enough that a chunk's own buffer and the
/// rayon task cost nothing beside formatting it (about 50 bytes a row), small enough that a
/// single curve of 30,000 rows splits over every core.
const CSV_CHUNK_ROWS: usize = 4096;

/// Boundaries as CSV, the rows of [`super::boundary::boundaries_table`] written directly (no
/// intermediate table: a boundary at the default tolerance has tens of thousands of rows).
pub fn boundaries_csv(bs: &[Boundary]) -> Vec<u8> {
    boundaries_csv_chunks(bs).concat()
}

/// [`boundaries_csv`] in consecutive parts (the header line first), to be written in order:
/// the 20 curves of the paper's Fig. 5 make 29 MB of CSV, which need not be copied into one
/// buffer before writing (the command line writes the parts one after another).
///
/// Formatting the numbers is most of the cost, so chunks of rows are formatted in parallel
/// (rayon): the bytes do not depend on the number of threads.
pub fn boundaries_csv_chunks(bs: &[Boundary]) -> Vec<Vec<u8>> {
    use rayon::prelude::*;
    let chunks: Vec<(&Boundary, &[crate::boundary::Vertex])> = bs
        .iter()
        .flat_map(|b| b.points.chunks(CSV_CHUNK_ROWS).map(move |c| (b, c)))
        .collect();
    let parts: Vec<Vec<u8>> = chunks
        .into_par_iter()
        .map(|(b, points)| {
            let mut out = Vec::new();
            push_boundary_rows(&mut out, b, points);
            out
        })
        .collect();
    let mut header = Vec::new();
    push_boundary_header(&mut header);
    std::iter::once(header).chain(parts).collect()
}

/// Appends the header line of boundary CSV (`delta,d,alpha,beta,piece`), the first line of
/// [`boundaries_csv`]; with [`push_boundary_rows`] a caller streams boundary CSV through one
/// buffer of its own.
pub fn push_boundary_header(out: &mut Vec<u8>) {
    for (i, c) in BOUNDARY_COLUMNS.iter().enumerate() {
        if i > 0 {
            out.push(b',');
        }
        push_text(out, c);
    }
    out.push(b'\n');
}

/// Appends the CSV rows of `points`, consecutive points of `b`, as [`boundaries_csv`] writes
/// them (the same bytes).
pub fn push_boundary_rows(out: &mut Vec<u8>, b: &Boundary, points: &[Vertex]) {
    // delta and d are the same on every row of a curve: formatted once.
    let start = out.len();
    push_num(out, b.delta);
    out.push(b',');
    push_num(out, b.d);
    out.push(b',');
    let prefix_len = out.len() - start;
    out.reserve(points.len() * (prefix_len + 56));
    for (k, p) in points.iter().enumerate() {
        if k > 0 {
            out.extend_from_within(start..start + prefix_len);
        }
        push_num(out, p.x);
        out.push(b',');
        push_num(out, p.y);
        out.push(b',');
        // piece names are plain words (a test checks): nothing to quote
        out.extend_from_slice(p.piece.name().as_bytes());
        out.push(b'\n');
    }
    if points.is_empty() {
        out.truncate(start);
    }
}

/// The table as CSV text (see [`to_csv_bytes`]).
pub fn to_csv(table: &Table) -> String {
    // only UTF-8 is ever written (the column names and text cells are `str`)
    String::from_utf8(to_csv_bytes(table))
        .unwrap_or_else(|e| String::from_utf8_lossy(e.as_bytes()).into_owned())
}

/// Appends the shortest round-trip form of `v` (see the module doc).
#[inline]
pub(crate) fn push_num(out: &mut Vec<u8>, v: f64) {
    if !v.is_finite() {
        // no value (JSON writes null): NaN or inf is never passed on as a number
        return;
    }
    // -0 and 0 are the same wall; a reader should not see a sign on nothing
    // (exact comparison on purpose: only the two zeros compare equal to 0)
    let v = if v == 0.0 { 0.0 } else { v };
    // zmij's shortest round-trip digits, the same text serde_json writes for an f64; its
    // buffer is an uninitialized stack array, so one per number costs nothing
    let mut buf = zmij::Buffer::new();
    let s = buf.format_finite(v).as_bytes();
    // integral values come out as `2.0`; keep CSV numbers plain: `2`
    out.extend_from_slice(s.strip_suffix(b".0").unwrap_or(s));
}

fn push_text(out: &mut Vec<u8>, s: &str) {
    if s.contains([',', '"', '\n', '\r']) {
        out.push(b'"');
        for part in s.split_inclusive('"') {
            out.extend_from_slice(part.as_bytes());
            if part.ends_with('"') {
                out.push(b'"');
            }
        }
        out.push(b'"');
    } else {
        out.extend_from_slice(s.as_bytes());
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn header_rows_and_quoting() {
        let mut t = Table::new(&["x", "label"]);
        t.push([Cell::Num(0.1), Cell::Text("a,b\"c".into())]);
        t.push([Cell::Num(-2.0), Cell::Static("plain")]);
        t.push([Cell::Num(3.3465615358663214e-5), Cell::Num(f64::NAN)]);
        t.push([Cell::Num(f64::NEG_INFINITY), Cell::Num(1e300)]);
        let text = to_csv(&t);
        assert_eq!(
            text.lines().take(3).collect::<Vec<_>>().join("\n"),
            "x,label\n0.1,\"a,b\"\"c\"\n-2,plain"
        );
        // numbers read back bit for bit
        let last: Vec<&str> = text.lines().nth(3).unwrap().split(',').collect();
        assert_eq!(
            last[0].parse::<f64>().unwrap().to_bits(),
            3.3465615358663214e-5f64.to_bits()
        );
        assert_eq!(last[1], "", "NaN is an empty field");
        let last: Vec<&str> = text.lines().nth(4).unwrap().split(',').collect();
        assert_eq!(last[0], "", "-inf is an empty field");
        assert_eq!(last[1].parse::<f64>().unwrap(), 1e300);
    }

    /// Every number reads back to the same bits, whatever its magnitude.
    #[test]
    fn negative_zero_prints_as_zero() {
        let mut out = Vec::new();
        push_num(&mut out, -0.0);
        out.push(b',');
        push_num(&mut out, -1e-300);
        assert_eq!(String::from_utf8(out).unwrap(), "0,-1e-300");
    }

    #[test]
    fn round_trip_many_magnitudes() {
        let mut out = Vec::new();
        let mut x = 1.234_567_890_123_456_7e-300_f64;
        while x < 1e300 {
            for v in [x, -x, x.round()] {
                out.clear();
                push_num(&mut out, v);
                let s = std::str::from_utf8(&out).unwrap();
                assert_eq!(s.parse::<f64>().unwrap().to_bits(), v.to_bits(), "{s}");
            }
            x *= 7.77;
        }
    }

    /// Piece names are written unquoted: none contains a character that needs quoting.
    #[test]
    fn piece_names_need_no_quoting() {
        use crate::boundary::Piece;
        for p in [
            Piece::Curve,
            Piece::AlphaZero,
            Piece::MinusOne,
            Piece::Bisection,
            Piece::Clipped,
        ] {
            let mut out = Vec::new();
            push_text(&mut out, p.name());
            assert_eq!(out, p.name().as_bytes());
        }
    }

    /// The direct boundary writer and the generic table writer give the same bytes.
    #[test]
    fn boundaries_csv_matches_the_table_path() {
        // The first curve at 1e-9 has 31,567 rows: several chunks of CSV_CHUNK_ROWS.
        let plants = [(0.5, 1.0, 1e-9), (3.0, 0.0, 1e-4), (0.0, 2.5, 1e-4)];
        let bs: Vec<_> = plants
            .iter()
            .map(|&(delta, d, tol)| {
                crate::boundary::exact(
                    crate::params::Plant::new(delta, d).unwrap(),
                    &crate::boundary::ExactOptions { tol },
                )
                .unwrap()
            })
            .collect();
        assert!(bs[0].points.len() > 3 * CSV_CHUNK_ROWS);
        let table = super::super::boundary::boundaries_table(&bs);
        assert_eq!(boundaries_csv(&bs), to_csv_bytes(&table));
    }
}
