//! Reads a hopsim MCAP recording back: the run's description, the scene file, the states,
//! the contact-impulse trace and the events (for `hopsim compare` and for tests).

use crate::mcap_format::{
    Channel, ContactsIn, StateIn, MESSAGE_ENCODING, METADATA_NAME, SCENE_MEDIA_TYPE,
};
use crate::{Event, EventKind, RecordError};
use hopsim_step::{ImpulseSample, ImpulseTrace};
use mcap::{MessageStream, Summary};
use std::collections::BTreeMap;
use std::path::Path;

/// Channel name of brake impulses in a trace read from MCAP (from `/hopsim/events`).
pub const BRAKE_CHANNEL: &str = "brake";

/// The `hopsim` metadata record.
#[derive(Clone, Debug, PartialEq)]
pub struct RecordingMetadata {
    pub scene: String,
    pub scene_path: String,
    /// Name of the scene-file attachment.
    pub scene_file: String,
    /// Step size, s.
    pub dt: f64,
    pub coordinates: Vec<String>,
    pub bodies: Vec<String>,
    pub contacts: Vec<String>,
    pub springs: Vec<String>,
    /// Version of hopsim that wrote the recording.
    pub hopsim_version: String,
}

/// The scene file stored in the recording.
#[derive(Clone, Debug, PartialEq)]
pub struct SceneAttachment {
    pub name: String,
    pub media_type: String,
    pub text: String,
}

/// One `/hopsim/state` message.
#[derive(Clone, Debug, PartialEq)]
pub struct StateSample {
    pub step: u64,
    /// Time, s.
    pub t: f64,
    /// Generalised coordinates, in the order of [`RecordingMetadata::coordinates`].
    pub q: Vec<f64>,
    /// Generalised velocities, same order.
    pub u: Vec<f64>,
}

/// A hopsim MCAP recording, read back.
#[derive(Clone, Debug, PartialEq)]
pub struct McapRecording {
    pub metadata: RecordingMetadata,
    /// The scene file, if the recording has it.
    pub scene: Option<SceneAttachment>,
    /// Every state message, in file (time) order.
    pub states: Vec<StateSample>,
    /// The contacts' percussions at the recorded steps (contacts with a non-zero `Λ_N` or
    /// `Λ_T`, channel = contact name) and each brake's impulse (channel [`BRAKE_CHANNEL`]).
    pub impulses: ImpulseTrace,
    /// Every event, in file (time) order.
    pub events: Vec<Event>,
}

impl McapRecording {
    /// Reads the recording at `path`; errors name the file and what is wrong with it.
    pub fn read(path: &Path) -> Result<Self, RecordError> {
        let bytes = std::fs::read(path).map_err(|e| RecordError::io(path, e))?;
        Self::from_bytes(&bytes, path)
    }

    /// Reads a recording held in memory; `origin` names it in errors.
    pub fn from_bytes(bytes: &[u8], origin: &Path) -> Result<Self, RecordError> {
        let fail = |message: String| RecordError::format(origin, message);
        if !bytes.starts_with(mcap::MAGIC) {
            return Err(fail("not an MCAP file (no MCAP magic at the start)".into()));
        }
        let summary = Summary::read(bytes)
            .map_err(|e| fail(format!("unreadable MCAP file: {e}")))?
            .ok_or_else(|| {
                fail("MCAP file without summary section (an unfinished recording?)".into())
            })?;
        let metadata = read_metadata(bytes, &summary).map_err(fail)?;
        for channel in Channel::ALL {
            let found = summary
                .channels
                .values()
                .find(|c| c.topic == channel.topic());
            match found {
                None => return Err(fail(format!("missing channel {}", channel.topic()))),
                Some(c) if c.message_encoding != MESSAGE_ENCODING => {
                    return Err(fail(format!(
                        "channel {} has message encoding '{}', expected '{MESSAGE_ENCODING}'",
                        c.topic, c.message_encoding
                    )))
                }
                Some(_) => {}
            }
        }
        let scene = read_scene(bytes, &summary, &metadata.scene_file).map_err(fail)?;
        let mut recording = Self {
            metadata,
            scene,
            states: Vec::new(),
            impulses: ImpulseTrace::default(),
            events: Vec::new(),
        };
        let stream =
            MessageStream::new(bytes).map_err(|e| fail(format!("unreadable MCAP file: {e}")))?;
        for message in stream {
            let message = message.map_err(|e| fail(format!("unreadable MCAP file: {e}")))?;
            let topic = message.channel.topic.as_str();
            recording
                .add_message(topic, &message.data)
                .map_err(|e| fail(format!("{topic} message {}: {e}", message.sequence)))?;
        }
        Ok(recording)
    }

