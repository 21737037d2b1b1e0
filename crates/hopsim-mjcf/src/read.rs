//! The MJCF document read into MuJoCo's own terms (3-D frames, geoms, joints), before the
//! plane is found: `<compiler>`, `<option>`, `<default>` classes, `<worldbody>`, `<actuator>`.

use std::collections::HashMap;

use nalgebra::{UnitQuaternion, Vector3};

use crate::attrs::{check_names, Context, Table, View, VISUAL};
use crate::error::{Location, NoticeKind, Result};
use crate::orient::{orientation, z_to, Angles, EPS};
use crate::tables;
use crate::xml::{Attr, Element};

/// The most bodies, joints or geoms a model may have.
pub const MAX_ELEMENTS: usize = 1000;

type V3 = Vector3<f64>;

/// `<compiler>` settings.
#[derive(Debug, Clone)]
pub(crate) struct Compiler {
    pub angles: Angles,
    /// `inertiafromgeom`: `Some(true)`, `Some(false)` or `None` for "auto".
    pub inertia_from_geom: Option<bool>,
    pub autolimits: bool,
    pub settotalmass: f64,
    pub boundmass: f64,
    pub inertia_groups: [i64; 2],
}

/// `<option>` and `<flag>`, raw.
#[derive(Debug, Clone)]
pub(crate) struct RawOptions {
    pub timestep: f64,
    pub gravity: V3,
    /// Flag name → enabled.
    pub flags: HashMap<&'static str, bool>,
}

#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) enum GeomType {
    Plane,
    Sphere,
    Capsule,
    Cylinder,
    Ellipsoid,
    Box,
}

#[derive(Debug, Clone)]
pub(crate) struct Geom3 {
    pub name: Option<String>,
    pub loc: Location,
    pub kind: GeomType,
    pub size: [f64; 3],
    pub pos: V3,
    pub quat: UnitQuaternion<f64>,
    /// Mass and principal inertias in the geom's frame (zero when not counted).
    pub mass: f64,
    pub inertia: V3,
    pub contype: u32,
    pub conaffinity: u32,
    pub condim: u32,
    pub priority: i32,
    pub friction: [f64; 3],
    pub rgba: [f64; 4],
    /// In `inertiagrouprange`: counts towards its body's mass.
    pub counted: bool,
}

#[derive(Debug, Clone)]
pub(crate) struct Joint3 {
    pub name: String,
    pub loc: Location,
    pub hinge: bool,
    pub pos: V3,
    pub axis: V3,
    pub range: Option<[f64; 2]>,
    pub reference: f64,
    pub spring_reference: f64,
    pub stiffness: f64,
    pub damping: f64,
    pub armature: f64,
    pub frictionloss: f64,
    pub actuator_force_range: Option<[f64; 2]>,
}

/// `<inertial>`: the inertia is `diag` in the frame `quat`, or `full` (xx yy zz xy xz yz) in
/// the body frame.
#[derive(Debug, Clone)]
pub(crate) struct Inertial3 {
    pub pos: V3,
    pub quat: UnitQuaternion<f64>,
    pub mass: f64,
    pub diag: V3,
    pub full: Option<[f64; 6]>,
}

#[derive(Debug, Clone)]
pub(crate) struct Body3 {
    pub name: String,
    pub loc: Location,
    /// `None` only for the world (body 0).
    pub parent: Option<usize>,
    pub pos: V3,
    pub quat: UnitQuaternion<f64>,
    pub joints: Vec<Joint3>,
    pub geoms: Vec<Geom3>,
    pub inertial: Option<Inertial3>,
}

#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) enum Kind3 {
    Motor,
    Position { kp: f64, kv: f64 },
    Velocity { kv: f64 },
}

#[derive(Debug, Clone)]
pub(crate) struct Actuator3 {
    pub name: Option<String>,
    /// The `joint` attribute (its value and location).
    pub joint: Attr,
    pub element: String,
    pub kind: Kind3,
    pub gear: f64,
    pub ctrl_range: Option<[f64; 2]>,
    pub force_range: Option<[f64; 2]>,
}

