//! A wheel overcoming an obstacle: rolling, trivial hop, rotational hop (docs/physics.md §5.2,
//! thesis ch. 4).
//!
//! The obstacle is a thin wall (a kerb of negligible thickness) of height `h < R` standing
//! on flat ground; the wheel approaches rolling at speed `u_x` and must continue on the
//! same flat ground behind it. The **cost** of a strategy is the energy that actuators must
//! supply so that the wheel ends up in its approach state again: the absolute actuator work
//! during the manoeuvre (driving and braking both cost, nothing is regenerated, as in the
//! thesis' "braking + spin energy" [4.7]) plus the mechanical-energy deficit after the last
//! impact (a surplus is not credited). All costs are ≥ 0 and, in units of `m g R`, depend
//! only on `α = I/(mR²)`, `Fr = u_x²/(gR)` and `h/R`.
//!
//! * Rolling (centred wheel, [`rolling_cost`]): the rim hits the wall's top edge; the
//!   restitution-0, no-slip impact uses the corner Jacobian [4.12] and the collision matrix
//!   (§3). The wheel then pivots about the edge (staying on it while the contact force is
//!   compressive, else flying), and lands back on the ground with a second impact. If it
//!   lacks the energy to get over the edge, a drive lifts it to the top (the shortfall is
//!   reported as `climb_assist_j`). Cost = climb assist + kinetic-energy deficit after the
//!   landing; without assist that is the energy dissipated by the impacts.
//! * Trivial hop ([`trivial_hop_cost`]): a vertical impulse at the contact lifts the wheel
//!   by `h`; its landing dissipates the same `m g h`. Cost `m g h`.
//! * Rotational hop (eccentric wheel `a = R/2`, [`rotational_hop`]): at a rolling phase
//!   `φ₀ ∈ (−π, 0)` a rotational impulse reverses the spin so that the wheel leaves the
//!   ground and reaches `φ = 0` (foot highest) at the apex of its centre of mass; cost =
//!   braking + spin energy [4.7] plus the energy deficit after the inelastic touchdown
//!   [4.9]; `φ₀` is chosen to minimise the cost ([`rotational_hop_cost`]).
//!
//! Sign conventions as everywhere (docs/physics.md §1): `x` to the right (the direction of
//! travel), `φ` counter-clockwise, so forward rolling has `φ̇ = −u_x/R`. The derivations are
//! in `docs/analysis.md`.

use crate::error::{require_positive, AnalysisError, Result};
use crate::grid::{par_map, CellDone};
use crate::impact;
use crate::numerics::{first_sign_change, golden_section_minimum, linspace};
use crate::STANDARD_GRAVITY;
use nalgebra::{DMatrix, DVector};
use serde::Serialize;
use std::f64::consts::PI;

/// A wheel: mass, radius, inertia about its centre of mass, gravity (serialised with the
/// units in the names: `mass_kg`, …).
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct Wheel {
    /// Mass `m` [kg].
    #[serde(rename = "mass_kg")]
    pub mass: f64,
    /// Radius `R` [m].
    #[serde(rename = "radius_m")]
    pub radius: f64,
    /// Moment of inertia about the centre of mass `I` [kg m²].
    #[serde(rename = "inertia_kg_m2")]
    pub inertia: f64,
    /// Gravitational acceleration [m/s²].
    #[serde(rename = "gravity_mps2")]
    pub gravity: f64,
}

/// Allometric radius `R = 0.2063 m^0.372` [m] (m in kg) [4.17–4.20].
pub fn allometric_radius(mass: f64) -> f64 {
    0.2063 * mass.powf(0.372)
}

/// Allometric inertia `I = 0.0004726 m^1.69` [kg m²] (m in kg) [4.17–4.20].
pub fn allometric_inertia(mass: f64) -> f64 {
    0.0004726 * mass.powf(1.69)
}

impl Wheel {
    /// A wheel of unit mass and radius with inertia factor `α` (`I = α`), `g = 9.81`: the
    /// dimensionless wheel of the `α × Fr` region maps.
    pub fn dimensionless(inertia_factor: f64) -> Self {
        Wheel {
            mass: 1.0,
            radius: 1.0,
            inertia: inertia_factor,
            gravity: STANDARD_GRAVITY,
        }
    }

