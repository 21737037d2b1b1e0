//! Comparing runs: recordings with recordings (impulses, states), traces with recordings,
//! and the errors that name the unreadable input.

mod common;

use common::{events, feed, frames, info, OwnedFrame};
use hopsim_record::{
    diff_run_files, ImpulseSample, ImpulseTrace, McapRecorder, McapRecording, Recorder,
    RunDiffOptions, StateMismatch, BRAKE_CHANNEL,
};
use std::path::{Path, PathBuf};

fn record(path: &Path, frames: &[OwnedFrame]) {
    let mut recorder = Box::new(McapRecorder::create(path, &info()).unwrap());
    feed(recorder.as_mut(), frames, &events());
    recorder.finish().unwrap();
}

fn with_states() -> RunDiffOptions {
    RunDiffOptions {
        state_tolerance: Some(1e-9),
        ..RunDiffOptions::default()
    }
}

struct Runs {
    _dir: tempfile::TempDir,
    reference: PathBuf,
    dir: PathBuf,
}

impl Runs {
    /// Records `frames` as the run compared with the reference (`b.mcap`).
    fn other(&self, frames: &[OwnedFrame]) -> PathBuf {
        let path = self.dir.join("b.mcap");
        record(&path, frames);
        path
    }
}

fn runs() -> Runs {
    let dir = tempfile::tempdir().unwrap();
    let reference = dir.path().join("a.mcap");
    record(&reference, &frames(12));
    Runs {
        reference,
        dir: dir.path().to_path_buf(),
        _dir: dir,
    }
}

#[test]
fn identical_recordings_agree() {
    let r = runs();
    let copy = r.other(&frames(12));
    let c = diff_run_files(&r.reference, &copy, &with_states()).unwrap();
    assert!(c.agree(), "{c}");
    let rec = McapRecording::read(&r.reference).unwrap();
    assert_eq!(c.impulse_samples, rec.impulses.samples.len());
    assert_eq!(c.states, Some(Ok(12)));
    assert_eq!(
        c.to_string(),
        format!(
            "identical within tolerance ({} samples)\nstates identical within tolerance (12 steps)\n",
            c.impulse_samples
        )
    );
}

#[test]
fn a_changed_impulse_is_named_with_step_time_and_contact() {
    let r = runs();
    let mut changed = frames(12);
    changed[4].contacts[0].impulse_tangent *= 1.01;
    changed[7].contacts[0].impulse_normal = 0.5;
    let other = r.other(&changed);
    let c = diff_run_files(&r.reference, &other, &RunDiffOptions::default()).unwrap();
    assert!(!c.agree());
    let d = c.impulses.as_ref().unwrap();
    assert_eq!(
        (d.step, d.t, d.channel.as_str(), d.component),
        (changed[4].step, changed[4].t, "disc/ground", "tangent")
    );
    assert_eq!(d.count, 2);
    let text = c.to_string();
    assert!(
        text.contains("impulses differ: first difference at step 41"),
        "{text}"
    );
}

#[test]
fn a_changed_state_is_named() {
    let r = runs();
    let mut changed = frames(12);
    changed[3].u[2] += 1e-6;
    let other = r.other(&changed);
    let c = diff_run_files(&r.reference, &other, &with_states()).unwrap();
    assert!(c.impulses.is_none() && !c.agree());
    let Some(Err(StateMismatch::Value(d))) = &c.states else {
        panic!("expected a state difference: {c}")
    };
    assert_eq!((d.step, d.variable.as_str(), d.count), (31, "u.phi", 1));
    // Without --states the same runs agree.
    assert!(
        diff_run_files(&r.reference, &other, &RunDiffOptions::default())
            .unwrap()
            .agree()
    );
}

#[test]
fn a_shorter_recording_differs_in_its_steps() {
    let r = runs();
    let other = r.other(&frames(10));
    let c = diff_run_files(&r.reference, &other, &with_states()).unwrap();
    assert_eq!(
        c.states,
        Some(Err(StateMismatch::Steps {
            only_in_reference: 2,
            only_in_other: 0,
            first: 101
        }))
    );
}

#[test]
fn a_trace_is_compared_at_the_recorded_steps_without_locks() {
    let r = runs();
    let rec = McapRecording::read(&r.reference).unwrap();
    // A full per-step trace: the recorded samples, plus steps the recording skipped, plus
    // a lock named as the stepper names it.
    let mut trace = ImpulseTrace::default();
    for s in rec
        .impulses
        .samples
        .iter()
        .filter(|s| s.channel != BRAKE_CHANNEL)
    {
        trace.samples.push(s.clone());
        trace.samples.push(ImpulseSample {
            step: s.step + 1,
            ..s.clone()
        });
    }
    trace.samples.push(ImpulseSample {
        step: 31,
        t: 0.0062,
        channel: "lock:disc-flywheel".into(),
        normal: -0.059,
        tangent: 0.0,
    });
    let path = r.dir.join("trace.csv");
    std::fs::write(&path, trace.to_csv()).unwrap();
    for (a, b) in [(&path, &r.reference), (&r.reference, &path)] {
        let c = diff_run_files(a, b, &RunDiffOptions::default()).unwrap();
        assert!(c.agree(), "{c}");
        assert!(c.notes[0].contains("only the 12 recorded steps"), "{c}");
    }
    // States need recordings on both sides.
    let e = diff_run_files(&path, &r.reference, &with_states()).unwrap_err();
    assert!(e.to_string().contains("trace.csv") && e.to_string().contains("--states"));
}

#[test]
fn unreadable_inputs_are_named() {
    let r = runs();
    let garbage = r.dir.join("garbage.bin");
    std::fs::write(&garbage, [0xff, 0x00, 0x13]).unwrap();
    let text = r.dir.join("notes.csv");
    std::fs::write(&text, "hello\n").unwrap();
    let fake = r.dir.join("fake.mcap");
    std::fs::write(&fake, "hello\n").unwrap();
    for (path, message) in [
        (
            &garbage,
            "neither a hopsim MCAP recording nor an impulse trace",
        ),
        (&text, "line 1: not an impulse trace or MCAP recording"),
        (&fake, "not an MCAP file"),
        (&r.dir.join("missing.csv"), "No such file"),
    ] {
        let e = diff_run_files(&r.reference, path, &RunDiffOptions::default())
            .unwrap_err()
            .to_string();
        assert!(e.starts_with(&path.display().to_string()), "{e}");
        assert!(e.contains(message), "{e}");
    }
}
