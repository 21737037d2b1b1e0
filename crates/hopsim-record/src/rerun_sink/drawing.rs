//! Drawing the robot: what is logged once (outlines, spokes, rails, the terrain) and
//! the state drawing keeps between frames (force-arrow scale, trail, event markers).

use super::RerunRecorder;
use crate::geometry::{
    palette, terrain_pieces, Outline, Point, RobotShapes, TerrainCover, INACTIVE_COLOR, RAIL_COLOR,
    TERRAIN_COLOR,
};
use crate::{EventKind, Frame, RecordError, RecordingInfo};
use rerun::{Arrows2D, Color, LineStrips2D, Points2D, SeriesLines, Transform3D};

/// Force-arrow scale when the robot's weight is unknown, m/N.
pub(super) const FALLBACK_ARROW_SCALE_M_PER_N: f64 = 0.01;
/// Longest contact arrow, in robot sizes (touchdown impacts would dwarf the scene).
pub(super) const MAX_ARROW_ROBOT_SIZES: f64 = 3.0;
/// How long an event's marker stays in the robot view, s of simulation time (the event
/// log keeps every event).
pub(super) const EVENT_MARKER_HOLD_S: f64 = 0.1;
/// Points per logged piece of the centre-of-mass trail (`world/trail/<n>`): only the
/// growing piece is logged again, so the trail costs little however long the run.
pub(super) const TRAIL_PIECE_POINTS: usize = 100;
/// Spacing of the trail's points, in robot sizes: a point is added when the centre of mass
/// moved that far from the last one (a hop is many robot sizes long; the trail's end is
/// closer to the robot than its centre-of-mass marker is wide).
const TRAIL_SPACING_ROBOT_SIZES: f64 = 0.05;
/// Colour of the contact-force arrows.
pub(super) const FORCE_COLOR: [u8; 3] = [214, 39, 40];
/// The prismatic links: from each joint's anchor on the parent to the child's joint point.
pub(super) const LINK_ENTITY: &str = "world/joints";
pub(super) const LINK_COLOR: [u8; 3] = [60, 60, 60];
/// The loop joints (docs/physics.md §8): their rods (distance, slot) per frame, and under
/// it the markers of world points; the markers of body points are `<body>/loops`.
pub(super) const LOOPS_ENTITY: &str = "world/loops";

/// Entity of the contacts: their impulses (a time series) and force arrows.
pub(super) const CONTACTS_ENTITY: &str = "world/contacts";
/// Entity of the arrows of contacts whose friction is indeterminate (docs/physics.md
/// §4.8): their normal force only, labelled so.
pub(super) const NORMAL_FORCE_ENTITY: &str = "world/contacts/normal_force";
const NORMAL_FORCE_COLOR: [u8; 3] = [148, 103, 189];
const NORMAL_FORCE_LABEL: &str = "normal force only (friction indeterminate)";
/// The robot's centre of mass: a frame there with the world's axes (a translation per
/// frame) and a marker at its origin.
pub(super) const COM_ENTITY: &str = "world/com";
/// The frame of the robot view: the centre of mass, mirrored as `world` so that y points
/// up in the view centred on it. A static transform of its own: the viewer takes an
/// entity's transform from its latest row, so a mirror logged once beside the centre of
/// mass's per-frame translation would be lost.
pub(super) const ROBOT_VIEW_ENTITY: &str = "world/com/view";
/// The bodies, `<this>/<body>`, each placed relative to the robot's centre of mass: a body
/// that moves with it (Robbit's disc and flywheel) keeps a constant translation, which the
/// recording stores almost for free.
pub(super) const BODIES_ENTITY: &str = "world/com/bodies";
/// The centre-of-mass trail, in pieces `world/trail/<n>`.
pub(super) const TRAIL_ENTITY: &str = "world/trail";

