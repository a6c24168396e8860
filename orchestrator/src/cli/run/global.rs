//! `moorfret run global CASE.json --out DIR [--duration-s X] [--transient-s X] [--threads N]
//! [--no-mirror]`.
//!
//! Reads the case and the floater file it names (relative to the case file), runs the coupled
//! statics and dynamics, and writes into DIR:
//! `hotspots.csv` (time_s, tension_n_i, curvature_per_m_i per hot spot i), `fairleads.csv`
//! (fairlead tension per line), `envelopes.csv` (per line and node: arc length, min/max tension,
//! max |κ|, κ range), `floater.csv` (surge … yaw), `summary.json`, `hotspots.svg` and
//! `static_shapes.svg`. A progress bar is drawn on a terminal, plain log lines otherwise.
//! Exit code 1 on any error (bad input names the field; a diverging step names time, line,
//! node and residual); nothing non-finite is written.

use std::io::{IsTerminal, Write};
use std::path::{Path, PathBuf};

use anyhow::{bail, Context};
use clap::Args;
use moorfret_solver::floater::prescribed::PrescribedMotion;
use moorfret_solver::floater::FloaterSpec;
use moorfret_solver::global::case::FloaterSource;
use moorfret_solver::global::{
    run, CaseSpec, FloaterInput, GlobalError, GlobalModel, GlobalResult, HotSpotSeries, RunParams,
};
use moorfret_solver::text::Num;

use moorfret_orchestrator::plot;

/// Arguments of `run global`.
#[derive(Debug, Args)]
pub(crate) struct GlobalArgs {
    /// Case file (JSON).
    pub(crate) case: PathBuf,
    /// Output directory (created if missing).
    #[arg(long)]
    pub(crate) out: PathBuf,
    /// Recorded duration after the transient (s), overriding the case.
    #[arg(long, allow_negative_numbers = true)]
    pub(crate) duration_s: Option<f64>,
    /// Discarded start-up time (s), overriding the case (the wave ramp is shortened to fit).
    #[arg(long, allow_negative_numbers = true)]
    pub(crate) transient_s: Option<f64>,
    /// Significant wave height (m), overriding the case's sea state.
    #[arg(long, allow_negative_numbers = true)]
    pub(crate) hs_m: Option<f64>,
    /// Peak period (s), overriding the case's sea state.
    #[arg(long, allow_negative_numbers = true)]
    pub(crate) tp_s: Option<f64>,
    /// Seed of the sea's realisation, overriding the case's.
    #[arg(long)]
    pub(crate) seed: Option<u64>,
    /// Worker threads for the lines (at most 256; more than the lines gain nothing).
    #[arg(long, default_value_t = 1, value_parser = clap::builder::TypedValueParser::map(clap::value_parser!(u16).range(1..=256), usize::from))]
    pub(crate) threads: usize,
    /// Solve every line, also those the stage writes as the mirror image of a symmetric
    /// partner (a check: the results agree within the lines' force tolerance).
    #[arg(long)]
    pub(crate) no_mirror: bool,
}

fn read(path: &Path) -> anyhow::Result<String> {
    std::fs::read_to_string(path).with_context(|| format!("reading {}", path.display()))
}

/// Loads the case and its floater input.
pub(crate) fn load_case(path: &Path) -> anyhow::Result<(CaseSpec, FloaterInput)> {
    let text = read(path)?;
    let case = CaseSpec::from_json_str(&text)
        .map_err(|e| {
            // the field path at fault, which the case's own reader does not give
            match moorfret_campaign::spec::from_json_with_path::<CaseSpec>(&text) {
                Err(with_path) if with_path.starts_with("field `") => {
                    anyhow::anyhow!("case file is not a valid case description: {with_path}")
                }
                _ => anyhow::Error::new(e),
            }
        })
        .with_context(|| format!("in case file {}", path.display()))?;
    let base = path.parent().unwrap_or(Path::new("."));
    let floater = match &case.floater {
        FloaterSource::RigidBody { spec_path } => {
            let p = base.join(spec_path);
            let text = read(&p)?;
            let spec = FloaterSpec::from_json_str(&text)
                .map_err(|e| {
                    // the field path at fault, which the floater's own reader does not give
                    match moorfret_campaign::spec::from_json_with_path::<FloaterSpec>(&text) {
                        Err(with_path) if with_path.starts_with("field `") => {
                            anyhow::anyhow!("not a valid floater description: {with_path}")
                        }
                        _ => anyhow::Error::new(e),
                    }
                })
                .with_context(|| format!("in floater file {}", p.display()))?;
            FloaterInput::RigidBody(Box::new(spec))
        }
        FloaterSource::PrescribedMotion { csv_path } => {
            let p = base.join(csv_path);
            FloaterInput::Prescribed(
                PrescribedMotion::from_csv_str(&read(&p)?)
                    .with_context(|| format!("in motion table {}", p.display()))?,
            )
        }
    };
    Ok((case, floater))
}

