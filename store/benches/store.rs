//! Queue overhead: claim + complete per job with 8 and 16 concurrent workers (separate pools,
//! as separate processes would have), and inserting a 10 000-job plan with dependencies.
//! Criterion's throughput of the `claim_complete_16_workers` group is the claim rate of a
//! 16-worker cluster: claims (each followed by its completion) per second.
//!
//! SQLite always; PostgreSQL too when `MOORFRET_BENCH_POSTGRES_URL` is set (each run in a
//! schema of its own, dropped afterwards). Targets (`docs/benchmarks.md`):
//! < 10 ms per claimed and completed job, < 1 s for a 10 000-job plan.
//!
//! Measured on a shared 2-core machine under heavy load (load average ≈ 13), wall time:
//! SQLite 400 jobs in 0.75 s (1.9 ms/job), PostgreSQL 1.49 s (3.7 ms/job); plan of 10 000 jobs
//! with 8 000 dependencies: SQLite 70 ms, PostgreSQL 0.73 s.
//! 16 workers, 1 600 jobs per sample, bench profile, criterion medians of three runs with the
//! 2 cores shared with other CPU-heavy work (load average 7.7-10.4): PostgreSQL 517, 536 and
//! 553 claims/s (1.8-1.9 ms per claim + complete), SQLite 776, 887 and 865 claims/s; single
//! samples 461-644/s and 647-1 111/s.

use std::time::{Duration, Instant};

use criterion::{criterion_group, criterion_main, Criterion, Throughput};
use moorfret_store::{
    ClaimFilter, JobKind, JobResults, NewCampaign, PlannedJob, Store, StoreOptions, WorkerInfo,
};
use serde_json::json;
use tokio::runtime::Runtime;

const JOBS_PER_RUN: usize = 400;
const JOBS_PER_RUN_16: usize = 1_600;
const PLAN_JOBS: usize = 10_000;

/// A fresh store: an SQLite file in `dir`, or a new schema on the PostgreSQL server.
fn locations(dir: &std::path::Path, run: usize) -> Vec<(&'static str, String, StoreOptions)> {
    let mut all = vec![(
        "sqlite",
        dir.join(format!("bench-{run}.sqlite"))
            .to_string_lossy()
            .into_owned(),
        StoreOptions::default(),
    )];
    if let Ok(url) = std::env::var("MOORFRET_BENCH_POSTGRES_URL") {
        let options = StoreOptions {
            postgres_schema: Some(format!("bench_{}", uuid::Uuid::new_v4().simple())),
            ..StoreOptions::default()
        };
        all.push(("postgres", url, options));
    }
    all
}

fn plan(jobs: usize) -> Vec<PlannedJob> {
    // One global job followed by the four strand jobs that depend on it, as a campaign plans.
    (0..jobs)
        .map(|i| {
            let global = i - i % 5;
            if i == global {
                PlannedJob::new(JobKind::Global, json!({ "seed": i }))
            } else {
                PlannedJob {
                    depends_on: vec![global],
                    ..PlannedJob::new(JobKind::Strand, json!({ "hot_spot": i % 5 }))
                }
            }
        })
        .collect()
}

async fn new_campaign(store: &Store, name: &str) -> moorfret_store::CampaignId {
    let campaign = NewCampaign {
        name: name.into(),
        spec: json!({}),
        spec_sha256: "0".repeat(64),
    };
    store
        .create_campaign(&campaign)
        .await
        .expect("create campaign")
}

