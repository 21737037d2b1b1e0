//! [`CsvRecorder`]: the recorded frames as one CSV row each, the events in a second file.

use crate::frame::FrameLayout;
use crate::{
    ActuatorInfo, AtomicFile, EnergySample, Event, Frame, RecordError, Recorder, RecordingInfo,
    Stop,
};
use hopsim_io::{csv_field, partial_path};
use std::io::Write;
use std::path::{Path, PathBuf};

/// Writes `FILE.csv` with one row per recorded frame and `FILE.events.csv` with one row per
/// event (docs/recording.md), both atomically. Numbers are written in their shortest
/// round-trip form.
pub struct CsvRecorder {
    frames: AtomicFile,
    events: AtomicFile,
    layout: FrameLayout,
}

/// The frame columns: `t_s, step, <q>_<unit>, <q>_dot_<unit>, com_x_m, com_y_m, energies,
/// actuator_torque_Nm` (or `actuator_force_N` for a prismatic joint's motor), then for each
/// actuator of the model `control_<name>`, and `effort_<name>_Nm` (or `_N`).
pub fn frame_columns(info: &RecordingInfo) -> Vec<String> {
    let mut columns = vec!["t_s".to_string(), "step".to_string()];
    let units = || {
        info.coordinates
            .iter()
            .enumerate()
            .map(|(i, n)| (n, info.coordinate_units[i]))
    };
    columns.extend(units().map(|(n, unit)| format!("{n}_{}", unit.position())));
    columns.extend(units().map(|(n, unit)| format!("{n}_dot_{}", unit.velocity())));
    columns.extend(["com_x_m", "com_y_m"].map(String::from));
    columns.extend(EnergySample::NAMES.map(|name| format!("{name}_J")));
    columns.push(info.actuator.column().into());
    columns.extend(info.actuators.iter().map(ActuatorInfo::control_column));
    columns.extend(info.actuators.iter().map(ActuatorInfo::effort_column));
    columns
}

/// The numbers of `frame` after `t_s` and `step`, in the order of [`frame_columns`]: `q`,
/// `u`, the centre of mass, the energies, the actuator torque, the actuators' controls and
/// efforts.
pub fn frame_values<'a>(frame: &Frame<'a>) -> impl Iterator<Item = f64> + 'a {
    let (q, u) = (frame.q, frame.u);
    let rest = frame
        .com
        .into_iter()
        .chain(frame.energy.values())
        .chain([frame.actuator_torque])
        .chain(frame.controls.iter().copied())
        .chain(frame.actuator_efforts.iter().copied());
    q.iter().chain(u).copied().chain(rest)
}

impl CsvRecorder {
    /// The events file of a frames file: `run.csv` → `run.events.csv`.
    pub fn events_path(path: &Path) -> PathBuf {
        let stem = path.file_stem().unwrap_or_default().to_string_lossy();
        path.with_file_name(format!("{stem}.events.csv"))
    }

    /// Starts `path` and its events file (both written under temporary names until `finish`).
    pub fn create(path: &Path, info: &RecordingInfo) -> Result<Self, RecordError> {
        let mut frames = AtomicFile::create(path)?;
        let events_path = Self::events_path(path);
        let mut events = AtomicFile::create(&events_path)?;
        let header: Vec<_> = frame_columns(info)
            .iter()
            .map(|c| csv_field(c).into_owned())
            .collect();
        writeln!(frames, "{}", header.join(",")).map_err(|e| RecordError::io(path, e))?;
        writeln!(events, "t_s,step,kind,details").map_err(|e| RecordError::io(&events_path, e))?;
        Ok(Self {
            frames,
            events,
            layout: FrameLayout::of(info),
        })
    }
}

impl Recorder for CsvRecorder {
    fn frame(&mut self, frame: &Frame<'_>) -> Result<(), RecordError> {
        self.layout
            .check(frame)
            .map_err(|m| RecordError::format(self.frames.path(), m))?;
        let w = &mut self.frames;
        let mut row = || -> std::io::Result<()> {
            write!(w, "{:?},{}", frame.t, frame.step)?;
            for x in frame_values(frame) {
                write!(w, ",{x:?}")?;
            }
            writeln!(w)
        };
        let written = row();
        written.map_err(|e| RecordError::io(self.frames.path(), e))
    }

    fn event(&mut self, event: &Event) -> Result<(), RecordError> {
        let details = event.kind.to_string();
        writeln!(
            self.events,
            "{:?},{},{},{}",
            event.t,
            event.step,
            event.kind.name(),
            csv_field(&details)
        )
        .map_err(|e| RecordError::io(self.events.path(), e))
    }

    fn finish(self: Box<Self>) -> Result<(), RecordError> {
        // The events first: the frames file appearing means both are complete.
        self.events.commit()?;
        Ok(self.frames.commit()?)
    }

    /// `FILE.partial.csv` and `FILE.partial.events.csv`, the latter ending with a row of
    /// kind `stopped` at the last completed step, its `details` the reason.
    fn finish_partial(mut self: Box<Self>, stop: &Stop) -> Result<Vec<PathBuf>, RecordError> {
        let reason = format!("reason={}", stop.reason);
        writeln!(
            self.events,
            "{:?},{},stopped,{}",
            stop.t,
            stop.step,
            csv_field(&reason)
        )
        .map_err(|e| RecordError::io(self.events.path(), e))?;
        let frames = partial_path(self.frames.path());
        let events = self.events.commit_as(&Self::events_path(&frames))?;
        Ok(vec![self.frames.commit_as(&frames)?, events])
    }
}
