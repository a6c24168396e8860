//! The store at cluster scale: 16 concurrent workers (separate pools, as separate processes
//! have) on SQLite and PostgreSQL, with and without crashes, and the wall-time claim limit.
//!
//! Invariants checked after every run: each job is done, exactly one attempt per job ended
//! `done`, results are stored once, and every other attempt is accounted for as lost.

mod scale_support;

use std::collections::{HashMap, HashSet};
use std::sync::atomic::{AtomicUsize, Ordering};
use std::sync::{Arc, Mutex};
use std::time::{Duration, Instant};

use moorfret_store::{
    complete_with_retry, AttemptOutcome, ClaimFilter, Clock, DamageInput, JobKind, JobResults,
    JobState, ManualClock, PlannedJob, QueuePolicy, RetryPolicy, StoreError, TestPayload,
    WallTimeBudget,
};
use scale_support::{campaign, result_by, test_job, worker_info, Backend, ScaleStore};
use serde_json::json;

const WORKERS: i64 = 16;
const T0_MS: i64 = 1_700_000_000_000;

macro_rules! on_both_backends {
    ($($name:ident),+ $(,)?) => {
        mod sqlite {
            $(
                #[tokio::test(flavor = "multi_thread", worker_threads = 2)]
                async fn $name() {
                    super::$name(super::Backend::Sqlite).await;
                }
            )+
        }
        mod postgres {
            $(
                #[tokio::test(flavor = "multi_thread", worker_threads = 2)]
                async fn $name() {
                    super::$name(super::Backend::Postgres).await;
                }
            )+
        }
    };
}

on_both_backends!(
    sixteen_workers_run_every_job_exactly_once,
    sixteen_workers_with_crashes_and_expiring_leases_complete_every_job_once,
    wall_time_budget_limits_what_a_worker_claims,
    retried_completion_of_a_lost_lease_is_still_rejected,
);

async fn sixteen_workers_run_every_job_exactly_once(backend: Backend) {
    const JOBS: usize = 800;
    let policy = QueuePolicy::default();
    let Some(ts) = ScaleStore::open(backend, Clock::System, policy).await else {
        return;
    };
    let id = campaign(&ts.store, "sixteen").await;
    let plan: Vec<PlannedJob> = (0..JOBS).map(|_| test_job(TestPayload::Succeed)).collect();
    ts.store.insert_plan(id, &plan).await.unwrap();

    let mut handles = Vec::new();
    for n in 0..WORKERS {
        let store = ts.another_handle(2).await;
        handles.push(tokio::spawn(async move {
            let worker = store.register_worker(&worker_info(n)).await?;
            let mut completed = 0_usize;
            while let Some(lease) = store.claim(&worker, &ClaimFilter::default()).await? {
                store.complete(&lease, &result_by(n)).await?;
                completed += 1;
            }
            store.close().await;
            Ok::<usize, StoreError>(completed)
        }));
    }
    let mut per_worker = Vec::new();
    for handle in handles {
        per_worker.push(handle.await.unwrap().expect("worker failed"));
    }
    assert_eq!(per_worker.iter().sum::<usize>(), JOBS);

    let jobs = ts.store.jobs_of_campaign(id).await.unwrap();
    assert!(jobs
        .iter()
        .all(|j| j.state == JobState::Done && j.attempt == 1 && j.lost_count == 0));
    // One attempt per job, by the worker the job row names, whose result it holds.
    let attempts = ts.store.attempts_of_campaign(id).await.unwrap();
    assert_eq!(attempts.len(), JOBS, "some job was claimed more than once");
    let by_job: HashMap<i64, _> = attempts.iter().map(|a| (a.job.0, a)).collect();
    for job in &jobs {
        let attempt = by_job[&job.id.0];
        assert_eq!(attempt.outcome, Some(AttemptOutcome::Done));
        assert_eq!(Some(&attempt.worker), job.worker.as_ref());
        let by = job.result.as_ref().and_then(|r| r["by"].as_i64()).unwrap();
        assert_eq!(attempt.host, format!("node{by}"));
    }
    ts.finish().await;
}

/// Damage row of job `job`: its value identifies the job, so a doubled or swapped row shows.
fn strand_results(job: i64) -> JobResults {
    JobResults {
        result: json!({ "job": job }),
        damage_inputs: vec![DamageInput {
            hot_spot_index: 0,
            measure: "fretting_sn".into(),
            seed_index: 0,
            effective_duration_s: 1_000.0,
            damage: job as f64 * 1e-9,
            details: json!({}),
        }],
        ..JobResults::default()
    }
}

