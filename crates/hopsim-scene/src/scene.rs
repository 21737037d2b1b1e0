//! The validated scene and how it is built from the file (`docs/scene-format.md`).

use crate::bodies::{read_bodies, read_shapes, read_springs, Names, ShapeSpec, MAX_SHAPES};
use crate::body_contacts::read_body_contacts;
use crate::controller::read_controller;
use crate::environment::read_environment;
use crate::error::{SceneError, Source};
use crate::overrides::{apply, Override};
use crate::reader::Table;
use crate::settings::{read_meta, read_settings, Meta, Settings};
use crate::start::{check_start, velocity, StartProblem, COORDINATE, PENETRATION_TOL};
use crate::tree::Node;
use hopsim_control::ControllerConfig;
use hopsim_model::{Kinematics, Model, ModelBuilder, ModelError, Vec2};
use hopsim_step::{State, StepSettings};
use nalgebra::DVector;
use std::path::{Path, PathBuf};

/// Largest scene file [`load`] reads, bytes (8 MiB: a hundred times the largest sensible
/// scene; `/dev/zero` or an endless pipe stops here instead of exhausting memory).
pub const MAX_SCENE_BYTES: u64 = 8 << 20;
/// Most potential contacts (shape features × terrain features) a scene may create: the
/// contact LCP is dense, its matrices grow with the square of this count.
pub const MAX_CONTACTS: usize = 1000;

/// A scene ready to simulate: model, initial state, controller and settings.
#[derive(Clone, Debug)]
pub struct Scene {
    /// The scene file.
    pub path: PathBuf,
    /// The file's text as read (overrides not applied), stored in recordings.
    pub text: String,
    /// The overrides applied on top of the file.
    pub overrides: Vec<Override>,
    /// `[meta]`.
    pub meta: Meta,
    /// Title for summaries and viewers (`meta.title`).
    pub title: String,
    /// `[simulation]`.
    pub settings: Settings,
    /// The multibody model.
    pub model: Model,
    /// Initial state (time zero).
    pub initial: State,
    /// The controller's settings.
    pub controller: ControllerConfig,
    /// Shapes the controller switches (canes); they start switched off.
    pub switchable: Vec<usize>,
    /// Names of the generalised coordinates, e.g. `["x", "y", "phi", "psi"]`.
    pub coordinates: Vec<String>,
}

impl Scene {
    /// The stepper's settings for this scene.
    pub fn step_settings(&self) -> StepSettings {
        StepSettings {
            dt: self.settings.dt,
            strict: self.settings.strict,
            max_speed: self.settings.max_speed,
            warm_start: self.settings.warm_start,
            ..StepSettings::default()
        }
    }
}

/// Reads and validates the scene file at `path` with `overrides` applied. Reads at most
/// [`MAX_SCENE_BYTES`].
pub fn load(path: &Path, overrides: &[Override]) -> Result<Scene, SceneError> {
    let text = read_bounded(path, MAX_SCENE_BYTES)?;
    parse(&text, path, overrides)
}

/// The text of the file at `path`: at most `limit` bytes of UTF-8 without NUL bytes. A
/// regular file above the limit is refused unread; any other input (a pipe, a device) is
/// read in blocks and refused at its first NUL byte or at the limit.
fn read_bounded(path: &Path, limit: u64) -> Result<String, SceneError> {
    hopsim_io::read_text_bounded(path, limit, "scene files").map_err(|source| SceneError::Io {
        path: path.to_path_buf(),
        source,
    })
}

/// Validates scene `text` (read from `path`, which names it in errors) with `overrides`.
pub fn parse(text: &str, path: &Path, overrides: &[Override]) -> Result<Scene, SceneError> {
    let src = Source { path, text };
    let mut root = Node::parse_document(text).map_err(|(message, span)| SceneError::Syntax {
        location: src.locate_offset(span.map_or(0, |s| s.start)),
        message,
    })?;
    for ov in overrides {
        apply(&mut root, ov)?;
    }
    let top = Table::root(src, &root);
    top.allow_only(&[
        "meta",
        "simulation",
        "summary",
        "environment",
        "bodies",
        "shapes",
        "springs",
        "body_contacts",
        "contact_pairs",
        "controller",
        "initial",
    ])?;
    let stem = path
        .file_stem()
        .map_or("scene".into(), |s| s.to_string_lossy());
    let meta = read_meta(top.opt_table("meta")?, &stem)?;
    let sim = top.table_or_empty("simulation")?;
    let summary = top.table_or_empty("summary")?;
    let settings = read_settings(&sim, &summary)?;
    sim.finish()?;
    summary.finish()?;
    let env = top.table_or_empty("environment")?;
    let (terrain, material) = read_environment(&env)?;
    env.finish()?;

    let mut body_names = Names::new(("body", "bodies"));
    let body_tables = top.tables("bodies")?;
    let (bodies, coordinates) = read_bodies(&top, &body_tables, &mut body_names)?;
    let mut shape_names = Names::new(("shape", "shapes"));
    let shape_tables = top.tables("shapes")?;
    let shapes = read_shapes(&shape_tables, &body_names, &mut shape_names, material)?;
    let spring_tables = top.tables("springs")?;
    let springs = read_springs(&spring_tables, &body_names)?;
    let control = top.table_or_empty("controller")?;
    let controller = read_controller(&control, &bodies, &body_names, &shapes, &shape_names)?;

    let instances = shapes.iter().map(|s| s.instance.clone()).collect();
    let gravity = Vec2::new(0.0, -settings.gravity);
    let mut builder = ModelBuilder::new(bodies, instances, terrain, springs, gravity, material)
        .map_err(|e| {
            // The scene's own checks come first; should the model still object, place
            // the error at the table it is about.
            let find = |tables: &[Table<'_>], name: &str| {
                tables
                    .iter()
                    .position(|t| t.opt_str("name").ok().flatten() == Some(name))
            };
            let at = match &e {
                ModelError::BadShape { shape, .. } => find(&shape_tables, shape)
                    .or_else(|| shape_names.find(shape))
                    .map(|i| &shape_tables[i]),
                ModelError::BadSpring { spring, .. } => {
                    find(&spring_tables, spring).map(|i| &spring_tables[i])
                }
                ModelError::NonPositive { body, .. }
                | ModelError::BadParent { body, .. }
                | ModelError::BadJoint { body, .. } => {
                    body_names.find(body).map(|i| &body_tables[i])
                }
                _ => None,
            };
            match at {
                Some(t) => t.error_here(e.to_string()),
                None => top.error_at_key("bodies", e.to_string()),
            }
        })?;
    let terrain_contacts = builder.model().contacts();
    if terrain_contacts.len() > MAX_CONTACTS {
        let first_extra = terrain_contacts[MAX_CONTACTS].shape;
        return Err(shape_tables[first_extra].error_here(format!(
            "the shapes make {} potential contacts with the terrain (a contact per shape \
             feature and terrain feature); a scene may have at most {MAX_CONTACTS} (and at \
             most {MAX_SHAPES} shapes)",
            terrain_contacts.len()
        )));
    }
    for (s, shape) in shapes.iter().enumerate() {
        builder.set_shape_material(s, shape.material);
    }
    read_body_contacts(&top, &shapes, &shape_names, &mut builder)?;
    let model = builder.build();
    let switchable: Vec<usize> = (0..shapes.len())
        .filter(|&s| shapes[s].switchable)
        .collect();

    let init = top.table_or_empty("initial")?;
    let initial = read_initial(&init, &model, &shapes, &coordinates, settings.max_speed)?;
    init.finish()?;
    top.finish()?;
    Ok(Scene {
        path: path.to_path_buf(),
        text: text.to_string(),
        overrides: overrides.to_vec(),
        title: meta.title.clone(),
        meta,
        settings,
        model,
        initial,
        controller,
        switchable,
        coordinates,
    })
}

