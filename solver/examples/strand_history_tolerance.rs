//! Effect of the turning-point tolerance of [`run_history`] on the results: the 1+6+1 benchmark
//! strand driven by an irregular (ε, κ) history (five incommensurate components each, tension
//! and curvature out of phase, 300 s at 0.25 s), solved with every sample kept (tolerance 0)
//! and with the default tolerance. Printed: samples solved, wall time, and the largest change of
//! every contact's largest slip range and of its peak normal force, relative to the largest
//! value over all contacts.
//!
//! Run: `cargo run --release -p moorfret-solver --example strand_history_tolerance [-- tol]`.

use std::time::Instant;

use moorfret_solver::contact::{ContactParameters, NormalLaw, TangentialLaw};
use moorfret_solver::strand::history::{
    run_history, HistoryOptions, HistoryResult, LoadSample, NoObserver,
};
use moorfret_solver::strand::model::{StrandModel, StrandModelParameters};
use moorfret_solver::strand::profile::profile_from_json;

#[path = "support/irregular.rs"]
mod irregular;
use irregular::irregular_history;

const BENCHMARK: &str = include_str!(concat!(
    env!("CARGO_MANIFEST_DIR"),
    "/../campaigns/benchmarks/strand_1_6_1.json"
));

/// ε = 1e-3 + 1.5e-4 e(t), κ = 1e-2 k(t) 1/m, 300 s at 0.25 s.
fn history() -> Vec<LoadSample> {
    irregular_history(300.0, 0.25, 1e-3, 1.5e-4, 1e-2)
}

fn max_range(r: &HistoryResult, c: usize) -> f64 {
    r.contacts[c]
        .cycles
        .iter()
        .map(|y| y.slip.range)
        .fold(0.0, f64::max)
}

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let tol: f64 = match std::env::args().nth(1) {
        Some(a) => a.parse()?,
        None => HistoryOptions::default().turning_point_tolerance,
    };
    let strand = profile_from_json(BENCHMARK)?.validate()?;
    let params = StrandModelParameters {
        contact: ContactParameters {
            normal: NormalLaw::Penalty {
                stiffness_n_per_m: 2e8,
            },
            tangential: TangentialLaw::ElasticSlip {
                elastic_slip_m: 1e-7,
            },
            ..ContactParameters::default()
        },
        ..StrandModelParameters::default()
    };
    let model = StrandModel::new(&strand, &params)?;
    let h = history();
    let run = |tolerance: f64| -> Result<HistoryResult, Box<dyn std::error::Error>> {
        let options = HistoryOptions {
            turning_point_tolerance: tolerance,
            ..HistoryOptions::default()
        };
        let t = Instant::now();
        let r = run_history(&model, &h, &options, &mut NoObserver)?;
        println!(
            "tolerance {tolerance}: {} of {} samples solved, {} sub-steps, {} iterations, {:.2} s",
            r.stats.kept_samples,
            r.stats.samples,
            r.stats.substeps,
            r.stats.iterations,
            t.elapsed().as_secs_f64()
        );
        Ok(r)
    };
    let exact = run(0.0)?;
    let reduced = run(tol)?;
    let n = model.contacts.len();
    let scale_range = (0..n).map(|c| max_range(&exact, c)).fold(0.0, f64::max);
    let scale_fn = exact
        .contacts
        .iter()
        .map(|c| c.max_normal_force_n)
        .fold(0.0, f64::max);
    let d_range = (0..n)
        .map(|c| (max_range(&exact, c) - max_range(&reduced, c)).abs())
        .fold(0.0, f64::max);
    let d_fn = (0..n)
        .map(|c| {
            (exact.contacts[c].max_normal_force_n - reduced.contacts[c].max_normal_force_n).abs()
        })
        .fold(0.0, f64::max);
    let cycles = |r: &HistoryResult| r.contacts.iter().map(|c| c.cycles.len()).sum::<usize>();
    println!(
        "largest slip range {scale_range:.4e} m: largest change {:.3} %; peak normal force \
         {scale_fn:.1} N: largest change {:.3} %; cycles {} vs {}",
        100.0 * d_range / scale_range,
        100.0 * d_fn / scale_fn,
        cycles(&exact),
        cycles(&reduced)
    );
    Ok(())
}
