//! The TOML scene format of hopsim (`docs/scene-format.md`).
//!
//! A scene file describes a robot and its world: `[meta]`, `[simulation]`,
//! `[environment]`, `[[bodies]]`, `[[shapes]]`, `[[springs]]`, `[body_contacts]`,
//! `[[contact_pairs]]`, `[[loops]]`, `[controller]`, `[[actuators]]` and `[initial]`. A MuJoCo model (MJCF, `.xml`) is
//! imported into the equivalent scene ([`import_mjcf`], docs/mjcf.md). [`load`] reads, overrides (`--set key=value`) and validates it into a
//! [`Scene`]: a [`hopsim_model::Model`], an initial [`hopsim_step::State`], a
//! [`hopsim_control::ControllerConfig`] and the run [`Settings`]. Every error says where
//! (file:line:column, or the `--set` argument), which key, what was found and what was
//! expected; unknown keys get a "did you mean". [`axis_label`] names a numeric key in words
//! with its unit, for figures.

mod actuators;
mod bodies;
mod body_contacts;
mod controller;
mod environment;
mod error;
mod import;
mod loops;
mod overrides;
mod reader;
mod scene;
mod schema;
mod settings;
mod start;
mod tree;
mod warnings;

pub use actuators::{MAX_ACTUATORS, MAX_CONTROL_FILE_BYTES};
pub use bodies::{MAX_BODIES, MAX_SHAPES, MAX_SPRINGS};
pub use error::{Location, SceneError};
pub use hopsim_sim::{check_start, check_state, StartProblem, StateProblem, PENETRATION_TOL};
pub use hopsim_sim::{check_steps, Settings, Setup, TooManySteps, DEFAULT_MAX_STEPS, MIN_DT};
pub use import::{import_mjcf, is_mjcf};
pub use loops::{MAX_LOOPS, START_LOOP_TOLERANCE};
pub use overrides::Override;
pub use reader::{MAX_COORDINATE, MAX_MAGNITUDE};
pub use scene::{document, load, parse, Scene, MAX_CONTACTS, MAX_SCENE_BYTES};
pub use schema::{axis_label, key_info, key_words, value_label, KeyInfo};
pub use settings::Meta;
pub use tree::MAX_DEPTH;
pub use warnings::{warnings, DAMPER_RATIO, IMPACT_TRAVEL, SPRING_OMEGA_DT, TURN_PER_STEP};
