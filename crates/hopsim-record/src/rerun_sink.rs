//! [`RerunRecorder`]: the run as a Rerun recording (`.rrd` file or live viewer), with the
//! robot drawn in 2D and time series of its state, energies and contact impulses
//! (entities and timelines in docs/recording.md).
//!
//! What changes every frame (time series, body poses, the centre of mass, springs,
//! contact forces) is buffered in columns and sent in chunks ([`RecordingStream::send_columns`]);
//! shape outlines are logged in their body's frame, once and again only when a shape is
//! switched, and placed by the body's transform.

use crate::frame::FrameLayout;
use crate::geometry::{
    palette, terrain_pieces, wrap_angle, CoordinateUnit, Outline, Point, RobotShapes, TerrainCover,
    INACTIVE_COLOR, RAIL_COLOR, TERRAIN_COLOR,
};
use crate::{
    ActuatorQuantity, EnergySample, Event, EventKind, Frame, JointInfo, RecordError, Recorder,
    RecordingInfo, Stop,
};
use hopsim_io::AtomicPath;
use rerun::blueprint::{
    Blueprint, ContainerLike, Horizontal, Spatial2DView, TextLogView, TimePanel, TimeSeriesView,
    Vertical,
};
use rerun::{
    Arrows2D, AsComponents, Color, LineStrips2D, Points2D, Quaternion, RecordingStream,
    RecordingStreamBuilder, Scalars, SerializedComponentColumn, SeriesLines, TextDocument, TextLog,
    TimeColumn, Transform3D,
};
use std::path::{Path, PathBuf};
use std::str::FromStr;
use std::time::{Duration, Instant};

/// How to get the Rerun viewer that matches the SDK hopsim is built with.
pub const RERUN_VIEWER_INSTALL: &str = "pip install rerun-sdk==0.36.3";
/// Timeline of simulation time, s.
pub const TIME_TIMELINE: &str = "sim_time";
/// Timeline of step indices.
pub const STEP_TIMELINE: &str = "step";
/// Force-arrow scale when the robot's weight is unknown, m/N.
const FALLBACK_ARROW_SCALE_M_PER_N: f64 = 0.01;
/// Longest contact arrow, in robot sizes (touchdown impacts would dwarf the scene).
const MAX_ARROW_ROBOT_SIZES: f64 = 3.0;
/// How long an event's marker stays in the robot view, s of simulation time (the event
/// log keeps every event).
const EVENT_MARKER_HOLD_S: f64 = 0.1;
/// Points per logged piece of the centre-of-mass trail (`world/com/trail/<n>`): only the
/// growing piece is logged again, so the trail costs little however long the run.
const TRAIL_PIECE_POINTS: usize = 100;
/// Frames per chunk of the columns sent to a file.
const CHUNK_FRAMES: usize = 1000;
/// Longest wall-clock time the columns of a live stream are held back.
const LIVE_FLUSH_INTERVAL: Duration = Duration::from_millis(50);
/// Colour of the contact-force arrows.
const FORCE_COLOR: [u8; 3] = [214, 39, 40];
/// The prismatic links: from each joint's anchor on the parent to the child's joint point.
const LINK_ENTITY: &str = "world/joints";
const LINK_COLOR: [u8; 3] = [60, 60, 60];

/// How fast a live stream ([`RerunRecorder::spawn`]) plays the run.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Pace {
    /// `factor` simulated seconds per wall-clock second (1: real time).
    Speed(f64),
    /// As fast as the simulation runs.
    Unpaced,
}

impl Default for Pace {
    fn default() -> Self {
        Pace::Speed(1.0)
    }
}

/// `max` or a positive factor, e.g. `0.25` (four times slower than real time).
impl FromStr for Pace {
    type Err = String;

    fn from_str(s: &str) -> Result<Self, Self::Err> {
        if s.trim() == "max" {
            return Ok(Pace::Unpaced);
        }
        match s.trim().parse::<f64>() {
            Ok(f) if f.is_finite() && f > 0.0 => Ok(Pace::Speed(f)),
            _ => Err(format!(
                "`{s}` is not a speed: give a positive factor of real time (1 = real time, \
                 0.5 = half speed) or `max` (as fast as possible)"
            )),
        }
    }
}

/// Streams a run to Rerun: a `.rrd` file ([`RerunRecorder::save`]) or a live viewer
/// ([`RerunRecorder::spawn`]).
pub struct RerunRecorder {
    /// Declared first so that it is dropped (and its file closed) before `output`.
    stream: RecordingStream,
    output: Option<AtomicPath>,
    drawing: Drawing,
    columns: Columns,
    layout: FrameLayout,
    /// Live stream: pacing and when the columns were last sent.
    live: Option<Live>,
    /// Where errors point: the `.rrd` path or "Rerun viewer".
    target: PathBuf,
}

/// A live stream's clock.
struct Live {
    pace: Pace,
    /// Wall-clock instant and simulation time of the first frame.
    start: Option<(Instant, f64)>,
    last_flush: Instant,
}

impl Live {
    /// Sleeps until the wall clock reaches simulation time `t` at the pace.
    fn wait_for(&mut self, t: f64) {
        let Pace::Speed(speed) = self.pace else {
            return;
        };
        let now = Instant::now();
        let (start, t0) = *self.start.get_or_insert((now, t));
        let ahead = (t - t0) / speed;
        if let Ok(ahead) = Duration::try_from_secs_f64(ahead) {
            if let Some(wait) = (start + ahead).checked_duration_since(now) {
                std::thread::sleep(wait);
            }
        }
    }
}

impl RerunRecorder {
    /// Records to the `.rrd` file `path`, written under a temporary name and renamed into
    /// place by `finish`.
    pub fn save(path: &Path, info: &RecordingInfo) -> Result<Self, RecordError> {
        let output = AtomicPath::create(path)?;
        let stream = builder(info)
            .save(output.temporary())
            .map_err(|e| RecordError::format(path, e))?;
        Self::start(stream, Some(output), None, path.to_path_buf(), info)
    }

