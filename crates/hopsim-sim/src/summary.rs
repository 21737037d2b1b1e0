//! The run summary of physics.md §6: distance, speed, hops, impulses, energy, LCP.

use crate::simulation::RunError;
use crate::{Observer, Periodicity, PeriodicityOptions, PoincareSection, Simulation, StepView};
use hopsim_control::ControllerConfig;
use hopsim_model::{Model, Shape, Workspace};
use hopsim_record::{EnergySample, EventKind};
use hopsim_scene::Scene;
use serde::Serialize;

/// Impulses applied by actuators: the brakes' angular impulses `ζ` (physics.md §5.3).
///
/// The JSON keys `total_Ns` and `impulse_per_distance_Ns_per_m` are the run-summary
/// contract's names; the values are in [`IMPULSE_UNIT`] (and per metre), given as `unit`.
#[derive(Clone, Debug, Default, Serialize)]
pub struct ImpulseSummary {
    pub count: u64,
    #[serde(rename = "total_Ns")]
    pub total_ns: f64,
    pub unit: &'static str,
}

/// Unit of the actuator impulses a scene can produce: brakes transfer angular impulse.
pub const IMPULSE_UNIT: &str = "N m s";

/// Energies at the end of the run and the account's error, J.
#[derive(Clone, Debug, Default, Serialize)]
pub struct EnergySummary {
    /// The ledger at the last step.
    #[serde(flatten)]
    pub at_end: EnergySample,
    /// The largest `|balance error|` over all steps.
    pub max_abs_balance_error: f64,
}

/// LCP statistics.
#[derive(Clone, Debug, Default, Serialize)]
pub struct LcpSummary {
    pub solves: u64,
    pub failures: u64,
    pub max_pivots: usize,
}

/// The impulse-actuated cube of physics.md §5.3 [5.21] at the robot's mean speed:
/// `ζ/x = g (m l² + I_S)(1 − ε) / (2 l u_x sin α)`, `l = 2(R − a)`, `α = π/4`, in N m s
/// of angular impulse per metre.
#[derive(Clone, Debug, Serialize)]
pub struct CubeBaseline {
    pub restitution: f64,
    #[serde(rename = "impulse_per_distance_Nms_per_m")]
    pub impulse_per_distance: f64,
}

impl CubeBaseline {
    /// The baseline for a robot of `mass` whose main body has inertia `inertia`, on a disc
    /// of `radius` with eccentricity `eccentricity`, moving at `speed` (m/s).
    pub fn new(
        mass: f64,
        inertia: f64,
        (radius, eccentricity): (f64, f64),
        gravity: f64,
        speed: f64,
        restitution: f64,
    ) -> Self {
        let l = 2.0 * (radius - eccentricity);
        let alpha = std::f64::consts::FRAC_PI_4;
        Self {
            restitution,
            impulse_per_distance: gravity * (mass * l * l + inertia) * (1.0 - restitution)
                / (2.0 * l * speed * alpha.sin()),
        }
    }

    /// The baseline for a Robbit scene: the robot's mass, the flywheel's parent's inertia
    /// `I_S` and the radius `R` and eccentricity `a` of the circle it carries (physics.md §2);
    /// `None` unless the scene runs the momentum-impulse controller on a disc.
    pub fn for_scene(scene: &Scene, speed: f64, restitution: f64) -> Option<Self> {
        let ControllerConfig::MomentumImpulse(c) = &scene.controller else {
            return None;
        };
        let model = &scene.model;
        let disc = model.bodies[c.flywheel].joint.as_ref()?.parent;
        let geometry = model.shapes.iter().find_map(|s| match s.shape {
            Shape::Circle { center, radius } if s.body == disc => Some((radius, center.norm())),
            _ => None,
        })?;
        let (mass, inertia) = (model.total_mass(), model.bodies[disc].inertia);
        Some(Self::new(
            mass,
            inertia,
            geometry,
            model.gravity.norm(),
            speed,
            restitution,
        ))
    }
}

/// Robbit's figures (physics.md §5.3), over the summary window.
#[derive(Clone, Debug, Serialize)]
pub struct RobbitSummary {
    pub brakes_per_s: f64,
    /// `Σζ / distance` over the window, N m s per m.
    #[serde(rename = "impulse_per_distance_Nms_per_m")]
    pub impulse_per_distance: f64,
    /// The cube at the same speed, for `ε = 0` and the scene's `summary.cube_restitution`;
    /// empty when the main body is not a disc.
    pub cube_baseline: Vec<CubeBaseline>,
}

