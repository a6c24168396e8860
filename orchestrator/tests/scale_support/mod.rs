//! Shared pieces of the scale-out tests: the PostgreSQL server under test, throw-away stores
//! on both backends, a worker loop on the store API that many tasks run at once, and (`slurm`)
//! a one-node Slurm cluster for the batch script.
//!
//! PostgreSQL comes from `MOORFRET_TEST_POSTGRES_URL` (default
//! `postgres://postgres@127.0.0.1:5432/test`); without a server the tests print that they are
//! skipped and pass.

#![allow(dead_code, unreachable_pub)]

use std::time::Duration;

use moorfret_store::{
    CampaignId, Clock, JobKind, JobResults, NewCampaign, PlannedJob, QueuePolicy, Store,
    StoreOptions, TestPayload, WorkerInfo,
};
use serde_json::json;

/// Which database a test store lives in.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Backend {
    Sqlite,
    Postgres,
}

/// The PostgreSQL server the tests use.
pub fn postgres_url() -> String {
    std::env::var("MOORFRET_TEST_POSTGRES_URL")
        .unwrap_or_else(|_| "postgres://postgres@127.0.0.1:5432/test".into())
}

/// Whether a server answers at `url`; prints why a test is skipped when not.
pub async fn postgres_reachable(url: &str) -> bool {
    use sqlx::Connection;
    let attempt = tokio::time::timeout(Duration::from_secs(3), sqlx::PgConnection::connect(url));
    match attempt.await {
        Ok(Ok(conn)) => {
            let _ = conn.close().await;
            true
        }
        Ok(Err(err)) => {
            skip_postgres(&format!("no server at {url}: {err}"));
            false
        }
        Err(_) => {
            skip_postgres(&format!("connecting to {url} timed out"));
            false
        }
    }
}

/// A throw-away store: an SQLite file in a temporary directory, or a schema of its own on the
/// PostgreSQL server (dropped by [`ScaleStore::finish`]).
pub struct ScaleStore {
    pub store: Store,
    pub location: String,
    pub options: StoreOptions,
    _dir: tempfile::TempDir,
}

impl ScaleStore {
    /// Opens a fresh store with `clock` and `policy`, or `None` when the backend is unavailable.
    pub async fn open(backend: Backend, clock: Clock, policy: QueuePolicy) -> Option<Self> {
        let dir = tempfile::tempdir().expect("temporary directory");
        let mut options = StoreOptions {
            clock,
            policy,
            max_connections: 4,
            postgres_schema: None,
        };
        let location = match backend {
            Backend::Sqlite => dir
                .path()
                .join("campaign.sqlite")
                .to_string_lossy()
                .into_owned(),
            Backend::Postgres => {
                let url = postgres_url();
                if !postgres_reachable(&url).await {
                    return None;
                }
                options.postgres_schema = Some(format!("t_{}", uuid::Uuid::new_v4().simple()));
                url
            }
        };
        let store = Store::open(&location, options.clone())
            .await
            .expect("open store");
        Some(Self {
            store,
            location,
            options,
            _dir: dir,
        })
    }

    /// Another handle with a pool of its own, as another worker process would have.
    pub async fn another_handle(&self, max_connections: u32) -> Store {
        let options = StoreOptions {
            max_connections,
            ..self.options.clone()
        };
        Store::open(&self.location, options)
            .await
            .expect("open another handle")
    }

    /// Drops the PostgreSQL schema and closes the pool.
    pub async fn finish(self) {
        self.store
            .drop_postgres_schema()
            .await
            .expect("drop test schema");
    }
}

/// Identity of the `n`-th simulated worker process.
pub fn worker_info(n: i64) -> WorkerInfo {
    WorkerInfo {
        host: format!("node{n}"),
        pid: 10_000 + n,
        version: "test".into(),
    }
}

/// Creates a campaign named `name`.
pub async fn campaign(store: &Store, name: &str) -> CampaignId {
    store
        .create_campaign(&NewCampaign {
            name: name.into(),
            spec: json!({ "name": name }),
            spec_sha256: "0".repeat(64),
        })
        .await
        .expect("create campaign")
}

/// A job of the test-only kind.
pub fn test_job(payload: TestPayload) -> PlannedJob {
    PlannedJob::new(
        JobKind::Test,
        serde_json::to_value(payload).expect("test payload"),
    )
}

/// A job-level result naming the worker that produced it.
pub fn result_by(worker: i64) -> JobResults {
    JobResults {
        result: json!({ "by": worker }),
        ..JobResults::default()
    }
}

/// Polls `check` every 100 ms until it holds; panics naming `what` after `limit`.
pub async fn wait_until<F, Fut>(limit: Duration, what: &str, mut check: F)
where
    F: FnMut() -> Fut,
    Fut: std::future::Future<Output = bool>,
{
    let start = std::time::Instant::now();
    while !check().await {
        assert!(start.elapsed() < limit, "timed out waiting until {what}");
        tokio::time::sleep(Duration::from_millis(100)).await;
    }
}

pub mod netns;
pub mod pg_database;
pub mod process_worker;
pub mod slurm;

/// Says why the PostgreSQL half of a test is skipped; fails instead where the environment
/// requires the services (`MOORFRET_REQUIRE_SERVICES`, set by `.ci/run`).
fn skip_postgres(reason: &str) {
    skip_unless_required("PostgreSQL", reason);
}

/// Says, past the test harness's capture, why the part of a test that needs `service` is
/// skipped; panics instead where the environment requires the services
/// (`MOORFRET_REQUIRE_SERVICES`, set by `.ci/run`), so that CI cannot pass by skipping.
pub fn skip_unless_required(service: &str, reason: &str) {
    if std::env::var_os("MOORFRET_REQUIRE_SERVICES").is_some() {
        panic!("{service} is required here (MOORFRET_REQUIRE_SERVICES is set): {reason}");
    }
    use std::io::Write;
    let _ = writeln!(std::io::stderr(), "SKIPPED ({service}): {reason}");
}
