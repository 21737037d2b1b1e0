//! Shared pieces of the `analyze` subcommands: output options, text tables, JSON, the
//! output directory, and the mapping of invalid input to exit code 2.

use clap::Args;
use hopsim_analysis::AnalysisError;
use std::fmt;
use std::path::{Path, PathBuf};
use std::process::ExitCode;

use crate::cmd::exit;

/// `--json`, `--out DIR` and `--quiet`, shared by every analyze subcommand.
#[derive(Args, Clone, Debug)]
pub struct OutputArgs {
    /// Print one JSON object instead of the table.
    #[arg(long)]
    pub json: bool,
    /// Write CSV files and PNG/SVG plots into DIR (created if missing).
    #[arg(long, value_name = "DIR")]
    pub out: Option<PathBuf>,
    /// Print nothing but errors (no progress bar, no table); --json still prints its
    /// object and --out still writes its files.
    #[arg(long, short)]
    pub quiet: bool,
}

impl OutputArgs {
    /// True when progress bars must not draw: with `--json` or `--quiet`.
    pub fn hide_progress(&self) -> bool {
        self.json || self.quiet
    }

    /// With `--out DIR`: creates `DIR`, lets `write` fill it and returns the files written;
    /// without `--out`, writes nothing and returns no files.
    pub fn write_files(
        &self,
        write: impl FnOnce(&mut OutDir) -> anyhow::Result<()>,
    ) -> anyhow::Result<Vec<String>> {
        let Some(dir) = &self.out else {
            return Ok(Vec::new());
        };
        let mut out = OutDir::create(dir)?;
        write(&mut out)?;
        Ok(out.files())
    }
}

/// Prints `wrote FILE` for each file written (the last lines of the table output).
pub fn print_written(files: &[String]) {
    for f in files {
        println!("wrote {f}");
    }
}

/// An invalid command-line argument (exit code 2).
#[derive(Debug)]
pub struct InvalidInput(pub String);

impl fmt::Display for InvalidInput {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(&self.0)
    }
}

impl std::error::Error for InvalidInput {}

/// Returns an [`InvalidInput`] error.
pub fn invalid<T>(message: impl Into<String>) -> anyhow::Result<T> {
    Err(InvalidInput(message.into()).into())
}

/// Maps a subcommand's result to an exit code: invalid input prints the error and exits
/// with 2; other errors go to `main` (exit 1).
pub fn exit_code(result: anyhow::Result<()>) -> anyhow::Result<ExitCode> {
    match result {
        Ok(()) => Ok(ExitCode::SUCCESS),
        Err(err) if is_invalid_input(&err) => {
            eprintln!("error: {err:#}");
            Ok(ExitCode::from(exit::INVALID_INPUT))
        }
        Err(err) => Err(err),
    }
}

fn is_invalid_input(err: &anyhow::Error) -> bool {
    err.chain().any(|e| {
        e.downcast_ref::<InvalidInput>().is_some()
            || matches!(
                e.downcast_ref::<AnalysisError>(),
                Some(AnalysisError::InvalidParameter { .. })
            )
    })
}

/// The `--out` directory: created on first use; remembers the files written.
pub struct OutDir {
    dir: PathBuf,
    files: Vec<PathBuf>,
}

impl OutDir {
    /// Creates `dir` (and parents).
    pub fn create(dir: &Path) -> anyhow::Result<Self> {
        hopsim_io::create_dir(dir)?;
        Ok(OutDir {
            dir: dir.to_path_buf(),
            files: Vec::new(),
        })
    }

    /// `dir/name`.
    pub fn path(&self, name: &str) -> PathBuf {
        self.dir.join(name)
    }

    /// Writes a CSV table as `dir/name`.
    pub fn csv(&mut self, name: &str, table: &hopsim_io::CsvTable) -> anyhow::Result<()> {
        let path = self.path(name);
        table.write(&path)?;
        self.files.push(path);
        Ok(())
    }

