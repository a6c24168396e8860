//! Effect of the turning-point tolerance of [`run_history`] on the results.
//!
//! Two set-ups:
//! - default: the 1+6+1 benchmark strand driven by an irregular (ε, κ) history (five
//!   incommensurate components each, tension and curvature out of phase, 300 s at 0.25 s),
//!   solved with every sample kept (tolerance 0) and with the given tolerance (default: the
//!   library's);
//! - `--six-layer LOAD.csv`: the paper's six-layer strand (periodic ends, the paper campaign's
//!   contact regularisation ε_N = 2e8 N/m, γ_e = 10 µm) driven by a hot-spot history
//!   `time_s,tension_n,curvature_per_m` (or a `moorfret run global` hot-spot file, hot spot 0),
//!   optionally cut to `--from-s A --to-s B`, with ε = T / EA (EA measured on the model unless
//!   `--ea N` is given), solved at every tolerance listed; the first is the reference (one tolerance: that run
//!   alone, e.g. to profile it with `RUST_LOG=moorfret_solver::linalg=trace`).
//!
//! Printed per run: samples solved, sub-steps, Newton iterations, wall time; against the
//! reference: the largest change of every contact's largest slip range and of its peak normal
//! force (relative to the largest value over all contacts), and per layer interface the change
//! of the largest slip range, of the accumulated slip Σ count × range and of the number of slip
//! cycles above 1 µm.
//!
//! `STRAND_CONTACT_LAWS='{"normal":{"law":"contact_mechanics"},"tangential":{"law":"elastic_slip",
//! "elastic_slip_m":1e-6}}'` gives the six-layer strand other contact laws (a
//! [`moorfret_solver::contact::ContactLaws`] in JSON), e.g. to see which of two laws keeps a
//! history from converging.
//!
//! `STRAND_FORCING=η` sets the largest forcing term of the inexact Newton solves
//! ([`moorfret_solver::linalg::NewtonParams::linear_forcing`]); `STRAND_PRECONDITIONER=single`
//! or `double` the precision of the LDLᵀ preconditioner's solves
//! ([`moorfret_solver::strand::history::HistoryOptions::preconditioner_precision`]).
//!
//! Run: `cargo run --release -p moorfret-studies --bin strand_history_tolerance [-- tol]`, or
//! `… -- --six-layer LOAD.csv [--from-s A] [--to-s B] [--ea N] [--threads N] tol_ref tol…`.

use std::time::Instant;

use moorfret_solver::linalg::FactorPrecision;
use moorfret_solver::strand::history::stiffness::{
    measure_axial_stiffness_n, samples_from_tension, SlackTension,
};
use moorfret_solver::strand::history::{
    run_history, HistoryOptions, HistoryResult, LoadSample, NoObserver,
};
use moorfret_solver::strand::model::{EndKind, StrandModel, StrandModelParameters};
use moorfret_solver::strand::profile::{profile_from_json, profiles_from_json};

use moorfret_studies::irregular::irregular_history;
use moorfret_studies::load_file::read_load;
use moorfret_studies::logging;

const BENCHMARK: &str = include_str!(concat!(
    env!("CARGO_MANIFEST_DIR"),
    "/../campaigns/benchmarks/strand_1_6_1.json"
));
const PROFILES: &str = include_str!(concat!(
    env!("CARGO_MANIFEST_DIR"),
    "/../campaigns/data/strand_profiles.json"
));

type Error = Box<dyn std::error::Error>;

fn max_range(r: &HistoryResult, c: usize) -> f64 {
    r.contacts[c]
        .cycles
        .iter()
        .map(|y| y.slip.range)
        .fold(0.0, f64::max)
}

