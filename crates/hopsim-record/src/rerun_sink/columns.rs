//! Column buffers: everything that changes every frame, buffered per entity and sent
//! as chunks ([`RecordingStream::send_columns`]).
//!
//! Each entity keeps its own rows ([`Track`]): a row equal to the two before it only moves
//! the end of their run, so a quantity that holds still (a constant torque, no contact in
//! flight, a fixed base) costs two rows per run. The viewer shows the latest row at or
//! before the time cursor and draws time series as lines between rows, so what it shows is
//! the same as with every row.

use super::drawing::{
    f32_point, Drawing, COM_ENTITY, CONTACTS_ENTITY, LINK_ENTITY, LOOPS_ENTITY, NORMAL_FORCE_ENTITY,
};
use super::{STEP_TIMELINE, TIME_TIMELINE};
use crate::geometry::{wrap_angle, CoordinateUnit};
use crate::{ActuatorQuantity, EnergySample, Frame, JointInfo, RecordingInfo};
use rerun::{
    Arrows2D, LineStrips2D, Quaternion, RecordingStream, Scalars, SerializationError,
    SerializedComponentColumn, TimeColumn, Transform3D,
};

/// Frames per chunk of the columns sent to a file.
pub(super) const CHUNK_FRAMES: usize = 20000;

/// Entity paths of the time series.
pub(super) const PLOT_POSITION: &str = "plots/position_m";
pub(super) const PLOT_ANGLE: &str = "plots/angle_rad";
pub(super) const PLOT_ENERGY: &str = "plots/energy_J";
pub(super) const PLOT_BALANCE: &str = "plots/energy_balance_error_J";
pub(super) const PLOT_CONTROLS: &str = "plots/controls";
pub(super) const PLOT_EFFORTS: &str = "plots/actuator_efforts";
/// Entity of the actuator's time series.
pub(super) fn actuator_plot(actuator: ActuatorQuantity) -> &'static str {
    match actuator {
        ActuatorQuantity::Torque => "plots/actuator_torque_Nm",
        ActuatorQuantity::Force => "plots/actuator_force_N",
    }
}

/// One entity's buffered rows: times, steps and a variable number of values per row.
pub(super) struct Track<T> {
    times: Vec<f64>,
    steps: Vec<i64>,
    pub(super) values: Vec<T>,
    lens: Vec<usize>,
    /// Some row was sent: later rows are sent even if empty (they clear what it showed).
    sent: bool,
}

impl<T: Copy + PartialEq> Track<T> {
    fn new(rows: usize, width: usize) -> Self {
        Self {
            times: Vec::with_capacity(rows),
            steps: Vec::with_capacity(rows),
            values: Vec::with_capacity(rows * width),
            lens: Vec::with_capacity(rows),
            sent: false,
        }
    }

    /// Appends a row at `(t, step)`; a row equal to the two before it replaces the time
    /// of the last one instead (the run's first and last rows are kept).
    pub(super) fn push(&mut self, t: f64, step: i64, row: impl IntoIterator<Item = T>) {
        let start = self.values.len();
        self.values.extend(row);
        let len = self.values.len() - start;
        let n = self.lens.len();
        if n >= 2 && self.lens[n - 1] == len && self.lens[n - 2] == len {
            let (last, before) = (start - len, start - 2 * len);
            let v = &self.values;
            if v[start..] == v[last..start] && v[last..start] == v[before..last] {
                self.values.truncate(start);
                self.times[n - 1] = t;
                self.steps[n - 1] = step;
                return;
            }
        }
        self.times.push(t);
        self.steps.push(step);
        self.lens.push(len);
    }

    /// Number of buffered rows.
    pub(super) fn rows(&self) -> usize {
        self.lens.len()
    }

