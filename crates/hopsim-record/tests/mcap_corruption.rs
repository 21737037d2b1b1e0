//! A damaged MCAP recording is an error, never a recording that compares "identical": every
//! single-bit flip, every truncation, a doubled file, trailing bytes and a bad footer are
//! "corrupt MCAP file" errors; endless inputs are refused at once. The fuzzing property at
//! the end (random flips, cuts and splices) asserts the reader never panics; 256 cases by
//! default, `PROPTEST_CASES` sets another budget and `HOPSIM_FUZZ_SEED` another seed.

mod common;

use common::{events, feed, frames, info};
use hopsim_record::{
    diff_run_files, McapRecorder, McapRecording, RecordError, Recorder, RunDiffOptions,
    METADATA_NAME,
};
use proptest::prelude::any;
use proptest::test_runner::{Config, RngAlgorithm, TestRng, TestRunner};
use std::collections::BTreeMap;
use std::panic::{catch_unwind, AssertUnwindSafe};
use std::path::Path;

/// A small valid recording (a few frames, every event kind, the scene attachment).
fn recording() -> Vec<u8> {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("run.mcap");
    let mut recorder = Box::new(McapRecorder::create(&path, &info()).unwrap());
    feed(recorder.as_mut(), &frames(6), &events());
    recorder.finish().unwrap();
    let bytes = std::fs::read(&path).unwrap();
    McapRecording::from_bytes(&bytes, &path).expect("the valid recording reads");
    bytes
}

/// The format error of reading `bytes`; panics if they read as a recording.
fn error(bytes: &[u8], what: &str) -> String {
    match McapRecording::from_bytes(bytes, Path::new("bad.mcap")) {
        Err(e @ RecordError::Format { .. }) => e.to_string(),
        Err(e) => panic!("{what}: expected a format error, got {e}"),
        Ok(_) => panic!("{what}: a damaged recording was read as valid"),
    }
}

fn assert_corrupt(bytes: &[u8], what: &str) -> String {
    let e = error(bytes, what);
    assert!(
        e.starts_with("bad.mcap: corrupt MCAP file: ")
            || e.starts_with("bad.mcap: not an MCAP file"),
        "{what}: {e}"
    );
    e
}

#[test]
fn every_single_bit_flip_is_an_error() {
    let good = recording();
    // One flip in every byte (the bit cycles with the offset), so every record, every
    // length, every CRC and both magics are hit.
    for i in 0..good.len() {
        let mut bad = good.clone();
        bad[i] ^= 1 << (i % 8);
        assert_corrupt(
            &bad,
            &format!("bit {} of byte {i} of {}", i % 8, good.len()),
        );
    }
}

#[test]
fn every_truncation_is_an_error() {
    let good = recording();
    for len in 0..good.len() {
        let e = error(
            &good[..len],
            &format!("first {len} of {} bytes", good.len()),
        );
        assert!(e.starts_with("bad.mcap: "), "{e}");
    }
}

#[test]
fn a_doubled_file_and_trailing_bytes_are_errors() {
    let good = recording();
    let twice = [good.as_slice(), good.as_slice()].concat();
    let e = assert_corrupt(&twice, "file concatenated twice");
    assert_eq!(
        e,
        "bad.mcap: corrupt MCAP file: file has more bytes after end magic"
    );
    for tail in [&b"\0"[..], b"\n", b"garbage"] {
        let bad = [good.as_slice(), tail].concat();
        assert_corrupt(&bad, "trailing bytes");
    }
}

#[test]
fn a_corrupted_footer_is_an_error() {
    let good = recording();
    // Footer: opcode, length, summary start (8), summary offset start (8), CRC (4), magic.
    let footer = good.len() - 8 - 20;
    for (offset, what) in [
        (0, "summary start"),
        (8, "summary offset start"),
        (16, "summary CRC"),
    ] {
        let mut bad = good.clone();
        bad[footer + offset] ^= 0x10;
        let e = assert_corrupt(&bad, what);
        assert!(
            e.contains("CRC") || e.contains("end of file"),
            "{what}: {e}"
        );
    }
}

#[test]
fn an_attachment_record_shorter_than_its_header_is_an_error_not_a_panic() {
    // Found by the fuzzing below (a length field overwritten): mcap 0.26's `parse_record`
    // slices out of bounds on such a record. Header: two times, two empty strings, a data
    // length (32 bytes); the 4-byte CRC is missing but one byte.
    let mut bytes = mcap::MAGIC.to_vec();
    bytes.push(0x09);
    bytes.extend_from_slice(&33u64.to_le_bytes());
    bytes.extend_from_slice(&[0; 33]);
    let e = assert_corrupt(&bytes, "short attachment");
    assert_eq!(
        e,
        "bad.mcap: corrupt MCAP file: attachment record of 33 bytes is shorter than its header"
    );
}