/// Runs `workers` workers until the queue is empty; returns the time they took.
async fn drain(location: &str, options: &StoreOptions, workers: usize) -> Duration {
    let mut handles = Vec::new();
    let mut stores = Vec::new();
    for _ in 0..workers {
        let options = StoreOptions {
            max_connections: 2,
            ..options.clone()
        };
        stores.push(
            Store::open(location, options)
                .await
                .expect("open worker store"),
        );
    }
    let start = Instant::now();
    for (n, store) in stores.into_iter().enumerate() {
        handles.push(tokio::spawn(async move {
            let info = WorkerInfo {
                host: "bench".into(),
                pid: n as i64,
                version: "bench".into(),
            };
            let worker = store.register_worker(&info).await.expect("register");
            while let Some(lease) = store
                .claim(&worker, &ClaimFilter::default())
                .await
                .expect("claim")
            {
                let results = JobResults {
                    result: json!({ "ok": true }),
                    ..JobResults::default()
                };
                store.complete(&lease, &results).await.expect("complete");
            }
            store.close().await;
        }));
    }
    for handle in handles {
        handle.await.expect("worker task");
    }
    start.elapsed()
}

fn claim_and_complete(c: &mut Criterion) {
    claim_and_complete_with(c, 8, JOBS_PER_RUN);
    claim_and_complete_with(c, 16, JOBS_PER_RUN_16);
}

/// `workers` workers drain `jobs` test jobs; throughput = claims per second.
fn claim_and_complete_with(c: &mut Criterion, workers: usize, jobs: usize) {
    let runtime = Runtime::new().expect("tokio runtime");
    let dir = tempfile::tempdir().expect("temp dir");
    let mut group = c.benchmark_group(format!("claim_complete_{workers}_workers"));
    group
        .sample_size(10)
        .throughput(Throughput::Elements(jobs as u64));
    for backend in ["sqlite", "postgres"] {
        let mut run = 0;
        if backend == "postgres" && std::env::var("MOORFRET_BENCH_POSTGRES_URL").is_err() {
            continue;
        }
        group.bench_function(backend, |b| {
            b.iter_custom(|iters| {
                let mut total = Duration::ZERO;
                for _ in 0..iters {
                    run += 1;
                    let (_, location, options) = locations(dir.path(), workers * 100_000 + run)
                        .into_iter()
                        .find(|(name, ..)| *name == backend)
                        .expect("backend location");
                    total += runtime.block_on(async {
                        let store = Store::open(&location, options.clone()).await.expect("open");
                        let campaign = new_campaign(&store, "bench").await;
                        let plan: Vec<PlannedJob> = (0..jobs)
                            .map(|i| PlannedJob::new(JobKind::Test, json!({ "i": i })))
                            .collect();
                        store.insert_plan(campaign, &plan).await.expect("plan");
                        let elapsed = drain(&location, &options, workers).await;
                        store.drop_postgres_schema().await.expect("clean up");
                        elapsed
                    });
                }
                total
            });
        });
    }
    group.finish();
}

fn plan_insert(c: &mut Criterion) {
    let runtime = Runtime::new().expect("tokio runtime");
    let dir = tempfile::tempdir().expect("temp dir");
    let jobs = plan(PLAN_JOBS);
    let mut group = c.benchmark_group("plan_insert_10000_jobs");
    group
        .sample_size(10)
        .throughput(Throughput::Elements(PLAN_JOBS as u64));
    for backend in ["sqlite", "postgres"] {
        if backend == "postgres" && std::env::var("MOORFRET_BENCH_POSTGRES_URL").is_err() {
            continue;
        }
        let mut run = 1_000_000;
        group.bench_function(backend, |b| {
            b.iter_custom(|iters| {
                let mut total = Duration::ZERO;
                for _ in 0..iters {
                    run += 1;
                    let (_, location, options) = locations(dir.path(), run)
                        .into_iter()
                        .find(|(name, ..)| *name == backend)
                        .expect("backend location");
                    total += runtime.block_on(async {
                        let store = Store::open(&location, options).await.expect("open");
                        let campaign = new_campaign(&store, "plan").await;
                        let start = Instant::now();
                        store.insert_plan(campaign, &jobs).await.expect("plan");
                        let elapsed = start.elapsed();
                        store.drop_postgres_schema().await.expect("clean up");
                        elapsed
                    });
                }
                total
            });
        });
    }
    group.finish();
}

criterion_group!(benches, claim_and_complete, plan_insert);
criterion_main!(benches);
