//! Reads a hopsim MCAP recording back: the run's description, the scene file, the states,
//! the contact-impulse trace, the events and, for a run that stopped early, its stop record
//! (for `hopsim compare`, the Python package and tests).

use crate::mcap_format::{
    Channel, ContactsIn, StateIn, MESSAGE_ENCODING, METADATA_NAME, SCENE_MEDIA_TYPE,
    STOP_METADATA_NAME,
};
use crate::{Event, EventKind, RecordError, Stop};
use crate::{ImpulseSample, ImpulseTrace};
use mcap::sans_io::{LinearReadEvent, LinearReader, LinearReaderOptions};
use mcap::{MessageStream, Summary};
use std::collections::BTreeMap;
use std::path::Path;

/// Largest recording [`McapRecording::read`] reads, bytes (2 GiB; the whole file is held in
/// memory).
pub const MAX_RECORDING_BYTES: u64 = 2 << 30;
/// Largest record (or decompressed chunk record) accepted, bytes: a corrupted length field
/// is an error, not a huge allocation.
const MAX_RECORD_BYTES: usize = 256 << 20;

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
    /// Actuator torque commanded in the step that ended at `t`, N m (0 when idle).
    pub actuator_torque: f64,
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
    /// Why the run stopped early, for a recording kept after the stop
    /// (`FILE.partial.mcap`, its [`STOP_METADATA_NAME`] record); `None` for a complete run.
    pub stop: Option<Stop>,
}

impl McapRecording {
    /// Reads the recording at `path` (at most [`MAX_RECORDING_BYTES`]); errors name the
    /// file and what is wrong with it.
    pub fn read(path: &Path) -> Result<Self, RecordError> {
        let bytes = read_input(path, MAX_RECORDING_BYTES)?;
        Self::from_bytes(&bytes, path)
    }

