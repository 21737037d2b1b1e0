//! What every supported element's attributes are to the planar reader (docs/mjcf.md has the
//! same as a table).

use crate::attrs::Neutral::{Never, Word, Zero};
use crate::attrs::Treat::{self, Ignore, Read, Soft, Unless};
use crate::attrs::{Table, VISUAL};

const SOLVER: &str = "a setting of MuJoCo's iterative constraint solver; hopsim solves its contact LCP exactly (Lemke's method)";
const FLUID: &str = "fluid forces (drag and lift) are not modelled";
const COLLISION: &str = "a setting of MuJoCo's collision detection";
const TRANSMISSION: &str = "only joint transmissions are supported";

pub(crate) const COMPILER: Table = &[
    ("angle", Read),
    ("eulerseq", Read),
    ("inertiafromgeom", Read),
    ("autolimits", Read),
    ("settotalmass", Read),
    ("boundmass", Read),
    ("inertiagrouprange", Read),
    (
        "boundinertia",
        Unless(Zero, "a lower bound on principal inertias"),
    ),
    (
        "balanceinertia",
        Unless(Word("false"), "balancing of non-physical inertias"),
    ),
    (
        "coordinate",
        Unless(Word("local"), "global coordinates (removed from MuJoCo)"),
    ),
    (
        "fusestatic",
        Ignore("bodies without joints are always welded into their parent here"),
    ),
    ("discardvisual", Ignore(VISUAL)),
    ("meshdir", Ignore("meshes are not supported")),
    ("texturedir", Ignore(VISUAL)),
    ("assetdir", Ignore("meshes are not supported")),
    ("strippath", Ignore("meshes are not supported")),
    ("convexhull", Ignore(COLLISION)),
    ("usethread", Ignore("a setting of MuJoCo's compiler")),
    ("fitaabb", Ignore("meshes are not supported")),
    ("exactmeshinertia", Ignore("meshes are not supported")),
    ("saveinertial", Ignore("a setting of MuJoCo's model writer")),
    ("alignfree", Ignore("free joints are not supported")),
    ("maxhullvert", Ignore("meshes are not supported")),
];

pub(crate) const OPTION: Table = &[
    ("timestep", Read),
    ("gravity", Read),
    ("wind", Unless(Zero, FLUID)),
    ("density", Unless(Zero, FLUID)),
    ("viscosity", Unless(Zero, FLUID)),
    ("magnetic", Ignore("only magnetometer sensors use it")),
    (
        "integrator",
        Ignore("hopsim steps with Moreau's midpoint scheme (docs/physics.md §4)"),
    ),
    (
        "cone",
        Ignore("in the plane the pyramidal and elliptic friction cones are the same"),
    ),
    ("impratio", Soft),
    ("o_margin", Soft),
    ("o_solref", Soft),
    ("o_solimp", Soft),
    ("o_friction", Ignore("used only with the override flag")),
    ("jacobian", Ignore(SOLVER)),
    ("solver", Ignore(SOLVER)),
    ("iterations", Ignore(SOLVER)),
    ("tolerance", Ignore(SOLVER)),
    ("ls_iterations", Ignore(SOLVER)),
    ("ls_tolerance", Ignore(SOLVER)),
    ("noslip_iterations", Ignore(SOLVER)),
    ("noslip_tolerance", Ignore(SOLVER)),
    ("ccd_iterations", Ignore(COLLISION)),
    ("ccd_tolerance", Ignore(COLLISION)),
    ("sdf_iterations", Ignore(COLLISION)),
    ("sdf_initpoints", Ignore(COLLISION)),
    (
        "actuatorgroupdisable",
        Unless(Zero, "disabled actuator groups"),
    ),
];

/// `<flag>` attributes read (each `enable` or `disable`).
pub(crate) const FLAGS_READ: [&str; 11] = [
    "constraint",
    "equality",
    "frictionloss",
    "limit",
    "contact",
    "spring",
    "damper",
    "gravity",
    "clampctrl",
    "filterparent",
    "actuation",
];

pub(crate) const FLAG: Table = &[
    ("constraint", Read),
    ("equality", Read),
    ("frictionloss", Read),
    ("limit", Read),
    ("contact", Read),
    ("spring", Read),
    ("damper", Read),
    ("gravity", Read),
    ("clampctrl", Read),
    ("filterparent", Read),
    ("actuation", Read),
    ("warmstart", Ignore(SOLVER)),
    ("refsafe", Ignore(SOLVER)),
    ("island", Ignore(SOLVER)),
    ("sensor", Ignore("sensors are not read")),
    ("midphase", Ignore(COLLISION)),
    ("nativeccd", Ignore(COLLISION)),
    ("multiccd", Ignore(COLLISION)),
    (
        "eulerdamp",
        Ignore("a setting of MuJoCo's Euler integrator"),
    ),
    ("autoreset", Ignore("a setting of MuJoCo's simulation loop")),
    (
        "energy",
        Ignore("hopsim always accounts for energy (docs/physics.md §6)"),
    ),
    ("fwdinv", Ignore("a setting of MuJoCo's inverse dynamics")),
    (
        "invdiscrete",
        Ignore("a setting of MuJoCo's inverse dynamics"),
    ),
    (
        "override",
        Unless(Word("disable"), "overriding contact parameters"),
    ),
];

