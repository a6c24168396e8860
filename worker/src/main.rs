//! `moorfret-worker --db URL [--artifacts DIR] [--exit-when-idle]`: one worker process, as its
//! own binary for cluster schedulers (Slurm arrays, Kubernetes Jobs); the same loop as
//! `moorfret worker`.

use std::process::ExitCode;

use clap::Parser;
use moorfret_worker::args::WorkerArgs;
use moorfret_worker::process;

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
    let cli = Cli::parse();
    match process::run(cli.args.options()) {
        Ok(()) => ExitCode::SUCCESS,
        Err(err) => {
            eprintln!("error: {}", moorfret_worker::failure::error_text(&err));
            ExitCode::from(1)
        }
    }
}
