//! `hopsim analyze fixed-points`: Robbit's periodic gaits and their stability (physics.md §5.3).

use clap::Args;

use super::common::OutputArgs;

/// Fixed-point controls β* = (T*, ζ0*) of Robbit's return map over a grid of take-off
/// angle × take-off energy, with the eigenvalues of the return-map Jacobian.
#[derive(Args)]
pub struct FixedPointsArgs {
    #[command(flatten)]
    pub output: OutputArgs,
}

pub fn run(_args: FixedPointsArgs) -> anyhow::Result<()> {
    anyhow::bail!("hopsim analyze fixed-points is not implemented yet")
}
