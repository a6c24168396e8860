//! Sweep of the global stage over the cells of a wave scatter diagram, one cell after the other
//! on one thread, for measuring which cells complete and what each costs.
//!
//! Every non-zero cell becomes a sea state with Hs at the middle of its height bin and Tp at
//! its column value, the given γ and seed; the case file supplies everything else (its own
//! `sea_state` is replaced). Per cell it prints Hs, Tp, the wall time of the whole run
//! (precomputation, statics and dynamics) and its CPU time (`/proc/self/stat`, Linux), time
//! steps, coupling passes, coupled step cuts, the lines' Newton iterations, factorisations,
//! step cuts and stalled attempts, the
//! high-frequency cut-off the stage chose, and the outcome (`ok`, the error, or `PANIC` and its
//! message); then the median, p90 and worst wall times of the completed cells and the ratio of
//! the worst to the median.
//!
//! ```text
//! cargo run --release -p moorfret-studies --bin global_sweep -- \
//!     CASE.json SCATTER.tsv DURATION_S GAMMA SEED \
//!     [--tp-max S] [--tp-min S] [--hs-max M] [--hs-min M] [--every N] [--cell HS,TP]...
//! ```
//!
//! `--tp-max`/`--tp-min`/`--hs-max`/`--hs-min` restrict the sweep to a part of the diagram,
//! `--every N` keeps every N-th remaining cell (a sample), `--cell HS,TP` runs the given sea
//! states instead of the diagram's cells, `--no-mirror` solves every line (also those the
//! stage would write as the mirror image of another). Paths inside the case are resolved relative to it.

use std::path::Path;
use std::time::Instant;

use moorfret_solver::floater::prescribed::PrescribedMotion;
use moorfret_solver::floater::FloaterSpec;
use moorfret_solver::global::case::{FloaterSource, GammaSpec};
use moorfret_solver::global::results::SeriesSummary;
use moorfret_solver::global::{run, CaseSpec, FloaterInput, GlobalModel, RunParams};
use moorfret_solver::waves::{IrregularSea, Jonswap, ScatterTable};

struct Options {
    case_path: String,
    scatter_path: String,
    duration_s: f64,
    gamma: f64,
    seed: u64,
    tp_range: (f64, f64),
    hs_range: (f64, f64),
    every: usize,
    cells: Vec<(f64, f64)>,
    variant: Variant,
}

/// Settings changed from the stage's own choices, for diagnosis.
#[derive(Clone, Copy, Default)]
struct Variant {
    /// Floater sea by direct summation instead of the table.
    direct_floater: bool,
    /// Wave components above this frequency (rad/s) dropped.
    cut_off_rad_s: Option<f64>,
    /// Node spacing of the floater table (m).
    table_spacing_m: Option<f64>,
    /// Every line solved, also those that mirror another.
    no_mirror: bool,
}

fn options() -> Result<Options, String> {
    let mut args = std::env::args().skip(1);
    let mut positional = Vec::new();
    let mut o = Options {
        case_path: String::new(),
        scatter_path: String::new(),
        duration_s: 0.0,
        gamma: 0.0,
        seed: 0,
        tp_range: (0.0, f64::INFINITY),
        hs_range: (0.0, f64::INFINITY),
        every: 1,
        cells: Vec::new(),
        variant: Variant::default(),
    };
    while let Some(a) = args.next() {
        let mut number = |name: &str| -> Result<f64, String> {
            args.next()
                .and_then(|v| v.parse::<f64>().ok())
                .ok_or_else(|| format!("{name} needs a number"))
        };
        match a.as_str() {
            "--tp-max" => o.tp_range.1 = number("--tp-max")?,
            "--tp-min" => o.tp_range.0 = number("--tp-min")?,
            "--hs-max" => o.hs_range.1 = number("--hs-max")?,
            "--hs-min" => o.hs_range.0 = number("--hs-min")?,
            "--direct-floater" => o.variant.direct_floater = true,
            "--no-mirror" => o.variant.no_mirror = true,
            "--cut-off" => o.variant.cut_off_rad_s = Some(number("--cut-off")?),
            "--table-spacing" => o.variant.table_spacing_m = Some(number("--table-spacing")?),
            "--every" => o.every = number("--every")?.max(1.0) as usize,
            "--cell" => {
                let v = args.next().ok_or("--cell needs HS,TP")?;
                let (hs, tp) = v.split_once(',').ok_or("--cell needs HS,TP")?;
                let parse = |s: &str| s.trim().parse::<f64>().map_err(|e| format!("{v}: {e}"));
                o.cells.push((parse(hs)?, parse(tp)?));
            }
            _ => positional.push(a),
        }
    }
    let [case, scatter, duration, gamma, seed] = positional.as_slice() else {
        return Err(
            "usage: global_sweep CASE.json SCATTER.tsv DURATION_S GAMMA SEED [--tp-max S] \
             [--tp-min S] [--hs-max M] [--hs-min M] [--every N] [--cell HS,TP]..."
                .into(),
        );
    };
    o.case_path = case.clone();
    o.scatter_path = scatter.clone();
    o.duration_s = duration.parse().map_err(|e| format!("duration: {e}"))?;
    o.gamma = gamma.parse().map_err(|e| format!("gamma: {e}"))?;
    o.seed = seed.parse().map_err(|e| format!("seed: {e}"))?;
    Ok(o)
}

