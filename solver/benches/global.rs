//! Coupled global stage on the paper case: coupled statics, and 20 s of coupled dynamics (a
//! 10 s transient and 10 s recorded, 200 steps of 0.1 s, floater + six lines), on one thread.
//! `cargo bench -p moorfret-solver --bench global`; the work split (lines / floater /
//! precomputation) of one run is printed once before the measurements.

use criterion::{criterion_group, criterion_main, Criterion};
use moorfret_solver::floater::FloaterSpec;
use moorfret_solver::global::dynamics::run_dynamics;
use moorfret_solver::global::system::{solve_coupled_statics, StaticsParams};
use moorfret_solver::global::DynamicsParams;
use moorfret_solver::global::{CaseSpec, FloaterInput, GlobalModel};

const CASE: &str = include_str!("../../campaigns/paper_case.json");
const FLOATER: &str = include_str!("../../campaigns/data/oc4_semi_floater.json");

fn model() -> GlobalModel {
    let mut case = CaseSpec::from_json_str(CASE).expect("paper case parses");
    case.timing.transient_s = 10.0;
    case.timing.wave_ramp_s = 10.0;
    let floater = FloaterInput::RigidBody(Box::new(
        FloaterSpec::from_json_str(FLOATER).expect("floater"),
    ));
    GlobalModel::new(&case, floater, Some(10.0)).expect("paper case model")
}

fn bench(c: &mut Criterion) {
    let model = model();
    let eq = solve_coupled_statics(&model, &StaticsParams::default(), None).expect("statics");
    let params = DynamicsParams::default();
    let r = run_dynamics(&model, &eq, &params, None, |_, _| {}).expect("dynamics");
    let s = r.stats;
    eprintln!(
        "20 s simulated, {} steps: {:.3} s total, lines {:.3} s, floater {:.3} s, \
         precompute {:.3} s; {} coupling iterations, {} line iterations",
        s.steps,
        s.dynamics_s + s.precompute_s,
        s.lines_s,
        s.floater_s,
        s.precompute_s,
        s.coupling_iterations,
        s.line_iterations
    );
    let mut g = c.benchmark_group("global");
    g.sample_size(10);
    g.bench_function("paper_case_statics", |b| {
        b.iter(|| solve_coupled_statics(&model, &StaticsParams::default(), None).expect("statics"))
    });
    g.bench_function("paper_case_20s_dynamics", |b| {
        b.iter(|| run_dynamics(&model, &eq, &params, None, |_, _| {}).expect("dynamics"))
    });
    g.finish();
}

criterion_group!(benches, bench);
criterion_main!(benches);
