//! The command-line arguments of a worker process, shared by `moorfret worker` and the
//! `moorfret-worker` binary (and, for the store, by the `moorfret campaign` commands), so the
//! two spellings of a worker cannot drift apart.

use std::path::PathBuf;

use clap::Args;
use moorfret_store::JobKind;

use crate::process::{ProcessOptions, StoreConfig};

/// Store location and queue timing.
#[derive(Debug, Clone, Args)]
pub struct StoreArgs {
    /// Store: an SQLite file path (or `sqlite://path`) or a `postgres://` URL.
    #[arg(long, default_value = "moorfret.sqlite", env = "MOORFRET_DB")]
    pub db: String,
    /// Artifact directory (default: `<db file>.artifacts` next to an SQLite store; required
    /// for PostgreSQL).
    #[arg(long)]
    pub artifacts: Option<PathBuf>,
    /// Lease length, ms (default 300 000); heartbeats come every tenth of it (at most 30 s).
    #[arg(long, hide = true, allow_negative_numbers = true, value_parser = positive_ms)]
    pub lease_ms: Option<i64>,
}

impl StoreArgs {
    /// The store these arguments name.
    pub fn config(&self) -> StoreConfig {
        StoreConfig {
            db: self.db.clone(),
            artifacts: self.artifacts.clone(),
            lease_ms: self.lease_ms,
        }
    }
}

/// Arguments of a worker process.
#[derive(Debug, Args)]
pub struct WorkerArgs {
    /// Store and artifacts.
    #[command(flatten)]
    pub store: StoreArgs,
    /// Exit once no campaign of the store has ready, running or blocked jobs (of the kinds
    /// this worker takes).
    #[arg(long)]
    pub exit_when_idle: bool,
    /// Pause between claims when nothing is ready, ms.
    #[arg(long, default_value_t = 500, allow_negative_numbers = true, value_parser = poll_ms)]
    pub poll_ms: u64,
    /// Wall time this worker may run, s (batch allocations): it never starts a job expected
    /// to take longer than what remains.
    #[arg(long, allow_negative_numbers = true)]
    pub wall_time_s: Option<f64>,
    /// Part of `--wall-time-s` kept for storing the last job's results, s.
    #[arg(long, allow_negative_numbers = true, default_value_t = 30.0)]
    pub wall_time_reserve_s: f64,
    /// Take only jobs of this kind (`global`, `strand`, `calibrate` or `strand_reduced`;
    /// repeatable; all kinds by default), e.g. global jobs on small nodes and FE strand jobs on
    /// large ones.
    #[arg(long = "kind", value_name = "KIND", value_parser = parse_kind)]
    pub kinds: Vec<JobKind>,
}

/// A lease length: a whole number of milliseconds above 0 (negative numbers are read as values,
/// so that they are refused by the option's name, not as unknown options).
fn positive_ms(text: &str) -> Result<i64, String> {
    match text.trim().parse::<i64>() {
        Ok(n) if n > 0 => Ok(n),
        Ok(n) => Err(format!("{n} ms: must be above 0")),
        Err(_) => Err(format!("{text}: must be a whole number of milliseconds")),
    }
}

/// A pause between claims: a whole number of milliseconds, 0 or more.
fn poll_ms(text: &str) -> Result<u64, String> {
    match text.trim().parse::<i64>() {
        Ok(n) if n >= 0 => u64::try_from(n).map_err(|e| e.to_string()),
        Ok(n) => Err(format!("{n} ms: must not be negative")),
        Err(_) => Err(format!("{text}: must be a whole number of milliseconds")),
    }
}

fn parse_kind(text: &str) -> Result<JobKind, String> {
    text.parse::<JobKind>().map_err(|e| e.to_string())
}

impl WorkerArgs {
    /// The process options of these arguments.
    pub fn options(&self) -> ProcessOptions {
        ProcessOptions {
            store: self.store.config(),
            exit_when_idle: self.exit_when_idle,
            poll_ms: self.poll_ms,
            wall_time_s: self.wall_time_s,
            wall_time_reserve_s: self.wall_time_reserve_s,
            kinds: self.kinds.clone(),
        }
    }
}
