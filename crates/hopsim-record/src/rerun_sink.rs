//! [`RerunRecorder`]: the run as a Rerun recording (`.rrd` file or live viewer), with the
//! robot drawn in 2D and time series of its state, energies and contact impulses
//! (entities and timelines in docs/recording.md).

use crate::frame::FrameLayout;
use crate::geometry::{terrain_pieces, to_world, Outline, Point};
use crate::{EnergySample, Event, EventKind, Frame, RecordError, Recorder, RecordingInfo};
use hopsim_io::AtomicPath;
use hopsim_model::Terrain;
use rerun::blueprint::{
    Blueprint, ContainerLike, Horizontal, Spatial2DView, TextLogView, TimePanel, TimeSeriesView,
    Vertical,
};
use rerun::{
    Arrows2D, AsComponents, Color, LineStrips2D, Points2D, RecordingStream, RecordingStreamBuilder,
    Scalars, SeriesLines, TextLog, Transform3D,
};
use std::path::{Path, PathBuf};
use std::time::Duration;

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
/// Colours of bodies, by body index (cycled).
const BODY_COLORS: [[u8; 3]; 6] = [
    [31, 119, 180],
    [255, 127, 14],
    [44, 160, 44],
    [148, 103, 189],
    [140, 86, 75],
    [227, 119, 194],
];
/// Colour of inactive shapes (a retracted cane).
const INACTIVE_COLOR: [u8; 3] = [170, 170, 170];

/// Streams a run to Rerun: a `.rrd` file ([`RerunRecorder::save`]) or a live viewer
/// ([`RerunRecorder::spawn`]).
pub struct RerunRecorder {
    /// Declared first so that it is dropped (and its file closed) before `output`.
    stream: RecordingStream,
    output: Option<AtomicPath>,
    drawing: Drawing,
    layout: FrameLayout,
    /// Where errors point: the `.rrd` path or "Rerun viewer".
    target: PathBuf,
}

impl RerunRecorder {
    /// Records to the `.rrd` file `path`, written under a temporary name and renamed into
    /// place by `finish`.
    pub fn save(path: &Path, info: &RecordingInfo) -> Result<Self, RecordError> {
        let output = AtomicPath::create(path)?;
        let stream = builder(info)
            .save(output.temporary())
            .map_err(|e| RecordError::format(path, e))?;
        Self::start(stream, Some(output), path.to_path_buf(), info)
    }

    /// Streams to a live Rerun viewer, started from the `rerun` executable on `PATH` (or
    /// reused if one listens on the default port). The viewer must match the SDK:
    /// [`RERUN_VIEWER_INSTALL`].
    pub fn spawn(info: &RecordingInfo) -> Result<Self, RecordError> {
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
        Self::start(stream, None, PathBuf::from("Rerun viewer"), info)
    }