/// The document in MuJoCo's terms.
#[derive(Debug, Clone)]
pub(crate) struct Document {
    pub name: String,
    pub compiler: Compiler,
    pub options: RawOptions,
    /// Body 0 is the world; parents before children (MuJoCo's order).
    pub bodies: Vec<Body3>,
    pub actuators: Vec<Actuator3>,
    /// `<connect>` and `<weld>`, active ones only.
    pub equalities: Vec<crate::equality::Equality3>,
}

/// One default class: the attributes its elements start from.
#[derive(Debug, Clone, Default)]
struct Class {
    joint: Vec<Attr>,
    geom: Vec<Attr>,
    /// Shared by `<motor>`, `<position>` and `<velocity>`, as in MuJoCo.
    actuator: Vec<Attr>,
    equality: Vec<Attr>,
}

/// Reads the root element `<mujoco>`.
pub(crate) fn read_document(root: &Element, ctx: &mut Context) -> Result<Document> {
    if root.name != "mujoco" {
        return Err(root.error(
            None,
            format!("the root element must be <mujoco>, found <{}>", root.name),
        ));
    }
    if let Some(a) = root.attrs.iter().find(|a| a.name != "model") {
        return Err(root.error(Some(&a.name), "unknown attribute; <mujoco> takes model"));
    }
    let mut compiler = Compiler {
        angles: Angles {
            degree: true,
            eulerseq: *b"xyz",
        },
        inertia_from_geom: None,
        autolimits: true,
        settotalmass: -1.0,
        boundmass: 0.0,
        inertia_groups: [0, 5],
    };
    for e in root.children.iter().filter(|e| e.name == "compiler") {
        read_compiler(e, &mut compiler, ctx)?;
    }
    let mut options = RawOptions {
        timestep: 0.002,
        gravity: V3::new(0.0, 0.0, -9.81),
        flags: HashMap::new(),
    };
    let mut classes: HashMap<String, Class> =
        HashMap::from([("main".to_string(), Class::default())]);
    for e in &root.children {
        match e.name.as_str() {
            "option" => read_option(e, &mut options, ctx)?,
            "default" => read_default(e, "main", &Class::default(), &mut classes, ctx, true)?,
            _ => {}
        }
    }
    let mut reader = Reader {
        compiler: &compiler,
        classes: &classes,
        ctx,
        bodies: Vec::new(),
        joints: 0,
        geoms: 0,
    };
    let mut actuators = Vec::new();
    let mut equalities = Vec::new();
    let mut world_seen = false;
    for e in &root.children {
        match e.name.as_str() {
            "compiler" | "option" | "default" => {}
            "worldbody" => {
                reader.world(e, world_seen)?;
                world_seen = true;
            }
            "actuator" => {
                for a in &e.children {
                    actuators.push(reader.actuator(a)?);
                }
            }
            "equality" => equalities.extend(crate::equality::read(
                e,
                |child| Ok(class_of(reader.classes, child, "main")?.equality.as_slice()),
                reader.ctx,
            )?),
            "tendon" => refuse_children(e, "tendons are not supported")?,
            "contact" => refuse_children(
                e,
                "explicit contact pairs and exclusions are not yet supported",
            )?,
            "extension" | "deformable" => {
                refuse_children(e, "plugins and deformable objects are not supported")?
            }
            "size" => reader.ctx.ignore_element(e, "memory sizes of MuJoCo"),
            "visual" | "asset" | "statistic" => reader.ctx.ignore_element(e, VISUAL),
            "custom" => reader.ctx.ignore_element(e, "user data"),
            "sensor" => reader.ctx.ignore_element(e, "sensors are not read"),
            "keyframe" => reader
                .ctx
                .ignore_element(e, "keyframes are not read (the initial state is qpos0)"),
            other => return Err(e.error(None, format!("unknown element <{other}> in <mujoco>"))),
        }
    }
    if !world_seen {
        reader.bodies.push(world_body(&root.loc));
    }
    let bodies = reader.bodies;
    Ok(Document {
        name: root
            .attr("model")
            .map_or_else(|| "MuJoCo Model".to_string(), |a| a.value.clone()),
        compiler,
        options,
        bodies,
        actuators,
        equalities,
    })
}

fn refuse_children(e: &Element, why: &str) -> Result<()> {
    match e.children.first() {
        Some(c) => Err(c.error(None, format!("not supported: {why}"))),
        None => Ok(()),
    }
}