    /// The wheel of an animal of `mass` kg by the allometric laws [4.17–4.20].
    pub fn allometric(mass: f64) -> Self {
        Wheel {
            mass,
            radius: allometric_radius(mass),
            inertia: allometric_inertia(mass),
            gravity: STANDARD_GRAVITY,
        }
    }

    /// Inertia factor `α = I / (m R²)`.
    pub fn inertia_factor(&self) -> f64 {
        self.inertia / (self.mass * self.radius * self.radius)
    }

    /// Froude number `Fr = u² / (g R)`.
    pub fn froude(&self, speed: f64) -> f64 {
        speed * speed / (self.gravity * self.radius)
    }

    /// Speed of a Froude number: `u = sqrt(Fr g R)`.
    pub fn speed_from_froude(&self, froude: f64) -> f64 {
        (froude * self.gravity * self.radius).sqrt()
    }

    /// Weight times radius, `m g R` [J]: the unit of the dimensionless costs.
    pub fn energy_unit(&self) -> f64 {
        self.mass * self.gravity * self.radius
    }

    /// Kinetic energy of a centred wheel rolling at `speed`: `½ (m + I/R²) u²`.
    pub fn rolling_kinetic_energy(&self, speed: f64) -> f64 {
        0.5 * (self.mass + self.inertia / (self.radius * self.radius)) * speed * speed
    }

    /// Checks the parameters.
    pub fn validate(&self) -> Result<()> {
        require_positive("mass", self.mass)?;
        require_positive("radius", self.radius)?;
        require_positive("inertia", self.inertia)?;
        require_positive("gravity", self.gravity)
    }

    fn mass_matrix(&self) -> DMatrix<f64> {
        DMatrix::from_diagonal(&DVector::from_vec(vec![self.mass, self.mass, self.inertia]))
    }
}

fn validate_case(wheel: &Wheel, speed: f64, height: f64) -> Result<()> {
    wheel.validate()?;
    require_positive("speed", speed)?;
    require_positive("height", height)?;
    if height >= wheel.radius {
        return Err(AnalysisError::invalid(
            "height",
            height,
            &format!("must be below the wheel radius R = {}", wheel.radius),
        ));
    }
    Ok(())
}

/// Jacobian of a contact at a corner (the wall's top edge) for a **centred** wheel whose
/// centre is at `centre` relative to the corner (`|centre| = R`): rows are the corner
/// point's velocity `(v_x − ω r_y, v_y + ω r_x)` with `r = −centre` the corner relative to
/// the centre.
pub fn corner_jacobian_at(centre: [f64; 2]) -> DMatrix<f64> {
    DMatrix::from_row_slice(2, 3, &[1.0, 0.0, centre[1], 0.0, 1.0, -centre[0]])
}

/// The corner Jacobian [4.12] at first contact, for a wheel moving to the right that hits
/// an edge of height `h` ahead of it: `[[1, 0, R − h], [0, 1, sqrt(2Rh − h²)]]`.
///
/// docs/physics.md prints the second row with `−sqrt(2Rh − h²)`: that is the mirror image (edge
/// behind the centre, or clockwise-positive `φ`). For an approach velocity without vertical
/// component both signs give the same collision loss; the sign here is the one that makes
/// the post-impact motion a rotation about an edge ahead of the wheel.
pub fn corner_jacobian(radius: f64, height: f64) -> DMatrix<f64> {
    let reach = (2.0 * radius * height - height * height).sqrt();
    corner_jacobian_at([-reach, radius - height])
}

/// Jacobian of a centred wheel's lowest point on flat ground: `[[1, 0, R], [0, 1, 0]]`.
pub fn ground_jacobian(radius: f64) -> DMatrix<f64> {
    DMatrix::from_row_slice(2, 3, &[1.0, 0.0, radius, 0.0, 1.0, 0.0])
}