    /// Sends the rows as one chunk of `entity` (the columns made by `columns` from the
    /// values and the row lengths) and empties the buffer. Rows are not sent before the
    /// first value: nothing is shown either way.
    fn send(
        &mut self,
        stream: &RecordingStream,
        entity: &str,
        columns: impl FnOnce(
            &[T],
            &[usize],
        ) -> Result<Vec<SerializedComponentColumn>, SerializationError>,
    ) -> Result<(), String> {
        if self.rows() > 0 && (self.sent || !self.values.is_empty()) {
            let time = TimeColumn::new_duration_secs(TIME_TIMELINE, self.times.iter().copied());
            let step = TimeColumn::new_sequence(STEP_TIMELINE, self.steps.iter().copied());
            let columns = columns(&self.values, &self.lens).map_err(|e| e.to_string())?;
            stream
                .send_columns(entity, [time, step], columns)
                .map_err(|e| e.to_string())?;
            self.sent = true;
        }
        self.times.clear();
        self.steps.clear();
        self.values.clear();
        self.lens.clear();
        Ok(())
    }
}

/// What a time series shows, per frame.
#[derive(Clone, Debug, PartialEq)]
pub(super) enum Quantity {
    /// These coordinates, lengths in metres (`x`, `y`, prismatic extensions).
    Lengths(Vec<usize>),
    /// These coordinates, angles (`φ, θ_1, …`) wrapped to (−π, π].
    Angles(Vec<usize>),
    /// These entries of [`EnergySample::values`].
    Energies(Vec<usize>),
    BalanceError,
    /// Λ_N of every contact, then Λ_T of every contact, 0 when not in the index set: rows
    /// of the contacts' entity, with their force arrows ([`Columns::push`]).
    Impulses,
    Torque,
    /// The model's actuators' controls, and their efforts at their joints.
    Controls,
    Efforts,
}

/// One time-series entity and its buffered rows (`names.len()` values per frame).
pub(super) struct Series {
    pub(super) entity: &'static str,
    pub(super) quantity: Quantity,
    pub(super) names: Vec<String>,
    /// Palette index of the first series: series drawn in one panel differ in colour.
    pub(super) first_color: usize,
    pub(super) track: Track<f64>,
}

impl Series {
    /// Appends the values of `frame`, rounded to single precision (7 significant digits,
    /// beyond what a plot shows; the MCAP and CSV recordings keep every digit).
    pub(super) fn push(&mut self, frame: &Frame<'_>, t: f64, step: i64) {
        let single = |v: f64| f64::from(v as f32);
        let track = &mut self.track;
        match &self.quantity {
            Quantity::Lengths(which) => {
                track.push(t, step, which.iter().map(|&i| single(frame.q[i])));
            }
            Quantity::Angles(which) => {
                let angles = which.iter().map(|&i| single(wrap_angle(frame.q[i])));
                track.push(t, step, angles);
            }
            Quantity::Energies(which) => {
                let e = frame.energy.values();
                track.push(t, step, which.iter().map(|&i| single(e[i])));
            }
            Quantity::BalanceError => track.push(t, step, [single(frame.energy.balance_error)]),
            Quantity::Impulses => {}
            Quantity::Torque => track.push(t, step, [single(frame.actuator_torque)]),
            Quantity::Controls => track.push(t, step, frame.controls.iter().map(|&c| single(c))),
            Quantity::Efforts => {
                track.push(t, step, frame.actuator_efforts.iter().map(|&e| single(e)));
            }
        }
    }
}

