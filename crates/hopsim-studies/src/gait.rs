//! A gait cycle by cycle (docs/physics.md §5.3, §5.4; the thesis' Fig. 5.11).
//!
//! A run of a scene ([`trace_of_scene`]) or a recording of one ([`trace_of_recording`],
//! an MCAP written by `hopsim run --mcap`) is cut into cycles ([`CycleSplit`]): at every
//! event of one kind (Robbit's brake) or every motor period (CaneBot). Per cycle: its
//! period, the distance its CoM travelled, the fractions of it spent in flight, in stance
//! and with the motor on (Robbit's flywheel spin-up), its apex height and hops. The
//! periodicity of the gait is decided on the Poincaré section at the cycle starts
//! (`hopsim_sim::PoincareSection`: the residual `r_p` for `p = 1, 2, …` and the detected
//! period `k`). The last cycles' `x`, `y` and `φ` are resampled against cycle progress
//! 0–100 % and overlaid with their mean (Fig. 5.11).
//!
//! Definitions (each over the interval `[t_i, t_{i+1}]` between two cycle starts):
//! * flight: the time between a take-off and the next touchdown event (`hopsim_sim`'s
//!   flight phases: every shape clear of the terrain by `HOP_CLEARANCE`); stance = 1 − flight.
//! * motor on: the steps whose commanded actuator torque is non-zero; a state sample
//!   stands for the interval since the previous sample (a recording at 1 kHz resolves it
//!   to 1 ms, a scene run to one step).
//! * apex height: the largest `y` of the floating base's centre of mass.
//! * section state: every coordinate but `x` and the angles of balanced rotors (a body
//!   whose centre of mass is on its joint axis and which carries no shape, spring or
//!   child, Robbit's flywheel: its angle never enters the dynamics), and every velocity,
//!   at the cycle start (interpolated between the bracketing samples when it falls between
//!   them).

use crate::plot::{
    on_white, three_significant_digits, Band, LinePlot, PlotStack, Scale, Series, SeriesStyle,
    BLACK, PALETTE,
};
use crate::report::{num, Report, ReportFile, TextTable};
use crate::{Result, StudyError};
use hopsim_control::ControllerConfig;
use hopsim_io::CsvTable;
use hopsim_model::{JointKind, Model};
use hopsim_record::{Event, McapRecording, StateSample};
use hopsim_scene::Scene;
use hopsim_sim::{Observer, Periodicity, PeriodicityOptions, PoincareSection, RunError, StepView};
use hopsim_theory::numerics::linspace;
use serde::Serialize;
use std::f64::consts::TAU;
use std::fmt::Write as _;
use std::path::Path;

/// Event kinds a [`CycleSplit::Event`] may name (`hopsim_record::EventKind::name`).
pub const EVENT_KINDS: [&str; 6] = [
    "brake",
    "take_off",
    "touchdown",
    "shape_switch",
    "shape_contact",
    "applied_impulse",
];

/// Where cycles start.
#[derive(Clone, Debug, PartialEq, Serialize)]
#[serde(tag = "kind", rename_all = "snake_case")]
pub enum CycleSplit {
    /// At every event of this kind (one of [`EVENT_KINDS`]).
    Event { event: String },
    /// At `t0 + k P`, `k = 0, 1, …`: the motor period of a periodically driven gait.
    Period {
        #[serde(rename = "period_s")]
        period: f64,
        #[serde(rename = "t0_s")]
        t0: f64,
    },
}

impl CycleSplit {
    /// A scene's own split: the brake for the momentum-impulse controller (§5.3), the
    /// motor period from `t0` for the pulse controller (§5.4), else the take-off.
    pub fn for_controller(controller: &ControllerConfig, t0: f64) -> Self {
        match controller {
            ControllerConfig::MomentumImpulse(_) => CycleSplit::event("brake"),
            ControllerConfig::Pulse(c) => CycleSplit::Period {
                period: c.period,
                t0,
            },
            ControllerConfig::Passive => CycleSplit::event("take_off"),
        }
    }

    /// A split at events of `kind`.
    pub fn event(kind: &str) -> Self {
        CycleSplit::Event {
            event: kind.to_string(),
        }
    }

    /// Checks the event kind or the period.
    pub fn validate(&self) -> Result<()> {
        match self {
            CycleSplit::Event { event } if !EVENT_KINDS.contains(&event.as_str()) => {
                Err(StudyError::Input(format!(
                    "no event kind '{event}'; the kinds are {}",
                    EVENT_KINDS.join(", ")
                )))
            }
            CycleSplit::Period { period, t0 } if !(period.is_finite() && *period > 0.0) => {
                Err(StudyError::Input(format!(
                    "the motor period must be a positive number of seconds, got {period} (from t0 = {t0} s)"
                )))
            }
            _ => Ok(()),
        }
    }
}