/// Energy lost when a centred wheel rolling at `speed` hits an edge of height `height`:
/// `−½ u_Rᵀ M_c u_R` with `u_R = u_x (1, 0, −1/R)` and the corner Jacobian [4.12].
pub fn corner_impact_loss(wheel: &Wheel, speed: f64, height: f64) -> Result<f64> {
    validate_case(wheel, speed, height)?;
    let u = DVector::from_vec(vec![speed, 0.0, -speed / wheel.radius]);
    Ok(-impact::impact_energy_change(
        &wheel.mass_matrix(),
        &corner_jacobian(wheel.radius, height),
        &u,
    )?)
}

/// How a rolling crossing ended.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
#[serde(rename_all = "kebab-case")]
pub enum RollingPath {
    /// Pivoted over the edge and touched the ground behind it while still on the edge.
    PivotOver,
    /// Left the edge (contact force would turn tensile) and flew to the ground.
    FlewOff,
}

impl RollingPath {
    /// Name for tables; the same as the JSON value (`pivot-over`, `flew-off`).
    pub fn name(self) -> &'static str {
        match self {
            RollingPath::PivotOver => "pivot-over",
            RollingPath::FlewOff => "flew-off",
        }
    }
}

/// The rolling strategy's energy account.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct RollingCrossing {
    /// Loss of the first impact with the edge [J].
    #[serde(rename = "corner_loss_J")]
    pub corner_loss_j: f64,
    /// Losses of all later impacts (landing behind the wall, re-contacts of the edge) [J].
    #[serde(rename = "landing_loss_J")]
    pub landing_loss_j: f64,
    /// Energy a drive had to add to get the centre over the edge [J] (0 when the wheel's
    /// own kinetic energy sufficed).
    #[serde(rename = "climb_assist_J")]
    pub climb_assist_j: f64,
    /// Number of impacts.
    pub impacts: usize,
    /// How the wheel got over.
    pub path: RollingPath,
    /// Speed after the crossing, rolling on the ground [m/s].
    pub final_speed_mps: f64,
    /// Cost: `climb_assist + max(0, T_approach − T_final)` [J]; without assist this is
    /// `corner + landing losses`.
    #[serde(rename = "cost_J")]
    pub cost_j: f64,
}

/// State of the rolling crossing, relative to the wall's top edge at the origin.
#[derive(Debug, Clone, Copy)]
enum CrossingState {
    /// On the edge: centre angle from the vertical `θ` (positive on the approach side) and
    /// body angular velocity `ω` (`θ̇ = ω`; forward is `ω < 0`).
    Pivot { theta: f64, omega: f64 },
    /// Free flight of the centre from `centre` with velocity `velocity`, spin `omega`.
    Flight {
        centre: [f64; 2],
        velocity: [f64; 2],
        omega: f64,
    },
}

const MAX_CROSSING_IMPACTS: usize = 50;

