//! Calibration of a reduced strand response on its FE model ([`super`] module docs).

use std::collections::BTreeMap;
use std::sync::atomic::{AtomicBool, AtomicUsize, Ordering};
use std::sync::mpsc;
use std::time::{Duration, Instant};

use super::compare::compare_records;
use super::design::{design_histories_weighted, DesignParams};
use super::fit::FitAccumulator;
use super::{
    CalibrationReport, InterfaceFit, LoadRange, LoadScaling, ReducedError, ReducedStrand,
    FORMAT_VERSION,
};
use crate::contact::TangentialLaw;
use crate::fretting::{ContactRecord, ContactSample};
use crate::strand::history::checkpoint::HistoryCheckpoint;
use crate::strand::history::monitors::contact_sites;
use crate::strand::history::monitors::{default_channels, MonitorTarget};
use crate::strand::history::{
    run_history, HistoryError, HistoryObserver, HistoryOptions, HistoryProgress, HistoryStats,
    LoadSample,
};
use crate::strand::model::{StrandModel, StrandModelParameters};
use crate::strand::profile::Strand;

/// Settings of a calibration.
#[derive(Clone, Debug, PartialEq)]
pub struct CalibrationOptions {
    /// Settings of the FE history runs (their turning-point tolerance is set to 0: the designed
    /// history has no sample to drop). Its threads solve the design's parts side by side.
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

/// Feeds every sample of one part's FE run to its fit, and passes progress on to the caller's
/// thread.
struct Learner<'a> {
    part: usize,
    scaling: LoadScaling,
    /// Least-squares weight of every designed sample, by index (= its time in s).
    weights: &'a [f64],
    fit: FitAccumulator,
    buffer: Vec<(f64, f64, f64)>,
    progress: mpsc::Sender<(usize, HistoryProgress)>,
    stop: &'a AtomicBool,
}

impl HistoryObserver for Learner<'_> {
    fn progress(&mut self, progress: &HistoryProgress) {
        // the receiver lives until every part has ended
        let _ = self.progress.send((self.part, *progress));
    }

    fn checkpoint(&mut self, _checkpoint: &HistoryCheckpoint) {}

    fn sample(&mut self, sample: &LoadSample, contacts: &[ContactSample], elements: &[f64]) {
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

    fn should_stop(&mut self) -> bool {
        self.stop.load(Ordering::Relaxed)
    }
}

/// What one part's FE run leaves: its fit sums, contact records and work counts.
struct PartRun {
    fit: FitAccumulator,
    contacts: Vec<ContactRecord>,
    stats: HistoryStats,
}

/// Runs the FE model through every part of the design, `threads` at a time side by side (each
/// run on its share of the threads), and hands the caller's `observer` the summed progress on
/// this thread. The results are in part order and do not depend on `threads`.
fn run_parts(
    model: &StrandModel,
    parts: &[(Vec<LoadSample>, Vec<f64>)],
    history: &HistoryOptions,
    scaling: LoadScaling,
    elements: usize,
    observer: &mut dyn HistoryObserver,
) -> Result<Vec<PartRun>, HistoryError> {
    let runners = history.threads.clamp(1, parts.len().max(1));
    let per_run = HistoryOptions {
        threads: (history.threads / runners).max(1),
        ..*history
    };
    let next = AtomicUsize::new(0);
    let stop = AtomicBool::new(false);
    let (tx, rx) = mpsc::channel::<(usize, HistoryProgress)>();
    let (done_tx, done_rx) = mpsc::channel::<(usize, Result<PartRun, HistoryError>)>();
    std::thread::scope(|scope| {
        for _ in 0..runners {
            let (tx, done_tx) = (tx.clone(), done_tx.clone());
            let (next, stop, per_run) = (&next, &stop, &per_run);
            scope.spawn(move || loop {
                let p = next.fetch_add(1, Ordering::Relaxed);
                let Some((samples, weights)) = parts.get(p) else {
                    break;
                };
                let mut learner = Learner {
                    part: p,
                    scaling,
                    weights,
                    fit: FitAccumulator::new(model.contacts.len(), elements),
                    buffer: Vec::with_capacity(model.contacts.len()),
                    progress: tx.clone(),
                    stop,
                };
                let run = run_history(model, samples, per_run, &mut learner).map(|fe| PartRun {
                    fit: learner.fit,
                    contacts: fe.contacts,
                    stats: fe.stats,
                });
                if run.is_err() {
                    // the calibration fails with the first failing part: stop the others
                    stop.store(true, Ordering::Relaxed);
                }
                let _ = done_tx.send((p, run));
            });
        }
        drop((tx, done_tx));
        // this thread passes the summed progress on and asks the observer whether to stop,
        // until every runner has ended (and dropped its sender)
        let total: usize = parts.iter().map(|(s, _)| s.len().saturating_sub(1)).sum();
        let mut latest: Vec<Option<HistoryProgress>> = vec![None; parts.len()];
        let start = Instant::now();
        loop {
            match rx.recv_timeout(Duration::from_millis(200)) {
                Ok((p, progress)) => {
                    latest[p] = Some(progress);
                    let segment = latest.iter().flatten().map(|l| l.segment).sum();
                    let last = latest
                        .iter()
                        .flatten()
                        .map(|l| l.time_s)
                        .fold(0.0, f64::max);
                    observer.progress(&HistoryProgress {
                        segment,
                        segments: total,
                        sample: segment,
                        time_s: last,
                        elapsed_s: start.elapsed().as_secs_f64(),
                    });
                    if observer.should_stop() {
                        stop.store(true, Ordering::Relaxed);
                    }
                }
                Err(mpsc::RecvTimeoutError::Timeout) => {}
                Err(mpsc::RecvTimeoutError::Disconnected) => break,
            }
        }
    });
    let mut done: Vec<Option<Result<PartRun, HistoryError>>> =
        (0..parts.len()).map(|_| None).collect();
    for (p, run) in done_rx.try_iter() {
        done[p] = Some(run);
    }
    done.into_iter()
        .enumerate()
        .map(|(p, run)| {
            run.unwrap_or_else(|| {
                Err(HistoryError::InvalidOption {
                    field: "parts",
                    value: p as f64,
                    reason: "a part of the designed history was not run".into(),
                })
            })
        })
        .collect()
}

