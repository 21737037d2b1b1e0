//! One module per `hopsim` subcommand.

pub mod analyze;
pub mod compare;
pub mod exit;
pub mod import;
pub mod interrupt;
pub mod lcp;
pub mod optimize;
pub mod progress;
pub mod render;
pub mod run;
pub mod scene;
pub mod sweep;

/// Clap value parser: a finite number (`nan`, `inf` refused with exit code 2).
pub fn finite(text: &str) -> Result<f64, String> {
    match text.trim().parse::<f64>() {
        Ok(v) if v.is_finite() => Ok(v),
        Ok(v) => Err(format!("expected a finite number, got {v}")),
        Err(_) => Err(format!("expected a number, got `{text}`")),
    }
}

/// Clap value parser: a finite number ≥ 0 (tolerances).
pub fn non_negative(text: &str) -> Result<f64, String> {
    finite(text).and_then(|v| {
        if v >= 0.0 {
            Ok(v)
        } else {
            Err(format!("expected a number ≥ 0, got {v}"))
        }
    })
}