/// Rolling over the wall (see the module docs): event-driven, with closed-form pivot and
/// flight phases and collision-matrix impacts. Errors only on invalid parameters.
pub fn rolling_cost(wheel: &Wheel, speed: f64, height: f64) -> Result<RollingCrossing> {
    validate_case(wheel, speed, height)?;
    let (m, r, g) = (wheel.mass, wheel.radius, wheel.gravity);
    let mass = wheel.mass_matrix();
    let pivot_inertia = wheel.inertia + m * r * r;
    let cos_ground = (r - height) / r; // cos θ of the centre when the rim touches the ground
    let theta_ground = cos_ground.acos();
    let initial_ke = wheel.rolling_kinetic_energy(speed);

    let u0 = DVector::from_vec(vec![speed, 0.0, -speed / r]);
    let first = impact::inelastic_impact(&mass, &corner_jacobian(r, height), &u0)?;
    let mut ledger = CrossingLedger {
        initial_ke,
        corner_loss: -first.energy_change,
        landing_loss: 0.0,
        climb_assist: 0.0,
        impacts: 1,
        flew: false,
    };
    let mut state = CrossingState::Pivot {
        theta: theta_ground,
        omega: first.velocity_after[2],
    };
    loop {
        match state {
            CrossingState::Pivot { theta, omega } => {
                // A wheel turning backwards on the edge is stopped (its energy is lost to
                // the account through the final energy balance).
                let (mut theta, mut omega) = (theta, omega.min(0.0));
                // Climb to the top if on the approach side; when the wheel's kinetic energy
                // does not suffice, a drive lifts it quasi-statically to the top.
                if theta > 0.0 {
                    let needed = m * g * r * (1.0 - theta.cos());
                    let available = 0.5 * pivot_inertia * omega * omega;
                    if available < needed {
                        ledger.climb_assist += needed - available;
                        theta = 0.0;
                        omega = 0.0;
                    }
                }
                // Contact force N = m g cos θ − m R ω², ω² from energy along the pivot.
                let kappa = 2.0 * m * r * r / pivot_inertia;
                let normal = g * theta.cos() - r * omega * omega;
                if normal < 0.0 {
                    ledger.flew = true;
                    state = pivot_to_flight(r, theta, omega);
                    continue;
                }
                // Separation on the far side where N = 0: cos θ* = (R ω² + κ g cos θ) / (g (1 + κ)).
                let cos_sep = (r * omega * omega + kappa * g * theta.cos()) / (g * (1.0 + kappa));
                let omega_at = |cos_t: f64| {
                    -(omega * omega + 2.0 * m * g * r * (theta.cos() - cos_t) / pivot_inertia)
                        .max(0.0)
                        .sqrt()
                };
                if cos_sep > cos_ground {
                    ledger.flew = true;
                    let theta_sep = -cos_sep.min(1.0).acos();
                    state = pivot_to_flight(r, theta_sep, omega_at(cos_sep));
                    continue;
                }
                // Touches the ground behind the wall at θ = −θ_ground, still on the edge.
                let omega_land = omega_at(cos_ground);
                let centre = [r * theta_ground.sin(), r * cos_ground];
                let u = DVector::from_vec(vec![
                    -omega_land * centre[1],
                    omega_land * centre[0],
                    omega_land,
                ]);
                let landing = impact::inelastic_impact(&mass, &ground_jacobian(r), &u)?;
                ledger.landing_loss -= landing.energy_change;
                ledger.impacts += 1;
                return Ok(ledger.finish(wheel, &landing.velocity_after));
            }
            CrossingState::Flight {
                centre,
                velocity,
                omega,
            } => {
                let event = next_flight_event(r, height, g, centre, velocity);
                let at = |t: f64| {
                    (
                        [
                            centre[0] + velocity[0] * t,
                            centre[1] + velocity[1] * t - 0.5 * g * t * t,
                        ],
                        [velocity[0], velocity[1] - g * t],
                    )
                };
                let (c, v) = at(event.time);
                let u = DVector::from_vec(vec![v[0], v[1], omega]);
                ledger.impacts += 1;
                if event.hits_edge {
                    let hit = impact::inelastic_impact(&mass, &corner_jacobian_at(c), &u)?;
                    ledger.landing_loss -= hit.energy_change;
                    state = CrossingState::Pivot {
                        theta: (-c[0]).atan2(c[1]),
                        omega: hit.velocity_after[2],
                    };
                } else {
                    let landing = impact::inelastic_impact(&mass, &ground_jacobian(r), &u)?;
                    ledger.landing_loss -= landing.energy_change;
                    return Ok(ledger.finish(wheel, &landing.velocity_after));
                }
                if ledger.impacts > MAX_CROSSING_IMPACTS {
                    // Chattering on the edge: treat the rest as a stop on the edge.
                    return Ok(ledger.finish(wheel, &DVector::zeros(3)));
                }
            }
        }
    }
}

/// What a rolling crossing has cost so far [J], and how it went.
struct CrossingLedger {
    /// Kinetic energy on the approach.
    initial_ke: f64,
    corner_loss: f64,
    landing_loss: f64,
    climb_assist: f64,
    impacts: usize,
    flew: bool,
}

