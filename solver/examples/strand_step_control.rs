//! Work of the Newton step control on the three curvature cases of the 1+6+1 benchmark strand
//! ('vs_analytical' regularisation): accepted steps, cut-backs, iterations, factorisations and
//! wall time per case for a few step-control settings.
//!
//! `cargo run --release -p moorfret-solver --example strand_step_control [kappa ...]`

use std::time::Instant;

use moorfret_solver::strand::driver::{run_case, StrandRunParameters};
use moorfret_solver::strand::model::{EndKind, StrandModel, StrandModelParameters};
use moorfret_solver::strand::profile::profile_from_json;

const BENCHMARK: &str = include_str!(concat!(
    env!("CARGO_MANIFEST_DIR"),
    "/../campaigns/benchmarks/strand_1_6_1.json"
));

fn main() {
    let mut kappas: Vec<f64> = std::env::args()
        .skip(1)
        .filter_map(|a| a.parse().ok())
        .collect();
    if kappas.is_empty() {
        kappas = vec![1e-2, 5e-2, 1.0];
    }
    let strand = profile_from_json(BENCHMARK)
        .and_then(|p| p.validate())
        .expect("benchmark profile is valid");
    let params = StrandModelParameters::penalty_contact(2e8, 1e-7, EndKind::PenaltyTies);
    let model = StrandModel::new(&strand, &params).expect("model builds");
    let base = StrandRunParameters::default();
    let mut variants: Vec<(String, StrandRunParameters)> = vec![("default".into(), base)];
    for halvings in [3usize, 6] {
        let mut p = base;
        p.newton.line_search_trials = halvings;
        variants.push((format!("line search {halvings}"), p));
    }
    for (growth, easy) in [(2.0, 12usize), (3.0, 15)] {
        let mut p = base;
        p.newton.line_search_trials = 3;
        p.newton.growth_factor = growth;
        p.newton.easy_iterations = easy;
        variants.push((format!("ls 3, growth {growth}, easy {easy}"), p));
    }
    // STEP_CONTROL=<index> runs one setting only
    if let Some(i) = std::env::var("STEP_CONTROL")
        .ok()
        .and_then(|v| v.parse::<usize>().ok())
    {
        variants = vec![variants.swap_remove(i.min(variants.len() - 1))];
    }
    for (name, run) in &variants {
        for &kappa in &kappas {
            let t = Instant::now();
            match run_case(&model, 1e-3, kappa, run) {
                Ok(r) => println!(
                    "{name:>28} kappa {kappa:>6}: {:>5} steps {:>4} cutbacks {:>6} iterations {:>6} factorisations, {:.3} s",
                    r.stats.steps,
                    r.stats.cutbacks,
                    r.stats.iterations,
                    r.stats.factorisations,
                    t.elapsed().as_secs_f64()
                ),
                Err(e) => println!("{name:>28} kappa {kappa:>6}: failed: {e}"),
            }
        }
    }
}
