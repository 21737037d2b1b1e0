//! [`McapRecorder`]: JSON messages with JSON Schemas in a chunked, zstd-compressed MCAP file
//! that Foxglove and the Python `mcap` reader open (docs/recording.md).

use crate::foxglove::{
    FoxgloveScene, SCENE_SCHEMA, SCENE_TOPIC, TRANSFORMS_SCHEMA, TRANSFORMS_TOPIC,
};
use crate::frame::FrameLayout;
use crate::mcap_format::{
    metadata, Channel, ContactsMessage, EnergyMessage, StateMessage, StateNames, MESSAGE_ENCODING,
    METADATA_NAME, SCENE_MEDIA_TYPE, SCHEMA_ENCODING, STOP_METADATA_NAME,
};
use crate::{
    ActuatorQuantity, AtomicFile, Event, Frame, RecordError, Recorder, RecordingInfo, Stop,
};
use mcap::records::{MessageHeader, Metadata};
use mcap::{Attachment, Compression, WriteOptions, Writer};
use serde::Serialize;
use std::borrow::Cow;
use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

/// Writes a hopsim MCAP recording: channels `/hopsim/state`, `/hopsim/contacts`,
/// `/hopsim/energy` (one message each per frame) and `/hopsim/events` (one per event);
/// Foxglove's `/foxglove/transforms` (per frame) and `/foxglove/scene` (when the scene
/// changes) for its 3D panel; log and publish time = simulation time in ns; the scene file
/// as an attachment and a metadata record `hopsim` describing the run.
pub struct McapRecorder {
    out: MessageWriter,
    scene: FoxgloveScene,
    layout: FrameLayout,
    coordinates: Vec<String>,
    bodies: Vec<String>,
    actuators: Vec<String>,
    contacts: Vec<String>,
    actuator: ActuatorQuantity,
}

/// The MCAP writer with its channels.
struct MessageWriter {
    writer: Writer<AtomicFile>,
    /// Channel id and message count, indexed like [`Channel::ALL`], then
    /// [`SCENE_SLOT`] and [`TRANSFORMS_SLOT`].
    channels: [(u16, u32); 6],
    /// Reused JSON buffer.
    buffer: Vec<u8>,
    path: PathBuf,
}

/// Channel slots of the Foxglove topics, after those of [`Channel::ALL`].
const SCENE_SLOT: usize = Channel::ALL.len();
const TRANSFORMS_SLOT: usize = SCENE_SLOT + 1;

/// Simulation time in ns, the MCAP log and publish time (negative and NaN times map to 0).
pub(crate) fn nanoseconds(t: f64) -> u64 {
    (t * 1e9).round() as u64
}

/// The attachment name of the scene file: its file name, or `scene.toml`.
pub(crate) fn scene_file_name(info: &RecordingInfo) -> String {
    Path::new(&info.scene_path)
        .file_name()
        .map_or_else(|| "scene.toml".into(), |n| n.to_string_lossy().into_owned())
}

impl McapRecorder {
    /// Writes the summary and index sections; the file is then complete but not yet in place.
    fn close(self: Box<Self>) -> Result<AtomicFile, RecordError> {
        let MessageWriter {
            mut writer, path, ..
        } = self.out;
        writer.finish().map_err(|e| RecordError::format(&path, e))?;
        Ok(writer.into_inner())
    }

