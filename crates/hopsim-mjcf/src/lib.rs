//! hopsim-mjcf: MuJoCo's model files (MJCF) of planar mechanisms read into a planar model
//! description ([`PlanarModel`]): bodies with their mass properties, hinge and slide joints
//! numbered as MuJoCo's `qpos`, geoms as planar shapes, actuators and options.
//!
//! [`scene_toml`] writes a planar model as the equivalent hopsim scene (TOML text whose
//! coordinates are MuJoCo's `qpos`), which `hopsim-scene` reads like any scene file.
//!
//! The plane is found from the joints, not assumed (docs/mjcf.md). Everything outside the
//! supported subset is an error located at `file:line:column` naming the element and
//! attribute; what is read without effect (visuals, solver settings, soft-contact
//! parameters) is listed in [`PlanarModel::notices`]. Masses and inertias are computed from
//! geoms exactly as MuJoCo's compiler does, and checked against MuJoCo itself
//! (`tests/mujoco_oracle.rs`).
//!
//! ```
//! let xml = r#"<mujoco><worldbody><body name="pole" pos="0 0 1">
//!   <joint name="hinge" type="hinge" axis="0 1 0"/>
//!   <geom type="capsule" fromto="0 0 0 0 0 1" size="0.05" mass="2"/>
//! </body></worldbody></mujoco>"#;
//! let model = hopsim_mjcf::read_str(xml, "pole.xml", None, &Default::default()).unwrap();
//! assert_eq!(model.bodies[0].mass, 2.0);
//! assert_eq!(model.joints[0].sign, -1.0); // +y is the x–z plane's −normal
//! ```

mod attrs;
mod equality;
mod error;
mod inertia;
mod model;
mod orient;
mod overlap;
mod planar;
mod read;
mod scene;
mod tables;
mod xml;

use std::path::Path;

pub use equality::{Equality, EqualityKind};
pub use error::{Location, MjcfError, Notice, NoticeKind, Subject};
pub use model::{
    Actuator, ActuatorKind, Body, Geom, Joint, JointKind, Options, Part, PlanarModel, Plane, Shape,
    Vec2,
};
pub use planar::PLANE_TOLERANCE;
pub use read::MAX_ELEMENTS;
pub use scene::{scene_toml, ImportError, SceneText, IMPORTED_DURATION};
pub use xml::{MAX_FILE_BYTES, MAX_INCLUDE_DEPTH};

/// How strictly to read.
#[derive(Debug, Clone, Default)]
pub struct ReadOptions {
    /// Read physics that the planar model leaves out (fluid forces, rolling friction,
    /// gravity compensation, …) as [`NoticeKind::Unmodelled`] notices instead of errors.
    /// Off by default: such a model would not move as in MuJoCo.
    pub unmodelled: bool,
}

/// Reads the MJCF file at `path` (its includes relative to its folder).
pub fn read_file(path: impl AsRef<Path>, options: &ReadOptions) -> Result<PlanarModel, MjcfError> {
    let root = xml::load_file(path.as_ref())?;
    build(&root, options)
}

/// Reads MJCF text, called `name` in messages; includes are resolved in `base_dir`.
pub fn read_str(
    text: &str,
    name: &str,
    base_dir: Option<&Path>,
    options: &ReadOptions,
) -> Result<PlanarModel, MjcfError> {
    let root = xml::load_str(text, name, base_dir)?;
    build(&root, options)
}

fn build(root: &xml::Element, options: &ReadOptions) -> Result<PlanarModel, MjcfError> {
    let mut ctx = attrs::Context::new(options.unmodelled);
    let doc = read::read_document(root, &mut ctx)?;
    planar::build(doc, &mut ctx)
}
