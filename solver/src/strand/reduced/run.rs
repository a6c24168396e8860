//! A load history through the reduced strand response ([`super`] module docs).
//!
//! The contacts are Jenkins elements coupled through their interfaces' collective modes, so
//! the run steps them sample by sample: at each sample, Newton's method on the modes'
//! amplitudes, the later iterations stepping only the contacts that may change state. Their
//! drives and normal forces are formed in tiles of contacts and blocks of samples, and their
//! streaming rainflow counters at each block's end, in parallel (rayon); the results do not
//! depend on the thread count. The monitor channels get the same contact series, and the
//! wire-element channels their fitted axial force.

use std::time::Instant;

use rayon::prelude::*;

mod coupled;

use super::iwan::IwanContact;
use super::{force_features, JenkinsState, ReducedError, ReducedStrand, FORCE_FEATURES};
use crate::fretting::{ContactCycleAccumulator, ContactRecord, ContactSample, SlipCycle};
use crate::strand::history::monitors::{MonitorQuantity, MonitorSeries, MonitorTarget};
use crate::strand::history::reduce::samples_on_path;
use crate::strand::history::{HistoryOptions, HistoryResult, HistoryStats, LoadSample};

/// Checks every sample: finite, times increasing, inside the calibrated range.
fn check_samples(reduced: &ReducedStrand, samples: &[LoadSample]) -> Result<(), ReducedError> {
    let mut previous = f64::NEG_INFINITY;
    for (index, s) in samples.iter().enumerate() {
        for (field, value) in [
            ("time_s", s.time_s),
            ("strain", s.strain),
            ("curvature_per_m", s.curvature_per_m),
        ] {
            if !value.is_finite() {
                return Err(ReducedError::InvalidSample {
                    index,
                    field,
                    value,
                    reason: "not a finite number".into(),
                });
            }
        }
        if s.time_s <= previous {
            return Err(ReducedError::InvalidSample {
                index,
                field: "time_s",
                value: s.time_s,
                reason: "times must increase strictly".into(),
            });
        }
        previous = s.time_s;
        reduced.range.check(index, s)?;
    }
    Ok(())
}

/// Sub-steps of each leg of the initialisation path.
const INITIAL_SUBSTEPS: usize = 16;

/// The FE initialisation's path to the first sample (`crate::strand::history`), in scaled
/// loads: the straight strand at a small tension (the FE's, or the calibrated range's lowest
/// if that is higher), where every contact starts unloaded tangentially, then the first
/// curvature at that tension, then the first tension.
struct Initialisation {
    /// Where the contacts are unloaded.
    start: (f64, f64),
    /// The path from there to the first sample, in sub-steps.
    path: Vec<(f64, f64)>,
}

fn initialisation(reduced: &ReducedStrand, first: &LoadSample) -> Initialisation {
    // not below the calibrated range: the laws are not extrapolated, also not here
    let small = (reduced.initial_strain_fraction * first.strain).max(reduced.range.strain[0]);
    let start = reduced.scaling.scaled(small, 0.0);
    let bent = reduced.scaling.scaled(small, first.curvature_per_m);
    let end = reduced.scaling.scaled(first.strain, first.curvature_per_m);
    let mut path = Vec::with_capacity(2 * INITIAL_SUBSTEPS);
    for (a, b) in [(start, bent), (bent, end)] {
        for k in 1..=INITIAL_SUBSTEPS {
            let f = k as f64 / INITIAL_SUBSTEPS as f64;
            path.push((a.0 + f * (b.0 - a.0), a.1 + f * (b.1 - a.1)));
        }
    }
    Initialisation { start, path }
}