    /// Streams to a live Rerun viewer, started from the `rerun` executable on `PATH` (or
    /// reused if one listens on the default port), at `pace`. The viewer must match the
    /// SDK: [`RERUN_VIEWER_INSTALL`].
    pub fn spawn(info: &RecordingInfo, pace: Pace) -> Result<Self, RecordError> {
        let options = rerun::SpawnOptions::default();
        find_viewer(
            &options.executable_name,
            std::env::var_os("PATH").as_deref(),
        )?;
        let stream = builder(info).spawn_opts(&options).map_err(|e| {
            RecordError::Viewer(format!(
                "could not start the Rerun viewer: {e} (the matching viewer is installed with \
                 `{RERUN_VIEWER_INSTALL}`)"
            ))
        })?;
        let live = Live {
            pace,
            start: None,
            last_flush: Instant::now(),
        };
        Self::start(
            stream,
            None,
            Some(live),
            PathBuf::from("Rerun viewer"),
            info,
        )
    }

    fn start(
        stream: RecordingStream,
        output: Option<AtomicPath>,
        live: Option<Live>,
        target: PathBuf,
        info: &RecordingInfo,
    ) -> Result<Self, RecordError> {
        let mut recorder = Self {
            stream,
            output,
            drawing: Drawing::new(info),
            columns: Columns::new(info),
            layout: FrameLayout::of(info),
            live,
            target,
        };
        recorder.log_static_entities()?;
        Ok(recorder)
    }

    fn error(&self, e: impl std::fmt::Display) -> RecordError {
        RecordError::format(&self.target, e)
    }

    fn log(&self, entity: &str, what: &impl AsComponents) -> Result<(), RecordError> {
        self.stream.log(entity, what).map_err(|e| self.error(e))
    }

    fn log_static(&self, entity: &str, what: &impl AsComponents) -> Result<(), RecordError> {
        self.stream
            .log_static(entity, what)
            .map_err(|e| self.error(e))
    }

    /// The y-up transform, the names and colours of the plotted series, and what of each
    /// body never changes: its centre of mass and spoke (body frame).
    fn log_static_entities(&mut self) -> Result<(), RecordError> {
        // Rerun's 2D views draw y downwards; mirror so that y (docs/physics.md §1) points up.
        self.log_static("world", &Transform3D::from_scale([1.0_f32, -1.0, 1.0]))?;
        for series in &self.columns.series {
            let colors = (0..series.names.len()).map(|i| rgb(palette(series.first_color + i)));
            self.log_static(
                series.entity,
                &SeriesLines::new()
                    .with_names(series.names.iter().map(String::as_str))
                    .with_colors(colors),
            )?;
        }
        // Appearance of the per-frame columns (static: applies at every time).
        let marker = self.drawing.marker_radius();
        self.log_static(
            "world/com",
            &Points2D::update_fields()
                .with_radii([1.5 * marker])
                .with_colors([Color::from_rgb(0, 0, 0)]),
        )?;
        if self.columns.spring_count > 0 {
            self.log_static(
                "world/springs",
                &LineStrips2D::update_fields().with_colors([Color::from_rgb(120, 120, 40)]),
            )?;
        }
        if !self.columns.prismatic.is_empty() {
            self.log_static(
                LINK_ENTITY,
                &LineStrips2D::update_fields()
                    .with_colors([rgb(LINK_COLOR)])
                    .with_radii([0.5 * marker]),
            )?;
        }
        // A prismatic joint's rail in its parent's frame: the extensions it may take.
        for (j, (parent, rail)) in self
            .columns
            .prismatic
            .iter()
            .filter_map(|j| Some((j, j.rail()?)))
        {
            let child = &self.drawing.bodies[j.body].entity;
            let child = child.rsplit('/').next().unwrap_or(child);
            self.log_static(
                &format!("{}/rail_{child}", self.drawing.bodies[parent].entity),
                &LineStrips2D::new([rail.map(f32_point)]).with_colors([rgb(RAIL_COLOR)]),
            )?;
        }
        if !self.drawing.contacts_empty {
            self.log_static(
                FORCE_ENTITY,
                &Arrows2D::update_fields().with_colors([rgb(FORCE_COLOR)]),
            )?;
        }
        for (b, body) in self.drawing.bodies.iter().enumerate() {
            let color = rgb(palette(b));
            self.log_static(
                &format!("{}/com", body.entity),
                &Points2D::new([[0.0_f32, 0.0]])
                    .with_colors([color])
                    .with_radii([marker]),
            )?;
            self.log_static(
                &format!("{}/spoke", body.entity),
                &LineStrips2D::new([[[0.0_f32, 0.0], [body.spoke_m as f32, 0.0]]])
                    .with_colors([color]),
            )?;
        }
        Ok(())
    }

    /// The terrain between the drawing's current bounds (static: shown at all times).
    fn log_terrain(&self) -> Result<(), RecordError> {
        let (x_lo, x_hi) = self.drawing.terrain.range;
        let (segments, corners) = terrain_pieces(&self.drawing.terrain_shape, x_lo, x_hi);
        let strips = segments.iter().map(|s| s.map(f32_point));
        self.log_static(
            "world/terrain",
            &LineStrips2D::new(strips).with_colors([rgb(TERRAIN_COLOR)]),
        )?;
        self.log_static(
            "world/terrain/corners",
            &Points2D::new(corners.into_iter().map(f32_point))
                .with_radii([self.drawing.marker_radius()])
                .with_colors([rgb(TERRAIN_COLOR)]),
        )
    }

    fn set_time(&self, t: f64, step: u64) {
        self.stream.set_duration_secs(TIME_TIMELINE, t.max(0.0));
        self.stream
            .set_time_sequence(STEP_TIMELINE, i64::try_from(step).unwrap_or(i64::MAX));
    }

