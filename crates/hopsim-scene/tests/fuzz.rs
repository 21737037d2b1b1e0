//! Fuzzing of the scene reader and of `--set` overrides: mutated bundled scenes, random
//! TOML-ish text and random override arguments give a scene or an error, never a panic
//! (and never a stack overflow). Each property runs 256 cases by default; the
//! `PROPTEST_CASES` environment variable sets another budget (e.g. 100000 for a long
//! campaign) and `HOPSIM_FUZZ_SEED` another seed (docs/reliability.md).
//!
//! proptest draws the seeds; each drives a small generator of scene text and overrides
//! (SplitMix64) in this file. A failing case prints its seed and input.

use hopsim_scene::{Override, Scene, SceneError};
use proptest::prelude::any;
use proptest::test_runner::{Config, RngAlgorithm, TestCaseError, TestRng, TestRunner};
use std::panic::{catch_unwind, AssertUnwindSafe};
use std::path::{Path, PathBuf};

/// SplitMix64: small, fast, good enough to drive mutations.
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
    fn pick<'a, T>(&mut self, items: &'a [T]) -> &'a T {
        &items[self.below(items.len())]
    }
    fn chance(&mut self, one_in: usize) -> bool {
        self.below(one_in) == 0
    }
}

fn seed() -> u64 {
    std::env::var("HOPSIM_FUZZ_SEED")
        .ok()
        .and_then(|v| v.parse().ok())
        .unwrap_or(0x5ce9e)
}

/// Runs `case` on the seeds proptest draws (`PROPTEST_CASES` of them, 256 by default) from
/// a runner seeded with `HOPSIM_FUZZ_SEED`, so that every run of the suite tries the same
/// cases; each seed drives its own generator. A panic is reported with the seed and the
/// input `case` describes.
fn run(name: &str, case: impl FnMut(&mut Rng) -> (String, Box<dyn FnOnce()>)) {
    let case = std::cell::RefCell::new(case);
    let mut key = [0u8; 32];
    key[..8].copy_from_slice(&seed().to_le_bytes());
    let rng = TestRng::from_seed(RngAlgorithm::ChaCha, &key);
    let mut runner = TestRunner::new_with_rng(Config::default(), rng);
    let result = runner.run(&any::<u64>(), |s| {
        let (input, check) = (case.borrow_mut())(&mut Rng(s));
        catch_unwind(AssertUnwindSafe(check)).map_err(|panic| {
            let what = panic
                .downcast_ref::<String>()
                .cloned()
                .or_else(|| panic.downcast_ref::<&str>().map(|s| s.to_string()))
                .unwrap_or_default();
            TestCaseError::fail(format!("case seed {s} panicked: {what}\ninput:\n{input}"))
        })
    });
    if let Err(e) = result {
        panic!("{name} (HOPSIM_FUZZ_SEED={}): {e}", seed());
    }
}

fn repo(path: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../..")
        .join(path)
}

fn bundled_scenes() -> Vec<String> {
    let mut out = Vec::new();
    for entry in std::fs::read_dir(repo("scenes")).unwrap() {
        let path = entry.unwrap().path();
        if path.extension().is_some_and(|e| e == "toml") {
            out.push(std::fs::read_to_string(path).unwrap());
        }
    }
    out.sort();
    out
}

/// Text that is likely to matter to a TOML scene.
const TOKENS: &[&str] = &[
    "[",
    "]",
    "[[",
    "]]",
    "{",
    "}",
    "=",
    ",",
    ".",
    "\"",
    "'",
    "\n",
    " ",
    "#",
    "-",
    "+",
    "0",
    "1",
    "-1",
    "0.0",
    "1e308",
    "-1e308",
    "1e-308",
    "5e-324",
    "inf",
    "-inf",
    "nan",
    "true",
    "9223372036854775807",
    "9223372036854775808",
    "0x7f",
    "1979-05-27T07:32:00Z",
    "\"\"",
    "\"disc\"",
    "\"flywheel\"",
    "\"a,b\"",
    "[[bodies]]",
    "[[shapes]]",
    "[[springs]]",
    "[initial]",
    "[controller]",
    "[simulation]",
    "[summary]",
    "[environment]",
    "name",
    "parent",
    "mass",
    "inertia",
    "vertices",
    "q",
    "u",
    "type",
    "\"polygon\"",
    "\"pulse\"",
    "\"momentum_impulse\"",
    "[1, 2]",
    "[[0, 0], [1, 0], [0, 1]]",
    "é",
    "\u{0}",
    "\t",
];

/// One random edit of `text` at a char boundary.
fn mutate(rng: &mut Rng, text: &mut String) {
    let bounds: Vec<usize> = text
        .char_indices()
        .map(|(i, _)| i)
        .chain([text.len()])
        .collect();
    let at = *rng.pick(&bounds);
    match rng.below(6) {
        0 => {
            // Delete a run of chars.
            let len = rng.below(24);
            let end = bounds
                .iter()
                .copied()
                .find(|&b| b >= at + len)
                .unwrap_or(text.len());
            text.replace_range(at..end, "");
        }
        1 | 2 => {
            let token: &&str = rng.pick(TOKENS);
            text.insert_str(at, token);
        }
        3 => {
            // Replace a number-looking char with another digit or sign.
            let c = *rng.pick(&['0', '9', '-', '.', 'e', '"', '[', ']', '=']);
            let end = bounds.iter().copied().find(|&b| b > at).unwrap_or(at);
            text.replace_range(at..end, &c.to_string());
        }
        4 => {
            // Duplicate or drop a line.
            let lines: Vec<&str> = text.lines().collect();
            if lines.is_empty() {
                return;
            }
            let i = rng.below(lines.len());
            let mut out: Vec<&str> = lines.clone();
            if rng.chance(2) {
                out.insert(i, lines[i]);
            } else {
                out.remove(i);
            }
            *text = out.join("\n");
        }
        _ => {
            // Swap two lines.
            let mut lines: Vec<String> = text.lines().map(String::from).collect();
            if lines.len() > 1 {
                let (i, j) = (rng.below(lines.len()), rng.below(lines.len()));
                lines.swap(i, j);
                *text = lines.join("\n");
            }
        }
    }
}

