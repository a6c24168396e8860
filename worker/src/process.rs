//! A worker process (`moorfret worker`, `moorfret-worker`): open the store and the artifact
//! directory, run the claim loop of [`crate::serve`] until SIGTERM, SIGINT, SIGHUP or idleness, and
//! release the running job's lease on the way out without consuming an attempt.
//!
//! The binaries parse their command lines into [`ProcessOptions`]; everything after that lives
//! here, so both behave alike.

use std::path::PathBuf;
use std::time::Duration;

use anyhow::Context;
use tokio::sync::watch;

use moorfret_store::{
    ArtifactStore, Clock, JobKind, QueuePolicy, Store, StoreLocation, StoreOptions, WallTimeBudget,
};

use crate::serve::{self, WorkerConfig};

/// Where a campaign store and its artifacts are, and the queue timing to use on it.
#[derive(Debug, Clone)]
pub struct StoreConfig {
    /// Store: an SQLite file path (or `sqlite://path`) or a `postgres://` URL.
    pub db: String,
    /// Artifact directory (default: `<db file>.artifacts` next to an SQLite store; required
    /// for PostgreSQL).
    pub artifacts: Option<PathBuf>,
    /// Lease length, ms (default 300 000); heartbeats come every tenth of it (at most 30 s).
    pub lease_ms: Option<i64>,
}

impl StoreConfig {
    /// Queue policy with the lease override applied.
    pub fn policy(&self) -> QueuePolicy {
        let mut policy = QueuePolicy::default();
        if let Some(lease) = self.lease_ms {
            policy.lease_ms = lease;
            policy.heartbeat_interval_ms = (lease / 10).clamp(1, policy.heartbeat_interval_ms);
        }
        policy
    }

    /// Store options for this location. A PostgreSQL store takes lease times from the
    /// server's clock, so workers on hosts with skewed clocks agree on when a lease has
    /// expired.
    fn store_options(&self) -> anyhow::Result<StoreOptions> {
        let clock = match StoreLocation::parse(&self.db)? {
            StoreLocation::Postgres(_) => Clock::Database,
            StoreLocation::Sqlite(_) => Clock::System,
        };
        Ok(StoreOptions {
            clock,
            policy: self.policy(),
            ..StoreOptions::default()
        })
    }

    /// Opens the moorfret store, or creates one where nothing is (`campaign launch` only).
    pub async fn open(&self) -> anyhow::Result<Store> {
        Store::open(&self.db, self.store_options()?)
            .await
            .with_context(|| format!("opening the store {}", self.db))
    }

    /// Opens the moorfret store; refuses anything else (no file, another program's
    /// database, an empty file) without creating or writing anything (every command but
    /// `campaign launch`).
    pub async fn open_existing(&self) -> anyhow::Result<Store> {
        Store::open_existing(&self.db, self.store_options()?)
            .await
            .with_context(|| format!("opening the store {}", self.db))
    }

    /// The moorfret store if there is one, `None` where nothing is; anything else is refused
    /// untouched.
    pub async fn open_if_present(&self) -> anyhow::Result<Option<Store>> {
        Store::open_if_present(&self.db, self.store_options()?)
            .await
            .with_context(|| format!("opening the store {}", self.db))
    }

    /// Where the artifact directory of this store is: `--artifacts`, or beside an SQLite
    /// store file; `None` for a PostgreSQL store without `--artifacts`.
    fn artifact_dir(&self) -> anyhow::Result<Option<PathBuf>> {
        Ok(match (&self.artifacts, StoreLocation::parse(&self.db)?) {
            (Some(dir), _) => Some(dir.clone()),
            (None, StoreLocation::Sqlite(path)) => Some(ArtifactStore::path_beside_database(&path)),
            (None, StoreLocation::Postgres(_)) => None,
        })
    }

    /// The artifact store of this store.
    pub fn artifact_store(&self) -> anyhow::Result<ArtifactStore> {
        let Some(dir) = self.artifact_dir()? else {
            anyhow::bail!("--artifacts DIR is required with a PostgreSQL store (a directory every worker shares)")
        };
        ArtifactStore::open(&dir)
            .with_context(|| format!("opening the artifact directory {}", dir.display()))
    }