    /// Clears the event markers whose hold time has passed at `t`.
    fn clear_expired_markers(&mut self, t: f64) -> Result<(), RecordError> {
        let mut markers = std::mem::take(&mut self.drawing.markers);
        let mut result = Ok(());
        markers.retain(|(entity, until)| {
            let expired = *until <= t;
            if expired && result.is_ok() {
                result = self.log(entity, &rerun::Clear::flat());
            }
            !expired
        });
        self.drawing.markers = markers;
        result
    }

    /// The outlines of every body whose shapes were switched since they were last logged
    /// (all of them at the first frame), in the body's frame: inactive shapes grey.
    fn log_outlines(&mut self, frame: &Frame<'_>) -> Result<(), RecordError> {
        if self.drawing.shapes_active.as_deref() == Some(frame.shapes_active) {
            return Ok(());
        }
        let before = self.drawing.shapes_active.take();
        let marker = self.drawing.marker_radius();
        let mut first = 0;
        for (b, body) in self.drawing.bodies.iter().enumerate() {
            let range = first..first + body.outlines.len();
            first = range.end;
            let active = &frame.shapes_active[range.clone()];
            if before.as_ref().is_some_and(|a| a[range] == *active) {
                continue;
            }
            let color = |on: bool| rgb(if on { palette(b) } else { INACTIVE_COLOR });
            let mut strips = Vec::new();
            let mut strip_colors = Vec::new();
            let mut points = Vec::new();
            let mut point_colors = Vec::new();
            for (outline, &on) in body.outlines.iter().zip(active) {
                match outline {
                    Outline::Strip(p) => {
                        strips.push(p.iter().copied().map(f32_point).collect::<Vec<_>>());
                        strip_colors.push(color(on));
                    }
                    Outline::Marker(p) => {
                        points.push(f32_point(*p));
                        point_colors.push(color(on));
                    }
                }
            }
            let path = &body.entity;
            if !strips.is_empty() {
                self.log(
                    &format!("{path}/outline"),
                    &LineStrips2D::new(strips).with_colors(strip_colors),
                )?;
            }
            if !points.is_empty() {
                self.log(
                    &format!("{path}/points"),
                    &Points2D::new(points)
                        .with_colors(point_colors)
                        .with_radii([marker]),
                )?;
            }
        }
        self.drawing.shapes_active = Some(frame.shapes_active.to_vec());
        Ok(())
    }

    /// Sends the buffered columns (nothing if none is buffered).
    fn flush(&mut self) -> Result<(), RecordError> {
        let result = self.columns.send(&self.stream, &self.drawing);
        result.map_err(|e| self.error(e))
    }
}

/// Entity paths of the time series.
const PLOT_POSITION: &str = "plots/position_m";
const PLOT_ANGLE: &str = "plots/angle_rad";
const PLOT_ENERGY: &str = "plots/energy_J";
const PLOT_BALANCE: &str = "plots/energy_balance_error_J";
const PLOT_IMPULSE: &str = "plots/impulse_Ns";
const PLOT_NORMAL_IMPULSE: &str = "plots/impulse_Ns/normal";
const PLOT_TANGENT_IMPULSE: &str = "plots/impulse_Ns/tangent";
/// Entity of the actuator's time series.
fn actuator_plot(actuator: ActuatorQuantity) -> &'static str {
    match actuator {
        ActuatorQuantity::Torque => "plots/actuator_torque_Nm",
        ActuatorQuantity::Force => "plots/actuator_force_N",
    }
}

/// Entity of the event log.
const EVENTS_ENTITY: &str = "events";
/// Entity of the contact-force arrows.
const FORCE_ENTITY: &str = "world/contacts/force";

/// What a time series shows, per frame.
#[derive(Clone, Debug, PartialEq)]
enum Quantity {
    /// These coordinates, lengths in metres (`x`, `y`, prismatic extensions).
    Lengths(Vec<usize>),
    /// These coordinates, angles (`φ, θ_1, …`) wrapped to (−π, π].
    Angles(Vec<usize>),
    /// These entries of [`EnergySample::values`].
    Energies(Vec<usize>),
    BalanceError,
    /// Λ_N (`false`) or Λ_T (`true`) of every contact, 0 when not in the index set.
    Impulses {
        tangent: bool,
    },
    Torque,
}

/// One time-series entity and its buffered column (`names.len()` values per frame).
struct Series {
    entity: &'static str,
    quantity: Quantity,
    names: Vec<String>,
    /// Palette index of the first series: series drawn in one panel differ in colour.
    first_color: usize,
    values: Vec<f64>,
}

impl Series {
    /// Appends the values of `frame`.
    fn push(&mut self, frame: &Frame<'_>) {
        let start = self.values.len();
        match &self.quantity {
            Quantity::Lengths(which) => self.values.extend(which.iter().map(|&i| frame.q[i])),
            Quantity::Angles(which) => {
                let angles = which.iter().map(|&i| wrap_angle(frame.q[i]));
                self.values.extend(angles);
            }
            Quantity::Energies(which) => {
                let e = frame.energy.values();
                self.values.extend(which.iter().map(|&i| e[i]));
            }
            Quantity::BalanceError => self.values.push(frame.energy.balance_error),
            Quantity::Impulses { tangent } => {
                self.values.resize(start + self.names.len(), 0.0);
                for c in frame.contacts {
                    let value = if *tangent {
                        c.impulse_tangent
                    } else {
                        c.impulse_normal
                    };
                    self.values[start + c.contact] = value;
                }
            }
            Quantity::Torque => self.values.push(frame.actuator_torque),
        }
    }
}

