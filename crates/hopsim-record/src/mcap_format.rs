//! The hopsim MCAP format (docs/recording.md): topics, JSON Schemas, and the JSON messages
//! as written (borrowing a [`Frame`]) and as read back.
//!
//! Every message is JSON (`message_encoding = "json"`) with a JSON Schema
//! (`schema encoding = "jsonschema"`, draft 2020-12), so Foxglove plots any field and the
//! Python `mcap` reader decodes it with `json.loads`. Field names carry SI units
//! (`_s`, `_m`, `_Ns`, `_J`, `_Nm`); non-finite numbers are written as `null`.

use crate::{ActuatorQuantity, BodyPose, ContactSample, Frame, RecordingInfo};
use serde::ser::SerializeMap;
use serde::{Deserialize, Deserializer, Serialize, Serializer};
use serde_json::{json, Map, Value};
use std::collections::BTreeMap;

/// Time, step, generalised coordinates and velocities, poses, CoM, actuator torque.
pub const STATE_TOPIC: &str = "/hopsim/state";
/// The contacts of the step's index set with their percussions (docs/physics.md §4).
pub const CONTACTS_TOPIC: &str = "/hopsim/contacts";
/// The energy ledger (docs/physics.md §6).
pub const ENERGY_TOPIC: &str = "/hopsim/energy";
/// Discrete events (touchdown, take-off, brake, shape switch, applied impulse).
pub const EVENTS_TOPIC: &str = "/hopsim/events";
/// Name of the metadata record describing the run.
pub const METADATA_NAME: &str = "hopsim";
/// Name of the metadata record of a recording kept after the run stopped early: why, and
/// the last step completed.
pub const STOP_METADATA_NAME: &str = "hopsim_stop";
/// Media type of the scene-file attachment.
pub(crate) const SCENE_MEDIA_TYPE: &str = "application/toml";
/// Version of this format, stored in the metadata record.
pub(crate) const FORMAT_VERSION: &str = "1";
/// Message encoding of every channel.
pub(crate) const MESSAGE_ENCODING: &str = "json";
/// Schema encoding of every channel.
pub(crate) const SCHEMA_ENCODING: &str = "jsonschema";

/// The channels of a hopsim recording, in the order they are created.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum Channel {
    State,
    Contacts,
    Energy,
    Events,
}

impl Channel {
    pub(crate) const ALL: [Channel; 4] = [
        Channel::State,
        Channel::Contacts,
        Channel::Energy,
        Channel::Events,
    ];

    pub(crate) fn topic(self) -> &'static str {
        match self {
            Channel::State => STATE_TOPIC,
            Channel::Contacts => CONTACTS_TOPIC,
            Channel::Energy => ENERGY_TOPIC,
            Channel::Events => EVENTS_TOPIC,
        }
    }

    pub(crate) fn schema_name(self) -> &'static str {
        match self {
            Channel::State => "hopsim.State",
            Channel::Contacts => "hopsim.Contacts",
            Channel::Energy => "hopsim.Energy",
            Channel::Events => "hopsim.Event",
        }
    }

    /// The channel's JSON Schema (the state's lists the scene's coordinates and bodies).
    pub(crate) fn schema(self, info: &RecordingInfo) -> Value {
        let body = match self {
            Channel::State => state_schema(info),
            Channel::Contacts => contacts_schema(),
            Channel::Energy => energy_schema(),
            Channel::Events => event_schema(),
        };
        let mut schema = json!({
            "$schema": "https://json-schema.org/draft/2020-12/schema",
            "title": self.schema_name(),
        });
        merge(&mut schema, body);
        schema
    }
}

fn merge(into: &mut Value, from: Value) {
    if let (Value::Object(into), Value::Object(from)) = (into, from) {
        into.extend(from);
    }
}

fn number(description: &str) -> Value {
    json!({ "type": "number", "description": description })
}

fn object(description: &str, properties: Map<String, Value>) -> Value {
    let required: Vec<String> = properties.keys().cloned().collect();
    json!({
        "type": "object",
        "description": description,
        "properties": properties,
        "required": required,
    })
}