#[test]
fn compare_reports_a_damaged_recording_as_unreadable() {
    let dir = tempfile::tempdir().unwrap();
    let good = recording();
    let (a, b) = (dir.path().join("a.mcap"), dir.path().join("b.mcap"));
    std::fs::write(&a, &good).unwrap();
    let mut bad = good.clone();
    let middle = good.len() / 2;
    bad[middle] ^= 0x04;
    std::fs::write(&b, &bad).unwrap();
    let e = diff_run_files(&a, &b, &RunDiffOptions::default()).unwrap_err();
    assert!(matches!(e, RecordError::Format { .. }), "{e}");
    assert!(e.to_string().contains("corrupt MCAP file"), "{e}");
}

#[test]
fn endless_inputs_are_refused_at_once() {
    for dev in ["/dev/zero", "/dev/urandom"] {
        if !Path::new(dev).exists() {
            continue;
        }
        let e = McapRecording::read(Path::new(dev)).unwrap_err().to_string();
        assert!(
            e.starts_with(&format!(
                "{dev}: neither an MCAP file (no MCAP magic at the start) nor text"
            )),
            "{e}"
        );
    }
}

#[test]
fn a_file_above_the_size_limit_is_refused_unread() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("huge.mcap");
    let file = std::fs::File::create(&path).unwrap();
    file.set_len((2 << 30) + 1).unwrap(); // sparse: costs no disk
    drop(file);
    let e = McapRecording::read(&path).unwrap_err().to_string();
    assert!(
        e.ends_with("huge.mcap: the file is larger than the 2048 MiB limit of recordings"),
        "{e}"
    );
}

// ---- fuzzing -------------------------------------------------------------------------

/// SplitMix64 (hopsim-record has no proptest dev-dependency).
struct Rng(u64);

