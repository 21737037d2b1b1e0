//! A scene's run and its summary (`hopsim run --summary FILE.json`, docs/physics.md §6): the run
//! loop's [`Summary`] with the sections the scene's controller calls for — Robbit's brakes
//! and cube baselines (§5.3) for the momentum-impulse controller, the gait's period on the
//! Poincaré section of §5.4 for the pulse controller.

use crate::report::Report;
use hopsim_control::ControllerConfig;
use hopsim_model::Shape;
use hopsim_sim::Setup;
use hopsim_sim::{
    per_forward_metre, Observer, OpenSummary, Periodicity, PeriodicityOptions, PoincareSection,
    RunError, Simulation, StepView, Summary,
};
use hopsim_theory::cube::Cube;
use serde::Serialize;
use std::fmt;

/// The impulse-actuated cube of docs/physics.md §5.3 [5.21] at the robot's mean speed.
#[derive(Clone, Debug, Serialize)]
pub struct CubeBaseline {
    /// The cube's face restitution `ε`.
    pub restitution: f64,
    /// `ζ/x`, N m s of angular impulse per metre.
    #[serde(rename = "impulse_per_distance_Nms_per_m")]
    pub impulse_per_distance: f64,
}

/// Robbit's figures (docs/physics.md §5.3), over the summary window.
#[derive(Clone, Debug, Serialize)]
pub struct RobbitSummary {
    pub brakes_per_s: f64,
    /// `Σζ / distance` over the window, N m s per m.
    #[serde(rename = "impulse_per_distance_Nms_per_m")]
    pub impulse_per_distance: f64,
    /// The cube at the same speed, for `ε = 0` and the scene's `summary.cube_restitution`;
    /// empty when the main body is not a disc or the robot did not move forward.
    pub cube_baseline: Vec<CubeBaseline>,
}

/// The run summary: the run loop's figures and the scene's own sections.
#[derive(Clone, Debug, Serialize)]
pub struct RunReport {
    #[serde(flatten)]
    pub summary: Summary,
    /// Scenes with the momentum-impulse controller.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub robbit: Option<RobbitSummary>,
    /// Pulse-driven scenes: the period of the gait on the section at the start of each
    /// motor period (`PeriodicityOptions::default()`).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub gait: Option<Periodicity>,
}

/// Runs `scene` for its duration, showing every step to `observer`, and returns its summary
/// with the scene's sections.
pub fn run_scene(scene: &Setup, observer: &mut dyn Observer) -> Result<RunReport, RunError> {
    run_simulation(
        &mut Simulation::new(scene),
        scene.settings.duration,
        observer,
    )
}

/// Continues `sim` for `duration` seconds ([`hopsim_sim::run_for`]) and returns the
/// summary of that span with the scene's sections; for a simulation at its scene's
/// initial state and the scene's duration this is [`run_scene`].
pub fn run_simulation(
    sim: &mut Simulation,
    duration: f64,
    observer: &mut dyn Observer,
) -> Result<RunReport, RunError> {
    let mut section = gait_section(sim.setup(), sim.state().t);
    let summary = hopsim_sim::run_for(sim, duration, &mut (&mut section, observer))?;
    let scene = sim.setup();
    Ok(RunReport {
        robbit: RobbitSummary::of(scene, &summary),
        gait: section.map(|s| s.detect(&PeriodicityOptions::default())),
        summary,
    })
}

/// The run summary of a simulation stepped by its caller (a controller written in Python),
/// whose end is known only when it stops: shown the start ([`Simulation::start`]) and every
/// step, it gives at [`RunWatch::finish`] what [`run_simulation`] gives for a span of that
/// length (the speed window at its end, [`OpenSummary`]).
pub struct RunWatch {
    summary: OpenSummary,
    section: Option<PoincareSection>,
}

impl RunWatch {
    /// Watches `sim` from its current state.
    pub fn new(sim: &Simulation) -> Self {
        Self {
            summary: OpenSummary::new(sim),
            section: gait_section(sim.setup(), sim.state().t),
        }
    }

    /// The summary of the steps seen, with the scene's sections, at `sim`'s last step.
    pub fn finish(self, sim: &Simulation) -> Result<RunReport, RunError> {
        let summary = self.summary.finish(sim)?;
        Ok(RunReport {
            robbit: RobbitSummary::of(sim.setup(), &summary),
            gait: self
                .section
                .map(|s| s.detect(&PeriodicityOptions::default())),
            summary,
        })
    }
}

impl Observer for RunWatch {
    fn on_step(&mut self, view: &StepView<'_>) -> Result<(), RunError> {
        self.summary.on_step(view)?;
        self.section.on_step(view)
    }

    fn on_start(&mut self, view: &StepView<'_>) -> Result<(), RunError> {
        self.summary.on_start(view)?;
        self.section.on_start(view)
    }
}