/// The end-of-run summary (`--summary FILE.json`).
#[derive(Clone, Debug, Serialize)]
pub struct Summary {
    pub scene: String,
    pub duration_s: f64,
    pub dt_s: f64,
    pub steps: u64,
    /// Forward displacement of the robot's centre of mass over the whole run.
    pub distance_m: f64,
    /// Mean forward speed of the centre of mass over the last `speed_window_s`.
    pub mean_speed_mps: f64,
    pub speed_window_s: f64,
    /// Flight phases (every enabled shape clear of the terrain by `HOP_CLEARANCE`).
    pub hops: u64,
    /// `distance_m / hops` (null without hops).
    pub distance_per_hop_m: f64,
    pub impulses: ImpulseSummary,
    /// All actuator impulses over the whole distance.
    #[serde(rename = "impulse_per_distance_Ns_per_m")]
    pub impulse_per_distance: f64,
    pub energy: EnergySummary,
    pub max_penetration_m: f64,
    pub lcp: LcpSummary,
    pub wall_time_s: f64,
    pub steps_per_s: f64,
    #[serde(skip_serializing_if = "Option::is_none")]
    pub robbit: Option<RobbitSummary>,
    /// Pulse-driven scenes: the period of the gait on the section at the start of each
    /// motor period (`PeriodicityOptions::default()`).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub gait: Option<Periodicity>,
}

/// Collects the summary while the run goes on.
pub(crate) struct SummaryCollector {
    title: String,
    window_start: f64,
    x_start: f64,
    x_window: Option<f64>,
    impulses: ImpulseSummary,
    window_impulse: f64,
    window_brakes: u64,
    max_penetration: f64,
    max_balance_error: f64,
    /// The state at the start of every motor period (pulse controller only).
    section: Option<PoincareSection>,
}

impl SummaryCollector {
    pub(crate) fn new(scene: &Scene) -> Self {
        let s = &scene.settings;
        let x_start = com_x(&scene.model, &scene.initial);
        let window_start = s.duration - s.speed_window;
        Self {
            title: scene.title.clone(),
            window_start,
            x_start,
            x_window: (window_start <= 0.0).then_some(x_start),
            impulses: ImpulseSummary {
                unit: IMPULSE_UNIT,
                ..ImpulseSummary::default()
            },
            window_impulse: 0.0,
            window_brakes: 0,
            max_penetration: 0.0,
            max_balance_error: 0.0,
            section: match &scene.controller {
                ControllerConfig::Pulse(c) => {
                    let mut section = PoincareSection::new(c.period, scene.initial.t);
                    let (q, u) = (&scene.initial.q, &scene.initial.u);
                    section.push(scene.initial.t, q.as_slice(), u.as_slice());
                    Some(section)
                }
                _ => None,
            },
        }
    }

    pub(crate) fn finish(self, sim: &Simulation<'_>, wall_time: f64, steps: u64) -> Summary {
        let scene = sim.scene();
        let record = sim.stepper().record();
        let duration = sim.state().t - scene.initial.t;
        let window = duration - self.window_start.max(0.0);
        let x_end = scene.model.center_of_mass(sim.stepper().workspace()).x;
        let distance = x_end - self.x_start;
        let window_distance = x_end - self.x_window.unwrap_or(x_end);
        let mean_speed = window_distance / window;
        let lcp = sim.stepper().lcp_stats();
        let e = record.energy;
        let robbit = match &scene.controller {
            ControllerConfig::MomentumImpulse(_) => Some(RobbitSummary {
                brakes_per_s: self.window_brakes as f64 / window,
                impulse_per_distance: per_forward_metre(self.window_impulse, window_distance),
                cube_baseline: cube_baselines(scene, mean_speed),
            }),
            _ => None,
        };
        Summary {
            scene: self.title,
            duration_s: duration,
            dt_s: scene.settings.dt,
            steps,
            distance_m: distance,
            mean_speed_mps: mean_speed,
            speed_window_s: window,
            hops: sim.hops(),
            distance_per_hop_m: if sim.hops() > 0 {
                distance / sim.hops() as f64
            } else {
                f64::NAN
            },
            impulse_per_distance: per_forward_metre(self.impulses.total_ns, distance),
            impulses: self.impulses,
            energy: EnergySummary {
                at_end: EnergySample::from_ledger(&e),
                max_abs_balance_error: self.max_balance_error,
            },
            max_penetration_m: self.max_penetration,
            lcp: LcpSummary {
                solves: lcp.solves,
                failures: lcp.failures,
                max_pivots: lcp.max_pivots,
            },
            wall_time_s: wall_time,
            steps_per_s: steps as f64 / wall_time.max(1e-9),
            robbit,
            gait: self
                .section
                .map(|s| s.detect(&PeriodicityOptions::default())),
        }
    }
}

/// The robot's centre-of-mass abscissa in `state`.
fn com_x(model: &Model, state: &hopsim_step::State) -> f64 {
    let mut ws = Workspace::new(model);
    ws.update(model, &state.q, &state.u);
    model.center_of_mass(&ws).x
}

/// `total / distance`, NaN (JSON `null`) unless the robot moved forward.
fn per_forward_metre(total: f64, distance: f64) -> f64 {
    if distance > 0.0 {
        total / distance
    } else {
        f64::NAN
    }
}

