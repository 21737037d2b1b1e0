//! Recording sinks: a simulation hands every recorded [`Frame`] and every [`Event`] to a
//! [`Recorder`]; MCAP, Rerun and CSV recorders turn them into files the usual tools open.

mod frame;

pub use frame::{
    BodyInfo, BodyPose, ContactSample, EnergySample, Event, EventKind, Frame, RecordingInfo,
};

/// What can go wrong while recording.
#[derive(Debug, thiserror::Error)]
pub enum RecordError {
    #[error("{path}: {source}")]
    Io {
        path: String,
        source: std::io::Error,
    },
    #[error("{path}: {message}")]
    Format { path: String, message: String },
}

/// A sink for frames and events. `finish` makes the output complete (e.g. renames the
/// temporary file into place); a recorder dropped without `finish` leaves no file that
/// looks complete.
pub trait Recorder {
    /// Records one frame (at the recording rate and at every event step).
    fn frame(&mut self, frame: &Frame<'_>) -> Result<(), RecordError>;
    /// Records a discrete event exactly at its time.
    fn event(&mut self, event: &Event) -> Result<(), RecordError>;
    /// Completes the output.
    fn finish(self: Box<Self>) -> Result<(), RecordError>;
}