/// 16 workers drain 400 strand-kind jobs while some of them "crash" (drop a lease without a
/// word and come back as a new process) and a sweeper moves the shared clock past the lease
/// length, so that live leases expire under running workers too. Completions of expired
/// leases must be refused, and the sweep must put every abandoned job back.
async fn sixteen_workers_with_crashes_and_expiring_leases_complete_every_job_once(
    backend: Backend,
) {
    const JOBS: usize = 400;
    let policy = QueuePolicy {
        max_lost: 1_000,
        ..QueuePolicy::default()
    };
    let clock = ManualClock::new(T0_MS);
    let Some(ts) = ScaleStore::open(backend, Clock::Manual(clock.clone()), policy.clone()).await
    else {
        return;
    };
    let id = campaign(&ts.store, "crashes").await;
    let plan: Vec<PlannedJob> = (0..JOBS)
        .map(|i| PlannedJob::new(JobKind::Strand, json!({ "i": i })))
        .collect();
    let job_ids = ts.store.insert_plan(id, &plan).await.unwrap();

    let crashes = Arc::new(AtomicUsize::new(0));
    let refused = Arc::new(AtomicUsize::new(0));
    let crashed = Arc::new(Mutex::new(HashSet::new()));
    let mut handles = Vec::new();
    for n in 0..WORKERS {
        let store = ts.another_handle(2).await;
        let (crashes, refused, crashed) = (crashes.clone(), refused.clone(), crashed.clone());
        handles.push(tokio::spawn(async move {
            let mut process = n;
            let mut worker = store.register_worker(&worker_info(process)).await?;
            loop {
                match store.claim(&worker, &ClaimFilter::default()).await? {
                    Some(lease) => {
                        // The first claim of every 7th job dies with its lease; the
                        // process restarts under a new identity.
                        if lease.job.0 % 7 == 0 && crashed.lock().unwrap().insert(lease.job.0) {
                            crashes.fetch_add(1, Ordering::Relaxed);
                            process += WORKERS;
                            worker = store.register_worker(&worker_info(process)).await?;
                            continue;
                        }
                        match store.complete(&lease, &strand_results(lease.job.0)).await {
                            Ok(()) => {}
                            Err(StoreError::LeaseLost { .. }) => {
                                refused.fetch_add(1, Ordering::Relaxed);
                            }
                            Err(err) => return Err(err),
                        }
                    }
                    None => {
                        let progress = store.progress(id).await?;
                        if progress.jobs_by_state[3].1 == JOBS as i64 {
                            break;
                        }
                        tokio::time::sleep(Duration::from_millis(5)).await;
                    }
                }
            }
            store.close().await;
            Ok::<(), StoreError>(())
        }));
    }
    let sweeper = {
        let store = ts.another_handle(1).await;
        let clock = clock.clone();
        let lease_ms = policy.lease_ms;
        tokio::spawn(async move {
            let mut swept = 0_usize;
            loop {
                tokio::time::sleep(Duration::from_millis(40)).await;
                clock.advance_ms(lease_ms + 1);
                swept += store.sweep_expired().await?.requeued.len();
                if store.progress(id).await?.jobs_by_state[3].1 == JOBS as i64 {
                    break;
                }
            }
            store.close().await;
            Ok::<usize, StoreError>(swept)
        })
    };
    // A bug that strands a job would otherwise loop the workers forever.
    let limit = Duration::from_secs(120);
    for handle in handles {
        tokio::time::timeout(limit, handle)
            .await
            .expect("workers did not finish the queue")
            .unwrap()
            .expect("worker failed");
    }
    let swept = tokio::time::timeout(limit, sweeper)
        .await
        .expect("sweeper did not stop")
        .unwrap()
        .expect("sweeper failed");

    let jobs = ts.store.jobs_of_campaign(id).await.unwrap();
    assert!(jobs.iter().all(|j| j.state == JobState::Done));
    let attempts = ts.store.attempts_of_campaign(id).await.unwrap();
    let mut done_per_job: HashMap<i64, usize> = HashMap::new();
    let mut lost = 0_usize;
    for attempt in &attempts {
        match attempt.outcome {
            Some(AttemptOutcome::Done) => *done_per_job.entry(attempt.job.0).or_default() += 1,
            Some(AttemptOutcome::Lost) => lost += 1,
            other => panic!("attempt {:?} ended {other:?}", attempt.id),
        }
    }
    assert_eq!(done_per_job.len(), JOBS);
    assert!(done_per_job.values().all(|&n| n == 1));
    let crashes = crashes.load(Ordering::Relaxed);
    let refused = refused.load(Ordering::Relaxed);
    let crash_jobs = job_ids.iter().filter(|j| j.0 % 7 == 0).count();
    assert_eq!(crashes, crash_jobs, "each chosen job crashed exactly once");
    // Every lost attempt was swept; each crash and each refused completion is one of them.
    assert_eq!(lost, swept);
    assert!(lost >= crashes + refused, "{lost} < {crashes} + {refused}");
    let lost_counted: i64 = jobs.iter().map(|j| j.lost_count).sum();
    assert_eq!(lost_counted as usize, lost);
    for (job, record) in job_ids.iter().zip(&jobs) {
        let stored = ts.store.results_of(*job).await.unwrap();
        assert_eq!(stored, strand_results(job.0), "job {job}");
        assert_eq!(record.attempt, 1, "lost claims are not counted as attempts");
    }
    ts.finish().await;
}