/// The series a scene has: positions and angles of its coordinates, the energies it can
/// have (spring energy with springs, actuator work and torque with a controller), the
/// balance error, contact impulses when it has contacts.
fn scene_series(info: &RecordingInfo) -> Vec<Series> {
    let series = |entity, quantity, names: Vec<String>, first_color| Series {
        entity,
        quantity,
        names,
        first_color,
        values: Vec::new(),
    };
    // Each coordinate in its unit: lengths in metres, angles in radians.
    let (lengths, angles): (Vec<usize>, Vec<usize>) = (0..info.coordinates.len())
        .partition(|&i| info.coordinate_units[i] == CoordinateUnit::Metre);
    let names = |which: &[usize]| which.iter().map(|&i| info.coordinates[i].clone()).collect();
    let mut all = Vec::new();
    if !lengths.is_empty() {
        let names = names(&lengths);
        all.push(series(PLOT_POSITION, Quantity::Lengths(lengths), names, 0));
    }
    if !angles.is_empty() {
        let names = names(&angles);
        all.push(series(PLOT_ANGLE, Quantity::Angles(angles), names, 0));
    }
    let energies: Vec<usize> = EnergySample::NAMES
        .iter()
        .enumerate()
        .filter(|&(_, &name)| match name {
            "spring" => !info.springs.is_empty(),
            "actuator_work" => info.actuated,
            "balance_error" => false,
            _ => true,
        })
        .map(|(i, _)| i)
        .collect();
    let names = energies
        .iter()
        .map(|&i| EnergySample::NAMES[i].replace('_', " "))
        .collect();
    all.push(series(PLOT_ENERGY, Quantity::Energies(energies), names, 0));
    let balance = vec!["balance error".to_string()];
    all.push(series(PLOT_BALANCE, Quantity::BalanceError, balance, 0));
    let n = info.contacts.len();
    if n > 0 {
        let names = |component: &str| {
            let names = info.contacts.iter().map(|c| format!("{component} {c}"));
            names.collect::<Vec<_>>()
        };
        let normal = Quantity::Impulses { tangent: false };
        all.push(series(PLOT_NORMAL_IMPULSE, normal, names("Λ_N"), 0));
        let tangent = Quantity::Impulses { tangent: true };
        all.push(series(PLOT_TANGENT_IMPULSE, tangent, names("Λ_T"), n));
    }
    if info.actuated {
        let torque = vec![info.actuator.words().to_string()];
        let entity = actuator_plot(info.actuator);
        all.push(series(entity, Quantity::Torque, torque, 0));
    }
    all
}

/// Everything that changes every frame, buffered in columns until sent.
struct Columns {
    times: Vec<f64>,
    steps: Vec<i64>,
    series: Vec<Series>,
    /// Per body: position (z = 0) and rotation about z.
    translations: Vec<Vec<[f32; 3]>>,
    rotations: Vec<Vec<Quaternion>>,
    com: Vec<[f32; 2]>,
    /// Spring segments, `springs` per frame.
    springs: Vec<[[f32; 2]; 2]>,
    spring_count: usize,
    /// The prismatic joints and their link segments, one per joint and frame.
    prismatic: Vec<JointInfo>,
    links: Vec<[[f32; 2]; 2]>,
    /// Contact-force arrows and how many each frame has.
    arrow_origins: Vec<[f32; 2]>,
    arrow_vectors: Vec<[f32; 2]>,
    arrows_per_frame: Vec<usize>,
}

impl Columns {
    fn new(info: &RecordingInfo) -> Self {
        let mut series = scene_series(info);
        for s in &mut series {
            s.values.reserve(CHUNK_FRAMES * s.names.len());
        }
        let bodies = info.bodies.len();
        Self {
            times: Vec::with_capacity(CHUNK_FRAMES),
            steps: Vec::with_capacity(CHUNK_FRAMES),
            series,
            translations: vec![Vec::with_capacity(CHUNK_FRAMES); bodies],
            rotations: vec![Vec::with_capacity(CHUNK_FRAMES); bodies],
            com: Vec::with_capacity(CHUNK_FRAMES),
            springs: Vec::with_capacity(CHUNK_FRAMES * info.springs.len()),
            spring_count: info.springs.len(),
            prismatic: prismatic_joints(info),
            links: Vec::with_capacity(CHUNK_FRAMES * prismatic_joints(info).len()),
            arrow_origins: Vec::new(),
            arrow_vectors: Vec::new(),
            arrows_per_frame: Vec::with_capacity(CHUNK_FRAMES),
        }
    }

    fn len(&self) -> usize {
        self.times.len()
    }

    /// Appends `frame`.
    fn push(&mut self, frame: &Frame<'_>, drawing: &Drawing) {
        self.times.push(frame.t.max(0.0));
        self.steps
            .push(i64::try_from(frame.step).unwrap_or(i64::MAX));
        for s in &mut self.series {
            s.push(frame);
        }
        for (b, pose) in frame.bodies.iter().enumerate() {
            let [x, y] = f32_point(pose.position);
            self.translations[b].push([x, y, 0.0]);
            let (sin, cos) = (0.5 * pose.angle).sin_cos();
            self.rotations[b].push(Quaternion::from_xyzw([0.0, 0.0, sin as f32, cos as f32]));
        }
        self.com.push(f32_point(frame.com));
        self.springs.extend(
            frame
                .springs
                .iter()
                .map(|(a, b)| [f32_point(*a), f32_point(*b)]),
        );
        self.links.extend(
            self.prismatic
                .iter()
                .map(|j| j.link(frame.bodies).map(f32_point)),
        );
        let before = self.arrow_origins.len();
        for c in frame.contacts {
            if let Some(v) = drawing.force_arrow(c.normal, c.impulse_normal, c.impulse_tangent) {
                self.arrow_origins.push(f32_point(c.point));
                self.arrow_vectors.push(f32_point(v));
            }
        }
        self.arrows_per_frame
            .push(self.arrow_origins.len() - before);
    }

