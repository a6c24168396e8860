//! `moorfret run strand PROFILE --load LOAD.csv --out DIR`: the strand FE model of a profile
//! driven through a load history (`moorfret_solver::strand::history`).
//!
//! LOAD.csv has a header naming three columns, in any order: `time_s`, `curvature_per_m` and
//! either `tension_n` or `axial_strain`; or it is the `hotspots.csv` of `run global` as written
//! (`time_s`, then `tension_n_K`, `curvature_per_m_K` per hot spot K), read at hot spot
//! `--hot-spot K` (0 by default). A tension history becomes the axial strain
//! ε = T / EA with EA measured on the model itself by a tension step
//! (`measure_axial_stiffness_n`, at `--stiffness-strain`; kept in a cache per model,
//! [`StiffnessCache`], or given by `--axial-stiffness-n`): the rule of a campaign's strand
//! jobs too (`moorfret_campaign::stiffness`); slack samples (T < 0) are refused
//! unless `--slack-as-zero` loads them as ε = 0. The whole history is checked before anything
//! is solved or written: an unknown or missing column, a value that is not a finite number,
//! a time that does not increase, a negative load or a curvature beyond the strand's
//! admissible fibre strain ends the run naming the sample (its index from 0 and its line in
//! the file) and the column.
//!
//! Writes into DIR:
//! - `monitors.csv`: `time_s,strain,curvature_per_m`, then one column per monitor channel
//!   (quantity, layer or layer interface, neutral axis / outer arc / ring angle), one row per
//!   turning point of the load (the samples an FE run solves; between them the monitors are
//!   interpolations of the solved states), or one row per sample with
//!   `--monitors every-sample`: the file grows with what was solved, not with the sampling;
//! - `contacts.csv`: one row per contact: layer interface, θ from the neutral axis, z, largest
//!   normal force, largest slip range, counted slip cycles, position class;
//! - `contact_records.json`: the full per-contact records with their slip cycles;
//! - `summary.json`: model sizes, the EA used, the history statistics with the split of the
//!   Newton work, where the slip stops drifting against the load (run-in, the campaigns'
//!   default detection), peak slip range and normal force per layer interface, wall time;
//! - SVG plots as the seed's Figs. 19-22 ([`moorfret_orchestrator::plot::strand_history_svgs`]) and of the load.
//!
//! `--checkpoint FILE` writes the solver's full state every `--checkpoint-every` segments (temp
//! file, then rename); with `--resume` a run starts from FILE if it exists, and gives results
//! identical to the bit to an uninterrupted run.

use crate::cli::output::outln;
use std::collections::BTreeMap;
use std::io::IsTerminal;
use std::path::{Path, PathBuf};
use std::time::{Duration, Instant};

use anyhow::{anyhow, bail, Context};
use clap::Args;
use moorfret_campaign::fatigue::RunInDetection;
use moorfret_campaign::spec::{HistorySettings, DEFAULT_CHECKPOINT_SEGMENTS, MAX_STRAND_THREADS};
use moorfret_campaign::stiffness::STIFFNESS_STRAIN;
use moorfret_solver::fretting::ContactRecord;
use moorfret_solver::global::series::{LoadKind, LoadTable};
use moorfret_solver::strand::history::checkpoint::HistoryCheckpoint;
use moorfret_solver::strand::history::monitors::{MonitorChannel, MonitorGroup, MonitorTarget};
use moorfret_solver::strand::history::reduce::reduce_history_on_scale;
use moorfret_solver::strand::history::{
    validate_samples, HistoryError, HistoryObserver, HistoryOptions, HistoryProgress,
    HistoryResult, HistoryStats, LoadSample,
};
use moorfret_solver::strand::model::StrandModel;
use moorfret_worker::strand::checkpoint::{CheckpointTarget, Checkpoints};
use moorfret_worker::strand::load::{self as strand_load, read_load, StiffnessOptions};
use moorfret_worker::strand::{run_fe, AxialStiffness, LazyModel, RefusedCheckpoint};
use serde::Serialize;

