//! `moorfret strand …`: the reduced strand response on its own.
//!
//! - `calibrate`: calibrate the reduced response of a strand model over the range of one or more
//!   load histories and/or given ranges, into the cache (and `--out FILE`), and print how well
//!   it reproduces its own calibration run;
//! - `compare`: compare two history runs of the same strand model (`moorfret run strand
//!   --load`, e.g. `--fidelity reduced` against `fe`), per layer interface (largest slip range,
//!   accumulated slip and number of the cycles of at least `--min-slip-range-m`) and per contact
//!   class (the damage inputs of the campaigns' default fatigue settings).

use crate::cli::output::outln;
use std::path::{Path, PathBuf};

use anyhow::{anyhow, bail, Context};
use clap::{Args, Subcommand};
use moorfret_campaign::fatigue::FatigueSpec;
use moorfret_solver::damage::{sea_state_damage_inputs, SeaStateInputs, TensionHistory};
use moorfret_solver::fretting::ContactRecord;
use moorfret_solver::strand::history::stiffness::straight_strand_stiffness;
use moorfret_solver::strand::history::HistoryOptions;
use moorfret_solver::strand::profile::Strand;
use moorfret_solver::strand::reduced::compare::{
    compare_records, relative_difference, InterfaceComparison,
};
use moorfret_solver::strand::reduced::LoadRange;

use super::run::strand_history::{samples_of, Observer, StiffnessArgs};
use super::run::strand_model::{load_strand, ModelArgs};
use super::run::strand_reduced::{
    calibration_for, range_of, write_calibration, CalibrationRequest,
};
use moorfret_solver::global::series::LoadTable;
use moorfret_worker::strand::load::{read_load, table_strain};
use moorfret_worker::strand::LazyModel;

/// The reduced strand response on its own.
#[derive(Debug, Subcommand)]
pub(crate) enum StrandCommand {
    /// Calibrate the reduced response of a strand model over load histories or ranges (kept
    /// in the cache; `--out` also writes it).
    Calibrate(CalibrateArgs),
    /// Compare two history runs of the same strand model, interface by interface and class by
    /// class (e.g. `--fidelity reduced` against `fe`).
    Compare(CompareArgs),
    /// Fretting damage of one history run per contact class under both fretting laws, and the
    /// life to the first crack of its most damaged contact.
    Fretting(FrettingArgs),
}

/// Arguments of `moorfret strand calibrate`.
#[derive(Debug, Args)]
#[command(allow_negative_numbers = true)]
pub(crate) struct CalibrateArgs {
    /// The strand model.
    #[command(flatten)]
    model: ModelArgs,
    /// Load history whose range the calibration covers (repeatable; columns as `run strand
    /// --load`).
    #[arg(long)]
    load: Vec<PathBuf>,
    /// Hot spot to read from a global run's `hotspots.csv` (as `run strand --hot-spot`).
    #[arg(long, default_value_t = 0)]
    hot_spot: usize,
    /// Axial strain range to cover, lowest and highest.
    #[arg(long, num_args = 2, value_names = ["LOW", "HIGH"], allow_negative_numbers = true)]
    strain_range: Option<Vec<f64>>,
    /// Curvature range to cover (1/m), lowest and highest (negative values allowed).
    #[arg(long, num_args = 2, value_names = ["LOW", "HIGH"], allow_negative_numbers = true)]
    curvature_range: Option<Vec<f64>>,
    /// Margin on each side of the range, as a fraction of it.
    #[arg(long, default_value_t = 0.05)]
    margin: f64,
    /// Threads of the FE calibration run.
    #[arg(long, default_value_t = 1, value_parser = clap::value_parser!(u16).range(1..=256))]
    threads: u16,
    /// Also write the calibration to this file (for `run strand --calibration`).
    #[arg(long)]
    out: Option<PathBuf>,
    /// EA and cache.
    #[command(flatten)]
    stiffness: StiffnessArgs,
}