/// A fault of the case as run: named by the command-line option that set the field at fault,
/// or else as a fault of the case file.
fn blame_option(args: &GlobalArgs, err: GlobalError) -> anyhow::Error {
    let given = |v: Option<f64>| v.map(|x| Num(x).to_string());
    let options = [
        ("timing.duration_s", "--duration-s", given(args.duration_s)),
        (
            "timing.transient_s",
            "--transient-s",
            given(args.transient_s),
        ),
        ("sea_state.hs_m", "--hs-m", given(args.hs_m)),
        ("sea_state.tp_s", "--tp-s", given(args.tp_s)),
        ("sea_state.seed", "--seed", args.seed.map(|s| s.to_string())),
    ];
    let in_case = || format!("in case file {}", args.case.display());
    match &err {
        GlobalError::InvalidCase { field, reason, .. } => {
            match options.iter().find(|(f, _, v)| f == field && v.is_some()) {
                Some((_, option, Some(value))) => anyhow::anyhow!(
                    "command-line option {option} {value}: {reason} (it sets the case's {field})"
                ),
                _ => anyhow::Error::new(err).context(in_case()),
            }
        }
        // the sea state as the options made it
        GlobalError::Waves(_) if args.hs_m.is_some() || args.tp_s.is_some() => {
            let set: Vec<String> = options[2..4]
                .iter()
                .filter_map(|(_, o, v)| v.as_ref().map(|v| format!("{o} {v}")))
                .collect();
            anyhow::Error::new(err).context(format!(
                "in the sea state set by the command-line option(s) {}",
                set.join(" ")
            ))
        }
        _ => anyhow::Error::new(err).context(in_case()),
    }
}

/// Runs the command.
pub(crate) fn execute(args: &GlobalArgs) -> anyhow::Result<()> {
    if args.threads == 0 {
        bail!("--threads must be >= 1");
    }
    let (mut case, floater) = load_case(&args.case)?;
    if let Some(t) = args.transient_s {
        case.timing.transient_s = t;
        case.timing.wave_ramp_s = case.timing.wave_ramp_s.min(t);
    }
    if let Some(hs) = args.hs_m {
        case.sea_state.hs_m = hs;
    }
    if let Some(tp) = args.tp_s {
        case.sea_state.tp_s = tp;
    }
    if let Some(seed) = args.seed {
        case.sea_state.seed = seed;
    }
    let model =
        GlobalModel::new(&case, floater, args.duration_s).map_err(|e| blame_option(args, e))?;
    let t_end = model.case.timing.transient_s + model.case.timing.duration_s;
    tracing::info!(
        case = %model.case.name,
        wind_m_s = model.wind_speed_m_s,
        thrust_n = model.thrust_n,
        t_end,
        "global run"
    );
    let mut params = RunParams {
        threads: args.threads,
        ..RunParams::default()
    };
    params.dynamics.mirror_lines = !args.no_mirror;
    let bar = std::io::stderr().is_terminal().then(|| {
        let b = indicatif::ProgressBar::new(1000);
        b.set_style(
            indicatif::ProgressStyle::with_template("{elapsed_precise} [{bar:40}] {msg}")
                .unwrap_or_else(|_| indicatif::ProgressStyle::default_bar()),
        );
        b
    });
    let mut next_log = 0.0;
    let result = run(&model, &params, |t, end| {
        if let Some(b) = &bar {
            b.set_position((1000.0 * t / end) as u64);
            b.set_message(format!("t = {t:.1} / {end:.1} s"));
        } else if t >= next_log {
            tracing::info!("t = {t:.1} / {end:.1} s");
            next_log += (end / 10.0).max(1.0);
        }
    });
    if let Some(b) = &bar {
        b.finish_and_clear();
    }
    let result = result.context("global run failed")?;
    write_outputs(&result, &args.out)?;
    let s = &result.stats;
    tracing::info!(
        steps = s.steps,
        coupling_iterations = s.coupling_iterations,
        dynamics_s = s.dynamics_s,
        out = %args.out.display(),
        "global run done"
    );
    Ok(())
}

