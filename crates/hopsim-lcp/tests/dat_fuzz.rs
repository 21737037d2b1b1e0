//! Property-based fuzzing of the `.dat` reader: random token streams, mutated valid files
//! and arbitrary bytes give a problem or an error, never a panic, and an accepted problem
//! is well formed. 256 cases per property by default; `PROPTEST_CASES=100000` runs a longer
//! campaign (docs/reliability.md).

use hopsim_lcp::dat::{parse_dat, parse_dat_with, DatLimits};
use hopsim_lcp::LcpProblem;
use nalgebra::{DMatrix, DVector};
use proptest::prelude::*;

/// 256 cases unless `PROPTEST_CASES` says otherwise.
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

/// Tokens a `.dat` file holds, and the ones that break it.
fn token() -> impl Strategy<Value = String> {
    prop_oneof![
        (0usize..8).prop_map(|n| n.to_string()),
        any::<f64>().prop_map(|v| format!("{v:e}")),
        any::<f64>().prop_map(|v| v.to_string()),
        any::<u64>().prop_map(|v| v.to_string()),
        Just("4294967296".to_string()),
        Just("18446744073709551615".to_string()),
        Just("18446744073709551616".to_string()),
        Just("nan".to_string()),
        Just("-inf".to_string()),
        Just("1e309".to_string()),
        Just("-0".to_string()),
        Just("#".to_string()),
        "[a-z0-9.+\\-eE]{1,6}",
        "\\PC{1,3}",
    ]
}

fn separator() -> impl Strategy<Value = &'static str> {
    prop_oneof![
        Just(" "),
        Just("\n"),
        Just("\t"),
        Just("\r\n"),
        Just("  \u{a0}")
    ]
}

/// The checks every accepted problem passes.
fn well_formed(p: &LcpProblem) {
    let n = p.n();
    assert!(n >= 1);
    assert_eq!((p.m.nrows(), p.m.ncols()), (n, n));
    assert!(p.m.iter().chain(p.q.iter()).all(|v| v.is_finite()));
}

fn small_problem() -> impl Strategy<Value = LcpProblem> {
    (1usize..5).prop_flat_map(|n| {
        (
            prop::collection::vec(-1e6..1e6f64, n * n),
            prop::collection::vec(-1e6..1e6f64, n),
            "[a-z #]{0,12}",
        )
            .prop_map(move |(m, q, comment)| LcpProblem {
                m: DMatrix::from_row_slice(n, n, &m),
                q: DVector::from_vec(q),
                comment: comment.trim().to_string(),
            })
    })
}

/// One edit of a text: delete a range, insert a token, or swap a char.
#[derive(Clone, Debug)]
enum Edit {
    Delete(usize, usize),
    Insert(usize, String),
    Replace(usize, char),
}

fn edit() -> impl Strategy<Value = Edit> {
    prop_oneof![
        (any::<usize>(), 0usize..16).prop_map(|(at, len)| Edit::Delete(at, len)),
        (any::<usize>(), token()).prop_map(|(at, t)| Edit::Insert(at, t)),
        (any::<usize>(), any::<char>()).prop_map(|(at, c)| Edit::Replace(at, c)),
    ]
}

/// Applies `edit` at a char boundary of `text`.
fn apply(text: &mut String, edit: &Edit) {
    let boundary = |at: usize| {
        let chars: Vec<usize> = text.char_indices().map(|(i, _)| i).collect();
        if chars.is_empty() {
            0
        } else {
            chars[at % chars.len()]
        }
    };
    match edit {
        Edit::Delete(at, len) => {
            let start = boundary(*at);
            let end = text[start..]
                .char_indices()
                .nth(*len)
                .map_or(text.len(), |(i, _)| start + i);
            text.replace_range(start..end, "");
        }
        Edit::Insert(at, t) => {
            let at = boundary(*at);
            text.insert_str(at, t);
        }
        Edit::Replace(at, c) => {
            if text.is_empty() {
                return;
            }
            let start = boundary(*at);
            let len = text[start..].chars().next().map_or(0, char::len_utf8);
            text.replace_range(start..start + len, &c.to_string());
        }
    }
}

proptest! {
    #![proptest_config(config())]

    #[test]
    fn random_token_streams_parse_or_fail_cleanly(
        parts in prop::collection::vec((token(), separator()), 0..40)
    ) {
        let text: String = parts.iter().map(|(t, s)| format!("{t}{s}")).collect();
        if let Ok(p) = parse_dat(&text, "fuzz.dat") {
            well_formed(&p);
        }
    }

    #[test]
    fn plausible_headers_with_random_bodies_parse_or_fail_cleanly(
        n in prop_oneof![0usize..6, Just(10_000usize), Just(10_001usize), Just(1usize << 32)],
        values in prop::collection::vec(token(), 0..40),
    ) {
        let text = format!("{n} 0 {n} {n} {n} {n}\n{}", values.join(" "));
        let tight = DatLimits { max_dimension: 4, ..DatLimits::default() };
        for result in [parse_dat(&text, "fuzz.dat"), parse_dat_with(&text, "fuzz.dat", &tight)] {
            match result {
                Ok(p) => well_formed(&p),
                Err(e) => prop_assert!(e.to_string().starts_with("fuzz.dat: ")),
            }
        }
    }

    #[test]
    fn mutated_valid_files_parse_or_fail_cleanly(
        problem in small_problem(),
        edits in prop::collection::vec(edit(), 1..6),
    ) {
        let mut text = problem.to_dat_string();
        for e in &edits {
            apply(&mut text, e);
        }
        if let Ok(p) = parse_dat(&text, "fuzz.dat") {
            well_formed(&p);
        }
    }

    #[test]
    fn arbitrary_bytes_parse_or_fail_cleanly(bytes in prop::collection::vec(any::<u8>(), 0..256)) {
        let text = String::from_utf8_lossy(&bytes);
        if let Ok(p) = parse_dat(&text, "fuzz.dat") {
            well_formed(&p);
        }
    }

    #[test]
    fn written_problems_read_back_exactly(problem in small_problem()) {
        let again = parse_dat(&problem.to_dat_string(), "copy.dat").unwrap();
        prop_assert_eq!(again, problem);
    }
}
