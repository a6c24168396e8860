//! Calibration of a reduced strand response on its FE model ([`super`] module docs).

use std::collections::{BTreeMap, VecDeque};
use std::sync::atomic::{AtomicBool, AtomicUsize, Ordering};
use std::sync::{mpsc, Mutex, OnceLock};
use std::time::Instant;

use super::compare::compare_records;
use super::design::{design_history_weighted, split_weights, DesignParams, LowestTension};
use super::fit::{FitAccumulator, StickStiffness};
use super::iwan::InitialStiffness;
use super::{
    CalibrationReport, ChainCost, InterfaceFit, LoadRange, LoadScaling, ModeCoupling, ReducedError,
    ReducedStrand, FORMAT_VERSION, MODES,
};
use crate::contact::TangentialLaw;
use crate::fretting::{ContactRecord, ContactSample};
use crate::strand::history::checkpoint::HistoryCheckpoint;
use crate::strand::history::monitors::{
    contact_sites, default_channels, ContactSite, MonitorChannel, MonitorTarget,
};
use crate::strand::history::{
    run_history, HistoryError, HistoryObserver, HistoryOptions, HistoryProgress, HistoryResult,
    LoadSample, NoObserver,
};
use crate::strand::model::{StrandModel, StrandModelParameters};
use crate::strand::profile::Strand;

/// Settings of a calibration.
#[derive(Clone, Debug, PartialEq)]
pub struct CalibrationOptions {
    /// Settings of the FE history run (its turning-point tolerance is set to 0: the designed
    /// history has no sample to drop).
    pub history: HistoryOptions,
    /// The designed history.
    pub design: DesignParams,
    /// Threshold of the counted slip cycles of the in-sample comparison (m).
    pub min_slip_range_m: f64,
}

impl Default for CalibrationOptions {
    fn default() -> Self {
        Self {
            history: HistoryOptions::default(),
            design: DesignParams::default(),
            min_slip_range_m: 1e-6,
        }
    }
}

/// The content address of a model's calibrations: what the FE model and its history run are
/// (threads excluded: results do not depend on them), the reduced format and the design.
pub fn model_key(
    strand: &Strand,
    params: &StrandModelParameters,
    options: &CalibrationOptions,
) -> String {
    use sha2::{Digest, Sha256};
    let history = HistoryOptions {
        threads: 1,
        ..options.history
    };
    let text = format!(
        "moorfret {} reduced strand format {FORMAT_VERSION}; strand {strand:?}; model \
         {params:?}; history {history:?}; design {:?}",
        env!("CARGO_PKG_VERSION"),
        options.design
    );
    Sha256::digest(text.as_bytes())
        .iter()
        .map(|b| format!("{b:02x}"))
        .collect()
}

/// Turns the samples of one chain of the calibration's FE run, in order, into least-squares
/// sums.
struct Fitter<'a> {
    scaling: LoadScaling,
    /// Least-squares weight of every sample of the chain, by index (= its time in s).
    weights: &'a [f64],
    fit: FitAccumulator,
    buffer: Vec<(f64, f64, f64)>,
}

impl Fitter<'_> {
    fn add(&mut self, sample: &LoadSample, contacts: &[ContactSample], elements: &[f64]) {
        let (x, y) = self.scaling.scaled(sample.strain, sample.curvature_per_m);
        self.buffer.clear();
        self.buffer.extend(
            contacts
                .iter()
                .map(|c| (c.slip_m, c.normal_force_n, c.tangential_force_n)),
        );
        let w = self
            .weights
            .get(sample.time_s as usize)
            .copied()
            .unwrap_or(1.0);
        self.fit.add(x, y, w, &self.buffer, elements);
    }
}

/// What the FE run of one chain tells the calling thread: the samples of the chain done so
/// far.
struct ChainProgress {
    chain: usize,
    samples: usize,
}