fn create(path: &Path) -> anyhow::Result<std::io::BufWriter<std::fs::File>> {
    Ok(std::io::BufWriter::new(
        std::fs::File::create(path).with_context(|| format!("creating {}", path.display()))?,
    ))
}

/// Writes every output file of `result` into `dir`.
pub(crate) fn write_outputs(result: &GlobalResult, dir: &Path) -> anyhow::Result<()> {
    std::fs::create_dir_all(dir).with_context(|| format!("creating {}", dir.display()))?;

    let path = dir.join("hotspots.csv");
    let series: Vec<HotSpotSeries> = result
        .hot_spots
        .iter()
        .map(|h| HotSpotSeries {
            time_s: result.time_s.clone(),
            tension_n: h.tension_n.clone(),
            curvature_per_m: h.curvature_per_m.clone(),
        })
        .collect();
    std::fs::write(&path, HotSpotSeries::table_csv(&series))
        .with_context(|| format!("writing {}", path.display()))?;

    let path = dir.join("fairleads.csv");
    let mut w = create(&path)?;
    let cols: Vec<String> = result
        .lines
        .iter()
        .map(|l| format!("tension_n_line{}", l.id))
        .collect();
    writeln!(w, "time_s,{}", cols.join(","))?;
    for (j, t) in result.time_s.iter().enumerate() {
        write!(w, "{t}")?;
        for l in &result.lines {
            write!(w, ",{}", l.fairlead_tension_n[j])?;
        }
        writeln!(w)?;
    }
    w.flush()
        .with_context(|| format!("writing {}", path.display()))?;

    let path = dir.join("envelopes.csv");
    let mut w = create(&path)?;
    writeln!(
        w,
        "line,node,arc_length_m,tension_min_n,tension_max_n,curvature_max_per_m,curvature_range_per_m"
    )?;
    for l in &result.lines {
        let e = &l.envelope;
        let range = e.curvature_range_per_m();
        for (i, curvature_range) in range.iter().enumerate() {
            writeln!(
                w,
                "{},{},{},{},{},{},{}",
                l.id,
                i,
                e.arc_length_m[i],
                e.tension_min_n[i],
                e.tension_max_n[i],
                e.curvature_max_per_m[i],
                curvature_range
            )?;
        }
    }
    w.flush()
        .with_context(|| format!("writing {}", path.display()))?;

    let path = dir.join("floater.csv");
    let mut w = create(&path)?;
    writeln!(
        w,
        "time_s,surge_m,sway_m,heave_m,roll_rad,pitch_rad,yaw_rad"
    )?;
    for (t, m) in result.floater.time_s.iter().zip(&result.floater.motion) {
        writeln!(
            w,
            "{t},{},{},{},{},{},{}",
            m[0], m[1], m[2], m[3], m[4], m[5]
        )?;
    }
    w.flush()
        .with_context(|| format!("writing {}", path.display()))?;

    let path = dir.join("summary.json");
    let text =
        serde_json::to_string_pretty(&result.summary()).context("serialising the summary")?;
    std::fs::write(&path, text).with_context(|| format!("writing {}", path.display()))?;

    plot::hotspots_svg(result, &dir.join("hotspots.svg"))?;
    plot::static_shapes_svg(result, &dir.join("static_shapes.svg"))?;
    Ok(())
}
