//! Contact-impulse traces: the per-step percussions of a run, as a regression artefact.
//!
//! A trace holds, for every step, the normal and tangential percussions `Λ_N`, `Λ_T` of each
//! contact that carried one and the impulse of each velocity lock (brake). Traces are
//! written as CSV (`tests/golden/*.csv`, `hopsim compare`), read back exactly (shortest
//! round-trip floats) and compared sample by sample with a tolerance; a sample missing on
//! one side counts as zero there, so a contact that touches with a vanishing percussion in
//! one run and not at all in the other is not a difference.

use hopsim_model::Model;
use hopsim_step::StepRecord;
use std::collections::hash_map::Entry;
use std::collections::{BTreeMap, HashMap};
use std::fmt::Write as _;
use std::path::Path;

/// First line of a trace file.
const HEADER: &str = "# hopsim impulse trace v1";
/// Column names (second line).
const COLUMNS: &str = "step,t_s,channel,normal_Ns,tangent_Ns";
/// Largest trace file [`ImpulseTrace::read`] reads, bytes (1 GiB: about fifteen million
/// rows, some thousand seconds of a run with contacts at every step).
pub const MAX_TRACE_BYTES: u64 = 1 << 30;
/// Environment variable that makes [`ImpulseTrace::check_golden`] rewrite golden files.
pub const BLESS_ENV: &str = "HOPSIM_BLESS";

/// One impulse of one step.
#[derive(Clone, Debug, PartialEq)]
pub struct ImpulseSample {
    /// Step index (1 for the first step).
    pub step: u64,
    /// Time at the end of the step, s.
    pub t: f64,
    /// A contact's name (e.g. `disc/terrain0`) or `lock:<body>-<other>` for a brake.
    pub channel: String,
    /// `Λ_N` of a contact, N s; the angular impulse of a lock on its first body, N m s.
    pub normal: f64,
    /// `Λ_T` of a contact, N s; 0 for a lock.
    pub tangent: f64,
}

/// How far two traces may differ: `|a − b| ≤ abs + rel·max(|a|, |b|)`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct TraceTolerance {
    /// Absolute tolerance, N s.
    pub abs: f64,
    /// Relative tolerance.
    pub rel: f64,
}

impl Default for TraceTolerance {
    /// `abs = 1e-9 N s`, `rel = 1e-6`: far above round-off differences between builds of
    /// the same code, far below any change of the physics.
    fn default() -> Self {
        Self {
            abs: 1e-9,
            rel: 1e-6,
        }
    }
}

/// The first place where two traces disagree.
#[derive(Clone, Debug, PartialEq)]
pub struct TraceDifference {
    /// Step of the first differing sample.
    pub step: u64,
    /// Its time, s.
    pub t: f64,
    /// Its channel.
    pub channel: String,
    /// `"normal"` or `"tangent"`.
    pub component: &'static str,
    /// Value in the reference trace (0 if it has no such sample).
    pub expected: f64,
    /// Value in the other trace (0 if it has no such sample).
    pub found: f64,
    /// Number of differing samples in all (a sample: one channel at one step, both its
    /// components; see [`ImpulseTrace::compared_samples`]).
    pub count: usize,
    /// Number of samples compared ([`ImpulseTrace::compared_samples`]).
    pub samples: usize,
    /// Largest absolute difference over all samples.
    pub max_abs: f64,
}

impl std::fmt::Display for TraceDifference {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(
            f,
            "first difference at step {} (t = {:.6} s), {} {}: expected {:e}, found {:e} \
             ({} of {} samples differ, largest difference {:e})",
            self.step,
            self.t,
            self.channel,
            self.component,
            self.expected,
            self.found,
            self.count,
            self.samples,
            self.max_abs
        )
    }
}

/// A trace file that cannot be read.
#[derive(Debug, thiserror::Error)]
pub enum TraceError {
    #[error("{path}: {source}")]
    Io {
        path: String,
        source: std::io::Error,
    },
    #[error("{path}:{line}: {message}")]
    Format {
        path: String,
        line: usize,
        message: String,
    },
}

/// The impulses of a run, in step order.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct ImpulseTrace {
    pub samples: Vec<ImpulseSample>,
}

