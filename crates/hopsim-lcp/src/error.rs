//! Input errors of the solver: returned, never panicked on.

/// Why an LCP `(M, q)` (or the solver options) cannot be solved at all.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum LcpInputError {
    /// `M` must be square.
    #[error("M is not square: {rows} rows, {cols} columns")]
    NotSquare { rows: usize, cols: usize },
    /// `q` must have as many entries as `M` has rows.
    #[error("q has {q_len} entries but M is {n}×{n}")]
    SizeMismatch { n: usize, q_len: usize },
    /// An entry of `M` (row-major index) or `q` is NaN or infinite.
    #[error("{what} entry {index} is not finite (row-major index for M)")]
    NonFinite { what: &'static str, index: usize },
    /// The covering vector of [`crate::LemkeOptions`] has the wrong length.
    #[error("covering vector has {len} entries but the problem has size {n}")]
    CoveringLength { n: usize, len: usize },
    /// Every covering-vector entry must be finite and strictly positive.
    #[error("covering vector entry {index} is {value}; it must be finite and > 0")]
    CoveringNotPositive { index: usize, value: f64 },
    /// The certificate's relative tolerance must be in `(0, 1)`: from 1 up, `z = 0` would
    /// certify for every `q`.
    #[error("relative tolerance {value} must be > 0 and < 1")]
    Tolerance { value: f64 },
}