/// One contact through the history: its record and, if asked, its sample series.
fn run_contact(
    reduced: &ReducedStrand,
    h: &Scaled,
    c: usize,
    slip_gate_m: f64,
    keep_series: bool,
) -> Result<(ContactRecord, Vec<ContactSample>), ReducedError> {
    let (initial, loads, features) = (&h.initial, &h.loads, &h.features);
    let law = &reduced.laws[c];
    let site = &reduced.sites[c];
    let stick_per_m = reduced.friction_coefficient / reduced.elastic_slip_m;
    let mut acc =
        ContactCycleAccumulator::new(slip_gate_m).map_err(|e| ReducedError::InvalidSetting {
            field: "slip_gate_m",
            value: slip_gate_m,
            reason: e.to_string(),
        })?;
    let mut cycles: Vec<SlipCycle> = Vec::new();
    let mut series = Vec::with_capacity(if keep_series { loads.len() } else { 0 });
    let mut max_normal = 0.0_f64;
    let start = law.drive_m(initial.start.0, initial.start.1);
    let (g, r) = (law.compliance_m_per_n(), law.stick_ratio());
    let iwan = reduced
        .cattaneo_mindlin
        .as_ref()
        .and_then(|k| k.get(c).copied());
    let mut jenkins = JenkinsState::unloaded(start);
    let mut bank = IwanContact::unloaded(start);
    let mu = reduced.friction_coefficient;
    let mut step = |drive: f64, normal: f64| match iwan {
        Some(k) => {
            let st = bank.step(drive, normal, k.at(normal), g, r, mu);
            (st.slip_m, st.force_n)
        }
        None => jenkins.step(drive, normal, g, r, stick_per_m, reduced.elastic_slip_m),
    };
    for &(x, y) in &initial.path {
        step(law.drive_m(x, y), law.normal_force_n(&force_features(x, y)));
    }
    for (&(x, y), f) in loads.iter().zip(features) {
        let normal = law.normal_force_n(f);
        let (slip, tangential) = step(law.drive_m(x, y), normal);
        let sample = ContactSample {
            slip_m: slip,
            normal_force_n: normal,
            tangential_force_n: tangential,
        };
        acc.push(sample, &mut cycles)
            .map_err(|e| ReducedError::Calibration {
                reason: format!("contact {c}: {e}"),
            })?;
        max_normal = max_normal.max(normal);
        if keep_series {
            series.push(sample);
        }
    }
    acc.finish(&mut cycles);
    Ok((
        ContactRecord {
            interface: site.interface,
            theta_rad: site.theta_rad,
            z_m: site.z_m,
            max_normal_force_n: max_normal,
            cycles,
        },
        series,
    ))
}

/// Every contact through the history: alone, or coupled by the interfaces' collective
/// modes if the calibration has them.
fn run_contacts(
    reduced: &ReducedStrand,
    h: &Scaled,
    slip_gate_m: f64,
    keep_series: &(dyn Fn(usize) -> bool + Sync),
    step_all: bool,
) -> Result<Vec<(ContactRecord, Vec<ContactSample>)>, ReducedError> {
    match &reduced.modes {
        Some(coupling) if coupling.interfaces() > 0 => {
            coupled::run_coupled(reduced, coupling, h, slip_gate_m, keep_series, step_all)
        }
        _ => (0..reduced.laws.len())
            .into_par_iter()
            .map(|c| run_contact(reduced, h, c, slip_gate_m, keep_series(c)))
            .collect(),
    }
}

/// A checked history in the scaled loads, with its force features and the initialisation's
/// path to its first sample: what every contact runs through.
struct Scaled {
    loads: Vec<(f64, f64)>,
    features: Vec<[f64; FORCE_FEATURES]>,
    initial: Initialisation,
}

/// `samples` as the contacts run through them: checked, then, for a turning-point reduction
/// (`tolerance`, `scale_floor` of [`samples_on_path`]), each moved onto the FE run's load path.
fn scaled(
    reduced: &ReducedStrand,
    samples: &[LoadSample],
    tolerance: f64,
    scale_floor: [f64; 2],
) -> Result<Scaled, ReducedError> {
    let Some(first) = samples.first() else {
        return Err(ReducedError::InvalidSetting {
            field: "samples",
            value: 0.0,
            reason: "the load history is empty".into(),
        });
    };
    check_samples(reduced, samples)?;
    let path = samples_on_path(samples, tolerance, scale_floor).map_err(|e| {
        ReducedError::InvalidSetting {
            field: "turning_point_tolerance",
            value: tolerance,
            reason: e.to_string(),
        }
    })?;
    let loads: Vec<(f64, f64)> = path
        .iter()
        .map(|s| reduced.scaling.scaled(s.strain, s.curvature_per_m))
        .collect();
    let features = loads.iter().map(|&(x, y)| force_features(x, y)).collect();
    Ok(Scaled {
        loads,
        features,
        initial: initialisation(reduced, first),
    })
}