impl CrossingLedger {
    /// The crossing, ended on the ground behind the wall with `velocity_after`.
    fn finish(&self, wheel: &Wheel, velocity_after: &DVector<f64>) -> RollingCrossing {
        // Rolling on the ground: ẋ = −R φ̇; a wheel rolling backwards must be stopped too,
        // so only forward rolling counts as recovered.
        let final_speed = (-wheel.radius * velocity_after[2]).max(0.0);
        let final_ke = wheel.rolling_kinetic_energy(final_speed);
        RollingCrossing {
            corner_loss_j: self.corner_loss,
            landing_loss_j: self.landing_loss,
            climb_assist_j: self.climb_assist,
            impacts: self.impacts,
            path: if self.flew {
                RollingPath::FlewOff
            } else {
                RollingPath::PivotOver
            },
            final_speed_mps: final_speed,
            cost_j: self.climb_assist + (self.initial_ke - final_ke).max(0.0),
        }
    }
}

fn pivot_to_flight(r: f64, theta: f64, omega: f64) -> CrossingState {
    let centre = [-r * theta.sin(), r * theta.cos()];
    CrossingState::Flight {
        centre,
        velocity: [-omega * centre[1], omega * centre[0]],
        omega,
    }
}

struct FlightEvent {
    time: f64,
    hits_edge: bool,
}

/// Next event of a flight that starts on the circle `|c| = R` about the edge with a
/// tangential velocity: the edge again (`|c(t)|² = R²`), or the ground (`c_y = R − h`).
/// With `c·v = 0` and `|c| = R`, `(|c(t)|² − R²)/t² = (|v|² − g c_y) − g v_y t + ¼ g² t²`.
fn next_flight_event(r: f64, h: f64, g: f64, c: [f64; 2], v: [f64; 2]) -> FlightEvent {
    let ground_time = (v[1] + (v[1] * v[1] + 2.0 * g * (c[1] - (r - h)).max(0.0)).sqrt()) / g;
    let a0 = v[0] * v[0] + v[1] * v[1] - g * c[1];
    let b = -g * v[1];
    let c2 = 0.25 * g * g;
    let disc = b * b - 4.0 * a0 * c2;
    let tiny = 1e-9 * (r / g).sqrt();
    let mut edge_time = f64::INFINITY;
    if disc >= 0.0 {
        for root in [
            (-b - disc.sqrt()) / (2.0 * c2),
            (-b + disc.sqrt()) / (2.0 * c2),
        ] {
            if root > tiny && root < edge_time {
                edge_time = root;
            }
        }
    }
    if edge_time < ground_time {
        FlightEvent {
            time: edge_time,
            hits_edge: true,
        }
    } else {
        FlightEvent {
            time: ground_time,
            hits_edge: false,
        }
    }
}

/// Trivial hop: `m g h` [J].
pub fn trivial_hop_cost(wheel: &Wheel, height: f64) -> f64 {
    wheel.mass * wheel.gravity * height
}

/// The rotational hop's energy account.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct RotationalHop {
    /// Rolling phase `φ₀` at which the spin is reversed [rad].
    pub takeoff_angle_rad: f64,
    /// Spin after the reversal `φ̇⁺` [rad/s] (counter-clockwise).
    pub spin_rad_s: f64,
    /// Braking the rolling spin, `½ I φ̇⁻²` [J].
    #[serde(rename = "braking_J")]
    pub braking_j: f64,
    /// Spinning up, `½ I φ̇⁺²` [J].
    #[serde(rename = "spin_J")]
    pub spin_j: f64,
    /// Loss of the touchdown impact [J].
    #[serde(rename = "touchdown_loss_J")]
    pub touchdown_loss_j: f64,
    /// Energy missing after touchdown to resume the approach state [J] (≥ 0).
    #[serde(rename = "deficit_J")]
    pub deficit_j: f64,
    /// Height of the foot's lowest point above the wall at the apex [m] (≥ 0).
    pub clearance_m: f64,
    /// Cost `braking + spin + deficit` [J].
    #[serde(rename = "cost_J")]
    pub cost_j: f64,
}