use super::strand_model::{load_strand, ContactLawsArg, ModelArgs, ModelSizes};
use super::strand_reduced::{
    cache_root, calibration_for, range_of, CalibrationRequest, CalibrationSource, Fidelity,
    ReducedArgs,
};
use moorfret_orchestrator::plot::{strand_history_svgs, LoadPlot};
use moorfret_solver::strand::reduced::run_reduced;

/// Options of a history run (`--load`).
#[derive(Debug, Args)]
pub(crate) struct HistoryArgs {
    /// Load slack samples (negative tension) as zero strain instead of refusing them.
    #[arg(long)]
    pub(crate) slack_as_zero: bool,
    /// Hot spot to read when the load file is a global run's `hotspots.csv` (columns
    /// `tension_n_K`, `curvature_per_m_K`).
    #[arg(long, default_value_t = 0)]
    pub(crate) hot_spot: usize,
    /// Turning-point tolerance of the history reduction, as a fraction of each channel's range.
    #[arg(long)]
    pub(crate) turning_point_tolerance: Option<f64>,
    /// Lower bounds of the scales the turning-point tolerance is a fraction of: strain and
    /// curvature (1/m); a channel whose range is smaller is reduced as if its range were this.
    #[arg(long, num_args = 2, value_names = ["STRAIN", "CURVATURE_PER_M"])]
    pub(crate) turning_point_scale: Option<Vec<f64>>,
    /// Stiffness along the sliding direction that the Newton iteration matrix gives every
    /// Cattaneo–Mindlin contact in gross slip at a step's first correction, as a fraction of
    /// its initial stiffness k₀ (a quarter of it at each further correction); the converged
    /// state is the law's own. 0: the consistent tangent. Refused under the other laws.
    /// [default: 0.1]
    #[arg(long)]
    pub(crate) sliding_stiffness: Option<f64>,
    /// Threads of the sparse factorisation and solves (results equal to round-off).
    #[arg(long, default_value_t = 1, value_parser = clap::value_parser!(u16).range(1..=MAX_STRAND_THREADS as i64))]
    pub(crate) threads: u16,
    /// EA of the tension-to-strain conversion and the cache.
    #[command(flatten)]
    pub(crate) stiffness: StiffnessArgs,
    /// Checkpoint file of the history run (written every `--checkpoint-every` segments).
    #[arg(long)]
    pub(crate) checkpoint: Option<PathBuf>,
    /// History segments between two checkpoints.
    #[arg(long, default_value_t = DEFAULT_CHECKPOINT_SEGMENTS, value_parser = clap::builder::TypedValueParser::map(clap::value_parser!(u64).range(1..), |n| n as usize))]
    pub(crate) checkpoint_every: usize,
    /// Start from the checkpoint file if it exists.
    #[arg(long, requires = "checkpoint")]
    pub(crate) resume: bool,
    /// Stop after this many segments, as an interrupted run would (tests of `--resume`).
    #[arg(long, hide = true)]
    pub(crate) stop_after_segments: Option<usize>,
    /// Rows of `monitors.csv`: the load's turning points (the samples an FE run solves) or
    /// every sample of the load.
    #[arg(long, value_enum, default_value_t = MonitorRows::TurningPoints)]
    pub(crate) monitors: MonitorRows,
    /// Fidelity and calibration of the strand response.
    #[command(flatten)]
    pub(crate) reduced: ReducedArgs,
}

/// Which samples `monitors.csv` holds.
#[derive(Debug, Clone, Copy, PartialEq, Eq, clap::ValueEnum)]
pub(crate) enum MonitorRows {
    /// The turning points of the load at the run's tolerance (the samples an FE run solves).
    TurningPoints,
    /// Every sample of the load.
    EverySample,
}

