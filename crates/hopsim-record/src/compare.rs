//! Differences between two runs' files (`hopsim compare`): their contact-impulse traces
//! ([`ImpulseTrace::first_difference`]) and optionally their states `q`, `u` at the same
//! steps ([`diff_recorded_states`]).
//!
//! Inputs are hopsim MCAP recordings or impulse-trace CSV files (told apart by content).
//! A recording holds the impulses of the recorded steps only (and each brake, from its
//! event); when a recording is compared with a trace, the trace is cut to the recording's
//! steps and the brake/lock channels are left out, since the two name them differently.

use crate::mcap_read::BRAKE_CHANNEL;
use crate::{ImpulseTrace, TraceDifference, TraceError, TraceTolerance};
use crate::{McapRecording, RecordError, StateSample};
use std::collections::{BTreeMap, BTreeSet};
use std::fmt;
use std::path::Path;

/// Channel prefix of velocity locks (brakes) in impulse traces.
const LOCK_PREFIX: &str = "lock:";

/// What [`diff_run_files`] compares and how strictly (default: [`TraceTolerance::default`],
/// no states).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct RunDiffOptions {
    /// Tolerance on impulses.
    pub tolerance: TraceTolerance,
    /// Also compare the states with this absolute tolerance (needs two recordings).
    pub state_tolerance: Option<f64>,
}

/// How a run differs from a reference run ([`diff_run_files`]).
#[derive(Clone, Debug, PartialEq)]
pub struct RunDiff {
    /// Impulse samples compared ([`ImpulseTrace::compared_samples`]: the distinct
    /// `(step, channel)` pairs of both sides).
    pub impulse_samples: usize,
    /// The first impulse that differs, if any.
    pub impulses: Option<TraceDifference>,
    /// With states compared: the steps compared, or how they differ.
    pub states: Option<Result<usize, StateMismatch>>,
    /// What was left out of the comparison, and why.
    pub notes: Vec<String>,
}

impl RunDiff {
    /// True when everything compared agrees within tolerance.
    pub fn agree(&self) -> bool {
        self.impulses.is_none() && !matches!(self.states, Some(Err(_)))
    }
}

impl fmt::Display for RunDiff {
    /// One line per compared quantity: `identical within tolerance (N samples)` or the
    /// first difference.
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        for note in &self.notes {
            writeln!(f, "note: {note}")?;
        }
        match &self.impulses {
            None => writeln!(
                f,
                "identical within tolerance ({} samples)",
                self.impulse_samples
            )?,
            Some(d) => writeln!(f, "impulses differ: {d}")?,
        }
        match &self.states {
            None => {}
            Some(Ok(steps)) => writeln!(f, "states identical within tolerance ({steps} steps)")?,
            Some(Err(m)) => writeln!(f, "states differ: {m}")?,
        }
        Ok(())
    }
}

/// The first state value that differs.
#[derive(Clone, Debug, PartialEq)]
pub struct StateDifference {
    pub step: u64,
    /// Time, s.
    pub t: f64,
    /// `q.<name>` or `u.<name>`.
    pub variable: String,
    pub expected: f64,
    pub found: f64,
    /// Differing values in all.
    pub count: usize,
    /// Largest absolute difference.
    pub max_abs: f64,
}

/// How the states of two recordings differ.
#[derive(Clone, Debug, PartialEq)]
pub enum StateMismatch {
    /// The recordings have different generalised coordinates.
    Coordinates {
        expected: Vec<String>,
        found: Vec<String>,
    },
    /// A value differs beyond tolerance.
    Value(StateDifference),
    /// All common steps agree, but some steps are recorded on one side only.
    Steps {
        only_in_reference: usize,
        only_in_other: usize,
        /// The first such step.
        first: u64,
    },
}

impl fmt::Display for StateMismatch {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            StateMismatch::Coordinates { expected, found } => write!(
                f,
                "different coordinates: expected [{}], found [{}]",
                expected.join(", "),
                found.join(", ")
            ),
            StateMismatch::Value(d) => write!(
                f,
                "first difference at step {} (t = {:.6} s), {}: expected {:e}, found {:e} \
                 ({} differing values, largest difference {:e})",
                d.step, d.t, d.variable, d.expected, d.found, d.count, d.max_abs
            ),
            StateMismatch::Steps {
                only_in_reference,
                only_in_other,
                first,
            } => write!(
                f,
                "recorded steps differ from step {first}: {only_in_reference} only in the \
                 reference, {only_in_other} only in the other"
            ),
        }
    }
}

/// An input of [`diff_run_files`].
enum RunFile {
    Trace(ImpulseTrace),
    Recording(Box<McapRecording>),
}

impl RunFile {
    /// Reads an MCAP recording (told by its magic bytes) or an impulse-trace CSV file, of
    /// at most [`MAX_RECORDING_BYTES`](crate::MAX_RECORDING_BYTES) (a device or an endless
    /// stream is refused at that size).
    fn read(path: &Path) -> Result<Self, RecordError> {
        let bytes = crate::mcap_read::read_input(path, crate::MAX_RECORDING_BYTES)?;
        let is_mcap_name = path
            .extension()
            .is_some_and(|e| e.eq_ignore_ascii_case("mcap"));
        if bytes.starts_with(mcap::MAGIC) || is_mcap_name {
            return McapRecording::from_bytes(&bytes, path)
                .map(|r| RunFile::Recording(Box::new(r)));
        }
        let text = String::from_utf8(bytes).map_err(|_| {
            RecordError::format(path, "neither a hopsim MCAP recording nor an impulse trace")
        })?;
        ImpulseTrace::from_csv(&text, &path.display().to_string())
            .map(RunFile::Trace)
            .map_err(|e| match e {
                TraceError::Io { path, source } => RecordError::Io { path, source },
                TraceError::Format {
                    path,
                    line,
                    message,
                } => RecordError::Format {
                    path,
                    message: format!(
                        "line {line}: not an impulse trace or MCAP recording: {message}"
                    ),
                },
            })
    }
}

