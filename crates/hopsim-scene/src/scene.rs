//! The validated scene and how it is built from the file (`docs/scene-format.md`).

use crate::actuators::read_actuators;
use crate::bodies::{read_bodies, read_shapes, read_springs, Names, ShapeSpec, MAX_SHAPES};
use crate::body_contacts::read_body_contacts;
use crate::controller::read_controller;
use crate::environment::read_environment;
use crate::error::{SceneError, Source};
use crate::loops::{close_start, read_loops};
use crate::overrides::{apply, Override};
use crate::reader::Table;
use crate::settings::{read_meta, read_settings, Meta};
use crate::start::{velocity, COORDINATE};
use crate::tree::Node;
use hopsim_model::{Kinematics, Model, ModelBuilder, ModelError, Vec2};
use hopsim_sim::{check_start, Setup, StartProblem, PENETRATION_TOL};
use hopsim_step::State;
use nalgebra::DVector;
use std::ops::{Deref, DerefMut};
use std::path::{Path, PathBuf};
use std::sync::Arc;

/// Largest scene file [`load`] reads, bytes (8 MiB: a hundred times the largest sensible
/// scene; `/dev/zero` or an endless pipe stops here instead of exhausting memory).
pub const MAX_SCENE_BYTES: u64 = 8 << 20;
/// Most potential contacts (shape features × terrain features) a scene may create: the
/// contact LCP is dense, its matrices grow with the square of this count.
pub const MAX_CONTACTS: usize = 1000;

/// A scene ready to simulate: the run's [`Setup`] (model, initial state, controller and
/// settings, its file and text) read from a scene file, with the file's `[meta]` and the
/// overrides applied. Dereferences to its `Setup`, which is what the run loop takes.
#[derive(Clone, Debug)]
pub struct Scene {
    /// What runs.
    pub setup: Setup,
    /// The overrides applied on top of the file.
    pub overrides: Vec<Override>,
    /// `[meta]`.
    pub meta: Meta,
    /// What the scene's source leaves out or expresses otherwise, one sentence each: the
    /// text's `# notice: …` lines (written by [`crate::import_mjcf`]).
    pub notices: Vec<String>,
}

impl Deref for Scene {
    type Target = Setup;

    fn deref(&self) -> &Setup {
        &self.setup
    }
}

impl DerefMut for Scene {
    fn deref_mut(&mut self) -> &mut Setup {
        &mut self.setup
    }
}

/// The start of a line of a scene's text that is a notice ([`Scene::notices`]).
pub(crate) const NOTICE: &str = "# notice: ";

/// Reads and validates the scene file at `path` with `overrides` applied. Reads at most
/// [`MAX_SCENE_BYTES`]. A MuJoCo model (`.xml`, [`crate::is_mjcf`]) is imported into the
/// equivalent scene first ([`crate::import_mjcf`]); errors in that scene name it
/// `<path> (imported)`.
pub fn load(path: &Path, overrides: &[Override]) -> Result<Scene, SceneError> {
    if crate::is_mjcf(path) {
        let text = crate::import_mjcf(path)?;
        let imported = PathBuf::from(format!("{} (imported)", path.display()));
        let mut scene = parse(&text, &imported, overrides)?;
        scene.path = path.to_path_buf();
        return Ok(scene);
    }
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

/// The document of scene `text` with `overrides` applied, before validation.
fn overridden(src: Source<'_>, overrides: &[Override]) -> Result<Node, SceneError> {
    let mut root =
        Node::parse_document(src.text).map_err(|(message, span)| SceneError::Syntax {
            location: src.locate_offset(span.map_or(0, |s| s.start)),
            message,
        })?;
    for ov in overrides {
        apply(&mut root, ov)?;
    }
    Ok(root)
}

/// The document the reader validates: scene `text` (read from `path`) with `overrides`
/// applied, as TOML values, for a front end that rebuilds the scene in its own terms
/// (Python's `Scene.model`). Not validated beyond TOML syntax and the overrides' paths.
pub fn document(
    text: &str,
    path: &Path,
    overrides: &[Override],
) -> Result<toml::Table, SceneError> {
    let root = overridden(Source { path, text }, overrides)?;
    Ok(root.to_toml_table())
}

/// Validates scene `text` (read from `path`, which names it in errors) with `overrides`.
pub fn parse(text: &str, path: &Path, overrides: &[Override]) -> Result<Scene, SceneError> {
    let src = Source { path, text };
    let root = overridden(src, overrides)?;
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
        "loops",
        "controller",
        "actuators",
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
    let actuator_tables = top.tables("actuators")?;
    let base = path.parent().unwrap_or(Path::new("."));
    let (actuators, control_signals) =
        read_actuators(&actuator_tables, &bodies, &body_names, base)?;

    let instances = shapes.iter().map(|s| s.instance.clone()).collect();
    let gravity = Vec2::new(settings.gravity_x, -settings.gravity);
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
    read_loops(&top.tables("loops")?, &body_names, &mut builder)?;
    for (actuator, table) in actuators.into_iter().zip(&actuator_tables) {
        builder
            .add_actuator(actuator)
            .map_err(|e| table.error_here(e.to_string()))?;
    }
    let model = builder.build();
    let switchable: Vec<usize> = (0..shapes.len())
        .filter(|&s| shapes[s].switchable)
        .collect();

    let init = top.table_or_empty("initial")?;
    let mut initial = read_initial(&init, &model, &shapes, &coordinates, settings.max_speed)?;
    close_start(&init, &model, &mut initial)?;
    init.finish()?;
    top.finish()?;
    Ok(Scene {
        setup: Setup {
            path: path.to_path_buf(),
            text: text.to_string(),
            title: meta.title.clone(),
            settings,
            model: Arc::new(model),
            initial,
            controller,
            switchable,
            control_signals,
            coordinates,
        },
        overrides: overrides.to_vec(),
        meta,
        notices: text
            .lines()
            .filter_map(|l| l.strip_prefix(NOTICE))
            .map(str::to_string)
            .collect(),
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
