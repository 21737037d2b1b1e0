//! [`RerunRecorder`]: the run as a Rerun recording (`.rrd` file or live viewer), with the
//! robot drawn in 2D and time series of its state, energies and contact impulses
//! (entities and timelines in docs/recording.md).
//!
//! What changes every frame (time series, body poses, the centre of mass, springs,
//! contact forces) is buffered in columns and sent in chunks ([`RecordingStream::send_columns`]);
//! shape outlines are logged in their body's frame, once and again only when a shape is
//! switched, and placed by the body's transform.
//!
//! Modules: [`live`] (pacing a live stream), [`columns`] (the per-frame column buffers),
//! [`drawing`] (the robot, terrain, arrows and markers), [`layout`] (the blueprint).

mod columns;
mod drawing;
mod layout;
mod live;

use crate::frame::FrameLayout;
use crate::{Event, Frame, RecordError, Recorder, RecordingInfo, Stop};
use columns::{Columns, CHUNK_FRAMES};
use drawing::{event_color, Drawing, EVENT_MARKER_HOLD_S, TRAIL_ENTITY};
use hopsim_io::AtomicPath;
use layout::{send_layout, APPLICATION_ID};
pub use live::Pace;
use live::{Live, LIVE_FLUSH_INTERVAL};
use rerun::{
    AsComponents, Color, LineStrips2D, Points2D, RecordingStream, RecordingStreamBuilder,
    TextDocument, TextLog,
};
use std::path::{Path, PathBuf};
use std::time::{Duration, Instant};

/// How to get the Rerun viewer that matches the SDK hopsim is built with.
pub const RERUN_VIEWER_INSTALL: &str = "pip install rerun-sdk==0.36.3";
/// Timeline of simulation time, s.
pub const TIME_TIMELINE: &str = "sim_time";
/// Timeline of step indices.
pub const STEP_TIMELINE: &str = "step";

/// Streams a run to Rerun: a `.rrd` file ([`RerunRecorder::save`]) or a live viewer
/// ([`RerunRecorder::spawn`]).
pub struct RerunRecorder {
    /// Declared first so that it is dropped (and its file closed) before `output`.
    stream: RecordingStream,
    output: Option<AtomicPath>,
    drawing: Drawing,
    columns: Columns,
    layout: FrameLayout,
    /// Live stream: pacing and when the columns were last sent.
    live: Option<Live>,
    /// The layout was sent (at the first frame, which sizes the robot view).
    layout_sent: bool,
    /// Where errors point: the `.rrd` path or "Rerun viewer".
    target: PathBuf,
}

impl RerunRecorder {
    /// Records to the `.rrd` file `path`, written under a temporary name and renamed into
    /// place by `finish`.
    pub fn save(path: &Path, info: &RecordingInfo) -> Result<Self, RecordError> {
        let output = AtomicPath::create(path)?;
        let stream = stream_builder(info)
            .save(output.temporary())
            .map_err(|e| RecordError::format(path, e))?;
        Self::start(stream, Some(output), None, path.to_path_buf(), info)
    }

    /// Streams to a live Rerun viewer, started from the `rerun` executable on `PATH` (or
    /// reused if one listens on the default port), at `pace`. The viewer must match the
    /// SDK: [`RERUN_VIEWER_INSTALL`].
    pub fn spawn(info: &RecordingInfo, pace: Pace) -> Result<Self, RecordError> {
        let options = rerun::SpawnOptions::default();
        find_viewer(
            &options.executable_name,
            std::env::var_os("PATH").as_deref(),
        )?;
        let stream = stream_builder(info).spawn_opts(&options).map_err(|e| {
            RecordError::Viewer(format!(
                "could not start the Rerun viewer: {e} (the matching viewer is installed with \
                 `{RERUN_VIEWER_INSTALL}`)"
            ))
        })?;
        let live = Live {
            pace,
            start: None,
            last_flush: Instant::now(),
        };
        Self::start(
            stream,
            None,
            Some(live),
            PathBuf::from("Rerun viewer"),
            info,
        )
    }

    fn start(
        stream: RecordingStream,
        output: Option<AtomicPath>,
        live: Option<Live>,
        target: PathBuf,
        info: &RecordingInfo,
    ) -> Result<Self, RecordError> {
        // Simulation time and step are the recording's timelines; the wall-clock time at
        // which a row was logged means nothing to a reader and would cost a column.
        stream.set_log_time_enabled(false);
        let mut recorder = Self {
            stream,
            output,
            drawing: Drawing::new(info),
            columns: Columns::new(info),
            layout: FrameLayout::of(info),
            live,
            layout_sent: false,
            target,
        };
        recorder.log_static_entities()?;
        Ok(recorder)
    }

