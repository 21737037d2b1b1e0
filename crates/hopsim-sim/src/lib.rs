//! The simulation loop: before each step the controller fills the actuation, the stepper
//! advances the state, and observers (recorders, the summary, golden traces, progress
//! displays) see the step's record and events.
//!
//! * [`Simulation`]: one step at a time (the scene's controller, or a caller's actuation
//!   with [`Simulation::step_with`]); [`run`]: a whole run and its [`Summary`];
//!   [`run_for`]: a span of a simulation under way.
//! * [`Observer`]: what watches a run ([`StepView`] after every step).
//! * [`RecordingObserver`]: frames and events to the recorders of `hopsim-record`.
//! * [`PoincareSection`]: a stroboscopic section of a run and its period ([`Periodicity`]).
//! * [`sweep`]: a scene run over a grid of overrides, in parallel.

mod error;
mod flight;
mod observer;
mod periodicity;
mod recording;
mod run;
mod simulation;
mod summary;
mod sweep;

pub use error::{panic_message, RunError};
pub use flight::{FlightEvent, FlightTracker, HOP_CLEARANCE};
pub use observer::{Observer, StepView, StopFlag};
pub use periodicity::{Periodicity, PeriodicityOptions, PoincareSection};
pub use recording::{recording_info, RecordingObserver};
pub use run::{run, run_for};
pub use simulation::{Simulation, CREATED_ENERGY, IMPACT_STEPS, PANIC_AT_STEP};
pub use summary::{
    per_forward_metre, EnergySummary, ImpulseSummary, LcpSummary, Summary, WindowTotals,
    BALANCE_WARNING, IMPULSE_UNIT,
};
pub use sweep::{
    grid_jobs, grid_points, sweep, GridAxis, Progress, SweepJob, SweepPoint, NO_PROGRESS,
};
