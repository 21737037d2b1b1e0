//! Why a run stops early.

use hopsim_record::RecordError;
use hopsim_step::StepError;

/// Why a run stopped early.
#[derive(Debug, thiserror::Error)]
pub enum RunError {
    #[error(transparent)]
    Step(#[from] StepError),
    #[error("recording failed: {0}")]
    Record(#[from] RecordError),
    /// The user stopped the run (an observer saw Ctrl-C), at simulation time `t`.
    #[error("interrupted at t = {t:.6} s")]
    Interrupted { t: f64 },
}
