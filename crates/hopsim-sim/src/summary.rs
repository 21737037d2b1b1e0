//! The run summary of docs/physics.md §6 (distance, speed, hops, impulses, energy, LCP), made of
//! what an observer sees of every step.

use crate::Setup;
use crate::{Observer, RunError, StepView};
use hopsim_model::{Kinematics, Model};
use hopsim_record::{EnergySample, EventKind};
use hopsim_step::{LcpStats, State};
use serde::Serialize;

/// Impulses applied by actuators: the brakes' angular impulses `ζ` (docs/physics.md §5.3).
///
/// The JSON keys `total_Ns` and `impulse_per_distance_Ns_per_m` are the run-summary
/// contract's names; the values are in [`IMPULSE_UNIT`] (and per metre), given as `unit`.
#[derive(Clone, Debug, Default, Serialize)]
pub struct ImpulseSummary {
    pub count: u64,
    /// Sum of the impulses' magnitudes, in `unit` (N m s for brakes).
    #[serde(rename = "total_Ns")]
    pub total: f64,
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
    /// When the largest `|balance error|` was reached, s.
    pub max_abs_balance_error_at_s: f64,
    /// The run's energy scale (the largest [`hopsim_step::EnergyLedger::scale`] of any step), J: what the
    /// balance error is measured against.
    #[serde(rename = "scale_J")]
    pub scale: f64,
    /// Impacts whose percussions added energy (`energy_created` events, docs/physics.md
    /// §4.7) and the energy they added, J.
    pub impacts_creating_energy: u64,
    #[serde(rename = "created_in_impacts_J")]
    pub created_in_impacts: f64,
}

/// LCP statistics.
#[derive(Clone, Debug, Default, Serialize)]
pub struct LcpSummary {
    pub solves: u64,
    pub failures: u64,
    pub max_pivots: usize,
    /// Solves answered by the previous step's basis, without pivots (docs/lcp.md).
    pub warm_starts: u64,
}

/// Totals over the speed window (the last `speed_window_s`), from which scene-specific
/// figures are made (Robbit's brakes per second and `Σζ / distance`, docs/physics.md §5.3). Not
/// part of the summary's JSON.
#[derive(Clone, Debug, Default)]
pub struct WindowTotals {
    /// Forward displacement of the centre of mass over the window, m.
    pub distance_m: f64,
    /// Brakes engaged in the window.
    pub brakes: u64,
    /// Sum of the actuator impulses in the window, in [`IMPULSE_UNIT`].
    pub impulse: f64,
}

/// The end-of-run summary of the run loop (`--summary FILE.json` adds scene-specific
/// sections to it).
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
    /// The largest loop error at the end of any step, m (docs/physics.md §8.4); absent
    /// for a model without loop joints.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub max_loop_error_m: Option<f64>,
    pub lcp: LcpSummary,
    pub wall_time_s: f64,
    pub steps_per_s: f64,
    /// What the run found that limits its accuracy (e.g. [`BALANCE_WARNING`]); empty when
    /// nothing did.
    pub warnings: Vec<String>,
    /// Totals over the speed window.
    #[serde(skip)]
    pub window: WindowTotals,
}

/// A run whose energy account misses more than this fraction of its energy scale is told
/// so in its summary (docs/physics.md §6.1): the midpoint scheme's error of a step too
/// coarse for the motion (a light body turning fast, a body sliding through a joint).
pub const BALANCE_WARNING: f64 = 0.05;

/// Collects the summary from the steps it is shown.
pub(crate) struct SummaryCollector {
    title: String,
    dt: f64,
    t_start: f64,
    window_start: f64,
    x_start: f64,
    x_window: Option<f64>,
    steps: u64,
    hops: u64,
    impulses: ImpulseSummary,
    window_impulse: f64,
    window_brakes: u64,
    max_penetration: f64,
    max_loop_error: Option<f64>,
    max_balance_error: f64,
    max_balance_error_at: f64,
    potential_start: Option<f64>,
    energy_scale: f64,
    impacts_creating_energy: u64,
    created_in_impacts: f64,
}

impl SummaryCollector {
    /// A summary of `duration` seconds of a run of `scene` that starts at `start`: the
    /// speed window is the last `summary.speed_window` seconds of that span.
    pub(crate) fn new(scene: &Setup, start: &State, duration: f64) -> Self {
        let s = &scene.settings;
        let x_start = com_x(&scene.model, start);
        let window_start = start.t + (duration - s.speed_window);
        Self {
            title: scene.title.clone(),
            dt: s.dt,
            t_start: start.t,
            window_start,
            x_start,
            x_window: (window_start <= start.t).then_some(x_start),
            steps: 0,
            hops: 0,
            impulses: ImpulseSummary {
                unit: IMPULSE_UNIT,
                ..ImpulseSummary::default()
            },
            window_impulse: 0.0,
            window_brakes: 0,
            max_penetration: 0.0,
            max_loop_error: (!scene.model.loops().is_empty()).then_some(0.0),
            impacts_creating_energy: 0,
            created_in_impacts: 0.0,
            max_balance_error: 0.0,
            max_balance_error_at: start.t,
            potential_start: None,
            energy_scale: 0.0,
        }
    }

    /// The speed window of a run whose end was not known at its start
    /// ([`crate::OpenSummary`]): where it starts, the centre of mass's abscissa there and
    /// the actuator impulses and brakes in it.
    pub(crate) fn set_window(&mut self, start: f64, x: Option<f64>, impulse: f64, brakes: u64) {
        self.window_start = start;
        self.x_window = x;
        self.window_impulse = impulse;
        self.window_brakes = brakes;
    }

