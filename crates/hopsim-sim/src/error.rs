//! Why a run stops early.

use hopsim_record::RecordError;
use hopsim_step::StepError;

/// Why a run stopped early.
#[derive(Debug, thiserror::Error)]
pub enum RunError {
    #[error(transparent)]
    Step(#[from] StepError),
    /// A loop joint reached a singular configuration or could not be closed
    /// ([`StepError::Loop`] with the loop's name, docs/physics.md §8.4).
    #[error("step {step} (t = {t:.6} s): loop '{name}' {}, loop error {error:.3e}", hopsim_step::loop_failure(*.singular))]
    Loop {
        step: u64,
        t: f64,
        name: String,
        singular: bool,
        error: f64,
    },
    #[error("recording failed: {0}")]
    Record(#[from] RecordError),
    /// A figure of the run overflowed (e.g. a potential energy of `inf` from a state near
    /// `1e308`): the run's results cannot be reported.
    #[error("the run's {figure} is {value}: a value overflowed, so the run has no result")]
    NotFinite { figure: &'static str, value: f64 },
    /// A command of [`crate::Simulation::step_with`] that the model cannot carry out; the
    /// step was not taken.
    #[error("actuation refused: {0}")]
    Actuation(#[from] hopsim_step::ActuationError),
    /// The user stopped the run (an observer saw Ctrl-C), at simulation time `t`.
    #[error("interrupted at t = {t:.6} s")]
    Interrupted { t: f64 },
    /// A bug: the step panicked (docs/reliability.md, "Panics"). The simulation refuses
    /// further steps; its recordings up to the last completed step can be kept.
    #[error(
        "internal error in step {step} (t = {t:.6} s): {message}. This is a bug in hopsim; \
         please report it with the scene file and the command line"
    )]
    Internal { step: u64, t: f64, message: String },
}

impl RunError {
    /// `err` of a step of `model`: a loop joint's error names the loop.
    pub fn of_step(err: StepError, model: &hopsim_model::Model) -> Self {
        match err {
            StepError::Loop {
                step,
                t,
                loop_index,
                singular,
                error,
            } => RunError::Loop {
                step,
                t,
                name: model.loops()[loop_index].name.clone(),
                singular,
                error,
            },
            e => RunError::Step(e),
        }
    }
}

/// The message of a panic's payload (`panic!` with a literal or a formatted string).
pub fn panic_message(payload: &(dyn std::any::Any + Send)) -> String {
    match (
        payload.downcast_ref::<&str>(),
        payload.downcast_ref::<String>(),
    ) {
        (Some(s), _) => format!("panicked: {s}"),
        (_, Some(s)) => format!("panicked: {s}"),
        _ => "panicked".to_string(),
    }
}
