//! hopsim-lcp: linear complementarity problems and Lemke's method.
//!
//! Finds `z` with `w = M z + q`, `z ≥ 0`, `w ≥ 0`, `zᵀw = 0` by Lemke's complementary
//! pivoting with the lexicographic minimum-ratio test (Murty, "Linear Complementarity,
//! Linear and Nonlinear Programming", ch. 2), as the Moreau time-stepper needs for the
//! frictional contact LCP of docs/physics.md §4. Every answer carries a [`Certificate`]; the
//! status is [`LcpStatus::Solved`] only when it holds. When Lemke's method fails, the
//! solver retries with another covering vector and, for small `n`, enumerates
//! complementary bases. Pure numerics: knows nothing of mechanics. See `docs/lcp.md`.
//!
//! ```
//! use hopsim_lcp::{solve_lcp, LcpStatus};
//! use nalgebra::{dmatrix, dvector};
//! let sol = solve_lcp(&dmatrix![2.0, 1.0; 1.0, 2.0], &dvector![-5.0, -6.0]).unwrap();
//! assert_eq!(sol.status, LcpStatus::Solved);
//! assert!((sol.z[0] - 4.0 / 3.0).abs() < 1e-12 && (sol.z[1] - 7.0 / 3.0).abs() < 1e-12);
//! ```

mod certificate;
pub mod dat;
mod enumerate;
mod error;
mod lemke;
mod primary;
mod problem;
mod solution;
mod tableau;

pub use certificate::Certificate;
pub use dat::DatError;
pub use error::LcpInputError;
pub use lemke::{solve_lcp, LemkeOptions, LemkeSolver, WarmStart};
pub use problem::LcpProblem;
pub use solution::{LcpSolution, LcpStatus, SolveMethod};