fn properties<'a>(fields: impl IntoIterator<Item = (&'a str, Value)>) -> Map<String, Value> {
    fields
        .into_iter()
        .map(|(name, value)| (name.to_string(), value))
        .collect()
}

fn xy(description: &str, unit: &str) -> Value {
    object(
        description,
        properties([("x", number(unit)), ("y", number(unit))]),
    )
}

/// The fields every message starts with.
fn stamp() -> [(&'static str, Value); 2] {
    [
        ("t_s", number("simulation time, s (end of the step)")),
        (
            "step",
            json!({ "type": "integer", "minimum": 0, "description": "step index" }),
        ),
    ]
}

fn state_schema(info: &RecordingInfo) -> Value {
    let coordinates = |velocity: bool| {
        let fields = info.coordinates.iter().enumerate().map(|(i, name)| {
            let unit = info.coordinate_units[i];
            let unit = if velocity {
                unit.velocity()
            } else {
                unit.position()
            };
            (name.as_str(), number(unit))
        });
        properties(fields)
    };
    let pose = object(
        "body pose",
        properties([
            ("x_m", number("centre of mass x, m")),
            ("y_m", number("centre of mass y, m")),
            (
                "angle_rad",
                number("absolute angle, rad, counter-clockwise"),
            ),
        ]),
    );
    let bodies = properties(info.bodies.iter().map(|b| (b.name.as_str(), pose.clone())));
    let controls = properties(info.actuators.iter().map(|a| {
        (
            a.name.as_str(),
            number("the actuator's control in this step"),
        )
    }));
    let efforts = properties(info.actuators.iter().map(|a| {
        let what = match a.effort {
            ActuatorQuantity::Torque => "torque the actuator exerts at its joint, N m",
            ActuatorQuantity::Force => "force the actuator exerts along its joint, N",
        };
        (a.name.as_str(), number(what))
    }));
    let actuators = [
        (
            "controls",
            object("the actuators' controls, by name", controls),
        ),
        (
            "actuator_efforts",
            object(
                "the actuators' efforts at their joints (gear times force), by name",
                efforts,
            ),
        ),
    ];
    let actuators = actuators.into_iter().filter(|_| !info.actuators.is_empty());
    object(
        "state of the robot at a recorded step",
        properties(stamp().into_iter().chain(actuators).chain([
            ("q", object("generalised coordinates q", coordinates(false))),
            (
                "u",
                object("generalised velocities u = dq/dt", coordinates(true)),
            ),
            ("com_m", xy("whole-robot centre of mass, m", "m")),
            ("bodies", object("pose of every body", bodies)),
            (
                info.actuator.column(),
                number(match info.actuator {
                    ActuatorQuantity::Torque => "actuator torque commanded this step, N m",
                    ActuatorQuantity::Force => {
                        "actuator force along the prismatic joint commanded this step, N"
                    }
                }),
            ),
        ])),
    )
}

fn contacts_schema() -> Value {
    let contact = object(
        "one contact of the step's index set",
        properties([
            (
                "name",
                json!({ "type": "string", "description": "contact name" }),
            ),
            ("point_m", xy("contact point, m", "m")),
            ("normal", xy("unit normal, terrain towards body", "1")),
            (
                "normal_impulse_Ns",
                number("normal percussion Λ_N over the step, N s"),
            ),
            (
                "tangent_impulse_Ns",
                number("tangential percussion Λ_T over the step, N s"),
            ),
            (
                "state",
                json!({ "type": "string", "description": "open, stick or slip" }),
            ),
        ]),
    );
    object(
        "contacts of the index set at a recorded step",
        properties(
            stamp()
                .into_iter()
                .chain([("contacts", json!({ "type": "array", "items": contact }))]),
        ),
    )
}

fn energy_schema() -> Value {
    object(
        "energy ledger, J (docs/physics.md §6)",
        properties(stamp().into_iter().chain([
            ("kinetic_J", number("kinetic energy, J")),
            ("potential_J", number("gravitational potential energy, J")),
            ("spring_J", number("energy stored in springs, J")),
            (
                "actuator_work_J",
                number("work done by the actuators so far, J"),
            ),
            (
                "dissipated_J",
                number("energy dissipated in impacts and friction so far, J"),
            ),
            (
                "balance_error_J",
                number("energy balance residual (0 when the ledger closes), J"),
            ),
        ])),
    )
}

fn event_schema() -> Value {
    let mut schema = object(
        "a discrete event, logged at its time",
        properties(stamp().into_iter().chain([(
            "kind",
            json!({
                "type": "string",
                "enum": [
                    "touchdown",
                    "take_off",
                    "brake",
                    "shape_switch",
                    "shape_contact",
                    "applied_impulse",
                    "joint_limit",
                    "energy_created",
                    "indeterminate_friction"
                ],
            }),
        )])),
    );
    let optional = properties([
        (
            "contact",
            json!({
                "type": "string",
                "description": "touchdown: the contact that landed; shape_contact: the \
                                switchable shape's contact that started carrying load; \
                                energy_created: the contact whose impact added energy; \
                                indeterminate_friction: the contact resolved without friction"
            }),
        ),
        (
            "energy_J",
            number(
                "energy_created: the work of the contact's percussions in the impact, J \
                 (docs/physics.md §4.7)",
            ),
        ),
        (
            "impulse_Nms",
            number("brake: angular impulse transferred ζ, N m s (docs/physics.md §5.3)"),
        ),
        (
            "shape",
            json!({ "type": "string", "description": "shape_switch: the switched shape" }),
        ),
        (
            "active",
            json!({ "type": "boolean", "description": "shape_switch: extended (true) or retracted" }),
        ),
        (
            "magnitude",
            number("applied_impulse: magnitude, N s (linear) or N m s (rotational)"),
        ),
        (
            "limit",
            json!({
                "type": "string",
                "description": "joint_limit: the stop that started carrying load, \
                                <body>/lower or <body>/upper"
            }),
        ),
        (
            "impulse",
            number(
                "joint_limit: the stop's percussion in that step, N m s (revolute joint) or \
                 N s (prismatic joint) (docs/physics.md §7); indeterminate_friction: the \
                 contact's normal percussion, N s (docs/physics.md §4.8)",
            ),
        ),
    ]);
    if let Some(Value::Object(p)) = schema.get_mut("properties") {
        p.extend(optional);
    }
    schema
}

/// A point as `{"x": .., "y": ..}`.
#[derive(Serialize)]
struct Xy {
    x: f64,
    y: f64,
}

impl From<[f64; 2]> for Xy {
    fn from([x, y]: [f64; 2]) -> Self {
        Self { x, y }
    }
}

/// Values serialised as a JSON object keyed by their names, in order.
struct Named<'a> {
    names: &'a [String],
    values: &'a [f64],
}