impl ImpulseTrace {
    /// Appends the percussions of `record` (contacts that carried one, and every lock).
    pub fn push_record(&mut self, model: &Model, record: &StepRecord) {
        for c in &record.contacts {
            if c.impulse_normal != 0.0 || c.impulse_tangent != 0.0 {
                self.samples.push(ImpulseSample {
                    step: record.step,
                    t: record.t,
                    channel: model.contacts()[c.contact].name.clone(),
                    normal: c.impulse_normal,
                    tangent: c.impulse_tangent,
                });
            }
        }
        for lock in &record.locks {
            self.samples.push(ImpulseSample {
                step: record.step,
                t: record.t,
                channel: format!(
                    "lock:{}-{}",
                    model.bodies()[lock.body].name,
                    model.bodies()[lock.other].name
                ),
                normal: lock.impulse,
                tangent: 0.0,
            });
        }
    }

    /// The trace as CSV (header line, column line, one row per sample).
    pub fn to_csv(&self) -> String {
        let mut s = format!("{HEADER}\n{COLUMNS}\n");
        for x in &self.samples {
            let _ = writeln!(
                s,
                "{},{:?},{},{:?},{:?}",
                x.step, x.t, x.channel, x.normal, x.tangent
            );
        }
        s
    }

    /// Parses [`ImpulseTrace::to_csv`] output; `origin` names the source in errors.
    pub fn from_csv(text: &str, origin: &str) -> Result<Self, TraceError> {
        let err = |line: usize, message: String| TraceError::Format {
            path: origin.to_string(),
            line,
            message,
        };
        let mut lines = text.lines().enumerate();
        match lines.next() {
            Some((_, HEADER)) => {}
            other => {
                let found = other.map_or("an empty file", |(_, l)| l);
                return Err(err(1, format!("expected '{HEADER}', found '{found}'")));
            }
        }
        match lines.next() {
            Some((_, COLUMNS)) => {}
            other => {
                let found = other.map_or("end of file", |(_, l)| l);
                return Err(err(2, format!("expected '{COLUMNS}', found '{found}'")));
            }
        }
        let mut samples = Vec::new();
        // The line of each (step, channel) seen: a second row would silently win.
        let mut first_line: HashMap<(u64, String), usize> = HashMap::new();
        for (i, line) in lines {
            if line.trim().is_empty() {
                continue;
            }
            let fields: Vec<&str> = line.split(',').collect();
            let [step, t, channel, normal, tangent] = fields[..] else {
                let n = fields.len();
                return Err(err(
                    i + 1,
                    format!("expected 5 fields ({COLUMNS}), found {n}"),
                ));
            };
            let number = |name: &str, v: &str| {
                v.parse::<f64>()
                    .ok()
                    .filter(|x| x.is_finite())
                    .ok_or_else(|| err(i + 1, format!("{name} '{v}' is not a finite number")))
            };
            let sample = ImpulseSample {
                step: step
                    .parse()
                    .map_err(|_| err(i + 1, format!("step '{step}' is not an integer")))?,
                t: number("t_s", t)?,
                channel: channel.to_string(),
                normal: number("normal_Ns", normal)?,
                tangent: number("tangent_Ns", tangent)?,
            };
            match first_line.entry((sample.step, sample.channel.clone())) {
                Entry::Occupied(first) => {
                    return Err(err(
                        i + 1,
                        format!(
                            "duplicate row for step {}, channel {} (first at line {})",
                            sample.step,
                            sample.channel,
                            first.get()
                        ),
                    ))
                }
                Entry::Vacant(slot) => {
                    slot.insert(i + 1);
                }
            }
            samples.push(sample);
        }
        Ok(Self { samples })
    }

    /// Reads a trace file of at most [`MAX_TRACE_BYTES`]; a NUL byte ends the read as not
    /// text (so `/dev/zero`, `/dev/urandom` or an endless pipe is an error, not an exhausted
    /// memory).
    pub fn read(path: &Path) -> Result<Self, TraceError> {
        let text = read_text(path, MAX_TRACE_BYTES).map_err(|source| TraceError::Io {
            path: path.display().to_string(),
            source,
        })?;
        Self::from_csv(&text, &path.display().to_string())
    }