/// Arguments of `moorfret strand compare`.
#[derive(Debug, Args)]
#[command(allow_negative_numbers = true)]
pub(crate) struct CompareArgs {
    /// The strand model both runs used (for the contact geometry of the damage inputs).
    #[command(flatten)]
    model: ModelArgs,
    /// Output directory of the reference run (e.g. the FE run).
    reference: PathBuf,
    /// Output directory of the compared run (e.g. the reduced run).
    compared: PathBuf,
    /// Smallest slip range of the counted cycles (m).
    #[arg(long, default_value_t = 1e-6)]
    min_slip_range_m: f64,
    /// Run-in left out of the statistics (s).
    #[arg(long, default_value_t = 0.0)]
    run_in_s: f64,
    /// The load history both runs were driven through (default: the `load` their summaries
    /// name, which must be the same file).
    #[arg(long)]
    load: Option<PathBuf>,
    /// Write the comparison as JSON to this file.
    #[arg(long)]
    json: Option<PathBuf>,
    /// Leave out the contacts within this distance (m) of the model's ends, z = 0 and z = L
    /// (with periodic ends, of the seam where the far ends are tied to the start ends), in
    /// both runs: the figures away from the end zone.
    #[arg(long, default_value_t = 0.0)]
    end_zone_m: f64,
}

/// Arguments of `moorfret strand fretting`.
#[derive(Debug, Args)]
#[command(allow_negative_numbers = true)]
pub(crate) struct FrettingArgs {
    /// The strand model of the run (for the contact geometry).
    #[command(flatten)]
    model: ModelArgs,
    /// Output directory of a `run strand --load` run.
    run: PathBuf,
    /// Run-in left out of the statistics (s).
    #[arg(long, default_value_t = 0.0)]
    run_in_s: f64,
    /// Wire surface of the contact-stress law: `bright`, `galvanised`, `sea_water`.
    #[arg(long, default_value = "galvanised")]
    wire_surface: String,
    /// Period of one load cycle (s): also print lives in load cycles.
    #[arg(long)]
    cycle_period_s: Option<f64>,
    /// The load history of the run (default: the `load` its summary names).
    #[arg(long)]
    load: Option<PathBuf>,
    /// Critical distance L of the contact-stress law (m), in place of the default.
    #[arg(long)]
    critical_distance_m: Option<f64>,
}

/// Execute a `strand` subcommand.
pub(crate) fn execute(cmd: StrandCommand) -> anyhow::Result<()> {
    match cmd {
        StrandCommand::Calibrate(args) => calibrate(&args),
        StrandCommand::Compare(args) => compare(&args),
        StrandCommand::Fretting(args) => fretting(&args),
    }
}

fn pair(v: &Option<Vec<f64>>, name: &str) -> anyhow::Result<Option<[f64; 2]>> {
    match v.as_deref() {
        None => Ok(None),
        Some(&[lo, hi]) if lo.is_finite() && hi.is_finite() && lo < hi => Ok(Some([lo, hi])),
        Some(other) => bail!("--{name} {other:?}: give two finite numbers, the lower first"),
    }
}