/// How the run in file `other` differs from the reference run in file `reference` (each an
/// MCAP recording or an impulse trace). `Err` when an input cannot be read or `--states` is
/// asked of an impulse trace; the error names the file.
pub fn diff_run_files(
    reference: &Path,
    other: &Path,
    options: &RunDiffOptions,
) -> Result<RunDiff, RecordError> {
    let (a, b) = (RunFile::read(reference)?, RunFile::read(other)?);
    let mut notes = Vec::new();
    let states = match (&a, &b, options.state_tolerance) {
        (RunFile::Recording(x), RunFile::Recording(y), Some(tol)) => {
            Some(diff_recorded_states(x, y, tol))
        }
        (_, _, None) => None,
        (RunFile::Trace(_), _, Some(_)) => return Err(needs_recording(reference)),
        (_, RunFile::Trace(_), Some(_)) => return Err(needs_recording(other)),
    };
    let (ta, tb) = match (a, b) {
        (RunFile::Trace(x), RunFile::Trace(y)) => (x, y),
        (RunFile::Recording(x), RunFile::Recording(y)) => (x.impulses, y.impulses),
        (RunFile::Trace(trace), RunFile::Recording(rec)) => align(trace, &rec, &mut notes),
        (RunFile::Recording(rec), RunFile::Trace(trace)) => {
            let (t, r) = align(trace, &rec, &mut notes);
            (r, t)
        }
    };
    Ok(RunDiff {
        impulse_samples: ta.compared_samples(&tb),
        impulses: ta.first_difference(&tb, options.tolerance),
        states,
        notes,
    })
}

fn needs_recording(path: &Path) -> RecordError {
    RecordError::format(
        path,
        "--states needs two .mcap recordings; this is an impulse trace without states",
    )
}

/// A trace and a recording's trace restricted to what both hold: the recorded steps,
/// without brake/lock channels.
fn align(
    trace: ImpulseTrace,
    recording: &McapRecording,
    notes: &mut Vec<String>,
) -> (ImpulseTrace, ImpulseTrace) {
    let steps: BTreeSet<u64> = recording.recorded_steps().collect();
    let keep = |trace: &ImpulseTrace, skip: &dyn Fn(&str) -> bool| ImpulseTrace {
        samples: trace
            .samples
            .iter()
            .filter(|s| steps.contains(&s.step) && !skip(&s.channel))
            .cloned()
            .collect(),
    };
    notes.push(format!(
        "comparing an impulse trace with a recording: only the {} recorded steps, \
         without brake/lock channels",
        steps.len()
    ));
    (
        keep(&trace, &|c| c.starts_with(LOCK_PREFIX)),
        keep(&recording.impulses, &|c| c == BRAKE_CHANNEL),
    )
}

/// How the recorded states of `other` differ from those of `reference` at the steps both
/// recorded: `Ok(steps compared)` when every `q` and `u` agrees within `abs_tolerance` and
/// both recorded the same steps.
pub fn diff_recorded_states(
    reference: &McapRecording,
    other: &McapRecording,
    abs_tolerance: f64,
) -> Result<usize, StateMismatch> {
    let names = &reference.metadata.coordinates;
    if *names != other.metadata.coordinates {
        return Err(StateMismatch::Coordinates {
            expected: names.clone(),
            found: other.metadata.coordinates.clone(),
        });
    }
    let by_step = |r: &McapRecording| -> BTreeMap<u64, StateSample> {
        r.states.iter().map(|s| (s.step, s.clone())).collect()
    };
    let (a, b) = (by_step(reference), by_step(other));
    let mut first: Option<StateDifference> = None;
    let (mut count, mut max_abs, mut compared) = (0, 0.0_f64, 0);
    for (step, sa) in &a {
        let Some(sb) = b.get(step) else { continue };
        compared += 1;
        let values = [("q", &sa.q, &sb.q), ("u", &sa.u, &sb.u)];
        for (vector, xa, xb) in values {
            for ((name, &x), &y) in names.iter().zip(xa.iter()).zip(xb.iter()) {
                let same = x == y || (x.is_nan() && y.is_nan()) || (x - y).abs() <= abs_tolerance;
                if same {
                    continue;
                }
                count += 1;
                let diff = (x - y).abs();
                max_abs = if diff.is_nan() {
                    f64::NAN
                } else {
                    max_abs.max(diff)
                };
                first.get_or_insert_with(|| StateDifference {
                    step: *step,
                    t: sa.t,
                    variable: format!("{vector}.{name}"),
                    expected: x,
                    found: y,
                    count: 0,
                    max_abs: 0.0,
                });
            }
        }
    }
    if let Some(d) = first {
        return Err(StateMismatch::Value(StateDifference {
            count,
            max_abs,
            ..d
        }));
    }
    let only_a: Vec<u64> = a.keys().filter(|s| !b.contains_key(s)).copied().collect();
    let only_b: Vec<u64> = b.keys().filter(|s| !a.contains_key(s)).copied().collect();
    match only_a.first().into_iter().chain(only_b.first()).min() {
        Some(&first) => Err(StateMismatch::Steps {
            only_in_reference: only_a.len(),
            only_in_other: only_b.len(),
            first,
        }),
        None => Ok(compared),
    }
}