/// How a tension history becomes a strain history (EA) and where measured values are cached.
#[derive(Debug, Args)]
pub(crate) struct StiffnessArgs {
    /// Axial strain of the tension step that measures EA.
    #[arg(long, default_value_t = STIFFNESS_STRAIN)]
    pub(crate) stiffness_strain: f64,
    /// EA (N) for ε = T / EA instead of measuring it, e.g. the `axial_stiffness.ea_n` of an
    /// earlier run's summary on the same model (saves the tension step).
    #[arg(long, conflicts_with = "stiffness_strain")]
    pub(crate) axial_stiffness_n: Option<f64>,
    /// Directory of the cache of measured EA values and of reduced-response calibrations
    /// (default: `$XDG_CACHE_HOME/moorfret`, else `~/.cache/moorfret`).
    #[arg(long, env = "MOORFRET_CACHE_DIR")]
    pub(crate) cache_dir: Option<PathBuf>,
    /// Measure EA (and calibrate a reduced response) even if the cache holds it; the new value
    /// replaces the cached one.
    #[arg(long)]
    pub(crate) no_cache: bool,
}

/// Progress bar on a terminal (log lines otherwise) and checkpoint writer.
pub(crate) struct Observer {
    bar: Option<indicatif::ProgressBar>,
    next_log: usize,
    checkpoints: Checkpoints<'static>,
    done: usize,
    stop_after: Option<usize>,
}

impl Observer {
    /// Progress only: a bar on a terminal, log lines otherwise; no checkpoints.
    pub(crate) fn progress_only() -> Self {
        Self {
            bar: progress_bar(),
            next_log: 0,
            checkpoints: Checkpoints::new(None, Duration::ZERO),
            done: 0,
            stop_after: None,
        }
    }

    /// Clears the bar.
    pub(crate) fn finish(&self) {
        if let Some(b) = &self.bar {
            b.finish_and_clear();
        }
    }
}

impl HistoryObserver for Observer {
    fn progress(&mut self, p: &HistoryProgress) {
        self.done = p.segment;
        let msg = format!(
            "segment {}/{}, t = {} s, {:.1} s",
            p.segment, p.segments, p.time_s, p.elapsed_s
        );
        if let Some(b) = &self.bar {
            b.set_length(p.segments as u64);
            b.set_position(p.segment as u64);
            b.set_message(msg);
        } else if p.segment >= self.next_log || p.segment == p.segments {
            tracing::info!("{msg}");
            self.next_log = p.segment + (p.segments / 10).max(1);
        }
    }

    fn checkpoint(&mut self, checkpoint: &HistoryCheckpoint) {
        self.checkpoints.offer(checkpoint);
    }

    fn should_stop(&mut self) -> bool {
        self.stop_after.is_some_and(|n| self.done >= n)
    }
}

/// A progress bar on a terminal, none otherwise (the observer logs lines then).
pub(crate) fn progress_bar() -> Option<indicatif::ProgressBar> {
    std::io::stderr().is_terminal().then(|| {
        let b = indicatif::ProgressBar::new(1);
        b.set_style(
            indicatif::ProgressStyle::with_template("{elapsed_precise} [{bar:40}] {msg}")
                .unwrap_or_else(|_| indicatif::ProgressStyle::default_bar()),
        );
        b
    })
}

#[derive(Debug, Default, Serialize)]
struct InterfacePeaks {
    contacts: usize,
    max_slip_range_m: f64,
    max_normal_force_n: f64,
    slip_cycles: f64,
}

#[derive(Debug, Serialize)]
struct Summary<'a> {
    #[serde(flatten)]
    model: ModelDescription,
    #[serde(flatten)]
    sizes: Option<ModelSizes>,
    /// "fe" or "reduced".
    fidelity: &'static str,
    /// The calibration of a reduced run.
    #[serde(skip_serializing_if = "Option::is_none")]
    calibration: Option<CalibrationSource>,
    load: String,
    load_kind: &'static str,
    /// Hot spot read from a global run's `hotspots.csv`.
    hot_spot: usize,
    slack_as_zero: bool,
    samples: usize,
    slack_samples: usize,
    #[serde(serialize_with = "stiffness_summary")]
    axial_stiffness: Option<AxialStiffness>,
    turning_point_tolerance: f64,
    turning_point_scale: [f64; 2],
    /// The Newton matrix's sliding stiffness (`--sliding-stiffness`).
    sliding_stiffness: f64,
    resumed_from_checkpoint: bool,
    checkpoints_written: usize,
    history: &'a HistoryStats,
    /// Where the slip monitors stop drifting against the load (the campaigns' default
    /// detection, `moorfret_campaign::fatigue::RunInDetection`).
    run_in: serde_json::Value,
    peaks_by_interface: BTreeMap<String, InterfacePeaks>,
    wall_time_s: f64,
}