impl Rng {
    fn next(&mut self) -> u64 {
        self.0 = self.0.wrapping_add(0x9e37_79b9_7f4a_7c15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
        z ^ (z >> 31)
    }
    fn below(&mut self, n: usize) -> usize {
        (self.next() % n.max(1) as u64) as usize
    }
}

fn env_or<T: std::str::FromStr>(name: &str, default: T) -> T {
    std::env::var(name)
        .ok()
        .and_then(|v| v.parse().ok())
        .unwrap_or(default)
}

/// Runs `case` on the seeds proptest draws (`PROPTEST_CASES` of them, 256 by default)
/// from a runner seeded with `HOPSIM_FUZZ_SEED`, so that every run of the suite tries the
/// same cases; each seed drives its own generator. A panicking case fails the test with
/// its seed.
fn for_each_seed(case: impl Fn(u64)) {
    let seed: u64 = env_or("HOPSIM_FUZZ_SEED", 7);
    let mut key = [0u8; 32];
    key[..8].copy_from_slice(&seed.to_le_bytes());
    let rng = TestRng::from_seed(RngAlgorithm::ChaCha, &key);
    let mut runner = TestRunner::new_with_rng(Config::default(), rng);
    if let Err(e) = runner.run(&any::<u64>(), |s| {
        case(s);
        Ok(())
    }) {
        panic!("HOPSIM_FUZZ_SEED={seed}: {e}");
    }
}

#[test]
fn damaged_recordings_never_panic_the_reader() {
    let good = recording();
    for_each_seed(|k| {
        let mut rng = Rng(k);
        let mut bytes = good.clone();
        let mut edits = Vec::new();
        for _ in 0..1 + rng.below(4) {
            let at = rng.below(bytes.len() + 1);
            match rng.below(5) {
                0 | 1 => {
                    if at < bytes.len() {
                        bytes[at] ^= 1 << rng.below(8);
                        edits.push(format!("flip at {at}"));
                    }
                }
                2 => {
                    bytes.truncate(at);
                    edits.push(format!("cut at {at}"));
                }
                3 => {
                    // Splice a run of the file elsewhere (records out of place).
                    let from = rng.below(good.len());
                    let len = rng.below(64).min(good.len() - from);
                    let at = at.min(bytes.len());
                    bytes.splice(at..at, good[from..from + len].iter().copied());
                    edits.push(format!("splice {from}+{len} at {at}"));
                }
                _ => {
                    let at = at.min(bytes.len());
                    let value = rng.next().to_le_bytes();
                    let end = (at + 8).min(bytes.len());
                    bytes[at..end].copy_from_slice(&value[..end - at]);
                    edits.push(format!("overwrite 8 bytes at {at}"));
                }
            }
        }
        let result = catch_unwind(AssertUnwindSafe(|| {
            McapRecording::from_bytes(&bytes, Path::new("fuzz.mcap"))
        }));
        match result {
            Err(_) => panic!("case seed {k} panicked after {edits:?}"),
            Ok(Ok(_)) if bytes != good => {
                panic!("case seed {k}: damaged file read as valid after {edits:?}")
            }
            Ok(_) => {}
        }
    });
}

/// JSON fragments that break a message or a metadata value in interesting ways.
const FRAGMENTS: &[&str] = &[
    "",
    "{",
    "}",
    "[",
    "]",
    ",",
    ":",
    "\"",
    "null",
    "true",
    "-1",
    "1e999",
    "-0",
    "NaN",
    "18446744073709551616",
    "\"x\"",
    "{}",
    "[]",
    "\"q\": {}",
    "\"step\": -1",
    "é",
    "\\u0000",
];

/// `text` with a few random edits at byte positions that are char boundaries.
fn mutate_text(rng: &mut Rng, text: &str) -> String {
    let mut out = text.to_string();
    for _ in 0..1 + rng.below(3) {
        let bounds: Vec<usize> = out
            .char_indices()
            .map(|(i, _)| i)
            .chain([out.len()])
            .collect();
        let at = bounds[rng.below(bounds.len())];
        if rng.below(2) == 0 {
            out.insert_str(at, FRAGMENTS[rng.below(FRAGMENTS.len())]);
        } else {
            let end = bounds
                .iter()
                .copied()
                .find(|&b| b >= at + rng.below(12))
                .unwrap_or(out.len());
            out.replace_range(at..end, "");
        }
    }
    out
}

#[test]
fn well_formed_files_with_damaged_content_never_panic_the_reader() {
    // The messages and metadata of a real recording, rewritten into valid MCAP files (good
    // CRCs) with random edits to their JSON: the decoding layer below the CRC checks.
    let good = recording();
    let summary = mcap::Summary::read(&good).unwrap().unwrap();
    let index = summary
        .metadata_indexes
        .iter()
        .find(|m| m.name == METADATA_NAME)
        .unwrap();
    let metadata = mcap::read::metadata(&good, index).unwrap().metadata;
    let messages: Vec<(String, u32, Vec<u8>)> = mcap::MessageStream::new(&good)
        .unwrap()
        .map(|m| {
            let m = m.unwrap();
            (m.channel.topic.clone(), m.sequence, m.data.into_owned())
        })
        .collect();
    for_each_seed(|k| {
        let mut rng = Rng(k);
        let mut meta: BTreeMap<String, String> = metadata.clone();
        if rng.below(3) == 0 {
            let keys: Vec<String> = meta.keys().cloned().collect();
            let key = &keys[rng.below(keys.len())];
            if rng.below(4) == 0 {
                meta.remove(key);
            } else {
                let value = mutate_text(&mut rng, &meta[key]);
                meta.insert(key.clone(), value);
            }
        }
        let mut out = std::io::Cursor::new(Vec::new());
        {
            let mut w = mcap::Writer::new(&mut out).unwrap();
            w.write_metadata(&mcap::records::Metadata {
                name: METADATA_NAME.into(),
                metadata: meta,
            })
            .unwrap();
            let schema = w.add_schema("x", "jsonschema", b"{}").unwrap();
            let mut channels = BTreeMap::new();
            for (i, (topic, sequence, data)) in messages.iter().enumerate() {
                let id = *channels.entry(topic.clone()).or_insert_with(|| {
                    w.add_channel(schema, topic, "json", &Default::default())
                        .unwrap()
                });
                let data = if rng.below(messages.len()) < 2 {
                    mutate_text(&mut rng, &String::from_utf8_lossy(data)).into_bytes()
                } else {
                    data.clone()
                };
                let header = mcap::records::MessageHeader {
                    channel_id: id,
                    sequence: *sequence,
                    log_time: i as u64,
                    publish_time: i as u64,
                };
                w.write_to_known_channel(&header, &data).unwrap();
            }
            w.finish().unwrap();
        }
        let bytes = out.into_inner();
        let result = catch_unwind(AssertUnwindSafe(|| {
            McapRecording::from_bytes(&bytes, Path::new("fuzz.mcap"))
        }));
        assert!(result.is_ok(), "case seed {k} panicked the reader");
    });
}
