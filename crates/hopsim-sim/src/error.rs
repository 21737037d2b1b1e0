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
    /// A figure of the run overflowed (e.g. a potential energy of `inf` from a state near
    /// `1e308`): the run's results cannot be reported.
    #[error("the run's {figure} is {value}: a value overflowed, so the run has no result")]
    NotFinite { figure: &'static str, value: f64 },
    /// The user stopped the run (an observer saw Ctrl-C), at simulation time `t`.
    #[error("interrupted at t = {t:.6} s")]
    Interrupted { t: f64 },
}