    /// Writes the trace atomically (hidden temporary sibling, synced, then renamed).
    pub fn write(&self, path: &Path) -> Result<(), TraceError> {
        hopsim_io::write_atomically(path, |w| w.write_all(self.to_csv().as_bytes())).map_err(|e| {
            TraceError::Io {
                path: path.display().to_string(),
                source: e.source,
            }
        })
    }

    /// The number of samples a comparison of `self` with `other` looks at. A sample is one
    /// channel (contact, joint stop or lock) at one step, with its normal and tangential
    /// percussion: the distinct `(step, channel)` pairs of both traces (a pair on one side
    /// only counts once, as zero on the other). Both "N samples" of `hopsim compare` and the
    /// differing count of [`TraceDifference`] count these.
    pub fn compared_samples(&self, other: &Self) -> usize {
        sample_keys(self, other).len()
    }

    /// The first sample of `other` that differs from `self` (the reference) beyond `tol`,
    /// with the number of differing samples; `None` when every sample agrees (a sample
    /// missing on one side counts as zero there).
    pub fn first_difference(&self, other: &Self, tol: TraceTolerance) -> Option<TraceDifference> {
        let (a, b) = (index(self), index(other));
        let mut first: Option<TraceDifference> = None;
        let (mut count, mut max_abs) = (0, 0.0_f64);
        for key in sample_keys(self, other) {
            let (sa, sb) = (a.get(&key), b.get(&key));
            let t = sa.or(sb).map_or(0.0, |s| s.t);
            let pick =
                |s: Option<&&ImpulseSample>, f: fn(&ImpulseSample) -> f64| s.map_or(0.0, |s| f(s));
            let mut differs = false;
            for (component, f) in [
                (
                    "normal",
                    (|s: &ImpulseSample| s.normal) as fn(&ImpulseSample) -> f64,
                ),
                ("tangent", |s: &ImpulseSample| s.tangent),
            ] {
                let (x, y) = (pick(sa, f), pick(sb, f));
                let diff = (x - y).abs();
                if diff <= tol.abs + tol.rel * x.abs().max(y.abs()) {
                    continue;
                }
                differs = true;
                max_abs = max_abs.max(diff);
                first.get_or_insert_with(|| TraceDifference {
                    step: key.0,
                    t,
                    channel: key.1.to_string(),
                    component,
                    expected: x,
                    found: y,
                    count: 0,
                    samples: 0,
                    max_abs: 0.0,
                });
            }
            count += usize::from(differs);
        }
        first.map(|d| TraceDifference {
            count,
            samples: self.compared_samples(other),
            max_abs,
            ..d
        })
    }

    /// Compares the trace with the golden file at `path`, or (re)writes that file when the
    /// environment variable `HOPSIM_BLESS` is set to anything but `0`. The error says what
    /// differs and how to regenerate the file deliberately.
    pub fn check_golden(&self, path: &Path, tol: TraceTolerance) -> Result<(), String> {
        let bless = std::env::var(BLESS_ENV).is_ok_and(|v| !v.is_empty() && v != "0");
        if bless {
            return self.write(path).map_err(|e| e.to_string());
        }
        let how =
            format!("if the change is intended, regenerate with {BLESS_ENV}=1 and review the diff");
        if !path.exists() {
            return Err(format!("{}: golden trace missing; {how}", path.display()));
        }
        let golden = Self::read(path).map_err(|e| e.to_string())?;
        match golden.first_difference(self, tol) {
            None => Ok(()),
            Some(d) => Err(format!("{}: {d}; {how}", path.display())),
        }
    }
}

/// The text of the file at `path`: at most `limit` bytes of UTF-8 without NUL bytes. A
/// regular file above the limit is refused unread; any other input is read in blocks and
/// refused at its first NUL byte or at the limit.
fn read_text(path: &Path, limit: u64) -> std::io::Result<String> {
    hopsim_io::read_text_bounded(path, limit, "impulse traces")
}

/// A trace's sample identity: step and channel.
type SampleKey<'a> = (u64, &'a str);

/// The samples of `trace` by step and channel.
fn index(trace: &ImpulseTrace) -> BTreeMap<SampleKey<'_>, &ImpulseSample> {
    trace
        .samples
        .iter()
        .map(|s| ((s.step, s.channel.as_str()), s))
        .collect()
}

