//! [`LemkeSolver`]: the public solver. The hot path (validation, trivial case, one Lemke
//! run, certificate) is in `primary.rs`, the pivoting in `tableau.rs`; this module adds
//! the recovery when that run does not certify: direct refinement of its final basis,
//! other covering vectors, then enumeration of complementary bases.
//!
//! `M` and `q` are scaled internally by powers of two (exact), so the pivoting tolerances
//! are relative to the problem; the certificate is always computed on the original data.

use crate::certificate::{MatRef, ProblemRef};
use crate::enumerate::{self, BasisScratch};
use crate::primary::{self, End, Primary, Settings};
use crate::solution::set_len;
use crate::tableau::{self, Ending, Scales, Work};
use crate::{Certificate, LcpInputError, LcpProblem, LcpSolution, LcpStatus, SolveMethod};
use nalgebra::{DMatrix, DMatrixView, DVector, DVectorView};

mod warm;
pub use warm::WarmStart;

/// Hard cap on the enumeration fallback: `2ⁿ` bases.
const ENUMERATION_CAP: usize = 20;
/// Number of alternate covering vectors the fallback tries (see `alternate_covering`).
const ALTERNATE_COVERINGS: usize = 4;

/// Options of [`LemkeSolver`].
#[derive(Debug, Clone, PartialEq)]
pub struct LemkeOptions {
    /// Pivot limit per Lemke run; `None`: `50 n + 100`.
    pub max_pivots: Option<usize>,
    /// Covering vector `d > 0`; `None`: all ones.
    pub covering: Option<Vec<f64>>,
    /// Relative tolerance of the certificate (see [`Certificate`]), in `(0, 1)`.
    pub rel_tol: f64,
    /// Largest `n` for which the exhaustive enumeration fallback runs (capped at 20).
    pub enumeration_limit: usize,
    /// When Lemke's method fails: retry with other covering vectors, then enumerate.
    pub fallback: bool,
}

impl Default for LemkeOptions {
    fn default() -> Self {
        LemkeOptions {
            max_pivots: None,
            covering: None,
            rel_tol: 1e-9,
            enumeration_limit: 10,
            fallback: true,
        }
    }
}

/// Reusable Lemke solver: all buffers grow to the largest `n` seen and are reused, so a
/// solve allocates nothing once they have (the time-stepper solves one LCP per step).
///
/// On a failure status the reported `z`, `w` are the last iterate of the run with the
/// configured covering vector, while `pivots` counts every Lemke run of the solve.
#[derive(Debug, Clone)]
pub struct LemkeSolver {
    options: LemkeOptions,
    /// Problem size the buffers can hold.
    cap: usize,
    work: Work,
    /// Outcome of the hot path of the last solve.
    prim: Primary,
    /// The size `n` for which `work.cover` holds the configured covering vector, checked
    /// (`usize::MAX`: none): it is checked and written once per size or options change,
    /// not per solve.
    cover_n: usize,
    zs: Vec<f64>,
    ws: Vec<f64>,
    lu: Vec<f64>,
    lu_rhs: Vec<f64>,
    z_basic: Vec<bool>,
    sol: LcpSolution,
}

impl Default for LemkeSolver {
    fn default() -> Self {
        LemkeSolver::new(LemkeOptions::default())
    }
}

impl LemkeSolver {
    pub fn new(options: LemkeOptions) -> Self {
        LemkeSolver {
            options,
            cap: 0,
            work: Work::default(),
            prim: Primary::default(),
            cover_n: usize::MAX,
            zs: Vec::new(),
            ws: Vec::new(),
            lu: Vec::new(),
            lu_rhs: Vec::new(),
            z_basic: Vec::new(),
            sol: LcpSolution::empty(),
        }
    }

    pub fn options(&self) -> &LemkeOptions {
        &self.options
    }

    pub fn set_options(&mut self, options: LemkeOptions) {
        self.options = options;
        self.cover_n = usize::MAX;
    }