impl Serialize for Named<'_> {
    fn serialize<S: Serializer>(&self, serializer: S) -> Result<S::Ok, S::Error> {
        let mut map = serializer.serialize_map(Some(self.values.len()))?;
        for (name, value) in self.names.iter().zip(self.values) {
            map.serialize_entry(name, value)?;
        }
        map.end()
    }
}

/// Body poses as a JSON object keyed by body name: `{"x_m", "y_m", "angle_rad"}` each.
struct Poses<'a> {
    names: &'a [String],
    poses: &'a [BodyPose],
}

impl Serialize for Poses<'_> {
    fn serialize<S: Serializer>(&self, serializer: S) -> Result<S::Ok, S::Error> {
        #[derive(Serialize)]
        struct Pose {
            x_m: f64,
            y_m: f64,
            angle_rad: f64,
        }
        let mut map = serializer.serialize_map(Some(self.poses.len()))?;
        for (name, pose) in self.names.iter().zip(self.poses) {
            let pose = Pose {
                x_m: pose.position[0],
                y_m: pose.position[1],
                angle_rad: pose.angle,
            };
            map.serialize_entry(name, &pose)?;
        }
        map.end()
    }
}

/// A `/hopsim/state` message.
#[derive(Serialize)]
pub(crate) struct StateMessage<'a> {
    t_s: f64,
    step: u64,
    q: Named<'a>,
    u: Named<'a>,
    com_m: Xy,
    bodies: Poses<'a>,
    /// The actuator value under the name of its quantity ([`ActuatorQuantity::column`]).
    #[serde(rename = "actuator_torque_Nm", skip_serializing_if = "Option::is_none")]
    actuator_torque: Option<f64>,
    #[serde(rename = "actuator_force_N", skip_serializing_if = "Option::is_none")]
    actuator_force: Option<f64>,
    /// The model's actuators' controls and efforts, by name (absent without actuators).
    #[serde(skip_serializing_if = "Option::is_none")]
    controls: Option<Named<'a>>,
    #[serde(skip_serializing_if = "Option::is_none")]
    actuator_efforts: Option<Named<'a>>,
}

