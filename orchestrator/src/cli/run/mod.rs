//! `moorfret run …`: single-stage runs for one case.

use clap::Subcommand;

pub(crate) mod catenary;
pub(crate) mod global;
pub(crate) mod strand;
pub(crate) mod strand_history;
pub(crate) mod strand_model;
pub(crate) mod strand_reduced;

/// Single-stage runs.
#[derive(Debug, Subcommand)]
pub(crate) enum RunCommand {
    /// Elastic catenary of one homogeneous line with seabed contact and friction.
    Catenary(catenary::CatenaryArgs),
    /// Coupled floater + mooring lines in one irregular sea state: writes hot-spot T(t), κ(t),
    /// fairlead tensions, envelopes, floater motions, a summary and plots.
    Global(global::GlobalArgs),
    /// Detailed strand FE model: tension, then each curvature of the profile's loading; with
    /// `--load LOAD.csv`, a tension (or strain) and curvature history instead.
    Strand(Box<strand::StrandArgs>),
}

/// Execute a `run` subcommand.
pub(crate) fn execute(cmd: RunCommand) -> anyhow::Result<()> {
    match cmd {
        RunCommand::Catenary(args) => catenary::execute(args),
        RunCommand::Global(args) => global::execute(&args),
        RunCommand::Strand(args) => strand::execute(*args),
    }
}
