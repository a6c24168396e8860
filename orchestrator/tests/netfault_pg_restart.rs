//! Database fault: PostgreSQL restarts in the middle of a campaign.
//!
//! Four worker processes drain 80 test jobs (200 ms sleeps, 2 s leases). Once a fifth of them
//! is done, the test locks the jobs table in a transaction of its own, so that every worker's
//! next store call (claim, sweep, heartbeat or completion: all write that table; in practice
//! the completion of the job it holds) waits on the lock, and restarts the server
//! (`pg_ctlcluster … restart`: connections are terminated, new ones refused until it is up
//! again). Every worker is thus cut off in the middle of a call; between calls the pool would
//! hide the restart, replacing dead connections by itself. Every worker must ride it out by
//! retrying with capped exponential backoff (`moorfret worker` must log the retry), go on
//! claiming after the restart, and exit cleanly when the queue is empty; every job ends done
//! exactly once, and each lost attempt (a lease that ran out during the outage) is counted on
//! its job.
//!
//! The scenario runs twice: with `moorfret worker` (its own retry policy, the production one),
//! and with the store-protocol worker of `scale_support::process_worker`.
//!
//! Needs root, `pg_ctlcluster` and a PostgreSQL server on this machine; otherwise prints why it
//! is skipped, or fails where `MOORFRET_REQUIRE_SERVICES` is set (as `.ci/run` does). Other clients of the server see the restart too.

mod scale_support;

use std::collections::{HashMap, HashSet};
use std::process::Command;
use std::time::Duration;

use moorfret_store::{
    AttemptOutcome, CampaignId, Clock, JobState, PlannedJob, Store, StoreOptions, TestPayload,
};
use scale_support::pg_database::TempDatabase;
use scale_support::process_worker::{self, fault_policy, WorkerProcess};
use scale_support::{
    campaign, postgres_reachable, postgres_url, skip_unless_required, test_job, wait_until,
};
use sqlx::{Connection, PgConnection};

const JOBS: usize = 80;
const WORKERS: usize = 4;

fn main() {
    process_worker::run_if_requested();
    let Some(cluster) = local_cluster() else {
        return;
    };
    let runtime = tokio::runtime::Builder::new_multi_thread()
        .worker_threads(2)
        .enable_all()
        .build()
        .expect("tokio runtime");
    runtime.block_on(async {
        if !postgres_reachable(&postgres_url()).await {
            return;
        }
        let artifacts = tempfile::tempdir().expect("artifact directory");
        let moorfret_worker =
            |url: &str, _name: &str| process_worker::spawn_moorfret(None, url, artifacts.path());
        every_worker_survives_a_server_restart(
            &cluster,
            moorfret_worker,
            Some("store call failed; retrying"),
        )
        .await;
        println!("test every_worker_survives_a_server_restart (moorfret worker) ... ok");
        let protocol_worker = |url: &str, name: &str| process_worker::spawn(None, url, name);
        every_worker_survives_a_server_restart(&cluster, protocol_worker, None).await;
        println!("test every_worker_survives_a_server_restart (store-protocol worker) ... ok");
    });
}

/// The local cluster's version directory (`/etc/postgresql/VERSION/main`), or why the test
/// is skipped.
fn local_cluster() -> Option<String> {
    let uid_is_root = std::fs::read_to_string("/proc/self/status")
        .map(|s| s.lines().any(|l| l.starts_with("Uid:\t0\t")))
        .unwrap_or(false);
    if !uid_is_root {
        skip_unless_required("database restart", "not running as root");
        return None;
    }
    let versions: Vec<String> = std::fs::read_dir("/etc/postgresql")
        .map(|dir| {
            dir.filter_map(|e| e.ok())
                .filter(|e| e.path().join("main").is_dir())
                .map(|e| e.file_name().to_string_lossy().into_owned())
                .collect()
        })
        .unwrap_or_default();
    let has_tool = Command::new("pg_ctlcluster").arg("--help").output().is_ok();
    match (versions.as_slice(), has_tool) {
        ([version], true) => Some(version.clone()),
        _ => {
            skip_unless_required(
                "database restart",
                &format!("need `pg_ctlcluster` and exactly one local cluster (found {versions:?})"),
            );
            None
        }
    }
}

fn restart_server(version: &str) {
    let out = Command::new("pg_ctlcluster")
        .args(["--skip-systemctl-redirect", version, "main", "restart"])
        .output()
        .expect("run pg_ctlcluster");
    assert!(
        out.status.success(),
        "restart failed: {}",
        String::from_utf8_lossy(&out.stderr)
    );
}

