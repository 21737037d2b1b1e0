//! Fixed points of Robbit's return map and their stability (docs/physics.md §5.3).
//!
//! For a section state `z = (φ_TO, φ̇_TO)` ([`crate::robbit`]) the fixed-point control
//! `β* = (T*, ζ0*)` solves `P(z; β) = z`: two equations in two unknowns, solved by
//! Levenberg–Marquardt ([`crate::numerics::levenberg_marquardt`]) on the residual
//! `r(β) = (φ' − φ, τ (φ̇' − φ̇))`, `τ = sqrt(R/g)`, in the variables `(ln T, ln ζ0)` (so that
//! `T, ζ0 > 0`), from several starting controls; of several fixed points the one with the
//! shortest cycle is kept. Stability: the eigenvalues of the 2 × 2 Jacobian `∂P/∂z` at fixed
//! `β*` by central differences on the section (`ψ̇` follows `φ̇` so that `ζ = ζ0` stays
//! true); stable iff all `|λ| < 1` [5.18]. docs/analysis.md §9.7–9.9.

use crate::error::{AnalysisError, Result};
use crate::grid::{par_map, CellDone};
use crate::numerics::{eigenvalues_2x2, levenberg_marquardt_from, linspace, Complex, LmSettings};
use crate::robbit::{cycle, return_map, Control, Cycle, NoCycle, RobbitParams, SectionState};
use serde::Serialize;
use std::fmt;

/// Settings of the fixed-point search.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct SolverSettings {
    /// Levenberg–Marquardt settings (tolerance on the residual norm in rad).
    pub lm: LmSettings,
    /// Starting torques `T` [N m] (crossed with `impulse_guesses`).
    pub torque_guesses: Vec<f64>,
    /// Starting impulse limits `ζ0` [N m s].
    pub impulse_guesses: Vec<f64>,
    /// Levenberg–Marquardt runs at most, from the starts with the smallest residuals.
    pub max_starts: usize,
    /// Central-difference step of `∂P/∂z` (relative to `max(|z_i|, 1)`).
    pub jacobian_step: f64,
}

impl Default for SolverSettings {
    /// Tolerance 1e-9 rad, 20 iterations, Jacobian step 1e-7; starts `T ∈ {0.1, 0.2, 0.35, 0.6}` ×
    /// `ζ0 ∈ {0.02, 0.04, 0.07, 0.12}`, at most 4 runs; `∂P/∂z` step 1e-6.
    fn default() -> Self {
        SolverSettings {
            lm: LmSettings {
                tolerance: 1e-9,
                max_iterations: 20,
                jacobian_step: 1e-7,
                initial_damping: 1e-3,
            },
            torque_guesses: vec![0.1, 0.2, 0.35, 0.6],
            impulse_guesses: vec![0.02, 0.04, 0.07, 0.12],
            max_starts: 4,
            jacobian_step: 1e-6,
        }
    }
}

/// A fixed point `P(z; β*) = z` with its stability.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct FixedPoint {
    /// The section state `z`.
    pub state: SectionState,
    /// `β* = (T*, ζ0*)`.
    pub control: Control,
    /// `‖r(β*)‖` [rad].
    pub residual: f64,
    /// Levenberg–Marquardt iterations of the successful run.
    pub iterations: usize,
    /// `∂P/∂z` at `β*`, rows `(∂φ'/∂φ, ∂φ'/∂φ̇)`, `(∂φ̇'/∂φ, ∂φ̇'/∂φ̇)`.
    pub jacobian: [[f64; 2]; 2],
    /// Its eigenvalues, largest modulus first.
    pub eigenvalues: [Complex; 2],
    /// `max |λ|`.
    pub spectral_radius: f64,
    /// `max |λ| < 1` [5.18].
    pub stable: bool,
    /// The periodic cycle.
    pub cycle: Cycle,
}

impl FixedPoint {
    /// Mean forward speed of the gait [m/s].
    pub fn speed(&self) -> f64 {
        self.cycle.speed()
    }