/// Every contact's (slip, normal force, tangential force) at every sample of `samples` as
/// given, in mesh contact order: the series behind [`run_reduced`]'s records (with a zero
/// turning-point tolerance), for studies that compare them sample by sample with an FE run.
pub fn contact_series(
    reduced: &ReducedStrand,
    samples: &[LoadSample],
) -> Result<Vec<Vec<ContactSample>>, ReducedError> {
    series(reduced, samples, false)
}

/// [`contact_series`] with every contact stepped in every Newton iteration of the coupled run:
/// the reference of its shortcut, which must give the same series to the bit.
#[cfg(test)]
pub(crate) fn contact_series_stepping_all(
    reduced: &ReducedStrand,
    samples: &[LoadSample],
) -> Result<Vec<Vec<ContactSample>>, ReducedError> {
    series(reduced, samples, true)
}

fn series(
    reduced: &ReducedStrand,
    samples: &[LoadSample],
    step_all: bool,
) -> Result<Vec<Vec<ContactSample>>, ReducedError> {
    let h = scaled(reduced, samples, 0.0, [0.0; 2])?;
    Ok(run_contacts(reduced, &h, 0.0, &|_| true, step_all)?
        .into_iter()
        .map(|r| r.1)
        .collect())
}

/// Runs `samples` through `reduced` (module docs): the outputs of an FE history run with
/// `options`, with every sample "kept" and the work counts of a run without sub-steps. The
/// contacts follow that FE run's load path: each sample on the straight segment between the
/// turning points around it, where the FE run solves it (`turning_point_tolerance` and
/// `turning_point_scale`; a zero tolerance takes every sample as it is). The slip rainflow
/// counters use `slip_gate_m`; the other options are the FE solver's own.
pub fn run_reduced(
    reduced: &ReducedStrand,
    samples: &[LoadSample],
    options: &HistoryOptions,
) -> Result<HistoryResult, ReducedError> {
    let start = Instant::now();
    let slip_gate_m = options.slip_gate_m;
    let h = scaled(
        reduced,
        samples,
        options.turning_point_tolerance,
        options.turning_point_scale,
    )?;
    let monitored: Vec<bool> = {
        let mut m = vec![false; reduced.laws.len()];
        for ch in &reduced.channels {
            if let MonitorTarget::Contact(c) = ch.target {
                if c < m.len() {
                    m[c] = true;
                }
            }
        }
        m
    };
    let results = run_contacts(reduced, &h, slip_gate_m, &|c| monitored[c], false)?;
    let mut monitors = MonitorSeries {
        time_s: samples.iter().map(|s| s.time_s).collect(),
        strain: samples.iter().map(|s| s.strain).collect(),
        curvature_per_m: samples.iter().map(|s| s.curvature_per_m).collect(),
        channels: reduced.channels.clone(),
    };
    let mut element = 0;
    for ch in &mut monitors.channels {
        ch.values = match ch.target {
            MonitorTarget::Contact(c) => {
                let series = results.get(c).map(|r| r.1.as_slice()).unwrap_or(&[]);
                series
                    .iter()
                    .map(|s| match ch.quantity {
                        MonitorQuantity::NormalForce => s.normal_force_n,
                        MonitorQuantity::TangentialForce => s.tangential_force_n,
                        _ => s.slip_m,
                    })
                    .collect()
            }
            MonitorTarget::Element(_) => {
                let fit = reduced
                    .element_fits
                    .get(element)
                    .copied()
                    .unwrap_or_default();
                element += 1;
                h.features
                    .iter()
                    .map(|f| f.iter().zip(&fit).map(|(a, b)| a * b).sum())
                    .collect()
            }
        };
    }
    let contacts = results.into_iter().map(|r| r.0).collect();
    let total = start.elapsed().as_secs_f64();
    Ok(HistoryResult {
        contacts,
        monitors,
        kept_samples: (0..samples.len()).collect(),
        stats: HistoryStats {
            samples: samples.len(),
            kept_samples: samples.len(),
            output_time_s: total,
            total_time_s: total,
            ..HistoryStats::default()
        },
    })
}