/// The elastic slip γ_e of the model's tangential law; other laws have no reduced form here.
fn elastic_slip_of(model: &StrandModel) -> Result<f64, ReducedError> {
    match model.contact_parameters.tangential {
        TangentialLaw::ElasticSlip { elastic_slip_m } => Ok(elastic_slip_m),
        TangentialLaw::Mindlin => Err(ReducedError::Calibration {
            reason: "the reduced response models the elastic-slip tangential law; this model \
                     uses the Mindlin law"
                .into(),
        }),
    }
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
    let range = range.validated()?;
    let elastic_slip_m = elastic_slip_of(model)?;
    let history = HistoryOptions {
        turning_point_tolerance: 0.0,
        checkpoint_interval_segments: 0,
        ..options.history
    };
    let parts: Vec<(Vec<LoadSample>, Vec<f64>)> =
        design_histories_weighted(&range, &options.design, &history)
            .into_iter()
            .map(|part| part.into_iter().unzip())
            .collect();
    let scaling = LoadScaling::of(&range);
    let sites = contact_sites(model);
    // the wire-element channels of the monitors the run makes
    let channels = default_channels(model, &sites);
    let elements = channels
        .iter()
        .filter(|c| matches!(c.target, MonitorTarget::Element(_)))
        .count();
    let runs = run_parts(model, &parts, &history, scaling, elements, observer)?;
    let mut fit = FitAccumulator::new(model.contacts.len(), elements);
    let mut fe_substeps = 0;
    let mut fe_iterations = 0;
    for run in &runs {
        fit.merge(&run.fit);
        fe_substeps += run.stats.substeps;
        fe_iterations += run.stats.iterations;
    }
    let fits = fit.contact_fits();
    let element_fits = fit
        .element_fits()
        .into_iter()
        .map(|f| f.coefficients)
        .collect();

    let mut per_interface: BTreeMap<usize, InterfaceFit> = BTreeMap::new();
    for (site, f) in sites.iter().zip(&fits) {
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

    let mut reduced = ReducedStrand {
        format: FORMAT_VERSION,
        model_key: String::new(),
        friction_coefficient: model.strand.friction_coefficient,
        elastic_slip_m,
        range,
        scaling,
        sites,
        laws: fits.iter().map(|f| f.law).collect(),
        channels: channels
            .into_iter()
            .map(|mut c| {
                c.values.clear();
                c
            })
            .collect(),
        element_fits,
        calibration: CalibrationReport {
            design_samples: parts.iter().map(|(s, _)| s.len()).sum(),
            design_parts: parts.len(),
            fe_substeps,
            fe_iterations,
            fe_wall_time_s: start.elapsed().as_secs_f64(),
            fits: fits_report,
            replay: Vec::new(),
        },
    };
    // the in-sample replay: every part through the reduced model as through the FE model, the
    // slip cycles of a contact over all parts together
    let mut fe_records: Vec<ContactRecord> = Vec::new();
    let mut replay_records: Vec<ContactRecord> = Vec::new();
    for ((samples, _), run) in parts.iter().zip(runs) {
        let replay = super::run_reduced(&reduced, samples, history.slip_gate_m)?;
        append_records(&mut fe_records, run.contacts);
        append_records(&mut replay_records, replay.contacts);
    }
    reduced.calibration.replay =
        compare_records(&fe_records, &replay_records, options.min_slip_range_m, 0);
    Ok(reduced)
}

/// Adds one part's records to the records of the parts before it: the same contacts, in mesh
/// order, with every slip cycle of both.
fn append_records(all: &mut Vec<ContactRecord>, part: Vec<ContactRecord>) {
    if all.is_empty() {
        *all = part;
        return;
    }
    for (a, b) in all.iter_mut().zip(part) {
        a.max_normal_force_n = a.max_normal_force_n.max(b.max_normal_force_n);
        a.cycles.extend(b.cycles);
    }
}
