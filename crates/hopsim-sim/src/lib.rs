//! The simulation loop: before each step the controller fills the actuation, the stepper
//! advances the state, and observers (recorders, the summary, golden traces, progress
//! displays) see the step's record and events.
//!
//! * [`Simulation`]: one step at a time (the scene's controller, or a caller's actuation
//!   with [`Simulation::step_with`]); [`run`]: a whole run and its [`Summary`];
//!   [`run_for`]: a span of a simulation under way; [`OpenSummary`]: the summary of a
//!   run stepped by its caller, whose end is known only when it stops.
//! * [`Batch`]: many copies of a model stepped together on a fixed number of threads.
//! * [`Observer`]: what watches a run ([`StepView`] after every step).
//! * [`RecordingObserver`]: frames and events to the recorders of `hopsim-record`.
//! * [`PoincareSection`]: a stroboscopic section of a run and its period ([`Periodicity`]).
//! * [`Setup`]: what a simulation runs (a model, its start, its controller, its
//!   [`Settings`]), however it was described; [`check_state`], [`check_start`]: a start
//!   state checked against it.

mod batch;
mod error;
mod flight;
mod observer;
mod open_summary;
mod periodicity;
mod recording;
mod run;
mod setup;
mod simulation;
mod start;
mod summary;

pub use batch::{Batch, BatchError};
pub use error::{panic_message, RunError};
pub use flight::{FlightEvent, FlightTracker, HOP_CLEARANCE};
pub use observer::{Observer, StepView, StopFlag};
pub use open_summary::OpenSummary;
pub use periodicity::{Periodicity, PeriodicityOptions, PoincareSection};
pub use recording::{recording_info, RecordingObserver};
pub use run::{run, run_for};
pub use setup::{
    check_steps, Settings, Setup, TooManySteps, DEFAULT_MAX_STEPS, MAX_COORDINATE, MAX_MAGNITUDE,
    MIN_DT,
};
pub use simulation::{Simulation, CREATED_ENERGY, IMPACT_STEPS, PANIC_AT_STEP};
pub use start::{check_start, check_state, StartProblem, StateProblem, PENETRATION_TOL};
pub use summary::{
    per_forward_metre, EnergySummary, ImpulseSummary, LcpSummary, Summary, WindowTotals,
    BALANCE_WARNING, IMPULSE_UNIT,
};