impl CycleSplit {
    /// A few words for figure titles: `brake to brake`, `motor period 0.357 s`.
    pub fn short(&self) -> String {
        match self {
            CycleSplit::Event { event } => format!("{event} to {event}"),
            CycleSplit::Period { period, .. } => format!("motor period {}", num(*period, "s")),
        }
    }
}

impl std::fmt::Display for CycleSplit {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            CycleSplit::Event { event } => write!(f, "at every {event} event"),
            CycleSplit::Period { period, t0 } => {
                write!(
                    f,
                    "every motor period of {} from {}",
                    num(*period, "s"),
                    num(*t0, "s")
                )
            }
        }
    }
}

/// What the analysis does.
#[derive(Clone, Debug)]
pub struct GaitParams {
    /// Where cycles start (`None`: the scene's own, [`CycleSplit::for_controller`]).
    pub split: Option<CycleSplit>,
    /// Cycles at the end of the run in the statistics and the overlay.
    pub last: usize,
    /// Points of each resampled cycle, from 0 to 100 % progress.
    pub profile_points: usize,
    /// How periodicity is decided on the section at the cycle starts.
    pub periodicity: PeriodicityOptions,
}

impl Default for GaitParams {
    /// The scene's split, the last 8 cycles (even, so a period-2 gait weighs both of its
    /// cycles alike), 101 points per cycle, periods up to 4 over the last 8 comparisons.
    fn default() -> Self {
        GaitParams {
            split: None,
            last: 8,
            profile_points: 101,
            periodicity: PeriodicityOptions::default(),
        }
    }
}

/// A run as the analysis reads it.
#[derive(Clone, Debug)]
pub struct GaitTrace {
    /// The scene's title.
    pub title: String,
    /// Where the run comes from (a scene file, a recording).
    pub source: String,
    /// Names of the generalised coordinates (`x`, `y`, `phi`, …).
    pub coordinates: Vec<String>,
    /// Indices of the coordinates left out of the section (balanced rotors).
    pub cyclic: Vec<usize>,
    /// Indices of the coordinates the gait travels along, also left out of the section:
    /// the `x` of each floating base ([`Model::horizontal_positions`]).
    pub translations: Vec<usize>,
    /// States in time order, each with the actuator torque of the step that ended there.
    pub states: Vec<StateSample>,
    /// Events in time order.
    pub events: Vec<Event>,
    /// The split the scene calls for ([`CycleSplit::for_controller`]).
    pub natural_split: CycleSplit,
}

/// Coordinates of balanced rotors: bodies whose centre of mass lies on their joint axis
/// and which carry no shape, no spring and no child body (their angle is cyclic: it
/// enters neither the mass matrix nor any force): revolute joints without a spring or
/// stops.
pub fn balanced_rotors(model: &Model) -> Vec<usize> {
    (0..model.bodies().len())
        .filter(|&b| {
            let balanced = model.bodies()[b].joint.as_ref().is_some_and(|j| {
                j.kind == JointKind::Revolute
                    && j.com_in_child.norm() == 0.0
                    && j.stiffness == 0.0
                    && j.limits.is_none()
            });
            let shaped = model.shapes().iter().any(|s| s.body == b);
            let sprung = model
                .springs()
                .iter()
                .any(|s| s.body_a == b || s.body_b == b);
            let parent = model
                .bodies()
                .iter()
                .any(|c| c.joint.as_ref().is_some_and(|j| j.parent == Some(b)));
            balanced && !shaped && !sprung && !parent
        })
        .filter_map(|b| model.coordinate(b))
        .collect()
}

/// Collects every state and event of a run.
struct TraceCollector {
    states: Vec<StateSample>,
    events: Vec<Event>,
}

impl TraceCollector {
    fn push(&mut self, view: &StepView<'_>, torque: f64) {
        self.states.push(StateSample {
            step: view.record.step,
            t: view.state.t,
            q: view.state.q.as_slice().to_vec(),
            u: view.state.u.as_slice().to_vec(),
            actuator_torque: torque,
        });
        self.events.extend_from_slice(view.events);
    }
}

impl Observer for TraceCollector {
    fn on_start(&mut self, view: &StepView<'_>) -> std::result::Result<(), RunError> {
        self.push(view, 0.0);
        Ok(())
    }

    fn on_step(&mut self, view: &StepView<'_>) -> std::result::Result<(), RunError> {
        self.push(view, view.torque);
        Ok(())
    }
}

