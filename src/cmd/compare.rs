//! `hopsim compare A B`: compares two recordings' contact-impulse traces and states.

use clap::Args;
use std::path::PathBuf;
use std::process::ExitCode;

/// Compare the contact impulses (and states) of two recordings; exit non-zero where they
/// differ beyond tolerance, naming the first time and contact that differs.
#[derive(Args)]
pub struct CompareArgs {
    /// The reference recording (.mcap) or impulse trace (.csv).
    pub reference: PathBuf,
    /// The recording to check against it.
    pub other: PathBuf,
}

pub fn run(_args: CompareArgs) -> anyhow::Result<ExitCode> {
    anyhow::bail!("hopsim compare is not implemented yet")
}