fn world_body(loc: &Location) -> Body3 {
    Body3 {
        name: "world".into(),
        loc: loc.clone(),
        parent: None,
        pos: V3::zeros(),
        quat: UnitQuaternion::identity(),
        joints: Vec::new(),
        geoms: Vec::new(),
        inertial: None,
    }
}

fn no_children(e: &Element) -> Result<()> {
    match e.children.first() {
        Some(c) => Err(c.error(None, format!("<{}> takes no child elements", e.name))),
        None => Ok(()),
    }
}

fn read_compiler(e: &Element, c: &mut Compiler, ctx: &mut Context) -> Result<()> {
    let v = View::new(e, &[]);
    v.check(tables::COMPILER, ctx)?;
    for child in &e.children {
        match child.name.as_str() {
            "lengthrange" => ctx.ignore_element(child, "used only by muscles"),
            "plugin" => return Err(child.error(None, "not supported: plugins")),
            other => {
                return Err(child.error(None, format!("unknown element <{other}> in <compiler>")))
            }
        }
    }
    if let Some(w) = v.word("angle", &["degree", "radian"])? {
        c.angles.degree = w == "degree";
    }
    if let Some(a) = v.get("eulerseq") {
        let s = a.value.trim().as_bytes();
        match <[u8; 3]>::try_from(s) {
            Ok(seq) if seq.iter().all(|b| b"xyzXYZ".contains(b)) => c.angles.eulerseq = seq,
            _ => {
                return Err(v.error_at(
                    a,
                    "expected three of x, y, z (rotating axes) or X, Y, Z (fixed axes)",
                ))
            }
        }
    }
    if v.get("inertiafromgeom").is_some() {
        c.inertia_from_geom = v.tristate("inertiafromgeom")?;
    }
    c.autolimits = v.boolean("autolimits", c.autolimits)?;
    c.settotalmass = v.number_or("settotalmass", c.settotalmass)?;
    c.boundmass = v.nonnegative("boundmass", c.boundmass)?;
    if let Some(a) = v.get("inertiagrouprange") {
        let [lo, hi] = v.values::<2>(a)?;
        if lo.fract() != 0.0 || hi.fract() != 0.0 {
            return Err(v.error_at(a, "expected two integers"));
        }
        c.inertia_groups = [lo as i64, hi as i64];
    }
    Ok(())
}

fn read_option(e: &Element, o: &mut RawOptions, ctx: &mut Context) -> Result<()> {
    let v = View::new(e, &[]);
    v.check(tables::OPTION, ctx)?;
    if let Some(a) = v.get("timestep") {
        let [dt] = v.values::<1>(a)?;
        if dt <= 0.0 {
            return Err(v.error_at(a, "must be positive"));
        }
        o.timestep = dt;
    }
    if let Some(g) = v.vector::<3>("gravity")? {
        o.gravity = V3::from(g);
    }
    for child in &e.children {
        if child.name != "flag" {
            return Err(child.error(
                None,
                format!(
                    "unknown element <{}> in <option>; expected <flag>",
                    child.name
                ),
            ));
        }
        no_children(child)?;
        let f = View::new(child, &[]);
        f.check(tables::FLAG, ctx)?;
        for name in tables::FLAGS_READ {
            if let Some(w) = f.word(name, &["enable", "disable"])? {
                o.flags.insert(name, w == "enable");
            }
        }
    }
    Ok(())
}