fn read(path: &Path) -> Result<String, String> {
    std::fs::read_to_string(path).map_err(|e| format!("reading {}: {e}", path.display()))
}

/// The floater content named by the case, read relative to the case file.
fn floater_input(case: &CaseSpec, case_path: &Path) -> Result<FloaterInput, String> {
    let base = case_path.parent().unwrap_or(Path::new("."));
    Ok(match &case.floater {
        FloaterSource::RigidBody { spec_path } => FloaterInput::RigidBody(Box::new(
            FloaterSpec::from_json_str(&read(&base.join(spec_path))?).map_err(|e| e.to_string())?,
        )),
        FloaterSource::PrescribedMotion { csv_path } => FloaterInput::Prescribed(
            PrescribedMotion::from_csv_str(&read(&base.join(csv_path))?)
                .map_err(|e| e.to_string())?,
        ),
    })
}

/// What one cell's run gave.
struct CellOutcome {
    wall_s: f64,
    /// CPU time of the process over the run (s), less sensitive than the wall time to other
    /// jobs on a shared machine.
    cpu_s: f64,
    steps: usize,
    passes: usize,
    cuts: usize,
    /// Line Newton iterations, factorisations, step cuts and attempts given up for lack of
    /// progress, over all lines.
    line_work: (usize, usize, usize, usize),
    cut_off: String,
    /// Standard deviations of tension (N) and curvature (1/m) at the first hot spot.
    hot_spot_std: (f64, f64),
    outcome: String,
}

/// User + system CPU time of this process (s) from `/proc/self/stat` (Linux; NaN elsewhere),
/// in clock ticks of 10 ms.
fn cpu_time_s() -> f64 {
    let Ok(stat) = std::fs::read_to_string("/proc/self/stat") else {
        return f64::NAN;
    };
    // Fields after the parenthesised command name: utime and stime are the 12th and 13th.
    let rest = stat.rsplit_once(')').map_or("", |(_, r)| r);
    let ticks: Vec<f64> = rest
        .split_whitespace()
        .skip(11)
        .take(2)
        .filter_map(|v| v.parse().ok())
        .collect();
    if ticks.len() == 2 {
        (ticks[0] + ticks[1]) / 100.0
    } else {
        f64::NAN
    }
}

fn run_cell(case: &CaseSpec, floater: &FloaterInput, v: Variant) -> CellOutcome {
    let clock = Instant::now();
    let cpu0 = cpu_time_s();
    let attempt = std::panic::catch_unwind(std::panic::AssertUnwindSafe(|| {
        let mut model = GlobalModel::new(case, floater.clone(), None)?;
        let mut params = RunParams::default();
        if v.direct_floater {
            params.dynamics.floater_table = None;
        }
        params.dynamics.mirror_lines = !v.no_mirror;
        if let (Some(t), Some(d)) = (params.dynamics.floater_table.as_mut(), v.table_spacing_m) {
            t.spacing_along_m = d;
            t.spacing_stretched_m = d;
        }
        if let Some(w) = v.cut_off_rad_s {
            let s = &case.sea_state;
            let spectrum = Jonswap::new(s.hs_m, s.tp_s, case.peak_enhancement()?)?;
            model.sea = IrregularSea::new(&spectrum, &case.realisation_params(Some(w)))?;
        }
        let cut_off = model.wave_cut_off.to_string();
        run(&model, &params, |_, _| {}).map(|r| (r, cut_off))
    }));
    let wall_s = clock.elapsed().as_secs_f64();
    let cpu_s = cpu_time_s() - cpu0;
    let empty = |outcome: String| CellOutcome {
        wall_s,
        cpu_s,
        steps: 0,
        passes: 0,
        cuts: 0,
        line_work: (0, 0, 0, 0),
        cut_off: String::new(),
        hot_spot_std: (f64::NAN, f64::NAN),
        outcome,
    };
    match attempt {
        Ok(Ok((r, cut_off))) => CellOutcome {
            wall_s,
            cpu_s,
            steps: r.stats.steps,
            passes: r.stats.coupling_iterations,
            cuts: r.stats.cut_coupled_steps,
            line_work: (
                r.stats.line_iterations,
                r.stats.line_factorizations,
                r.stats.cut_steps,
                r.stats.line_stalled_attempts,
            ),
            cut_off,
            hot_spot_std: r.hot_spots.first().map_or((f64::NAN, f64::NAN), |h| {
                (
                    SeriesSummary::of(&h.tension_n).std,
                    SeriesSummary::of(&h.curvature_per_m).std,
                )
            }),
            outcome: "ok".into(),
        },
        Ok(Err(e)) => empty(format!("error: {e}")),
        Err(p) => {
            let msg = p
                .downcast_ref::<String>()
                .cloned()
                .or_else(|| p.downcast_ref::<&str>().map(|s| s.to_string()))
                .unwrap_or_default();
            empty(format!("PANIC: {msg}"))
        }
    }
}