    /// Impulse per travelled distance `ζ0 / stride` [N m s per m] (docs/physics.md §5.3).
    pub fn impulse_per_distance(&self) -> f64 {
        self.control.impulse_limit / self.cycle.stride
    }

    /// Where the no-slip, closed-contact assumptions of the model fail on this gait
    /// (empty: consistent): a pulling touchdown, a friction cone exceeded at touchdown or in
    /// stance (`μ` from the parameters), a stance that would need a pulling ground.
    pub fn warnings(&self, p: &RobbitParams) -> Vec<String> {
        let mut out = Vec::new();
        let td = &self.cycle.touchdown;
        if td.normal_percussion < 0.0 {
            out.push(format!(
                "touchdown needs a pulling normal percussion ({:.3e} N s)",
                td.normal_percussion
            ));
        } else if td.tangential_percussion.abs() > p.friction * td.normal_percussion {
            out.push(format!(
                "touchdown leaves the friction cone (|Λ_T|/Λ_N = {:.3} > μ = {})",
                td.tangential_percussion.abs() / td.normal_percussion,
                p.friction
            ));
        }
        let st = &self.cycle.stance;
        if st.min_normal_force < 0.0 {
            out.push(format!(
                "the stance needs a pulling ground (min normal force {:.3} N)",
                st.min_normal_force
            ));
        }
        if st.max_friction_ratio > p.friction {
            out.push(format!(
                "the stance leaves the friction cone (max |F_T|/F_N = {:.3} > μ = {})",
                st.max_friction_ratio, p.friction
            ));
        }
        out
    }
}

/// Why a section state has no fixed point.
#[derive(Debug, Clone, PartialEq, Serialize)]
#[serde(tag = "kind", rename_all = "kebab-case")]
pub enum NoFixedPoint {
    /// No cycle exists for any control (the brake cannot lift the disc), or none of the
    /// starting controls gave one; the reason of the first start.
    NoCycle {
        /// Why.
        reason: NoCycle,
    },
    /// Levenberg–Marquardt did not reach the tolerance from any start ("solver failed").
    #[serde(rename = "solver-failed")]
    NotConverged {
        /// Smallest residual reached [rad].
        residual: f64,
        /// Where.
        control: Control,
    },
    /// The periodic gait moves backwards (stride ≤ 0).
    MovesBackward {
        /// Stride of the cycle [m].
        stride: f64,
        /// The fixed-point control.
        control: Control,
    },
}

impl fmt::Display for NoFixedPoint {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            NoFixedPoint::NoCycle { reason } => write!(f, "no cycle: {reason}"),
            NoFixedPoint::NotConverged { residual, control } => write!(
                f,
                "solver failed: residual {residual:.2e} rad at T = {:.4} N m, ζ0 = {:.4} N m s",
                control.torque, control.impulse_limit
            ),
            NoFixedPoint::MovesBackward { stride, control } => write!(
                f,
                "the periodic gait moves backwards (stride {stride:.4} m at T = {:.4} N m, ζ0 = {:.4} N m s)",
                control.torque, control.impulse_limit
            ),
        }
    }
}

impl NoFixedPoint {
    /// The kind of failure as the fixed-point study counts it: the cycle's reason
    /// ([`NoCycle::kind`]) when there is no cycle, else `solver-failed` or `moves-backward`
    /// (the first also starts the [`fmt::Display`] text: `solver failed: …`).
    pub fn kind(&self) -> &'static str {
        match self {
            NoFixedPoint::NoCycle { reason } => reason.kind(),
            NoFixedPoint::NotConverged { .. } => "solver-failed",
            NoFixedPoint::MovesBackward { .. } => "moves-backward",
        }
    }
}

/// `τ = sqrt(R/g)`: scales the angular-velocity residual to radians.
fn time_scale(p: &RobbitParams) -> f64 {
    (p.radius / p.gravity).sqrt()
}