    /// Sends every buffered column as one chunk per entity and empties the buffers.
    fn send(&mut self, stream: &RecordingStream, drawing: &Drawing) -> Result<(), String> {
        let rows = self.len();
        if rows == 0 {
            return Ok(());
        }
        let time = TimeColumn::new_duration_secs(TIME_TIMELINE, self.times.iter().copied());
        let step = TimeColumn::new_sequence(STEP_TIMELINE, self.steps.iter().copied());
        let send = |entity: &str,
                    columns: Result<
            Vec<SerializedComponentColumn>,
            rerun::SerializationError,
        >| {
            let columns = columns.map_err(|e| e.to_string())?;
            stream
                .send_columns(entity, [time.clone(), step.clone()], columns)
                .map_err(|e| e.to_string())
        };
        for s in &self.series {
            let scalars = Scalars::update_fields().with_scalars(s.values.iter().copied());
            let lengths = std::iter::repeat_n(s.names.len(), rows);
            send(s.entity, scalars.columns(lengths).map(Iterator::collect))?;
        }
        for (b, body) in drawing.bodies.iter().enumerate() {
            let transform = Transform3D::update_fields()
                .with_many_translation(self.translations[b].iter().copied())
                .with_many_quaternion(self.rotations[b].iter().copied());
            send(
                &body.entity,
                transform.columns_of_unit_batches().map(Iterator::collect),
            )?;
        }
        let com = Points2D::update_fields().with_positions(self.com.iter().copied());
        send(
            "world/com",
            com.columns_of_unit_batches().map(Iterator::collect),
        )?;
        if self.spring_count > 0 {
            let springs = LineStrips2D::update_fields().with_strips(self.springs.iter().copied());
            let lengths = std::iter::repeat_n(self.spring_count, rows);
            send(
                "world/springs",
                springs.columns(lengths).map(Iterator::collect),
            )?;
        }
        if !self.prismatic.is_empty() {
            let links = LineStrips2D::update_fields().with_strips(self.links.iter().copied());
            let lengths = std::iter::repeat_n(self.prismatic.len(), rows);
            send(LINK_ENTITY, links.columns(lengths).map(Iterator::collect))?;
        }
        if !drawing.contacts_empty {
            let arrows = Arrows2D::update_fields()
                .with_vectors(self.arrow_vectors.iter().copied())
                .with_origins(self.arrow_origins.iter().copied());
            let lengths = self.arrows_per_frame.iter().copied();
            send(FORCE_ENTITY, arrows.columns(lengths).map(Iterator::collect))?;
        }
        self.times.clear();
        self.steps.clear();
        for s in &mut self.series {
            s.values.clear();
        }
        self.translations.iter_mut().for_each(Vec::clear);
        self.rotations.iter_mut().for_each(Vec::clear);
        self.com.clear();
        self.springs.clear();
        self.links.clear();
        self.arrow_origins.clear();
        self.arrow_vectors.clear();
        self.arrows_per_frame.clear();
        Ok(())
    }
}

/// Application id and blueprint shared by file and viewer recordings.
fn builder(info: &RecordingInfo) -> RecordingStreamBuilder {
    RecordingStreamBuilder::new("hopsim")
        .recording_name(info.scene.clone())
        .enabled(true)
        .with_blueprint(blueprint(&scene_series(info)))
}

/// The prismatic joints of a recording (drawn as links).
fn prismatic_joints(info: &RecordingInfo) -> Vec<JointInfo> {
    info.joints
        .iter()
        .filter(|j| j.is_prismatic())
        .cloned()
        .collect()
}

/// Title of the panel of a time-series entity, with its unit.
fn panel_title(entity: &str) -> &'static str {
    match entity {
        PLOT_POSITION => "position, m",
        PLOT_ANGLE => "angles wrapped to (−π, π], rad",
        PLOT_ENERGY => "energy, J",
        PLOT_BALANCE => "energy balance error, J",
        PLOT_NORMAL_IMPULSE | PLOT_TANGENT_IMPULSE => "contact impulses Λ_N, Λ_T, N s",
        _ => "actuator torque, N m",
    }
}

/// The robot on the left; on the right one panel per time series the scene has (both
/// impulse components in one) and the event log; on the simulation time (the viewer
/// would otherwise pick the step timeline).
fn blueprint(series: &[Series]) -> Blueprint {
    let mut panels: Vec<ContainerLike> = Vec::new();
    for s in series {
        let origin = match s.entity {
            PLOT_TANGENT_IMPULSE => continue,
            PLOT_NORMAL_IMPULSE => PLOT_IMPULSE,
            entity => entity,
        };
        panels.push(
            TimeSeriesView::new(panel_title(s.entity))
                .with_origin(origin)
                .into(),
        );
    }
    panels.push(TextLogView::new("events").with_origin(EVENTS_ENTITY).into());
    let robot = Spatial2DView::new("robot")
        .with_origin("/")
        .with_contents(["/world/**"]);
    let right = Vertical::new(panels);
    Blueprint::new(Horizontal::new([robot.into(), right.into()]).with_column_shares([2.0_f32, 1.0]))
        .with_time_panel(TimePanel::new().with_timeline(TIME_TIMELINE))
}

/// The executable `name` in the folders of `path_var` (the value of `PATH`), or an error
/// saying how to install the viewer that matches the SDK.
fn find_viewer(name: &str, path_var: Option<&std::ffi::OsStr>) -> Result<PathBuf, RecordError> {
    path_var
        .into_iter()
        .flat_map(std::env::split_paths)
        .map(|dir| dir.join(name))
        .find(|candidate| candidate.is_file())
        .ok_or_else(|| {
            RecordError::Viewer(format!(
                "the Rerun viewer `{name}` is not on PATH; install the matching viewer with \
                 `{RERUN_VIEWER_INSTALL}`"
            ))
        })
}

fn f32_point(p: Point) -> [f32; 2] {
    [p[0] as f32, p[1] as f32]
}

fn rgb(c: [u8; 3]) -> Color {
    Color::from_rgb(c[0], c[1], c[2])
}