/// The `axial_stiffness` of the summary ([`AxialStiffness::summary`]).
fn stiffness_summary<S: serde::Serializer>(
    stiffness: &Option<AxialStiffness>,
    s: S,
) -> Result<S::Ok, S::Error> {
    stiffness.as_ref().map(AxialStiffness::summary).serialize(s)
}

/// The strand model of a run as its summary names it: profile file, regularisation, ends.
#[derive(Debug, Serialize)]
struct ModelDescription {
    profile: String,
    regularisation: String,
    ends: String,
}

impl ModelDescription {
    fn of(args: &ModelArgs) -> Self {
        Self {
            profile: args.profile.display().to_string(),
            regularisation: args.regularisation_name(),
            ends: format!("{:?}", args.ends.end_kind()),
        }
    }
}

/// Readable name of an interface: "layer2_on_layer1", "layer1_on_core".
fn interface_name(interface: usize) -> String {
    if interface == 0 {
        "layer1_on_core".into()
    } else {
        format!("layer{}_on_layer{interface}", interface + 1)
    }
}

/// Column name of a monitor channel.
fn channel_name(ch: &MonitorChannel) -> String {
    let place = match ch.target {
        MonitorTarget::Element(_) => format!("layer{}", ch.layer + 1),
        MonitorTarget::Contact(_) => interface_name(ch.layer),
    };
    let group = match ch.group {
        MonitorGroup::NeutralAxis => "neutral_axis".to_string(),
        MonitorGroup::OuterArc => "outer_arc".to_string(),
        MonitorGroup::Ring => format!("ring_theta_{:.0}deg", ch.theta_rad.to_degrees()),
    };
    format!("{}_{place}_{group}", ch.quantity.as_str())
}

/// Unique column names of the channels (a clash gets the target index appended).
fn channel_names(channels: &[MonitorChannel]) -> Vec<String> {
    let mut seen = std::collections::BTreeSet::new();
    channels
        .iter()
        .map(|ch| {
            let mut name = channel_name(ch);
            if !seen.insert(name.clone()) {
                let index = match ch.target {
                    MonitorTarget::Element(i) => format!("_element{i}"),
                    MonitorTarget::Contact(i) => format!("_contact{i}"),
                };
                name.push_str(&index);
                seen.insert(name.clone());
            }
            name
        })
        .collect()
}

/// `monitors.csv` at the samples `rows` (indices into the series, increasing).
fn write_monitors(path: &Path, r: &HistoryResult, rows: &[usize]) -> anyhow::Result<()> {
    let m = &r.monitors;
    let mut w = csv::Writer::from_path(path)?;
    let mut header = vec![
        "time_s".to_string(),
        "strain".into(),
        "curvature_per_m".into(),
    ];
    header.extend(channel_names(&m.channels));
    w.write_record(&header)?;
    for &i in rows.iter().filter(|&&i| i < m.time_s.len()) {
        let mut row = vec![
            m.time_s[i].to_string(),
            m.strain[i].to_string(),
            m.curvature_per_m[i].to_string(),
        ];
        row.extend(m.channels.iter().map(|c| c.values[i].to_string()));
        w.write_record(&row)?;
    }
    w.flush()?;
    Ok(())
}

fn write_contacts(path: &Path, contacts: &[ContactRecord]) -> anyhow::Result<()> {
    let mut w = csv::Writer::from_path(path)?;
    w.write_record([
        "contact",
        "layer_interface",
        "theta_rad",
        "z_m",
        "max_normal_force_n",
        "max_slip_range_m",
        "slip_cycles",
        "position_class",
    ])?;
    for (i, c) in contacts.iter().enumerate() {
        w.write_record([
            i.to_string(),
            c.interface.to_string(),
            c.theta_rad.to_string(),
            c.z_m.to_string(),
            c.max_normal_force_n.to_string(),
            c.max_slip_range_m().to_string(),
            c.slip_cycle_count().to_string(),
            c.class().position.as_str().to_string(),
        ])?;
    }
    w.flush()?;
    Ok(())
}