    /// The result of the last call of [`LemkeSolver::solve`] that did not return an error.
    pub fn solution(&self) -> &LcpSolution {
        &self.sol
    }

    /// Grows every buffer to hold problems of size `n` (`solve` does this as needed).
    #[inline]
    pub fn reserve(&mut self, n: usize) {
        if n > self.cap {
            self.grow(n);
        }
    }

    #[cold]
    #[inline(never)]
    fn grow(&mut self, n: usize) {
        self.work.reserve(n);
        self.zs.resize(n, 0.0);
        self.ws.resize(n, 0.0);
        self.lu.resize(n * n, 0.0);
        self.lu_rhs.resize(n, 0.0);
        self.z_basic.resize(n, false);
        for v in [&mut self.sol.z, &mut self.sol.w] {
            let mut data: Vec<f64> = std::mem::replace(v, DVector::zeros(0)).data.into();
            data.reserve(n.saturating_sub(data.len()));
            *v = DVector::from_vec(data);
        }
        self.cap = n;
        self.cover_n = usize::MAX;
    }

    /// Solves `w = M z + q, z ≥ 0, w ≥ 0, zᵀw = 0` (the contact LCP of docs/physics.md §4 is
    /// one) by Lemke's method, then, if that fails and `options.fallback`, other covering
    /// vectors and enumeration.
    ///
    /// Reuses internal buffers: no heap allocation once they have grown to size `n`.
    /// Never reports [`LcpStatus::Solved`] unless the certificate holds.
    pub fn solve(
        &mut self,
        m: DMatrixView<'_, f64>,
        q: DVectorView<'_, f64>,
    ) -> Result<&LcpSolution, LcpInputError> {
        let n = m.nrows();
        if m.ncols() != n {
            return Err(LcpInputError::NotSquare {
                rows: n,
                cols: m.ncols(),
            });
        }
        if q.len() != n {
            return Err(LcpInputError::SizeMismatch { n, q_len: q.len() });
        }
        if self.cover_n != n {
            self.load_cover(n)?;
        }
        if n == 0 {
            set_len(&mut self.sol.z, 0);
            set_len(&mut self.sol.w, 0);
            let sol = &mut self.sol;
            (sol.status, sol.method, sol.pivots) = (LcpStatus::Solved, SolveMethod::Trivial, 0);
            sol.certificate = Certificate::default();
            return Ok(&self.sol);
        }
        let q = q.as_slice();
        let m = MatRef::new(&m);
        if self.sol.z.len() != n {
            // The last answer stays as it was unless this call answers.
            primary::check_finite(m, q)?;
            set_len(&mut self.sol.z, n);
            set_len(&mut self.sol.w, n);
        }
        let settings = Settings {
            rel_tol: self.options.rel_tol,
            max_pivots: self.max_pivots(n),
        };
        let z = self.sol.z.as_mut_slice();
        let w = self.sol.w.as_mut_slice();
        let prim = &mut self.prim;
        primary::primary(&mut self.work, m, q, z, w, &settings, prim)?;
        let sol = &mut self.sol;
        sol.pivots = prim.pivots;
        sol.certificate = prim.certificate;
        sol.status = LcpStatus::Solved;
        match prim.end {
            End::Trivial => sol.method = SolveMethod::Trivial,
            End::Solved => sol.method = SolveMethod::Lemke,
            End::Failed(ending) => {
                let prim = self.prim;
                self.recover(m, q, &prim, ending);
            }
        }
        Ok(&self.sol)
    }

