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

use super::{
    force_features, mode_shapes, JenkinsState, ReducedError, ReducedStrand, FORCE_FEATURES, MODES,
};
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

/// Contacts per tile of a block (`Tiles`).
const TILE: usize = 256;

/// Tolerance on the mode amplitudes (m): far below the slips that count (1 µm).
const MODE_TOLERANCE_M: f64 = 1e-13;

/// Relative margin on a stuck contact's distance to sliding within which a Newton iteration
/// steps it again (rounding of the drives is some 1e-16 of them).
const STICK_MARGIN: f64 = 1e-6;

/// One contact at one sample of the coupled run: its drive, normal force and
/// [`slide_factor`](super::slide_factor).
#[derive(Clone, Copy, Default)]
struct Row {
    drive_m: f64,
    normal_force_n: f64,
    factor: f64,
}

/// Every contact's [`Row`] over a block of samples, in tiles of [`TILE`] contacts, each tile
/// sample by sample: a tile is computed (and its contacts' counters fed) on one thread, and
/// the sequential solve reads a sample's contacts tile after tile, each run contiguous.
struct Tiles {
    rows: Vec<Row>,
}

impl Tiles {
    fn new(contacts: usize) -> Self {
        Self {
            rows: vec![Row::default(); contacts.div_ceil(TILE) * TILE * BLOCK],
        }
    }

    /// Contact `c` at sample `k` of the block.
    #[inline]
    fn at(&self, c: usize, k: usize) -> Row {
        self.rows[(c / TILE) * TILE * BLOCK + k * TILE + c % TILE]
    }

    /// The tiles, each with the index of its first contact.
    fn tiles_mut(&mut self) -> impl IndexedParallelIterator<Item = (usize, &mut [Row])> {
        self.rows
            .par_chunks_mut(TILE * BLOCK)
            .enumerate()
            .map(|(t, tile)| (t * TILE, tile))
    }

    fn tiles(&self) -> impl IndexedParallelIterator<Item = &[Row]> {
        self.rows.par_chunks(TILE * BLOCK)
    }
}

/// The contacts' geometry in the interfaces' modes: each one's interface and mode shapes, and
/// the norms of each interface's mode shapes.
struct ModeGeometry {
    interface: Vec<usize>,
    shapes: Vec<[f64; MODES]>,
    norm: Vec<[f64; MODES]>,
}

impl ModeGeometry {
    fn new(reduced: &ReducedStrand, interfaces: usize) -> Self {
        let interface: Vec<usize> = reduced
            .sites
            .iter()
            .map(|s| s.interface.min(interfaces.max(1) - 1))
            .collect();
        let shapes: Vec<[f64; MODES]> = reduced
            .sites
            .iter()
            .map(|s| mode_shapes(s.theta_rad))
            .collect();
        let mut norm = vec![[0.0; MODES]; interfaces];
        for (&i, sh) in interface.iter().zip(&shapes) {
            for (n, v) in norm[i].iter_mut().zip(sh) {
                *n += v * v;
            }
        }
        Self {
            interface,
            shapes,
            norm,
        }
    }

    /// The collective drive of contact `c` under the interfaces' collective drives `w`.
    #[inline]
    fn collective(&self, c: usize, w: &[f64]) -> f64 {
        let (i, sh) = (self.interface[c], &self.shapes[c]);
        (0..MODES).map(|m| sh[m] * w[i * MODES + m]).sum()
    }

    /// The projections of the irreversible slips `plastic` on each interface's mode shapes.
    fn project(&self, plastic: &[f64]) -> Vec<f64> {
        let mut p = vec![0.0; self.norm.len() * MODES];
        for (c, &s) in plastic.iter().enumerate() {
            self.add(&mut p, c, s);
        }
        self.normalise(&mut p);
        p
    }