/// Runs `scene` for its duration and keeps every step's state and every event.
pub fn trace_of_scene(scene: &Scene) -> Result<GaitTrace> {
    let mut collector = TraceCollector {
        states: Vec::new(),
        events: Vec::new(),
    };
    hopsim_sim::run(scene, &mut collector)?;
    Ok(GaitTrace {
        title: scene.title.clone(),
        source: scene.path.display().to_string(),
        coordinates: scene.coordinates.clone(),
        cyclic: balanced_rotors(&scene.model),
        translations: scene.model.horizontal_positions(),
        states: collector.states,
        events: collector.events,
        natural_split: CycleSplit::for_controller(&scene.controller, scene.initial.t),
    })
}

/// Reads a recording of `hopsim run --mcap`: its states (at the recording rate and at every
/// event step) and events; the scene file it carries gives the balanced rotors and the
/// natural split (the file as it was read: `--set` overrides of that run are not stored).
pub fn trace_of_recording(path: &Path) -> Result<GaitTrace> {
    let recording = McapRecording::read(path)?;
    let attachment = recording.scene.as_ref().ok_or_else(|| {
        StudyError::Input(format!(
            "{}: the recording carries no scene file, which the analysis needs for the robot's structure",
            path.display()
        ))
    })?;
    let scene = hopsim_scene::parse(
        &attachment.text,
        Path::new(&recording.metadata.scene_path),
        &[],
    )?;
    if scene.coordinates != recording.metadata.coordinates {
        return Err(StudyError::Input(format!(
            "{}: the recording's coordinates {:?} differ from those of its scene file {:?}",
            path.display(),
            recording.metadata.coordinates,
            scene.coordinates
        )));
    }
    Ok(GaitTrace {
        title: recording.metadata.scene.clone(),
        source: path.display().to_string(),
        coordinates: recording.metadata.coordinates,
        cyclic: balanced_rotors(&scene.model),
        translations: scene.model.horizontal_positions(),
        states: recording.states,
        events: recording.events,
        natural_split: CycleSplit::for_controller(&scene.controller, scene.initial.t),
    })
}

/// One cycle.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Cycle {
    /// 0-based, in time order.
    pub index: usize,
    #[serde(rename = "start_s")]
    pub start: f64,
    #[serde(rename = "period_s")]
    pub period: f64,
    /// `x` at the end minus `x` at the start.
    #[serde(rename = "distance_m")]
    pub distance: f64,
    /// `distance / period`.
    #[serde(rename = "speed_mps")]
    pub speed: f64,
    pub flight_fraction: f64,
    pub stance_fraction: f64,
    /// Fraction with a non-zero motor torque (Robbit: the flywheel's spin-up).
    pub motor_on_fraction: f64,
    /// Largest `y` of the base's centre of mass.
    #[serde(rename = "apex_height_m")]
    pub apex_height: f64,
    /// Take-offs in the cycle.
    pub hops: usize,
}

/// The last cycles together: times summed over cycles, so the fractions and the speed are
/// time-weighted.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct CycleStatistics {
    /// Cycles included.
    pub cycles: usize,
    #[serde(rename = "mean_period_s")]
    pub mean_period: f64,
    #[serde(rename = "min_period_s")]
    pub min_period: f64,
    #[serde(rename = "max_period_s")]
    pub max_period: f64,
    #[serde(rename = "mean_distance_m")]
    pub mean_distance: f64,
    #[serde(rename = "speed_mps")]
    pub speed: f64,
    pub flight_fraction: f64,
    pub stance_fraction: f64,
    pub motor_on_fraction: f64,
    #[serde(rename = "mean_apex_height_m")]
    pub mean_apex_height: f64,
    /// Take-offs per cycle.
    pub hops_per_cycle: f64,
}

impl CycleStatistics {
    fn of(cycles: &[Cycle]) -> Self {
        let n = cycles.len() as f64;
        let sum = |f: fn(&Cycle) -> f64| cycles.iter().map(f).sum::<f64>();
        let time = sum(|c| c.period);
        let weighted =
            |f: fn(&Cycle) -> f64| cycles.iter().map(|c| f(c) * c.period).sum::<f64>() / time;
        CycleStatistics {
            cycles: cycles.len(),
            mean_period: time / n,
            min_period: cycles
                .iter()
                .map(|c| c.period)
                .fold(f64::INFINITY, f64::min),
            max_period: cycles
                .iter()
                .map(|c| c.period)
                .fold(f64::NEG_INFINITY, f64::max),
            mean_distance: sum(|c| c.distance) / n,
            speed: sum(|c| c.distance) / time,
            flight_fraction: weighted(|c| c.flight_fraction),
            stance_fraction: weighted(|c| c.stance_fraction),
            motor_on_fraction: weighted(|c| c.motor_on_fraction),
            mean_apex_height: sum(|c| c.apex_height) / n,
            hops_per_cycle: cycles.iter().map(|c| c.hops as f64).sum::<f64>() / n,
        }
    }
}

