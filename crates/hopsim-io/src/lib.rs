//! Output files for every hopsim writer: atomic files ([`AtomicFile`], [`AtomicPath`],
//! [`write_atomically`]), CSV tables ([`CsvTable`]) and JSON without negative zeros
//! ([`to_json_value`]).
//!
//! A failed or interrupted run never leaves a file that looks complete: every output is
//! written under a hidden temporary name beside its target (`.<name>.partial-<pid>-XXXXXX`),
//! flushed, synced, and renamed over the target only when complete.

mod atomic;
mod bounded;
mod csv;
mod json;

pub use atomic::{
    create_dir, partial_path, remove_temporary_files, write_atomically, AtomicFile, AtomicPath,
};
pub use bounded::{read_bounded, read_text_bounded, Content};
pub use csv::{csv_field, Cell, CsvTable};
pub use json::{to_json_string_pretty, to_json_value};

use std::path::{Path, PathBuf};

/// A number for messages: the shortest text that reads back as `v` (at most 17
/// significant digits), in exponent form for very large or very small magnitudes, so
/// `1e308` is not printed with 309 digits.
pub fn number(v: f64) -> String {
    let magnitude = v.abs();
    if v == 0.0 || !v.is_finite() || (1e-4..1e16).contains(&magnitude) {
        format!("{v}")
    } else {
        format!("{v:e}")
    }
}

/// An I/O error on a named file.
#[derive(Debug, thiserror::Error)]
#[error("{}: {source}", path.display())]
pub struct IoError {
    /// The file the user named (never the temporary sibling).
    pub path: PathBuf,
    #[source]
    pub source: std::io::Error,
}

impl IoError {
    /// `source` on `path`.
    pub fn new(path: &Path, source: std::io::Error) -> Self {
        Self {
            path: path.to_path_buf(),
            source,
        }
    }
}
