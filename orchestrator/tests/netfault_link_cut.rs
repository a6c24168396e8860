//! Network fault: a worker's link is cut in the middle of a job.
//!
//! Two worker processes run on simulated hosts (network namespaces on veth links) and reach
//! the PostgreSQL server through a TCP forwarder on their link's host-side address. Host A
//! claims the only job (a 6 s sleep of the test kind, 2 s leases); its link goes down; host B
//! finds the lease expired, sweeps it and runs the job; A's link comes back and A, whose sleep
//! has ended, tries to complete. Expected: A's completion is refused by its lease token, B's
//! stands, the job is done once, A's claim is recorded as lost.
//!
//! The scenario runs twice: with `moorfret worker`, and with the store-protocol worker of
//! `scale_support::process_worker` (which retries its store calls through the retry helper).
//!
//! Needs root, `ip netns` and a PostgreSQL server (`MOORFRET_TEST_POSTGRES_URL`); otherwise
//! prints why it is skipped, or fails where `MOORFRET_REQUIRE_SERVICES` is set (as `.ci/run`
//! does).

mod scale_support;

use std::time::Duration;

use moorfret_store::{AttemptOutcome, Clock, JobState, Store, StoreOptions, TestPayload};
use scale_support::netns::{self, Forwarder, Host};
use scale_support::pg_database::TempDatabase;
use scale_support::process_worker::{self, fault_policy, WorkerProcess};
use scale_support::{
    campaign, postgres_reachable, postgres_url, skip_unless_required, test_job, wait_until,
};

fn main() {
    process_worker::run_if_requested();
    if let Some(reason) = netns::unavailable() {
        skip_unless_required("network namespaces", &reason);
        return;
    }
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
        let moorfret_worker = |host: &Host, url: &str, _name: &str| {
            process_worker::spawn_moorfret(Some(host.launcher()), url, artifacts.path())
        };
        cut_worker_loses_its_job_and_its_late_completion_is_rejected(
            moorfret_worker,
            "lease lost: results discarded",
        )
        .await;
        println!("test cut_worker_loses_its_job_and_its_late_completion_is_rejected (moorfret worker) ... ok");
        let protocol_worker = |host: &Host, url: &str, name: &str| {
            process_worker::spawn(Some(host.launcher()), url, name)
        };
        cut_worker_loses_its_job_and_its_late_completion_is_rejected(protocol_worker, "REJECTED job=")
            .await;
        println!("test cut_worker_loses_its_job_and_its_late_completion_is_rejected (store-protocol worker) ... ok");
    });
}

/// Runs the scenario with workers started by `start(host, url, name)`; `rejected` is the text
/// of the line a worker prints when its completion is refused.
async fn cut_worker_loses_its_job_and_its_late_completion_is_rejected<F>(start: F, rejected: &str)
where
    F: Fn(&Host, &str, &str) -> WorkerProcess,
{
    let db = TempDatabase::create(&postgres_url()).await;
    let options = StoreOptions {
        clock: Clock::Database,
        policy: fault_policy(),
        max_connections: 2,
        postgres_schema: None,
    };
    let store = Store::open(&db.url(), options).await.expect("open store");
    let id = campaign(&store, "link-cut").await;
    let job = store
        .insert_plan(id, &[test_job(TestPayload::Sleep { duration_ms: 6_000 })])
        .await
        .unwrap()[0];

    let host_a = Host::create().expect("host A");
    let host_b = Host::create().expect("host B");
    let via_a = Forwarder::start(host_a.host_addr, db.server_addr())
        .await
        .unwrap();
    let via_b = Forwarder::start(host_b.host_addr, db.server_addr())
        .await
        .unwrap();

    let worker_a = start(&host_a, &db.url_via(&via_a.addr.to_string()), "host-a");
    let pid_a = worker_a.pid();
    let claimed_by = |pid: i64| {
        let store = store.clone();
        move || {
            let store = store.clone();
            async move {
                store
                    .attempts_of_campaign(id)
                    .await
                    .unwrap()
                    .iter()
                    .any(|a| a.pid == pid)
            }
        }
    };
    wait_until(
        Duration::from_secs(30),
        "host A claims the job",
        claimed_by(pid_a),
    )
    .await;

    // Mid-job: A's sleep has 6 s to go, its lease 2 s.
    host_a.cut();
    let worker_b = start(&host_b, &db.url_via(&via_b.addr.to_string()), "host-b");
    let pid_b = worker_b.pid();
    wait_until(
        Duration::from_secs(30),
        "host B takes the job over",
        claimed_by(pid_b),
    )
    .await;
    host_a.restore();

    let (a_ok, a_lines) = worker_a.finish(Duration::from_secs(90)).await;
    let (b_ok, b_lines) = worker_b.finish(Duration::from_secs(90)).await;
    let show = |lines: &[String]| lines.join("\n");
    assert!(a_ok, "worker A failed:\n{}", show(&a_lines));
    assert!(b_ok, "worker B failed:\n{}", show(&b_lines));
    assert!(
        a_lines.iter().any(|l| l.contains(rejected)),
        "A's late completion must be refused:\n{}",
        show(&a_lines)
    );

    let record = store.job(job).await.unwrap();
    assert_eq!(record.state, JobState::Done);
    assert_eq!((record.attempt, record.lost_count), (1, 1));
    let outcomes: Vec<(i64, Option<AttemptOutcome>)> = store
        .attempts_of_campaign(id)
        .await
        .unwrap()
        .into_iter()
        .map(|a| (a.pid, a.outcome))
        .collect();
    assert_eq!(
        outcomes,
        vec![
            (pid_a, Some(AttemptOutcome::Lost)),
            (pid_b, Some(AttemptOutcome::Done))
        ]
    );
    store.close().await;
    drop((via_a, via_b));
    drop((host_a, host_b));
    db.finish().await;
}