/// What is precomputed for drawing, and the little state drawing keeps between frames.
struct Drawing {
    bodies: Vec<BodyDrawing>,
    terrain_shape: hopsim_model::Terrain,
    terrain: TerrainCover,
    /// Size of the robot, m.
    robot_size_m: f64,
    /// Contact force arrow scale, m/N.
    arrow_scale_m_per_n: f64,
    max_arrow_m: f64,
    dt: f64,
    /// The scene has no contacts (no force arrows).
    contacts_empty: bool,
    /// The shapes' activity when the outlines were last logged (none before).
    shapes_active: Option<Vec<bool>>,
    /// The growing piece of the CoM trail and its number.
    trail: Vec<[f32; 2]>,
    trail_piece: usize,
    /// The robot's CoM at the last frame (where event markers are drawn).
    last_com: Option<[f32; 2]>,
    /// Event markers on view, with the simulation time at which each is cleared.
    markers: Vec<(String, f64)>,
}

struct BodyDrawing {
    /// `world/bodies/<name>`: the body's frame.
    entity: String,
    outlines: Vec<Outline>,
    /// Length of the body-fixed spoke, m.
    spoke_m: f64,
}

impl Drawing {
    fn new(info: &RecordingInfo) -> Self {
        let shapes = RobotShapes::of(info);
        let bodies = info
            .bodies
            .iter()
            .zip(shapes.outlines)
            .zip(shapes.spokes_m)
            .map(|((b, outlines), spoke_m)| BodyDrawing {
                entity: format!("world/bodies/{}", entity_part(&b.name)),
                outlines,
                spoke_m,
            })
            .collect();
        let robot_size_m = shapes.size_m;
        let weight = info.weight_newtons;
        let arrow_scale_m_per_n = if weight.is_finite() && weight > 0.0 {
            robot_size_m / weight
        } else {
            FALLBACK_ARROW_SCALE_M_PER_N
        };
        Self {
            bodies,
            terrain_shape: info.terrain.clone(),
            terrain: TerrainCover::new(robot_size_m),
            robot_size_m,
            arrow_scale_m_per_n,
            max_arrow_m: MAX_ARROW_ROBOT_SIZES * robot_size_m,
            dt: if info.dt > 0.0 { info.dt } else { 1.0 },
            contacts_empty: info.contacts.is_empty(),
            shapes_active: None,
            trail: Vec::new(),
            trail_piece: 0,
            last_com: None,
            markers: Vec::new(),
        }
    }

    fn marker_radius(&self) -> f32 {
        (0.02 * self.robot_size_m) as f32
    }

    /// The arrow of a contact's mean force `(Λ_N n + Λ_T t)/Δt` with `t = (n_y, −n_x)`
    /// (docs/physics.md §1), scaled and clipped; `None` for a contact without force.
    fn force_arrow(
        &self,
        normal: Point,
        normal_impulse: f64,
        tangent_impulse: f64,
    ) -> Option<Point> {
        let [nx, ny] = normal;
        let impulse = [
            normal_impulse * nx + tangent_impulse * ny,
            normal_impulse * ny - tangent_impulse * nx,
        ];
        let mut v = impulse.map(|x| x / self.dt * self.arrow_scale_m_per_n);
        let length = v[0].hypot(v[1]);
        if length > self.max_arrow_m {
            v = v.map(|x| x * self.max_arrow_m / length);
        }
        (length > 0.0).then_some(v)
    }

    /// Adds the CoM to the trail when it moved far enough; true if it did. A full piece
    /// is left as logged and a new one starts at its last point.
    fn extend_trail(&mut self, com: Point) -> bool {
        let p = f32_point(com);
        self.last_com = Some(p);
        let spacing = (0.02 * self.robot_size_m) as f32;
        let moved = self
            .trail
            .last()
            .is_none_or(|q| (p[0] - q[0]).hypot(p[1] - q[1]) >= spacing);
        if moved {
            if self.trail.len() >= TRAIL_PIECE_POINTS {
                let last = self.trail[self.trail.len() - 1];
                self.trail.clear();
                self.trail.push(last);
                self.trail_piece += 1;
            }
            self.trail.push(p);
        }
        moved
    }
}

/// `name` as one entity-path part (letters, digits, `_`, `-`; anything else becomes `_`).
fn entity_part(name: &str) -> String {
    name.chars()
        .map(|c| {
            if c.is_ascii_alphanumeric() || c == '-' {
                c
            } else {
                '_'
            }
        })
        .collect()
}

/// Colour of an event's marker.
fn event_color(kind: &EventKind) -> Color {
    match kind {
        EventKind::Touchdown { .. } => Color::from_rgb(44, 160, 44),
        EventKind::TakeOff => Color::from_rgb(31, 119, 180),
        EventKind::Brake { .. } => Color::from_rgb(214, 39, 40),
        EventKind::ShapeSwitch { .. } => Color::from_rgb(148, 103, 189),
        EventKind::ShapeContact { .. } => Color::from_rgb(140, 86, 75),
        EventKind::AppliedImpulse { .. } => Color::from_rgb(255, 127, 14),
        EventKind::JointLimit { .. } => Color::from_rgb(23, 190, 207),
        EventKind::EnergyCreated { .. } => Color::from_rgb(227, 119, 194),
        EventKind::IndeterminateFriction { .. } => Color::from_rgb(188, 189, 34),
    }
}

impl Recorder for RerunRecorder {
    fn frame(&mut self, frame: &Frame<'_>) -> Result<(), RecordError> {
        self.layout.check(frame).map_err(|m| self.error(m))?;
        if let Some(live) = &mut self.live {
            live.wait_for(frame.t);
        }
        self.set_time(frame.t, frame.step);
        if self.drawing.terrain.cover(frame.com[0]) {
            self.log_terrain()?;
        }
        self.log_outlines(frame)?;
        self.clear_expired_markers(frame.t)?;
        if self.drawing.extend_trail(frame.com) {
            let trail = LineStrips2D::new([self.drawing.trail.iter().copied()])
                .with_colors([Color::from_rgb(160, 160, 160)]);
            let piece = self.drawing.trail_piece;
            self.log(&format!("world/com/trail/{piece}"), &trail)?;
        }
        self.columns.push(frame, &self.drawing);
        let due = match &mut self.live {
            Some(live) => {
                let due = live.last_flush.elapsed() >= LIVE_FLUSH_INTERVAL;
                if due {
                    live.last_flush = Instant::now();
                }
                due
            }
            None => self.columns.len() >= CHUNK_FRAMES,
        };
        if due {
            self.flush()?;
        }
        Ok(())
    }