fn calibrate(args: &CalibrateArgs) -> anyhow::Result<()> {
    if !(args.margin.is_finite() && (0.0..=1.0).contains(&args.margin)) {
        bail!("--margin {}: must lie in [0, 1]", args.margin);
    }
    let (_, strand, params) = load_strand(&args.model)?;
    let mut lazy = LazyModel::new(&strand, &params);
    let options = HistoryOptions {
        threads: usize::from(args.threads),
        ..HistoryOptions::default()
    };
    let mut range: Option<LoadRange> = None;
    for path in &args.load {
        let table = read_load(path, true, args.hot_spot)?;
        let (samples, _, _) = samples_of(&table, &mut lazy, &args.stiffness, &options)?;
        let r = range_of(&samples).with_context(|| format!("in {}", path.display()))?;
        range = Some(range.map_or(r, |a| a.union(r)));
    }
    let strain = pair(&args.strain_range, "strain-range")?;
    let curvature = pair(&args.curvature_range, "curvature-range")?;
    let range = match (range, strain, curvature) {
        (r, Some(s), Some(k)) => {
            let given = LoadRange {
                strain: s,
                curvature_per_m: k,
            };
            r.map_or(given, |r| r.union(given))
        }
        (Some(r), s, k) => {
            let mut r = r;
            if let Some(s) = s {
                r = r.union(LoadRange {
                    strain: s,
                    curvature_per_m: r.curvature_per_m,
                });
            }
            if let Some(k) = k {
                r = r.union(LoadRange {
                    strain: r.strain,
                    curvature_per_m: k,
                });
            }
            r
        }
        (None, _, _) => bail!(
            "nothing to calibrate over: give --load FILE, or both --strain-range and \
             --curvature-range"
        ),
    };
    let range = range.widened(args.margin);
    let request = CalibrationRequest {
        strand: &strand,
        params: &params,
        cache_dir: args.stiffness.cache_dir.as_deref(),
        given: None,
        threads: usize::from(args.threads),
        refresh: args.stiffness.no_cache,
    };
    let mut observer = Observer::progress_only();
    let mut build = || {
        moorfret_solver::strand::model::StrandModel::new(&strand, &params)
            .map_err(anyhow::Error::from)
    };
    let (reduced, source) = calibration_for(&request, &range, range, &mut build, &mut observer)?;
    observer.finish();
    outln!(
        "reduced strand response {} ({}): {} contacts, strain {:.4e} … {:.4e}, curvature \
         {:.4e} … {:.4e} 1/m",
        source.source,
        source.file.as_deref().unwrap_or("not cached"),
        reduced.laws.len(),
        reduced.range.strain[0],
        reduced.range.strain[1],
        reduced.range.curvature_per_m[0],
        reduced.range.curvature_per_m[1],
    )?;
    let c = &reduced.calibration;
    outln!(
        "calibration run: {} samples, {} FE sub-steps, {} Newton iterations, {:.1} s",
        c.design_samples,
        c.fe_substeps,
        c.fe_iterations,
        c.fe_wall_time_s
    )?;
    for (k, chain) in c.chains.iter().enumerate() {
        outln!(
            "  chain {k}: {} samples, {} sub-steps, {} iterations, {:.1} s",
            chain.samples,
            chain.substeps,
            chain.iterations,
            chain.wall_time_s
        )?;
    }
    if let Some(m) = &reduced.modes {
        outln!(
            "collective modes of the interfaces, known after {:.1} s (beside the chains): \
             own amplification, uniform / bending, per interface",
            c.modes_wall_time_s
        )?;
        for (x, table) in m.knots.iter().zip(&m.amplification) {
            let own: Vec<String> = table
                .iter()
                .enumerate()
                .map(|(i, row)| format!("{:.2}/{:.2}", row[i][0], row[i][1]))
                .collect();
            outln!("  scaled tension {x:+.2}: {}", own.join("  "))?;
        }
    }
    outln!("interface  slip rms resid/spread  f_N rms resid/spread  refit  replay: max range  accumulated  cycles  as range")?;
    for (f, r) in c.fits.iter().zip(&c.replay) {
        outln!(
            "{:>9}  {:>9.2e} / {:<9.2e}  {:>8.2e} / {:<9.2e}  {:>5}  {:>+16.1}%  {:>+10.1}%  {:>+5.1}%  {:>8}",
            f.interface,
            f.slip_rms_residual_m,
            f.slip_rms_m,
            f.normal_rms_residual_n,
            f.normal_rms_n,
            f.compliance_clamped,
            100.0 * r.max_slip_range_error,
            100.0 * r.accumulated_slip_error,
            100.0 * r.cycles_error,
            r.cycles_as_range_label()
        )?;
    }
    if let Some(out) = &args.out {
        write_calibration(out, &reduced)?;
        outln!("written to {}", out.display())?;
    }
    Ok(())
}

/// Contact records and load of a `run strand --load` output directory (`summary.json`).
struct RunOutput {
    records: Vec<ContactRecord>,
    /// The load file as the run's summary names it.
    load: PathBuf,
    hot_spot: usize,
    slack_as_zero: bool,
    samples: usize,
    /// EA of a tension history's conversion (none for a strain history).
    ea_n: Option<f64>,
}

