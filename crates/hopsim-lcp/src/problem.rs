//! An LCP as data: `M`, `q` and a free-text comment (from a `.dat` file).

use nalgebra::{DMatrix, DVector};

/// The LCP `w = M z + q, z ≥ 0, w ≥ 0, zᵀw = 0`.
#[derive(Debug, Clone, PartialEq)]
pub struct LcpProblem {
    pub m: DMatrix<f64>,
    pub q: DVector<f64>,
    /// Free text found after `q` in a `.dat` file (trimmed; may be empty).
    pub comment: String,
}

impl LcpProblem {
    /// Size `n` of the problem.
    pub fn n(&self) -> usize {
        self.q.len()
    }

    /// The problem in the dense Siconos `.dat` format that [`crate::dat::parse_dat`] reads
    /// (numbers printed exactly, shortest round-trip form).
    pub fn to_dat_string(&self) -> String {
        use std::fmt::Write;
        let n = self.n();
        let mut s = format!(
            "{n}\n0\n{}\n{}\n{}\t{}\n",
            self.m.nrows(),
            self.m.ncols(),
            self.m.nrows(),
            self.m.ncols()
        );
        for i in 0..self.m.nrows() {
            let row: Vec<String> = self.m.row(i).iter().map(|v| format!("{v:e}")).collect();
            let _ = writeln!(s, "{}", row.join(" "));
        }
        let q: Vec<String> = self.q.iter().map(|v| format!("{v:e}")).collect();
        let _ = writeln!(s, "{}", q.join(" "));
        if !self.comment.is_empty() {
            let _ = writeln!(s, "\n{}", self.comment);
        }
        s
    }
}