    fn event(&mut self, event: &Event) -> Result<(), RecordError> {
        self.set_time(event.t, event.step);
        let kind = event.kind.name();
        let text = format!(
            "t = {:.4} s, step {}: {kind} {}",
            event.t, event.step, event.kind
        );
        self.log(
            EVENTS_ENTITY,
            &TextLog::new(text).with_level(rerun::TextLogLevel::INFO),
        )?;
        // A marker at the robot's last recorded centre of mass, one entity per kind, shown
        // for EVENT_MARKER_HOLD_S.
        if let Some(at) = self.drawing.last_com {
            let entity = format!("world/events/{kind}");
            self.log(
                &entity,
                &Points2D::new([at])
                    .with_labels([kind])
                    .with_colors([event_color(&event.kind)])
                    .with_radii([2.0 * self.drawing.marker_radius()]),
            )?;
            let until = event.t + EVENT_MARKER_HOLD_S;
            let markers = &mut self.drawing.markers;
            match markers.iter_mut().find(|(e, _)| *e == entity) {
                Some(marker) => marker.1 = until,
                None => markers.push((entity, until)),
            }
        }
        Ok(())
    }

    fn finish(self: Box<Self>) -> Result<(), RecordError> {
        self.close()?.map_or(Ok(()), |output| Ok(output.commit()?))
    }

    fn finish_partial(self: Box<Self>, stop: &Stop) -> Result<Vec<PathBuf>, RecordError> {
        self.set_time(stop.t, stop.step);
        let text = stop.to_string();
        self.log(
            EVENTS_ENTITY,
            &TextLog::new(text.clone()).with_level(rerun::TextLogLevel::ERROR),
        )?;
        self.stream
            .send_property("stop", &TextDocument::new(text))
            .map_err(|e| self.error(e))?;
        match self.close()? {
            Some(output) => Ok(vec![output.commit_partial()?]),
            None => Ok(Vec::new()),
        }
    }
}