/// Feeds every sample of one chain's FE run to its fit, passes progress to the calling thread,
/// and stops when asked to. The fit takes the collective modes' answer off the FE slips: while
/// the modes are still being measured on another thread, the samples wait in `pending`.
/// `modes` holds `None` once known to be absent (a calibration without them).
struct Learner<'a> {
    chain: usize,
    prepared: &'a Prepared,
    modes: &'a OnceLock<Option<ModeCoupling>>,
    fitter: Option<Fitter<'a>>,
    pending: Vec<RecordedSample>,
    progress: mpsc::Sender<ChainProgress>,
    stop: &'a AtomicBool,
}

impl<'a> Learner<'a> {
    /// Starts the fit as soon as the modes are known, with the samples that waited for them.
    fn catch_up(&mut self) {
        if self.fitter.is_some() {
            return;
        }
        if let Some(modes) = self.modes.get() {
            let mut fitter = self.prepared.fitter(self.chain, modes.as_ref());
            for (sample, contacts, elements) in self.pending.drain(..) {
                fitter.add(&sample, &contacts, &elements);
            }
            self.pending = Vec::new();
            self.fitter = Some(fitter);
        }
    }
}

impl HistoryObserver for Learner<'_> {
    fn progress(&mut self, progress: &HistoryProgress) {
        // the calling thread may have gone (an error there): nothing left to tell
        let _ = self.progress.send(ChainProgress {
            chain: self.chain,
            samples: progress.sample + 1,
        });
    }

    fn checkpoint(&mut self, _checkpoint: &HistoryCheckpoint) {}

    fn sample(&mut self, sample: &LoadSample, contacts: &[ContactSample], elements: &[f64]) {
        self.catch_up();
        match &mut self.fitter {
            Some(fitter) => fitter.add(sample, contacts, elements),
            None => self
                .pending
                .push((*sample, contacts.to_vec(), elements.to_vec())),
        }
    }

    fn should_stop(&mut self) -> bool {
        self.stop.load(Ordering::Relaxed)
    }
}

/// The reduced form of the model's tangential law: the elastic slip γ_e of the elastic-slip
/// law (0 for the others) and the contacts' stick stiffness; the Cattaneo–Mindlin law's
/// contacts are Iwan banks with the FE elements' initial stiffness ([`super::iwan`]).
fn tangential_of(model: &StrandModel) -> Result<(f64, StickStiffness), ReducedError> {
    match model.contact_parameters.tangential {
        TangentialLaw::ElasticSlip { elastic_slip_m } => Ok((
            elastic_slip_m,
            StickStiffness::PerNewton(model.strand.friction_coefficient / elastic_slip_m),
        )),
        TangentialLaw::Mindlin => Err(ReducedError::Calibration {
            reason: "the reduced response models the elastic-slip and the Cattaneo-Mindlin \
                     tangential laws; this model uses Mindlin's stiffness up to the Coulomb \
                     limit (hertz-mindlin): run the FE model (fidelity fe)"
                .into(),
        }),
        TangentialLaw::CattaneoMindlin => {
            let stiffness = model
                .contacts
                .iter()
                .enumerate()
                .map(|(c, pair)| {
                    InitialStiffness::of(pair.laws()).ok_or(ReducedError::Calibration {
                        reason: format!(
                            "contact {c}: its laws have no Cattaneo-Mindlin initial stiffness"
                        ),
                    })
                })
                .collect::<Result<Vec<_>, _>>()?;
            Ok((0.0, StickStiffness::Initial(stiffness)))
        }
    }
}

/// What a calibration fits from: the designed history's chains and their weights.
struct Prepared {
    range: LoadRange,
    elastic_slip_m: f64,
    /// The contacts' stick stiffness.
    stick: StickStiffness,
    history: HistoryOptions,
    design: Vec<Vec<LoadSample>>,
    weights: Vec<Vec<f64>>,
    scaling: LoadScaling,
    sites: Vec<ContactSite>,
    channels: Vec<MonitorChannel>,
    element_channels: usize,
    modes: Option<ModeCoupling>,
    /// The load points of the modes' measurement ([`super::modes::mode_points`]).
    mode_points: Vec<(f64, f64)>,
}

