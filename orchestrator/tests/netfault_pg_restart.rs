//! Database fault: PostgreSQL restarts in the middle of a campaign.
//!
//! Four worker processes drain 80 test jobs (200 ms sleeps, 2 s leases); once a fifth of them
//! is done the server is restarted (`pg_ctlcluster … restart`: connections are terminated,
//! new ones refused until it is up again). Every worker must ride it out by retrying with
//! capped exponential backoff, go on claiming after the restart, and exit cleanly when the
//! queue is empty; every job ends done exactly once.
//!
//! Needs root, `pg_ctlcluster` and a PostgreSQL server on this machine; otherwise prints why it
//! is skipped. Other clients of the server see the restart too.

mod scale_support;

use std::collections::HashMap;
use std::process::Command;
use std::time::Duration;

use moorfret_orchestrator::store::{
    clock::system_now_ms, AttemptOutcome, CampaignId, Clock, JobState, PlannedJob, Store,
    StoreOptions, TestPayload,
};
use scale_support::pg_database::TempDatabase;
use scale_support::process_worker::{self, fault_policy};
use scale_support::{campaign, postgres_reachable, postgres_url, test_job, wait_until};

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
        every_worker_survives_a_server_restart(&cluster).await;
        println!("test every_worker_survives_a_server_restart ... ok");
    });
}

/// The local cluster's version directory (`/etc/postgresql/VERSION/main`), or why the test
/// is skipped.
fn local_cluster() -> Option<String> {
    let uid_is_root = std::fs::read_to_string("/proc/self/status")
        .map(|s| s.lines().any(|l| l.starts_with("Uid:\t0\t")))
        .unwrap_or(false);
    if !uid_is_root {
        eprintln!("SKIPPED (database restart): not running as root");
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
            eprintln!(
                "SKIPPED (database restart): need `pg_ctlcluster` and exactly one local cluster \
                 (found {versions:?})"
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

async fn every_worker_survives_a_server_restart(version: &str) {
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

    let workers: Vec<_> = (0..WORKERS)
        .map(|n| process_worker::spawn(None, &db.url(), &format!("worker-{n}")))
        .collect();
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
    watcher.close().await;

    restart_server(version);
    let restarted_at_ms = system_now_ms();

    let mut results = Vec::new();
    for worker in workers {
        results.push(worker.finish(Duration::from_secs(120)).await);
    }
    for (n, (ok, events)) in results.iter().enumerate() {
        assert!(ok, "worker {n} did not survive the restart: {events:?}");
    }

    let store = Store::open(&db.url(), options).await.expect("reopen store");
    let jobs = store.jobs_of_campaign(id).await.unwrap();
    assert!(jobs.iter().all(|j| j.state == JobState::Done));
    let attempts = store.attempts_of_campaign(id).await.unwrap();
    let mut done_per_job: HashMap<i64, usize> = HashMap::new();
    let mut claimed_after_restart: HashMap<String, usize> = HashMap::new();
    for attempt in &attempts {
        match attempt.outcome {
            Some(AttemptOutcome::Done) => *done_per_job.entry(attempt.job.0).or_default() += 1,
            Some(AttemptOutcome::Lost) => {}
            other => panic!("attempt {:?} ended {other:?}", attempt.id),
        }
        if attempt.started_at_ms > restarted_at_ms {
            *claimed_after_restart
                .entry(attempt.host.clone())
                .or_default() += 1;
        }
    }
    assert_eq!(done_per_job.len(), JOBS);
    assert!(
        done_per_job.values().all(|&n| n == 1),
        "a job was done twice"
    );
    let lost: i64 = jobs.iter().map(|j| j.lost_count).sum();
    let lost_attempts = attempts.len() - JOBS;
    assert_eq!(lost as usize, lost_attempts);
    eprintln!(
        "claims after the restart per worker: {claimed_after_restart:?}; leases lost: {lost}"
    );
    assert_eq!(
        claimed_after_restart.len(),
        WORKERS,
        "every worker went on claiming after the restart"
    );
    store.close().await;
    db.finish().await;
}