/// Reads a `<default>` class (and its nested classes) inheriting from `parent`.
fn read_default(
    e: &Element,
    inherited_name: &str,
    parent: &Class,
    classes: &mut HashMap<String, Class>,
    ctx: &mut Context,
    top: bool,
) -> Result<()> {
    if let Some(a) = e.attrs.iter().find(|a| a.name != "class") {
        return Err(e.error(Some(&a.name), "unknown attribute; <default> takes class"));
    }
    let name = match e.attr("class") {
        Some(a) => a.value.clone(),
        None if top => inherited_name.to_string(),
        None => return Err(e.error(None, "a nested <default> needs a `class`")),
    };
    if top && name != "main" {
        return Err(e.error(Some("class"), "the top-level <default> is the class `main`"));
    }
    let mut class = if top {
        classes.get("main").cloned().unwrap_or_default()
    } else {
        if classes.contains_key(&name) {
            return Err(e.error(
                Some("class"),
                format!("the default class `{name}` is defined twice"),
            ));
        }
        parent.clone()
    };
    let mut nested = Vec::new();
    for child in &e.children {
        let (list, table): (&mut Vec<Attr>, Table) = match child.name.as_str() {
            "default" => {
                nested.push(child);
                continue;
            }
            "joint" => (&mut class.joint, tables::JOINT),
            "geom" => (&mut class.geom, tables::GEOM),
            "motor" => (&mut class.actuator, tables::MOTOR),
            "position" => (&mut class.actuator, tables::POSITION),
            "velocity" => (&mut class.actuator, tables::VELOCITY),
            "equality" => (&mut class.equality, crate::equality::DEFAULTS),
            "site" | "camera" | "light" | "mesh" | "material" | "texture" => {
                ctx.ignore_element(child, VISUAL);
                continue;
            }
            "general" | "intvelocity" | "damper" | "cylinder" | "muscle" | "adhesion"
            | "tendon" | "spatial" | "fixed" | "pair" | "flex" => {
                ctx.notice(
                    NoticeKind::Ignored,
                    &child.loc,
                    &child.name,
                    None,
                    "defaults of an element outside the supported subset (an error where one is used)",
                );
                continue;
            }
            other => {
                return Err(child.error(None, format!("unknown element <{other}> in <default>")))
            }
        };
        no_children(child)?;
        check_names(child, table)?;
        for a in &child.attrs {
            list.retain(|b| b.name != a.name);
            list.push(a.clone());
        }
    }
    classes.insert(name.clone(), class.clone());
    for child in nested {
        read_default(child, &name, &class, classes, ctx, false)?;
    }
    Ok(())
}

/// Reads bodies, depth first, numbering them as MuJoCo does.
struct Reader<'a> {
    compiler: &'a Compiler,
    classes: &'a HashMap<String, Class>,
    ctx: &'a mut Context,
    bodies: Vec<Body3>,
    joints: usize,
    geoms: usize,
}

/// The default class of `e`: its `class`, else the inherited `childclass`.
fn class_of<'a>(
    classes: &'a HashMap<String, Class>,
    e: &Element,
    inherited: &str,
) -> Result<&'a Class> {
    let name = e.attr("class").map_or(inherited, |a| a.value.as_str());
    classes
        .get(name)
        .ok_or_else(|| e.error(Some("class"), format!("no default class `{name}`")))
}