/// Parses `text` with `overrides`; an accepted scene must be usable.
fn check_scene(text: &str, overrides: &[Override]) {
    match hopsim_scene::parse(text, Path::new("fuzz.toml"), overrides) {
        Ok(scene) => well_formed(&scene),
        Err(e) => error_is_located(&e),
    }
}

fn well_formed(scene: &Scene) {
    let n = scene.model.dof();
    assert_eq!(scene.initial.q.len(), n);
    assert_eq!(scene.initial.u.len(), n);
    assert!(scene.initial.q.iter().all(|v| v.is_finite()));
    assert!(scene.initial.u.iter().all(|v| v.is_finite()));
    let s = &scene.settings;
    assert!(s.dt > 0.0 && s.dt < s.duration && s.duration.is_finite());
    assert!(s.speed_window >= s.dt && s.speed_window <= s.duration);
    assert!(scene
        .model
        .bodies()
        .iter()
        .all(|b| !b.name.trim().is_empty()));
}

fn error_is_located(e: &SceneError) {
    let text = e.to_string();
    assert!(!text.is_empty());
    assert!(text.len() < 4096, "an error of {} bytes", text.len());
    match e {
        SceneError::Invalid { .. } | SceneError::Syntax { .. } => {
            assert!(e.location().is_some(), "{text}")
        }
        SceneError::Override { text: arg, .. } => assert!(text.starts_with(arg.as_str())),
        SceneError::Io { .. } => panic!("parse cannot fail on I/O: {text}"),
        SceneError::Import(_) => panic!("parse imports nothing: {text}"),
    }
}

#[test]
fn mutated_bundled_scenes_parse_or_fail_cleanly() {
    let scenes = bundled_scenes();
    assert!(scenes.len() >= 4);
    run("mutated scene", |rng| {
        let mut text = rng.pick(&scenes).clone();
        for _ in 0..1 + rng.below(8) {
            mutate(rng, &mut text);
        }
        let input = text.clone();
        (input, Box::new(move || check_scene(&text, &[])))
    });
}

#[test]
fn random_toml_like_text_parses_or_fails_cleanly() {
    run("random text", |rng| {
        let text: String = (0..rng.below(80)).map(|_| *rng.pick(TOKENS)).collect();
        let input = text.clone();
        (input, Box::new(move || check_scene(&text, &[])))
    });
}

/// Keys of the bundled scenes and a few that are not.
const KEYS: &[&str] = &[
    "simulation",
    "simulation.duration",
    "simulation.dt",
    "simulation.record_rate",
    "simulation.max_speed",
    "summary.speed_window",
    "environment.terrain",
    "environment.friction",
    "environment.restitution",
    "bodies",
    "bodies.0",
    "bodies.disc",
    "bodies.disc.name",
    "bodies.disc.mass",
    "bodies.flywheel.parent",
    "bodies.1.inertia",
    "bodies.9.mass",
    "shapes.0.radius",
    "shapes.disc.type",
    "shapes.0.vertices",
    "controller",
    "controller.type",
    "controller.torque",
    "controller.period",
    "initial.q",
    "initial.q.1",
    "initial.u.3",
    "initial.rest_on_ground",
    "meta.title",
    "new.key",
    "a.b.c.d",
];

const VALUES: &[&str] = &[
    "0",
    "1",
    "-1",
    "0.5",
    "1e308",
    "-1e308",
    "1e-308",
    "inf",
    "nan",
    "true",
    "fast",
    "\"\"",
    "\"a,b\"",
    "[1, 2]",
    "[0.0, 0.1, 0.0, 0.0]",
    "[[0, 0], [1, 0], [0, 1]]",
    "{x = 1}",
    "[[[[[[[[[[1]]]]]]]]]]",
    "disc",
    "flywheel",
    "polygon",
    "pulse",
    "=",
    "",
    "é",
];

#[test]
fn random_overrides_apply_or_fail_cleanly() {
    let scenes = bundled_scenes();
    run("overrides", |rng| {
        let text = rng.pick(&scenes).clone();
        let mut args = Vec::new();
        for _ in 0..1 + rng.below(4) {
            let key = if rng.chance(5) {
                (0..1 + rng.below(5))
                    .map(|_| *rng.pick(&["a", "0", "99999999999999999999", "disc", "", " "]))
                    .collect::<Vec<_>>()
                    .join(".")
            } else {
                rng.pick(KEYS).to_string()
            };
            let value = if rng.chance(4) {
                (0..rng.below(6)).map(|_| *rng.pick(TOKENS)).collect()
            } else {
                rng.pick(VALUES).to_string()
            };
            args.push(format!("{key}={value}"));
        }
        let input = args.join("\n");
        (
            input,
            Box::new(move || {
                // The argument parser either accepts an argument or says why not.
                let mut overrides = Vec::new();
                for arg in &args {
                    match arg.parse::<Override>() {
                        Ok(o) => overrides.push(o),
                        Err(message) => assert!(!message.is_empty()),
                    }
                }
                check_scene(&text, &overrides);
            }),
        )
    });
}