/// The series a scene has: positions and angles of its coordinates, the energies it can
/// have (spring energy with springs, actuator work and torque with a controller), the
/// balance error, contact impulses when it has contacts.
pub(super) fn scene_series(info: &RecordingInfo) -> Vec<Series> {
    let series = |entity, quantity, names: Vec<String>, first_color| Series {
        entity,
        quantity,
        names,
        first_color,
        track: Track::new(0, 0),
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
    if !info.contacts.is_empty() {
        let names = |component: &str| {
            let names = info.contacts.iter().map(|c| format!("{component} {c}"));
            names.collect::<Vec<_>>()
        };
        let names = [names("Λ_N"), names("Λ_T")].concat();
        all.push(series(CONTACTS_ENTITY, Quantity::Impulses, names, 0));
    }
    if info.actuated {
        let torque = vec![info.actuator.words().to_string()];
        let entity = actuator_plot(info.actuator);
        all.push(series(entity, Quantity::Torque, torque, 0));
    }
    if !info.actuators.is_empty() {
        let controls = info.actuators.iter().map(|a| a.name.clone()).collect();
        all.push(series(PLOT_CONTROLS, Quantity::Controls, controls, 0));
        let efforts = info.actuators.iter().map(|a| {
            let unit = match a.effort {
                ActuatorQuantity::Torque => "N m",
                ActuatorQuantity::Force => "N",
            };
            format!("{}, {unit}", a.name)
        });
        all.push(series(
            PLOT_EFFORTS,
            Quantity::Efforts,
            efforts.collect(),
            0,
        ));
    }
    all
}

/// Everything that changes every frame, buffered in columns until sent.
pub(super) struct Columns {
    /// Frames pushed since the columns were last sent.
    frames: usize,
    pub(super) series: Vec<Series>,
    /// Per body: position relative to the robot's centre of mass (z = 0) and rotation about
    /// z (a quaternion `x, y, z, w`).
    poses: Vec<Track<([f32; 3], [f32; 4])>>,
    /// The robot's centre of mass: the translation of its frame (`world/com`).
    com: Track<[f32; 3]>,
    /// Spring segments, `spring_count` per frame.
    springs: Track<[[f32; 2]; 2]>,
    pub(super) spring_count: usize,
    /// The prismatic joints and their link segments, one per joint and frame.
    pub(super) prismatic: Vec<JointInfo>,
    pub(super) links: Track<[[f32; 2]; 2]>,
    /// The loop joints drawn as segments (distance, slot) and their segments per frame.
    pub(super) rods: Vec<crate::LoopInfo>,
    /// The loop joints' points: per body in its frame, and the world points.
    pub(super) loop_markers: (Vec<Vec<[f64; 2]>>, Vec<[f64; 2]>),
    rod_segments: Track<[[f32; 2]; 2]>,
    /// The contacts' impulses and their force arrows, and the arrows of the normal force
    /// only where friction is indeterminate (`[origin, vector]`).
    contacts: Track<ContactValue>,
    contact_count: usize,
    normal_forces: Track<[[f32; 2]; 2]>,
}

/// A value of a row of the contacts' entity: an impulse (N s, a time series) or a force
/// arrow `[origin, vector]` (m). One entity holds both, so they share one row per frame.
#[derive(Clone, Copy, Debug, PartialEq)]
enum ContactValue {
    Impulse(f64),
    Force([[f32; 2]; 2]),
}

/// The impulses and the force arrows of a row of the contacts' entity, each in order.
fn split_contact_row(row: &[ContactValue]) -> (Vec<f64>, Vec<[[f32; 2]; 2]>) {
    let mut impulses = Vec::with_capacity(row.len());
    let mut forces = Vec::new();
    for value in row {
        match *value {
            ContactValue::Impulse(x) => impulses.push(x),
            ContactValue::Force(arrow) => forces.push(arrow),
        }
    }
    (impulses, forces)
}

impl Columns {
    pub(super) fn new(info: &RecordingInfo) -> Self {
        let mut series = scene_series(info);
        for s in &mut series {
            s.track = Track::new(CHUNK_FRAMES, s.names.len());
        }
        let prismatic = prismatic_joints(info);
        let contacts = info.contacts.len();
        Self {
            frames: 0,
            series,
            poses: (0..info.bodies.len())
                .map(|_| Track::new(CHUNK_FRAMES, 1))
                .collect(),
            com: Track::new(CHUNK_FRAMES, 1),
            springs: Track::new(CHUNK_FRAMES, info.springs.len()),
            spring_count: info.springs.len(),
            links: Track::new(CHUNK_FRAMES, prismatic.len()),
            prismatic,
            rod_segments: Track::new(CHUNK_FRAMES, info.loops.len()),
            rods: crate::loops::rods(info),
            loop_markers: crate::loops::markers(info),
            contacts: Track::new(CHUNK_FRAMES, 3 * contacts),
            contact_count: contacts,
            normal_forces: Track::new(CHUNK_FRAMES, 0),
        }
    }

    /// Frames pushed since the columns were last sent.
    pub(super) fn len(&self) -> usize {
        self.frames
    }

    /// Appends `frame`.
    pub(super) fn push(&mut self, frame: &Frame<'_>, drawing: &Drawing) {
        self.frames += 1;
        let t = frame.t.max(0.0);
        let step = i64::try_from(frame.step).unwrap_or(i64::MAX);
        for s in &mut self.series {
            s.push(frame, t, step);
        }
        let [cx, cy] = frame.com;
        for (track, pose) in self.poses.iter_mut().zip(frame.bodies) {
            let [x, y] = f32_point([pose.position[0] - cx, pose.position[1] - cy]);
            let (sin, cos) = (0.5 * pose.angle).sin_cos();
            track.push(t, step, [([x, y, 0.0], [0.0, 0.0, sin as f32, cos as f32])]);
        }
        let [x, y] = f32_point(frame.com);
        self.com.push(t, step, [[x, y, 0.0]]);
        let springs = frame.springs.iter();
        self.springs.push(
            t,
            step,
            springs.map(|(a, b)| [f32_point(*a), f32_point(*b)]),
        );
        let links = self
            .prismatic
            .iter()
            .map(|j| j.link(frame.bodies).map(f32_point));
        self.links.push(t, step, links);
        let rods = self
            .rods
            .iter()
            .map(|l| l.ends(frame.bodies).map(f32_point));
        self.rod_segments.push(t, step, rods);
        let n = self.contact_count;
        let impulse = |i: usize| {
            let sample = frame.contacts.iter().find(|c| c.contact == i % n);
            let value = sample.map_or(0.0, |c| {
                if i < n {
                    c.impulse_normal
                } else {
                    c.impulse_tangent
                }
            });
            // Single precision: 7 significant digits, beyond what a plot shows (the MCAP
            // and CSV recordings keep every digit).
            ContactValue::Impulse(f64::from(value as f32))
        };
        let arrow = |indeterminate: bool| {
            let contacts = frame.contacts.iter();
            contacts
                .filter(move |c| c.friction_indeterminate == indeterminate)
                .filter_map(move |c| {
                    // Without friction the tangential percussion is 0 (docs/physics.md
                    // §4.8); the arrow says so whatever the record holds.
                    let tangent = if indeterminate {
                        0.0
                    } else {
                        c.impulse_tangent
                    };
                    let v = drawing.force_arrow(c.normal, c.impulse_normal, tangent)?;
                    Some([f32_point(c.point), f32_point(v)])
                })
        };
        let forces = arrow(false).map(ContactValue::Force);
        self.contacts
            .push(t, step, (0..2 * n).map(impulse).chain(forces));
        self.normal_forces.push(t, step, arrow(true));
    }

    /// Sends every buffered column as one chunk per entity and empties the buffers.
    pub(super) fn send(
        &mut self,
        stream: &RecordingStream,
        drawing: &Drawing,
    ) -> Result<(), String> {
        self.frames = 0;
        for s in &mut self.series {
            s.track.send(stream, s.entity, |values, lens| {
                let scalars = Scalars::update_fields().with_scalars(values.iter().copied());
                scalars.columns(lens.iter().copied()).map(Iterator::collect)
            })?;
        }
        for (track, body) in self.poses.iter_mut().zip(&drawing.bodies) {
            track.send(stream, &body.entity, |poses, _| {
                Transform3D::update_fields()
                    .with_many_translation(poses.iter().map(|p| p.0))
                    .with_many_quaternion(poses.iter().map(|p| Quaternion::from_xyzw(p.1)))
                    .columns_of_unit_batches()
                    .map(Iterator::collect)
            })?;
        }
        self.com.send(stream, COM_ENTITY, |com, _| {
            Transform3D::update_fields()
                .with_many_translation(com.iter().copied())
                .columns_of_unit_batches()
                .map(Iterator::collect)
        })?;
        let strips = |segments: &[[[f32; 2]; 2]], lens: &[usize]| {
            let strips = LineStrips2D::update_fields().with_strips(segments.iter().copied());
            strips.columns(lens.iter().copied()).map(Iterator::collect)
        };
        self.springs.send(stream, "world/springs", strips)?;
        self.links.send(stream, LINK_ENTITY, strips)?;
        self.rod_segments.send(stream, LOOPS_ENTITY, strips)?;
        let arrows = |arrows: &[[[f32; 2]; 2]], lens: &[usize]| {
            Arrows2D::update_fields()
                .with_origins(arrows.iter().map(|a| a[0]))
                .with_vectors(arrows.iter().map(|a| a[1]))
                .columns(lens.iter().copied())
                .map(Iterator::collect)
        };
        self.contacts
            .send(stream, CONTACTS_ENTITY, |values, lens| {
                let (mut impulses, mut forces) = (Vec::new(), Vec::new());
                let (mut impulse_lens, mut force_lens) = (Vec::new(), Vec::new());
                let mut start = 0;
                for &len in lens {
                    let (row_impulses, row_forces) = split_contact_row(&values[start..start + len]);
                    impulse_lens.push(row_impulses.len());
                    force_lens.push(row_forces.len());
                    impulses.extend(row_impulses);
                    forces.extend(row_forces);
                    start += len;
                }
                let scalars = Scalars::update_fields().with_scalars(impulses);
                let mut columns: Vec<_> = scalars.columns(impulse_lens)?.collect();
                columns.extend(arrows(&forces, &force_lens)?);
                Ok(columns)
            })?;
        self.normal_forces.send(stream, NORMAL_FORCE_ENTITY, arrows)
    }
}

/// The prismatic joints of a recording (drawn as links).
pub(super) fn prismatic_joints(info: &RecordingInfo) -> Vec<JointInfo> {
    info.joints
        .iter()
        .filter(|j| j.is_prismatic())
        .cloned()
        .collect()
}

#[cfg(test)]
mod tests {
    use super::super::drawing::FALLBACK_ARROW_SCALE_M_PER_N;
    use super::super::tests::empty_info;
    use super::*;
    use crate::geometry::palette;

    /// The first frame of a run with these bodies and contacts.
    fn frame_at_rest<'a>(
        bodies: &'a [crate::BodyPose],
        contacts: &'a [crate::ContactSample],
    ) -> Frame<'a> {
        Frame {
            t: 0.0,
            step: 0,
            q: &[],
            u: &[],
            bodies,
            com: [0.0, 0.0],
            contacts,
            springs: &[],
            shapes_active: &[],
            energy: EnergySample::default(),
            actuator_torque: 0.0,
            controls: &[],
            actuator_efforts: &[],
        }
    }

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
        columns.push(&frame_at_rest(&poses, &[]), &Drawing::new(&info));
        let [a, b] = columns.links.values[0];
        let close =
            |p: [f32; 2], q: [f32; 2]| (p[0] - q[0]).abs() < 1e-6 && (p[1] - q[1]).abs() < 1e-6;
        assert!(close(a, [1.0, 2.1]), "{a:?}");
        assert!(close(b, [0.9, 2.1]), "{b:?}");
        // Its rail in the parent's frame: the anchor plus 0 to 0.5 along (0, −1).
        assert_eq!(info.joints[0].rail(), Some((0, [[0.1, 0.0], [0.1, -0.5]])));
    }

    /// A contact carrying the robot's weight draws an arrow as long as the robot along its
    /// force; one whose friction is indeterminate draws its normal force alone, apart; both
    /// contacts' impulses are plotted.
    #[test]
    fn force_arrows_show_the_normal_force_alone_where_friction_is_indeterminate() {
        let mut info = empty_info();
        info.contacts = vec!["foot/ground".into(), "guide/ground".into()];
        info.weight_newtons = 9.81;
        let drawing = Drawing::new(&info);
        let size = drawing.robot_size_m;
        // Λ = W Δt: the mean force over the step is the weight.
        let impulse = info.weight_newtons * info.dt;
        let sample = |contact, tangent, friction_indeterminate| crate::ContactSample {
            contact,
            point: [0.5, 0.0],
            normal: [0.0, 1.0],
            impulse_normal: impulse,
            impulse_tangent: tangent,
            state: "stick",
            friction_indeterminate,
        };
        // Λ_T = −3/4 Λ_N along t = (n_y, −n_x) = (1, 0): the force leans back.
        let contacts = [
            sample(0, -0.75 * impulse, false),
            sample(1, 0.5 * impulse, true),
        ];
        let mut columns = Columns::new(&info);
        columns.push(&frame_at_rest(&[], &contacts), &drawing);
        let close = |p: [f32; 2], q: [f64; 2]| {
            (f64::from(p[0]) - q[0]).abs() < 1e-6 * size
                && (f64::from(p[1]) - q[1]).abs() < 1e-6 * size
        };
        let (impulses, forces) = split_contact_row(&columns.contacts.values);
        assert_eq!(forces.len(), 1);
        assert!(close(forces[0][0], [0.5, 0.0]));
        assert!(close(forces[0][1], [-0.75 * size, size]), "{:?}", forces[0]);
        let normal = &columns.normal_forces.values;
        assert_eq!(normal.len(), 1);
        assert!(close(normal[0][1], [0.0, size]), "{:?}", normal[0]);
        let single = |x: f64| f64::from(x as f32);
        assert_eq!(
            impulses,
            [impulse, impulse, -0.75 * impulse, 0.5 * impulse].map(single)
        );
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
                CONTACTS_ENTITY,
                actuator_plot(ActuatorQuantity::Torque)
            ]
        );
        // Series sharing a panel get different colours.
        let series = scene_series(&info);
        let impulses = series.iter().find(|s| s.entity == CONTACTS_ENTITY).unwrap();
        assert_eq!(impulses.names, ["Λ_N disc/ground", "Λ_T disc/ground"]);
        assert_ne!(
            palette(impulses.first_color),
            palette(impulses.first_color + 1)
        );
        assert_ne!(palette(0), palette(1), "x and y differ");
        assert_eq!(
            Drawing::new(&empty_info()).arrow_scale_m_per_n,
            FALLBACK_ARROW_SCALE_M_PER_N
        );
    }

    /// The value the viewer shows at `t`: that of the latest kept row at or before `t`.
    fn shown_at(track: &Track<u8>, t: f64) -> Option<&[u8]> {
        let row = track.times.iter().rposition(|&s| s <= t)?;
        let start: usize = track.lens[..row].iter().sum();
        Some(&track.values[start..start + track.lens[row]])
    }

    proptest::proptest! {
        /// Dropping the inside of runs of equal rows changes nothing the viewer shows: at
        /// each frame's time the latest kept row is that frame's row, and a run costs at
        /// most two rows.
        #[test]
        fn trimmed_rows_show_every_frame(rows in proptest::collection::vec(
            proptest::collection::vec(0u8..2, 0..3), 1..60)) {
            let mut track = Track::new(0, 0);
            for (k, row) in rows.iter().enumerate() {
                track.push(k as f64, k as i64, row.iter().copied());
            }
            for (k, row) in rows.iter().enumerate() {
                proptest::prop_assert_eq!(shown_at(&track, k as f64), Some(row.as_slice()));
            }
            let runs = 1 + rows.windows(2).filter(|w| w[0] != w[1]).count();
            proptest::prop_assert!(track.rows() <= 2 * runs);
            proptest::prop_assert_eq!(track.times.last(), Some(&((rows.len() - 1) as f64)));
        }
    }
}
