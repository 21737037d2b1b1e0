//! CSV tables built in memory and written atomically (RFC 4180 quoting, `\n` line ends).

use crate::{write_atomically, IoError};
use std::borrow::Cow;
use std::path::Path;

/// `field` quoted if it holds a comma, quote or line break (RFC 4180).
pub fn csv_field(field: &str) -> Cow<'_, str> {
    if field.contains([',', '"', '\n', '\r']) {
        format!("\"{}\"", field.replace('"', "\"\"")).into()
    } else {
        field.into()
    }
}

/// A CSV table. Cells are numbers (written in Rust's shortest round-trip form, empty when
/// missing or not finite) or text.
#[derive(Debug, Clone, Default)]
pub struct CsvTable {
    header: Vec<String>,
    rows: Vec<Vec<String>>,
}

/// One CSV cell.
#[derive(Debug, Clone)]
pub enum Cell {
    /// A number; NaN and infinities are written as an empty cell.
    Number(f64),
    /// A missing value (empty cell).
    Empty,
    /// Text; quoted when it contains a comma, quote or line break.
    Text(String),
}

impl From<f64> for Cell {
    fn from(value: f64) -> Self {
        Cell::Number(value)
    }
}

impl From<Option<f64>> for Cell {
    fn from(value: Option<f64>) -> Self {
        value.map_or(Cell::Empty, Cell::Number)
    }
}

impl From<usize> for Cell {
    fn from(value: usize) -> Self {
        Cell::Text(value.to_string())
    }
}

impl From<u64> for Cell {
    fn from(value: u64) -> Self {
        Cell::Text(value.to_string())
    }
}

impl From<bool> for Cell {
    fn from(value: bool) -> Self {
        Cell::Text(value.to_string())
    }
}

impl From<&str> for Cell {
    fn from(value: &str) -> Self {
        Cell::Text(value.to_string())
    }
}

impl From<String> for Cell {
    fn from(value: String) -> Self {
        Cell::Text(value)
    }
}

impl Cell {
    fn render(&self) -> String {
        match self {
            Cell::Number(x) if x.is_finite() => format!("{x}"),
            Cell::Number(_) | Cell::Empty => String::new(),
            Cell::Text(s) => csv_field(s).into_owned(),
        }
    }
}

impl CsvTable {
    /// An empty table with the given column names.
    pub fn new<S: AsRef<str>>(header: &[S]) -> Self {
        CsvTable {
            header: header
                .iter()
                .map(|s| csv_field(s.as_ref()).into_owned())
                .collect(),
            rows: Vec::new(),
        }
    }

    /// Appends a row; it must have as many cells as the header.
    pub fn push(&mut self, row: Vec<Cell>) {
        debug_assert_eq!(row.len(), self.header.len(), "CSV row width");
        self.rows.push(row.iter().map(Cell::render).collect());
    }

    /// Number of data rows.
    pub fn len(&self) -> usize {
        self.rows.len()
    }

    /// True when the table has no data rows.
    pub fn is_empty(&self) -> bool {
        self.rows.is_empty()
    }

    /// The table as CSV text (header line first, `\n` line ends).
    pub fn to_csv_string(&self) -> String {
        let mut out = self.header.join(",");
        out.push('\n');
        for row in &self.rows {
            out.push_str(&row.join(","));
            out.push('\n');
        }
        out
    }

    /// Writes the table to `path` atomically.
    pub fn write(&self, path: &Path) -> Result<(), IoError> {
        write_atomically(path, |w| w.write_all(self.to_csv_string().as_bytes()))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn cells_render_numbers_round_trip_and_quote_text() {
        let mut t = CsvTable::new(&["a", "b,c", "d"]);
        t.push(vec![0.1.into(), Cell::Number(f64::NAN), "x, \"y\"".into()]);
        t.push(vec![Cell::Empty, 3usize.into(), true.into()]);
        assert_eq!(
            t.to_csv_string(),
            "a,\"b,c\",d\n0.1,,\"x, \"\"y\"\"\"\n,3,true\n"
        );
        assert_eq!(t.len(), 2);
    }
}
