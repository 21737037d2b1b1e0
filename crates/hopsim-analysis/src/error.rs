//! Errors of the analyses: invalid parameters, singular impact problems.

/// Everything that can go wrong in `hopsim-analysis`. Libraries never panic on user input:
/// bad parameters come back as [`AnalysisError::InvalidParameter`].
#[derive(Debug, thiserror::Error)]
pub enum AnalysisError {
    /// A parameter is out of its physical range (e.g. a negative mass).
    #[error("invalid parameter `{name}` = {value}: {reason}")]
    InvalidParameter {
        /// The parameter's name as the CLI spells it.
        name: String,
        /// The offending value, formatted.
        value: String,
        /// What the parameter must satisfy.
        reason: String,
    },
    /// A matrix that must be symmetric positive definite is not: a mass matrix with a
    /// non-positive entry, or a contact Jacobian without full row rank (`J M⁻¹ Jᵀ` singular).
    #[error("{what} is not positive definite")]
    NotPositiveDefinite {
        /// Which matrix.
        what: &'static str,
    },
    /// Matrix or vector dimensions do not fit together.
    #[error("dimension mismatch: {0}")]
    Dimension(String),
}

/// Result alias of this crate.
pub type Result<T> = std::result::Result<T, AnalysisError>;

impl AnalysisError {
    /// Shorthand for an [`AnalysisError::InvalidParameter`].
    pub fn invalid(name: &str, value: f64, reason: &str) -> Self {
        AnalysisError::InvalidParameter {
            name: name.to_string(),
            value: format!("{value}"),
            reason: reason.to_string(),
        }
    }
}

/// Checks that `value` is finite and strictly positive.
pub fn require_positive(name: &str, value: f64) -> Result<()> {
    if value.is_finite() && value > 0.0 {
        Ok(())
    } else {
        Err(AnalysisError::invalid(
            name,
            value,
            "must be a finite number > 0",
        ))
    }
}

/// Checks that `value` is finite.
pub fn require_finite(name: &str, value: f64) -> Result<()> {
    if value.is_finite() {
        Ok(())
    } else {
        Err(AnalysisError::invalid(
            name,
            value,
            "must be a finite number",
        ))
    }
}