/// The names a `/hopsim/state` message uses.
#[derive(Clone, Copy)]
pub(crate) struct StateNames<'a> {
    pub coordinates: &'a [String],
    pub bodies: &'a [String],
    pub actuators: &'a [String],
}

impl<'a> StateMessage<'a> {
    pub(crate) fn new(
        frame: &'a Frame<'a>,
        names: StateNames<'a>,
        actuator: ActuatorQuantity,
    ) -> Self {
        let StateNames {
            coordinates,
            bodies,
            actuators,
        } = names;
        let value = Some(frame.actuator_torque);
        let force = actuator == ActuatorQuantity::Force;
        let by_actuator = |values: &'a [f64]| {
            (!actuators.is_empty()).then_some(Named {
                names: actuators,
                values,
            })
        };
        Self {
            t_s: frame.t,
            step: frame.step,
            q: Named {
                names: coordinates,
                values: frame.q,
            },
            u: Named {
                names: coordinates,
                values: frame.u,
            },
            com_m: frame.com.into(),
            bodies: Poses {
                names: bodies,
                poses: frame.bodies,
            },
            actuator_torque: value.filter(|_| !force),
            actuator_force: value.filter(|_| force),
            controls: by_actuator(frame.controls),
            actuator_efforts: by_actuator(frame.actuator_efforts),
        }
    }
}

/// A `/hopsim/contacts` message.
pub(crate) struct ContactsMessage<'a> {
    pub(crate) frame: &'a Frame<'a>,
    pub(crate) names: &'a [String],
}

impl Serialize for ContactsMessage<'_> {
    fn serialize<S: Serializer>(&self, serializer: S) -> Result<S::Ok, S::Error> {
        #[derive(Serialize)]
        #[allow(non_snake_case)]
        struct Contact<'a> {
            name: &'a str,
            point_m: Xy,
            normal: Xy,
            normal_impulse_Ns: f64,
            tangent_impulse_Ns: f64,
            state: &'a str,
        }
        struct Contacts<'a>(&'a [ContactSample], &'a [String]);
        impl Serialize for Contacts<'_> {
            fn serialize<S: Serializer>(&self, serializer: S) -> Result<S::Ok, S::Error> {
                serializer.collect_seq(self.0.iter().map(|c| Contact {
                    name: self.1.get(c.contact).map_or("", String::as_str),
                    point_m: c.point.into(),
                    normal: c.normal.into(),
                    normal_impulse_Ns: c.impulse_normal,
                    tangent_impulse_Ns: c.impulse_tangent,
                    state: c.state,
                }))
            }
        }
        #[derive(Serialize)]
        struct Message<'a> {
            t_s: f64,
            step: u64,
            contacts: Contacts<'a>,
        }
        Message {
            t_s: self.frame.t,
            step: self.frame.step,
            contacts: Contacts(self.frame.contacts, self.names),
        }
        .serialize(serializer)
    }
}

/// A `/hopsim/energy` message.
#[derive(Serialize)]
#[allow(non_snake_case)]
pub(crate) struct EnergyMessage {
    t_s: f64,
    step: u64,
    kinetic_J: f64,
    potential_J: f64,
    spring_J: f64,
    actuator_work_J: f64,
    dissipated_J: f64,
    balance_error_J: f64,
}

