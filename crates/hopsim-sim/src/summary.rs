//! The run summary of physics.md §6: distance, speed, hops, impulses, energy, LCP.

use crate::simulation::RunError;
use crate::{Observer, Simulation, StepView};
use hopsim_control::ControllerConfig;
use hopsim_model::Shape;
use hopsim_record::EventKind;
use hopsim_scene::Scene;
use serde::Serialize;

/// Impulses applied by actuators (brakes, applied impulses).
#[derive(Clone, Debug, Default, Serialize)]
pub struct ImpulseSummary {
    pub count: u64,
    #[serde(rename = "total_Ns")]
    pub total_ns: f64,
}

/// Energies at the end of the run and the account's error, J.
#[derive(Clone, Debug, Default, Serialize)]
pub struct EnergySummary {
    pub kinetic: f64,
    pub potential: f64,
    pub spring: f64,
    pub actuator_work: f64,
    pub dissipated: f64,
    pub balance_error: f64,
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
/// `ζ/x = g (m l² + I_S)(1 - ε) / (2 l u_x sin α)`, `l = 2(R - a)`, `α = π/4`.
#[derive(Clone, Debug, Serialize)]
pub struct CubeBaseline {
    pub restitution: f64,
    #[serde(rename = "impulse_per_distance_Ns_per_m")]
    pub impulse_per_distance: f64,
}

impl CubeBaseline {
    /// The baseline for a robot of `mass`, body inertia `inertia`, disc radius `radius`
    /// and eccentricity `eccentricity` moving at `speed`.
    pub fn new(mass: f64, inertia: f64, radius: f64, eccentricity: f64, gravity: f64, speed: f64, restitution: f64) -> Self {
        let l = 2.0 * (radius - eccentricity);
        let alpha = std::f64::consts::FRAC_PI_4;
        Self {
            restitution,
            impulse_per_distance: gravity * (mass * l * l + inertia) * (1.0 - restitution)
                / (2.0 * l * speed * alpha.sin()),
        }
    }
}

/// Robbit's extra figures (physics.md §5.3), over the summary window.
#[derive(Clone, Debug, Serialize)]
pub struct RobbitSummary {
    pub brakes_per_s: f64,
    #[serde(rename = "impulse_per_distance_Ns_per_m")]
    pub impulse_per_distance: f64,
    pub cube_baseline: Vec<CubeBaseline>,
}

/// The end-of-run summary (`--summary FILE.json`).
#[derive(Clone, Debug, Serialize)]
pub struct Summary {
    pub scene: String,
    pub duration_s: f64,
    pub dt_s: f64,
    pub steps: u64,
    pub distance_m: f64,
    pub mean_speed_mps: f64,
    pub speed_window_s: f64,
    pub hops: u64,
    pub impulses: ImpulseSummary,
    #[serde(rename = "impulse_per_distance_Ns_per_m")]
    pub impulse_per_distance: f64,
    pub energy: EnergySummary,
    pub max_penetration_m: f64,
    pub lcp: LcpSummary,
    pub wall_time_s: f64,
    pub steps_per_s: f64,
    #[serde(skip_serializing_if = "Option::is_none")]
    pub robbit: Option<RobbitSummary>,
}

/// Restitution of the second cube baseline line (the first is `ε = 0`).
pub const CUBE_RESTITUTION: f64 = 0.5;

/// Collects the summary while the run goes on.
pub(crate) struct SummaryCollector {
    title: String,
    window_start: f64,
    x_window: Option<f64>,
    impulses: ImpulseSummary,
    window_impulse: f64,
    window_brakes: u64,
    max_penetration: f64,
    max_balance_error: f64,
}

impl SummaryCollector {
    pub(crate) fn new(scene: &Scene, duration: f64) -> Self {
        Self {
            title: scene.title.clone(),
            window_start: duration * (1.0 - scene.settings.speed_window),
            x_window: (scene.settings.speed_window >= 1.0).then(|| com_x_initial(scene)),
            impulses: ImpulseSummary::default(),
            window_impulse: 0.0,
            window_brakes: 0,
            max_penetration: 0.0,
            max_balance_error: 0.0,
        }
    }