/// The layer interfaces' collective modes of `model` over `range`, measured on the FE model
/// (the `modes` module), as a calibration measures them beside its designed history.
pub fn measure_modes(
    model: &StrandModel,
    range: LoadRange,
    options: &CalibrationOptions,
) -> Result<ModeCoupling, ReducedError> {
    let mut p = prepare(model, range, options)?;
    p.design.clear();
    p.weights.clear();
    let (modes, _, _) = run_chains(model, &p, &mut NoObserver)?;
    modes.ok_or(ReducedError::Calibration {
        reason: "no load point at which to measure the collective modes".into(),
    })
}

impl Prepared {
    /// Empty sums for every contact and element channel.
    fn accumulator(&self) -> FitAccumulator {
        FitAccumulator::new(self.sites.len(), self.element_channels, self.stick.clone())
    }

    /// Empty sums for one chain, which take the answer of `modes` off the FE slips.
    fn fitter(&self, chain: usize, modes: Option<&ModeCoupling>) -> Fitter<'_> {
        Fitter {
            scaling: self.scaling,
            weights: &self.weights[chain],
            fit: self.accumulator().with_modes(&self.sites, modes),
            buffer: Vec::with_capacity(self.sites.len()),
        }
    }
}

/// The checked range, the FE run's settings, and the designed history's chains of a
/// calibration with the least-squares weight of every sample.
type Designed = (
    LoadRange,
    HistoryOptions,
    Vec<Vec<LoadSample>>,
    Vec<Vec<f64>>,
);

/// Whether the calibration of `model` measures the layer interfaces' collective modes: under
/// the elastic-slip law, not under the Cattaneo–Mindlin law. Under that law the reduced
/// response follows the FE model closer without them, on a mild, a medium and a severe cell
/// of the paper's diagram (`docs/reduced-strand.md`): the irreversible slip that would feed
/// them, s − f_T/k, is the micro-slip of every contact in partial slip, local to its contact,
/// and the modes then move contacts that the FE model holds still.
fn measures_modes(model: &StrandModel) -> bool {
    !model.contact_parameters.is_cattaneo_mindlin()
}

/// How low in tension the calibration of `model` goes ([`LowestTension::of_law`]).
fn lowest_tension_of(model: &StrandModel) -> LowestTension {
    LowestTension::of_law(model.contact_parameters.is_cattaneo_mindlin())
}

fn designed(
    range: LoadRange,
    options: &CalibrationOptions,
    lowest: LowestTension,
) -> Result<Designed, ReducedError> {
    let range = range.validated()?;
    let history = HistoryOptions {
        turning_point_tolerance: 0.0,
        checkpoint_interval_segments: 0,
        ..options.history
    };
    let (design, weights) = split_weights(design_history_weighted(
        &range,
        &options.design,
        &history,
        lowest,
    ));
    Ok((range, history, design, weights))
}

fn prepare(
    model: &StrandModel,
    range: LoadRange,
    options: &CalibrationOptions,
) -> Result<Prepared, ReducedError> {
    let (elastic_slip_m, stick) = tangential_of(model)?;
    let lowest = lowest_tension_of(model);
    let (range, history, design, weights) = designed(range, options, lowest)?;
    let sites = contact_sites(model);
    let channels = default_channels(model, &sites);
    let element_channels = channels
        .iter()
        .filter(|c| matches!(c.target, MonitorTarget::Element(_)))
        .count();
    Ok(Prepared {
        modes: None,
        mode_points: super::modes::mode_points(lowest.mode_floor(&range)),
        scaling: LoadScaling::of(&range),
        range,
        elastic_slip_m,
        stick,
        history,
        design,
        weights,
        sites,
        channels,
        element_channels,
    })
}

/// The designed history of a calibration of `model` over `range`, as its chains (what its FE
/// runs solve, one run per chain, and what [`fit_recorded`] expects to be given, sample by
/// sample), and the settings of those runs.
pub fn calibration_design(
    model: &StrandModel,
    range: LoadRange,
    options: &CalibrationOptions,
) -> Result<(Vec<Vec<LoadSample>>, HistoryOptions), ReducedError> {
    let (_, history, design, _) = designed(range, options, lowest_tension_of(model))?;
    Ok((design, history))
}

/// One chain's FE run and the sums it fed.
struct ChainRun {
    fit: FitAccumulator,
    fe: HistoryResult,
    wall_time_s: f64,
}

