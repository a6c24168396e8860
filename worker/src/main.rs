//! `moorfret-worker --db URL [--artifacts DIR] [--exit-when-idle]`: the worker loop of
//! `moorfret worker`, as its own binary for clusters (Slurm arrays, Kubernetes Jobs).

use clap::Parser;
use moorfret_orchestrator::cli::worker::{execute, WorkerArgs};
use std::process::ExitCode;

/// moorfret worker: claims sea-state jobs from a campaign store and runs them.
#[derive(Debug, Parser)]
#[command(name = "moorfret-worker", version, about, long_about = None)]
struct Cli {
    #[command(flatten)]
    args: WorkerArgs,
}

fn main() -> ExitCode {
    tracing_subscriber::fmt()
        .with_writer(std::io::stderr)
        .with_ansi(std::io::IsTerminal::is_terminal(&std::io::stderr()))
        .with_env_filter(
            tracing_subscriber::EnvFilter::try_from_default_env()
                .unwrap_or_else(|_| tracing_subscriber::EnvFilter::new("info")),
        )
        .init();
    match execute(Cli::parse().args) {
        Ok(()) => ExitCode::SUCCESS,
        Err(err) => {
            eprintln!("error: {err:#}");
            ExitCode::from(1)
        }
    }
}
