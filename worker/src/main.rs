//! `moorfret-worker --db URL [--artifacts DIR] [--exit-when-idle]`: one worker process, as its
//! own binary for cluster schedulers (Slurm arrays, Kubernetes Jobs); the same loop as
//! `moorfret worker`.

use std::path::PathBuf;
use std::process::ExitCode;

use clap::Parser;
use moorfret_worker::{process, ProcessOptions, StoreConfig};

/// moorfret worker: claims sea-state jobs from a campaign store and runs them.
#[derive(Debug, Parser)]
#[command(name = "moorfret-worker", version, about, long_about = None)]
struct Cli {
    /// Store: an SQLite file path (or `sqlite://path`) or a `postgres://` URL.
    #[arg(long, default_value = "moorfret.sqlite", env = "MOORFRET_DB")]
    db: String,
    /// Artifact directory (default: `<db file>.artifacts` next to an SQLite store; required
    /// for PostgreSQL).
    #[arg(long)]
    artifacts: Option<PathBuf>,
    /// Lease length, ms (default 300 000); heartbeats come every tenth of it (at most 30 s).
    #[arg(long, hide = true)]
    lease_ms: Option<i64>,
    /// Exit once no campaign of the store has ready, running or blocked jobs.
    #[arg(long)]
    exit_when_idle: bool,
    /// Pause between claims when nothing is ready, ms.
    #[arg(long, default_value_t = 500)]
    poll_ms: u64,
    /// Wall time this worker may run, s (batch allocations): it never starts a job expected
    /// to take longer than what remains.
    #[arg(long)]
    wall_time_s: Option<f64>,
    /// Part of `--wall-time-s` kept for storing the last job's results, s.
    #[arg(long, default_value_t = 30.0)]
    wall_time_reserve_s: f64,
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
    let options = ProcessOptions {
        store: StoreConfig {
            db: cli.db,
            artifacts: cli.artifacts,
            lease_ms: cli.lease_ms,
        },
        exit_when_idle: cli.exit_when_idle,
        poll_ms: cli.poll_ms,
        wall_time_s: cli.wall_time_s,
        wall_time_reserve_s: cli.wall_time_reserve_s,
    };
    match process::run(options) {
        Ok(()) => ExitCode::SUCCESS,
        Err(err) => {
            eprintln!("error: {err:#}");
            ExitCode::from(1)
        }
    }
}