impl RerunRecorder {
    /// Sends what is buffered and closes the stream; the file to commit, if any.
    fn close(mut self: Box<Self>) -> Result<Option<AtomicPath>, RecordError> {
        self.flush()?;
        let Self {
            stream,
            output,
            target,
            ..
        } = *self;
        let err = |e: &dyn std::fmt::Display| RecordError::format(&target, e);
        match output {
            Some(output) => {
                stream.flush_blocking().map_err(|e| err(&e))?;
                // Closes the file sink, which writes the RRD footer.
                stream.disconnect();
                drop(stream);
                Ok(Some(output))
            }
            None => {
                stream
                    .flush_with_timeout(Duration::from_secs(30))
                    .map_err(|e| err(&e))?;
                Ok(None)
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use hopsim_model::Terrain;

    #[test]
    fn a_missing_viewer_says_how_to_install_it() {
        let dir = tempfile::tempdir().unwrap();
        let path = std::env::join_paths([dir.path()]).unwrap();
        let e = find_viewer("rerun", Some(&path)).unwrap_err().to_string();
        assert!(
            e.contains("not on PATH") && e.contains("pip install rerun-sdk==0.36.3"),
            "{e}"
        );
        assert!(find_viewer("rerun", None).is_err());
        std::fs::write(dir.path().join("rerun"), "").unwrap();
        assert_eq!(
            find_viewer("rerun", Some(&path)).unwrap(),
            dir.path().join("rerun")
        );
    }

    /// A recording without bodies, contacts or springs.
    fn empty_info() -> RecordingInfo {
        RecordingInfo {
            scene: String::new(),
            scene_path: String::new(),
            scene_text: String::new(),
            coordinates: vec![],
            coordinate_units: vec![],
            bodies: vec![],
            contacts: vec![],
            joints: vec![],
            springs: vec![],
            terrain: Terrain::flat(0.0),
            dt: 1e-3,
            weight_newtons: 0.0,
            actuated: false,
            actuator: ActuatorQuantity::Torque,
        }
    }

    #[test]
    fn event_markers_are_cleared_after_their_hold_time() {
        let dir = tempfile::tempdir().unwrap();
        let mut rec = RerunRecorder::save(&dir.path().join("run.rrd"), &empty_info()).unwrap();
        let frame = |t: f64| Frame {
            t,
            step: (t * 1e3).round() as u64,
            q: &[],
            u: &[],
            bodies: &[],
            com: [t, 0.1],
            contacts: &[],
            springs: &[],
            shapes_active: &[],
            energy: EnergySample::default(),
            actuator_torque: 0.0,
        };
        rec.frame(&frame(0.0)).unwrap();
        let event = |t: f64, kind: EventKind| Event { t, step: 0, kind };
        rec.event(&event(0.01, EventKind::TakeOff)).unwrap();
        rec.event(&event(0.05, EventKind::Brake { impulse: 0.05 }))
            .unwrap();
        rec.event(&event(0.06, EventKind::TakeOff)).unwrap();
        let on_view = |rec: &RerunRecorder| {
            let mut m: Vec<_> = rec.drawing.markers.iter().map(|(e, _)| e.clone()).collect();
            m.sort();
            m
        };
        assert_eq!(
            on_view(&rec),
            ["world/events/brake", "world/events/take_off"]
        );
        rec.frame(&frame(0.01 + EVENT_MARKER_HOLD_S)).unwrap();
        assert_eq!(
            on_view(&rec),
            ["world/events/brake", "world/events/take_off"],
            "the second take-off renewed its marker"
        );
        rec.frame(&frame(0.05 + EVENT_MARKER_HOLD_S)).unwrap();
        assert_eq!(on_view(&rec), ["world/events/take_off"]);
        rec.frame(&frame(0.06 + EVENT_MARKER_HOLD_S)).unwrap();
        assert!(on_view(&rec).is_empty());
        Box::new(rec).finish().unwrap();
    }

    /// A prismatic joint's link is drawn each frame from its anchor on the parent to the
    /// child's joint point. The parent at `(1, 2)` turned by 90°: its anchor `(0.1, 0)` is
    /// at `(1, 2.1)` and its axis `(0, −1)` points along world `+x`. The child at
    /// `(0.7, 2.1)`, also at 90°, has its joint point `(0, −0.2)` at `(0.9, 2.1)`: the
    /// link ends at `anchor + s axis` with `s = −0.1`.
    #[test]
    fn prismatic_links_go_from_the_anchor_to_the_joint_point() {
        let mut info = empty_info();
        info.bodies = ["cart", "slider"]
            .map(|name| crate::BodyInfo {
                name: name.into(),
                shapes: vec![],
            })
            .to_vec();
        info.joints = vec![JointInfo {
            body: 1,
            parent: Some(0),
            anchor_m: [0.1, 0.0],
            child_point_m: [0.0, -0.2],
            kind: crate::JointInfoKind::Prismatic {
                axis: [0.0, -1.0],
                stroke_m: [0.0, 0.5],
            },
        }];
        let half_pi = std::f64::consts::FRAC_PI_2;
        let poses = [
            crate::BodyPose {
                position: [1.0, 2.0],
                angle: half_pi,
            },
            crate::BodyPose {
                position: [0.7, 2.1],
                angle: half_pi,
            },
        ];
        let mut columns = Columns::new(&info);
        let frame = Frame {
            t: 0.0,
            step: 0,
            q: &[],
            u: &[],
            bodies: &poses,
            com: [0.0, 0.0],
            contacts: &[],
            springs: &[],
            shapes_active: &[],
            energy: EnergySample::default(),
            actuator_torque: 0.0,
        };
        columns.push(&frame, &Drawing::new(&info));
        let [a, b] = columns.links[0];
        let close =
            |p: [f32; 2], q: [f32; 2]| (p[0] - q[0]).abs() < 1e-6 && (p[1] - q[1]).abs() < 1e-6;
        assert!(close(a, [1.0, 2.1]), "{a:?}");
        assert!(close(b, [0.9, 2.1]), "{b:?}");
        // Its rail in the parent's frame: the anchor plus 0 to 0.5 along (0, −1).
        assert_eq!(info.joints[0].rail(), Some((0, [[0.1, 0.0], [0.1, -0.5]])));
    }

    #[test]
    fn series_and_panels_follow_what_the_scene_has() {
        let names = |info: &RecordingInfo| -> Vec<(&'static str, Vec<String>)> {
            scene_series(info)
                .into_iter()
                .map(|s| (s.entity, s.names))
                .collect()
        };
        // A passive point without contacts or springs: no impulse or torque panel, no
        // spring energy or actuator work.
        let mut info = empty_info();
        info.coordinates = ["x", "y"].map(String::from).to_vec();
        info.coordinate_units = vec![CoordinateUnit::Metre; 2];
        let passive = names(&info);
        assert_eq!(
            passive,
            [
                (PLOT_POSITION, vec!["x".to_string(), "y".to_string()]),
                (
                    PLOT_ENERGY,
                    ["kinetic", "potential", "dissipated"]
                        .map(String::from)
                        .to_vec()
                ),
                (PLOT_BALANCE, vec!["balance error".to_string()]),
            ]
        );
        info.coordinates.push("phi".into());
        info.coordinate_units.push(CoordinateUnit::Radian);
        info.contacts = vec!["disc/ground".into()];
        info.springs = vec!["spring".into()];
        info.actuated = true;
        let entities: Vec<_> = names(&info).into_iter().map(|(e, _)| e).collect();
        assert_eq!(
            entities,
            [
                PLOT_POSITION,
                PLOT_ANGLE,
                PLOT_ENERGY,
                PLOT_BALANCE,
                PLOT_NORMAL_IMPULSE,
                PLOT_TANGENT_IMPULSE,
                actuator_plot(ActuatorQuantity::Torque)
            ]
        );
        // Series sharing a panel get different colours.
        let series = scene_series(&info);
        let impulse_colors: Vec<_> = series
            .iter()
            .filter(|s| s.entity.starts_with(PLOT_IMPULSE))
            .map(|s| palette(s.first_color))
            .collect();
        assert_ne!(impulse_colors[0], impulse_colors[1]);
        assert_ne!(palette(0), palette(1), "x and y differ");
        assert_eq!(
            Drawing::new(&empty_info()).arrow_scale_m_per_n,
            FALLBACK_ARROW_SCALE_M_PER_N
        );
    }

    #[test]
    fn speeds_are_positive_factors_or_max() {
        assert_eq!("max".parse::<Pace>(), Ok(Pace::Unpaced));
        assert_eq!("0.5".parse::<Pace>(), Ok(Pace::Speed(0.5)));
        assert_eq!(Pace::default(), Pace::Speed(1.0));
        for bad in ["0", "-1", "inf", "NaN", "fast"] {
            let e = bad.parse::<Pace>().unwrap_err();
            assert!(e.contains("positive factor") && e.contains("max"), "{e}");
        }
    }

    /// A live stream at speed 4 takes a quarter of the simulated time, however fast the
    /// frames come; unpaced it does not wait.
    #[test]
    fn a_paced_stream_waits_for_the_wall_clock() {
        let mut live = Live {
            pace: Pace::Speed(4.0),
            start: None,
            last_flush: Instant::now(),
        };
        let started = Instant::now();
        for k in 0..=20 {
            live.wait_for(1.0 + 0.01 * k as f64);
        }
        let elapsed = started.elapsed().as_secs_f64();
        // 0.2 s simulated at speed 4: 0.05 s, plus sleeping overshoot (a few ms).
        assert!((0.05..0.2).contains(&elapsed), "{elapsed} s");
        live.pace = Pace::Unpaced;
        let started = Instant::now();
        live.wait_for(1e6);
        assert!(started.elapsed() < Duration::from_millis(10));
    }
}