/// One rotational hop with eccentricity `a = R/2` reversing its spin at the rolling phase
/// `takeoff_angle ∈ (−π, 0)`, the disc centre moving at `speed`; `None` when the foot does
/// not clear the wall at the apex. See `docs/analysis.md` for the derivation:
///
/// * rolling at `φ₀` with `φ̇⁻ = −u/R`: CoM velocity `φ̇⁻ (a cos φ₀ − R, a sin φ₀)`, so
///   `v_y = −(u/R) a sin φ₀ > 0`, height `y₀ = R − a cos φ₀`;
/// * a rotational impulse sets `φ̇⁺ = −φ₀ g / v_y` so that `φ = 0` at the apex `t_a = v_y/g`;
///   the contact opens since `γ_N⁺ = a sin φ₀ (φ̇⁻ − φ̇⁺) > 0`;
/// * clearance: `y₀ + v_y²/(2g) + a − R ≥ h`;
/// * touchdown on the ground behind the wall at the first `t > t_a` with
///   `y(t) + a cos φ(t) = R`, restitution-0 no-slip impact (collision matrix);
/// * deficit `= max(0, E_approach − E_after)` with `E = T + m g y`; kinetic energy of a
///   wheel that rolls backwards after touchdown counts as lost.
pub fn rotational_hop(
    wheel: &Wheel,
    speed: f64,
    height: f64,
    takeoff_angle: f64,
) -> Option<RotationalHop> {
    if !(takeoff_angle > -PI && takeoff_angle < 0.0) {
        return None;
    }
    let (m, r, g, inertia) = (wheel.mass, wheel.radius, wheel.gravity, wheel.inertia);
    let a = 0.5 * r;
    let phi0 = takeoff_angle;
    let w_minus = -speed / r;
    let y0 = r - a * phi0.cos();
    let vx = w_minus * (a * phi0.cos() - r);
    let vy = w_minus * a * phi0.sin();
    if vy.is_nan() || vy <= 0.0 {
        return None;
    }
    let t_apex = vy / g;
    let w_plus = -phi0 / t_apex;
    let y_apex = y0 + vy * vy / (2.0 * g);
    let clearance = y_apex + a - r - height;
    if clearance.is_nan() || clearance < 0.0 {
        return None;
    }
    let y_at = |t: f64| y0 + vy * t - 0.5 * g * t * t;
    let gap = |t: f64| y_at(t) + a * (phi0 + w_plus * t).cos() - r;
    // The gap is ≥ h at the apex; the ground is reached before y + a = R.
    let t_bound = (vy + (vy * vy + 2.0 * g * (y0 + a - r)).sqrt()) / g;
    let steps = ((w_plus.abs() * (t_bound - t_apex) / 0.05).ceil() as usize).clamp(64, 100_000);
    let t_td = first_sign_change(gap, t_apex, t_bound * (1.0 + 1e-12), steps, 1e-14 * t_bound)?;
    let phi_td = phi0 + w_plus * t_td;
    let u = DVector::from_vec(vec![vx, vy - g * t_td, w_plus]);
    let jac = DMatrix::from_row_slice(
        2,
        3,
        &[1.0, 0.0, r - a * phi_td.cos(), 0.0, 1.0, -a * phi_td.sin()],
    );
    let hit = impact::inelastic_impact(&wheel.mass_matrix(), &jac, &u).ok()?;
    let u_after = &hit.velocity_after;
    let y_td = r - a * phi_td.cos();
    let kinetic_after = impact::kinetic_energy(&wheel.mass_matrix(), u_after);
    let rolls_forward = u_after[2] < 0.0;
    let energy_after = m * g * y_td + if rolls_forward { kinetic_after } else { 0.0 };
    let rolling_inertia = m * (r * r + a * a - 2.0 * r * a * phi0.cos()) + inertia;
    let energy_approach = 0.5 * rolling_inertia * w_minus * w_minus + m * g * y0;
    let braking = 0.5 * inertia * w_minus * w_minus;
    let spin = 0.5 * inertia * w_plus * w_plus;
    let deficit = (energy_approach - energy_after).max(0.0);
    Some(RotationalHop {
        takeoff_angle_rad: phi0,
        spin_rad_s: w_plus,
        braking_j: braking,
        spin_j: spin,
        touchdown_loss_j: -hit.energy_change,
        deficit_j: deficit,
        clearance_m: clearance,
        cost_j: braking + spin + deficit,
    })
}