/// The run-in of a history run by the campaigns' default detection, on windows of the load's
/// mean sample interval.
fn run_in_of(result: &HistoryResult) -> serde_json::Value {
    let t = &result.monitors.time_s;
    let dt = match t.len() {
        0 | 1 => {
            return serde_json::json!({ "stabilised": false, "error": "fewer than two samples" })
        }
        n => (t[n - 1] - t[0]) / (n - 1) as f64,
    };
    RunInDetection::default().detect(&result.monitors, dt).1
}

fn peaks_by_interface(contacts: &[ContactRecord]) -> BTreeMap<String, InterfacePeaks> {
    let mut out: BTreeMap<String, InterfacePeaks> = BTreeMap::new();
    for c in contacts {
        let p = out.entry(interface_name(c.interface)).or_default();
        p.contacts += 1;
        p.max_slip_range_m = p.max_slip_range_m.max(c.max_slip_range_m());
        p.max_normal_force_n = p.max_normal_force_n.max(c.max_normal_force_n);
        p.slip_cycles += c.slip_cycle_count();
    }
    out
}

/// The load samples of `table` on the model of `lazy` under the stiffness options `args`
/// ([`moorfret_worker::strand::load::samples_of`]), with the EA used, printed, and the slack
/// sample count.
pub(crate) fn samples_of(
    table: &LoadTable,
    lazy: &mut LazyModel<'_>,
    args: &StiffnessArgs,
    options: &HistoryOptions,
) -> anyhow::Result<(Vec<LoadSample>, Option<AxialStiffness>, usize)> {
    let cache_dir = cache_root(args.cache_dir.as_deref());
    let stiffness = StiffnessOptions {
        given_ea_n: args.axial_stiffness_n,
        strain: args.stiffness_strain,
        cache_dir: cache_dir.as_deref(),
        refresh: args.no_cache,
    };
    let (samples, ea, slack) = strand_load::samples_of(table, lazy, &stiffness, options)?;
    if let Some((ea, estimates)) = ea.as_ref().and_then(|ea| Some((ea, ea.estimates?))) {
        let how = match ea.measured_at_strain {
            Some(strain) => format!("{} on the model at ε = {strain}", ea.source.as_str()),
            None => ea.source.as_str().to_string(),
        };
        outln!(
            "axial stiffness EA = {:.6e} N ({how}; straight strand {:.6e} N, \
             Costello-corrected {:.6e} N{})",
            ea.ea_n,
            estimates.simple_n,
            estimates.costello_n,
            estimates
                .contact_compliant_n
                .map_or(String::new(), |c| format!(
                    ", with the contacts' compliance {c:.6e} N"
                ))
        )?;
    }
    Ok((samples, ea, slack))
}

