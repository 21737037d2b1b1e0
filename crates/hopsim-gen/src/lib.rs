//! Generated mechanisms for testing hopsim (docs/reliability.md, "Generated mechanisms").
//!
//! [`genes`] draws random numbers with proptest; [`Mechanism::from_genes`] reads them into
//! a valid scene of 1 … 8 bodies in one or more trees (floating, pinned and fixed bases,
//! revolute and prismatic joints with stops, springs and dampers), every shape type, flat,
//! inclined and stepped terrain, contacts between bodies, springs, every controller and a
//! range of `Δt`, written as TOML so that it goes through the validation every scene goes
//! through. [`run_and_check`] runs one and checks what every run must satisfy.

mod check;
pub mod genes;
mod mechanism;

pub use check::{run_and_check, scene_of, Outcome, RunFigures, Violation};
pub use genes::{genes, Genes, MAX_GENERATED_BODIES};
pub use mechanism::{Body, Mechanism, Mount, Shape};