/// What one task of [`run_chains`] left: the amplifications at a knot of the collective modes,
/// or a chain's FE run with its fit, or its samples if the modes were not known yet.
enum Done<'a> {
    Knot(Vec<Vec<[f64; MODES]>>),
    Chain(Box<ChainDone<'a>>),
}

/// A chain's FE run with its fit, or its samples if the modes were not known yet.
struct ChainDone<'a> {
    fitter: Option<Fitter<'a>>,
    pending: Vec<RecordedSample>,
    fe: HistoryResult,
    wall_time_s: f64,
}

/// A task of [`run_chains`].
#[derive(Clone, Copy, Debug)]
enum Task {
    /// The FE run to the knots of the collective modes.
    Stroke,
    /// The collective modes at one knot, from the stroke's state there.
    Knot(usize),
    /// One chain of the design.
    Chain(usize),
}

/// Measures the collective modes at the knots of `p.mode_points` and runs the
/// FE model through every chain of the design, as many of these tasks at a time as
/// `p.history.threads` (each on one thread; with more threads than tasks, the threads are
/// shared out): first one FE run through the knots ([`super::modes::Stroke`]), beside the
/// first chains; then the knots, each probed from the stroke's state there, before the
/// chains left. A chain that runs while the modes are still being measured keeps its samples
/// until they are known, then fits them in order: the sums, and so the results, do not depend
/// on the threads. `observer` sees the samples done over all chains and may stop the runs.
/// Without knots there is no stroke and no modes: every chain fits as it runs.
/// Returns the modes, the chains' runs and the wall time until the modes were known (s).
fn run_chains(
    model: &StrandModel,
    p: &Prepared,
    observer: &mut dyn HistoryObserver,
) -> Result<(Option<ModeCoupling>, Vec<ChainRun>, f64), ReducedError> {
    let start = Instant::now();
    let knots = &p.mode_points[..];
    let chains = p.design.len();
    // the stroke, the knots and the chains, in the order of `results`
    let tasks = 1 + knots.len() + chains;
    let slot_of = |task: Task| match task {
        Task::Stroke => 0,
        Task::Knot(k) => 1 + k,
        Task::Chain(c) => 1 + knots.len() + c,
    };
    let concurrent = p.history.threads.clamp(1, 1 + chains.max(knots.len()));
    let per_run = HistoryOptions {
        threads: (p.history.threads / concurrent).max(1),
        ..p.history
    };
    let with_modes = !knots.is_empty();
    let queue: Mutex<VecDeque<Task>> = Mutex::new(
        with_modes
            .then_some(Task::Stroke)
            .into_iter()
            .chain((0..chains).map(Task::Chain))
            .collect(),
    );
    let stroke: OnceLock<super::modes::Stroke> = OnceLock::new();
    let stroke_pending = AtomicBool::new(with_modes);
    let knots_left = AtomicUsize::new(knots.len());
    let modes: OnceLock<Option<ModeCoupling>> = OnceLock::new();
    if !with_modes {
        let _ = modes.set(None);
    }
    let modes_known_s = Mutex::new(0.0);
    let stop = AtomicBool::new(false);
    let results: Vec<Mutex<Option<Result<Done, ReducedError>>>> =
        (0..tasks).map(|_| Mutex::new(None)).collect();
    let total: usize = p.design.iter().map(Vec::len).sum();
    let (sender, receiver) = mpsc::channel();
    std::thread::scope(|scope| {
        for _ in 0..concurrent {
            let sender = sender.clone();
            let (queue, stop, results, per_run) = (&queue, &stop, &results, &per_run);
            let (stroke, stroke_pending, knots_left, modes, modes_known_s) = (
                &stroke,
                &stroke_pending,
                &knots_left,
                &modes,
                &modes_known_s,
            );
            scope.spawn(move || loop {
                if stop.load(Ordering::Relaxed) {
                    break;
                }
                let Some(task) = queue.lock().ok().and_then(|mut q| q.pop_front()) else {
                    // the stroke, still running, will queue the knots
                    if stroke_pending.load(Ordering::SeqCst) {
                        std::thread::sleep(std::time::Duration::from_millis(20));
                        continue;
                    }
                    break;
                };
                let outcome = match task {
                    Task::Stroke => {
                        let run = super::modes::Stroke::run(model, &p.scaling, knots, per_run);
                        let outcome = match run {
                            Ok(s) => {
                                let _ = stroke.set(s);
                                // the knots go before the chains not started yet
                                if let Ok(mut q) = queue.lock() {
                                    for k in (0..knots.len()).rev() {
                                        q.push_front(Task::Knot(k));
                                    }
                                }
                                None
                            }
                            Err(e) => Some(Err(e)),
                        };
                        stroke_pending.store(false, Ordering::SeqCst);
                        match outcome {
                            None => continue,
                            Some(e) => e,
                        }
                    }
                    Task::Knot(k) => {
                        let measured = stroke
                            .get()
                            .ok_or(ReducedError::Calibration {
                                reason: "a knot of the modes before their stroke".into(),
                            })
                            .and_then(|s| s.probe(model, k))
                            .and_then(|probe| super::modes::measure_point(&probe));
                        match measured {
                            Ok(table) => {
                                if let Ok(mut slot) = results[slot_of(task)].lock() {
                                    *slot = Some(Ok(Done::Knot(table)));
                                }
                                // the last knot measured: the modes are known to every chain
                                if knots_left.fetch_sub(1, Ordering::SeqCst) == 1 {
                                    let amplification = results[1..1 + knots.len()]
                                        .iter()
                                        .filter_map(|slot| match slot.lock().ok()?.as_ref()? {
                                            Ok(Done::Knot(table)) => Some(table.clone()),
                                            _ => None,
                                        })
                                        .collect();
                                    let _ = modes.set(Some(ModeCoupling {
                                        knots: knots.iter().map(|k| k.0).collect(),
                                        amplification,
                                    }));
                                    if let Ok(mut t) = modes_known_s.lock() {
                                        *t = start.elapsed().as_secs_f64();
                                    }
                                }
                                continue;
                            }
                            Err(e) => Err(e),
                        }
                    }
                    Task::Chain(chain) => {
                        let t = Instant::now();
                        let mut learner = Learner {
                            chain,
                            prepared: p,
                            modes,
                            fitter: None,
                            pending: Vec::new(),
                            progress: sender.clone(),
                            stop,
                        };
                        let run = run_history(model, &p.design[chain], per_run, &mut learner);
                        learner.catch_up();
                        run.map(|fe| {
                            Done::Chain(Box::new(ChainDone {
                                fitter: learner.fitter,
                                pending: learner.pending,
                                fe,
                                wall_time_s: t.elapsed().as_secs_f64(),
                            }))
                        })
                        .map_err(|source| ReducedError::History { chain, source })
                    }
                };
                if outcome.is_err() {
                    stop.store(true, Ordering::Relaxed);
                }
                if let Ok(mut slot) = results[slot_of(task)].lock() {
                    *slot = Some(outcome);
                }
            });
        }
        drop(sender);
        let mut done = vec![0; chains];
        for ChainProgress { chain, samples } in receiver {
            done[chain] = samples;
            let samples: usize = done.iter().sum();
            observer.progress(&HistoryProgress {
                segment: samples,
                segments: total,
                sample: samples.saturating_sub(1),
                time_s: samples as f64,
                elapsed_s: start.elapsed().as_secs_f64(),
            });
            if observer.should_stop() {
                stop.store(true, Ordering::Relaxed);
            }
        }
    });
    // the first task that failed, rather than one that stopped because of it; a task that
    // never started was stopped before it
    let mut done = Vec::with_capacity(chains);
    let mut stopped = None;
    for (task, slot) in results.into_iter().enumerate() {
        let chain = task.saturating_sub(1 + knots.len());
        let slot = slot.into_inner().ok().flatten();
        if task == 0 && slot.is_none() && (!with_modes || stroke.get().is_some()) {
            continue;
        }
        match slot {
            Some(Ok(d)) => done.push(d),
            Some(Err(
                e @ ReducedError::History {
                    source: HistoryError::Stopped { .. },
                    ..
                },
            )) => {
                stopped.get_or_insert(e);
            }
            Some(Err(e)) => return Err(e),
            None => {
                stopped.get_or_insert(ReducedError::History {
                    chain,
                    source: HistoryError::Stopped {
                        segment: 0,
                        time_s: 0.0,
                    },
                });
            }
        }
    }
    if let Some(e) = stopped {
        return Err(e);
    }
    let modes = modes.get().cloned().ok_or(ReducedError::Calibration {
        reason: "the collective modes were not measured at every knot".into(),
    })?;
    let modes_known_s = modes_known_s.into_inner().unwrap_or(0.0);
    let mut runs = Vec::with_capacity(chains);
    for (chain, d) in done.into_iter().skip(knots.len()).enumerate() {
        if let Done::Chain(chain_done) = d {
            let ChainDone {
                fitter,
                pending,
                fe,
                wall_time_s,
            } = *chain_done;
            // a chain that ended before the modes were known fits its samples now
            let mut fitter = fitter.unwrap_or_else(|| p.fitter(chain, modes.as_ref()));
            for (sample, contacts, elements) in pending {
                fitter.add(&sample, &contacts, &elements);
            }
            runs.push(ChainRun {
                fit: fitter.fit,
                fe,
                wall_time_s,
            });
        }
    }
    Ok((modes, runs, modes_known_s))
}