/// The residual `r(β) = (φ' − φ, τ (φ̇' − φ̇))` of `P(z; β) = z` [rad].
pub fn residual(
    p: &RobbitParams,
    z: &SectionState,
    control: &Control,
) -> std::result::Result<[f64; 2], NoCycle> {
    let next = return_map(p, z, control)?;
    Ok([
        next.angle - z.angle,
        time_scale(p) * (next.angular_velocity - z.angular_velocity),
    ])
}

fn control_of(log: &[f64; 2]) -> Control {
    Control {
        torque: log[0].exp(),
        impulse_limit: log[1].exp(),
    }
}

/// `∂P/∂z` at `(z, β)` by central differences on the section (step `h max(|z_i|, 1)`).
pub fn return_map_jacobian(
    p: &RobbitParams,
    z: &SectionState,
    control: &Control,
    step: f64,
) -> std::result::Result<[[f64; 2]; 2], NoCycle> {
    let mut jac = [[0.0; 2]; 2];
    let base = [z.angle, z.angular_velocity];
    for col in 0..2 {
        let h = step * base[col].abs().max(1.0);
        let image = |d: f64| {
            let mut s = base;
            s[col] += d;
            let shifted = SectionState {
                angle: s[0],
                angular_velocity: s[1],
            };
            return_map(p, &shifted, control).map(|n| [n.angle, n.angular_velocity])
        };
        let (plus, minus) = (image(h)?, image(-h)?);
        for row in 0..2 {
            jac[row][col] = (plus[row] - minus[row]) / (2.0 * h);
        }
    }
    Ok(jac)
}

/// Eigenvalues, spectral radius and stability of `∂P/∂z` [5.18].
pub fn stability(jacobian: [[f64; 2]; 2]) -> ([Complex; 2], f64, bool) {
    let eigenvalues = eigenvalues_2x2(jacobian);
    let radius = eigenvalues[0].modulus().max(eigenvalues[1].modulus());
    (eigenvalues, radius, radius < 1.0)
}

