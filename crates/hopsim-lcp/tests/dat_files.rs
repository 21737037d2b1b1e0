//! The Siconos `.dat` sample problems (tests/data/lcp) and the reader's error messages.

use hopsim_lcp::dat::{parse_dat, read_dat};
use hopsim_lcp::{DatError, LcpStatus, LemkeSolver};
use std::path::PathBuf;

fn data(name: &str) -> PathBuf {
    PathBuf::from(concat!(env!("CARGO_MANIFEST_DIR"), "/../../tests/data/lcp")).join(name)
}

fn solve_file(name: &str) -> (hopsim_lcp::LcpProblem, hopsim_lcp::LcpSolution) {
    let problem = read_dat(&data(name)).unwrap();
    let sol = LemkeSolver::default()
        .solve_problem(&problem)
        .unwrap()
        .clone();
    assert_eq!(sol.status, LcpStatus::Solved, "{name}");
    assert!(sol.certificate.holds(), "{name}: {:?}", sol.certificate);
    (problem, sol)
}

#[test]
fn lcp_trivial_has_z_i_equal_one_over_i() {
    let (problem, sol) = solve_file("lcp_trivial.dat");
    assert_eq!(problem.n(), 9);
    for i in 0..9 {
        let expected = 1.0 / (i + 1) as f64;
        assert!((sol.z[i] - expected).abs() < 1e-14, "z[{i}] = {}", sol.z[i]);
    }
}

#[test]
fn lcp_deudeu_has_the_known_solution() {
    let (problem, sol) = solve_file("lcp_deudeu.dat");
    assert_eq!(problem.m[(0, 1)], 1.0);
    assert!((sol.z[0] - 4.0 / 3.0).abs() < 1e-14);
    assert!((sol.z[1] - 7.0 / 3.0).abs() < 1e-14);
}

#[test]
fn lcp_exp_murty_has_the_known_solution() {
    let (problem, sol) = solve_file("lcp_exp_murty.dat");
    // Read row by row: lower triangular.
    assert_eq!((problem.m[(1, 0)], problem.m[(0, 1)]), (2.0, 0.0));
    assert_eq!(problem.comment, "# from Murty (1988) chapter 6");
    assert_eq!(sol.z.as_slice(), &[1.0, 0.0, 0.0, 0.0, 0.0, 0.0]);
    assert_eq!(sol.pivots, 64, "2ⁿ pivots on Murty's example");
}

fn format_error(text: &str) -> String {
    let err = parse_dat(text, "lcp_x.dat").unwrap_err();
    assert!(matches!(err, DatError::Format { .. }));
    assert_eq!(err.file(), "lcp_x.dat");
    err.to_string()
}

#[test]
fn parse_errors_name_the_file_and_the_problem() {
    let cases = [
        ("", "lcp_x.dat: file ends before the problem size n"),
        (
            "2 0 2 2 2 2 1 2 3",
            "lcp_x.dat: expected 4 matrix entries, found 3",
        ),
        (
            "2 0 2 2 2 2 1 2 3 4 -1",
            "lcp_x.dat: expected 2 entries of q, found 1",
        ),
        (
            "2 0 2 2 2 2 1 2 abc 4 -1 -1",
            "lcp_x.dat: token 9 'abc' (matrix entries) is not a number",
        ),
        (
            "2 0 2 2 2 2 1 2 3 4 -1 nan",
            "lcp_x.dat: token 12 'nan' (entries of q) is not a finite number",
        ),
        (
            "2 1 2 2 2 2",
            "lcp_x.dat: storage flag 1 is not supported (only 0 = dense)",
        ),
        (
            "2 0 2 3 2 3",
            "lcp_x.dat: matrix shape 2×3 (repeated as 2×3) does not match problem size 2",
        ),
        (
            "x",
            "lcp_x.dat: token 1 'x' (problem size n) is not a non-negative integer",
        ),
        ("0 0 0 0 0 0", "lcp_x.dat: problem size n is 0"),
    ];
    for (text, expected) in cases {
        assert_eq!(format_error(text), expected, "input {text:?}");
    }
}

#[test]
fn a_6x6_file_with_30_entries_names_the_count() {
    let text = format!("6 0 6 6 6 6 {}", "1 ".repeat(30));
    assert_eq!(
        format_error(&text),
        "lcp_x.dat: expected 36 matrix entries, found 30"
    );
}

#[test]
fn unreadable_file_names_the_path() {
    let path = data("no_such_problem.dat");
    let err = read_dat(&path).unwrap_err();
    assert!(matches!(err, DatError::Io { .. }));
    let msg = err.to_string();
    assert!(msg.starts_with(&path.display().to_string()), "{msg}");
    assert!(msg.contains("cannot read"), "{msg}");
}

#[test]
fn written_problems_read_back_exactly() {
    let problem = read_dat(&data("lcp_deudeu.dat")).unwrap();
    let text = problem.to_dat_string();
    assert_eq!(parse_dat(&text, "copy.dat").unwrap(), problem);
}
