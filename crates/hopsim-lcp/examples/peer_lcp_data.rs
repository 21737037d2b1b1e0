//! Writes the contact LCPs of the peer benchmark (`benches/peers/`) as dense Siconos `.dat`
//! files, so Siconos' C Lemke and hopsim solve exactly the same numbers:
//!
//! ```text
//! cargo run --release -p hopsim-lcp --example peer_lcp_data -- benches/peers/data
//! ```
//!
//! The problems are those of the criterion benchmark `benches/lemke.rs` (same generator,
//! same seeds): the 6 × 6 two-contact Robbit LCP and rows of 2, 4 and 8 eccentric discs
//! (n = 12, 24, 48). The files are committed; rerun this only to regenerate them.

#[path = "../tests/common/mod.rs"]
mod common;

use hopsim_lcp::{LcpProblem, LcpStatus, LemkeSolver};
use nalgebra::{DMatrix, DVector};
use std::path::PathBuf;

fn main() {
    let dir = PathBuf::from(
        std::env::args()
            .nth(1)
            .unwrap_or_else(|| "benches/peers/data".into()),
    );
    if let Err(e) = std::fs::create_dir_all(&dir) {
        eprintln!("error: cannot create {}: {e}", dir.display());
        std::process::exit(1);
    }
    let mut problems: Vec<(String, DMatrix<f64>, DVector<f64>, String)> = Vec::new();
    let (m, q) = common::robbit_two_contacts();
    problems.push((
        "robbit_6x6".into(),
        m,
        q,
        "Robbit (docs/physics.md 5.3) rolling into the corner of a 5 cm step: two closed \
         frictional contacts, mu = 1, dt = 2e-4 s; the criterion benchmark lemke_robbit_6x6 \
         (crates/hopsim-lcp/tests/common/mod.rs, robbit_two_contacts)."
            .into(),
    ));
    for (n, discs) in [(12, 2), (24, 4), (48, 8)] {
        let mut rng = common::Rng(0x5eed_0000 + n as u64);
        let (m, q) = common::disc_row(&mut rng, discs, false, Some(1.0));
        assert_eq!(q.len(), n);
        problems.push((
            format!("contact_{n}"),
            m,
            q,
            format!(
                "A row of {discs} eccentric discs on the ground, each touching the next, the \
                 last against a wall: {} frictional contacts, mu = 1; the criterion benchmark \
                 lemke_contact/{n} (crates/hopsim-lcp/tests/common/mod.rs, disc_row, seed \
                 0x5eed0000 + {n}).",
                2 * discs
            ),
        ));
    }
    let mut solver = LemkeSolver::default();
    for (name, m, q, comment) in problems {
        let problem = LcpProblem { m, q, comment };
        let sol = solver.solve_problem(&problem).expect("valid problem");
        assert_eq!(sol.status, LcpStatus::Solved, "{name} must solve");
        let path = dir.join(format!("{name}.dat"));
        if let Err(e) = std::fs::write(&path, problem.to_dat_string()) {
            eprintln!("error: cannot write {}: {e}", path.display());
            std::process::exit(1);
        }
        println!(
            "{}: n = {}, {} pivots, method {}",
            path.display(),
            problem.n(),
            sol.pivots,
            sol.method
        );
    }
}
