//! Column buffers: everything that changes every frame, buffered per entity and sent
//! as chunks ([`RecordingStream::send_columns`]).

use super::drawing::{f32_point, Drawing, FORCE_ENTITY, LINK_ENTITY};
use super::{STEP_TIMELINE, TIME_TIMELINE};
use crate::geometry::{wrap_angle, CoordinateUnit};
use crate::{ActuatorQuantity, EnergySample, Frame, JointInfo, RecordingInfo};
use rerun::{
    Arrows2D, LineStrips2D, Points2D, Quaternion, RecordingStream, Scalars,
    SerializedComponentColumn, TimeColumn, Transform3D,
};

/// Frames per chunk of the columns sent to a file.
pub(super) const CHUNK_FRAMES: usize = 1000;

/// Entity paths of the time series.
pub(super) const PLOT_POSITION: &str = "plots/position_m";
pub(super) const PLOT_ANGLE: &str = "plots/angle_rad";
pub(super) const PLOT_ENERGY: &str = "plots/energy_J";
pub(super) const PLOT_BALANCE: &str = "plots/energy_balance_error_J";
pub(super) const PLOT_IMPULSE: &str = "plots/impulse_Ns";
pub(super) const PLOT_NORMAL_IMPULSE: &str = "plots/impulse_Ns/normal";
pub(super) const PLOT_TANGENT_IMPULSE: &str = "plots/impulse_Ns/tangent";
/// Entity of the actuator's time series.
pub(super) fn actuator_plot(actuator: ActuatorQuantity) -> &'static str {
    match actuator {
        ActuatorQuantity::Torque => "plots/actuator_torque_Nm",
        ActuatorQuantity::Force => "plots/actuator_force_N",
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
    /// Λ_N (`false`) or Λ_T (`true`) of every contact, 0 when not in the index set.
    Impulses {
        tangent: bool,
    },
    Torque,
}

/// One time-series entity and its buffered column (`names.len()` values per frame).
pub(super) struct Series {
    pub(super) entity: &'static str,
    pub(super) quantity: Quantity,
    pub(super) names: Vec<String>,
    /// Palette index of the first series: series drawn in one panel differ in colour.
    pub(super) first_color: usize,
    pub(super) values: Vec<f64>,
}

impl Series {
    /// Appends the values of `frame`.
    pub(super) fn push(&mut self, frame: &Frame<'_>) {
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
pub(super) fn scene_series(info: &RecordingInfo) -> Vec<Series> {
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
pub(super) struct Columns {
    pub(super) times: Vec<f64>,
    pub(super) steps: Vec<i64>,
    pub(super) series: Vec<Series>,
    /// Per body: position (z = 0) and rotation about z.
    pub(super) translations: Vec<Vec<[f32; 3]>>,
    pub(super) rotations: Vec<Vec<Quaternion>>,
    pub(super) com: Vec<[f32; 2]>,
    /// Spring segments, `springs` per frame.
    pub(super) springs: Vec<[[f32; 2]; 2]>,
    pub(super) spring_count: usize,
    /// The prismatic joints and their link segments, one per joint and frame.
    pub(super) prismatic: Vec<JointInfo>,
    pub(super) links: Vec<[[f32; 2]; 2]>,
    /// Contact-force arrows and how many each frame has.
    pub(super) arrow_origins: Vec<[f32; 2]>,
    pub(super) arrow_vectors: Vec<[f32; 2]>,
    pub(super) arrows_per_frame: Vec<usize>,
}

impl Columns {
    pub(super) fn new(info: &RecordingInfo) -> Self {
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

    pub(super) fn len(&self) -> usize {
        self.times.len()
    }

    /// Appends `frame`.
    pub(super) fn push(&mut self, frame: &Frame<'_>, drawing: &Drawing) {
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
    pub(super) fn send(
        &mut self,
        stream: &RecordingStream,
        drawing: &Drawing,
    ) -> Result<(), String> {
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
}