pub(crate) const BODY: Table = &[
    ("name", Read),
    ("childclass", Read),
    ("pos", Read),
    ("quat", Read),
    ("axisangle", Read),
    ("xyaxes", Read),
    ("zaxis", Read),
    ("euler", Read),
    ("mocap", Unless(Word("false"), "mocap bodies")),
    ("gravcomp", Unless(Zero, "gravity compensation")),
    ("user", Ignore("user data")),
];

pub(crate) const INERTIAL: Table = &[
    ("pos", Read),
    ("quat", Read),
    ("axisangle", Read),
    ("xyaxes", Read),
    ("zaxis", Read),
    ("euler", Read),
    ("mass", Read),
    ("diaginertia", Read),
    ("fullinertia", Read),
];

pub(crate) const JOINT: Table = &[
    ("name", Read),
    ("type", Read),
    ("pos", Read),
    ("axis", Read),
    ("limited", Read),
    ("range", Read),
    ("ref", Read),
    ("springref", Read),
    ("stiffness", Read),
    ("damping", Read),
    ("armature", Read),
    ("frictionloss", Read),
    ("actuatorfrclimited", Read),
    ("actuatorfrcrange", Read),
    (
        "springdamper",
        Unless(Zero, "springs given by time constant and damping ratio"),
    ),
    (
        "actuatorgravcomp",
        Unless(Word("false"), "gravity compensation"),
    ),
    ("solreflimit", Soft),
    ("solimplimit", Soft),
    ("solreffriction", Soft),
    ("solimpfriction", Soft),
    ("margin", Soft),
    ("group", Ignore(VISUAL)),
    ("user", Ignore("user data")),
];

pub(crate) const GEOM: Table = &[
    ("name", Read),
    ("type", Read),
    ("size", Read),
    ("fromto", Read),
    ("pos", Read),
    ("quat", Read),
    ("axisangle", Read),
    ("xyaxes", Read),
    ("zaxis", Read),
    ("euler", Read),
    ("mass", Read),
    ("density", Read),
    ("friction", Read),
    ("contype", Read),
    ("conaffinity", Read),
    ("condim", Read),
    ("priority", Read),
    ("group", Read),
    ("rgba", Read),
    ("solmix", Soft),
    ("solref", Soft),
    ("solimp", Soft),
    ("margin", Soft),
    ("gap", Soft),
    (
        "shellinertia",
        Unless(Word("false"), "inertia of hollow shells"),
    ),
    ("fluidshape", Unless(Word("none"), FLUID)),
    ("fluidcoef", Ignore("used only with fluidshape")),
    ("mesh", Unless(Never, "mesh geoms")),
    ("hfield", Unless(Never, "height-field geoms")),
    ("fitscale", Ignore("meshes are not supported")),
    ("material", Ignore(VISUAL)),
    ("user", Ignore("user data")),
];

/// Attributes common to the actuator shortcuts.
const ACTUATOR_COMMON: [(&str, Treat); 20] = [
    ("name", Read),
    ("joint", Read),
    ("gear", Read),
    ("ctrllimited", Read),
    ("ctrlrange", Read),
    ("forcelimited", Read),
    ("forcerange", Read),
    ("lengthrange", Ignore("used only by muscles")),
    ("group", Ignore(VISUAL)),
    ("user", Ignore("user data")),
    ("cranklength", Unless(Zero, TRANSMISSION)),
    ("jointinparent", Unless(Never, TRANSMISSION)),
    ("tendon", Unless(Never, TRANSMISSION)),
    ("cranksite", Unless(Never, TRANSMISSION)),
    ("slidersite", Unless(Never, TRANSMISSION)),
    ("site", Unless(Never, TRANSMISSION)),
    ("refsite", Unless(Never, TRANSMISSION)),
    ("body", Unless(Never, TRANSMISSION)),
    ("actlimited", Unless(Word("false"), "actuator activation")),
    ("actrange", Unless(Zero, "actuator activation")),
];

const fn with<const M: usize, const N: usize>(
    extra: [(&'static str, Treat); M],
) -> [(&'static str, Treat); N] {
    let mut out = [("", Read); N];
    let mut i = 0;
    while i < ACTUATOR_COMMON.len() {
        out[i] = ACTUATOR_COMMON[i];
        i += 1;
    }
    let mut j = 0;
    while j < M {
        out[i + j] = extra[j];
        j += 1;
    }
    out
}

pub(crate) const MOTOR: Table = &with::<0, 20>([]);
pub(crate) const POSITION: Table = &with::<5, 25>([
    ("kp", Read),
    ("kv", Read),
    ("dampratio", Unless(Zero, "damping given as a ratio")),
    ("timeconst", Unless(Zero, "activation dynamics")),
    (
        "inheritrange",
        Unless(Zero, "control ranges inherited from the joint"),
    ),
]);
pub(crate) const VELOCITY: Table = &with::<1, 21>([("kv", Read)]);
