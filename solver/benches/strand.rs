//! The three curvature cases of the 1+6+1 benchmark strand (ε = 1e-3, then κ = 1e-2, 5e-2,
//! 1.0 1/m, 'vs_analytical' regularisation), each solved from the reference configuration.

use criterion::{criterion_group, criterion_main, Criterion};
use moorfret_solver::strand::driver::{run_case, StrandRunParameters};
use moorfret_solver::strand::model::{EndKind, StrandModel, StrandModelParameters};
use moorfret_solver::strand::profile::profile_from_json;

const BENCHMARK: &str = include_str!(concat!(
    env!("CARGO_MANIFEST_DIR"),
    "/../campaigns/benchmarks/strand_1_6_1.json"
));

fn strand_cases(c: &mut Criterion) {
    let strand = profile_from_json(BENCHMARK)
        .and_then(|p| p.validate())
        .expect("benchmark profile is valid");
    let params = StrandModelParameters::penalty_contact(2e8, 1e-7, EndKind::PenaltyTies);
    let model = StrandModel::new(&strand, &params).expect("model builds");
    let run = StrandRunParameters::default();
    let mut group = c.benchmark_group("strand_1_6_1");
    group.sample_size(10);
    group.bench_function("three_curvature_cases", |b| {
        b.iter(|| {
            let mut work = (0, 0);
            for kappa in [1e-2, 5e-2, 1.0] {
                let r = run_case(&model, 1e-3, kappa, &run).expect("case converges");
                work.0 += r.stats.iterations;
                work.1 += r.stats.factorisations;
            }
            work
        })
    });
    group.finish();
}

criterion_group!(benches, strand_cases);
criterion_main!(benches);
