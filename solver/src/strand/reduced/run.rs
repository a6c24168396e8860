//! A load history through the reduced strand response ([`super`] module docs).
//!
//! The contacts are independent Jenkins elements, so they run in parallel (rayon), each through
//! the whole history into its own streaming rainflow counter; the results do not depend on the
//! thread count. The monitor channels get the same contact series, and the wire-element
//! channels their fitted axial force.

use std::time::Instant;

use rayon::prelude::*;

use super::{
    force_features, mode_shapes, JenkinsState, ReducedError, ReducedStrand, FORCE_FEATURES, MODES,
};
use crate::fretting::{ContactCycleAccumulator, ContactRecord, ContactSample, SlipCycle};
use crate::strand::history::monitors::{MonitorQuantity, MonitorSeries, MonitorTarget};
use crate::strand::history::{HistoryResult, HistoryStats, LoadSample};

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
    let mut state = JenkinsState::unloaded(law.drive_m(initial.start.0, initial.start.1));
    for &(x, y) in &initial.path {
        state.step(
            law.drive_m(x, y),
            law.normal_force_n(&force_features(x, y)),
            law.compliance_m_per_n(),
            law.stick_ratio(),
            stick_per_m,
            reduced.elastic_slip_m,
        );
    }
    for (&(x, y), f) in loads.iter().zip(features) {
        let normal = law.normal_force_n(f);
        let (slip, tangential) = state.step(
            law.drive_m(x, y),
            normal,
            law.compliance_m_per_n(),
            law.stick_ratio(),
            stick_per_m,
            reduced.elastic_slip_m,
        );
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

/// Largest number of Newton iterations on the interfaces' mode amplitudes per sample.
const MODE_ITERATIONS: usize = 60;

/// Samples per block of the coupled run's drives and normal forces, computed side by side.
const BLOCK: usize = 128;

/// Tolerance on the mode amplitudes (m): far below the slips that count (1 µm).
const MODE_TOLERANCE_M: f64 = 1e-13;

/// Every contact through the history, coupled by the interfaces' collective modes
/// ([`super::ModeCoupling`]): at every sample, the mode amplitudes `q` solve `q = P(s_p(q))`,
/// the projections of the contacts' irreversible slips after the step taken with the drives
/// `d + Σ a ψ q`, by Newton's method on the piecewise-linear map (a sliding contact passes a
/// change of its drive whole to its irreversible slip).
fn run_coupled(
    reduced: &ReducedStrand,
    coupling: &super::ModeCoupling,
    h: &Scaled,
    slip_gate_m: f64,
    keep_series: &(dyn Fn(usize) -> bool + Sync),
) -> Result<Vec<(ContactRecord, Vec<ContactSample>)>, ReducedError> {
    let nc = reduced.laws.len();
    let ni = coupling.interfaces();
    let nq = ni * MODES;
    let stick_per_m = reduced.friction_coefficient / reduced.elastic_slip_m;
    let gamma = reduced.elastic_slip_m;
    let interface: Vec<usize> = reduced
        .sites
        .iter()
        .map(|s| s.interface.min(ni.max(1) - 1))
        .collect();
    let shapes: Vec<[f64; MODES]> = reduced
        .sites
        .iter()
        .map(|s| mode_shapes(s.theta_rad))
        .collect();
    let mut norm = vec![[0.0; MODES]; ni];
    for (&i, sh) in interface.iter().zip(&shapes) {
        for (n, v) in norm[i].iter_mut().zip(sh) {
            *n += v * v;
        }
    }
    let (x0, y0) = h.initial.start;
    let mut states: Vec<JenkinsState> = reduced
        .laws
        .iter()
        .map(|law| JenkinsState::unloaded(law.drive_m(x0, y0)))
        .collect();
    let project = |states: &[JenkinsState]| {
        let mut p = vec![0.0; nq];
        for ((st, &i), sh) in states.iter().zip(&interface).zip(&shapes) {
            for m in 0..MODES {
                p[i * MODES + m] += sh[m] * st.plastic_slip_m;
            }
        }
        for i in 0..ni {
            for m in 0..MODES {
                p[i * MODES + m] /= norm[i][m].max(f64::MIN_POSITIVE);
            }
        }
        p
    };
    let origin = project(&states);
    let mut q = vec![0.0; nq];
    let mut counters = Vec::with_capacity(nc);
    for c in 0..nc {
        counters.push(Counter {
            accumulator: ContactCycleAccumulator::new(slip_gate_m).map_err(|e| {
                ReducedError::InvalidSetting {
                    field: "slip_gate_m",
                    value: slip_gate_m,
                    reason: e.to_string(),
                }
            })?,
            cycles: Vec::new(),
            series: Vec::with_capacity(if keep_series(c) { h.loads.len() } else { 0 }),
            max_normal: 0.0,
        });
    }
    let mut outputs = vec![
        ContactSample {
            slip_m: 0.0,
            normal_force_n: 0.0,
            tangential_force_n: 0.0,
        };
        nc * BLOCK
    ];
    let mut base: Vec<(f64, f64)> = vec![(0.0, 0.0); nc];
    let mut trial = states.clone();
    let mut out: Vec<(f64, f64)> = vec![(0.0, 0.0); nc];
    let mut amp = Vec::new();
    let steps = h.initial.path.len();
    let points: Vec<(f64, f64)> = h.initial.path.iter().chain(&h.loads).copied().collect();
    // every contact's drive and normal force over a block of samples, computed side by side
    // (contact-major: `block[c · BLOCK + k]`)
    let mut block: Vec<(f64, f64)> = vec![(0.0, 0.0); nc * BLOCK];
    for (n, &(x, y)) in points.iter().enumerate() {
        let k = n % BLOCK;
        if k == 0 {
            let end = (n + BLOCK).min(points.len());
            let span = &points[n..end];
            block
                .par_chunks_mut(BLOCK)
                .enumerate()
                .for_each(|(c, column)| {
                    let law = &reduced.laws[c];
                    for (b, &(x, y)) in column.iter_mut().zip(span) {
                        *b = (law.drive_m(x, y), law.normal_force_n(&force_features(x, y)));
                    }
                });
        }
        for (c, b) in base.iter_mut().enumerate() {
            *b = block[c * BLOCK + k];
        }
        coupling.at(x, &mut amp);
        let mut converged = false;
        for iteration in 0..MODE_ITERATIONS {
            // the collective drive per interface and mode
            let w: Vec<f64> = (0..nq)
                .map(|im| {
                    let (i, m) = (im / MODES, im % MODES);
                    (0..ni)
                        .map(|j| amp[(i * ni + j) * MODES + m] * q[j * MODES + m])
                        .sum()
                })
                .collect();
            let mut p = vec![0.0; nq];
            // Σ ψ_m ψ_l over each interface's sliding contacts
            let mut slide = vec![[[0.0; MODES]; MODES]; ni];
            for c in 0..nc {
                let law = &reduced.laws[c];
                let (i, sh) = (interface[c], &shapes[c]);
                let collective: f64 = (0..MODES).map(|m| sh[m] * w[i * MODES + m]).sum();
                let mut st = states[c];
                out[c] = st.step(
                    base[c].0 + collective,
                    base[c].1,
                    law.compliance_m_per_n(),
                    law.stick_ratio(),
                    stick_per_m,
                    gamma,
                );
                let sliding = st.plastic_slip_m != states[c].plastic_slip_m;
                trial[c] = st;
                for m in 0..MODES {
                    p[i * MODES + m] += sh[m] * st.plastic_slip_m;
                    if sliding {
                        for l in 0..MODES {
                            slide[i][m][l] += sh[m] * sh[l];
                        }
                    }
                }
            }
            let mut r = nalgebra::DVector::<f64>::zeros(nq);
            for im in 0..nq {
                let (i, m) = (im / MODES, im % MODES);
                r[im] = p[im] / norm[i][m].max(f64::MIN_POSITIVE) - origin[im] - q[im];
            }
            if r.iter().all(|v| v.abs() <= MODE_TOLERANCE_M) {
                converged = true;
                break;
            }
            // (1 − ∂P/∂q) Δq = r, ∂P_{I,m}/∂q_{J,l} = Σ_sliding ψ_m ψ_l a[I][J][l] / norm_{I,m}
            let mut a = nalgebra::DMatrix::<f64>::identity(nq, nq);
            for i in 0..ni {
                for m in 0..MODES {
                    let nm = norm[i][m].max(f64::MIN_POSITIVE);
                    for j in 0..ni {
                        for l in 0..MODES {
                            a[(i * MODES + m, j * MODES + l)] -=
                                slide[i][m][l] * amp[(i * ni + j) * MODES + l] / nm;
                        }
                    }
                }
            }
            let dq = a.lu().solve(&r).unwrap_or(r);
            // a full step can cycle between two sets of sliding contacts: halve it late on
            let step = if iteration < MODE_ITERATIONS / 2 {
                1.0
            } else {
                0.5
            };
            for (v, d) in q.iter_mut().zip(dq.iter()) {
                *v += step * d;
            }
        }
        if !converged {
            return Err(ReducedError::Calibration {
                reason: format!(
                    "the interfaces' collective modes did not converge in {MODE_ITERATIONS} \
                     iterations at sample {} (scaled loads {x:.4}, {y:.4})",
                    n.saturating_sub(steps)
                ),
            });
        }
        std::mem::swap(&mut states, &mut trial);
        // the block's samples go to the contacts' counters side by side at its end
        for (c, o) in out.iter().enumerate() {
            outputs[c * BLOCK + k] = ContactSample {
                slip_m: o.0,
                normal_force_n: base[c].1,
                tangential_force_n: o.1,
            };
        }
        if k + 1 == BLOCK || n + 1 == points.len() {
            let from = steps.saturating_sub(n - k).min(k + 1);
            outputs
                .par_chunks(BLOCK)
                .zip(counters.par_iter_mut())
                .enumerate()
                .try_for_each(|(c, (column, counter))| {
                    for &sample in &column[from..=k] {
                        counter
                            .accumulator
                            .push(sample, &mut counter.cycles)
                            .map_err(|e| ReducedError::Calibration {
                                reason: format!("contact {c}: {e}"),
                            })?;
                        counter.max_normal = counter.max_normal.max(sample.normal_force_n);
                        if keep_series(c) {
                            counter.series.push(sample);
                        }
                    }
                    Ok::<(), ReducedError>(())
                })?;
        }
    }
    let mut results = Vec::with_capacity(nc);
    for (c, mut counter) in counters.into_iter().enumerate() {
        counter.accumulator.finish(&mut counter.cycles);
        let site = &reduced.sites[c];
        results.push((
            ContactRecord {
                interface: site.interface,
                theta_rad: site.theta_rad,
                z_m: site.z_m,
                max_normal_force_n: counter.max_normal,
                cycles: counter.cycles,
            },
            counter.series,
        ));
    }
    Ok(results)
}

/// One contact's slip-cycle counter and outputs in the coupled run.
struct Counter {
    accumulator: ContactCycleAccumulator,
    cycles: Vec<SlipCycle>,
    series: Vec<ContactSample>,
    max_normal: f64,
}

/// Every contact through the history: alone, or coupled by the interfaces' collective
/// modes if the calibration has them.
fn run_contacts(
    reduced: &ReducedStrand,
    h: &Scaled,
    slip_gate_m: f64,
    keep_series: &(dyn Fn(usize) -> bool + Sync),
) -> Result<Vec<(ContactRecord, Vec<ContactSample>)>, ReducedError> {
    match &reduced.modes {
        Some(coupling) if coupling.interfaces() > 0 => {
            run_coupled(reduced, coupling, h, slip_gate_m, keep_series)
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

fn scaled(reduced: &ReducedStrand, samples: &[LoadSample]) -> Result<Scaled, ReducedError> {
    let Some(first) = samples.first() else {
        return Err(ReducedError::InvalidSetting {
            field: "samples",
            value: 0.0,
            reason: "the load history is empty".into(),
        });
    };
    check_samples(reduced, samples)?;
    let loads: Vec<(f64, f64)> = samples
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

/// Every contact's (slip, normal force, tangential force) at every sample of `samples`, in
/// mesh contact order: the series behind [`run_reduced`]'s records, for studies that compare
/// them sample by sample with an FE run.
pub fn contact_series(
    reduced: &ReducedStrand,
    samples: &[LoadSample],
) -> Result<Vec<Vec<ContactSample>>, ReducedError> {
    let h = scaled(reduced, samples)?;
    Ok(run_contacts(reduced, &h, 0.0, &|_| true)?
        .into_iter()
        .map(|r| r.1)
        .collect())
}

/// Runs `samples` through `reduced` (module docs): the outputs of an FE history run, with
/// every sample "kept" and the work counts of a run without sub-steps. `slip_gate_m` is the
/// hysteresis gate of the slip rainflow counters, as [`crate::strand::history::HistoryOptions`].
pub fn run_reduced(
    reduced: &ReducedStrand,
    samples: &[LoadSample],
    slip_gate_m: f64,
) -> Result<HistoryResult, ReducedError> {
    let start = Instant::now();
    let h = scaled(reduced, samples)?;
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
    let results = run_contacts(reduced, &h, slip_gate_m, &|c| monitored[c])?;
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
