//! Figures as files: each drawn as PNG and SVG into temporary files and committed together
//! (`hopsim_io`), so that a figure appears whole or not at all.

use super::{Figure, Typeset};
use crate::error::{Result, StudyError};
use hopsim_io::{AtomicPath, IoError};
use plotters::prelude::*;
use std::path::{Path, PathBuf};

/// Draws `figure` as a PNG file into a temporary file for `path`, committed by the caller.
fn stage_png<F: Figure>(figure: &F, path: &Path) -> Result<AtomicPath> {
    let output = AtomicPath::create(path)?;
    {
        let backend = BitMapBackend::new(output.temporary(), figure.size());
        let root = Typeset::raster(backend).into_drawing_area();
        figure
            .draw(&root)
            .and_then(|()| root.present().map_err(|e| e.to_string()))
            .map_err(|message| plot_error(path, message))?;
    }
    Ok(output)
}

/// Draws `figure` as an SVG file into a temporary file for `path`, committed by the caller.
fn stage_svg<F: Figure>(figure: &F, path: &Path) -> Result<AtomicPath> {
    let mut svg = String::new();
    {
        let backend = SVGBackend::with_string(&mut svg, figure.size());
        let root = Typeset::vector(backend).into_drawing_area();
        figure
            .draw(&root)
            .and_then(|()| root.present().map_err(|e| e.to_string()))
            .map_err(|message| plot_error(path, message))?;
    }
    let output = AtomicPath::create(path)?;
    std::fs::write(output.temporary(), svg).map_err(|e| IoError::new(path, e))?;
    Ok(output)
}

fn plot_error(path: &Path, message: String) -> StudyError {
    StudyError::Plot {
        path: path.to_path_buf(),
        message,
    }
}

/// The files of the figure `stem`: `stem.png` and `stem.svg`.
pub fn figure_paths(stem: &Path) -> [PathBuf; 2] {
    ["png", "svg"].map(|extension| stem.with_extension(extension))
}

/// Draws `stem.png` and `stem.svg` into temporary files, committed by the caller (so that a
/// set of files appears together, [`crate::write_files`]).
pub fn stage_png_and_svg<F: Figure>(figure: &F, stem: &Path) -> Result<Vec<AtomicPath>> {
    let [png, svg] = figure_paths(stem);
    Ok(vec![stage_png(figure, &png)?, stage_svg(figure, &svg)?])
}

/// Writes `stem.png` and `stem.svg` (atomically, both or neither); returns both paths.
pub fn write_png_and_svg<F: Figure>(figure: &F, stem: &Path) -> Result<Vec<PathBuf>> {
    commit_all(stage_png_and_svg(figure, stem)?)
}

/// Commits every staged file, in order; returns their paths.
pub fn commit_all(staged: Vec<AtomicPath>) -> Result<Vec<PathBuf>> {
    staged
        .into_iter()
        .map(|output| {
            let path = output.path().to_path_buf();
            output.commit()?;
            Ok(path)
        })
        .collect()
}