impl<'a> Reader<'a> {
    /// The `count`-th joint or geom `e` seen through its class's defaults (`defaults`
    /// picks them), checked against `table`.
    fn begin<'c>(
        &mut self,
        e: &'c Element,
        count: usize,
        childclass: &str,
        defaults: fn(&Class) -> &Vec<Attr>,
        table: Table,
    ) -> Result<View<'c>>
    where
        'a: 'c,
    {
        no_children(e)?;
        if count > MAX_ELEMENTS {
            return Err(e.error(
                None,
                format!("more than {MAX_ELEMENTS} <{}> elements", e.name),
            ));
        }
        let class = class_of(self.classes, e, childclass)?;
        let v = View::new(e, defaults(class));
        v.check(table, self.ctx)?;
        Ok(v)
    }

    fn world(&mut self, e: &Element, again: bool) -> Result<()> {
        if let Some(a) = e.attrs.first() {
            return Err(e.error(Some(&a.name), "<worldbody> takes no attributes"));
        }
        if !again {
            self.bodies.push(world_body(&e.loc));
        }
        self.children(e, 0, "main")
    }

    /// The child elements of body `index`, whose elements default to class `childclass`.
    fn children(&mut self, e: &Element, index: usize, childclass: &str) -> Result<()> {
        for child in &e.children {
            match child.name.as_str() {
                "body" => self.body(child, index, childclass)?,
                "geom" => {
                    let g = self.geom(child, childclass)?;
                    self.bodies[index].geoms.push(g);
                }
                "joint" if index > 0 => {
                    let j = self.joint(child, childclass)?;
                    self.bodies[index].joints.push(j);
                }
                "inertial" if index > 0 => {
                    if self.bodies[index].inertial.is_some() {
                        return Err(child.error(None, "a body has at most one <inertial>"));
                    }
                    let i = self.inertial(child)?;
                    self.bodies[index].inertial = Some(i);
                }
                "freejoint" => {
                    return Err(child.error(
                        None,
                        "not supported: a free joint leaves the plane (use two slides and a hinge)",
                    ))
                }
                "site" | "camera" | "light" => self.ctx.ignore_element(child, VISUAL),
                "frame" | "replicate" | "attach" | "composite" | "flexcomp" | "plugin" => {
                    return Err(child.error(None, format!("not supported: <{}>", child.name)))
                }
                other => {
                    let place = if index == 0 { "<worldbody>" } else { "<body>" };
                    return Err(child.error(None, format!("unknown element <{other}> in {place}")));
                }
            }
        }
        Ok(())
    }

    fn body(&mut self, e: &Element, parent: usize, childclass: &str) -> Result<()> {
        if self.bodies.len() > MAX_ELEMENTS {
            return Err(e.error(None, format!("more than {MAX_ELEMENTS} bodies")));
        }
        let v = View::new(e, &[]);
        v.check(tables::BODY, self.ctx)?;
        let childclass = match v.get("childclass") {
            Some(a) => {
                if !self.classes.contains_key(&a.value) {
                    return Err(v.error_at(a, format!("no default class `{}`", a.value)));
                }
                a.value.as_str()
            }
            None => childclass,
        };
        let index = self.bodies.len();
        self.bodies.push(Body3 {
            name: v
                .string("name")
                .map_or_else(|| format!("body{index}"), str::to_string),
            loc: e.loc.clone(),
            parent: Some(parent),
            pos: V3::from(v.vector::<3>("pos")?.unwrap_or_default()),
            quat: orientation(&v, &self.compiler.angles)?,
            joints: Vec::new(),
            geoms: Vec::new(),
            inertial: None,
        });
        self.children(e, index, childclass)
    }

    fn inertial(&mut self, e: &Element) -> Result<Inertial3> {
        no_children(e)?;
        let v = View::new(e, &[]);
        v.check(tables::INERTIAL, self.ctx)?;
        let need = |name: &str| {
            v.get(name)
                .ok_or_else(|| v.error(format!("missing attribute `{name}`")))
        };
        let pos = v.values::<3>(need("pos")?)?;
        let mass = v.values::<1>(need("mass")?)?[0];
        if mass < 0.0 {
            return Err(v.error_at(need("mass")?, "must not be negative"));
        }
        let full = v.vector::<6>("fullinertia")?;
        let diag = v.vector::<3>("diaginertia")?;
        if full.is_some() == diag.is_some() {
            return Err(v.error("give exactly one of `diaginertia` and `fullinertia`"));
        }
        let quat = orientation(&v, &self.compiler.angles)?;
        if full.is_some()
            && crate::orient::ORIENTATION
                .iter()
                .any(|n| v.get(n).is_some())
        {
            return Err(v.error("`fullinertia` and an inertial orientation cannot both be given"));
        }
        let diag = V3::from(diag.unwrap_or_default());
        if diag.iter().any(|x| *x < 0.0) {
            return Err(v.error_at(need("diaginertia")?, "must not be negative"));
        }
        if diag.x + diag.y < diag.z || diag.x + diag.z < diag.y || diag.y + diag.z < diag.x {
            return Err(v.error_at(
                need("diaginertia")?,
                "principal inertias must satisfy A + B ≥ C",
            ));
        }
        Ok(Inertial3 {
            pos: V3::from(pos),
            quat,
            mass,
            diag,
            full,
        })
    }

    fn joint(&mut self, e: &Element, childclass: &str) -> Result<Joint3> {
        self.joints += 1;
        let v = self.begin(e, self.joints, childclass, |c| &c.joint, tables::JOINT)?;
        let hinge = match v.word("type", &["hinge", "slide", "ball", "free"])? {
            None | Some("hinge") => true,
            Some("slide") => false,
            Some(other) => {
                return Err(v.error_for(
                    "type",
                    format!("not supported: a {other} joint leaves the plane"),
                ));
            }
        };
        let angle = |x: f64| {
            if hinge {
                self.compiler.angles.to_radians(x)
            } else {
                x
            }
        };
        let range = self.limits(&v, "limited", "range")?.map(|r| r.map(angle));
        let axis = V3::from(v.vector::<3>("axis")?.unwrap_or([0.0, 0.0, 1.0]));
        if axis.norm() < EPS {
            return Err(v.error_for("axis", "axis too small"));
        }
        Ok(Joint3 {
            name: v
                .string("name")
                .map_or_else(|| format!("joint{}", self.joints - 1), str::to_string),
            loc: e.loc.clone(),
            hinge,
            pos: V3::from(v.vector::<3>("pos")?.unwrap_or_default()),
            axis: axis / axis.norm(),
            range,
            reference: angle(v.number_or("ref", 0.0)?),
            spring_reference: angle(v.number_or("springref", 0.0)?),
            stiffness: v.nonnegative("stiffness", 0.0)?,
            damping: v.nonnegative("damping", 0.0)?,
            armature: v.nonnegative("armature", 0.0)?,
            frictionloss: v.nonnegative("frictionloss", 0.0)?,
            actuator_force_range: self.limits(&v, "actuatorfrclimited", "actuatorfrcrange")?,
        })
    }

    /// A range that is on as MuJoCo decides: `limited="true"`, or "auto" with `autolimits`
    /// and a range given; an "auto" range without `autolimits` is an error.
    fn limits(&self, v: &View, limited: &str, range: &str) -> Result<Option<[f64; 2]>> {
        let r = v.vector::<2>(range)?;
        let given = r.is_some_and(|r| r != [0.0, 0.0]);
        let on = match v.tristate(limited)? {
            Some(on) => on,
            None if given && !self.compiler.autolimits => {
                return Err(v.error_for(range, format!("`{range}` without `{limited}`: set <compiler autolimits=\"true\"/> or give `{limited}`")));
            }
            None => r.is_some_and(|[lo, hi]| lo < hi),
        };
        if !on {
            return Ok(None);
        }
        let r = r.unwrap_or_default();
        if r[0] >= r[1] {
            return Err(v.error_for(
                range,
                format!("a limited `{range}` needs its lower bound below its upper bound"),
            ));
        }
        Ok(Some(r))
    }

    fn geom(&mut self, e: &Element, childclass: &str) -> Result<Geom3> {
        self.geoms += 1;
        let v = self.begin(e, self.geoms, childclass, |c| &c.geom, tables::GEOM)?;
        let kind = match v.word(
            "type",
            &[
                "plane",
                "sphere",
                "capsule",
                "cylinder",
                "ellipsoid",
                "box",
                "mesh",
                "hfield",
                "sdf",
            ],
        )? {
            None | Some("sphere") => GeomType::Sphere,
            Some("plane") => GeomType::Plane,
            Some("capsule") => GeomType::Capsule,
            Some("cylinder") => GeomType::Cylinder,
            Some("ellipsoid") => GeomType::Ellipsoid,
            Some("box") => GeomType::Box,
            Some(other) => {
                return Err(v.error_for("type", format!("not supported: {other} geoms")));
            }
        };
        let mut size = v.up_to("size", [0.0; 3])?;
        let mut pos = V3::from(v.vector::<3>("pos")?.unwrap_or_default());
        let quat = if let Some(a) = v.get("fromto") {
            let f = v.values::<6>(a)?;
            if !matches!(
                kind,
                GeomType::Capsule | GeomType::Cylinder | GeomType::Ellipsoid | GeomType::Box
            ) {
                return Err(v.error_at(a, "fromto needs a capsule, cylinder, ellipsoid or box"));
            }
            if pos != V3::zeros() {
                return Err(v.error_at(a, "both `pos` and `fromto` are given"));
            }
            if let Some(o) = crate::orient::ORIENTATION.iter().find_map(|n| v.get(n)) {
                return Err(v.error_at(o, "both an orientation and `fromto` are given"));
            }
            let from = V3::new(f[0], f[1], f[2]);
            let to = V3::new(f[3], f[4], f[5]);
            let d = from - to;
            let half = d.norm() / 2.0;
            if half < EPS {
                return Err(v.error_at(a, "the two points are too close"));
            }
            size[1] = half;
            if matches!(kind, GeomType::Ellipsoid | GeomType::Box) {
                size[2] = half;
                size[1] = size[0];
            }
            pos = (from + to) / 2.0;
            z_to(&(d / d.norm()))
        } else {
            orientation(&v, &self.compiler.angles)?
        };
        let count = match kind {
            GeomType::Plane => 0,
            GeomType::Sphere => 1,
            GeomType::Capsule | GeomType::Cylinder => 2,
            GeomType::Ellipsoid | GeomType::Box => 3,
        };
        if let Some(i) = (0..count).find(|&i| size[i] <= 0.0) {
            return Err(v.error_for(
                "size",
                format!("size {} of a {:?} geom must be positive", i + 1, kind).to_lowercase(),
            ));
        }
        let condim = v.integer("condim", 3)?;
        if ![1, 3, 4, 6].contains(&condim) {
            return Err(v.error_for("condim", "expected 1, 3, 4 or 6"));
        }
        if condim == 4 {
            let loc = v.get("condim").map_or(&e.loc, |a| &a.loc);
            self.ctx.notice(
                NoticeKind::Ignored,
                loc,
                &e.name,
                Some("condim"),
                "torsional friction acts about the contact normal, which lies in the plane: no effect on planar motion",
            );
        }
        if condim == 6 {
            let loc = v.get("condim").map_or(&e.loc, |a| &a.loc);
            self.ctx
                .unmodelled(loc, &e.name, Some("condim"), "rolling friction (condim 6)")?;
        }
        let bits = |name: &str| -> Result<u32> {
            let x = v.integer(name, 1)?;
            u32::try_from(x)
                .map_err(|_| v.error_for(name, "expected a 32-bit mask (0 to 4294967295)"))
        };
        let density = v.nonnegative("density", 1000.0)?;
        let mass = match v.get("mass") {
            Some(a) => {
                let [m] = v.values::<1>(a)?;
                if m < 0.0 {
                    return Err(v.error_at(a, "must not be negative"));
                }
                Some(m)
            }
            None => None,
        };
        let group = v.integer("group", 0)?;
        let counted =
            group >= self.compiler.inertia_groups[0] && group <= self.compiler.inertia_groups[1];
        let mut g = Geom3 {
            name: v.string("name").map(str::to_string),
            loc: e.loc.clone(),
            kind,
            size,
            pos,
            quat,
            mass: 0.0,
            inertia: V3::zeros(),
            contype: bits("contype")?,
            conaffinity: bits("conaffinity")?,
            condim: condim as u32,
            priority: i32::try_from(v.integer("priority", 0)?)
                .map_err(|_| v.error_for("priority", "out of range"))?,
            friction: v.up_to("friction", [1.0, 0.005, 0.0001])?,
            rgba: v.vector::<4>("rgba")?.unwrap_or([0.5, 0.5, 0.5, 1.0]),
            counted,
        };
        if counted {
            crate::inertia::set_geom_mass(&mut g, mass, density);
        }
        Ok(g)
    }

    fn actuator(&mut self, e: &Element) -> Result<Actuator3> {
        no_children(e)?;
        let table = match e.name.as_str() {
            "motor" => tables::MOTOR,
            "position" => tables::POSITION,
            "velocity" => tables::VELOCITY,
            "general" | "intvelocity" | "damper" | "cylinder" | "muscle" | "adhesion"
            | "plugin" => {
                return Err(e.error(
                    None,
                    "not supported: only <motor>, <position> and <velocity> actuators are",
                ))
            }
            other => return Err(e.error(None, format!("unknown element <{other}> in <actuator>"))),
        };
        let class = class_of(self.classes, e, "main")?;
        let v = View::new(e, &class.actuator);
        v.check(table, self.ctx)?;
        let joint = v.get("joint").cloned().ok_or_else(|| {
            v.error("missing attribute `joint` (only joint transmissions are supported)")
        })?;
        let kind = match e.name.as_str() {
            "motor" => Kind3::Motor,
            "position" => Kind3::Position {
                kp: v.nonnegative("kp", 1.0)?,
                kv: v.nonnegative("kv", 0.0)?,
            },
            _ => Kind3::Velocity {
                kv: v.nonnegative("kv", 1.0)?,
            },
        };
        Ok(Actuator3 {
            name: v.string("name").map(str::to_string),
            joint,
            element: e.name.clone(),
            kind,
            gear: v.up_to("gear", [1.0, 0.0, 0.0, 0.0, 0.0, 0.0])?[0],
            ctrl_range: self.limits(&v, "ctrllimited", "ctrlrange")?,
            force_range: self.limits(&v, "forcelimited", "forcerange")?,
        })
    }
}
