//! The impulse-trace reader: a repeated (step, channel) row is a located error instead of
//! silently replacing the first, endless inputs stop at the size limit, and (fuzzing)
//! random or mutated traces give a trace or an error, never a panic. 256 cases per
//! property by default; `PROPTEST_CASES=100000` runs a longer campaign.

use hopsim_record::{ImpulseSample, ImpulseTrace, TraceError, MAX_TRACE_BYTES};
use proptest::prelude::*;
use std::path::Path;

const HEAD: &str = "# hopsim impulse trace v1\nstep,t_s,channel,normal_Ns,tangent_Ns\n";

#[test]
fn a_repeated_step_and_channel_is_a_located_error() {
    let text = format!(
        "{HEAD}1,0.001,disc/terrain0,0.5,0\n1,0.001,lock:disc-flywheel,0.1,0\n\
         2,0.002,disc/terrain0,0.4,0\n1,0.001,disc/terrain0,0.7,0\n"
    );
    let e = ImpulseTrace::from_csv(&text, "run.csv").unwrap_err();
    assert!(matches!(e, TraceError::Format { line: 6, .. }), "{e:?}");
    assert_eq!(
        e.to_string(),
        "run.csv:6: duplicate row for step 1, channel disc/terrain0 (first at line 3)"
    );
}

#[test]
fn the_same_channel_at_other_steps_and_other_channels_at_one_step_are_fine() {
    let text =
        format!("{HEAD}1,0.001,a,0.5,0\n1,0.001,b,0.1,0\n2,0.002,a,0.4,0\n\n2,0.002,b,0.3,0\n");
    let trace = ImpulseTrace::from_csv(&text, "run.csv").unwrap();
    assert_eq!(trace.samples.len(), 4);
}

#[test]
fn endless_inputs_are_refused_at_once() {
    for dev in ["/dev/zero", "/dev/urandom"] {
        if !Path::new(dev).exists() {
            continue;
        }
        let e = ImpulseTrace::read(Path::new(dev)).unwrap_err();
        let msg = e.to_string();
        assert!(matches!(e, TraceError::Io { .. }), "{msg}");
        assert!(
            msg.starts_with(&format!("{dev}: not a text file (NUL byte at offset ")),
            "{msg}"
        );
    }
}

#[test]
fn a_file_above_the_size_limit_is_refused_unread() {
    // A sparse file: its size is above the limit, its blocks cost nothing.
    let path = Path::new(env!("CARGO_TARGET_TMPDIR")).join("hopsim_step_huge_trace.csv");
    let file = std::fs::File::create(&path).unwrap();
    file.set_len(MAX_TRACE_BYTES + 1).unwrap();
    drop(file);
    let msg = ImpulseTrace::read(&path).unwrap_err().to_string();
    std::fs::remove_file(&path).unwrap();
    assert!(
        msg.ends_with(
            "hopsim_step_huge_trace.csv: the file is larger than the 1024 MiB limit of \
                       impulse traces"
        ),
        "{msg}"
    );
}

fn config() -> ProptestConfig {
    let cases = std::env::var("PROPTEST_CASES")
        .ok()
        .and_then(|v| v.parse().ok())
        .unwrap_or(256);
    ProptestConfig {
        cases,
        ..ProptestConfig::default()
    }
}

fn field() -> impl Strategy<Value = String> {
    prop_oneof![
        any::<u64>().prop_map(|v| v.to_string()),
        (0u64..4).prop_map(|v| v.to_string()),
        any::<f64>().prop_map(|v| format!("{v:?}")),
        prop_oneof![Just("a"), Just("b"), Just("disc/terrain0"), Just("")].prop_map(String::from),
        Just("nan".to_string()),
        Just("-inf".to_string()),
        "\\PC{0,6}",
    ]
}

fn row() -> impl Strategy<Value = String> {
    prop::collection::vec(field(), 0..7).prop_map(|f| f.join(","))
}

fn sample() -> impl Strategy<Value = ImpulseSample> {
    (
        0u64..5,
        -1e3..1e3f64,
        "[a-z/:0-9-]{1,8}",
        -1e3..1e3f64,
        -1e3..1e3f64,
    )
        .prop_map(|(step, t, channel, normal, tangent)| ImpulseSample {
            step,
            t,
            channel,
            normal,
            tangent,
        })
}

proptest! {
    #![proptest_config(config())]

    #[test]
    fn random_rows_read_or_fail_cleanly(
        rows in prop::collection::vec(row(), 0..20),
        header in any::<bool>(),
    ) {
        let body = rows.join("\n");
        let text = if header { format!("{HEAD}{body}") } else { body };
        match ImpulseTrace::from_csv(&text, "fuzz.csv") {
            Ok(t) => prop_assert!(t
                .samples
                .iter()
                .all(|s| s.t.is_finite() && s.normal.is_finite() && s.tangent.is_finite())),
            Err(e) => prop_assert!(e.to_string().starts_with("fuzz.csv:")),
        }
    }

    #[test]
    fn mutated_traces_read_or_fail_cleanly(
        samples in prop::collection::vec(sample(), 0..12),
        cuts in prop::collection::vec((any::<prop::sample::Index>(), 0usize..8, "\\PC{0,4}"), 1..5),
    ) {
        let mut text = ImpulseTrace { samples }.to_csv();
        for (at, len, insert) in &cuts {
            let bounds: Vec<usize> = text
                .char_indices()
                .map(|(i, _)| i)
                .chain([text.len()])
                .collect();
            let start = bounds[at.index(bounds.len())];
            let end = bounds
                .iter()
                .copied()
                .find(|&b| b >= start + len)
                .unwrap_or(text.len());
            text.replace_range(start..end, insert);
        }
        let _ = ImpulseTrace::from_csv(&text, "fuzz.csv");
    }

    #[test]
    fn traces_without_duplicates_round_trip(samples in prop::collection::vec(sample(), 0..12)) {
        let mut seen = std::collections::HashSet::new();
        let samples: Vec<ImpulseSample> = samples
            .into_iter()
            .filter(|s| seen.insert((s.step, s.channel.clone())))
            .collect();
        let trace = ImpulseTrace { samples };
        prop_assert_eq!(ImpulseTrace::from_csv(&trace.to_csv(), "rt.csv").unwrap(), trace);
    }
}