/// The load both compared runs were driven through, and its time step.
struct SharedLoad {
    table: LoadTable,
    dt_s: f64,
}

fn read_json<T: serde::de::DeserializeOwned>(path: &Path) -> anyhow::Result<T> {
    let text =
        std::fs::read_to_string(path).with_context(|| format!("reading {}", path.display()))?;
    serde_json::from_str(&text).with_context(|| format!("reading {}", path.display()))
}

fn read_run(dir: &Path) -> anyhow::Result<RunOutput> {
    let records: Vec<ContactRecord> = read_json(&dir.join("contact_records.json"))?;
    let path = dir.join("summary.json");
    let summary: serde_json::Value = read_json(&path)?;
    let field = |name: &str| {
        summary
            .get(name)
            .ok_or_else(|| anyhow!("{}: no `{name}`", path.display()))
    };
    let load = field("load")?
        .as_str()
        .ok_or_else(|| anyhow!("{}: `load` is not a path", path.display()))?;
    let samples = field("samples")?
        .as_u64()
        .ok_or_else(|| anyhow!("{}: `samples` is not a count", path.display()))?;
    Ok(RunOutput {
        records,
        load: PathBuf::from(load),
        hot_spot: summary
            .get("hot_spot")
            .and_then(serde_json::Value::as_u64)
            .unwrap_or(0) as usize,
        slack_as_zero: summary
            .get("slack_as_zero")
            .and_then(serde_json::Value::as_bool)
            .unwrap_or(false),
        samples: samples as usize,
        ea_n: summary
            .pointer("/axial_stiffness/ea_n")
            .and_then(serde_json::Value::as_f64),
    })
}

/// The load of the compared runs, read from `given` or from the load file their summaries name
/// (the same for both).
fn shared_load(given: Option<&Path>, a: &RunOutput, b: &RunOutput) -> anyhow::Result<SharedLoad> {
    if given.is_none() && a.load != b.load {
        bail!(
            "the runs name different load files ({} and {}); give --load if they hold the \
             same history",
            a.load.display(),
            b.load.display()
        );
    }
    let path = given.unwrap_or(&a.load);
    let table = read_load(path, a.slack_as_zero, a.hot_spot)
        .context("the load of the compared runs (--load to give it)")?;
    for run in [a, b] {
        if run.samples != table.time_s.as_slice().len() {
            bail!(
                "{}: {} samples, but a run was driven through {}",
                path.display(),
                table.time_s.as_slice().len(),
                run.samples
            );
        }
    }
    let time = table.time_s.as_slice();
    if time.len() < 2 {
        bail!("{}: fewer than two samples", path.display());
    }
    let dt_s = (time[time.len() - 1] - time[0]) / (time.len() - 1) as f64;
    Ok(SharedLoad { table, dt_s })
}

fn damage_inputs(
    run: &RunOutput,
    load: &SharedLoad,
    strand: &Strand,
    run_in_samples: usize,
) -> anyhow::Result<SeaStateInputs> {
    damage_inputs_with(run, load, strand, run_in_samples, &FatigueSpec::default())
}

fn damage_inputs_with(
    run: &RunOutput,
    load: &SharedLoad,
    strand: &Strand,
    run_in_samples: usize,
    spec: &FatigueSpec,
) -> anyhow::Result<SeaStateInputs> {
    // the wire stress of the damage inputs is T / A with A = EA / E, i.e. E ε whatever EA is:
    // a strain history takes the straight-strand EA
    let ea_n = run
        .ea_n
        .unwrap_or_else(|| straight_strand_stiffness(strand).simple_n);
    let config = spec.fretting_config(strand, ea_n);
    let tension: Vec<f64> = table_strain(&load.table, run.ea_n)?
        .iter()
        .map(|e| e * ea_n)
        .collect();
    let history = TensionHistory {
        tension_n: &tension,
        dt_s: load.dt_s,
        run_in_samples,
    };
    Ok(sea_state_damage_inputs(&run.records, &history, &config)?)
}