/// Calibrates the reduced response of `model` over `range` (module docs of [`super`]);
/// `observer` sees the progress of the FE run and may stop it.
pub fn calibrate(
    model: &StrandModel,
    range: LoadRange,
    options: &CalibrationOptions,
    observer: &mut dyn HistoryObserver,
) -> Result<ReducedStrand, ReducedError> {
    let start = Instant::now();
    let mut p = prepare(model, range, options)?;
    if !measures_modes(model) {
        p.mode_points.clear();
    }
    let (modes, runs, modes_wall_time_s) = run_chains(model, &p, observer)?;
    p.modes = modes;
    let mut fit = p.accumulator();
    let mut costs = Vec::with_capacity(runs.len());
    for (chain, run) in runs.iter().enumerate() {
        fit.merge(&run.fit);
        costs.push(ChainCost {
            samples: p.design[chain].len(),
            substeps: run.fe.stats.substeps,
            iterations: run.fe.stats.iterations,
            wall_time_s: run.wall_time_s,
        });
    }
    let mut reduced = assemble(model, &p, &fit, costs, start);
    reduced.calibration.modes_wall_time_s = modes_wall_time_s;
    // the design replayed chain by chain, every contact's cycles of all chains together
    let mut fe: Vec<ContactRecord> = Vec::new();
    let mut replay: Vec<ContactRecord> = Vec::new();
    for (chain, run) in p.design.iter().zip(runs) {
        let r = super::run_reduced(&reduced, chain, &p.history)?;
        append_cycles(&mut fe, run.fe.contacts);
        append_cycles(&mut replay, r.contacts);
    }
    reduced.calibration.replay = compare_records(&fe, &replay, options.min_slip_range_m, 0);
    Ok(reduced)
}

