//! Convergence and speed study of the global stage on the paper case (Hs 8.75 m, Tp 16.5 s).
//!
//! Runs the case with its defaults and with one setting changed at a time, and prints the hot
//! spot (line 1, s = 79 m) tension and curvature ranges and standard deviations with their
//! relative change from the defaults, plus the wall time and work counts of each run:
//!
//! - `base`: the case as given (Δt = 0.1 s, rope elements 10 m / 2 m / 12.5 m as in the paper);
//! - `dt`: Δt halved (outputs still every 0.1 s);
//! - `mesh`: every rope segment with twice the elements (element length halved);
//! - `tight`: coupling tolerance and line force tolerance 100× tighter (the converged
//!   coupling the defaults are compared with);
//! - `direct`: the sea sampled as before the precomputed floater table: the floater's strips by
//!   direct summation (the reference the tabulated kinematics are compared with; not among the
//!   variants run by default).
//!
//! ```text
//! cargo run --release -p moorfret-studies --bin global_convergence -- \
//!     [--duration-s 300] [--transient-s 50] [--repeat 1] [--sea-duration-s S] [base dt mesh tight]
//! ```
//!
//! `--repeat N` runs each variant N times and reports the median wall time (one thread).
//! `--series-dir DIR` writes the hot spot series of each variant to `DIR/VARIANT.csv`
//! (time, tension, curvature); `--compare-dir DIR` reads `DIR/VARIANT.csv` written by an earlier
//! run (e.g. of another build) and prints min, max and standard deviation of both and the
//! largest absolute difference of the series.
//! `--sea-duration-s S` realises the sea for S seconds (transient included) instead of the
//! simulated time, so that a short run samples the sea of a long one (same components and
//! repeat period: e.g. `--sea-duration-s 1050` gives a short run the per-step cost of the
//! 1000 s case).

use std::time::Instant;

use moorfret_solver::floater::FloaterSpec;
use moorfret_solver::global::results::SeriesSummary;
use moorfret_solver::global::{run, CaseSpec, FloaterInput, GlobalModel, GlobalResult, RunParams};

const CASE: &str = include_str!("../../../campaigns/paper_case.json");
const FLOATER: &str = include_str!("../../../campaigns/data/oc4_semi_floater.json");

struct Options {
    duration_s: f64,
    transient_s: f64,
    repeat: usize,
    sea_duration_s: Option<f64>,
    series_dir: Option<std::path::PathBuf>,
    compare_dir: Option<std::path::PathBuf>,
    variants: Vec<String>,
}

fn options() -> Result<Options, String> {
    let mut o = Options {
        duration_s: 300.0,
        transient_s: 50.0,
        repeat: 1,
        sea_duration_s: None,
        series_dir: None,
        compare_dir: None,
        variants: Vec::new(),
    };
    let mut args = std::env::args().skip(1);
    while let Some(a) = args.next() {
        let mut value = |name: &str| -> Result<f64, String> {
            args.next()
                .and_then(|v| v.parse::<f64>().ok())
                .ok_or_else(|| format!("{name} needs a number"))
        };
        match a.as_str() {
            "--duration-s" => o.duration_s = value("--duration-s")?,
            "--transient-s" => o.transient_s = value("--transient-s")?,
            "--repeat" => o.repeat = value("--repeat")?.max(1.0) as usize,
            "--sea-duration-s" => o.sea_duration_s = Some(value("--sea-duration-s")?),
            "--series-dir" | "--compare-dir" => {
                let dir = args
                    .next()
                    .ok_or_else(|| format!("{a} needs a directory"))?;
                let dir = Some(std::path::PathBuf::from(dir));
                if a == "--series-dir" {
                    o.series_dir = dir;
                } else {
                    o.compare_dir = dir;
                }
            }
            "base" | "dt" | "mesh" | "tight" | "direct" => o.variants.push(a),
            other => return Err(format!("unknown argument {other}")),
        }
    }
    if o.variants.is_empty() {
        o.variants = ["base", "dt", "mesh", "tight"].map(String::from).to_vec();
    }
    Ok(o)
}