    /// Adds contact `c`'s irreversible slip (or its change) `s` to the projection sums `p`.
    #[inline]
    fn add(&self, p: &mut [f64], c: usize, s: f64) {
        let (i, sh) = (self.interface[c], &self.shapes[c]);
        for m in 0..MODES {
            p[i * MODES + m] += sh[m] * s;
        }
    }

    fn normalise(&self, p: &mut [f64]) {
        for (i, n) in self.norm.iter().enumerate() {
            for m in 0..MODES {
                p[i * MODES + m] /= n[m].max(f64::MIN_POSITIVE);
            }
        }
    }
}

/// The collective drives `w[I, m] = Σ_J a[I][J][m] q[J, m]` of the mode amplitudes `q`.
fn collective_drives(amp: &[f64], q: &[f64], ni: usize, w: &mut [f64]) {
    for (im, v) in w.iter_mut().enumerate() {
        let (i, m) = (im / MODES, im % MODES);
        *v = (0..ni)
            .map(|j| amp[(i * ni + j) * MODES + m] * q[j * MODES + m])
            .sum();
    }
}

/// Every contact through the history, coupled by the interfaces' collective modes
/// ([`super::ModeCoupling`]): at every sample, the mode amplitudes `q` solve `q = P(s_p(q))`,
/// the projections of the contacts' irreversible slips after the step taken with the drives
/// `d + Σ a ψ q`, by Newton's method on the piecewise-linear map (a sliding contact passes a
/// change of its drive whole to its irreversible slip).
///
/// The first iteration of a sample steps every contact; the later ones step only the contacts
/// that slid or opened in the first and the stuck ones whose distance to sliding the change of
/// their collective drive since may reach (`|ψ_m| ≤ 1`: the change is at most the sum of the
/// changes of their interface's collective drives); the others stay stuck. `step_all` steps
/// every contact in every iteration instead, to the same results to the bit (a test's
/// reference). The samples' outputs and the slip counters follow in blocks, contacts side by
/// side, with the converged collective drives.
fn run_coupled(
    reduced: &ReducedStrand,
    coupling: &super::ModeCoupling,
    h: &Scaled,
    slip_gate_m: f64,
    keep_series: &(dyn Fn(usize) -> bool + Sync),
    step_all: bool,
) -> Result<Vec<(ContactRecord, Vec<ContactSample>)>, ReducedError> {
    let nc = reduced.laws.len();
    let ni = coupling.interfaces();
    let nq = ni * MODES;
    let stick_per_m = reduced.friction_coefficient / reduced.elastic_slip_m;
    let gamma = reduced.elastic_slip_m;
    // the stuck contacts nearer sliding than this (m of drive) are listed after a sample's
    // first iteration; a later one that moves an interface's drives further steps them all
    let near_m = 0.1 * gamma;
    let geometry = ModeGeometry::new(reduced, ni);
    let (x0, y0) = h.initial.start;
    let mut plastic: Vec<f64> = reduced
        .laws
        .iter()
        .map(|law| JenkinsState::unloaded(law.drive_m(x0, y0)).plastic_slip_m)
        .collect();
    let origin = geometry.project(&plastic);
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
    let steps = h.initial.path.len();
    let points: Vec<(f64, f64)> = h.initial.path.iter().chain(&h.loads).copied().collect();
    // every contact's drive, normal force and slide factor over a block of samples, computed
    // side by side
    let mut tiles = Tiles::new(nc);
    // the irreversible slips at the block's start and the converged collective drives
    let mut block_start = plastic.clone();
    let mut converged_w = vec![0.0; nq * BLOCK];
    let all: Vec<usize> = (0..nc).collect();
    let mut amp = Vec::new();
    let mut w = vec![0.0; nq];
    let mut w_first = vec![0.0; nq];
    let mut p_first = vec![0.0; nq];
    // the first iteration's irreversible slips; each contact's distance to sliding then (m of
    // drive; −1 if it slid or is open) and the contacts that slid, opened or were near sliding
    let mut first = plastic.clone();
    let mut distance = vec![0.0; nc];
    let mut near: Vec<usize> = Vec::with_capacity(nc);
    // the later iterations' irreversible slips of the contacts they step, in contact order
    let mut trial = plastic.clone();
    let mut stepped: Vec<usize> = Vec::with_capacity(nc);
    for (n, &(x, _)) in points.iter().enumerate() {
        let k = n % BLOCK;
        if k == 0 {
            let end = (n + BLOCK).min(points.len());
            let span = &points[n..end];
            tiles.tiles_mut().for_each(|(first, tile)| {
                for (j, law) in reduced.laws[first..].iter().take(TILE).enumerate() {
                    let (g, r) = (law.compliance_m_per_n(), law.stick_ratio());
                    for (k, &(x, y)) in span.iter().enumerate() {
                        let normal_force_n = law.normal_force_n(&force_features(x, y));
                        let (_, factor) = super::slide_factor(normal_force_n, g, r, stick_per_m);
                        tile[k * TILE + j] = Row {
                            drive_m: law.drive_m(x, y),
                            normal_force_n,
                            factor,
                        };
                    }
                }
            });
            block_start.copy_from_slice(&plastic);
        }
        let tiles_now = &tiles;
        coupling.at(x, &mut amp);
        // contact `c` stepped under the collective drives `w`: its irreversible slip, and its
        // distance to sliding (−1 if it slid or is open); its part of `Σ ψ_m ψ_l` over the
        // sliding contacts added to `slide`
        let step = |c: usize, w: &[f64], slide: &mut [[[f64; MODES]; MODES]]| -> (f64, f64) {
            let r = tiles_now.at(c, k);
            let drive = r.drive_m + geometry.collective(c, w);
            if r.normal_force_n <= 0.0 {
                // open: its irreversible slip follows the drive, as sliding
                if drive != plastic[c] {
                    add_outer(&mut slide[geometry.interface[c]], &geometry.shapes[c]);
                }
                return (drive, -1.0);
            }
            let mut st = JenkinsState {
                plastic_slip_m: plastic[c],
            };
            let elastic = st.advance(drive, r.factor, gamma);
            if st.plastic_slip_m != plastic[c] {
                add_outer(&mut slide[geometry.interface[c]], &geometry.shapes[c]);
                (st.plastic_slip_m, -1.0)
            } else if elastic.abs() >= gamma {
                (st.plastic_slip_m, -1.0)
            } else {
                (st.plastic_slip_m, (gamma - elastic.abs()) * r.factor)
            }
        };
        let mut converged = false;
        let mut last = 0;
        for iteration in 0..MODE_ITERATIONS {
            collective_drives(&amp, &q, ni, &mut w);
            let mut slide = vec![[[0.0; MODES]; MODES]; ni];
            let p = if iteration == 0 {
                near.clear();
                p_first.iter_mut().for_each(|v| *v = 0.0);
                for c in 0..nc {
                    let (s, d) = step(c, &w, &mut slide);
                    first[c] = s;
                    distance[c] = d;
                    if d < near_m + STICK_MARGIN * gamma * tiles_now.at(c, k).factor {
                        near.push(c);
                    }
                    geometry.add(&mut p_first, c, s);
                }
                geometry.normalise(&mut p_first);
                w_first.copy_from_slice(&w);
                p_first.clone()
            } else {
                // how far each interface's collective drive moved since the first iteration
                let reach: Vec<f64> = (0..ni)
                    .map(|i| {
                        (0..MODES)
                            .map(|m| (w[i * MODES + m] - w_first[i * MODES + m]).abs())
                            .sum()
                    })
                    .collect();
                let candidates = if step_all || reach.iter().any(|&r| r >= near_m) {
                    &all
                } else {
                    &near
                };
                stepped.clear();
                let mut change = vec![0.0; nq];
                for &c in candidates {
                    let (i, d) = (geometry.interface[c], distance[c]);
                    if step_all
                        || d < 0.0
                        || d <= reach[i] + STICK_MARGIN * gamma * tiles_now.at(c, k).factor
                    {
                        let (s, _) = step(c, &w, &mut slide);
                        trial[c] = s;
                        stepped.push(c);
                        geometry.add(&mut change, c, s - first[c]);
                    }
                }
                geometry.normalise(&mut change);
                p_first.iter().zip(&change).map(|(a, b)| a + b).collect()
            };
            last = iteration;
            let mut r = nalgebra::DVector::<f64>::zeros(nq);
            for im in 0..nq {
                r[im] = p[im] - origin[im] - q[im];
            }
            if r.iter().all(|v| v.abs() <= MODE_TOLERANCE_M) {
                converged = true;
                break;
            }
            // (1 − ∂P/∂q) Δq = r, ∂P_{I,m}/∂q_{J,l} = Σ_sliding ψ_m ψ_l a[I][J][l] / norm_{I,m}
            let mut a = nalgebra::DMatrix::<f64>::identity(nq, nq);
            for i in 0..ni {
                for m in 0..MODES {
                    let nm = geometry.norm[i][m].max(f64::MIN_POSITIVE);
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
                     iterations at sample {} (scaled loads {x:.4}, {:.4})",
                    n.saturating_sub(steps),
                    points[n].1
                ),
            });
        }
        if last == 0 {
            plastic.copy_from_slice(&first);
        } else {
            // the contacts the last iteration did not step stayed stuck
            for &c in &stepped {
                plastic[c] = trial[c];
            }
        }
        converged_w[k * nq..(k + 1) * nq].copy_from_slice(&w);
        // the block's samples go to the contacts' counters side by side at its end, stepped
        // again from the block's start with the converged collective drives
        if k + 1 == BLOCK || n + 1 == points.len() {
            let from = steps.saturating_sub(n - k).min(k + 1);
            let (tiles, converged_w, plastic) = (&tiles, &converged_w, &plastic);
            counters
                .par_chunks_mut(TILE)
                .zip(block_start.par_chunks(TILE))
                .zip(tiles.tiles())
                .enumerate()
                .try_for_each(|(t, ((counters, starts), tile))| {
                    for (j, (counter, &start)) in counters.iter_mut().zip(starts).enumerate() {
                        let c = t * TILE + j;
                        let mut st = JenkinsState {
                            plastic_slip_m: start,
                        };
                        for (kk, w) in converged_w.chunks_exact(nq).take(k + 1).enumerate() {
                            let r = tile[kk * TILE + j];
                            let (slip, tangential) = st.step_factored(
                                r.drive_m + geometry.collective(c, w),
                                r.normal_force_n,
                                stick_per_m * r.normal_force_n,
                                r.factor,
                                gamma,
                            );
                            if kk < from {
                                continue;
                            }
                            let sample = ContactSample {
                                slip_m: slip,
                                normal_force_n: r.normal_force_n,
                                tangential_force_n: tangential,
                            };
                            counter
                                .accumulator
                                .push(sample, &mut counter.cycles)
                                .map_err(|e| ReducedError::Calibration {
                                    reason: format!("contact {c}: {e}"),
                                })?;
                            counter.max_normal = counter.max_normal.max(r.normal_force_n);
                            if keep_series(c) {
                                counter.series.push(sample);
                            }
                        }
                        debug_assert_eq!(st.plastic_slip_m, plastic[c], "contact {c}");
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

/// Adds `ψ ψᵀ` to `sum`.
#[inline]
fn add_outer(sum: &mut [[f64; MODES]; MODES], sh: &[f64; MODES]) {
    for m in 0..MODES {
        for l in 0..MODES {
            sum[m][l] += sh[m] * sh[l];
        }
    }
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
    step_all: bool,
) -> Result<Vec<(ContactRecord, Vec<ContactSample>)>, ReducedError> {
    match &reduced.modes {
        Some(coupling) if coupling.interfaces() > 0 => {
            run_coupled(reduced, coupling, h, slip_gate_m, keep_series, step_all)
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