/// Finds `β*` with `P(z; β*) = z` and its stability (module docs).
///
/// The starts of `settings` are ranked by their residual norm and Levenberg–Marquardt runs
/// from the best `max_starts` of them, within the box `T ∈ [TORQUE_BOUNDS]`,
/// `ζ0 ∈ [IMPULSE_BOUNDS]` (outside it the residual counts as undefined). A section state
/// can have several fixed points (stances with more rocking swings and lower torque); of
/// the forward-moving ones found, the one with the **shortest cycle period** is returned.
pub fn find_fixed_point(
    p: &RobbitParams,
    z: &SectionState,
    settings: &SolverSettings,
) -> Result<std::result::Result<FixedPoint, NoFixedPoint>> {
    p.validate()?;
    if !(z.angle.is_finite() && z.angular_velocity.is_finite()) {
        return Err(AnalysisError::invalid(
            "section state",
            z.angle + z.angular_velocity,
            "must be finite",
        ));
    }
    let bounded = |log: &[f64; 2]| {
        let c = control_of(log);
        let inside = (TORQUE_BOUNDS.0..=TORQUE_BOUNDS.1).contains(&c.torque)
            && (IMPULSE_BOUNDS.0..=IMPULSE_BOUNDS.1).contains(&c.impulse_limit);
        inside.then_some(c)
    };
    let mut first_failure: Option<NoCycle> = None;
    // Each start's log-control, residual and residual norm.
    let mut starts: Vec<([f64; 2], [f64; 2], f64)> = Vec::new();
    for &torque in &settings.torque_guesses {
        for &impulse_limit in &settings.impulse_guesses {
            let log = [torque.ln(), impulse_limit.ln()];
            let Some(control) = bounded(&log) else {
                continue;
            };
            match residual(p, z, &control) {
                Ok(r) => starts.push((log, r, r[0].hypot(r[1]))),
                // The brake's lift-off does not depend on β: no cycle at all.
                Err(reason @ NoCycle::NoLiftOff { .. }) => {
                    return Ok(Err(NoFixedPoint::NoCycle { reason }))
                }
                Err(reason) => {
                    first_failure.get_or_insert(reason);
                }
            }
        }
    }
    starts.sort_by(|a, b| a.2.total_cmp(&b.2));
    let mut closest: Option<(f64, Control)> = None;
    let mut found: Vec<(Control, usize, f64, Cycle)> = Vec::new();
    for (log, r0, _) in starts.iter().take(settings.max_starts) {
        let run = levenberg_marquardt_from(
            |x: &[f64; 2]| bounded(x).and_then(|c| residual(p, z, &c).ok()),
            *log,
            Some(*r0),
            &settings.lm,
        );
        let Some(run) = run else { continue };
        let control = control_of(&run.x);
        if !run.converged {
            if closest.is_none_or(|(r, _)| run.residual_norm < r) {
                closest = Some((run.residual_norm, control));
            }
            continue;
        }
        let duplicate = found.iter().any(|(c, ..)| {
            (c.torque - control.torque).abs() < 1e-6 * control.torque
                && (c.impulse_limit - control.impulse_limit).abs() < 1e-6 * control.impulse_limit
        });
        if duplicate {
            continue;
        }
        match cycle(p, z, &control) {
            Ok(c) => found.push((control, run.iterations, run.residual_norm, c)),
            Err(reason) => {
                first_failure.get_or_insert(reason);
            }
        }
    }
    let forward = found
        .iter()
        .filter(|(.., c)| c.stride > 0.0)
        .min_by(|a, b| a.3.period.total_cmp(&b.3.period));
    let Some((control, iterations, residual_norm, cyc)) = forward else {
        return Ok(Err(match (found.first(), closest, first_failure) {
            (Some((control, .., c)), ..) => NoFixedPoint::MovesBackward {
                stride: c.stride,
                control: *control,
            },
            (None, Some((residual, control)), _) => {
                NoFixedPoint::NotConverged { residual, control }
            }
            (None, None, Some(reason)) => NoFixedPoint::NoCycle { reason },
            (None, None, None) => NoFixedPoint::NoCycle {
                reason: NoCycle::Numerical {
                    message: "no starting control inside the search box".into(),
                },
            },
        }));
    };
    let jacobian = match return_map_jacobian(p, z, control, settings.jacobian_step) {
        Ok(j) => j,
        Err(reason) => return Ok(Err(NoFixedPoint::NoCycle { reason })),
    };
    let (eigenvalues, spectral_radius, stable) = stability(jacobian);
    Ok(Ok(FixedPoint {
        state: *z,
        control: *control,
        residual: *residual_norm,
        iterations: *iterations,
        jacobian,
        eigenvalues,
        spectral_radius,
        stable,
        cycle: *cyc,
    }))
}

/// Search box of the torque `T` [N m].
pub const TORQUE_BOUNDS: (f64, f64) = (1e-3, 5.0);
/// Search box of the impulse limit `ζ0` [N m s]: excludes the degenerate limit `ζ0 → 0`,
/// `T → ∞` in which the cycle shrinks to nothing and `P` tends to the identity.
pub const IMPULSE_BOUNDS: (f64, f64) = (1e-3, 0.5);

/// A take-off angle × take-off energy grid (docs/physics.md §5.3; the thesis used 150 × 150).
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct FixedPointGrid {
    /// Robot parameters.
    pub params: RobbitParams,
    /// `φ_TO` values [rad] (x axis).
    pub angles: Vec<f64>,
    /// `E_TO` values [J] (y axis).
    pub energies: Vec<f64>,
    /// Solver settings.
    pub settings: SolverSettings,
}

/// Default `φ_TO` range [rad]: the brake lifts the disc only for `sin φ_TO < 0`.
pub const DEFAULT_ANGLE_RANGE: (f64, f64) = (-1.5, -0.05);
/// Default `E_TO` range [J].
pub const DEFAULT_ENERGY_RANGE: (f64, f64) = (0.005, 0.15);