fn case_for(variant: &str, o: &Options) -> Result<(CaseSpec, RunParams), String> {
    let mut case = CaseSpec::from_json_str(CASE).map_err(|e| e.to_string())?;
    case.timing.transient_s = o.transient_s;
    case.timing.wave_ramp_s = case.timing.wave_ramp_s.min(o.transient_s);
    case.timing.duration_s = o.duration_s;
    let mut params = RunParams::default();
    match variant {
        "dt" => case.timing.time_step_s *= 0.5,
        "mesh" => {
            let types = case.mooring.line_types.clone();
            for s in case.mooring.segments.iter_mut() {
                let rope = types
                    .get(&s.line_type)
                    .is_some_and(|t| t.bending_stiffness_nm2 > 0.0);
                if rope {
                    s.elements *= 2;
                }
            }
        }
        "tight" => {
            params.dynamics.tolerance *= 0.01;
            params.dynamics.line.force_tolerance_n *= 0.01;
        }
        "direct" => params.dynamics.floater_table = None,
        _ => {}
    }
    Ok((case, params))
}

fn run_case(
    case: &CaseSpec,
    params: &RunParams,
    sea_duration_s: Option<f64>,
) -> Result<(GlobalResult, f64), String> {
    let floater = FloaterInput::RigidBody(Box::new(
        FloaterSpec::from_json_str(FLOATER).map_err(|e| e.to_string())?,
    ));
    let (transient_s, duration_s) = (case.timing.transient_s, case.timing.duration_s);
    // The sea is realised for the case's transient + duration: realise it for the longer
    // sea duration, then simulate the requested time only.
    let sea_duration = sea_duration_s.map(|s| (s - transient_s).max(duration_s));
    let mut model = GlobalModel::new(case, floater, sea_duration).map_err(|e| e.to_string())?;
    model.case.timing.duration_s = duration_s;
    let clock = Instant::now();
    let r = run(&model, params, |_, _| {}).map_err(|e| e.to_string())?;
    Ok((r, clock.elapsed().as_secs_f64()))
}

fn main() -> Result<(), String> {
    let o = options()?;
    println!(
        "paper case, hot spot line 1 s = 79 m, {} s after a {} s transient",
        o.duration_s, o.transient_s
    );
    println!(
        "{:<6} {:>12} {:>8} {:>12} {:>8} {:>11} {:>11} {:>9} {:>7} {:>8} {:>6} {:>8} {:>8} {:>8}",
        "case",
        "T range N",
        "dT %",
        "k range 1/m",
        "dk %",
        "T std N",
        "k std 1/m",
        "wall s",
        "steps",
        "passes",
        "cuts",
        "line it",
        "line LU",
        "line asm"
    );
    let mut base: Option<(SeriesSummary, SeriesSummary)> = None;
    let mut first_motion: Option<Vec<[f64; 6]>> = None;
    for v in &o.variants {
        let (case, params) = case_for(v, &o)?;
        let mut walls = Vec::new();
        let mut last = None;
        for _ in 0..o.repeat {
            let (r, wall) = run_case(&case, &params, o.sea_duration_s)?;
            walls.push(wall);
            last = Some(r);
        }
        walls.sort_by(f64::total_cmp);
        let wall = walls[walls.len() / 2];
        let r = last.ok_or("no run")?;
        let hs = r.hot_spots.first().ok_or("no hot spot")?;
        let t = SeriesSummary::of(&hs.tension_n);
        let k = SeriesSummary::of(&hs.curvature_per_m);
        let (b_t, b_k) = *base.get_or_insert((t, k));
        let s = r.stats;
        println!(
            "{:<6} {:>12.1} {:>8.3} {:>12.5e} {:>8.3} {:>11.1} {:>11.4e} {:>9.2} {:>7} {:>8} {:>6} {:>8} {:>8} {:>8}",
            v,
            t.range,
            100.0 * (t.range / b_t.range - 1.0),
            k.range,
            100.0 * (k.range / b_k.range - 1.0),
            t.std,
            k.std,
            wall,
            s.steps,
            s.coupling_iterations,
            s.cut_coupled_steps,
            s.line_iterations,
            s.line_factorizations,
            s.line_assemblies
        );
        eprintln!("{v}: {s:?}; T {t:?}; k {k:?}");
        if let Some(dir) = &o.series_dir {
            write_series(&dir.join(format!("{v}.csv")), &r)?;
        }
        if let Some(dir) = &o.compare_dir {
            compare_series(&dir.join(format!("{v}.csv")), v, &r)?;
        }
        // Floater motion: standard deviations, and the largest difference from the first
        // variant (the motions, unlike the slack events at the hot spot, are smooth functions of
        // the wave loads).
        let motion = &r.floater.motion;
        let std_of =
            |d: usize| SeriesSummary::of(&motion.iter().map(|m| m[d]).collect::<Vec<_>>()).std;
        let reference = first_motion.get_or_insert_with(|| motion.clone());
        let max_diff = |d: usize| {
            reference
                .iter()
                .zip(motion)
                .map(|(a, b)| (a[d] - b[d]).abs())
                .fold(0.0, f64::max)
        };
        println!(
            "{:<6} floater std surge {:.4} m heave {:.4} m pitch {:.5} rad; largest difference \
             from {}: surge {:.2e} m heave {:.2e} m pitch {:.2e} rad",
            v,
            std_of(0),
            std_of(2),
            std_of(4),
            o.variants[0],
            max_diff(0),
            max_diff(2),
            max_diff(4)
        );
    }
    Ok(())
}