/// Runs the history mode of `moorfret run strand`: the model of `args` through `load` with the
/// settings `h`, outputs into `out`.
pub(super) fn execute(
    args: &ModelArgs,
    h: &HistoryArgs,
    load: &Path,
    out: &Path,
) -> anyhow::Result<()> {
    let start = Instant::now();
    if h.sliding_stiffness.is_some() && args.contact_laws != ContactLawsArg::ContactMechanics {
        bail!(
            "--sliding-stiffness acts on the Cattaneo–Mindlin contacts of --contact-laws \
             contact-mechanics only; --contact-laws {} has none",
            args.contact_laws.name()
        );
    }
    let table = read_load(load, h.slack_as_zero, h.hot_spot)?;
    let (_, strand, params) = load_strand(args)?;
    let mut lazy = LazyModel::new(&strand, &params);
    let fidelity = h.reduced.fidelity;
    if fidelity == Fidelity::Fe {
        lazy.get()?;
    }
    let settings = HistorySettings {
        threads: usize::from(h.threads),
        turning_point_tolerance: h.turning_point_tolerance,
        turning_point_scale: match h.turning_point_scale.as_deref() {
            Some(&[e, k]) => Some([e, k]),
            _ => None,
        },
        checkpoint_interval_segments: if h.checkpoint.is_some() || h.stop_after_segments.is_some() {
            h.checkpoint_every
        } else {
            0
        },
        sliding_stiffness: h.sliding_stiffness,
    };
    let options = settings.options().validated()?;
    let (samples, stiffness, slack_samples) =
        samples_of(&table, &mut lazy, &h.stiffness, &options)?;
    if fidelity == Fidelity::Reduced {
        let run = ReducedRun {
            args,
            h,
            load,
            out,
            table: &table,
            samples: &samples,
            stiffness,
            slack_samples,
            options: &options,
            start,
        };
        return run.execute(&mut lazy);
    }
    let model = lazy.get()?;
    validate_samples(model, &samples, &options)
        .map_err(|e| strand_load::refused(load, table.kind, e))?;
    let resume = match (&h.checkpoint, h.resume) {
        (Some(path), true) => CheckpointTarget::File(path.clone())
            .read()
            .map_err(|e| anyhow!("reading checkpoint {}: {e}", path.display()))?,
        _ => None,
    };
    std::fs::create_dir_all(out).with_context(|| format!("creating {}", out.display()))?;

    let bar = progress_bar();
    let mut observer = Observer {
        bar,
        next_log: 0,
        checkpoints: Checkpoints::new(
            h.checkpoint.clone().map(CheckpointTarget::File),
            Duration::ZERO,
        ),
        done: 0,
        stop_after: h.stop_after_segments,
    };
    let run = run_fe(
        model,
        &samples,
        &options,
        resume.as_ref(),
        RefusedCheckpoint::Fail,
        &mut observer,
    );
    observer.finish();
    let result = match run {
        Ok(run) => run.result,
        Err(HistoryError::Checkpoint { reason }) if resume.is_some() => bail!(
            "checkpoint {} does not belong to this profile and load history ({reason}); \
             remove it or run without --resume",
            h.checkpoint.as_deref().unwrap_or(Path::new("")).display()
        ),
        Err(e @ HistoryError::Stopped { .. }) => {
            bail!("{e}; continue with --resume")
        }
        Err(e) => return Err(anyhow!(e).context("strand history run failed")),
    };

    write_outputs(out, &result, &table, h.monitors, &result.kept_samples)?;
    let summary = Summary {
        model: ModelDescription::of(args),
        sizes: Some(ModelSizes::of(model)),
        fidelity: fidelity.as_str(),
        calibration: None,
        load: load.display().to_string(),
        load_kind: table.kind.column(),
        hot_spot: h.hot_spot,
        slack_as_zero: h.slack_as_zero,
        samples: samples.len(),
        slack_samples,
        axial_stiffness: stiffness,
        turning_point_tolerance: options.turning_point_tolerance,
        turning_point_scale: options.turning_point_scale,
        sliding_stiffness: options.sliding_stiffness,
        resumed_from_checkpoint: resume.is_some(),
        checkpoints_written: observer.checkpoints.written(),
        history: &result.stats,
        run_in: run_in_of(&result),
        peaks_by_interface: peaks_by_interface(&result.contacts),
        wall_time_s: start.elapsed().as_secs_f64(),
    };
    std::fs::write(
        out.join("summary.json"),
        serde_json::to_string_pretty(&summary)?,
    )?;
    let s = &result.stats;
    tracing::info!(
        samples = s.samples,
        kept = s.kept_samples,
        substeps = s.substeps,
        iterations = s.iterations,
        wall_s = summary.wall_time_s,
        "strand history done; outputs in {}",
        out.display()
    );
    Ok(())
}