/// Adds every contact's cycles of `more` to those of `all` (the same contacts, in order), the
/// largest normal force the larger of the two.
fn append_cycles(all: &mut Vec<ContactRecord>, more: Vec<ContactRecord>) {
    if all.is_empty() {
        *all = more;
        return;
    }
    for (a, b) in all.iter_mut().zip(more) {
        a.max_normal_force_n = a.max_normal_force_n.max(b.max_normal_force_n);
        a.cycles.extend(b.cycles);
    }
}

/// One sample of a calibration's FE run: the load, every contact's state and every
/// wire-element channel's axial force, as the run's observer sees them.
pub type RecordedSample = (LoadSample, Vec<ContactSample>, Vec<f64>);

/// The reduced response fitted on recorded FE runs of the chains of [`calibration_design`]
/// (every chain's samples in order, as [`HistoryObserver::sample`] saw them), without running
/// the FE model: for studies of the reduced model's form on one FE run, with the collective
/// modes measured apart ([`measure_modes`]). The report has no FE cost and no replay.
pub fn fit_recorded<C>(
    model: &StrandModel,
    range: LoadRange,
    options: &CalibrationOptions,
    modes: ModeCoupling,
    chains: impl IntoIterator<Item = C>,
) -> Result<ReducedStrand, ReducedError>
where
    C: IntoIterator<Item = RecordedSample>,
{
    let start = Instant::now();
    let mut p = prepare(model, range, options)?;
    p.modes = Some(modes);
    let mut fit = p.accumulator();
    for (chain, samples) in chains.into_iter().enumerate() {
        if chain >= p.design.len() {
            return Err(ReducedError::Calibration {
                reason: format!(
                    "a recording of {} chains or more for a design of {}",
                    chain + 1,
                    p.design.len()
                ),
            });
        }
        let mut fitter = p.fitter(chain, p.modes.as_ref());
        for (load, contacts, elements) in samples {
            fitter.add(&load, &contacts, &elements);
        }
        fit.merge(&fitter.fit);
    }
    Ok(assemble(model, &p, &fit, Vec::new(), start))
}