    /// Writes a figure as `dir/stem.png` and `dir/stem.svg`.
    pub fn figure<F: hopsim_studies::plot::Figure>(
        &mut self,
        stem: &str,
        figure: &F,
    ) -> anyhow::Result<()> {
        let written = hopsim_studies::plot::write_png_and_svg(figure, &self.path(stem))?;
        self.files.extend(written);
        Ok(())
    }

    /// The files written so far, as strings.
    pub fn files(&self) -> Vec<String> {
        self.files.iter().map(|p| p.display().to_string()).collect()
    }
}

/// A two-column text table with a title.
pub struct Table {
    title: String,
    rows: Vec<(String, String)>,
}

impl Table {
    /// An empty table.
    pub fn new(title: impl Into<String>) -> Self {
        Table {
            title: title.into(),
            rows: Vec::new(),
        }
    }

    /// Adds a row.
    pub fn row(&mut self, key: impl Into<String>, value: impl fmt::Display) -> &mut Self {
        self.rows.push((key.into(), value.to_string()));
        self
    }
}

impl fmt::Display for Table {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let width = self
            .rows
            .iter()
            .map(|(k, _)| k.chars().count())
            .max()
            .unwrap_or(0);
        writeln!(f, "{}", self.title)?;
        for (key, value) in &self.rows {
            let pad = width - key.chars().count();
            writeln!(f, "  {key}{}  {value}", " ".repeat(pad))?;
        }
        Ok(())
    }
}

/// A number with 5 significant digits (scientific outside [1e-3, 1e6)) and a unit.
pub fn num(value: f64, unit: &str) -> String {
    let text = if !value.is_finite() {
        format!("{value}")
    } else if value == 0.0 || (value.abs() >= 1e-3 && value.abs() < 1e6) {
        let digits = if value == 0.0 {
            0
        } else {
            value.abs().log10().floor() as i32
        };
        let decimals = (4 - digits).clamp(0, 8) as usize;
        format!("{value:.decimals$}")
    } else {
        format!("{value:.4e}")
    };
    if unit.is_empty() {
        text
    } else {
        format!("{text} {unit}")
    }
}

/// Several [`num`]s separated by ` / `, e.g. `1.0000 kg / 0.50000 m`.
pub fn nums(values: &[(f64, &str)]) -> String {
    values
        .iter()
        .map(|&(value, unit)| num(value, unit))
        .collect::<Vec<_>>()
        .join(" / ")
}

/// A range `lo … hi`, both ends formatted with [`num`] in `unit`.
pub fn num_range(lo: f64, hi: f64, unit: &str) -> String {
    format!("{} … {}", num(lo, unit), num(hi, unit))
}

/// `Some(x)` formatted with [`num`], or `fallback`.
pub fn opt_num(value: Option<f64>, unit: &str, fallback: &str) -> String {
    value.map_or_else(|| fallback.to_string(), |v| num(v, unit))
}

/// Prints a JSON value (pretty) on stdout.
pub fn print_json(value: &serde_json::Value) -> anyhow::Result<()> {
    println!("{}", serde_json::to_string_pretty(value)?);
    Ok(())
}

/// Checks that an optional override is finite (clap already parsed it as a number).
pub fn check_finite(name: &str, value: Option<f64>) -> anyhow::Result<()> {
    match value {
        Some(v) if !v.is_finite() => invalid(format!("--{name} must be a finite number, got {v}")),
        _ => Ok(()),
    }
}

/// [`check_finite`] for each `(name, value)` in order; the first non-finite one is the error.
pub fn check_all_finite(values: &[(&str, Option<f64>)]) -> anyhow::Result<()> {
    values
        .iter()
        .try_for_each(|&(name, value)| check_finite(name, value))
}

/// A progress bar that draws only on a terminal, and never when `hidden` (see
/// [`OutputArgs::hide_progress`]).
pub fn bar(len: usize, message: &str, hidden: bool) -> indicatif::ProgressBar {
    let bar = crate::cmd::progress::count_bar(len as u64, "cells", hidden);
    bar.set_message(message.to_string());
    bar
}