/// Writes time, tension and curvature of the first hot spot.
fn write_series(path: &std::path::Path, r: &GlobalResult) -> Result<(), String> {
    use std::fmt::Write;
    let hs = r.hot_spots.first().ok_or("no hot spot")?;
    let mut text = String::from("time_s,tension_n,curvature_per_m\n");
    for ((t, x), k) in r.time_s.iter().zip(&hs.tension_n).zip(&hs.curvature_per_m) {
        writeln!(text, "{t},{x:e},{k:e}").map_err(|e| e.to_string())?;
    }
    std::fs::write(path, text).map_err(|e| format!("writing {}: {e}", path.display()))
}

/// Compares the first hot spot with the series written to `path` by an earlier run.
fn compare_series(path: &std::path::Path, variant: &str, r: &GlobalResult) -> Result<(), String> {
    let text =
        std::fs::read_to_string(path).map_err(|e| format!("reading {}: {e}", path.display()))?;
    let (mut t_ref, mut k_ref) = (Vec::new(), Vec::new());
    for line in text.lines().skip(1) {
        let v: Vec<f64> = line
            .split(',')
            .map(|x| {
                x.parse::<f64>()
                    .map_err(|e| format!("{}: {e}", path.display()))
            })
            .collect::<Result<_, _>>()?;
        if v.len() != 3 {
            return Err(format!("{}: expected 3 columns", path.display()));
        }
        t_ref.push(v[1]);
        k_ref.push(v[2]);
    }
    let hs = r.hot_spots.first().ok_or("no hot spot")?;
    if t_ref.len() != hs.tension_n.len() {
        return Err(format!(
            "{}: {} samples, this run {}",
            path.display(),
            t_ref.len(),
            hs.tension_n.len()
        ));
    }
    let largest = |a: &[f64], b: &[f64]| {
        a.iter()
            .zip(b)
            .map(|(x, y)| (x - y).abs())
            .fold(0.0, f64::max)
    };
    for (name, now, before) in [
        ("T N", &hs.tension_n, &t_ref),
        ("k 1/m", &hs.curvature_per_m, &k_ref),
    ] {
        let (a, b) = (SeriesSummary::of(now), SeriesSummary::of(before));
        println!(
            "{variant:<6} {name:<6} vs {}: std {:.6e} / {:.6e} ({:+.4} %), max {:.6e} / {:.6e} \
             ({:+.4} %), min {:.6e} / {:.6e}, largest difference {:.3e} ({:.3} % of the std)",
            path.display(),
            a.std,
            b.std,
            100.0 * (a.std / b.std - 1.0),
            a.max,
            b.max,
            100.0 * (a.max / b.max - 1.0),
            a.min,
            b.min,
            largest(now, before),
            100.0 * largest(now, before) / b.std
        );
    }
    Ok(())
}