/// `x − x(start)`, `y` and `φ` of the last cycles against cycle progress (Fig. 5.11); `φ`
/// shifted by whole turns so that each cycle starts in `(−π, π]`.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Profiles {
    #[serde(rename = "progress_percent")]
    pub progress: Vec<f64>,
    /// Indices of the cycles, in order.
    pub cycles: Vec<usize>,
    /// Per cycle, per progress point.
    #[serde(rename = "x_m")]
    pub x: Vec<Vec<f64>>,
    #[serde(rename = "y_m")]
    pub y: Vec<Vec<f64>>,
    #[serde(rename = "phi_rad")]
    pub phi: Vec<Vec<f64>>,
    /// Means over the cycles, per progress point.
    #[serde(rename = "mean_x_m")]
    pub mean_x: Vec<f64>,
    #[serde(rename = "mean_y_m")]
    pub mean_y: Vec<f64>,
    #[serde(rename = "mean_phi_rad")]
    pub mean_phi: Vec<f64>,
    /// Per cycle, its flight phases as progress intervals (%), for the figure.
    #[serde(skip)]
    pub flights: Vec<Vec<(f64, f64)>>,
}

/// The gait analysis of a run.
#[derive(Clone, Debug, Serialize)]
pub struct GaitReport {
    analysis: &'static str,
    pub title: String,
    pub source: String,
    pub split: CycleSplit,
    /// Time covered by the run, s.
    #[serde(rename = "duration_s")]
    pub duration: f64,
    /// Every complete cycle.
    pub cycles: Vec<Cycle>,
    /// The last cycles.
    pub last: CycleStatistics,
    /// Names of the section state's components.
    pub section: Vec<String>,
    /// The period of the gait on the section at the cycle starts, in cycles.
    pub periodicity: Periodicity,
    /// The last cycles against progress.
    pub profiles: Profiles,
}

/// The analysis of `trace` (its natural split unless `params.split` says otherwise).
pub fn analyze(trace: &GaitTrace, params: &GaitParams) -> Result<GaitReport> {
    let split = params
        .split
        .clone()
        .unwrap_or_else(|| trace.natural_split.clone());
    split.validate()?;
    if params.last == 0 {
        return Err(StudyError::Input(
            "the statistics need at least the last cycle (last = 0)".into(),
        ));
    }
    if params.profile_points < 2 {
        return Err(StudyError::Input(format!(
            "a cycle's profile needs at least two points, got {}",
            params.profile_points
        )));
    }
    let states = &trace.states;
    let (Some(first), Some(end)) = (states.first(), states.last()) else {
        return Err(StudyError::Input(format!("{}: no states", trace.source)));
    };
    if trace.coordinates.len() < 3 || states.iter().any(|s| s.q.len() != trace.coordinates.len()) {
        return Err(StudyError::Input(format!(
            "{}: every state needs the base's x, y, phi and one value per coordinate",
            trace.source
        )));
    }
    let starts = cycle_starts(trace, &split, first.t, end.t);
    if starts.len() < 2 {
        return Err(StudyError::Input(format!(
            "{}: {} cycle start{} ({split}) in {} s: no complete cycle to analyse",
            trace.source,
            starts.len(),
            if starts.len() == 1 { "" } else { "s" },
            num(end.t - first.t, "")
        )));
    }
    let flights = flight_intervals(&trace.events, first.t, end.t);
    let cycles: Vec<Cycle> = starts
        .windows(2)
        .enumerate()
        .map(|(index, w)| cycle(trace, &flights, index, w[0], w[1]))
        .collect();
    let last = params.last.min(cycles.len());
    let recent = &cycles[cycles.len() - last..];
    let (section, names) = section(trace, &starts);
    Ok(GaitReport {
        analysis: "gait",
        title: trace.title.clone(),
        source: trace.source.clone(),
        split,
        duration: end.t - first.t,
        last: CycleStatistics::of(recent),
        section: names,
        periodicity: section.detect(&params.periodicity),
        profiles: profiles(trace, recent, &flights, params.profile_points),
        cycles,
    })
}