/// The distinct `(step, channel)` pairs of two traces, sorted.
fn sample_keys<'a>(a: &'a ImpulseTrace, b: &'a ImpulseTrace) -> Vec<SampleKey<'a>> {
    let mut keys: Vec<SampleKey<'a>> = a
        .samples
        .iter()
        .chain(&b.samples)
        .map(|s| (s.step, s.channel.as_str()))
        .collect();
    keys.sort_unstable();
    keys.dedup();
    keys
}

#[cfg(test)]
mod tests {
    use super::*;

    fn sample(step: u64, channel: &str, normal: f64, tangent: f64) -> ImpulseSample {
        ImpulseSample {
            step,
            t: step as f64 * 1e-3,
            channel: channel.into(),
            normal,
            tangent,
        }
    }

    fn trace(samples: Vec<ImpulseSample>) -> ImpulseTrace {
        ImpulseTrace { samples }
    }

    #[test]
    fn csv_round_trips_exactly() {
        let a = trace(vec![
            sample(1, "disc/terrain0", 0.1 + 0.2, -1.0 / 3.0),
            sample(7, "lock:disc-flywheel", 5.9e-2, 0.0),
        ]);
        let b = ImpulseTrace::from_csv(&a.to_csv(), "mem").unwrap();
        assert_eq!(a, b);
    }

    #[test]
    fn identical_traces_agree_and_a_changed_sample_is_named() {
        let a = trace(vec![
            sample(1, "c", 1.0, 0.5),
            sample(2, "c", 1.0, 0.5),
            sample(3, "c", 1.0, 0.5),
        ]);
        let tol = TraceTolerance::default();
        assert_eq!(a.first_difference(&a.clone(), tol), None);
        let mut b = a.clone();
        b.samples[1].tangent = 0.5 + 1e-3;
        b.samples[2].normal = 2.0;
        let d = a.first_difference(&b, tol).unwrap();
        assert_eq!(
            (d.step, d.channel.as_str(), d.component),
            (2, "c", "tangent")
        );
        assert_eq!(d.count, 2);
        assert!((d.max_abs - 1.0).abs() < 1e-15);
        // Both components of one sample: one differing sample.
        b.samples[2].tangent = 0.7;
        assert_eq!(a.first_difference(&b, tol).unwrap().count, 2);
    }

    #[test]
    fn samples_are_counted_by_step_and_channel_over_both_traces() {
        let a = trace(vec![sample(1, "c", 1.0, 0.5), sample(1, "d", 1.0, 0.5)]);
        let b = trace(vec![sample(1, "c", 3.0, 0.1), sample(2, "c", 1.0, 0.5)]);
        assert_eq!(a.compared_samples(&b), 3);
        assert_eq!(a.compared_samples(&a), 2);
        let d = a.first_difference(&b, TraceTolerance::default()).unwrap();
        assert_eq!(
            (d.step, d.channel.as_str(), d.component),
            (1, "c", "normal")
        );
        assert_eq!(d.count, 3);
        // The differing samples are counted like the compared ones.
        assert_eq!(d.samples, a.compared_samples(&b));
        assert!(d.to_string().contains("(3 of 3 samples differ"), "{d}");
    }

    #[test]
    fn a_missing_sample_counts_as_zero() {
        let a = trace(vec![sample(1, "c", 1.0, 0.0), sample(2, "d", 1e-12, 0.0)]);
        let b = trace(vec![sample(1, "c", 1.0, 0.0)]);
        assert_eq!(a.first_difference(&b, TraceTolerance::default()), None);
        let c = trace(vec![sample(1, "c", 1.0, 0.0), sample(2, "d", 0.1, 0.0)]);
        let d = b.first_difference(&c, TraceTolerance::default()).unwrap();
        assert_eq!((d.step, d.expected, d.found), (2, 0.0, 0.1));
    }

    #[test]
    fn malformed_files_name_the_line() {
        let e = ImpulseTrace::from_csv("nope", "f.csv")
            .unwrap_err()
            .to_string();
        assert!(e.starts_with("f.csv:1:"), "{e}");
        let text = format!("{HEADER}\n{COLUMNS}\n1,0.1,c,abc,0\n");
        let e = ImpulseTrace::from_csv(&text, "f.csv")
            .unwrap_err()
            .to_string();
        assert!(
            e.contains("f.csv:3:") && e.contains("normal_Ns 'abc'"),
            "{e}"
        );
    }
}