/// Number of take-off phases scanned before the golden-section refinement.
const PHASE_SCAN: usize = 121;

/// The cheapest rotational hop over the take-off phase `φ₀ ∈ (−π, 0)`: a scan of 121
/// phases, then golden-section refinement around the best; `None` when no phase clears
/// the wall.
pub fn rotational_hop_cost(
    wheel: &Wheel,
    speed: f64,
    height: f64,
) -> Result<Option<RotationalHop>> {
    validate_case(wheel, speed, height)?;
    let margin = 1e-3;
    let phases = linspace(-PI + margin, -margin, PHASE_SCAN);
    let cost = |phi: f64| {
        rotational_hop(wheel, speed, height, phi).map_or(f64::INFINITY, |hop| hop.cost_j)
    };
    let (best_index, best_cost) =
        phases
            .iter()
            .map(|&phi| cost(phi))
            .enumerate()
            .fold(
                (0, f64::INFINITY),
                |best, (i, c)| if c < best.1 { (i, c) } else { best },
            );
    if !best_cost.is_finite() {
        return Ok(None);
    }
    let lo = phases[best_index.saturating_sub(1)];
    let hi = phases[(best_index + 1).min(PHASE_SCAN - 1)];
    let (phi, refined) = golden_section_minimum(cost, lo, hi, 40);
    let phi = if refined <= best_cost {
        phi
    } else {
        phases[best_index]
    };
    Ok(rotational_hop(wheel, speed, height, phi))
}

/// A strategy to get over the wall.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
#[serde(rename_all = "kebab-case")]
pub enum Strategy {
    /// Roll over it.
    Rolling,
    /// Hop straight up by `h`.
    TrivialHop,
    /// Eccentric wheel, spin reversal.
    RotationalHop,
}

impl Strategy {
    /// All strategies, in map-legend order.
    pub const ALL: [Strategy; 3] = [
        Strategy::Rolling,
        Strategy::TrivialHop,
        Strategy::RotationalHop,
    ];

    /// Name for tables and CSV.
    pub fn name(self) -> &'static str {
        match self {
            Strategy::Rolling => "rolling",
            Strategy::TrivialHop => "trivial-hop",
            Strategy::RotationalHop => "rotational-hop",
        }
    }

    /// Index into [`Strategy::ALL`].
    pub fn index(self) -> usize {
        Strategy::ALL.iter().position(|&s| s == self).unwrap_or(0)
    }
}

/// The three strategies at one operating point.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct StrategyComparison {
    /// Approach speed [m/s].
    pub speed_mps: f64,
    /// Wall height [m].
    pub height_m: f64,
    /// `Fr = u²/(gR)`.
    pub froude: f64,
    /// `α = I/(mR²)`.
    pub inertia_factor: f64,
    /// `h/R`.
    pub height_ratio: f64,
    /// `m g R` [J], the unit of the `*_per_mgr` costs.
    #[serde(rename = "energy_unit_J")]
    pub energy_unit_j: f64,
    /// Rolling.
    pub rolling: RollingCrossing,
    /// Trivial hop cost [J].
    #[serde(rename = "trivial_hop_J")]
    pub trivial_hop_j: f64,
    /// Rotational hop (None when it cannot clear the wall).
    pub rotational_hop: Option<RotationalHop>,
    /// The cheapest strategy.
    pub cheapest: Strategy,
}