    /// Checks the options (the tolerance, the configured covering vector for size `n`)
    /// and writes the covering vector into `work.cover` (growing the buffers to `n`).
    #[cold]
    #[inline(never)]
    fn load_cover(&mut self, n: usize) -> Result<(), LcpInputError> {
        let rel_tol = self.options.rel_tol;
        if !(rel_tol > 0.0 && rel_tol < 1.0) {
            return Err(LcpInputError::Tolerance { value: rel_tol });
        }
        if let Some(d) = &self.options.covering {
            if d.len() != n {
                return Err(LcpInputError::CoveringLength { n, len: d.len() });
            }
            if let Some((index, &value)) = d
                .iter()
                .enumerate()
                .find(|(_, v)| !(v.is_finite() && **v > 0.0))
            {
                return Err(LcpInputError::CoveringNotPositive { index, value });
            }
        }
        if n > 0 {
            self.reserve(n);
            let cover = self.work.parts(n).cover;
            match &self.options.covering {
                Some(d) => cover.copy_from_slice(d),
                None => cover.fill(1.0),
            }
        }
        self.cover_n = n;
        Ok(())
    }

    /// Solves a parsed [`LcpProblem`] (see [`LemkeSolver::solve`]).
    pub fn solve_problem(&mut self, problem: &LcpProblem) -> Result<&LcpSolution, LcpInputError> {
        self.solve(problem.m.as_view(), problem.q.as_view())
    }

    fn max_pivots(&self, n: usize) -> usize {
        self.options.max_pivots.unwrap_or(50 * n + 100)
    }

    /// Everything after a primary run that did not certify: refinement of its final basis,
    /// then (if enabled) other covering vectors and enumeration. Publishes the result.
    #[cold]
    #[inline(never)]
    fn recover(&mut self, m: MatRef<'_>, q: &[f64], prim: &Primary, ending: Ending) {
        let n = q.len();
        let p = &ProblemRef {
            m,
            q,
            m_norm: prim.m_norm,
            q_norm: prim.q_norm,
            rel_tol: self.options.rel_tol,
        };
        let scales = &prim.scales;
        let pivots = prim.pivots;
        if let Some(cert) = self.refine(p, scales, ending) {
            self.commit(n, LcpStatus::Solved, SolveMethod::Lemke, cert, pivots);
            return;
        }
        // Unless a fallback succeeds, report the primary run's last iterate.
        let status = match ending {
            Ending::Ray => LcpStatus::RayTermination,
            Ending::PivotLimit => LcpStatus::PivotLimit,
            Ending::Complementary | Ending::Breakdown => LcpStatus::NumericalBreakdown,
        };
        self.extract(n, scales);
        let cert = p.certify(&self.zs[..n], &self.ws[..n], self.work.parts(n).mz);
        // An iterate that certifies (data within the tolerance of zero) is a solution: a
        // failure status never carries a certificate that holds.
        let status = if cert.holds() {
            LcpStatus::Solved
        } else {
            status
        };
        self.commit(n, status, SolveMethod::Lemke, cert, pivots);
        if !self.options.fallback || status == LcpStatus::Solved {
            return;
        }
        let mut pivots = pivots;
        let user = self.options.covering.is_some();
        // The alternates overwrite the configured covering vector.
        self.cover_n = usize::MAX;
        for attempt in 0..ALTERNATE_COVERINGS {
            alternate_covering(self.work.parts(n).cover, p.q, attempt, user);
            let (ending, more) = self.run(p, scales);
            pivots += more;
            self.sol.pivots = pivots;
            if ending == Ending::Complementary {
                self.extract(n, scales);
                let mut cert = p.certify(&self.zs[..n], &self.ws[..n], self.work.parts(n).mz);
                if !cert.holds() {
                    match self.refine(p, scales, ending) {
                        Some(c) => cert = c,
                        None => continue,
                    }
                }
                let method = SolveMethod::LemkeAlternateCovering;
                self.commit(n, LcpStatus::Solved, method, cert, pivots);
                return;
            }
        }
        if n <= self.options.enumeration_limit.min(ENUMERATION_CAP) {
            let mut scratch = BasisScratch {
                a: &mut self.lu[..n * n],
                b: &mut self.lu_rhs[..n],
                z_basic: &mut self.z_basic[..n],
            };
            let (zs, ws) = (&mut self.zs[..n], &mut self.ws[..n]);
            let mz = self.work.parts(n).mz;
            if let Some(cert) = enumerate::enumerate(p, &mut scratch, zs, ws, mz) {
                self.commit(n, LcpStatus::Solved, SolveMethod::Enumeration, cert, pivots);
            }
        }
    }