    /// Decodes one message into the recording.
    fn add_message(&mut self, topic: &str, data: &[u8]) -> Result<(), String> {
        let bad_json = |e: serde_json::Error| format!("invalid message JSON: {e}");
        match Channel::ALL.into_iter().find(|c| c.topic() == topic) {
            Some(Channel::State) => {
                let state: StateIn = serde_json::from_slice(data).map_err(bad_json)?;
                let names = &self.metadata.coordinates;
                self.states.push(StateSample {
                    step: state.step,
                    t: state.t_s.0,
                    q: ordered(&state.q, names, "q")?,
                    u: ordered(&state.u, names, "u")?,
                });
            }
            Some(Channel::Contacts) => {
                let contacts: ContactsIn = serde_json::from_slice(data).map_err(bad_json)?;
                let samples = contacts.contacts.into_iter().filter_map(|c| {
                    let (normal, tangent) = (c.normal_impulse_Ns.0, c.tangent_impulse_Ns.0);
                    (normal != 0.0 || tangent != 0.0).then_some(ImpulseSample {
                        step: contacts.step,
                        t: contacts.t_s.0,
                        channel: c.name,
                        normal,
                        tangent,
                    })
                });
                self.impulses.samples.extend(samples);
            }
            Some(Channel::Events) => {
                let event: Event = serde_json::from_slice(data).map_err(bad_json)?;
                if let EventKind::Brake { impulse } = event.kind {
                    self.impulses.samples.push(ImpulseSample {
                        step: event.step,
                        t: event.t,
                        channel: BRAKE_CHANNEL.into(),
                        normal: impulse,
                        tangent: 0.0,
                    });
                }
                self.events.push(event);
            }
            Some(Channel::Energy) | None => {}
        }
        Ok(())
    }

    /// The steps that have a state message, in order.
    pub fn recorded_steps(&self) -> impl Iterator<Item = u64> + '_ {
        self.states.iter().map(|s| s.step)
    }
}

/// The values of `map` in the order of `names`.
fn ordered(
    map: &BTreeMap<String, crate::mcap_format::Number>,
    names: &[String],
    what: &str,
) -> Result<Vec<f64>, String> {
    names
        .iter()
        .map(|name| {
            map.get(name)
                .map(|v| v.0)
                .ok_or_else(|| format!("no {what}.{name}"))
        })
        .collect()
}

fn read_metadata(bytes: &[u8], summary: &Summary) -> Result<RecordingMetadata, String> {
    let index = summary
        .metadata_indexes
        .iter()
        .find(|m| m.name == METADATA_NAME)
        .ok_or_else(|| format!("not a hopsim recording (no '{METADATA_NAME}' metadata record)"))?;
    let record = mcap::read::metadata(bytes, index)
        .map_err(|e| format!("unreadable '{METADATA_NAME}' metadata record: {e}"))?;
    let field = |key: &str| {
        record
            .metadata
            .get(key)
            .cloned()
            .ok_or_else(|| format!("the '{METADATA_NAME}' metadata record has no '{key}'"))
    };
    let list = |key: &str| {
        let text = field(key)?;
        serde_json::from_str::<Vec<String>>(&text).map_err(|e| {
            format!("'{METADATA_NAME}' metadata '{key}' is not a JSON list of names: {e}")
        })
    };
    let dt = field("dt_s")?;
    Ok(RecordingMetadata {
        scene: field("scene")?,
        scene_path: field("scene_path")?,
        scene_file: field("scene_file")?,
        dt: dt
            .parse()
            .map_err(|_| format!("'{METADATA_NAME}' metadata 'dt_s' = '{dt}' is not a number"))?,
        coordinates: list("coordinates")?,
        bodies: list("bodies")?,
        contacts: list("contacts")?,
        springs: list("springs")?,
        hopsim_version: field("hopsim_version")?,
    })
}

fn read_scene(
    bytes: &[u8],
    summary: &Summary,
    name: &str,
) -> Result<Option<SceneAttachment>, String> {
    let Some(index) = summary
        .attachment_indexes
        .iter()
        .find(|a| a.name == name && a.media_type == SCENE_MEDIA_TYPE)
    else {
        return Ok(None);
    };
    let attachment = mcap::read::attachment(bytes, index)
        .map_err(|e| format!("unreadable attachment '{name}': {e}"))?;
    let text = String::from_utf8(attachment.data.into_owned())
        .map_err(|_| format!("attachment '{name}' is not UTF-8 text"))?;
    Ok(Some(SceneAttachment {
        name: attachment.name,
        media_type: attachment.media_type,
        text,
    }))
}