impl EnergyMessage {
    pub(crate) fn new(frame: &Frame<'_>) -> Self {
        let e = &frame.energy;
        Self {
            t_s: frame.t,
            step: frame.step,
            kinetic_J: e.kinetic,
            potential_J: e.potential,
            spring_J: e.spring,
            actuator_work_J: e.actuator_work,
            dissipated_J: e.dissipated,
            balance_error_J: e.balance_error,
        }
    }
}

/// A number as read back: `null` (a non-finite value when written) becomes NaN.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct Number(pub(crate) f64);

impl<'de> Deserialize<'de> for Number {
    fn deserialize<D: Deserializer<'de>>(deserializer: D) -> Result<Self, D::Error> {
        Ok(Number(
            Option::<f64>::deserialize(deserializer)?.unwrap_or(f64::NAN),
        ))
    }
}

/// The part of a `/hopsim/state` message the reader uses.
#[derive(Deserialize)]
pub(crate) struct StateIn {
    pub(crate) t_s: Number,
    pub(crate) step: u64,
    pub(crate) q: BTreeMap<String, Number>,
    pub(crate) u: BTreeMap<String, Number>,
    #[serde(rename = "actuator_torque_Nm")]
    pub(crate) actuator_torque: Option<Number>,
    #[serde(rename = "actuator_force_N")]
    pub(crate) actuator_force: Option<Number>,
}

/// The part of a `/hopsim/contacts` message the reader uses.
#[derive(Deserialize)]
pub(crate) struct ContactsIn {
    pub(crate) t_s: Number,
    pub(crate) step: u64,
    pub(crate) contacts: Vec<ContactIn>,
}

#[derive(Deserialize)]
#[allow(non_snake_case)]
pub(crate) struct ContactIn {
    pub(crate) name: String,
    pub(crate) normal_impulse_Ns: Number,
    pub(crate) tangent_impulse_Ns: Number,
}

/// The metadata record `hopsim`: what is needed to rerun the recording.
/// The metadata `joints`: a JSON list of `{body, parent, kind, anchor_m, child_point_m}`
/// (bodies by name, `parent` null for the world), prismatic joints with `axis` and
/// `stroke_m`.
fn joints_json(info: &RecordingInfo) -> String {
    let name = |b: usize| info.bodies.get(b).map_or("", |body| body.name.as_str());
    let joints: Vec<Value> = info
        .joints
        .iter()
        .map(|j| {
            let mut v = serde_json::to_value(j.kind).unwrap_or(Value::Null);
            if let Value::Object(map) = &mut v {
                map.insert("body".into(), name(j.body).into());
                map.insert("parent".into(), j.parent.map(name).into());
                map.insert("anchor_m".into(), j.anchor_m.to_vec().into());
                map.insert("child_point_m".into(), j.child_point_m.to_vec().into());
            }
            v
        })
        .collect();
    Value::from(joints).to_string()
}

pub(crate) fn metadata(info: &RecordingInfo, scene_file: &str) -> BTreeMap<String, String> {
    let list = |names: &[String]| Value::from(names).to_string();
    let bodies: Vec<String> = info.bodies.iter().map(|b| b.name.clone()).collect();
    [
        ("scene", info.scene.clone()),
        ("scene_path", info.scene_path.clone()),
        ("scene_file", scene_file.to_string()),
        ("dt_s", format!("{:?}", info.dt)),
        ("coordinates", list(&info.coordinates)),
        ("bodies", list(&bodies)),
        ("contacts", list(&info.contacts)),
        ("springs", list(&info.springs)),
        ("joints", joints_json(info)),
        ("loops", crate::loops::loops_json(info)),
        ("hopsim_version", env!("CARGO_PKG_VERSION").to_string()),
        ("format_version", FORMAT_VERSION.to_string()),
    ]
    .into_iter()
    .map(|(k, v)| (k.to_string(), v))
    .collect()
}