/// The output files of a history run, FE or reduced: monitors, contacts, contact records and
/// plots. `turning_points` are the samples an FE run at the run's tolerance solves.
fn write_outputs(
    out: &Path,
    result: &HistoryResult,
    table: &LoadTable,
    monitors: MonitorRows,
    turning_points: &[usize],
) -> anyhow::Result<()> {
    let every: Vec<usize>;
    let rows = match monitors {
        MonitorRows::TurningPoints => turning_points,
        MonitorRows::EverySample => {
            every = (0..result.monitors.time_s.len()).collect();
            &every
        }
    };
    write_monitors(&out.join("monitors.csv"), result, rows)?;
    write_contacts(&out.join("contacts.csv"), &result.contacts)?;
    std::fs::write(
        out.join("contact_records.json"),
        serde_json::to_vec(&result.contacts)?,
    )?;
    let load_plot = LoadPlot {
        tension_n: (table.kind == LoadKind::Tension).then_some(table.value.as_slice()),
    };
    strand_history_svgs(&result.monitors, &load_plot, out)?;
    Ok(())
}

/// A history run through the reduced response (`--fidelity reduced`).
struct ReducedRun<'a> {
    args: &'a ModelArgs,
    h: &'a HistoryArgs,
    load: &'a Path,
    out: &'a Path,
    table: &'a LoadTable,
    samples: &'a [LoadSample],
    stiffness: Option<AxialStiffness>,
    slack_samples: usize,
    options: &'a HistoryOptions,
    start: Instant,
}