/// The section at the start of every motor period from `t0`, for pulse-driven scenes.
fn gait_section(scene: &Setup, t0: f64) -> Option<PoincareSection> {
    match &scene.controller {
        ControllerConfig::Pulse(c) => {
            Some(PoincareSection::new(c.period, t0).leaving_out(scene.model.horizontal_positions()))
        }
        _ => None,
    }
}

/// The cube Robbit is compared with (docs/physics.md §5.3): the robot's mass, the flywheel's
/// parent's inertia `I_S`, and the radius `R` and eccentricity `a` of the circle that body
/// carries; `None` unless the scene runs the momentum-impulse controller on a disc.
pub fn robbit_cube(scene: &Setup) -> Option<Cube> {
    let ControllerConfig::MomentumImpulse(c) = &scene.controller else {
        return None;
    };
    let model = &scene.model;
    let disc = model.bodies()[c.flywheel].joint.as_ref()?.parent?;
    let (radius, eccentricity) = model.shapes().iter().find_map(|s| match s.shape {
        Shape::Circle { center, radius } if s.body == disc => Some((radius, center.norm())),
        _ => None,
    })?;
    Some(Cube::of_disc(
        model.total_mass(),
        model.bodies()[disc].inertia,
        radius,
        eccentricity,
        model.gravity().norm(),
    ))
}

impl RobbitSummary {
    /// Robbit's figures of a run of `scene`; `None` unless it runs the momentum-impulse
    /// controller.
    pub fn of(scene: &Setup, summary: &Summary) -> Option<Self> {
        if !matches!(scene.controller, ControllerConfig::MomentumImpulse(_)) {
            return None;
        }
        let window = &summary.window;
        let speed = summary.mean_speed_mps;
        // The cube's cost is per forward metre: none unless the robot moved forward.
        let cube_baseline = match robbit_cube(scene) {
            _ if speed <= 0.0 => Vec::new(),
            Some(cube) => [0.0, scene.settings.cube_restitution]
                .iter()
                .map(|&restitution| CubeBaseline {
                    restitution,
                    impulse_per_distance: cube.impulse_per_distance(speed, restitution),
                })
                .collect(),
            None => Vec::new(),
        };
        Some(RobbitSummary {
            brakes_per_s: window.brakes as f64 / summary.speed_window_s,
            impulse_per_distance: per_forward_metre(window.impulse, window.distance_m),
            cube_baseline,
        })
    }
}

impl Report for RunReport {
    fn text(&self) -> String {
        format!("{self}\n")
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

/// The printed summary (without a final newline).
impl fmt::Display for RunReport {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let s = &self.summary;
        let e = &s.energy.at_end;
        let w = s.speed_window_s;
        writeln!(
            f,
            "{}: {:.3} s simulated in {} steps of {:e} s",
            s.scene, s.duration_s, s.steps, s.dt_s
        )?;
        writeln!(f, "  distance           {:>10.4} m", s.distance_m)?;
        writeln!(
            f,
            "  mean speed         {:>10.4} m/s (last {w:.2} s)",
            s.mean_speed_mps
        )?;
        if s.hops > 0 {
            writeln!(
                f,
                "  hops               {:>10} ({:.4} m per hop)",
                s.hops, s.distance_per_hop_m
            )?;
        } else {
            writeln!(f, "  hops               {:>10} (no flight phase)", 0)?;
        }
        let unit = s.impulses.unit;
        if s.impulses.count > 0 {
            writeln!(
                f,
                "  actuator impulses  {:>10} totalling {:.4} {unit} ({})",
                s.impulses.count,
                s.impulses.total,
                per_metre(s.impulse_per_distance, unit, 0)
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
            e.actuator_work, e.dissipated, e.balance_error, s.energy.max_abs_balance_error
        )?;
        if s.energy.impacts_creating_energy > 0 {
            writeln!(
                f,
                "  energy created     {:.4e} J in {} impacts (tangential restitution ≠ normal \
                 with friction; docs/physics.md §4.7)",
                s.energy.created_in_impacts, s.energy.impacts_creating_energy
            )?;
        }
        writeln!(f, "  max penetration    {:>10.3e} m", s.max_penetration_m)?;
        if let Some(loop_error) = s.max_loop_error_m {
            writeln!(f, "  max loop error     {loop_error:>10.3e} m")?;
        }
        writeln!(
            f,
            "  LCP                {} solves ({} from the previous step's basis), {} failures, at most {} pivots",
            s.lcp.solves, s.lcp.warm_starts, s.lcp.failures, s.lcp.max_pivots
        )?;
        write!(
            f,
            "  wall time          {:>10.3} s ({:.0} steps/s)",
            s.wall_time_s, s.steps_per_s
        )?;
        for warning in &s.warnings {
            write!(f, "\n  warning: {warning}")?;
        }
        Ok(())
    }
}