async fn wall_time_budget_limits_what_a_worker_claims(backend: Backend) {
    let Some(ts) = ScaleStore::open(backend, Clock::System, QueuePolicy::default()).await else {
        return;
    };
    let id = campaign(&ts.store, "wall-time").await;
    // Highest priority first: the long job is offered first whenever it fits.
    let plan: Vec<PlannedJob> = [(3_000.0, 3), (600.0, 2), (60.0, 1)]
        .into_iter()
        .map(|(cost_s, priority)| PlannedJob {
            expected_cost_s: cost_s,
            priority,
            ..PlannedJob::new(JobKind::Strand, json!({ "cost_s": cost_s }))
        })
        .collect();
    let jobs = ts.store.insert_plan(id, &plan).await.unwrap();
    let worker = ts.store.register_worker(&worker_info(1)).await.unwrap();
    // A 1 h allocation keeping 120 s for finishing, 50 min in: 480 s of work still fit.
    let start = Instant::now();
    let budget = WallTimeBudget::new(3_600.0, 120.0, start).unwrap();
    let late = start + Duration::from_secs(3_000);
    let filter = budget.restrict(&ClaimFilter::default(), late);
    assert_eq!(filter.max_expected_cost_s, Some(480.0));
    let lease = ts.store.claim(&worker, &filter).await.unwrap().unwrap();
    assert_eq!(lease.job, jobs[2], "only the 60 s job fits in 480 s");
    assert!(ts.store.claim(&worker, &filter).await.unwrap().is_none());
    ts.store
        .complete(&lease, &JobResults::default())
        .await
        .unwrap();

    // Inside the reserve nothing is claimed; early on the long job comes first.
    let closing = budget.restrict(&ClaimFilter::default(), start + Duration::from_secs(3_500));
    assert_eq!(closing.max_expected_cost_s, Some(0.0));
    assert!(ts.store.claim(&worker, &closing).await.unwrap().is_none());
    let early = budget.restrict(&ClaimFilter::default(), start);
    let lease = ts.store.claim(&worker, &early).await.unwrap().unwrap();
    assert_eq!(lease.job, jobs[0]);

    let nan = ClaimFilter {
        max_expected_cost_s: Some(f64::NAN),
        ..ClaimFilter::default()
    };
    assert!(matches!(
        ts.store.claim(&worker, &nan).await,
        Err(StoreError::InvalidParameter {
            field: "max_expected_cost_s",
            ..
        })
    ));
    ts.finish().await;
}

async fn retried_completion_of_a_lost_lease_is_still_rejected(backend: Backend) {
    let policy = QueuePolicy::default();
    let clock = ManualClock::new(T0_MS);
    let Some(ts) = ScaleStore::open(backend, Clock::Manual(clock.clone()), policy.clone()).await
    else {
        return;
    };
    let id = campaign(&ts.store, "retry").await;
    let job = ts
        .store
        .insert_plan(id, &[PlannedJob::new(JobKind::Strand, json!({}))])
        .await
        .unwrap()[0];
    let slow = ts.store.register_worker(&worker_info(1)).await.unwrap();
    let fast = ts.store.register_worker(&worker_info(2)).await.unwrap();
    let retry = RetryPolicy::default();
    let stale = ts
        .store
        .claim(&slow, &ClaimFilter::default())
        .await
        .unwrap()
        .unwrap();
    clock.advance_ms(policy.lease_ms + 1);
    ts.store.sweep_expired().await.unwrap();
    let current = ts
        .store
        .claim(&fast, &ClaimFilter::default())
        .await
        .unwrap()
        .unwrap();
    let late = complete_with_retry(&ts.store, &stale, &strand_results(1), &retry).await;
    assert!(matches!(late, Err(StoreError::LeaseLost { job: j, .. }) if j == job));
    complete_with_retry(&ts.store, &current, &strand_results(2), &retry)
        .await
        .unwrap();
    assert_eq!(
        ts.store.attempt_outcome(stale.attempt_id).await.unwrap(),
        Some(AttemptOutcome::Lost)
    );
    assert_eq!(
        ts.store.attempt_outcome(current.attempt_id).await.unwrap(),
        Some(AttemptOutcome::Done)
    );
    assert_eq!(ts.store.results_of(job).await.unwrap(), strand_results(2));
    ts.finish().await;
}
