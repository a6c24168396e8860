//! Network fault: a worker's link is cut in the middle of a job.
//!
//! Two worker processes run on simulated hosts (network namespaces on veth links) and reach
//! the PostgreSQL server through a TCP forwarder on their link's host-side address. Host A
//! claims the only job (a 6 s sleep of the test kind, 2 s leases); its link goes down; host B
//! finds the lease expired, sweeps it and runs the job; A's link comes back and A, whose sleep
//! has ended, tries to complete. Expected: A's completion is refused by its lease token, B's
//! stands, the job is done once, A's claim is recorded as lost.
//!
//! Needs root, `ip netns` and a PostgreSQL server (`MOORFRET_TEST_POSTGRES_URL`); otherwise
//! prints why it is skipped.

mod scale_support;

use std::time::Duration;

use moorfret_orchestrator::store::{
    AttemptOutcome, CampaignId, Clock, JobState, Store, StoreOptions, TestPayload,
};
use scale_support::netns::{self, Forwarder, Host};
use scale_support::pg_database::TempDatabase;
use scale_support::process_worker::{self, fault_policy};
use scale_support::{campaign, postgres_reachable, postgres_url, test_job, wait_until};

fn main() {
    process_worker::run_if_requested();
    if let Some(reason) = netns::unavailable() {
        eprintln!("SKIPPED (network faults): {reason}");
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
        cut_worker_loses_its_job_and_its_late_completion_is_rejected().await;
        println!("test cut_worker_loses_its_job_and_its_late_completion_is_rejected ... ok");
    });
}

async fn cut_worker_loses_its_job_and_its_late_completion_is_rejected() {
    let db = TempDatabase::create(&postgres_url()).await;
    let options = StoreOptions {
        clock: Clock::Database,
        policy: fault_policy(),
        max_connections: 2,
        postgres_schema: None,
    };
    let store = Store::open(&db.url(), options).await.expect("open store");
    let id = campaign(&store, "link-cut").await;
    assert_eq!(
        id,
        CampaignId(1),
        "the worker processes expect the first campaign"
    );
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

    let worker_a = process_worker::spawn(
        Some(host_a.launcher()),
        &db.url_via(&via_a.addr.to_string()),
        "host-a",
    );
    let attempts_by = |host: &'static str| {
        let store = store.clone();
        move || {
            let store = store.clone();
            async move {
                store
                    .attempts_of_campaign(id)
                    .await
                    .unwrap()
                    .iter()
                    .any(|a| a.host == host)
            }
        }
    };
    wait_until(
        Duration::from_secs(30),
        "host A claims the job",
        attempts_by("host-a"),
    )
    .await;

    // Mid-job: A's sleep has 6 s to go, its lease 2 s.
    host_a.cut();
    let worker_b = process_worker::spawn(
        Some(host_b.launcher()),
        &db.url_via(&via_b.addr.to_string()),
        "host-b",
    );
    wait_until(
        Duration::from_secs(30),
        "host B takes the job over",
        attempts_by("host-b"),
    )
    .await;
    host_a.restore();

    let (a_ok, a_events) = worker_a.finish(Duration::from_secs(90)).await;
    let (b_ok, b_events) = worker_b.finish(Duration::from_secs(90)).await;
    eprintln!("host A: {a_events:?}\nhost B: {b_events:?}");
    assert!(a_ok && b_ok, "both workers survive and exit cleanly");
    let rejected = format!("REJECTED job={job}");
    assert!(
        a_events.iter().any(|e| e.starts_with(&rejected)),
        "A's late completion must be refused"
    );
    assert!(b_events.contains(&format!("COMPLETED job={job}")));

    let record = store.job(job).await.unwrap();
    assert_eq!(record.state, JobState::Done);
    assert_eq!((record.attempt, record.lost_count), (1, 1));
    assert_eq!(
        record.result.as_ref().and_then(|r| r["by"].as_str()),
        Some("host-b")
    );
    let outcomes: Vec<(String, Option<AttemptOutcome>)> = store
        .attempts_of_campaign(id)
        .await
        .unwrap()
        .into_iter()
        .map(|a| (a.host, a.outcome))
        .collect();
    assert_eq!(
        outcomes,
        vec![
            ("host-a".to_owned(), Some(AttemptOutcome::Lost)),
            ("host-b".to_owned(), Some(AttemptOutcome::Done)),
        ]
    );
    store.close().await;
    drop((via_a, via_b));
    drop((host_a, host_b));
    db.finish().await;
}