fn fretting(args: &FrettingArgs) -> anyhow::Result<()> {
    let (_, strand, _) = load_strand(&args.model)?;
    let run = read_run(&args.run)?;
    let load = shared_load(args.load.as_deref(), &run, &run)?;
    if !(args.run_in_s >= 0.0 && args.run_in_s.is_finite()) {
        bail!("--run-in-s {}: must be finite and ≥ 0", args.run_in_s);
    }
    if let Some(p) = args.cycle_period_s {
        if !(p > 0.0 && p.is_finite()) {
            bail!("--cycle-period-s {p}: must be finite and > 0");
        }
    }
    let wire_surface = serde_json::from_value(serde_json::Value::String(args.wire_surface.clone()))
        .map_err(|_| {
            anyhow!(
                "--wire-surface `{}`: one of bright, galvanised, sea_water",
                args.wire_surface
            )
        })?;
    let spec = FatigueSpec {
        wire_surface,
        critical_distance_m: args.critical_distance_m,
        ..FatigueSpec::default()
    };
    spec.contact_stress_law()
        .validate()
        .map_err(|e| anyhow!("--critical-distance-m: {e}"))?;
    let run_in = (args.run_in_s / load.dt_s).round() as usize;
    let inputs = damage_inputs_with(&run, &load, &strand, run_in, &spec)?;
    let period = args.cycle_period_s;
    outln!(
        "per contact class, damage rate (1/s) of the most damaged contact: contact stress \
         ({}), rope S-N per slip cycle; cycles per hour by regime (contact-stress law)",
        args.wire_surface
    )?;
    outln!(
        "{:<24} {:>8} {:>12} {:>12} {:>10} {:>10} {:>10}{}",
        "class",
        "p0_GPa",
        "stress_max",
        "rope_tn_max",
        "stick/h",
        "partial/h",
        "gross/h",
        if period.is_some() {
            "   life_stress   life_rope_tn (load cycles)"
        } else {
            ""
        }
    )?;
    let life = |rate: f64| match period {
        Some(p) if rate > 0.0 => format!("{:>14.3e}", 1.0 / (rate * p)),
        Some(_) => format!("{:>14}", "inf"),
        None => String::new(),
    };
    let mut worst = (0.0_f64, 0.0_f64);
    for c in &inputs.classes {
        let r = &c.regime_cycles_per_hour;
        outln!(
            "{:<24} {:>8.2} {:>12.3e} {:>12.3e} {:>10.1} {:>10.1} {:>10.1}{}{}",
            format!("{}/{}", c.class.interface, c.class.position.as_str()),
            c.peak_pressure_max_pa * 1e-9,
            c.contact_stress_damage_rate_max_per_s,
            c.rope_tn_damage_rate_max_per_s,
            r.stick,
            r.partial_slip,
            r.gross_slip,
            life(c.contact_stress_damage_rate_max_per_s),
            life(c.rope_tn_damage_rate_max_per_s),
        )?;
        worst.0 = worst.0.max(c.contact_stress_damage_rate_max_per_s);
        worst.1 = worst.1.max(c.rope_tn_damage_rate_max_per_s);
    }
    outln!(
        "most damaged contact: {:.3e} 1/s (contact stress), {:.3e} 1/s (rope S-N per slip cycle){}",
        worst.0,
        worst.1,
        match period {
            Some(_) => format!(
                "; first crack after{} and{} load cycles",
                life(worst.0),
                life(worst.1)
            ),
            None => String::new(),
        }
    )?;
    Ok(())
}