/// The reduced response of the fitted sums, with its in-sample fit report (no replay yet).
fn assemble(
    model: &StrandModel,
    p: &Prepared,
    fit: &FitAccumulator,
    chains: Vec<ChainCost>,
    start: Instant,
) -> ReducedStrand {
    let fits = fit.contact_fits();
    let element_fits = fit
        .element_fits()
        .into_iter()
        .map(|f| f.coefficients)
        .collect();
    let mut per_interface: BTreeMap<usize, InterfaceFit> = BTreeMap::new();
    for (site, f) in p.sites.iter().zip(&fits) {
        let e = per_interface.entry(site.interface).or_insert(InterfaceFit {
            interface: site.interface,
            contacts: 0,
            slip_rms_residual_m: 0.0,
            slip_rms_m: 0.0,
            normal_rms_residual_n: 0.0,
            normal_rms_n: 0.0,
            compliance_clamped: 0,
        });
        e.contacts += 1;
        e.slip_rms_residual_m += f.slip_residual_ss;
        e.slip_rms_m += f.slip_spread_ss;
        e.normal_rms_residual_n += f.normal_residual_ss;
        e.normal_rms_n += f.normal_spread_ss;
        e.compliance_clamped += usize::from(f.compliance_clamped);
    }
    // weighted root mean squares (the weights of the design, `design::design_history_weighted`)
    let n = fit.weight().max(f64::MIN_POSITIVE);
    let fits_report = per_interface
        .into_values()
        .map(|mut e| {
            let m = n * e.contacts.max(1) as f64;
            e.slip_rms_residual_m = (e.slip_rms_residual_m / m).sqrt();
            e.slip_rms_m = (e.slip_rms_m / m).sqrt();
            e.normal_rms_residual_n = (e.normal_rms_residual_n / m).sqrt();
            e.normal_rms_n = (e.normal_rms_n / m).sqrt();
            e
        })
        .collect();

    ReducedStrand {
        format: FORMAT_VERSION,
        model_key: String::new(),
        friction_coefficient: model.strand.friction_coefficient,
        elastic_slip_m: p.elastic_slip_m,
        initial_strain_fraction: p.history.initial_strain_fraction,
        range: p.range,
        scaling: p.scaling,
        sites: p.sites.clone(),
        modes: p.modes.clone(),
        cattaneo_mindlin: match &p.stick {
            StickStiffness::Initial(k0) => Some(k0.clone()),
            StickStiffness::PerNewton(_) => None,
        },
        laws: fits.iter().map(|f| f.law).collect(),
        channels: p
            .channels
            .iter()
            .cloned()
            .map(|mut c| {
                c.values.clear();
                c
            })
            .collect(),
        element_fits,
        calibration: CalibrationReport {
            design_samples: p.design.iter().map(Vec::len).sum(),
            fe_substeps: chains.iter().map(|c| c.substeps).sum(),
            fe_iterations: chains.iter().map(|c| c.iterations).sum(),
            fe_wall_time_s: start.elapsed().as_secs_f64(),
            chains,
            modes_wall_time_s: 0.0,
            fits: fits_report,
            replay: Vec::new(),
        },
    }
}
