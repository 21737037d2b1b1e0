//! Errors of the analyses: invalid parameters, singular impact problems.

/// Everything that can go wrong in `hopsim-theory`. Libraries never panic on user input:
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
            value: short_number(value),
            reason: reason.to_string(),
        }
    }
}

/// `value` in its shortest exact form (`3`, `0.25`, `1e308`; never 300 digits).
fn short_number(value: f64) -> String {
    if value.fract() == 0.0 && value.abs() < 1e16 {
        format!("{}", value as i64)
    } else {
        format!("{value:?}")
    }
}

/// The largest magnitude a parameter may have (as in scene files): beyond it the models'
/// figures overflow to `inf` or `NaN`.
pub const MAX_MAGNITUDE: f64 = 1e9;

/// Checks that `value` is finite, strictly positive and at most [`MAX_MAGNITUDE`].
pub fn require_positive(name: &str, value: f64) -> Result<()> {
    if value > 0.0 && value <= MAX_MAGNITUDE {
        Ok(())
    } else {
        Err(AnalysisError::invalid(
            name,
            value,
            "must be a finite number > 0 of magnitude at most 1e9",
        ))
    }
}

/// Checks that `value` is finite with magnitude at most [`MAX_MAGNITUDE`].
pub fn require_finite(name: &str, value: f64) -> Result<()> {
    if value.abs() <= MAX_MAGNITUDE {
        Ok(())
    } else {
        Err(AnalysisError::invalid(
            name,
            value,
            "must be a finite number of magnitude at most 1e9",
        ))
    }
}
