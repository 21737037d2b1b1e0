//! The Moreau midpoint time-stepper of docs/physics.md §4 (Glocker/Studer).
//!
//! One [`Stepper::step`] advances a [`State`] by `Δt`: midpoint configuration, index set
//! of closed contacts, the frictional contact LCP solved by Lemke's method, velocity and
//! position update. Impulsive actuation (applied impulses, brakes locking a joint) acts
//! inside a step. Each step yields a [`StepRecord`] with the contact percussions and an
//! energy ledger whose balance closes to the scheme's own error.

mod actuation;
mod linalg;
mod record;
mod state;
mod stepper;

pub use actuation::{
    check_controls, check_lock, Actuation, ActuationError, ImpulseCommand, JointForceCommand,
    TorqueCommand,
};
pub use record::{
    ContactRecord, ContactState, EnergyLedger, LcpStats, LimitRecord, LockRecord, Resolution,
    StepRecord, STATE_MARGIN,
};
pub use state::State;
pub use stepper::{loop_failure, StepError, StepSettings, Stepper, DEPENDENT_ROWS, LOOP_TOLERANCE};