/// Cycle start times in `[t_first, t_end]`, increasing.
fn cycle_starts(trace: &GaitTrace, split: &CycleSplit, t_first: f64, t_end: f64) -> Vec<f64> {
    let mut starts: Vec<f64> = match split {
        CycleSplit::Event { event } => trace
            .events
            .iter()
            .filter(|e| e.kind.name() == event)
            .map(|e| e.t)
            .collect(),
        CycleSplit::Period { period, t0 } => {
            let first = ((t_first - t0) / period).ceil().max(0.0) as u64;
            (first..)
                .map(|k| t0 + k as f64 * period)
                .take_while(|&t| t <= t_end)
                .collect()
        }
    };
    starts.retain(|&t| t >= t_first && t <= t_end);
    starts.dedup();
    starts
}

/// Flight phases `[take-off, touchdown]`; one still open at the end closes there, and a
/// touchdown without a take-off before it (a run starting in the air) opens at the start.
fn flight_intervals(events: &[Event], t_first: f64, t_end: f64) -> Vec<(f64, f64)> {
    let mut flights = Vec::new();
    let mut open = None;
    let mut seen = false;
    for e in events {
        match e.kind.name() {
            "take_off" => {
                open = Some(e.t);
                seen = true;
            }
            "touchdown" => {
                let from = open.take().or((!seen).then_some(t_first));
                if let Some(from) = from {
                    flights.push((from, e.t));
                }
                seen = true;
            }
            _ => {}
        }
    }
    if let Some(from) = open {
        flights.push((from, t_end));
    }
    flights
}

/// Length of the overlap of `[a, b]` and `[c, d]`.
fn overlap(a: f64, b: f64, c: f64, d: f64) -> f64 {
    (b.min(d) - a.max(c)).max(0.0)
}

/// Index of the first state at or after `t`.
fn first_at_or_after(states: &[StateSample], t: f64) -> usize {
    states.partition_point(|s| s.t < t)
}

/// Coordinate `i` at time `t`, linear between the bracketing states.
fn coordinate_at(states: &[StateSample], i: usize, t: f64) -> f64 {
    value_at(states, t, |s| s.q[i])
}

fn value_at(states: &[StateSample], t: f64, f: impl Fn(&StateSample) -> f64) -> f64 {
    let k = first_at_or_after(states, t).min(states.len() - 1);
    if k == 0 || states[k].t == t {
        return f(&states[k]);
    }
    let (a, b) = (&states[k - 1], &states[k]);
    let s = (t - a.t) / (b.t - a.t);
    f(a) + s * (f(b) - f(a))
}

fn cycle(trace: &GaitTrace, flights: &[(f64, f64)], index: usize, a: f64, b: f64) -> Cycle {
    let states = &trace.states;
    let period = b - a;
    let distance = coordinate_at(states, 0, b) - coordinate_at(states, 0, a);
    let flight: f64 = flights.iter().map(|&(c, d)| overlap(a, b, c, d)).sum();
    let (from, to) = (first_at_or_after(states, a), first_at_or_after(states, b));
    // A sample's torque acts over the interval since the previous sample.
    let motor_on: f64 = (from.max(1)..=to.min(states.len() - 1))
        .filter(|&k| states[k].actuator_torque != 0.0)
        .map(|k| overlap(a, b, states[k - 1].t, states[k].t))
        .sum();
    let apex_height = states[from..to].iter().map(|s| s.q[1]).fold(
        coordinate_at(states, 1, a).max(coordinate_at(states, 1, b)),
        f64::max,
    );
    let hops = trace
        .events
        .iter()
        .filter(|e| e.kind.name() == "take_off" && e.t >= a && e.t < b)
        .count();
    Cycle {
        index,
        start: a,
        period,
        distance,
        speed: distance / period,
        flight_fraction: flight / period,
        stance_fraction: 1.0 - flight / period,
        motor_on_fraction: motor_on / period,
        apex_height,
        hops,
    }
}

/// The section at every cycle start, and the names of its components.
fn section(trace: &GaitTrace, starts: &[f64]) -> (PoincareSection, Vec<String>) {
    let kept: Vec<usize> = (0..trace.coordinates.len())
        .filter(|i| !trace.cyclic.contains(i) && !trace.translations.contains(i))
        .collect();
    let reduced = |s: &StateSample| -> Vec<f64> { kept.iter().map(|&i| s.q[i]).collect() };
    let mut section = PoincareSection::at_events().leaving_out(Vec::new());
    let mut next = starts.iter().peekable();
    for (k, s) in trace.states.iter().enumerate() {
        while let Some(&&t) = next.peek() {
            if t > s.t {
                break;
            }
            let at = |f: &dyn Fn(&StateSample) -> f64| value_at(&trace.states[..=k], t, f);
            let q: Vec<f64> = kept.iter().map(|&i| at(&|s| s.q[i])).collect();
            let u: Vec<f64> = (0..s.u.len()).map(|i| at(&|s| s.u[i])).collect();
            section.sample(t, &q, &u);
            next.next();
        }
        section.push(s.t, &reduced(s), &s.u);
    }
    let names = kept
        .iter()
        .map(|&i| trace.coordinates[i].clone())
        .chain(trace.coordinates.iter().map(|c| format!("{c}_dot")))
        .collect();
    (section, names)
}

