//! Reports: what every study returns. A report serialises to the `--json` object, prints
//! as text tables, and lists its files (CSV tables and figures); [`write_files`] writes
//! them. Front ends (the command line, Python) only choose which of these to show.

use crate::error::Result;
use crate::plot::{
    commit_all, figure_paths, stage_png_and_svg, CategoryMap, Figure, Heatmap, LinePlot, PlotStack,
};
use hopsim_io::CsvTable;
use hopsim_io::{AtomicPath, IoError};
use serde::Serialize;
use std::fmt;
use std::path::{Path, PathBuf};

/// A study's result.
pub trait Report: Serialize {
    /// The human-readable text: tables and notes, ending with a newline.
    fn text(&self) -> String;

    /// The report's files: CSV tables and figures (none by default).
    fn files(&self) -> Vec<ReportFile> {
        Vec::new()
    }
}

/// A figure of any kind a report draws.
pub enum AnyFigure {
    Line(LinePlot),
    Heatmap(Heatmap),
    Categories(CategoryMap),
    Stack(PlotStack),
}

impl From<LinePlot> for AnyFigure {
    fn from(f: LinePlot) -> Self {
        AnyFigure::Line(f)
    }
}

impl From<Heatmap> for AnyFigure {
    fn from(f: Heatmap) -> Self {
        AnyFigure::Heatmap(f)
    }
}

impl From<CategoryMap> for AnyFigure {
    fn from(f: CategoryMap) -> Self {
        AnyFigure::Categories(f)
    }
}

impl From<PlotStack> for AnyFigure {
    fn from(f: PlotStack) -> Self {
        AnyFigure::Stack(f)
    }
}

impl Figure for AnyFigure {
    fn size(&self) -> (u32, u32) {
        match self {
            AnyFigure::Line(f) => f.size(),
            AnyFigure::Heatmap(f) => f.size(),
            AnyFigure::Categories(f) => f.size(),
            AnyFigure::Stack(f) => f.size(),
        }
    }

    fn draw<DB: plotters::prelude::DrawingBackend>(
        &self,
        root: &plotters::prelude::DrawingArea<crate::plot::Typeset<DB>, plotters::coord::Shift>,
    ) -> crate::plot::DrawResult {
        match self {
            AnyFigure::Line(f) => f.draw(root),
            AnyFigure::Heatmap(f) => f.draw(root),
            AnyFigure::Categories(f) => f.draw(root),
            AnyFigure::Stack(f) => f.draw(root),
        }
    }
}

/// One output file of a report.
pub enum ReportFile {
    /// A CSV table written as `name` (e.g. `fixed_points.csv`).
    Csv { name: String, table: CsvTable },
    /// A figure written as `stem.png` and `stem.svg`.
    Figure { stem: String, figure: AnyFigure },
}

impl ReportFile {
    /// A CSV file.
    pub fn csv(name: impl Into<String>, table: CsvTable) -> Self {
        ReportFile::Csv {
            name: name.into(),
            table,
        }
    }

    /// A figure (PNG and SVG).
    pub fn figure(stem: impl Into<String>, figure: impl Into<AnyFigure>) -> Self {
        ReportFile::Figure {
            stem: stem.into(),
            figure: figure.into(),
        }
    }
}

/// A figure [`write_files`] could not draw or write: a warning, never a lost study.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct MissingFigure {
    /// The figure's stem (`sweep`).
    pub figure: String,
    /// Its files that were not written (`DIR/sweep.png`, `DIR/sweep.svg`).
    pub files: Vec<PathBuf>,
    /// Why.
    pub reason: String,
}

impl fmt::Display for MissingFigure {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let files: Vec<String> = self.files.iter().map(|p| p.display().to_string()).collect();
        write!(
            f,
            "the figure `{}` could not be drawn, so {} are missing: {}",
            self.figure,
            files.join(" and "),
            self.reason
        )
    }
}

/// What [`write_files`] wrote, and the figures it could not.
#[derive(Clone, Debug, Default, PartialEq, Serialize)]
pub struct WrittenFiles {
    /// The files written: the tables, then the figures.
    pub files: Vec<PathBuf>,
    /// The figures left out.
    pub missing_figures: Vec<MissingFigure>,
}

/// Writes `files` into `dir` (created if missing), tables before figures, every file
/// atomically (complete under a temporary name, then renamed into place):
///
/// 1. the CSV tables, as one set (all renamed into place once all are written), so that
///    an error writing one (an `Err`) leaves none;
/// 2. then each figure, its PNG and SVG together; a figure that cannot be drawn or written
///    leaves both out and is listed in [`WrittenFiles::missing_figures`], never an error:
///    the tables hold the study's results, the figures only show them.
pub fn write_files(dir: &Path, files: &[ReportFile]) -> Result<WrittenFiles> {
    hopsim_io::create_dir(dir)?;
    let mut tables = Vec::new();
    for file in files {
        if let ReportFile::Csv { name, table } = file {
            let path = dir.join(name);
            let output = AtomicPath::create(&path)?;
            std::fs::write(output.temporary(), table.to_csv_string())
                .map_err(|e| IoError::new(&path, e))?;
            tables.push(output);
        }
    }
    let mut written = WrittenFiles {
        files: commit_all(tables)?,
        missing_figures: Vec::new(),
    };
    for file in files {
        if let ReportFile::Figure { stem, figure } = file {
            let stem_path = dir.join(stem);
            match stage_png_and_svg(figure, &stem_path).and_then(commit_all) {
                Ok(paths) => written.files.extend(paths),
                Err(e) => written.missing_figures.push(MissingFigure {
                    figure: stem.clone(),
                    files: figure_paths(&stem_path).to_vec(),
                    reason: e.to_string(),
                }),
            }
        }
    }
    Ok(written)
}

/// A two-column text table with a title.
#[derive(Clone, Debug, Default)]
pub struct TextTable {
    title: String,
    rows: Vec<(String, String)>,
}

impl TextTable {
    /// An empty table.
    pub fn new(title: impl Into<String>) -> Self {
        TextTable {
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

impl fmt::Display for TextTable {
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

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn numbers_keep_five_significant_digits() {
        assert_eq!(num(0.123456, "m"), "0.12346 m");
        assert_eq!(num(1234.5678, ""), "1234.6");
        assert_eq!(num(1.5e-5, "s"), "1.5000e-5 s");
        assert_eq!(num_range(0.0, 2.0, "J"), "0.0000 J … 2.0000 J");
    }

    #[test]
    fn tables_align_their_keys() {
        let mut t = TextTable::new("title");
        t.row("a", 1).row("longer", "x");
        assert_eq!(t.to_string(), "title\n  a       1\n  longer  x\n");
    }
}