    /// Checks, without creating anything or opening the store, that what already stands where
    /// the artifact directory goes can take files (see [`ArtifactStore::check_existing`]).
    pub fn check_existing_artifacts(&self) -> anyhow::Result<()> {
        let Some(dir) = self.artifact_dir()? else {
            return Ok(());
        };
        ArtifactStore::check_existing(&dir)
            .with_context(|| format!("the artifact directory {} cannot take files", dir.display()))
    }

    /// Arguments that hand the same store to a child process.
    pub fn child_args(&self) -> Vec<String> {
        let mut args = vec!["--db".to_owned(), self.db.clone()];
        if let Some(dir) = &self.artifacts {
            args.push("--artifacts".into());
            args.push(dir.to_string_lossy().into_owned());
        }
        if let Some(lease) = self.lease_ms {
            args.push("--lease-ms".into());
            args.push(lease.to_string());
        }
        args
    }
}

/// Settings of a worker process.
#[derive(Debug, Clone)]
pub struct ProcessOptions {
    /// Store and artifacts.
    pub store: StoreConfig,
    /// Exit once no campaign of the store has ready, running or blocked jobs.
    pub exit_when_idle: bool,
    /// Pause between claims when nothing is ready, ms.
    pub poll_ms: u64,
    /// Wall time this worker may run, s (batch allocations): it never starts a job expected
    /// to take longer than what remains.
    pub wall_time_s: Option<f64>,
    /// Part of `wall_time_s` kept for storing the last job's results, s.
    pub wall_time_reserve_s: f64,
    /// Job kinds this worker takes (all if empty).
    pub kinds: Vec<JobKind>,
}

/// Runs a worker until a signal (or idle, with `exit_when_idle`).
pub fn run(options: ProcessOptions) -> anyhow::Result<()> {
    let wall_time = options
        .wall_time_s
        .map(|s| WallTimeBudget::new(s, options.wall_time_reserve_s, std::time::Instant::now()))
        .transpose()
        .context("--wall-time-s / --wall-time-reserve-s")?;
    let runtime = tokio::runtime::Builder::new_multi_thread()
        .worker_threads(2)
        .enable_all()
        .build()
        .context("starting the async runtime")?;
    let summary = runtime.block_on(async {
        let store = options.store.open_existing().await?;
        let artifacts = options.store.artifact_store()?;
        let (tx, rx) = watch::channel(false);
        tokio::spawn(async move {
            wait_for_signal().await;
            tracing::info!("stop signal received");
            let _ = tx.send(true);
        });
        let config = WorkerConfig {
            exit_when_idle: options.exit_when_idle,
            idle_poll: Duration::from_millis(options.poll_ms),
            wall_time,
            kinds: options.kinds.clone(),
            ..WorkerConfig::default()
        };
        let summary = serve::run(store.clone(), artifacts, config, rx).await;
        store.close().await;
        summary.context("worker loop")
    })?;
    tracing::info!(
        completed = summary.completed,
        cached = summary.cached,
        failed = summary.failed,
        lost = summary.lost,
        "worker stopped"
    );
    // A stage still running on a blocking thread is abandoned: its lease is already released.
    runtime.shutdown_timeout(Duration::from_millis(100));
    Ok(())
}

/// Resolves on SIGTERM, SIGINT or SIGHUP (a closed terminal ends a worker as `kill` does:
/// its lease goes back at once).
async fn wait_for_signal() {
    use tokio::signal::unix::{signal, SignalKind};
    match (
        signal(SignalKind::terminate()),
        signal(SignalKind::interrupt()),
        signal(SignalKind::hangup()),
    ) {
        (Ok(mut term), Ok(mut int), Ok(mut hup)) => {
            tokio::select! {
                _ = term.recv() => {}
                _ = int.recv() => {}
                _ = hup.recv() => {}
            }
        }
        _ => {
            let _ = tokio::signal::ctrl_c().await;
        }
    }
}