/// `x − x(start)`, `y`, `φ` of `cycles` at `points` progress values, their means, and the
/// `flights` within each cycle in progress.
fn profiles(
    trace: &GaitTrace,
    cycles: &[Cycle],
    flights: &[(f64, f64)],
    points: usize,
) -> Profiles {
    let states = &trace.states;
    let progress = linspace(0.0, 1.0, points);
    let mut p = Profiles {
        progress: progress.iter().map(|s| 100.0 * s).collect(),
        cycles: cycles.iter().map(|c| c.index).collect(),
        x: Vec::new(),
        y: Vec::new(),
        phi: Vec::new(),
        mean_x: Vec::new(),
        mean_y: Vec::new(),
        mean_phi: Vec::new(),
        flights: Vec::new(),
    };
    for c in cycles {
        let end = c.start + c.period;
        let percent = |t: f64| 100.0 * (t - c.start) / c.period;
        p.flights.push(
            (flights.iter())
                .filter(|&&(a, b)| overlap(c.start, end, a, b) > 0.0)
                .map(|&(a, b)| (percent(a.max(c.start)), percent(b.min(end))))
                .collect(),
        );
        let times: Vec<f64> = progress.iter().map(|s| c.start + s * c.period).collect();
        let x0 = coordinate_at(states, 0, c.start);
        let turns = (coordinate_at(states, 2, c.start) / TAU).round() * TAU;
        p.x.push(
            times
                .iter()
                .map(|&t| coordinate_at(states, 0, t) - x0)
                .collect(),
        );
        p.y.push(times.iter().map(|&t| coordinate_at(states, 1, t)).collect());
        p.phi.push(
            times
                .iter()
                .map(|&t| coordinate_at(states, 2, t) - turns)
                .collect(),
        );
    }
    let all = |rows: &[Vec<f64>]| mean_profile(&rows.iter().collect::<Vec<_>>());
    p.mean_x = all(&p.x);
    p.mean_y = all(&p.y);
    p.mean_phi = all(&p.phi);
    p
}

/// The point-by-point mean of `rows` (of equal length; empty without rows).
fn mean_profile(rows: &[&Vec<f64>]) -> Vec<f64> {
    let points = rows.first().map_or(0, |r| r.len());
    (0..points)
        .map(|j| rows.iter().map(|r| r[j]).sum::<f64>() / rows.len() as f64)
        .collect()
}

/// Cycle numbers as `54–61` when consecutive, else `70, 72, 74`.
fn cycle_list(numbers: &[usize]) -> String {
    match (numbers.first(), numbers.last()) {
        (Some(a), Some(b)) if numbers.len() > 2 && b - a + 1 == numbers.len() => format!("{a}–{b}"),
        _ => (numbers.iter().map(ToString::to_string))
            .collect::<Vec<_>>()
            .join(", "),
    }
}

/// Opacity of the flight shading where every cycle of a kind is in flight.
const FLIGHT_OPACITY: f64 = 0.15;

impl GaitReport {
    /// How many kinds of cycle the overlay groups the last cycles into, by cycle index
    /// modulo this number: the detected period; without one, the lag whose residual is
    /// smallest if it is at most half the residual of lag 1 (a gait that alternates
    /// without closing within the tolerance); else 1.
    pub fn cycle_kinds(&self) -> usize {
        if let Some(p) = self.periodicity.period {
            return p;
        }
        let r = &self.periodicity.residuals;
        let best = (1..=r.len())
            .filter(|&p| r[p - 1].is_finite())
            .min_by(|&a, &b| r[a - 1].total_cmp(&r[b - 1]));
        match best {
            Some(p) if p > 1 && r[p - 1] <= 0.5 * r[0] => p,
            _ => 1,
        }
    }

