//! Planning the paper campaign (`campaigns/paper.json`) with enough seeds per sea state for
//! about 10 000 jobs: sea states, seeds, payloads, cache keys, and the whole plan stored in one
//! SQLite transaction (`plan::create`). Target (`docs/benchmarks.md`): < 1 s.

use std::path::Path;
use std::time::{Duration, Instant};

use criterion::{criterion_group, criterion_main, Criterion};
use moorfret_campaign::resolve;
use moorfret_orchestrator::plan;
use moorfret_store::{Store, StoreOptions};

fn plan_ten_thousand_jobs(c: &mut Criterion) {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("../campaigns/paper.json");
    let mut resolved = resolve(&path).expect("paper campaign resolves");
    let cells = resolved.sectors[0]
        .table
        .cells()
        .iter()
        .filter(|c| c.value > 0.0)
        .count();
    // one global and one strand job per (sea state, seed)
    let seeds = 10_000_usize.div_ceil(2 * cells);
    resolved.inputs.spec.simulation.seeds_per_sea_state = seeds as u32;
    let rt = tokio::runtime::Runtime::new().expect("runtime");
    let dir = tempfile::tempdir().expect("temp dir");
    let mut run = 0;
    let mut group = c.benchmark_group("campaign");
    group.sample_size(10);
    group.bench_function(format!("plan {} jobs", 2 * cells * seeds), |b| {
        b.iter_custom(|iters| {
            let mut total = Duration::ZERO;
            for _ in 0..iters {
                run += 1;
                let db = dir.path().join(format!("plan-{run}.sqlite"));
                let store = rt
                    .block_on(Store::open(&db.to_string_lossy(), StoreOptions::default()))
                    .expect("store");
                let start = Instant::now();
                let (_, jobs) = rt.block_on(plan::create(&store, &resolved)).expect("plan");
                total += start.elapsed();
                assert_eq!(jobs.len(), 2 * cells * seeds);
                rt.block_on(store.close());
            }
            total
        })
    });
    group.finish();
}

criterion_group!(benches, plan_ten_thousand_jobs);
criterion_main!(benches);
