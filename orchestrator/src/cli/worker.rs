//! `moorfret worker --db URL [--artifacts DIR] [--exit-when-idle]` (also the `moorfret-worker`
//! binary): one worker process serving every campaign of a store until SIGTERM/SIGINT, which
//! releases the running job's lease without consuming an attempt.

use std::path::PathBuf;

use clap::Args;
use moorfret_worker::{process, ProcessOptions, StoreConfig};

/// Store location and queue timing shared by the campaign and worker commands.
#[derive(Debug, Clone, Args)]
pub(crate) struct StoreArgs {
    /// Store: an SQLite file path (or `sqlite://path`) or a `postgres://` URL.
    #[arg(long, default_value = "moorfret.sqlite", env = "MOORFRET_DB")]
    pub(crate) db: String,
    /// Artifact directory (default: `<db file>.artifacts` next to an SQLite store; required
    /// for PostgreSQL).
    #[arg(long)]
    pub(crate) artifacts: Option<PathBuf>,
    /// Lease length, ms (default 300 000); heartbeats come every tenth of it (at most 30 s).
    #[arg(long, hide = true)]
    pub(crate) lease_ms: Option<i64>,
}

impl StoreArgs {
    /// The store these arguments name.
    pub(crate) fn config(&self) -> StoreConfig {
        StoreConfig {
            db: self.db.clone(),
            artifacts: self.artifacts.clone(),
            lease_ms: self.lease_ms,
        }
    }
}

/// Arguments of `worker`.
#[derive(Debug, Args)]
pub(crate) struct WorkerArgs {
    /// Store and artifacts.
    #[command(flatten)]
    store: StoreArgs,
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

/// Runs the command: a worker until a signal (or idle, with `--exit-when-idle`).
pub(crate) fn execute(args: WorkerArgs) -> anyhow::Result<()> {
    process::run(ProcessOptions {
        store: args.store.config(),
        exit_when_idle: args.exit_when_idle,
        poll_ms: args.poll_ms,
        wall_time_s: args.wall_time_s,
        wall_time_reserve_s: args.wall_time_reserve_s,
    })
}