    /// The Fig. 5.11 overlay: one panel each for `x − x(start)`, `y` and `φ` against cycle
    /// progress, the cycles of each kind ([`GaitReport::cycle_kinds`]) thin in its colour
    /// with their mean bold and their flight phases shaded; no mean for a gait without a
    /// period (it would stand for no cycle). One legend, one x label.
    pub fn profile_figure(&self) -> PlotStack {
        let p = &self.profiles;
        let kinds = self.cycle_kinds();
        let mean_shown = kinds > 1 || self.periodicity.period.is_some();
        let members = |kind: usize| -> Vec<usize> {
            (0..p.cycles.len())
                .filter(|&k| p.cycles[k] % kinds == kind)
                .collect()
        };
        let name = |kind: usize| match kinds {
            1 => String::new(),
            _ => format!("{}: ", char::from(b'A' + (kind % 26) as u8)),
        };
        // Thin cycles, their bold mean and their flight shading.
        let colour = |kind: usize| match kinds {
            1 => (PALETTE[0], BLACK, PALETTE[0]),
            _ => {
                let c = PALETTE[kind % PALETTE.len()];
                (on_white(c, 0.5), c, c)
            }
        };
        let curve = |values: &[f64], color, size| {
            let points = p.progress.iter().copied().zip(values.iter().copied());
            Series::line("", points.collect()).color(color).size(size)
        };
        let panel = |label: &str, rows: &[Vec<f64>], last: bool| {
            let x_label = if last { "cycle progress (%)" } else { "" };
            let mut plot = LinePlot::new("", x_label, label).with_x_range(0.0, 100.0);
            for kind in 0..kinds {
                let cycles = members(kind);
                let (thin, bold, shade) = colour(kind);
                let opacity = 1.0 - (1.0 - FLIGHT_OPACITY).powf(1.0 / cycles.len().max(1) as f64);
                let flight = match kinds {
                    1 => "flight (shaded; stance unshaded)".to_string(),
                    _ => format!("{}flight (shaded)", name(kind)),
                };
                for (from, to) in cycles.iter().flat_map(|&k| p.flights[k].iter().copied()) {
                    let band = Band::new(flight.clone(), from, to, shade).opacity(opacity);
                    plot = plot.with_band(band);
                }
                let numbers: Vec<usize> = cycles.iter().map(|&k| p.cycles[k]).collect();
                let label = format!("{}cycles {}", name(kind), cycle_list(&numbers));
                let mut thin_label = Some(label.clone());
                for &k in &cycles {
                    let mut series = curve(&rows[k], thin, 1).unlabelled();
                    series.label = thin_label.take().filter(|_| !mean_shown);
                    plot = plot.with_series(series);
                }
                if mean_shown && !cycles.is_empty() {
                    let mean = mean_profile(&cycles.iter().map(|&k| &rows[k]).collect::<Vec<_>>());
                    let mut series = curve(&mean, bold, 3);
                    series.label = Some(format!("{label} (thin) and their mean (bold)"));
                    plot = plot.with_series(series);
                }
            }
            plot
        };
        let grouping = match (kinds, self.periodicity.period) {
            (1, Some(_)) => "period 1".to_string(),
            (k, Some(_)) => format!("period {k}, {k} kinds of cycle"),
            (1, None) => format!("no period ≤ {}, so no mean", self.periodicity.residuals.len()),
            (k, None) => format!(
                "{k} kinds of cycle: alternating, though not periodic within the tolerance (r_{k} = {})",
                three_significant_digits(self.periodicity.residuals[k - 1])
            ),
        };
        PlotStack::new(
            format!(
                "{}: the last {} cycles ({}), {grouping}",
                self.title,
                p.cycles.len(),
                self.split.short()
            ),
            vec![
                panel("x − x(start) (m)", &p.x, false),
                panel("y (m)", &p.y, false),
                panel("φ (rad)", &p.phi, true),
            ],
        )
        .with_shared_legend()
    }

    /// Every cycle's distance (and, for cycles between events, its period) against its
    /// index, and the section residual `r_p` against the lag `p` on a logarithmic axis
    /// with the tolerance `r_p = 1`; cycle numbers and lags are ticked at whole numbers.
    pub fn periodicity_figure(&self) -> PlotStack {
        let per_cycle = |label: &str, unit: &str, value: fn(&Cycle) -> f64| {
            let points = self
                .cycles
                .iter()
                .map(|c| (c.index as f64, value(c)))
                .collect();
            LinePlot::new("", "cycle number", format!("{label} ({unit})"))
                .with_x_scale(Scale::Integer)
                .with_series(
                    Series::line("", points)
                        .style(SeriesStyle::LineAndPoints)
                        .unlabelled(),
                )
        };
        let mut panels = vec![per_cycle("distance per cycle", "m", |c| c.distance)];
        if matches!(self.split, CycleSplit::Event { .. }) {
            panels[0].x_label.clear();
            panels.push(per_cycle("period", "s", |c| c.period));
        }
        let residuals: Vec<(f64, f64)> = self
            .periodicity
            .residuals
            .iter()
            .enumerate()
            .map(|(i, &r)| ((i + 1) as f64, r))
            .collect();
        let n = residuals.len() as f64;
        let positive = || (residuals.iter().map(|p| p.1)).filter(|r| r.is_finite() && *r > 0.0);
        let top = positive().fold(1.0, f64::max);
        let bottom = positive().fold(1.0, f64::min);
        let bottom = LinePlot::new("", "lag p (cycles)", "residual r_p (1 = tolerance)")
            .with_x_scale(Scale::Integer)
            .with_y_scale(Scale::Log)
            .with_x_range(0.5, n + 0.5)
            .with_y_range(bottom / 3.0, 3.0 * top)
            .with_series(Series::points("r_p", residuals).color(PALETTE[3]).size(6))
            .with_series(
                Series::line(
                    "tolerance (periodic at or below)",
                    vec![(0.5, 1.0), (n + 0.5, 1.0)],
                )
                .color(BLACK),
            );
        let detected = match self.periodicity.period {
            Some(k) => format!("period {k}"),
            None => format!("no period ≤ {}", self.periodicity.residuals.len()),
        };
        panels.push(bottom);
        PlotStack::new(
            format!(
                "{}: {detected} on the section at the cycle starts ({})",
                self.title,
                self.split.short()
            ),
            panels,
        )
    }
}