    fn start(
        stream: RecordingStream,
        output: Option<AtomicPath>,
        target: PathBuf,
        info: &RecordingInfo,
    ) -> Result<Self, RecordError> {
        let mut recorder = Self {
            stream,
            output,
            drawing: Drawing::new(info),
            layout: FrameLayout::of(info),
            target,
        };
        recorder.log_static_entities(info)?;
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

    /// The y-up transform and the names of the plotted series.
    fn log_static_entities(&mut self, info: &RecordingInfo) -> Result<(), RecordError> {
        // Rerun's 2D views draw y downwards; mirror so that y (physics.md §1) points up.
        self.log_static("world", &Transform3D::from_scale([1.0_f32, -1.0, 1.0]))?;
        let (positions, angles) = info.coordinates.split_at(info.coordinates.len().min(2));
        let series = [
            (PLOT_POSITION, positions.to_vec()),
            (PLOT_ANGLE, angles.to_vec()),
            (PLOT_ENERGY, EnergySample::NAMES.map(String::from).to_vec()),
            (PLOT_NORMAL_IMPULSE, info.contacts.clone()),
            (PLOT_TANGENT_IMPULSE, info.contacts.clone()),
            (PLOT_TORQUE, vec!["actuator_torque".to_string()]),
        ];
        for (entity, names) in series {
            if !names.is_empty() {
                self.log_static(entity, &SeriesLines::new().with_names(names))?;
            }
        }
        Ok(())
    }

    /// The terrain between the drawing's current bounds (static: shown at all times).
    fn log_terrain(&self) -> Result<(), RecordError> {
        let (x_lo, x_hi) = self.drawing.terrain_range;
        let (segments, corners) = terrain_pieces(&self.drawing.terrain, x_lo, x_hi);
        let strips = segments.iter().map(|s| s.map(f32_point));
        self.log_static(
            "world/terrain",
            &LineStrips2D::new(strips).with_colors([Color::from_rgb(90, 90, 90)]),
        )?;
        self.log_static(
            "world/terrain/corners",
            &Points2D::new(corners.into_iter().map(f32_point))
                .with_radii([self.drawing.marker_radius()])
                .with_colors([Color::from_rgb(90, 90, 90)]),
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

    fn log_bodies(&self, frame: &Frame<'_>) -> Result<(), RecordError> {
        let marker = self.drawing.marker_radius();
        let mut shape_index = 0;
        for (b, (body, pose)) in self.drawing.bodies.iter().zip(frame.bodies).enumerate() {
            let active = &frame.shapes_active[shape_index..shape_index + body.outlines.len()];
            shape_index += body.outlines.len();
            let color = |on: bool| rgb(if on { body_color(b) } else { INACTIVE_COLOR });
            let world = |p: &Point| f32_point(to_world(pose, *p));
            let mut strips = Vec::new();
            let mut strip_colors = Vec::new();
            let mut points = Vec::new();
            let mut point_colors = Vec::new();
            for (outline, &on) in body.outlines.iter().zip(active) {
                match outline {
                    Outline::Strip(p) => {
                        strips.push(p.iter().map(world).collect::<Vec<_>>());
                        strip_colors.push(color(on));
                    }
                    Outline::Marker(p) => {
                        points.push(world(p));
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
            let com = f32_point(pose.position);
            self.log(
                &format!("{path}/com"),
                &Points2D::new([com])
                    .with_colors([color(true)])
                    .with_radii([marker]),
            )?;
            // A body-fixed spoke along the body's x axis: shows rotation of any body.
            let tip = world(&[body.spoke_m, 0.0]);
            self.log(
                &format!("{path}/spoke"),
                &LineStrips2D::new([[com, tip]]).with_colors([color(true)]),
            )?;
        }
        Ok(())
    }

    fn log_contacts(&self, frame: &Frame<'_>) -> Result<(), RecordError> {
        let d = &self.drawing;
        let mut origins = Vec::with_capacity(frame.contacts.len());
        let mut vectors = Vec::with_capacity(frame.contacts.len());
        for c in frame.contacts {
            let [nx, ny] = c.normal;
            // Λ = Λ_N n + Λ_T t with t = (n_y, -n_x) (physics.md §1), drawn as Λ/Δt.
            let impulse = [
                c.impulse_normal * nx + c.impulse_tangent * ny,
                c.impulse_normal * ny - c.impulse_tangent * nx,
            ];
            let mut v = impulse.map(|x| x / d.dt * d.arrow_scale_m_per_n);
            let length = v[0].hypot(v[1]);
            if length > d.max_arrow_m {
                v = v.map(|x| x * d.max_arrow_m / length);
            }
            if length > 0.0 {
                origins.push(f32_point(c.point));
                vectors.push(f32_point(v));
            }
        }
        self.log(
            "world/contacts/force",
            &Arrows2D::from_vectors(vectors)
                .with_origins(origins)
                .with_colors([Color::from_rgb(214, 39, 40)]),
        )
    }

    fn log_plots(&mut self, frame: &Frame<'_>) -> Result<(), RecordError> {
        let split = frame.q.len().min(2);
        self.log(
            PLOT_POSITION,
            &Scalars::new(frame.q[..split].iter().copied()),
        )?;
        if frame.q.len() > split {
            self.log(PLOT_ANGLE, &Scalars::new(frame.q[split..].iter().copied()))?;
        }
        self.log(PLOT_ENERGY, &Scalars::new(frame.energy.values()))?;
        self.log(PLOT_TORQUE, &Scalars::single(frame.actuator_torque))?;
        if !self.drawing.impulses.is_empty() {
            for (component, entity) in [(0, PLOT_NORMAL_IMPULSE), (1, PLOT_TANGENT_IMPULSE)] {
                self.drawing.impulses.fill(0.0);
                for c in frame.contacts {
                    let value = [c.impulse_normal, c.impulse_tangent][component];
                    self.drawing.impulses[c.contact] = value;
                }
                self.log(entity, &Scalars::new(self.drawing.impulses.iter().copied()))?;
            }
        }
        Ok(())
    }
}

/// Entity paths of the time series.
const PLOT_POSITION: &str = "plots/position_m";
const PLOT_ANGLE: &str = "plots/angle_rad";
const PLOT_ENERGY: &str = "plots/energy_J";
const PLOT_NORMAL_IMPULSE: &str = "plots/impulse_Ns/normal";
const PLOT_TANGENT_IMPULSE: &str = "plots/impulse_Ns/tangent";
const PLOT_TORQUE: &str = "plots/actuator_torque_Nm";
/// Entity of the event log.
const EVENTS_ENTITY: &str = "events";

/// Application id and blueprint shared by file and viewer recordings.
fn builder(info: &RecordingInfo) -> RecordingStreamBuilder {
    RecordingStreamBuilder::new("hopsim")
        .recording_name(info.scene.clone())
        .enabled(true)
        .with_blueprint(blueprint())
}

/// The robot on the left, time series and the event log on the right, on the simulation
/// time (the viewer would otherwise pick the step timeline).
fn blueprint() -> Blueprint {
    let plots: [ContainerLike; 5] = [
        ("position", PLOT_POSITION),
        ("angles", PLOT_ANGLE),
        ("energy", PLOT_ENERGY),
        ("contact impulses", "plots/impulse_Ns"),
        ("actuator torque", PLOT_TORQUE),
    ]
    .map(|(name, origin)| TimeSeriesView::new(name).with_origin(origin).into());
    let right = Vertical::new(
        plots
            .into_iter()
            .chain([TextLogView::new("events").with_origin(EVENTS_ENTITY).into()]),
    );
    let robot = Spatial2DView::new("robot")
        .with_origin("/")
        .with_contents(["/world/**"]);
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

fn body_color(body: usize) -> [u8; 3] {
    BODY_COLORS[body % BODY_COLORS.len()]
}

/// What is precomputed for drawing, and the little state drawing keeps between frames.
struct Drawing {
    bodies: Vec<BodyDrawing>,
    terrain: Terrain,
    /// Abscissae covered by the logged terrain, m (empty before the first frame).
    terrain_range: (f64, f64),
    /// Size of the robot: the largest reach of a shape from its body's CoM, m.
    robot_size_m: f64,
    /// Contact force arrow scale, m/N.
    arrow_scale_m_per_n: f64,
    max_arrow_m: f64,
    dt: f64,
    /// The growing piece of the CoM trail and its number.
    trail: Vec<[f32; 2]>,
    trail_piece: usize,
    /// The robot's CoM at the last frame (where event markers are drawn).
    last_com: Option<[f32; 2]>,
    /// Event markers on view, with the simulation time at which each is cleared.
    markers: Vec<(String, f64)>,
    /// Per-contact impulse buffer for the time series.
    impulses: Vec<f64>,
}

struct BodyDrawing {
    /// `world/bodies/<name>`.
    entity: String,
    outlines: Vec<Outline>,
    /// Length of the body-fixed spoke, m.
    spoke_m: f64,
}

impl Drawing {
    fn new(info: &RecordingInfo) -> Self {
        let bodies: Vec<BodyDrawing> = info
            .bodies
            .iter()
            .map(|b| {
                let outlines: Vec<Outline> = b.shapes.iter().map(|(_, s)| Outline::of(s)).collect();
                let reach = outlines.iter().map(Outline::reach).fold(0.0, f64::max);
                BodyDrawing {
                    entity: format!("world/bodies/{}", entity_part(&b.name)),
                    outlines,
                    spoke_m: reach,
                }
            })
            .collect();
        let reach = bodies.iter().map(|b| b.spoke_m).fold(0.0, f64::max);
        let robot_size_m = if reach > 0.0 { reach } else { 0.1 };
        let mut bodies = bodies;
        for body in &mut bodies {
            // A body without shapes (Robbit's flywheel) still gets a visible spoke.
            if body.spoke_m <= 0.0 {
                body.spoke_m = 0.5 * robot_size_m;
            }
        }
        let weight = info.weight_newtons;
        let arrow_scale_m_per_n = if weight.is_finite() && weight > 0.0 {
            robot_size_m / weight
        } else {
            FALLBACK_ARROW_SCALE_M_PER_N
        };
        Self {
            bodies,
            terrain: info.terrain.clone(),
            terrain_range: (f64::INFINITY, f64::NEG_INFINITY),
            robot_size_m,
            arrow_scale_m_per_n,
            max_arrow_m: MAX_ARROW_ROBOT_SIZES * robot_size_m,
            dt: if info.dt > 0.0 { info.dt } else { 1.0 },
            trail: Vec::new(),
            trail_piece: 0,
            last_com: None,
            markers: Vec::new(),
            impulses: vec![0.0; info.contacts.len()],
        }
    }

    fn marker_radius(&self) -> f32 {
        (0.02 * self.robot_size_m) as f32
    }

    /// Widens the terrain range so that it reaches well beyond `x` on both sides; true if
    /// it changed (and must be logged again). Grows geometrically, so it is redrawn rarely.
    fn cover(&mut self, x: f64) -> bool {
        if !x.is_finite() {
            return false;
        }
        // A few robot sizes: the 2D view fits what it shows, so a long terrain line would
        // shrink the robot to a dot.
        let margin = (3.0 * self.robot_size_m).max(0.5);
        let (lo, hi) = self.terrain_range;
        if lo.is_finite() && x - lo >= 0.5 * margin && hi - x >= 0.5 * margin {
            return false;
        }
        let width = if lo.is_finite() { hi - lo } else { 0.0 };
        self.terrain_range = if !lo.is_finite() {
            (x - margin, x + margin)
        } else if x - lo < 0.5 * margin {
            (x - margin.max(width), hi)
        } else {
            (lo, x + margin.max(width))
        };
        true
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
    }
}

impl Recorder for RerunRecorder {
    fn frame(&mut self, frame: &Frame<'_>) -> Result<(), RecordError> {
        self.layout.check(frame).map_err(|m| self.error(m))?;
        self.set_time(frame.t, frame.step);
        if self.drawing.cover(frame.com[0]) {
            self.log_terrain()?;
        }
        self.log_bodies(frame)?;
        self.clear_expired_markers(frame.t)?;
        let springs = frame
            .springs
            .iter()
            .map(|(a, b)| [f32_point(*a), f32_point(*b)]);
        if !frame.springs.is_empty() {
            self.log(
                "world/springs",
                &LineStrips2D::new(springs).with_colors([Color::from_rgb(120, 120, 40)]),
            )?;
        }
        let radius = self.drawing.marker_radius();
        self.log(
            "world/com",
            &Points2D::new([f32_point(frame.com)])
                .with_radii([1.5 * radius])
                .with_colors([Color::from_rgb(0, 0, 0)]),
        )?;
        if self.drawing.extend_trail(frame.com) {
            let trail = LineStrips2D::new([self.drawing.trail.iter().copied()])
                .with_colors([Color::from_rgb(160, 160, 160)]);
            let piece = self.drawing.trail_piece;
            self.log(&format!("world/com/trail/{piece}"), &trail)?;
        }
        self.log_contacts(frame)?;
        self.log_plots(frame)
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
                output.commit()?;
            }
            None => {
                stream
                    .flush_with_timeout(Duration::from_secs(30))
                    .map_err(|e| err(&e))?;
            }
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

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
            bodies: vec![],
            contacts: vec![],
            springs: vec![],
            terrain: Terrain::flat(0.0),
            dt: 1e-3,
            weight_newtons: 0.0,
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

    #[test]
    fn terrain_coverage_grows_ahead_of_the_robot_and_rarely() {
        let mut drawing = Drawing::new(&empty_info());
        assert!(drawing.cover(0.0));
        let (lo, hi) = drawing.terrain_range;
        assert!(lo <= -0.5 && hi >= 0.5);
        assert!(!drawing.cover(0.1), "well inside: no redraw");
        let redraws = (0..10_000)
            .filter(|&k| drawing.cover(k as f64 * 1e-2))
            .count();
        assert!(redraws <= 10, "{redraws} redraws over 100 m");
        assert!(drawing.terrain_range.1 >= 100.0 && drawing.terrain_range.0 <= -0.5);
        assert_eq!(drawing.arrow_scale_m_per_n, FALLBACK_ARROW_SCALE_M_PER_N);
    }
}
