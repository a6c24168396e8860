//! The global stage's speed target: the paper case's full sea state (Hs 8.75 m, Tp 16.5 s,
//! 50 s transient + 1000 s recorded, 10 500 steps of 0.1 s, floater + six lines) end to end on
//! one thread, as `moorfret run global campaigns/paper_case.json --threads 1` runs it: model,
//! sea precomputation, coupled statics and dynamics (output files excluded). Target ≤ 20 s.
//!
//! `cargo bench -p moorfret-solver --bench global_1000s` (ten runs, about three minutes); the work
//! split of the first run is printed before the measurements.

use std::time::Duration;

use criterion::{criterion_group, criterion_main, Criterion, SamplingMode};
use moorfret_solver::floater::FloaterSpec;
use moorfret_solver::global::{run, CaseSpec, FloaterInput, GlobalModel, RunParams};

const CASE: &str = include_str!("../../campaigns/paper_case.json");
const FLOATER: &str = include_str!("../../campaigns/data/oc4_semi_floater.json");

fn model() -> GlobalModel {
    let case = CaseSpec::from_json_str(CASE).expect("paper case parses");
    let floater = FloaterInput::RigidBody(Box::new(
        FloaterSpec::from_json_str(FLOATER).expect("floater"),
    ));
    GlobalModel::new(&case, floater, None).expect("paper case model")
}

fn bench(c: &mut Criterion) {
    let params = RunParams::default();
    let first = run(&model(), &params, |_, _| {}).expect("paper case runs");
    let s = first.stats;
    eprintln!(
        "1000 s after 50 s, {} steps: precomputation {:.2} s, statics {:.2} s, dynamics {:.2} s \
         (lines {:.2} s, floater {:.2} s); {} coupling passes, {} line iterations, \
         {} factorisations, {} assemblies",
        s.steps,
        s.precompute_s,
        s.statics_s,
        s.dynamics_s,
        s.lines_s,
        s.floater_s,
        s.coupling_iterations,
        s.line_iterations,
        s.line_factorizations,
        s.line_assemblies
    );
    let mut g = c.benchmark_group("global");
    // Ten runs of one iteration each.
    g.sample_size(10);
    g.sampling_mode(SamplingMode::Flat);
    g.measurement_time(Duration::from_secs(150));
    g.bench_function("paper_case_1000s_one_thread", |b| {
        b.iter(|| run(&model(), &params, |_, _| {}).expect("paper case runs"))
    });
    g.finish();
}

criterion_group!(benches, bench);
criterion_main!(benches);