/// The cost of each of the three strategies for `wheel` at `speed` over a wall of `height`,
/// and the cheapest (docs/physics.md §5.2).
pub fn compare_strategies(wheel: &Wheel, speed: f64, height: f64) -> Result<StrategyComparison> {
    let rolling = rolling_cost(wheel, speed, height)?;
    let trivial = trivial_hop_cost(wheel, height);
    let rotational = rotational_hop_cost(wheel, speed, height)?;
    let mut cheapest = (Strategy::Rolling, rolling.cost_j);
    if trivial < cheapest.1 {
        cheapest = (Strategy::TrivialHop, trivial);
    }
    if let Some(hop) = &rotational {
        if hop.cost_j < cheapest.1 {
            cheapest = (Strategy::RotationalHop, hop.cost_j);
        }
    }
    Ok(StrategyComparison {
        speed_mps: speed,
        height_m: height,
        froude: wheel.froude(speed),
        inertia_factor: wheel.inertia_factor(),
        height_ratio: height / wheel.radius,
        energy_unit_j: wheel.energy_unit(),
        rolling,
        trivial_hop_j: trivial,
        rotational_hop: rotational,
        cheapest: cheapest.0,
    })
}

/// One cell of a region map: the three costs in units of `m g R` and the cheapest.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct RegionCell {
    /// x-axis value (α, or body mass in kg).
    pub x: f64,
    /// y-axis value (Fr, or speed in m/s).
    pub y: f64,
    /// Rolling cost / (m g R).
    pub rolling: f64,
    /// Trivial hop cost / (m g R) (= h/R).
    pub trivial_hop: f64,
    /// Rotational hop cost / (m g R) (None when it cannot clear the wall).
    pub rotational_hop: Option<f64>,
    /// Cheapest strategy.
    pub cheapest: Strategy,
}

fn region_cell(wheel: &Wheel, speed: f64, height: f64, x: f64, y: f64) -> Result<RegionCell> {
    let cmp = compare_strategies(wheel, speed, height)?;
    let unit = wheel.energy_unit();
    Ok(RegionCell {
        x,
        y,
        rolling: cmp.rolling.cost_j / unit,
        trivial_hop: cmp.trivial_hop_j / unit,
        rotational_hop: cmp.rotational_hop.map(|h| h.cost_j / unit),
        cheapest: cmp.cheapest,
    })
}

/// Region map over `α × Fr` (dimensionless wheel, `m = R = 1`) for one `h/R`; cells in
/// row-major order (`Fr` outer, `α` inner), computed in parallel.
pub fn region_map_inertia_froude(
    height_ratio: f64,
    inertia_factors: &[f64],
    froudes: &[f64],
    progress: CellDone<'_>,
) -> Result<Vec<RegionCell>> {
    region_map(
        height_ratio,
        ("inertia-factor", inertia_factors),
        ("froude", froudes),
        progress,
        |alpha, fr| {
            let wheel = Wheel::dimensionless(alpha);
            region_cell(&wheel, wheel.speed_from_froude(fr), height_ratio, alpha, fr)
        },
    )
}

/// Region map over body mass × speed with the allometric wheel ([`Wheel::allometric`]) and
/// a wall of `height_ratio · R(m)`; cells in row-major order (speed outer, mass inner).
pub fn region_map_allometric(
    height_ratio: f64,
    masses: &[f64],
    speeds: &[f64],
    progress: CellDone<'_>,
) -> Result<Vec<RegionCell>> {
    region_map(
        height_ratio,
        ("mass", masses),
        ("speed", speeds),
        progress,
        |mass, speed| {
            let wheel = Wheel::allometric(mass);
            region_cell(&wheel, speed, height_ratio * wheel.radius, mass, speed)
        },
    )
}

/// The cells `cell(x, y)` of a region map in row-major order (`y` outer, `x` inner),
/// computed in parallel, after checking that every axis value is positive (named by its
/// axis) and that `height_ratio` is a valid wall.
fn region_map(
    height_ratio: f64,
    (x_name, xs): (&str, &[f64]),
    (y_name, ys): (&str, &[f64]),
    progress: CellDone<'_>,
    cell: impl Fn(f64, f64) -> Result<RegionCell> + Sync,
) -> Result<Vec<RegionCell>> {
    let mut points = Vec::with_capacity(xs.len() * ys.len());
    for &y in ys {
        for &x in xs {
            require_positive(x_name, x)?;
            require_positive(y_name, y)?;
            points.push((x, y));
        }
    }
    validate_case(&Wheel::dimensionless(1.0), 1.0, height_ratio)?;
    par_map(&points, progress, |&(x, y)| cell(x, y))
        .into_iter()
        .collect()
}