fn percentile(sorted: &[f64], p: f64) -> f64 {
    if sorted.is_empty() {
        return f64::NAN;
    }
    let i = ((sorted.len() - 1) as f64 * p).round() as usize;
    sorted[i.min(sorted.len() - 1)]
}

fn main() -> Result<(), String> {
    let o = options()?;
    let case_path = Path::new(&o.case_path);
    let mut case = CaseSpec::from_json_str(&read(case_path)?).map_err(|e| e.to_string())?;
    case.timing.duration_s = o.duration_s;
    let floater = floater_input(&case, case_path)?;
    let cells: Vec<(f64, f64)> = if o.cells.is_empty() {
        let table =
            ScatterTable::parse(&read(Path::new(&o.scatter_path))?).map_err(|e| e.to_string())?;
        table
            .cells()
            .into_iter()
            .filter(|c| c.value > 0.0)
            .map(|c| (0.5 * (c.hs_lower_m + c.hs_upper_m), c.tp_s))
            .filter(|&(hs, tp)| {
                (o.hs_range.0..=o.hs_range.1).contains(&hs)
                    && (o.tp_range.0..=o.tp_range.1).contains(&tp)
            })
            .step_by(o.every)
            .collect()
    } else {
        o.cells.clone()
    };
    println!(
        "{} cells, {} s after a {} s transient, gamma {}, seed {}, one thread",
        cells.len(),
        o.duration_s,
        case.timing.transient_s,
        o.gamma,
        o.seed
    );
    println!(
        "{:>6} {:>6} {:>9} {:>8} {:>7} {:>8} {:>6} {:>8} {:>8} {:>6} {:>6} {:>10} {:>10}  {:<40} outcome",
        "Hs m",
        "Tp s",
        "wall s",
        "cpu s",
        "steps",
        "passes",
        "cuts",
        "line it",
        "factors",
        "l cuts",
        "stalls",
        "T std N",
        "k std 1/m",
        "wave band"
    );
    let mut walls = Vec::new();
    let mut cpus: Vec<f64> = Vec::new();
    let mut failed = 0;
    let sweep = Instant::now();
    for &(hs, tp) in &cells {
        case.sea_state.hs_m = hs;
        case.sea_state.tp_s = tp;
        case.sea_state.gamma = GammaSpec::Value(o.gamma);
        case.sea_state.seed = o.seed;
        case.name = format!("hs{hs}_tp{tp}");
        let c = run_cell(&case, &floater, o.variant);
        println!(
            "{:>6.2} {:>6.1} {:>9.2} {:>8.2} {:>7} {:>8} {:>6} {:>8} {:>8} {:>6} {:>6} {:>10.1} {:>10.3e}  {:<40} {}",
            hs,
            tp,
            c.wall_s,
            c.cpu_s,
            c.steps,
            c.passes,
            c.cuts,
            c.line_work.0,
            c.line_work.1,
            c.line_work.2,
            c.line_work.3,
            c.hot_spot_std.0,
            c.hot_spot_std.1,
            c.cut_off,
            c.outcome
        );
        if c.outcome == "ok" {
            walls.push((c.wall_s, hs, tp));
            cpus.push(c.cpu_s);
        } else {
            failed += 1;
        }
    }
    let mut sorted: Vec<f64> = walls.iter().map(|w| w.0).collect();
    sorted.sort_by(f64::total_cmp);
    let median = percentile(&sorted, 0.5);
    let worst = walls
        .iter()
        .copied()
        .max_by(|a, b| a.0.total_cmp(&b.0))
        .unwrap_or((f64::NAN, 0.0, 0.0));
    println!(
        "completed {}/{}, failed {failed}; wall median {:.2} s, p90 {:.2} s, worst {:.2} s \
         (Hs {} Tp {}), worst/median {:.2}; sweep {:.1} s",
        walls.len(),
        cells.len(),
        median,
        percentile(&sorted, 0.9),
        worst.0,
        worst.1,
        worst.2,
        worst.0 / median,
        sweep.elapsed().as_secs_f64()
    );
    cpus.sort_by(f64::total_cmp);
    println!(
        "cpu median {:.2} s, p90 {:.2} s, worst {:.2} s, worst/median {:.2}, total {:.1} s",
        percentile(&cpus, 0.5),
        percentile(&cpus, 0.9),
        cpus.last().copied().unwrap_or(f64::NAN),
        cpus.last().copied().unwrap_or(f64::NAN) / percentile(&cpus, 0.5),
        cpus.iter().sum::<f64>()
    );
    Ok(())
}