/// Runs the scenario with workers started by `start(url, name)`. `retried`, if given, is the
/// text of the log line a worker writes when it retries a store call that failed on the
/// connection; every worker must have written it.
async fn every_worker_survives_a_server_restart<F>(version: &str, start: F, retried: Option<&str>)
where
    F: Fn(&str, &str) -> WorkerProcess,
{
    let db = TempDatabase::create(&postgres_url()).await;
    let options = StoreOptions {
        clock: Clock::Database,
        policy: fault_policy(),
        max_connections: 1,
        postgres_schema: None,
    };
    let store = Store::open(&db.url(), options.clone())
        .await
        .expect("open store");
    let id = campaign(&store, "restart").await;
    assert_eq!(
        id,
        CampaignId(1),
        "the worker processes expect the first campaign"
    );
    let plan: Vec<PlannedJob> = (0..JOBS)
        .map(|_| test_job(TestPayload::Sleep { duration_ms: 200 }))
        .collect();
    store.insert_plan(id, &plan).await.unwrap();
    store.close().await;

    // To cut every worker off in the middle of a store call, the test's own transaction will
    // lock the jobs table against writes, so that each worker's next call waits on the lock
    // until the restart terminates it. This connection is opened before the workers start:
    // PostgreSQL's postmaster signals its backends newest first, so the workers' backends are
    // told to terminate before the lock holder's, and none of them can take the lock and
    // finish its call while the server goes down.
    let mut blocker = PgConnection::connect(&db.url()).await.expect("connect");

    let workers: Vec<WorkerProcess> = (0..WORKERS)
        .map(|n| start(&db.url(), &format!("worker-{n}")))
        .collect();
    let pids: HashSet<i64> = workers.iter().map(WorkerProcess::pid).collect();
    let watcher = Store::open(&db.url(), options.clone())
        .await
        .expect("open store");
    wait_until(
        Duration::from_secs(60),
        "a fifth of the jobs is done",
        || {
            let watcher = watcher.clone();
            async move {
                let done = watcher.progress(id).await.unwrap().jobs_by_state[3].1;
                done >= (JOBS / 5) as i64
            }
        },
    )
    .await;
    for statement in ["BEGIN", "LOCK TABLE jobs IN EXCLUSIVE MODE"] {
        sqlx::query(statement)
            .execute(&mut blocker)
            .await
            .expect("lock the jobs table");
    }
    let done_when_locked = watcher.progress(id).await.unwrap().jobs_by_state[3].1;
    watcher.close().await;
    let mut observer = PgConnection::connect(&db.url()).await.expect("connect");
    let mut waiting = 0;
    let deadline = std::time::Instant::now() + Duration::from_secs(30);
    while waiting < WORKERS as i64 {
        assert!(
            std::time::Instant::now() < deadline,
            "only {waiting} store calls wait on the lock"
        );
        tokio::time::sleep(Duration::from_millis(50)).await;
        waiting = sqlx::query_scalar(
            "SELECT count(*) FROM pg_stat_activity \
             WHERE datname = current_database() AND wait_event_type = 'Lock'",
        )
        .fetch_one(&mut observer)
        .await
        .expect("read pg_stat_activity");
    }
    // Jobs still sleeping end and their completions queue up behind the lock too.
    tokio::time::sleep(Duration::from_millis(1_000)).await;
    drop(observer);

    restart_server(version);
    drop(blocker);
    let mut conn = PgConnection::connect(&db.url()).await.expect("connect");
    let restarted_at_ms: i64 = sqlx::query_scalar(
        "SELECT (extract(epoch FROM pg_postmaster_start_time()) * 1000)::bigint",
    )
    .fetch_one(&mut conn)
    .await
    .expect("read the server's start time");
    let _ = conn.close().await;

    let mut results = Vec::new();
    for worker in workers {
        results.push(worker.finish(Duration::from_secs(120)).await);
    }
    for (n, (ok, lines)) in results.iter().enumerate() {
        assert!(
            ok,
            "worker {n} did not survive the restart:\n{}",
            lines.join("\n")
        );
        if let Some(text) = retried {
            assert!(
                lines.iter().any(|l| l.contains(text)),
                "worker {n} was not cut off in a store call (no {text:?} in its log):\n{}",
                lines.join("\n")
            );
        }
    }

    let store = Store::open(&db.url(), options).await.expect("reopen store");
    let jobs = store.jobs_of_campaign(id).await.unwrap();
    let attempts = store.attempts_of_campaign(id).await.unwrap();
    let mut done_per_job: HashMap<i64, usize> = HashMap::new();
    let mut lost_per_job: HashMap<i64, i64> = HashMap::new();
    let mut claimed_after_restart: HashMap<i64, usize> = HashMap::new();
    for attempt in &attempts {
        assert!(
            pids.contains(&attempt.pid),
            "attempt {:?} by pid {}, not a worker of this test",
            attempt.id,
            attempt.pid
        );
        match attempt.outcome {
            Some(AttemptOutcome::Done) => *done_per_job.entry(attempt.job.0).or_default() += 1,
            Some(AttemptOutcome::Lost) => *lost_per_job.entry(attempt.job.0).or_default() += 1,
            other => panic!("attempt {:?} ended {other:?}", attempt.id),
        }
        if attempt.started_at_ms > restarted_at_ms {
            *claimed_after_restart.entry(attempt.pid).or_default() += 1;
        }
    }
    assert_eq!(jobs.len(), JOBS);
    for job in &jobs {
        assert_eq!(job.state, JobState::Done, "job {} is {}", job.id, job.state);
        assert!(job.result.is_some(), "job {} has no result", job.id);
        assert_eq!(
            done_per_job.get(&job.id.0).copied(),
            Some(1),
            "job {} must be done exactly once",
            job.id
        );
        assert_eq!(
            lost_per_job.get(&job.id.0).copied().unwrap_or(0),
            job.lost_count,
            "job {}: lost attempts against its lost count",
            job.id
        );
    }
    assert_eq!(done_per_job.len(), JOBS);
    let lost: i64 = jobs.iter().map(|j| j.lost_count).sum();
    assert_eq!(lost as usize, attempts.len() - JOBS);
    // The calls each worker retried, from the `operation="…"` of its retry log lines.
    let retried_calls: Vec<Vec<&str>> = results
        .iter()
        .map(|(_, lines)| {
            lines
                .iter()
                .filter(|l| retried.is_some_and(|text| l.contains(text)))
                .filter_map(|l| l.split("operation=\"").nth(1)?.split('"').next())
                .collect()
        })
        .collect();
    eprintln!(
        "done when the table was locked: {done_when_locked}; claims after the restart per worker \
         pid: {claimed_after_restart:?}; leases lost: {lost}; calls retried per worker: \
         {retried_calls:?}"
    );
    assert_eq!(
        claimed_after_restart.len(),
        WORKERS,
        "every worker went on claiming after the restart"
    );
    store.close().await;
    db.finish().await;
}