    /// Starts a recording at `path` (written under a temporary name until `finish`).
    pub fn create(path: &Path, info: &RecordingInfo) -> Result<Self, RecordError> {
        let err = |e: mcap::McapError| RecordError::format(path, e);
        let file = AtomicFile::create(path)?;
        let options = WriteOptions::new()
            .compression(Some(Compression::Zstd))
            .compression_threads(0)
            .library(format!("hopsim {}", env!("CARGO_PKG_VERSION")));
        let mut writer = options.create(file).map_err(err)?;
        let scene_file = scene_file_name(info);
        writer
            .write_metadata(&Metadata {
                name: METADATA_NAME.into(),
                metadata: metadata(info, &scene_file),
            })
            .map_err(err)?;
        writer
            .attach(&Attachment {
                log_time: 0,
                create_time: 0,
                name: scene_file,
                media_type: SCENE_MEDIA_TYPE.into(),
                data: Cow::Borrowed(info.scene_text.as_bytes()),
            })
            .map_err(err)?;
        let ours = Channel::ALL.map(|c| (c.topic(), c.schema_name(), c.schema(info).to_string()));
        let foxglove = [
            (SCENE_TOPIC, SCENE_SCHEMA),
            (TRANSFORMS_TOPIC, TRANSFORMS_SCHEMA),
        ]
        .map(|(topic, (name, schema))| (topic, name, schema.to_string()));
        let mut channels = [(0, 0); 6];
        for (slot, (topic, name, schema)) in
            channels.iter_mut().zip(ours.into_iter().chain(foxglove))
        {
            let schema_id = writer
                .add_schema(name, SCHEMA_ENCODING, schema.as_bytes())
                .map_err(err)?;
            let id = writer
                .add_channel(schema_id, topic, MESSAGE_ENCODING, &BTreeMap::new())
                .map_err(err)?;
            *slot = (id, 0);
        }
        Ok(Self {
            out: MessageWriter {
                writer,
                channels,
                buffer: Vec::with_capacity(1024),
                path: path.to_path_buf(),
            },
            scene: FoxgloveScene::new(info),
            layout: FrameLayout::of(info),
            coordinates: info.coordinates.clone(),
            bodies: info.bodies.iter().map(|b| b.name.clone()).collect(),
            actuators: info.actuators.iter().map(|a| a.name.clone()).collect(),
            contacts: info.contacts.clone(),
            actuator: info.actuator,
        })
    }
}

impl MessageWriter {
    /// Serialises `message` and writes it on `channel` at simulation time `t`.
    fn write(
        &mut self,
        channel: Channel,
        t: f64,
        message: &impl Serialize,
    ) -> Result<(), RecordError> {
        self.write_slot(channel as usize, t, message)
    }

    /// Serialises `message` and writes it on the channel of `slot` at simulation time `t`.
    fn write_slot(
        &mut self,
        slot: usize,
        t: f64,
        message: &impl Serialize,
    ) -> Result<(), RecordError> {
        self.buffer.clear();
        serde_json::to_writer(&mut self.buffer, message)
            .map_err(|e| RecordError::format(&self.path, e))?;
        let (channel_id, count) = &mut self.channels[slot];
        let time = nanoseconds(t);
        let header = MessageHeader {
            channel_id: *channel_id,
            sequence: *count,
            log_time: time,
            publish_time: time,
        };
        *count = count.wrapping_add(1);
        self.writer
            .write_to_known_channel(&header, &self.buffer)
            .map_err(|e| RecordError::format(&self.path, e))
    }
}

impl Recorder for McapRecorder {
    fn frame(&mut self, frame: &Frame<'_>) -> Result<(), RecordError> {
        let out = &mut self.out;
        self.layout
            .check(frame)
            .map_err(|m| RecordError::format(&out.path, m))?;
        let names = StateNames {
            coordinates: &self.coordinates,
            bodies: &self.bodies,
            actuators: &self.actuators,
        };
        let state = StateMessage::new(frame, names, self.actuator);
        out.write(Channel::State, frame.t, &state)?;
        let contacts = ContactsMessage {
            frame,
            names: &self.contacts,
        };
        out.write(Channel::Contacts, frame.t, &contacts)?;
        out.write(Channel::Energy, frame.t, &EnergyMessage::new(frame))?;
        if let Some(update) = self.scene.update(frame) {
            out.write_slot(SCENE_SLOT, frame.t, &update)?;
        }
        let transforms = self.scene.transforms(frame);
        out.write_slot(TRANSFORMS_SLOT, frame.t, &transforms)
    }

    fn event(&mut self, event: &Event) -> Result<(), RecordError> {
        self.out.write(Channel::Events, event.t, event)
    }

    fn finish(self: Box<Self>) -> Result<(), RecordError> {
        Ok(self.close()?.commit()?)
    }

    /// `FILE.partial.mcap` with a metadata record [`STOP_METADATA_NAME`]: `reason`, `step`
    /// and `t_s` of the last completed step.
    fn finish_partial(mut self: Box<Self>, stop: &Stop) -> Result<Vec<PathBuf>, RecordError> {
        let out = &mut self.out;
        let metadata = [
            ("reason", stop.reason.clone()),
            ("step", stop.step.to_string()),
            ("t_s", format!("{:?}", stop.t)),
        ];
        out.writer
            .write_metadata(&Metadata {
                name: STOP_METADATA_NAME.into(),
                metadata: metadata
                    .into_iter()
                    .map(|(k, v)| (k.to_string(), v))
                    .collect(),
            })
            .map_err(|e| RecordError::format(&out.path, e))?;
        Ok(vec![self.close()?.commit_partial()?])
    }
}