fn compare(args: &CompareArgs) -> anyhow::Result<()> {
    let (_, strand, _) = load_strand(&args.model)?;
    let mut a = read_run(&args.reference)?;
    let mut b = read_run(&args.compared)?;
    if a.records.len() != b.records.len() {
        bail!(
            "{} has {} contacts, {} has {}: not the same strand model",
            args.reference.display(),
            a.records.len(),
            args.compared.display(),
            b.records.len()
        );
    }
    let length = strand.model_length_m;
    if !(args.end_zone_m >= 0.0 && args.end_zone_m < 0.5 * length) {
        bail!(
            "--end-zone-m {}: must be ≥ 0 and below half the model length ({length} m)",
            args.end_zone_m
        );
    }
    if args.end_zone_m > 0.0 {
        let zone = args.end_zone_m;
        let keep: Vec<bool> = a
            .records
            .iter()
            .map(|r| r.z_m.min(length - r.z_m) >= zone)
            .collect();
        for run in [&mut a, &mut b] {
            let mut k = keep.iter();
            run.records.retain(|_| k.next().copied().unwrap_or(false));
        }
        outln!(
            "{} of {} contacts, those at least {zone} m from the model's ends",
            a.records.len(),
            keep.len()
        )?;
    }
    if !(args.run_in_s >= 0.0 && args.run_in_s.is_finite()) {
        bail!("--run-in-s {}: must be finite and ≥ 0", args.run_in_s);
    }
    let load = shared_load(args.load.as_deref(), &a, &b)?;
    let run_in = (args.run_in_s / load.dt_s).round() as usize;
    let interfaces = compare_records(&a.records, &b.records, args.min_slip_range_m, run_in);
    outln!(
        "per interface, cycles of at least {:.2e} m after {} s (compared / reference − 1):",
        args.min_slip_range_m,
        args.run_in_s
    )?;
    outln!("{}", InterfaceComparison::HEADER)?;
    for c in &interfaces {
        outln!("{c}")?;
    }
    let da = damage_inputs(&a, &load, &strand, run_in)?;
    let db = damage_inputs(&b, &load, &strand, run_in)?;
    outln!("per contact class, damage inputs (compared / reference − 1):")?;
    outln!("class                      fretting damage rate mean       max              slip cycles/h (all regimes)")?;
    let mut classes = Vec::new();
    for ca in &da.classes {
        let Some(cb) = db.classes.iter().find(|c| c.class == ca.class) else {
            continue;
        };
        let total =
            |r: &moorfret_solver::damage::RegimeCounts| r.stick + r.partial_slip + r.gross_slip;
        let row = serde_json::json!({
            "interface": ca.class.interface,
            "position": ca.class.position.as_str(),
            "damage_rate_mean_per_s": [ca.fretting_damage_rate_mean_per_s, cb.fretting_damage_rate_mean_per_s],
            "damage_rate_max_per_s": [ca.fretting_damage_rate_max_per_s, cb.fretting_damage_rate_max_per_s],
            "cycles_per_hour": [total(&ca.regime_cycles_per_hour), total(&cb.regime_cycles_per_hour)],
        });
        outln!(
            "{:>2} {:<22} {:.3e} → {:.3e} {:>+6.1}%  {:.3e} → {:.3e} {:>+6.1}%  {:.3e} → {:.3e} {:>+6.1}%",
            ca.class.interface,
            ca.class.position.as_str(),
            ca.fretting_damage_rate_mean_per_s,
            cb.fretting_damage_rate_mean_per_s,
            100.0
                * relative_difference(
                    ca.fretting_damage_rate_mean_per_s,
                    cb.fretting_damage_rate_mean_per_s
                ),
            ca.fretting_damage_rate_max_per_s,
            cb.fretting_damage_rate_max_per_s,
            100.0
                * relative_difference(
                    ca.fretting_damage_rate_max_per_s,
                    cb.fretting_damage_rate_max_per_s
                ),
            total(&ca.regime_cycles_per_hour),
            total(&cb.regime_cycles_per_hour),
            100.0
                * relative_difference(
                    total(&ca.regime_cycles_per_hour),
                    total(&cb.regime_cycles_per_hour)
                ),
        )?;
        classes.push(row);
    }
    if let Some(path) = &args.json {
        let doc = serde_json::json!({
            "reference": args.reference.display().to_string(),
            "compared": args.compared.display().to_string(),
            "min_slip_range_m": args.min_slip_range_m,
            "run_in_s": args.run_in_s,
            "end_zone_m": args.end_zone_m,
            "interfaces": interfaces,
            "classes": classes,
        });
        std::fs::write(path, serde_json::to_vec_pretty(&doc)?)
            .with_context(|| format!("writing {}", path.display()))?;
    }
    Ok(())
}