    /// A run ended on a complementary basis whose tableau values do not certify: solve
    /// that basis directly (LU on the original data) and certify again.
    fn refine(
        &mut self,
        p: &ProblemRef<'_>,
        scales: &Scales,
        ending: Ending,
    ) -> Option<Certificate> {
        if ending != Ending::Complementary {
            return None;
        }
        let n = p.q.len();
        self.extract(n, scales);
        self.z_basic[..n].fill(false);
        for &v in self.work.parts(n).basis.iter() {
            if (n..2 * n).contains(&v) {
                self.z_basic[v - n] = true;
            }
        }
        let mut scratch = BasisScratch {
            a: &mut self.lu[..n * n],
            b: &mut self.lu_rhs[..n],
            z_basic: &mut self.z_basic[..n],
        };
        if !enumerate::solve_basis(p, &mut scratch, &mut self.zs[..n], &mut self.ws[..n]) {
            return None;
        }
        let cert = p.certify(&self.zs[..n], &self.ws[..n], self.work.parts(n).mz);
        cert.holds().then_some(cert)
    }

    /// Another Lemke run (recovery only) with covering vector `work.cover`, with the
    /// scales of the primary run (the same data gives the same scales).
    fn run(&mut self, p: &ProblemRef<'_>, scales: &Scales) -> (Ending, usize) {
        let n = p.q.len();
        let max_pivots = self.max_pivots(n);
        let mut t = self.work.parts(n);
        let m_inv = tableau::load(n, &mut t, p.q, scales.q_inv, p.m_norm);
        tableau::pivot_loop(n, &mut t, p.m, m_inv, max_pivots)
    }

    /// Copies the basic values of the tableau into `zs`, `ws` (unscaled); zeros if any
    /// value is not finite.
    fn extract(&mut self, n: usize, scales: &Scales) {
        let (zs, ws) = (&mut self.zs[..n], &mut self.ws[..n]);
        if !tableau::extract(n, &self.work.parts(n), scales, zs, ws) {
            zs.fill(0.0);
            ws.fill(0.0);
        }
    }

    /// Publishes `zs`, `ws` and the rest into `self.sol` (no allocation: capacity was
    /// reserved).
    fn commit(
        &mut self,
        n: usize,
        status: LcpStatus,
        method: SolveMethod,
        certificate: Certificate,
        pivots: usize,
    ) {
        let (z, w) = (&self.zs[..n], &self.ws[..n]);
        self.sol.publish(z, w, status, method, certificate, pivots);
    }
}

/// Alternate covering vector number `attempt` (entries in `[1, n + 1]`): `1 + i`, `n − i`,
/// `1 + (7i mod n)`, `1 + n·|q_i|/‖q‖_∞`; all ones replaces the first if the primary
/// covering vector was user-given.
fn alternate_covering(d: &mut [f64], q: &[f64], attempt: usize, user: bool) {
    let n = d.len();
    let q_norm = q.iter().fold(0.0_f64, |a, &b| a.max(b.abs()));
    for (i, (di, &qi)) in d.iter_mut().zip(q).enumerate() {
        *di = match attempt {
            0 if user => 1.0,
            0 => 1.0 + i as f64,
            1 => (n - i) as f64,
            2 => 1.0 + ((7 * i) % n) as f64,
            _ => 1.0 + n as f64 * qi.abs() / q_norm,
        };
    }
}

/// One-shot convenience: `LemkeSolver::new(Default::default()).solve(..).cloned()`.
pub fn solve_lcp(m: &DMatrix<f64>, q: &DVector<f64>) -> Result<LcpSolution, LcpInputError> {
    LemkeSolver::default()
        .solve(m.as_view(), q.as_view())
        .cloned()
}