impl Report for GaitReport {
    fn text(&self) -> String {
        let s = &self.last;
        let mut t = TextTable::new(format!("{} ({})", self.title, self.source));
        t.row(
            "cycles",
            format!("{} complete, split {}", self.cycles.len(), self.split),
        )
        .row("last cycles", s.cycles)
        .row(
            "period",
            format!(
                "mean {}, from {} to {}",
                num(s.mean_period, "s"),
                num(s.min_period, "s"),
                num(s.max_period, "s")
            ),
        )
        .row("distance per cycle", num(s.mean_distance, "m"))
        .row("speed", num(s.speed, "m/s"))
        .row(
            "flight / stance",
            format!(
                "{} / {}",
                num(s.flight_fraction, ""),
                num(s.stance_fraction, "")
            ),
        )
        .row("motor on (spin-up)", num(s.motor_on_fraction, ""))
        .row("apex height (mean)", num(s.mean_apex_height, "m"))
        .row("hops per cycle", num(s.hops_per_cycle, ""))
        .row("periodicity", &self.periodicity)
        .row("section", self.section.join(", "));
        let mut text = t.to_string();
        let _ = writeln!(
            text,
            "\n  cycle   start [s]  period [s]  distance [m]  speed [m/s]  flight  motor on  apex [m]  hops"
        );
        for c in &self.cycles[self.cycles.len() - s.cycles..] {
            let _ = writeln!(
                text,
                "  {:>5}  {:>10.4}  {:>10.4}  {:>12.4}  {:>11.4}  {:>6.3}  {:>8.3}  {:>8.4}  {:>4}",
                c.index,
                c.start,
                c.period,
                c.distance,
                c.speed,
                c.flight_fraction,
                c.motor_on_fraction,
                c.apex_height,
                c.hops
            );
        }
        text
    }

    fn files(&self) -> Vec<ReportFile> {
        let mut cycles = CsvTable::new(&[
            "cycle",
            "start_s",
            "period_s",
            "distance_m",
            "speed_mps",
            "flight_fraction",
            "stance_fraction",
            "motor_on_fraction",
            "apex_height_m",
            "hops",
        ]);
        for c in &self.cycles {
            cycles.push(vec![
                c.index.into(),
                c.start.into(),
                c.period.into(),
                c.distance.into(),
                c.speed.into(),
                c.flight_fraction.into(),
                c.stance_fraction.into(),
                c.motor_on_fraction.into(),
                c.apex_height.into(),
                c.hops.into(),
            ]);
        }
        let p = &self.profiles;
        let mut profiles = CsvTable::new(&["cycle", "progress_percent", "x_m", "y_m", "phi_rad"]);
        let mut push = |cycle: String, x: &[f64], y: &[f64], phi: &[f64]| {
            for (j, &progress) in p.progress.iter().enumerate() {
                profiles.push(vec![
                    cycle.clone().into(),
                    progress.into(),
                    x[j].into(),
                    y[j].into(),
                    phi[j].into(),
                ]);
            }
        };
        for (k, c) in p.cycles.iter().enumerate() {
            push(c.to_string(), &p.x[k], &p.y[k], &p.phi[k]);
        }
        push("mean".into(), &p.mean_x, &p.mean_y, &p.mean_phi);
        vec![
            ReportFile::csv("gait_cycles.csv", cycles),
            ReportFile::csv("gait_profiles.csv", profiles),
            ReportFile::figure("gait_profiles", self.profile_figure()),
            ReportFile::figure("gait_periodicity", self.periodicity_figure()),
        ]
    }
}
