//! `hopsim lcp solve FILE...`

use clap::{Args, Subcommand};
use std::process::ExitCode;

#[derive(Args)]
pub struct LcpArgs {
    #[command(subcommand)]
    pub command: LcpCommand,
}

#[derive(Subcommand)]
pub enum LcpCommand {
    /// Solve LCPs stored in dense Siconos `.dat` files.
    Solve {
        /// The `.dat` files to solve.
        #[arg(required = true)]
        files: Vec<std::path::PathBuf>,
    },
}

pub fn run(_args: LcpArgs) -> anyhow::Result<ExitCode> {
    anyhow::bail!("not implemented yet")
}