    pub(crate) fn finish(self, sim: &Simulation<'_>, wall_time: f64, steps: u64) -> Summary {
        let scene = sim.scene();
        let state = sim.state();
        let record = sim.stepper().record();
        let duration = state.t - scene.initial.t;
        let window = duration - self.window_start;
        let x_end = scene.model.center_of_mass(sim.stepper().workspace()).x;
        let x0 = com_x_initial(scene);
        let distance = x_end - x0;
        let window_distance = x_end - self.x_window.unwrap_or(x0);
        let mean_speed = window_distance / window;
        let lcp = sim.stepper().lcp_stats();
        let e = record.energy;
        let robbit = match &scene.controller {
            ControllerConfig::MomentumImpulse(c) => Some(robbit_summary(
                scene,
                c.flywheel,
                mean_speed,
                self.window_brakes as f64 / window,
                self.window_impulse / window_distance,
            )),
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
            impulse_per_distance: self.impulses.total_ns / distance,
            impulses: self.impulses,
            energy: EnergySummary {
                kinetic: e.kinetic,
                potential: e.potential,
                spring: e.spring,
                actuator_work: e.actuator_work,
                dissipated: e.dissipated(),
                balance_error: e.balance_error(),
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
        }
    }
}

fn com_x_initial(scene: &Scene) -> f64 {
    let mut ws = hopsim_model::Workspace::new(&scene.model);
    ws.update(&scene.model, &scene.initial.q, &scene.initial.u);
    scene.model.center_of_mass(&ws).x
}

fn robbit_summary(scene: &Scene, flywheel: usize, speed: f64, brakes_per_s: f64, per_distance: f64) -> RobbitSummary {
    let model = &scene.model;
    let disc = model.bodies[flywheel].joint.as_ref().map_or(0, |j| j.parent);
    // The disc's radius and eccentricity from its circle shape (physics.md §2).
    let (radius, eccentricity) = model
        .shapes
        .iter()
        .find_map(|s| match s.shape {
            Shape::Circle { center, radius } if s.body == disc => Some((radius, center.norm())),
            _ => None,
        })
        .unwrap_or((f64::NAN, f64::NAN));
    let gravity = model.gravity.norm();
    let baseline = |eps| {
        CubeBaseline::new(model.total_mass(), model.bodies[disc].inertia, radius, eccentricity, gravity, speed, eps)
    };
    RobbitSummary {
        brakes_per_s,
        impulse_per_distance: per_distance,
        cube_baseline: vec![baseline(0.0), baseline(CUBE_RESTITUTION)],
    }
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
                    if in_window {
                        self.window_brakes += 1;
                    }
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
        self.max_balance_error = self
            .max_balance_error
            .max(view.record.energy.balance_error().abs());
        Ok(())
    }
}

impl std::fmt::Display for Summary {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        let e = &self.energy;
        writeln!(f, "{}: {:.3} s simulated in {} steps of {:e} s", self.scene, self.duration_s, self.steps, self.dt_s)?;
        writeln!(f, "  distance          {:>12.4} m", self.distance_m)?;
        writeln!(f, "  mean speed        {:>12.4} m/s (last {:.2} s)", self.mean_speed_mps, self.speed_window_s)?;
        writeln!(f, "  hops              {:>12}", self.hops)?;
        writeln!(f, "  actuator impulses {:>12} totalling {:.4} N s ({:.4} N s/m)", self.impulses.count, self.impulses.total_ns, self.impulse_per_distance)?;
        if let Some(r) = &self.robbit {
            writeln!(f, "  brakes            {:>12.3} per s (last {:.2} s)", r.brakes_per_s, self.speed_window_s)?;
            writeln!(f, "  impulse/distance  {:>12.4} N s/m (last {:.2} s)", r.impulse_per_distance, self.speed_window_s)?;
            for c in &r.cube_baseline {
                writeln!(f, "  cube, ε = {:<4}    {:>12.4} N s/m at the same speed", c.restitution, c.impulse_per_distance)?;
            }
        }
        writeln!(f, "  energy [J]        kinetic {:.4}, potential {:.4}, spring {:.4}", e.kinetic, e.potential, e.spring)?;
        writeln!(f, "                    actuator work {:.4}, dissipated {:.4}, balance error {:.2e} (max {:.2e})", e.actuator_work, e.dissipated, e.balance_error, e.max_abs_balance_error)?;
        writeln!(f, "  max penetration   {:>12.3e} m", self.max_penetration_m)?;
        writeln!(f, "  LCP               {} solves, {} failures, at most {} pivots", self.lcp.solves, self.lcp.failures, self.lcp.max_pivots)?;
        write!(f, "  wall time         {:>12.3} s ({:.0} steps/s)", self.wall_time_s, self.steps_per_s)
    }
}