/// Per interface: largest slip range, accumulated slip Σ count × range, cycles above 1 µm.
fn interface_figures(r: &HistoryResult) -> Vec<[f64; 3]> {
    let interfaces = r
        .contacts
        .iter()
        .map(|c| c.interface + 1)
        .max()
        .unwrap_or(0);
    let mut out = vec![[0.0f64; 3]; interfaces];
    for (c, record) in r.contacts.iter().enumerate() {
        let f = &mut out[record.interface];
        f[0] = f[0].max(max_range(r, c));
        for y in &record.cycles {
            f[1] += y.slip.count * y.slip.range;
            if y.slip.range > 1e-6 {
                f[2] += y.slip.count;
            }
        }
    }
    out
}

fn compare(model: &StrandModel, reference: &HistoryResult, reduced: &HistoryResult) {
    let n = model.contacts.len();
    let scale_range = (0..n).map(|c| max_range(reference, c)).fold(0.0, f64::max);
    let scale_fn = reference
        .contacts
        .iter()
        .map(|c| c.max_normal_force_n)
        .fold(0.0, f64::max);
    let d_range = (0..n)
        .map(|c| (max_range(reference, c) - max_range(reduced, c)).abs())
        .fold(0.0, f64::max);
    let d_fn = (0..n)
        .map(|c| {
            (reference.contacts[c].max_normal_force_n - reduced.contacts[c].max_normal_force_n)
                .abs()
        })
        .fold(0.0, f64::max);
    let cycles = |r: &HistoryResult| r.contacts.iter().map(|c| c.cycles.len()).sum::<usize>();
    println!(
        "  largest slip range {scale_range:.4e} m: largest change {:.3} %; peak normal force \
         {scale_fn:.1} N: largest change {:.3} %; cycles {} vs {}",
        100.0 * d_range / scale_range,
        100.0 * d_fn / scale_fn,
        cycles(reference),
        cycles(reduced)
    );
    let rel = |a: f64, b: f64| if a != 0.0 { 100.0 * (b - a) / a } else { 0.0 };
    for (i, (a, b)) in interface_figures(reference)
        .iter()
        .zip(interface_figures(reduced))
        .enumerate()
    {
        println!(
            "  interface {i}: largest slip range {:.3e} m ({:+.2} %), accumulated slip {:.3e} m \
             ({:+.2} %), cycles above 1 µm {:.1} ({:+.2} %)",
            b[0],
            rel(a[0], b[0]),
            b[1],
            rel(a[1], b[1]),
            b[2],
            rel(a[2], b[2])
        );
    }
}

fn run(
    model: &StrandModel,
    samples: &[LoadSample],
    tolerance: f64,
    threads: usize,
) -> Result<HistoryResult, Error> {
    let mut options = HistoryOptions {
        turning_point_tolerance: tolerance,
        threads,
        ..HistoryOptions::default()
    };
    if let Some(f) = std::env::var_os("STRAND_FORCING") {
        options.newton.linear_forcing = f.to_string_lossy().parse()?;
    }
    if let Some(p) = std::env::var_os("STRAND_PRECONDITIONER") {
        options.preconditioner_precision = match p.to_string_lossy().as_ref() {
            "single" => FactorPrecision::Single,
            "double" => FactorPrecision::Double,
            other => return Err(format!("STRAND_PRECONDITIONER={other}: single or double").into()),
        };
    }
    let t = Instant::now();
    let r = run_history(model, samples, &options, &mut NoObserver)?;
    let (s, w, l) = (&r.stats, &r.stats.work, &r.stats.linear);
    println!(
        "tolerance {tolerance}: {} of {} samples solved, {} sub-steps ({} in the \
         initialisation), {} Newton iterations, {} cut-backs, {:.1} s (initialisation {:.1} s); \
         assembly {:.1} s, factorisation {:.1} s, solves {:.1} s; {} GMRES solves, {} \
         iterations, {} LDLᵀ factorisations, {} reuses, {} refreshes, {} LU fallbacks",
        s.kept_samples,
        s.samples,
        s.substeps,
        s.initialisation_substeps,
        s.iterations,
        s.cutbacks,
        t.elapsed().as_secs_f64(),
        s.initialisation_time_s,
        w.assembly_s,
        w.factorisation_s,
        w.solve_s,
        l.solves,
        l.iterations,
        l.factorisations,
        l.reuses,
        l.refreshes,
        l.lu_fallbacks
    );
    Ok(r)
}