/// One grid point.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct GridPoint {
    /// `φ_TO` [rad].
    pub angle: f64,
    /// `E_TO` [J].
    pub energy: f64,
    /// `φ̇_TO` [rad/s].
    pub angular_velocity: f64,
    /// The fixed point, if found.
    pub fixed_point: Option<FixedPoint>,
    /// Why not, otherwise.
    pub no_fixed_point: Option<NoFixedPoint>,
}

impl FixedPointGrid {
    /// `n_angles × n_energies` points evenly spaced over the given ranges.
    pub fn new(
        params: RobbitParams,
        angle_range: (f64, f64),
        energy_range: (f64, f64),
        n_angles: usize,
        n_energies: usize,
    ) -> Self {
        FixedPointGrid {
            params,
            angles: linspace(angle_range.0, angle_range.1, n_angles),
            energies: linspace(energy_range.0, energy_range.1, n_energies),
            settings: SolverSettings::default(),
        }
    }

    /// Section states in row-major order (`E_TO` outer, `φ_TO` inner).
    pub fn states(&self) -> Result<Vec<(f64, f64, SectionState)>> {
        let mut out = Vec::with_capacity(self.angles.len() * self.energies.len());
        for &energy in &self.energies {
            for &angle in &self.angles {
                out.push((
                    angle,
                    energy,
                    SectionState::from_energy(&self.params, angle, energy)?,
                ));
            }
        }
        Ok(out)
    }

    /// Solves every point in parallel (rayon), calling `progress` per point; row-major order
    /// (`E_TO` outer, `φ_TO` inner).
    pub fn run(&self, progress: CellDone<'_>) -> Result<Vec<GridPoint>> {
        self.params.validate()?;
        if self.angles.is_empty() || self.energies.is_empty() {
            return Err(AnalysisError::invalid(
                "grid",
                0.0,
                "needs at least one angle and one energy",
            ));
        }
        let states = self.states()?;
        let results = par_map(&states, progress, |(angle, energy, z)| {
            let outcome = find_fixed_point(&self.params, z, &self.settings);
            let (fixed_point, no_fixed_point) = match outcome {
                Ok(Ok(fp)) => (Some(fp), None),
                Ok(Err(reason)) => (None, Some(reason)),
                Err(err) => (
                    None,
                    Some(NoFixedPoint::NoCycle {
                        reason: NoCycle::Numerical {
                            message: err.to_string(),
                        },
                    }),
                ),
            };
            GridPoint {
                angle: *angle,
                energy: *energy,
                angular_velocity: z.angular_velocity,
                fixed_point,
                no_fixed_point,
            }
        });
        Ok(results)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// `kind()` is the serialised tag (of the cycle's reason when there is no cycle).
    #[test]
    fn kinds_are_the_serialised_tags() {
        let control = Control {
            torque: 0.2,
            impulse_limit: 0.05,
        };
        let cycles = [
            NoCycle::NoLiftOff {
                normal_percussion: 0.1,
            },
            NoCycle::RollsAway { duration: 1.0 },
            NoCycle::NeverBrakes {
                stored_impulse: 0.01,
            },
            NoCycle::Numerical {
                message: "x".into(),
            },
        ];
        for reason in cycles {
            let tag = serde_json::to_value(&reason).unwrap()["kind"].clone();
            assert_eq!(tag, reason.kind());
            assert_eq!(NoFixedPoint::NoCycle { reason }.kind(), tag);
        }
        for no in [
            NoFixedPoint::NotConverged {
                residual: 1e-3,
                control,
            },
            NoFixedPoint::MovesBackward {
                stride: -0.1,
                control,
            },
        ] {
            assert_eq!(serde_json::to_value(&no).unwrap()["kind"], no.kind());
        }
        let failed = NoFixedPoint::NotConverged {
            residual: 1e-3,
            control,
        };
        assert!(failed.to_string().starts_with("solver failed: "));
    }
}