    fn error(&self, e: impl std::fmt::Display) -> RecordError {
        RecordError::format(&self.target, e)
    }

    fn log(&self, entity: &str, what: &impl AsComponents) -> Result<(), RecordError> {
        self.stream.log(entity, what).map_err(|e| self.error(e))
    }

    fn log_static(&self, entity: &str, what: &impl AsComponents) -> Result<(), RecordError> {
        self.stream
            .log_static(entity, what)
            .map_err(|e| self.error(e))
    }
}

/// A stream of the hopsim application named after the scene.
fn stream_builder(info: &RecordingInfo) -> RecordingStreamBuilder {
    RecordingStreamBuilder::new(APPLICATION_ID)
        .recording_name(info.scene.clone())
        .enabled(true)
}

impl RerunRecorder {
    fn set_time(&self, t: f64, step: u64) {
        self.stream.set_duration_secs(TIME_TIMELINE, t.max(0.0));
        self.stream
            .set_time_sequence(STEP_TIMELINE, i64::try_from(step).unwrap_or(i64::MAX));
    }

    /// Sends the buffered columns (nothing if none is buffered).
    fn flush(&mut self) -> Result<(), RecordError> {
        let result = self.columns.send(&self.stream, &self.drawing);
        result.map_err(|e| self.error(e))
    }
}

/// Entity of the event log.
const EVENTS_ENTITY: &str = "events";

/// The executable `name` in the folders of `path_var` (the value of `PATH`), or an error
/// saying how to install the viewer that matches the SDK.
fn find_viewer(name: &str, path_var: Option<&std::ffi::OsStr>) -> Result<PathBuf, RecordError> {
    path_var
        .into_iter()
        .flat_map(std::env::split_paths)
        .map(|dir| dir.join(name))
        .find(|candidate| candidate.is_file())
        .ok_or_else(|| {
            RecordError::Viewer(format!(
                "the Rerun viewer `{name}` is not on PATH; install the matching viewer with \
                 `{RERUN_VIEWER_INSTALL}`"
            ))
        })
}

impl Recorder for RerunRecorder {
    fn frame(&mut self, frame: &Frame<'_>) -> Result<(), RecordError> {
        self.layout.check(frame).map_err(|m| self.error(m))?;
        if let Some(live) = &mut self.live {
            live.wait_for(frame.t);
        }
        self.set_time(frame.t, frame.step);
        if !self.layout_sent {
            let extent = self.drawing.robot_extent(frame);
            send_layout(&self.stream, &self.columns.series, extent).map_err(|e| self.error(e))?;
            self.layout_sent = true;
        }
        if self.drawing.terrain.cover(frame.com[0]) {
            self.log_terrain()?;
        }
        self.log_outlines(frame)?;
        self.clear_expired_markers(frame.t)?;
        if self.drawing.extend_trail(frame.com) {
            let trail = LineStrips2D::new([self.drawing.trail.iter().copied()])
                .with_colors([Color::from_rgb(160, 160, 160)]);
            let piece = self.drawing.trail_piece;
            self.log(&format!("{TRAIL_ENTITY}/{piece}"), &trail)?;
        }
        self.columns.push(frame, &self.drawing);
        let due = match &mut self.live {
            Some(live) => {
                let due = live.last_flush.elapsed() >= LIVE_FLUSH_INTERVAL;
                if due {
                    live.last_flush = Instant::now();
                }
                due
            }
            None => self.columns.len() >= CHUNK_FRAMES,
        };
        if due {
            self.flush()?;
        }
        Ok(())
    }

    fn event(&mut self, event: &Event) -> Result<(), RecordError> {
        self.set_time(event.t, event.step);
        let kind = event.kind.name();
        let text = format!(
            "t = {:.4} s, step {}: {kind} {}",
            event.t, event.step, event.kind
        );
        self.log(
            EVENTS_ENTITY,
            &TextLog::new(text).with_level(rerun::TextLogLevel::INFO),
        )?;
        // A marker at the robot's last recorded centre of mass, one entity per kind, shown
        // for EVENT_MARKER_HOLD_S.
        if let Some(at) = self.drawing.last_com {
            let entity = format!("world/events/{kind}");
            self.log(
                &entity,
                &Points2D::new([at])
                    .with_labels([kind])
                    .with_colors([event_color(&event.kind)])
                    .with_radii([2.0 * self.drawing.marker_radius()]),
            )?;
            let until = event.t + EVENT_MARKER_HOLD_S;
            let markers = &mut self.drawing.markers;
            match markers.iter_mut().find(|(e, _)| *e == entity) {
                Some(marker) => marker.1 = until,
                None => markers.push((entity, until)),
            }
        }
        Ok(())
    }

    fn finish(self: Box<Self>) -> Result<(), RecordError> {
        self.close()?.map_or(Ok(()), |output| Ok(output.commit()?))
    }

