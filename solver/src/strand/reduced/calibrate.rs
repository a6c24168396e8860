//! Calibration of a reduced strand response on its FE model ([`super`] module docs).

use std::collections::BTreeMap;
use std::time::Instant;

use super::compare::compare_records;
use super::design::{design_history_weighted, DesignParams};
use super::fit::FitAccumulator;
use super::{
    CalibrationReport, InterfaceFit, LoadRange, LoadScaling, ReducedError, ReducedStrand,
    FORMAT_VERSION,
};
use crate::contact::TangentialLaw;
use crate::fretting::ContactSample;
use crate::strand::history::checkpoint::HistoryCheckpoint;
use crate::strand::history::monitors::{
    contact_sites, default_channels, ContactSite, MonitorChannel, MonitorTarget,
};
use crate::strand::history::{
    run_history, HistoryObserver, HistoryOptions, HistoryProgress, HistoryStats, LoadSample,
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

/// Turns the samples of the calibration's FE run, in order, into least-squares sums.
struct Fitter {
    scaling: LoadScaling,
    /// Least-squares weight of every designed sample, by index (= its time in s).
    weights: Vec<f64>,
    fit: FitAccumulator,
    buffer: Vec<(f64, f64, f64)>,
}

impl Fitter {
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

/// Feeds every sample of the FE run to the fit, and passes progress on.
struct Learner<'a> {
    fitter: Fitter,
    inner: &'a mut dyn HistoryObserver,
}

impl HistoryObserver for Learner<'_> {
    fn progress(&mut self, progress: &HistoryProgress) {
        self.inner.progress(progress);
    }

    fn checkpoint(&mut self, _checkpoint: &HistoryCheckpoint) {}

    fn sample(&mut self, sample: &LoadSample, contacts: &[ContactSample], elements: &[f64]) {
        self.fitter.add(sample, contacts, elements);
    }

    fn should_stop(&mut self) -> bool {
        self.inner.should_stop()
    }
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

/// What a calibration fits from: the designed history and the sums it feeds.
struct Prepared {
    range: LoadRange,
    elastic_slip_m: f64,
    history: HistoryOptions,
    design: Vec<LoadSample>,
    sites: Vec<ContactSite>,
    channels: Vec<MonitorChannel>,
    fitter: Fitter,
}

/// The checked range, the model's elastic slip, the FE run's settings and the weighted
/// designed history of a calibration.
type Designed = (LoadRange, f64, HistoryOptions, Vec<(LoadSample, f64)>);

fn designed(
    model: &StrandModel,
    range: LoadRange,
    options: &CalibrationOptions,
) -> Result<Designed, ReducedError> {
    let range = range.validated()?;
    let elastic_slip_m = elastic_slip_of(model)?;
    let history = HistoryOptions {
        turning_point_tolerance: 0.0,
        checkpoint_interval_segments: 0,
        ..options.history
    };
    let weighted = design_history_weighted(&range, &options.design, &history);
    Ok((range, elastic_slip_m, history, weighted))
}

fn prepare(
    model: &StrandModel,
    range: LoadRange,
    options: &CalibrationOptions,
) -> Result<Prepared, ReducedError> {
    let (range, elastic_slip_m, history, weighted) = designed(model, range, options)?;
    let weights: Vec<f64> = weighted.iter().map(|(_, w)| *w).collect();
    let design: Vec<LoadSample> = weighted.into_iter().map(|(s, _)| s).collect();
    let sites = contact_sites(model);
    let channels = default_channels(model, &sites);
    let elements = channels
        .iter()
        .filter(|c| matches!(c.target, MonitorTarget::Element(_)))
        .count();
    let fitter = Fitter {
        scaling: LoadScaling::of(&range),
        weights,
        fit: FitAccumulator::new(model.contacts.len(), elements),
        buffer: Vec::with_capacity(model.contacts.len()),
    };
    Ok(Prepared {
        range,
        elastic_slip_m,
        history,
        design,
        sites,
        channels,
        fitter,
    })
}

/// The designed history of a calibration of `model` over `range` (what its FE run solves, and
/// what [`fit_recorded`] expects to be given, sample by sample).
pub fn calibration_design(
    model: &StrandModel,
    range: LoadRange,
    options: &CalibrationOptions,
) -> Result<(Vec<LoadSample>, HistoryOptions), ReducedError> {
    let (_, _, history, weighted) = designed(model, range, options)?;
    Ok((weighted.into_iter().map(|(s, _)| s).collect(), history))
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
    let p = prepare(model, range, options)?;
    let mut learner = Learner {
        fitter: p.fitter,
        inner: observer,
    };
    let fe = run_history(model, &p.design, &p.history, &mut learner)?;
    let p = Prepared {
        fitter: learner.fitter,
        ..p
    };
    let mut reduced = assemble(model, &p, &fe.stats, start);
    let replay = super::run_reduced(&reduced, &p.design, p.history.slip_gate_m)?;
    reduced.calibration.replay =
        compare_records(&fe.contacts, &replay.contacts, options.min_slip_range_m, 0);
    Ok(reduced)
}

/// One sample of a calibration's FE run: the load, every contact's state and every
/// wire-element channel's axial force, as the run's observer sees them.
pub type RecordedSample = (LoadSample, Vec<ContactSample>, Vec<f64>);

/// The reduced response fitted on a recorded FE run of [`calibration_design`] (the samples in
/// order, as [`HistoryObserver::sample`] saw them), without running the FE model: for studies
/// of the reduced model's form on one FE run. The report has no FE cost and no replay.
pub fn fit_recorded(
    model: &StrandModel,
    range: LoadRange,
    options: &CalibrationOptions,
    samples: impl IntoIterator<Item = RecordedSample>,
) -> Result<ReducedStrand, ReducedError> {
    let start = Instant::now();
    let mut p = prepare(model, range, options)?;
    for (load, contacts, elements) in samples {
        p.fitter.add(&load, &contacts, &elements);
    }
    Ok(assemble(model, &p, &HistoryStats::default(), start))
}

/// The reduced response of the fitted sums, with its in-sample fit report (no replay yet).
fn assemble(model: &StrandModel, p: &Prepared, fe: &HistoryStats, start: Instant) -> ReducedStrand {
    let fit = &p.fitter.fit;
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
        scaling: p.fitter.scaling,
        sites: p.sites.clone(),
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
            design_samples: p.design.len(),
            fe_substeps: fe.substeps,
            fe_iterations: fe.iterations,
            fe_wall_time_s: start.elapsed().as_secs_f64(),
            fits: fits_report,
            replay: Vec::new(),
        },
    }
}
