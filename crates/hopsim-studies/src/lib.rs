//! Studies of hopsim, above the run loop: each takes parameters, runs reduced models
//! (`hopsim-theory`) or simulations (`hopsim-sim`, the only run loop), and returns a
//! serialisable [`Report`] with its tables, CSV files and figures. The command line and
//! the Python package are thin front ends over these reports.
//!
//! * [`report`]: the [`Report`] trait, text tables, number formatting, writing files.
//! * [`plot`]: line plots, heatmaps and category maps as PNG + SVG.
//! * [`robbit_gait`]: Robbit in the time-stepper, the cross-check of a predicted gait;
//!   [`fixed_points`]: Robbit's periodic gaits and their stability over a grid.
//! * [`gait`]: a run or a recording cycle by cycle: periods, fractions, periodicity and
//!   the overlay of the last cycles (Fig. 5.11).
//! * [`run_summary`]: a scene's run and its summary with the controller's sections;
//!   [`sweep`]: a scene over a grid of parameters, with its CSV and figure.
//! * [`template`], [`obstacle`], [`impulsive_wheel`]: the reduced models of docs/physics.md
//!   §5.1, §5.2 and §5.5 as studies.
//! * [`optimize`]: CMA-ES over scene keys (or any function) with checkpoints.
//! * [`progress`]: how studies report progress over their grids.

pub mod error;
pub mod fixed_points;
pub mod gait;
pub mod impulsive_wheel;
pub mod obstacle;
pub mod optimize;
pub mod plot;
pub mod progress;
pub mod report;
pub mod robbit_gait;
pub mod run_summary;
pub mod sweep;
pub mod template;

pub use error::{Result, StudyError};
pub use report::{
    write_files, AnyFigure, MissingFigure, Report, ReportFile, TextTable, WrittenFiles,
};
