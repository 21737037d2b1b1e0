//! A campaign over generated mechanisms, for looking at what they do: how runs end, how
//! much energy passive runs gain, which steps fail their LCP.
//!
//! `cargo run --release -p hopsim-gen --example campaign -- CASES [SEED] [--show KIND]`
//! prints a tally of the outcomes and the cases of the worst kind; `--show stopped`,
//! `--show gain` or `--show lcp` writes those cases' scenes to `out/campaign/`.

use hopsim_gen::{genes, run_and_check, Mechanism, Outcome};
use proptest::strategy::{Strategy, ValueTree};
use proptest::test_runner::{Config, RngAlgorithm, TestRng, TestRunner};
use std::collections::BTreeMap;

fn main() {
    let args: Vec<String> = std::env::args().collect();
    let cases: usize = args.get(1).and_then(|v| v.parse().ok()).unwrap_or(1000);
    let seed: u64 = args.get(2).and_then(|v| v.parse().ok()).unwrap_or(1);
    let show = args
        .iter()
        .position(|a| a == "--show")
        .and_then(|i| args.get(i + 1).cloned());
    let mut key = [0u8; 32];
    key[..8].copy_from_slice(&seed.to_le_bytes());
    let mut runner = TestRunner::new_with_rng(
        Config::default(),
        TestRng::from_seed(RngAlgorithm::ChaCha, &key),
    );
    let mut tally: BTreeMap<String, usize> = BTreeMap::new();
    let (mut worst_clean, mut worst_balance) = (f64::NEG_INFINITY, 0.0_f64);
    let out = std::path::Path::new("out/campaign");
    let _ = std::fs::create_dir_all(out);
    for case in 0..cases {
        let g = genes().new_tree(&mut runner).unwrap().current();
        let m = Mechanism::from_genes(&g);
        let (kind, detail) = match run_and_check(&m) {
            Ok(Outcome::Ran(f)) => {
                let relative = f.energy_gain / f.energy_scale.max(1e-300);
                if m.is_passive() && f.warnings == 0 {
                    worst_clean = worst_clean.max(relative);
                    worst_balance =
                        worst_balance.max(f.max_balance_error / f.energy_scale.max(1e-300));
                }
                if m.is_passive() && relative > 0.1 {
                    (
                        "gain".to_string(),
                        format!("{relative:.3} of {:.3e} J", f.energy_scale),
                    )
                } else if f.lcp_failures > 0 {
                    ("lcp".to_string(), format!("{} failures", f.lcp_failures))
                } else {
                    ("ran".to_string(), String::new())
                }
            }
            Ok(Outcome::Stopped(e)) => {
                let kind = e
                    .split(':')
                    .nth(1)
                    .unwrap_or("")
                    .trim()
                    .split(' ')
                    .next()
                    .unwrap_or("")
                    .to_string();
                (format!("stopped {kind}"), e)
            }
            Ok(Outcome::Rejected(_)) => ("refused".to_string(), String::new()),
            Err(v) => ("VIOLATION".to_string(), v.0),
        };
        let kind = if m.is_passive() {
            format!("passive {kind}")
        } else {
            kind
        };
        *tally.entry(kind.clone()).or_default() += 1;
        if !kind.ends_with("ran") && !kind.ends_with("refused") {
            println!("case {case}: {kind}: {detail}");
            if show
                .as_deref()
                .is_some_and(|s| kind.contains(s) || s == "all")
            {
                // The scene as run (lifted where its start overlapped).
                let text = match hopsim_gen::scene_of(&m) {
                    Ok(Ok(scene)) => scene.setup.text,
                    _ => m.to_toml(),
                };
                let _ = std::fs::write(out.join(format!("case-{case}.toml")), text);
            }
        }
    }
    println!("{tally:#?}");
    println!(
        "passive runs without warnings: largest energy gain {worst_clean:.3e}, largest balance \
         error {worst_balance:.3e} of the energy scale"
    );
}
