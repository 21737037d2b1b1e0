//! The simulation loop: before each step the controller fills the actuation, the stepper
//! advances the state, and observers (recorders, the summary, golden traces) see the
//! step's record and events.

mod flight;
mod observer;
mod periodicity;
mod recording;
mod simulation;
mod summary;
mod sweep;

pub use flight::{FlightEvent, FlightTracker, HOP_CLEARANCE};
pub use observer::{Observer, StepView};
pub use periodicity::{Periodicity, PeriodicityOptions, PoincareSection};
pub use recording::{recording_info, RecordingObserver};
pub use simulation::{run, RunError, RunOptions, Simulation};
pub use summary::{
    CubeBaseline, EnergySummary, ImpulseSummary, LcpSummary, RobbitSummary, Summary,
};
pub use sweep::{grid_jobs, grid_points, sweep, GridAxis, SweepJob, SweepPoint};
