//! `moorfret import moordyn DECK --out CASE.json (--motion TABLE.csv | --floater FLOATER.json)`:
//! a MoorDyn v2 deck written as a global-stage case (calm water; see `solver::io::moordyn` for
//! what maps). What does not map is printed as warnings naming the deck row; a deck moorfret
//! cannot represent is refused with its row.

use crate::cli::output::outln;
use std::path::{Component, Path, PathBuf};

use anyhow::{bail, Context};
use clap::{Args, Subcommand};
use moorfret_solver::floater::prescribed::PrescribedMotion;
use moorfret_solver::global::case::{FloaterSource, HotSpotSpec};
use moorfret_solver::io::moordyn::{import, ImportSettings};

/// Other tools' input files.
#[derive(Debug, Subcommand)]
pub(crate) enum ImportCommand {
    /// A MoorDyn v2 input deck into a global case file (calm water, prescribed or rigid-body
    /// floater).
    Moordyn(MoordynArgs),
}

/// Arguments of `import moordyn`.
#[derive(Debug, Args)]
pub(crate) struct MoordynArgs {
    /// The MoorDyn v2 input deck.
    pub(crate) deck: PathBuf,
    /// Case file to write (JSON).
    #[arg(long)]
    pub(crate) out: PathBuf,
    /// Prescribed floater motion table (`time_s,surge_m,…,yaw_rad`, read at simulation time).
    #[arg(long, conflicts_with = "floater", required_unless_present = "floater")]
    pub(crate) motion: Option<PathBuf>,
    /// Rigid-body floater description (JSON) instead of a prescribed motion.
    #[arg(long)]
    pub(crate) floater: Option<PathBuf>,
    /// Recorded duration (s); by default the end of the motion table.
    #[arg(long, allow_negative_numbers = true)]
    pub(crate) duration_s: Option<f64>,
    /// Time step and output interval (s).
    #[arg(long, allow_negative_numbers = true, default_value_t = 0.1)]
    pub(crate) time_step_s: f64,
    /// Hot spot `LINE:ARC_M` (MoorDyn id of the line at the fairlead, arc length from the
    /// fairlead); repeatable.
    #[arg(long = "hot-spot", value_parser = parse_hot_spot)]
    pub(crate) hot_spots: Vec<HotSpotSpec>,
}

fn parse_hot_spot(text: &str) -> Result<HotSpotSpec, String> {
    let (line, arc) = text
        .split_once(':')
        .ok_or_else(|| format!("'{text}' must be LINE:ARC_M, e.g. 3:79"))?;
    let line = line
        .trim()
        .parse::<u32>()
        .map_err(|_| format!("line '{line}' must be a line id"))?;
    let arc_length_m = arc
        .trim()
        .parse::<f64>()
        .ok()
        .filter(|a| a.is_finite() && *a >= 0.0)
        .ok_or_else(|| format!("arc length '{arc}' must be a number >= 0"))?;
    Ok(HotSpotSpec { line, arc_length_m })
}

/// `target` written relative to the directory `base` (both made absolute first; both must
/// exist).
pub(crate) fn relative_path(target: &Path, base: &Path) -> anyhow::Result<PathBuf> {
    let target = target
        .canonicalize()
        .with_context(|| format!("reading {}", target.display()))?;
    let base = base
        .canonicalize()
        .with_context(|| format!("reading {}", base.display()))?;
    let t: Vec<Component> = target.components().collect();
    let b: Vec<Component> = base.components().collect();
    let common = t.iter().zip(&b).take_while(|(x, y)| x == y).count();
    let mut out = PathBuf::new();
    for _ in common..b.len() {
        out.push("..");
    }
    for c in &t[common..] {
        out.push(c.as_os_str());
    }
    Ok(out)
}

/// Runs the command.
pub(crate) fn execute(cmd: ImportCommand) -> anyhow::Result<()> {
    let ImportCommand::Moordyn(args) = cmd;
    // the options by their names, before the deck is read or anything written
    for (option, value) in [
        ("--duration-s", args.duration_s),
        ("--time-step-s", Some(args.time_step_s)),
    ] {
        if let Some(v) = value.filter(|v| !(v.is_finite() && *v > 0.0)) {
            bail!("{option} must be a positive number of seconds (got {v})");
        }
    }
    let text = std::fs::read_to_string(&args.deck)
        .with_context(|| format!("reading {}", args.deck.display()))?;
    let out_dir = match args.out.parent() {
        Some(p) if !p.as_os_str().is_empty() => p.to_path_buf(),
        _ => PathBuf::from("."),
    };
    std::fs::create_dir_all(&out_dir).with_context(|| format!("creating {}", out_dir.display()))?;
    let (floater, table_end_s) = match (&args.motion, &args.floater) {
        (Some(motion), _) => {
            let table = std::fs::read_to_string(motion)
                .with_context(|| format!("reading {}", motion.display()))?;
            let m = PrescribedMotion::from_csv_str(&table)
                .with_context(|| format!("in motion table {}", motion.display()))?;
            let csv_path = relative_path(motion, &out_dir)?.display().to_string();
            (
                FloaterSource::PrescribedMotion { csv_path },
                Some(m.time_range().1),
            )
        }
        (None, Some(floater)) => {
            let spec_path = relative_path(floater, &out_dir)?.display().to_string();
            (FloaterSource::RigidBody { spec_path }, None)
        }
        (None, None) => bail!("give the floater: --motion TABLE.csv or --floater FLOATER.json"),
    };
    let duration_s = match (args.duration_s, table_end_s) {
        (Some(d), _) => d,
        (None, Some(end)) => end,
        (None, None) => bail!("--duration-s is needed with --floater"),
    };
    let name = args
        .deck
        .file_stem()
        .map_or("moordyn".into(), |s| s.to_string_lossy().into_owned());
    let imported = import(
        &text,
        &ImportSettings {
            name,
            floater,
            time_step_s: args.time_step_s,
            duration_s,
            hot_spots: args.hot_spots,
        },
    )
    .with_context(|| format!("in MoorDyn deck {}", args.deck.display()))?;
    for note in &imported.notes {
        eprintln!("warning: {note}");
    }
    let json = serde_json::to_string_pretty(&imported.case)?;
    std::fs::write(&args.out, json + "\n")
        .with_context(|| format!("writing {}", args.out.display()))?;
    let m = &imported.case.mooring;
    outln!(
        "wrote {}: {} line(s) of {} segment(s), {:.1} m each, calm water, {} s at {} s steps ({} warning(s))",
        args.out.display(),
        m.lines.len(),
        m.segments.len(),
        imported.case.line_spec().length_m(),
        duration_s,
        args.time_step_s,
        imported.notes.len()
    )?;
    Ok(())
}