impl ReducedRun<'_> {
    fn execute(self, lazy: &mut LazyModel<'_>) -> anyhow::Result<()> {
        let h = self.h;
        let margin = h.reduced.calibration_margin;
        if !(margin.is_finite() && (0.0..=1.0).contains(&margin)) {
            bail!("--calibration-margin {margin}: must lie in [0, 1]");
        }
        let range = range_of(self.samples)?;
        let request = CalibrationRequest {
            strand: lazy.strand,
            params: lazy.params,
            cache_dir: h.stiffness.cache_dir.as_deref(),
            given: h.reduced.calibration.as_deref(),
            threads: self.options.threads,
            refresh: h.stiffness.no_cache,
        };
        let mut observer = Observer::progress_only();
        let (strand, params) = (lazy.strand, lazy.params);
        let mut build = || StrandModel::new(strand, params).map_err(anyhow::Error::from);
        let (reduced, mut source) = calibration_for(
            &request,
            &range,
            range.widened(margin),
            &mut build,
            &mut observer,
        )?;
        observer.finish();
        let floor = reduced.lowest_designed_strain();
        source.samples_below_design_strain =
            self.samples.iter().filter(|s| s.strain < floor).count();
        let result = run_reduced(&reduced, self.samples, self.options)
            .map_err(|e| anyhow!("{}: {e}", self.load.display()))?;
        std::fs::create_dir_all(self.out)
            .with_context(|| format!("creating {}", self.out.display()))?;
        let turning_points = reduce_history_on_scale(
            self.samples,
            self.options.turning_point_tolerance,
            self.options.turning_point_scale,
        )?;
        write_outputs(self.out, &result, self.table, h.monitors, &turning_points)?;
        let summary = Summary {
            model: ModelDescription::of(self.args),
            sizes: None,
            fidelity: Fidelity::Reduced.as_str(),
            calibration: Some(source),
            load: self.load.display().to_string(),
            load_kind: self.table.kind.column(),
            hot_spot: h.hot_spot,
            slack_as_zero: h.slack_as_zero,
            samples: self.samples.len(),
            slack_samples: self.slack_samples,
            axial_stiffness: self.stiffness,
            turning_point_tolerance: self.options.turning_point_tolerance,
            turning_point_scale: self.options.turning_point_scale,
            sliding_stiffness: self.options.sliding_stiffness,
            resumed_from_checkpoint: false,
            checkpoints_written: 0,
            history: &result.stats,
            run_in: run_in_of(&result),
            peaks_by_interface: peaks_by_interface(&result.contacts),
            wall_time_s: self.start.elapsed().as_secs_f64(),
        };
        std::fs::write(
            self.out.join("summary.json"),
            serde_json::to_string_pretty(&summary)?,
        )?;
        tracing::info!(
            samples = self.samples.len(),
            reduced_s = result.stats.total_time_s,
            wall_s = summary.wall_time_s,
            "reduced strand history done; outputs in {}",
            self.out.display()
        );
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn table(text: &str) -> anyhow::Result<LoadTable> {
        let dir = tempfile::tempdir().unwrap();
        let p = dir.path().join("load.csv");
        std::fs::write(&p, text).unwrap();
        read_load(&p, false, 0)
    }

    #[test]
    fn load_columns_are_named_by_the_header_in_any_order() {
        let t = table("curvature_per_m,time_s,axial_strain\n0.01,0,1e-3\n0.02,1,2e-3\n").unwrap();
        assert_eq!(t.kind, LoadKind::Strain);
        assert_eq!(t.time_s, [0.0, 1.0]);
        assert_eq!(t.value, [1e-3, 2e-3]);
        assert_eq!(t.curvature_per_m, [0.01, 0.02]);
        let e = table("time_s,tension_n,axial_strain,curvature_per_m\n").unwrap_err();
        assert!(e.to_string().contains("column axial_strain"), "{e}");
        let e = table("time_s,curvature_per_m\n0,0\n").unwrap_err();
        assert!(e.to_string().contains("missing column tension_n"), "{e}");
        let e = table("time_s,tension_n,curvature_per_m\n0,1e4,0\n1,x,0\n").unwrap_err();
        assert!(
            e.to_string()
                .contains("sample 1 (line 3), column tension_n"),
            "{e}"
        );
    }

    #[test]
    fn a_global_runs_hot_spot_series_is_read_as_written() {
        let dir = tempfile::tempdir().unwrap();
        let p = dir.path().join("hotspots.csv");
        std::fs::write(
            &p,
            "time_s,tension_n_0,curvature_per_m_0,tension_n_1,curvature_per_m_1\n\
             0,1e5,0.01,2e5,0.02\n0.1,1.1e5,0.011,2.1e5,0.021\n",
        )
        .unwrap();
        let t = read_load(&p, false, 1).unwrap();
        assert_eq!(t.kind, LoadKind::Tension);
        assert_eq!(t.time_s, [0.0, 0.1]);
        assert_eq!(t.value, [2e5, 2.1e5]);
        assert_eq!(t.curvature_per_m, [0.02, 0.021]);
        assert_eq!(read_load(&p, false, 0).unwrap().value, [1e5, 1.1e5]);
        let e = read_load(&p, false, 2).unwrap_err().to_string();
        assert!(e.contains("no hot spot 2") && e.contains("[0, 1]"), "{e}");
    }

    #[test]
    fn channel_names_say_quantity_place_and_group() {
        let ch = |quantity, target, group, layer, theta_rad| MonitorChannel {
            quantity,
            target,
            group,
            layer,
            theta_rad,
            z_m: 0.1,
            values: Vec::new(),
        };
        use moorfret_solver::strand::history::monitors::MonitorQuantity as Q;
        let names = channel_names(&[
            ch(
                Q::Slip,
                MonitorTarget::Contact(3),
                MonitorGroup::OuterArc,
                1,
                1.5,
            ),
            ch(
                Q::WireAxialForce,
                MonitorTarget::Element(7),
                MonitorGroup::NeutralAxis,
                0,
                0.0,
            ),
            ch(
                Q::NormalForce,
                MonitorTarget::Contact(4),
                MonitorGroup::Ring,
                0,
                -std::f64::consts::FRAC_PI_2,
            ),
            ch(
                Q::NormalForce,
                MonitorTarget::Contact(5),
                MonitorGroup::Ring,
                0,
                -std::f64::consts::FRAC_PI_2,
            ),
        ]);
        assert_eq!(
            names,
            [
                "slip_m_layer2_on_layer1_outer_arc",
                "wire_axial_force_n_layer1_neutral_axis",
                "normal_force_n_layer1_on_core_ring_theta_-90deg",
                "normal_force_n_layer1_on_core_ring_theta_-90deg_contact5",
            ]
        );
    }
}
