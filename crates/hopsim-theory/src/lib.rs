//! Closed-form impact maps and reduced models of hopsim (docs/physics.md §3 and §5).
//!
//! * [`impact`]: collision matrix, inelastic impacts, applied impulses (§3).
//! * [`template`]: the four-map impulsive eccentric-wheel template (§5.1).
//! * [`obstacle`]: energy to overcome a step by rolling, trivial and rotational hopping (§5.2).
//! * [`impulsive_wheel`]: the take-off-angle return map of the impulsive wheel (§5.5).
//! * [`robbit`]: Robbit's hopping cycle as a return map on the section before the brake
//!   (§5.3); [`fixed_points`]: its fixed-point controls `β* = (T*, ζ0*)` and their stability
//!   over a take-off angle × energy grid; [`cube`]: the impulse-actuated cube it is compared
//!   with (§5.3 [5.21]).
//! * [`grid`]: parallel grids reporting progress through a callback; [`numerics`]: root
//!   finding, minimisation, Dormand–Prince.
//!
//! Pure theory: no time-stepper, no plotting, no progress display (the studies of
//! `hopsim-studies` cross-check these models against the time-stepper and draw them).
//! `docs/analysis.md` documents every equation, derivation and sign convention.

pub mod cube;
pub mod dop853;
pub mod error;
pub mod fixed_points;
pub mod grid;
pub mod impact;
pub mod impulsive_wheel;
pub mod numerics;
pub mod obstacle;
pub mod robbit;
pub mod template;

pub use error::{AnalysisError, Result};

/// Gravitational acceleration used by default, `g = 9.81 m/s²` (docs/physics.md §1).
pub const STANDARD_GRAVITY: f64 = 9.81;
