//! Studies of hopsim, above the run loop: each takes parameters, runs reduced models
//! (`hopsim-analysis`) or simulations (`hopsim-sim`, the only run loop), and returns a
//! serialisable [`Report`] with its tables, CSV files and figures. The command line and
//! the Python package are thin front ends over these reports.
//!
//! * [`report`]: the [`Report`] trait, text tables, number formatting, writing files.
//! * [`plot`]: line plots, heatmaps and category maps as PNG + SVG.
//! * [`robbit_gait`]: Robbit in the time-stepper, the cross-check of a predicted gait.

pub mod error;
pub mod plot;
pub mod report;
pub mod robbit_gait;

pub use error::{Result, StudyError};
pub use report::{write_files, AnyFigure, Report, ReportFile, Table};