fn six_layer(args: &[String]) -> Result<(), Error> {
    let (mut load, mut from, mut to, mut ea, mut threads) =
        (None, f64::NEG_INFINITY, f64::INFINITY, None, 1);
    let mut tolerances = Vec::new();
    let mut it = args.iter();
    while let Some(a) = it.next() {
        let mut value = || it.next().ok_or(format!("{a} needs a value"));
        match a.as_str() {
            "--six-layer" => load = Some(value()?.clone()),
            "--from-s" => from = value()?.parse()?,
            "--to-s" => to = value()?.parse()?,
            "--ea" => ea = Some(value()?.parse::<f64>()?),
            "--threads" => threads = value()?.parse()?,
            t => tolerances.push(t.parse::<f64>()?),
        }
    }
    let load = load.ok_or("--six-layer LOAD.csv")?;
    if tolerances.is_empty() {
        return Err("give a reference tolerance (and others to compare with it)".into());
    }
    let strand = profiles_from_json(PROFILES)?
        .get("paper_six_layer")
        .ok_or("profile paper_six_layer missing")?
        .validate()?;
    let mut params = StrandModelParameters::penalty_contact(2e8, 1e-5, EndKind::Periodic);
    if let Ok(laws) = std::env::var("STRAND_CONTACT_LAWS") {
        params.contact = serde_json::from_str(&laws)
            .map_err(|e| format!("STRAND_CONTACT_LAWS is not a contact-law pair: {e}"))?;
        println!("contact laws {:?}", params.contact);
    }
    let model = StrandModel::new(&strand, &params)?;
    let ea = match ea {
        Some(v) => v,
        None => {
            let t = Instant::now();
            let options = HistoryOptions {
                threads,
                ..HistoryOptions::default()
            };
            let v = measure_axial_stiffness_n(&model, 1e-3, &options)?;
            println!(
                "EA = {v:.4e} N, measured in {:.1} s",
                t.elapsed().as_secs_f64()
            );
            v
        }
    };
    let [t, tension, kappa] = read_load(&load, from, to)?;
    let (samples, _) = samples_from_tension(&t, &tension, &kappa, ea, 1, SlackTension::Refuse)?;
    println!(
        "{} samples, t = {:.1} … {:.1} s",
        samples.len(),
        t.first().copied().unwrap_or(0.0),
        t.last().copied().unwrap_or(0.0)
    );
    let reference = run(&model, &samples, tolerances[0], threads)?;
    for &tol in &tolerances[1..] {
        let reduced = run(&model, &samples, tol, threads)?;
        compare(&model, &reference, &reduced);
    }
    Ok(())
}

fn main() -> Result<(), Error> {
    logging::init();
    let args: Vec<String> = std::env::args().skip(1).collect();
    if args.iter().any(|a| a == "--six-layer") {
        return six_layer(&args);
    }
    let tol: f64 = match args.first() {
        Some(a) => a.parse()?,
        None => HistoryOptions::default().turning_point_tolerance,
    };
    let strand = profile_from_json(BENCHMARK)?.validate()?;
    let params = StrandModelParameters::penalty_contact(2e8, 1e-7, EndKind::PenaltyTies);
    let model = StrandModel::new(&strand, &params)?;
    // ε = 1e-3 + 1.5e-4 e(t), κ = 1e-2 k(t) 1/m, 300 s at 0.25 s
    let h = irregular_history(300.0, 0.25, 1e-3, 1.5e-4, 1e-2);
    let exact = run(&model, &h, 0.0, 1)?;
    let reduced = run(&model, &h, tol, 1)?;
    compare(&model, &exact, &reduced);
    Ok(())
}
