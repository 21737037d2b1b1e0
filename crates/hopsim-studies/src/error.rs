//! Errors of the studies.

use std::path::PathBuf;

/// Everything that can stop a study.
#[derive(Debug, thiserror::Error)]
pub enum StudyError {
    /// A reduced model rejected its parameters or failed numerically.
    #[error(transparent)]
    Analysis(#[from] hopsim_theory::AnalysisError),
    /// A scene built by the study is invalid.
    #[error(transparent)]
    Scene(#[from] hopsim_scene::SceneError),
    /// A model built by the study is invalid.
    #[error(transparent)]
    Model(#[from] hopsim_model::ModelError),
    /// A time-stepper run stopped.
    #[error("time-stepper: {0}")]
    Run(#[from] hopsim_sim::RunError),
    /// Writing an output file failed.
    #[error("cannot write {0}")]
    Io(#[from] hopsim_io::IoError),
    /// A recording could not be read (missing, corrupt, not a hopsim recording); its
    /// message names the file and the cause.
    #[error("{0}")]
    Record(hopsim_record::RecordError),
    /// The input does not allow the study (e.g. a run without two cycles to compare).
    #[error("{0}")]
    Input(String),
    /// Drawing a figure failed (e.g. no usable font on the machine).
    #[error("cannot draw {}: {message}", path.display())]
    Plot { path: PathBuf, message: String },
}

impl From<hopsim_record::RecordError> for StudyError {
    fn from(e: hopsim_record::RecordError) -> Self {
        StudyError::Record(e)
    }
}

impl StudyError {
    /// True when the error is the user's input (exit code 2 at the command line), not a
    /// failure of the study.
    pub fn is_invalid_input(&self) -> bool {
        matches!(
            self,
            StudyError::Analysis(hopsim_theory::AnalysisError::InvalidParameter { .. })
                | StudyError::Scene(_)
                | StudyError::Record(_)
                | StudyError::Input(_)
        )
    }
}

/// Result alias of this crate.
pub type Result<T> = std::result::Result<T, StudyError>;