    fn finish_partial(self: Box<Self>, stop: &Stop) -> Result<Vec<PathBuf>, RecordError> {
        self.set_time(stop.t, stop.step);
        let text = stop.to_string();
        self.log(
            EVENTS_ENTITY,
            &TextLog::new(text.clone()).with_level(rerun::TextLogLevel::ERROR),
        )?;
        self.stream
            .send_property("stop", &TextDocument::new(text))
            .map_err(|e| self.error(e))?;
        match self.close()? {
            Some(output) => Ok(vec![output.commit_partial()?]),
            None => Ok(Vec::new()),
        }
    }
}

impl RerunRecorder {
    /// Sends what is buffered and closes the stream; the file to commit, if any.
    fn close(mut self: Box<Self>) -> Result<Option<AtomicPath>, RecordError> {
        self.flush()?;
        let Self {
            stream,
            output,
            target,
            ..
        } = *self;
        let err = |e: &dyn std::fmt::Display| RecordError::format(&target, e);
        match output {
            Some(output) => {
                stream.flush_blocking().map_err(|e| err(&e))?;
                // Closes the file sink, which writes the RRD footer.
                stream.disconnect();
                drop(stream);
                Ok(Some(output))
            }
            None => {
                stream
                    .flush_with_timeout(Duration::from_secs(30))
                    .map_err(|e| err(&e))?;
                Ok(None)
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::{ActuatorQuantity, EnergySample, EventKind};
    use hopsim_model::Terrain;

    #[test]
    fn a_missing_viewer_says_how_to_install_it() {
        let dir = tempfile::tempdir().unwrap();
        let path = std::env::join_paths([dir.path()]).unwrap();
        let e = find_viewer("rerun", Some(&path)).unwrap_err().to_string();
        assert!(
            e.contains("not on PATH") && e.contains("pip install rerun-sdk==0.36.3"),
            "{e}"
        );
        assert!(find_viewer("rerun", None).is_err());
        std::fs::write(dir.path().join("rerun"), "").unwrap();
        assert_eq!(
            find_viewer("rerun", Some(&path)).unwrap(),
            dir.path().join("rerun")
        );
    }

    /// A recording without bodies, contacts or springs.
    pub(super) fn empty_info() -> RecordingInfo {
        RecordingInfo {
            scene: String::new(),
            scene_path: String::new(),
            scene_text: String::new(),
            coordinates: vec![],
            coordinate_units: vec![],
            bodies: vec![],
            contacts: vec![],
            joints: vec![],
            loops: vec![],
            springs: vec![],
            terrain: Terrain::flat(0.0),
            dt: 1e-3,
            weight_newtons: 0.0,
            actuated: false,
            actuator: ActuatorQuantity::Torque,
            actuators: Vec::new(),
        }
    }

    #[test]
    fn event_markers_are_cleared_after_their_hold_time() {
        let dir = tempfile::tempdir().unwrap();
        let mut rec = RerunRecorder::save(&dir.path().join("run.rrd"), &empty_info()).unwrap();
        let frame = |t: f64| Frame {
            t,
            step: (t * 1e3).round() as u64,
            q: &[],
            u: &[],
            bodies: &[],
            com: [t, 0.1],
            contacts: &[],
            springs: &[],
            shapes_active: &[],
            energy: EnergySample::default(),
            actuator_torque: 0.0,
            controls: &[],
            actuator_efforts: &[],
        };
        rec.frame(&frame(0.0)).unwrap();
        let event = |t: f64, kind: EventKind| Event { t, step: 0, kind };
        rec.event(&event(0.01, EventKind::TakeOff)).unwrap();
        rec.event(&event(0.05, EventKind::Brake { impulse: 0.05 }))
            .unwrap();
        rec.event(&event(0.06, EventKind::TakeOff)).unwrap();
        let on_view = |rec: &RerunRecorder| {
            let mut m: Vec<_> = rec.drawing.markers.iter().map(|(e, _)| e.clone()).collect();
            m.sort();
            m
        };
        assert_eq!(
            on_view(&rec),
            ["world/events/brake", "world/events/take_off"]
        );
        rec.frame(&frame(0.01 + EVENT_MARKER_HOLD_S)).unwrap();
        assert_eq!(
            on_view(&rec),
            ["world/events/brake", "world/events/take_off"],
            "the second take-off renewed its marker"
        );
        rec.frame(&frame(0.05 + EVENT_MARKER_HOLD_S)).unwrap();
        assert_eq!(on_view(&rec), ["world/events/take_off"]);
        rec.frame(&frame(0.06 + EVENT_MARKER_HOLD_S)).unwrap();
        assert!(on_view(&rec).is_empty());
        Box::new(rec).finish().unwrap();
    }
}