    /// Reads a recording held in memory; `origin` names it in errors. The whole file is
    /// checked first: its chunk, data-section and summary CRCs, its records, and that
    /// nothing follows its closing magic; any failure is a "corrupt MCAP file" error.
    pub fn from_bytes(bytes: &[u8], origin: &Path) -> Result<Self, RecordError> {
        let fail = |message: String| RecordError::format(origin, message);
        if !bytes.starts_with(mcap::MAGIC) {
            return Err(fail("not an MCAP file (no MCAP magic at the start)".into()));
        }
        validate(bytes).map_err(|e| fail(format!("corrupt MCAP file: {e}")))?;
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
        let stop = read_stop(bytes, &summary).map_err(fail)?;
        let mut recording = Self {
            metadata,
            scene,
            states: Vec::new(),
            impulses: ImpulseTrace::default(),
            events: Vec::new(),
            stop,
        };
        let options = mcap::read::Options::ValidateChunkCrcs.into();
        let stream = MessageStream::new_with_options(bytes, options)
            .map_err(|e| fail(format!("unreadable MCAP file: {e}")))?;
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
                    actuator_torque: state
                        .actuator_torque
                        .or(state.actuator_force)
                        .map_or(0.0, |n| n.0),
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

/// Reads the whole MCAP file `bytes` as a stream of records, checking every CRC the file
/// has (chunks, data section, summary section; attachments are checked when parsed), the
/// closing magic, and that no byte follows it (a file concatenated to itself, or
/// trailing garbage).
fn validate(bytes: &[u8]) -> Result<(), String> {
    let options = LinearReaderOptions::default()
        .with_validate_chunk_crcs(true)
        .with_validate_data_section_crc(true)
        .with_validate_summary_section_crc(true)
        .with_check_finishes_after_end_magic(true)
        .with_record_length_limit(MAX_RECORD_BYTES);
    let mut reader = LinearReader::new_with_options(options);
    let mut rest = bytes;
    while let Some(event) = reader.next_event() {
        match event.map_err(|e| e.to_string())? {
            LinearReadEvent::ReadRequest(n) => {
                let n = n.min(rest.len());
                reader.insert(n).copy_from_slice(&rest[..n]);
                reader.notify_read(n);
                rest = &rest[n..];
            }
            LinearReadEvent::Record { opcode, data } => {
                // mcap 0.26 `parse_record` slices out of bounds (panics) on an attachment
                // record shorter than its header and CRC: check that first.
                if opcode == mcap::records::op::ATTACHMENT && !attachment_fits(data) {
                    return Err(format!(
                        "attachment record of {} bytes is shorter than its header",
                        data.len()
                    ));
                }
                // Parsing checks each record's own structure (and an attachment's CRC).
                mcap::parse_record(opcode, data).map_err(|e| e.to_string())?;
            }
        }
    }
    Ok(())
}

/// Whether an attachment record's body holds its header (log and create time, name and
/// media type as length-prefixed strings, data length) and the trailing CRC.
fn attachment_fits(body: &[u8]) -> bool {
    let length_at = |at: usize| -> Option<usize> {
        let b = body.get(at..at.checked_add(4)?)?;
        usize::try_from(u32::from_le_bytes(b.try_into().ok()?)).ok()
    };
    let header_and_crc = || -> Option<usize> {
        let media_at = 20usize.checked_add(length_at(16)?)?;
        media_at
            .checked_add(4)?
            .checked_add(length_at(media_at)?)?
            .checked_add(8 + 4)
    };
    header_and_crc().is_some_and(|len| len <= body.len())
}

/// The bytes of the input file at `path`: at most `limit`. A regular file above the limit
/// is refused unread; any other input (a pipe, a device) is read in blocks up to the
/// limit, and refused at once when it neither starts with the MCAP magic nor is text (a
/// NUL byte), so `/dev/zero` or `/dev/urandom` costs one block.
pub(crate) fn read_input(path: &Path, limit: u64) -> Result<Vec<u8>, RecordError> {
    let content = hopsim_io::Content::MagicOrText {
        magic: mcap::MAGIC,
        format: "MCAP",
    };
    hopsim_io::read_bounded(path, limit, "recordings", content)
        .map_err(|e| RecordError::io(path, e))
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
    let name = METADATA_NAME;
    let record = metadata_record(bytes, summary, name)?
        .ok_or_else(|| format!("not a hopsim recording (no '{name}' metadata record)"))?;
    let field = |key: &str| metadata_field(&record, name, key).map(str::to_string);
    let list = |key: &str| {
        let text = field(key)?;
        serde_json::from_str::<Vec<String>>(&text)
            .map_err(|e| format!("'{name}' metadata '{key}' is not a JSON list of names: {e}"))
    };
    Ok(RecordingMetadata {
        scene: field("scene")?,
        scene_path: field("scene_path")?,
        scene_file: field("scene_file")?,
        dt: metadata_number(&record, name, "dt_s", "a number")?,
        coordinates: list("coordinates")?,
        bodies: list("bodies")?,
        contacts: list("contacts")?,
        springs: list("springs")?,
        hopsim_version: field("hopsim_version")?,
    })
}

/// The [`STOP_METADATA_NAME`] record (`reason`, `step`, `t_s`), if the recording has one.
fn read_stop(bytes: &[u8], summary: &Summary) -> Result<Option<Stop>, String> {
    let name = STOP_METADATA_NAME;
    let Some(record) = metadata_record(bytes, summary, name)? else {
        return Ok(None);
    };
    Ok(Some(Stop {
        reason: metadata_field(&record, name, "reason")?.to_string(),
        step: metadata_number(&record, name, "step", "a step number")?,
        t: metadata_number(&record, name, "t_s", "a number")?,
    }))
}

/// The key–value pairs of the metadata record `name`, if the recording has one.
fn metadata_record(
    bytes: &[u8],
    summary: &Summary,
    name: &str,
) -> Result<Option<BTreeMap<String, String>>, String> {
    let Some(index) = summary.metadata_indexes.iter().find(|m| m.name == name) else {
        return Ok(None);
    };
    let record = mcap::read::metadata(bytes, index)
        .map_err(|e| format!("unreadable '{name}' metadata record: {e}"))?;
    Ok(Some(record.metadata))
}

/// The value of `key` in the metadata record `name`.
fn metadata_field<'r>(
    record: &'r BTreeMap<String, String>,
    name: &str,
    key: &str,
) -> Result<&'r str, String> {
    record
        .get(key)
        .map(String::as_str)
        .ok_or_else(|| format!("the '{name}' metadata record has no '{key}'"))
}

/// The value of `key` in the metadata record `name`, parsed as `what`.
fn metadata_number<T: std::str::FromStr>(
    record: &BTreeMap<String, String>,
    name: &str,
    key: &str,
    what: &str,
) -> Result<T, String> {
    let text = metadata_field(record, name, key)?;
    text.parse()
        .map_err(|_| format!("'{name}' metadata '{key}' = '{text}' is not {what}"))
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