impl RerunRecorder {
    /// The loop joints' markers of `radius`: each body's loop points in its frame, the
    /// world points under [`LOOPS_ENTITY`], and the rods' appearance.
    fn log_loop_markers(&mut self, radius: f32) -> Result<(), RecordError> {
        let (on_bodies, on_world) = self.columns.loop_markers.clone();
        let points = |pins: &[Point]| {
            Points2D::new(pins.iter().map(|p| f32_point(*p)))
                .with_colors([rgb(crate::loops::LOOP_COLOR)])
                .with_radii([radius])
        };
        for (b, pins) in on_bodies.iter().enumerate() {
            if !pins.is_empty() {
                let entity = format!("{}/loops", self.drawing.bodies[b].entity);
                self.log_static(&entity, &points(pins))?;
            }
        }
        if !on_world.is_empty() {
            self.log_static(&format!("{LOOPS_ENTITY}/world"), &points(&on_world))?;
        }
        if !self.columns.rods.is_empty() {
            self.log_static(
                LOOPS_ENTITY,
                &LineStrips2D::update_fields()
                    .with_colors([rgb(crate::loops::LOOP_COLOR)])
                    .with_radii([0.5 * radius]),
            )?;
        }
        Ok(())
    }

    /// The y-up transform, the names and colours of the plotted series, and what of each
    /// body never changes: its centre of mass and spoke (body frame).
    pub(super) fn log_static_entities(&mut self) -> Result<(), RecordError> {
        // Rerun's 2D views draw y downwards; mirror so that y (docs/physics.md §1) points up,
        // in the views of the world and of the centre of mass.
        let mirror = Transform3D::update_fields().with_scale([1.0_f32, -1.0, 1.0]);
        self.log_static("world", &mirror)?;
        self.log_static(ROBOT_VIEW_ENTITY, &mirror)?;
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
            COM_ENTITY,
            &Points2D::new([[0.0_f32, 0.0]])
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
        self.log_loop_markers(1.5 * marker)?;
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
                CONTACTS_ENTITY,
                &Arrows2D::update_fields().with_colors([rgb(FORCE_COLOR)]),
            )?;
            self.log_static(
                NORMAL_FORCE_ENTITY,
                &Arrows2D::update_fields()
                    .with_colors([rgb(NORMAL_FORCE_COLOR)])
                    .with_labels([NORMAL_FORCE_LABEL]),
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
    pub(super) fn log_terrain(&self) -> Result<(), RecordError> {
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

    /// Clears the event markers whose hold time has passed at `t`.
    pub(super) fn clear_expired_markers(&mut self, t: f64) -> Result<(), RecordError> {
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
    pub(super) fn log_outlines(&mut self, frame: &Frame<'_>) -> Result<(), RecordError> {
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
}

pub(super) fn f32_point(p: Point) -> [f32; 2] {
    [p[0] as f32, p[1] as f32]
}

pub(super) fn rgb(c: [u8; 3]) -> Color {
    Color::from_rgb(c[0], c[1], c[2])
}

/// What is precomputed for drawing, and the little state drawing keeps between frames.
pub(super) struct Drawing {
    pub(super) bodies: Vec<BodyDrawing>,
    pub(super) terrain_shape: hopsim_model::Terrain,
    pub(super) terrain: TerrainCover,
    /// Size of the robot, m.
    pub(super) robot_size_m: f64,
    /// Contact force arrow scale, m/N.
    pub(super) arrow_scale_m_per_n: f64,
    pub(super) max_arrow_m: f64,
    pub(super) dt: f64,
    /// The scene has no contacts (no force arrows).
    pub(super) contacts_empty: bool,
    /// The shapes' activity when the outlines were last logged (none before).
    pub(super) shapes_active: Option<Vec<bool>>,
    /// The growing piece of the CoM trail and its number.
    pub(super) trail: Vec<[f32; 2]>,
    pub(super) trail_piece: usize,
    /// The robot's CoM at the last frame (where event markers are drawn).
    pub(super) last_com: Option<[f32; 2]>,
    /// Event markers on view, with the simulation time at which each is cleared.
    pub(super) markers: Vec<(String, f64)>,
}

pub(super) struct BodyDrawing {
    /// `world/com/bodies/<name>`: the body's frame.
    pub(super) entity: String,
    pub(super) outlines: Vec<Outline>,
    /// Length of the body-fixed spoke, m.
    pub(super) spoke_m: f64,
}

impl Drawing {
    pub(super) fn new(info: &RecordingInfo) -> Self {
        let shapes = RobotShapes::of(info);
        let bodies = info
            .bodies
            .iter()
            .zip(shapes.outlines)
            .zip(shapes.spokes_m)
            .map(|((b, outlines), spoke_m)| BodyDrawing {
                entity: format!("{BODIES_ENTITY}/{}", entity_part(&b.name)),
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

    /// How far the robot reaches from its centre of mass at `frame`, m: the largest
    /// distance of a body's centre of mass from it plus that body's reach.
    pub(super) fn robot_extent(&self, frame: &Frame<'_>) -> f64 {
        let [cx, cy] = frame.com;
        let reach = self.bodies.iter().zip(frame.bodies).map(|(body, pose)| {
            let [x, y] = pose.position;
            (x - cx).hypot(y - cy) + body.spoke_m
        });
        let extent = reach.fold(0.0, f64::max);
        if extent.is_finite() && extent > 0.0 {
            extent
        } else {
            self.robot_size_m
        }
    }

    pub(super) fn marker_radius(&self) -> f32 {
        (0.02 * self.robot_size_m) as f32
    }

    /// The arrow of a contact's mean force `(Λ_N n + Λ_T t)/Δt` with `t = (n_y, −n_x)`
    /// (docs/physics.md §1), scaled and clipped; `None` for a contact without force.
    pub(super) fn force_arrow(
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
    pub(super) fn extend_trail(&mut self, com: Point) -> bool {
        let p = f32_point(com);
        self.last_com = Some(p);
        let spacing = (TRAIL_SPACING_ROBOT_SIZES * self.robot_size_m) as f32;
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
pub(super) fn entity_part(name: &str) -> String {
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
pub(super) fn event_color(kind: &EventKind) -> Color {
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

#[cfg(test)]
mod tests {
    use super::super::tests::empty_info;
    use super::*;

    /// The trail of a centre of mass moving along a parabola: its points are at least the
    /// spacing apart (the robot moves less between two of them than the marker is wide),
    /// each piece holds at most `TRAIL_PIECE_POINTS` and starts where the one before ended,
    /// and the pieces together pass within one spacing of every position.
    #[test]
    fn the_trail_follows_the_centre_of_mass_in_pieces() {
        let mut drawing = Drawing::new(&empty_info());
        let spacing = TRAIL_SPACING_ROBOT_SIZES * drawing.robot_size_m;
        // The centre-of-mass marker has radius 1.5 marker radii.
        let marker_width = 3.0 * f64::from(drawing.marker_radius());
        assert!(
            spacing < marker_width,
            "{spacing} m, marker {marker_width} m"
        );
        let mut pieces: Vec<Vec<[f32; 2]>> = vec![];
        let path = |k: usize| {
            let x = 0.002 * k as f64;
            [x, 0.5 - (x - 1.0).powi(2)]
        };
        for k in 0..3000 {
            if drawing.extend_trail(path(k)) {
                pieces.truncate(drawing.trail_piece);
                pieces.push(drawing.trail.clone());
            }
            let end = drawing.trail[drawing.trail.len() - 1];
            let [x, y] = path(k);
            let lag = (x - f64::from(end[0])).hypot(y - f64::from(end[1]));
            assert!(lag < spacing + 1e-6, "frame {k}: {lag} m behind");
        }
        assert!(pieces.len() > 2, "{} pieces", pieces.len());
        for (a, b) in pieces.iter().zip(&pieces[1..]) {
            assert_eq!(a.len(), TRAIL_PIECE_POINTS);
            assert_eq!(a.last(), b.first());
        }
        for piece in &pieces {
            for w in piece.windows(2) {
                let d = f64::from(w[1][0] - w[0][0]).hypot(f64::from(w[1][1] - w[0][1]));
                assert!(d >= spacing * (1.0 - 1e-6), "{d} < {spacing}");
            }
        }
    }
}
