//! `moorfret run …`: single-stage runs for one case.

use clap::Subcommand;

/// Single-stage runs.
#[derive(Debug, Subcommand)]
pub enum RunCommand {}

/// Execute a `run` subcommand.
pub fn execute(cmd: RunCommand) -> anyhow::Result<()> {
    match cmd {}
}
