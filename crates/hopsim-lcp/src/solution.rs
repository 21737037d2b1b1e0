//! What a solve returns: status, iterate, pivot count, certificate, method.

use crate::Certificate;
use nalgebra::DVector;

/// Outcome of a solve. Only [`LcpStatus::Solved`] claims a solution, and only when its
/// [`Certificate`] holds.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum LcpStatus {
    /// `z`, `w` satisfy the LCP within the certificate's tolerance.
    Solved,
    /// Lemke's method left along an unbounded ray (the LCP may have no solution), and the
    /// fallbacks, if enabled, found none either.
    RayTermination,
    /// The pivot limit was reached.
    PivotLimit,
    /// Lemke's method ended but its result does not certify (round-off), or the tableau
    /// became non-finite.
    NumericalBreakdown,
}

impl LcpStatus {
    /// `"solved"`, `"ray_termination"`, `"pivot_limit"` or `"numerical_breakdown"`.
    pub fn as_str(self) -> &'static str {
        match self {
            LcpStatus::Solved => "solved",
            LcpStatus::RayTermination => "ray_termination",
            LcpStatus::PivotLimit => "pivot_limit",
            LcpStatus::NumericalBreakdown => "numerical_breakdown",
        }
    }
}

impl std::fmt::Display for LcpStatus {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(self.as_str())
    }
}

/// Which method produced the reported `z`, `w`.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum SolveMethod {
    /// `q ≥ 0`: `z = 0`, `w = q`, no pivots.
    Trivial,
    /// Lemke's method with the configured covering vector.
    Lemke,
    /// Lemke's method with the alternate covering vector (fallback).
    LemkeAlternateCovering,
    /// Exhaustive enumeration of complementary bases (fallback, small `n` only).
    Enumeration,
    /// The complementary basis of an earlier answer, solved directly and certified
    /// ([`crate::LemkeSolver::solve_warm`]); no pivots.
    WarmStart,
}

impl SolveMethod {
    /// `"trivial"`, `"lemke"`, `"lemke_alternate_covering"`, `"enumeration"` or
    /// `"warm_start"`.
    pub fn as_str(self) -> &'static str {
        match self {
            SolveMethod::Trivial => "trivial",
            SolveMethod::Lemke => "lemke",
            SolveMethod::LemkeAlternateCovering => "lemke_alternate_covering",
            SolveMethod::Enumeration => "enumeration",
            SolveMethod::WarmStart => "warm_start",
        }
    }
}

impl std::fmt::Display for SolveMethod {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(self.as_str())
    }
}

/// Result of one solve of `w = M z + q, z ≥ 0, w ≥ 0, zᵀw = 0`.
///
/// On a failure status `z`, `w` hold the last Lemke iterate (zeros if it was not finite);
/// its certificate then does not hold.
#[derive(Debug, Clone, PartialEq)]
pub struct LcpSolution {
    pub status: LcpStatus,
    pub z: DVector<f64>,
    pub w: DVector<f64>,
    /// Pivots of all Lemke runs of this solve (primary plus alternate covering).
    pub pivots: usize,
    pub certificate: Certificate,
    pub method: SolveMethod,
}

impl LcpSolution {
    pub(crate) fn empty() -> Self {
        LcpSolution {
            status: LcpStatus::Solved,
            z: DVector::zeros(0),
            w: DVector::zeros(0),
            pivots: 0,
            certificate: Certificate::default(),
            method: SolveMethod::Trivial,
        }
    }

    /// Publishes `z`, `w` (equal lengths) and the rest; allocates nothing when the vectors'
    /// capacity holds them.
    #[inline(always)]
    pub(crate) fn publish(
        &mut self,
        z: &[f64],
        w: &[f64],
        status: LcpStatus,
        method: SolveMethod,
        certificate: Certificate,
        pivots: usize,
    ) {
        let n = z.len();
        set_len(&mut self.z, n);
        set_len(&mut self.w, n);
        self.z.as_mut_slice().copy_from_slice(z);
        self.w.as_mut_slice().copy_from_slice(&w[..n]);
        self.status = status;
        self.method = method;
        self.certificate = certificate;
        self.pivots = pivots;
    }
}

/// Resizes `v` to `n` entries without allocating when its capacity suffices.
#[inline]
pub(crate) fn set_len(v: &mut DVector<f64>, n: usize) {
    if v.len() != n {
        resize(v, n);
    }
}

#[cold]
#[inline(never)]
fn resize(v: &mut DVector<f64>, n: usize) {
    let mut data: Vec<f64> = std::mem::replace(v, DVector::zeros(0)).data.into();
    data.resize(n, 0.0);
    *v = DVector::from_vec(data);
}
