//! Output files: atomic writes (temporary file in the same directory, then rename) and CSV.
//!
//! A failed or interrupted run never leaves a file that looks complete: every file is
//! first written to a hidden temporary sibling, flushed, and renamed over the target.

use crate::error::{AnalysisError, Result};
use std::io::Write;
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicU64, Ordering};

static TEMP_COUNTER: AtomicU64 = AtomicU64::new(0);

/// A hidden temporary path next to `target` that keeps `target`'s extension (plot
/// backends pick the image format from it), e.g. `dir/.map.tmp-123-0.png` for `dir/map.png`.
pub fn temporary_sibling(target: &Path) -> PathBuf {
    let dir = target.parent().unwrap_or_else(|| Path::new("."));
    let stem = target
        .file_stem()
        .map(|s| s.to_string_lossy().into_owned())
        .unwrap_or_else(|| "output".into());
    let n = TEMP_COUNTER.fetch_add(1, Ordering::Relaxed);
    let mut name = format!(".{stem}.tmp-{}-{n}", std::process::id());
    if let Some(ext) = target.extension() {
        name.push('.');
        name.push_str(&ext.to_string_lossy());
    }
    dir.join(name)
}

/// Renames a finished temporary file over `target`; removes the temporary on failure.
pub fn commit_temporary(temporary: &Path, target: &Path) -> Result<()> {
    std::fs::rename(temporary, target).map_err(|source| {
        let _ = std::fs::remove_file(temporary);
        AnalysisError::Io {
            path: target.to_path_buf(),
            source,
        }
    })
}

/// Writes `bytes` to `path` atomically.
pub fn write_atomic(path: &Path, bytes: &[u8]) -> Result<()> {
    let temporary = temporary_sibling(path);
    let io = |source| AnalysisError::Io {
        path: path.to_path_buf(),
        source,
    };
    let written = (|| -> std::io::Result<()> {
        let mut file = std::fs::File::create(&temporary)?;
        file.write_all(bytes)?;
        file.sync_all()
    })();
    if let Err(source) = written {
        let _ = std::fs::remove_file(&temporary);
        return Err(io(source));
    }
    commit_temporary(&temporary, path)
}

/// Creates `dir` (and its parents) if it does not exist.
pub fn create_dir(dir: &Path) -> Result<()> {
    std::fs::create_dir_all(dir).map_err(|source| AnalysisError::Io {
        path: dir.to_path_buf(),
        source,
    })
}

/// A CSV table built in memory and written atomically. Cells are numbers (written in
/// Rust's shortest round-trip form, empty when missing or not finite) or text.
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
    /// Text; quoted when it contains a comma, quote or newline.
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
            Cell::Text(s) if s.contains([',', '"', '\n']) => {
                format!("\"{}\"", s.replace('"', "\"\""))
            }
            Cell::Text(s) => s.clone(),
        }
    }
}

impl CsvTable {
    /// An empty table with the given column names.
    pub fn new<S: AsRef<str>>(header: &[S]) -> Self {
        CsvTable {
            header: header.iter().map(|s| s.as_ref().to_string()).collect(),
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
    pub fn write(&self, path: &Path) -> Result<()> {
        write_atomic(path, self.to_csv_string().as_bytes())
    }
}
