//! Recording sinks: a simulation hands every recorded [`Frame`] and every [`Event`] to a
//! [`Recorder`]; MCAP, Rerun and CSV recorders turn them into files the usual tools open
//! (docs/recording.md). Every file is written atomically ([`AtomicFile`]).
//!
//! The crate also reads its MCAP recordings back ([`McapRecording`]) and compares two
//! recordings or impulse traces ([`diff_run_files`], used by `hopsim compare`).

mod compare;
mod csv;
mod foxglove;
mod frame;
mod geometry;
mod loops;
mod mcap_format;
mod mcap_read;
mod mcap_write;
#[cfg(feature = "rerun")]
mod rerun_sink;
mod trace;

pub use compare::{
    diff_recorded_states, diff_run_files, RunDiff, RunDiffOptions, StateDifference, StateMismatch,
};
pub use csv::{frame_columns, frame_values, CsvRecorder};
pub use foxglove::{body_frame, SCENE_TOPIC as FOXGLOVE_SCENE_TOPIC};
pub use foxglove::{TRANSFORMS_TOPIC as FOXGLOVE_TRANSFORMS_TOPIC, WORLD_FRAME};
pub use frame::{
    recorded_time, ActuatorInfo, ActuatorQuantity, BodyInfo, BodyPose, ContactSample, EnergySample,
    Event, EventKind, Frame, JointInfo, JointInfoKind, RecordingInfo, TIME_DECIMALS,
};
pub use geometry::CoordinateUnit;
pub use hopsim_io::{partial_path, write_atomically, AtomicFile};
pub use loops::{LoopInfo, LoopInfoKind};
pub use mcap_format::{
    CONTACTS_TOPIC, ENERGY_TOPIC, EVENTS_TOPIC, METADATA_NAME, STATE_TOPIC, STOP_METADATA_NAME,
};
pub use mcap_read::{
    McapRecording, RecordingMetadata, SceneAttachment, StateSample, BRAKE_CHANNEL,
    MAX_RECORDING_BYTES,
};
pub use mcap_write::McapRecorder;
#[cfg(feature = "rerun")]
pub use rerun_sink::{Pace, RerunRecorder, RERUN_VIEWER_INSTALL, STEP_TIMELINE, TIME_TIMELINE};
pub use trace::{
    ImpulseSample, ImpulseTrace, TraceDifference, TraceError, TraceTolerance, BLESS_ENV,
    MAX_TRACE_BYTES,
};

/// Types of the public API from other hopsim crates, re-exported for the CLI and tests.
pub use hopsim_model::{Shape, Terrain};

use std::path::{Path, PathBuf};

/// What can go wrong while recording or reading a recording.
#[derive(Debug, thiserror::Error)]
pub enum RecordError {
    #[error("{path}: {source}")]
    Io {
        path: String,
        source: std::io::Error,
    },
    #[error("{path}: {message}")]
    Format { path: String, message: String },
    /// The live Rerun viewer could not be started.
    #[error("{0}")]
    Viewer(String),
}

impl From<hopsim_io::IoError> for RecordError {
    fn from(e: hopsim_io::IoError) -> Self {
        Self::io(&e.path, e.source)
    }
}

impl RecordError {
    pub(crate) fn io(path: &Path, source: std::io::Error) -> Self {
        Self::Io {
            path: path.display().to_string(),
            source,
        }
    }

    pub(crate) fn format(path: &Path, message: impl std::fmt::Display) -> Self {
        Self::Format {
            path: path.display().to_string(),
            message: message.to_string(),
        }
    }
}

/// Why a run stopped before its end, and the last step it completed: what a recording
/// kept after the stop says about itself.
#[derive(Clone, Debug, PartialEq)]
pub struct Stop {
    /// The error that stopped the run, in words.
    pub reason: String,
    /// The last step the run completed (0: none after the initial state).
    pub step: u64,
    /// Simulation time at the end of that step, s.
    pub t: f64,
}

impl std::fmt::Display for Stop {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(
            f,
            "the run stopped after step {} (t = {} s): {}",
            self.step, self.t, self.reason
        )
    }
}

/// A sink for frames and events. `finish` makes the output complete (e.g. renames the
/// temporary file into place); a recorder dropped without `finish` leaves no file that
/// looks complete. Recorders are `Send`, so that a run stepped on another thread (a copy of
/// a batch) can be recorded.
pub trait Recorder: Send {
    /// Records one frame (at the recording rate and at every event step).
    fn frame(&mut self, frame: &Frame<'_>) -> Result<(), RecordError>;
    /// Records a discrete event exactly at its time.
    fn event(&mut self, event: &Event) -> Result<(), RecordError>;
    /// Completes the output.
    fn finish(self: Box<Self>) -> Result<(), RecordError>;
    /// Keeps what was recorded before the run stopped, with `stop` in the recording, under
    /// the [`partial_path`] of each output (`robbit.partial.mcap`); returns those paths.
    /// The complete outputs' paths are left as they were. A recorder without files (frames
    /// kept in memory) keeps nothing.
    fn finish_partial(self: Box<Self>, stop: &Stop) -> Result<Vec<PathBuf>, RecordError> {
        let _ = stop;
        Ok(Vec::new())
    }
}

/// Several recorders fed the same frames and events, in the order they were pushed.
#[derive(Default)]
pub struct RecorderSet {
    recorders: Vec<Box<dyn Recorder>>,
}

impl RecorderSet {
    /// Adds a recorder.
    pub fn push(&mut self, recorder: Box<dyn Recorder>) {
        self.recorders.push(recorder);
    }

    /// True when no recorder was added (the caller may then skip building frames).
    pub fn is_empty(&self) -> bool {
        self.recorders.is_empty()
    }

    /// Hands `frame` to every recorder; stops at the first error.
    pub fn frame(&mut self, frame: &Frame<'_>) -> Result<(), RecordError> {
        self.recorders.iter_mut().try_for_each(|r| r.frame(frame))
    }

    /// Hands `event` to every recorder; stops at the first error.
    pub fn event(&mut self, event: &Event) -> Result<(), RecordError> {
        self.recorders.iter_mut().try_for_each(|r| r.event(event))
    }

    /// Keeps every recorder's output up to `stop` ([`Recorder::finish_partial`]), even
    /// after one failed; returns the files kept, or the first error.
    pub fn finish_partial(self, stop: &Stop) -> Result<Vec<PathBuf>, RecordError> {
        let mut kept = Vec::new();
        let mut first = Ok(());
        for recorder in self.recorders {
            match recorder.finish_partial(stop) {
                Ok(paths) => kept.extend(paths),
                Err(e) if first.is_ok() => first = Err(e),
                Err(_) => {}
            }
        }
        first.map(|()| kept)
    }

    /// Finishes every recorder, even after one failed, and returns the first error.
    pub fn finish(self) -> Result<(), RecordError> {
        let mut first = Ok(());
        for recorder in self.recorders {
            let result = recorder.finish();
            if first.is_ok() {
                first = result;
            }
        }
        first
    }
}
