//! `moorfret run …`: single-stage runs for one case.

use clap::Subcommand;

pub mod catenary;

/// Single-stage runs.
#[derive(Debug, Subcommand)]
pub enum RunCommand {
    /// Elastic catenary of one homogeneous line with seabed contact and friction.
    Catenary(catenary::CatenaryArgs),
}

/// Execute a `run` subcommand.
pub fn execute(cmd: RunCommand) -> anyhow::Result<()> {
    match cmd {
        RunCommand::Catenary(args) => catenary::execute(args),
    }
}