    /// The summary, given the last step (`end`), the run's LCP statistics and its wall time.
    pub(crate) fn finish(self, end: &StepView<'_>, lcp: LcpStats, wall_time_s: f64) -> Summary {
        let warnings = self.warnings();
        let duration = end.state.t - self.t_start;
        let window = duration - self.window_start.max(0.0);
        let x_end = end.model.center_of_mass(end.kinematics).x;
        let distance = x_end - self.x_start;
        let window_distance = x_end - self.x_window.unwrap_or(x_end);
        Summary {
            scene: self.title,
            duration_s: duration,
            dt_s: self.dt,
            steps: self.steps,
            distance_m: distance,
            mean_speed_mps: window_distance / window,
            speed_window_s: window,
            hops: self.hops,
            distance_per_hop_m: if self.hops > 0 {
                distance / self.hops as f64
            } else {
                f64::NAN
            },
            impulse_per_distance: per_forward_metre(self.impulses.total, distance),
            impulses: self.impulses,
            warnings,
            energy: EnergySummary {
                at_end: EnergySample::from_ledger(&end.record.energy),
                max_abs_balance_error: self.max_balance_error,
                max_abs_balance_error_at_s: self.max_balance_error_at,
                scale: self.energy_scale,
                impacts_creating_energy: self.impacts_creating_energy,
                created_in_impacts: self.created_in_impacts,
            },
            max_penetration_m: self.max_penetration,
            max_loop_error_m: self.max_loop_error,
            lcp: LcpSummary {
                solves: lcp.solves,
                failures: lcp.failures,
                max_pivots: lcp.max_pivots,
                warm_starts: lcp.warm_starts,
            },
            wall_time_s,
            steps_per_s: self.steps as f64 / wall_time_s.max(1e-9),
            window: WindowTotals {
                distance_m: window_distance,
                brakes: self.window_brakes,
                impulse: self.window_impulse,
            },
        }
    }
}

impl SummaryCollector {
    /// The accuracy warnings of the run (see [`Summary::warnings`]).
    fn warnings(&self) -> Vec<String> {
        let mut warnings = Vec::new();
        if self.max_balance_error > BALANCE_WARNING * self.energy_scale {
            warnings.push(format!(
                "the energy account misses {:.3e} J at t = {:.4} s, {:.0} % of the run's \
                 energy ({:.3e} J): the time step {:e} s is too coarse for this motion \
                 (a smaller simulation.dt reduces the error; docs/physics.md §6.1)",
                self.max_balance_error,
                self.max_balance_error_at,
                100.0 * self.max_balance_error / self.energy_scale,
                self.energy_scale,
                self.dt
            ));
        }
        warnings
    }
}

impl Summary {
    /// The first figure that is not finite, with its value; `None` when all are. The
    /// ratios that are NaN by definition (per hop without hops, per metre without forward
    /// motion) are not checked.
    pub fn first_non_finite(&self) -> Option<(&'static str, f64)> {
        let e = &self.energy.at_end;
        [
            ("distance", self.distance_m),
            ("mean speed", self.mean_speed_mps),
            ("speed window", self.speed_window_s),
            ("total impulse", self.impulses.total),
            ("maximum penetration", self.max_penetration_m),
            ("kinetic energy", e.kinetic),
            ("potential energy", e.potential),
            ("spring energy", e.spring),
            ("actuator work", e.actuator_work),
            ("dissipated energy", e.dissipated),
            ("energy balance error", self.energy.max_abs_balance_error),
            ("window distance", self.window.distance_m),
            ("window impulse", self.window.impulse),
        ]
        .into_iter()
        .find(|(_, v)| !v.is_finite())
    }
}

/// The robot's centre-of-mass abscissa in `state`.
fn com_x(model: &Model, state: &State) -> f64 {
    let mut kinematics = Kinematics::new(model);
    kinematics.update(model, &state.q, &state.u);
    model.center_of_mass(&kinematics).x
}

/// `total / distance`, NaN (JSON `null`) unless the robot moved forward.
pub fn per_forward_metre(total: f64, distance: f64) -> f64 {
    if distance > 0.0 {
        total / distance
    } else {
        f64::NAN
    }
}

impl Observer for SummaryCollector {
    fn on_step(&mut self, view: &StepView<'_>) -> Result<(), RunError> {
        let t = view.state.t;
        self.steps += 1;
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
                EventKind::TakeOff => {
                    self.hops += 1;
                    continue;
                }
                EventKind::EnergyCreated { energy, .. } => {
                    self.impacts_creating_energy += 1;
                    self.created_in_impacts += energy;
                    continue;
                }
                _ => continue,
            };
            self.impulses.count += 1;
            self.impulses.total += magnitude;
            if in_window {
                self.window_impulse += magnitude;
            }
        }
        self.max_penetration = self.max_penetration.max(view.record.max_penetration);
        if let Some(worst) = &mut self.max_loop_error {
            *worst = worst.max(view.record.loop_error);
        }
        let energy = &view.record.energy;
        let balance = energy.balance_error().abs();
        if balance > self.max_balance_error {
            self.max_balance_error = balance;
            self.max_balance_error_at = t;
        }
        let potential_start = *self.potential_start.get_or_insert(energy.potential);
        self.energy_scale = self.energy_scale.max(energy.scale(potential_start));
        Ok(())
    }
}