/// `[initial]`: `q`, `u` (default zero) and `rest_on_ground`; rejects a start inside the
/// terrain with the penetration depth.
fn read_initial(
    init: &Table<'_>,
    model: &Model,
    shapes: &[ShapeSpec],
    coordinates: &[String],
    max_speed: f64,
) -> Result<State, SceneError> {
    let n = model.dof();
    let names = coordinates.join(", ");
    let mut q = init
        .opt_f64_list("q", Some(n), COORDINATE)?
        .ok_or_else(|| init.error_at_key("q", format!("missing; expected {n} values ({names})")))
        .map(DVector::from_vec)?;
    let u = init
        .opt_f64_list("u", Some(n), velocity(max_speed))?
        .map_or_else(|| DVector::zeros(n), DVector::from_vec);
    let rest = init.bool_or("rest_on_ground", false)?;
    let mut ws = Kinematics::new(model);
    if rest {
        if model.bodies()[0].joint.is_some() {
            return Err(init.error_at_key(
                "rest_on_ground",
                format!(
                    "the first body '{}' is not a floating base: there is no y to lower",
                    model.bodies()[0].name
                ),
            ));
        }
        // Lower (or raise) the first tree along y until its lowest active shape touches.
        let first_tree = |c: usize| model.root(model.shapes()[model.contacts()[c].shape].body) == 0;
        for _ in 0..8 {
            let Some((gap, normal_y, _)) =
                lowest_contact(model, shapes, &mut ws, &q, &u, &first_tree)
            else {
                return Err(init.error_at_key(
                    "rest_on_ground",
                    "no active shape can touch the terrain below the robot",
                ));
            };
            if gap.abs() <= PENETRATION_TOL * 1e-3 || normal_y <= 1e-9 {
                break;
            }
            q[1] -= gap / normal_y;
        }
    }
    let state = State { t: 0.0, q, u };
    let inactive: Vec<bool> = shapes.iter().map(|s| s.switchable).collect();
    if let Err(problem) = check_start(model, &state, &inactive) {
        let fix = match &problem {
            StartProblem::InTerrain { shape, .. } => {
                let body = model
                    .shapes()
                    .iter()
                    .find(|s| &s.name == shape)
                    .map_or(0, |s| s.body);
                if model.root(body) == 0 && model.bodies()[0].joint.is_none() {
                    "raise y (q[1]) by at least that much or set rest_on_ground = true"
                } else {
                    "move its body out of the terrain"
                }
            }
            StartProblem::Overlap { .. } => "move their bodies apart",
            StartProblem::PastStop { .. } => {
                "start the joint between its limits (limits are in rad or m, like q)"
            }
        };
        return Err(init.error_at_key("q", format!("{problem}; {fix}")));
    }
    Ok(state)
}

/// The smallest gap over the contacts of non-switchable shapes that `among` accepts, at
/// `q`: `(gap, n_y, contact)`.
fn lowest_contact(
    model: &Model,
    shapes: &[ShapeSpec],
    ws: &mut Kinematics,
    q: &DVector<f64>,
    u: &DVector<f64>,
    among: &dyn Fn(usize) -> bool,
) -> Option<(f64, f64, usize)> {
    ws.update(model, q, u);
    (0..model.contacts().len())
        .filter(|&i| !shapes[model.contacts()[i].shape].switchable && among(i))
        .filter_map(|i| {
            model
                .contact_geometry(ws, i)
                .map(|g| (g.gap, g.normal.y, i))
        })
        .min_by(|a, b| a.0.total_cmp(&b.0))
}