/// Cube baselines for `ε = 0` and `summary.cube_restitution` (empty when the main body
/// is not a disc or the robot did not move forward: the cube's cost is per forward metre).
fn cube_baselines(scene: &Scene, speed: f64) -> Vec<CubeBaseline> {
    if speed <= 0.0 {
        return Vec::new();
    }
    [0.0, scene.settings.cube_restitution]
        .iter()
        .filter_map(|&eps| CubeBaseline::for_scene(scene, speed, eps))
        .collect()
}

impl Observer for SummaryCollector {
    fn on_step(&mut self, view: &StepView<'_>) -> Result<(), RunError> {
        let t = view.state.t;
        if self.x_window.is_none() && t >= self.window_start {
            self.x_window = Some(view.model.center_of_mass(view.kinematics).x);
        }
        let in_window = t > self.window_start;
        for ev in view.events {
            let magnitude = match ev.kind {
                EventKind::Brake { impulse } => {
                    self.window_brakes += u64::from(in_window);
                    impulse
                }
                EventKind::AppliedImpulse { magnitude } => magnitude,
                _ => continue,
            };
            self.impulses.count += 1;
            self.impulses.total_ns += magnitude;
            if in_window {
                self.window_impulse += magnitude;
            }
        }
        self.max_penetration = self.max_penetration.max(view.record.max_penetration);
        let balance = view.record.energy.balance_error().abs();
        self.max_balance_error = self.max_balance_error.max(balance);
        if let Some(section) = &mut self.section {
            section.push(t, view.state.q.as_slice(), view.state.u.as_slice());
        }
        Ok(())
    }
}

/// `x` rounded to zero below the 4 decimals printed, so that round-off never shows as
/// `-0.0000`.
fn shown(x: f64) -> f64 {
    if x.abs() < 5e-5 {
        0.0
    } else {
        x
    }
}

/// `value` in `unit` per metre (the number right-aligned in `width`), or a dash where the
/// robot made no forward distance.
fn per_metre(value: f64, unit: &str, width: usize) -> String {
    if value.is_finite() {
        format!("{value:>width$.4} {unit}/m")
    } else {
        format!("{:>width$} (no forward distance)", "–")
    }
}

impl std::fmt::Display for Summary {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        let e = &self.energy.at_end;
        let w = self.speed_window_s;
        writeln!(
            f,
            "{}: {:.3} s simulated in {} steps of {:e} s",
            self.scene, self.duration_s, self.steps, self.dt_s
        )?;
        writeln!(f, "  distance           {:>10.4} m", self.distance_m)?;
        writeln!(
            f,
            "  mean speed         {:>10.4} m/s (last {w:.2} s)",
            self.mean_speed_mps
        )?;
        if self.hops > 0 {
            writeln!(
                f,
                "  hops               {:>10} ({:.4} m per hop)",
                self.hops, self.distance_per_hop_m
            )?;
        } else {
            writeln!(f, "  hops               {:>10} (no flight phase)", 0)?;
        }
        let unit = self.impulses.unit;
        if self.impulses.count > 0 {
            writeln!(
                f,
                "  actuator impulses  {:>10} totalling {:.4} {unit} ({})",
                self.impulses.count,
                self.impulses.total_ns,
                per_metre(self.impulse_per_distance, unit, 0)
            )?;
        }
        if let Some(r) = &self.robbit {
            writeln!(
                f,
                "  brakes             {:>10.3} per s (last {w:.2} s)",
                r.brakes_per_s
            )?;
            writeln!(
                f,
                "  impulse/distance   {} (last {w:.2} s)",
                per_metre(r.impulse_per_distance, unit, 10)
            )?;
            for c in &r.cube_baseline {
                writeln!(
                    f,
                    "  cube, ε = {:<4}     {} at the same speed",
                    c.restitution,
                    per_metre(c.impulse_per_distance, unit, 10)
                )?;
            }
            if r.cube_baseline.is_empty() {
                writeln!(
                    f,
                    "  cube baseline      none: needs a disc body (l = 2(R − a), §5.3) moving forward"
                )?;
            }
        }
        if let Some(g) = &self.gait {
            writeln!(f, "  gait               {g}")?;
        }
        writeln!(
            f,
            "  energy             kinetic {:.4} J, potential {:.4} J, spring {:.4} J",
            shown(e.kinetic),
            shown(e.potential),
            shown(e.spring)
        )?;
        writeln!(
            f,
            "                     actuator work {:.4} J, dissipated {:.4} J, balance error {:.2e} J (max {:.2e} J)",
            e.actuator_work, e.dissipated, e.balance_error, self.energy.max_abs_balance_error
        )?;
        writeln!(
            f,
            "  max penetration    {:>10.3e} m",
            self.max_penetration_m
        )?;
        writeln!(
            f,
            "  LCP                {} solves, {} failures, at most {} pivots",
            self.lcp.solves, self.lcp.failures, self.lcp.max_pivots
        )?;
        write!(
            f,
            "  wall time          {:>10.3} s ({:.0} steps/s)",
            self.wall_time_s, self.steps_per_s
        )
    }
}
