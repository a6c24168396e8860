//! The contacts coupled by their interfaces' collective modes ([`super::super::ModeCoupling`]),
//! sample by sample, in named phases over one state:
//!
//! 1. [`State::load_block`]: every contact's drive, normal force and slide factor over the next
//!    block of samples, in tiles of contacts, side by side;
//! 2. [`State::solve_sample`]: Newton's method on the modes' amplitudes `q = P(s_p(q))`, the
//!    first iteration stepping every contact ([`Newton::first_pass`]), the later ones only those
//!    that may change state ([`Newton::later_pass`]), each followed by [`newton_update`];
//! 3. [`Newton::commit`]: the sample's irreversible slips;
//! 4. [`State::flush_block`]: at the block's end, the block's samples stepped again with the
//!    converged collective drives into each contact's rainflow counter.

use rayon::prelude::*;

use super::super::iwan::{stick_fraction, structure_compliance, IwanContact};
use super::super::{force_features, ReducedStrand, MODES};
use super::super::{mode_shapes, slide_factor, JenkinsState, ModeCoupling, ReducedError};
use super::Scaled;
use crate::fretting::{ContactCycleAccumulator, ContactRecord, ContactSample, SlipCycle};

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
/// [`slide_factor`]; for an Iwan bank, its structure compliance `g + r / k` in `factor` (k its
/// stiffness in stick) and
/// its initial stiffness `k₀`.
#[derive(Clone, Copy, Default)]
struct Row {
    drive_m: f64,
    normal_force_n: f64,
    factor: f64,
    k0: f64,
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

/// Adds `ψ ψᵀ` to `sum`.
#[inline]
fn add_outer(sum: &mut [[f64; MODES]; MODES], sh: &[f64; MODES]) {
    add_outer_scaled(sum, sh, 1.0);
}

/// Adds `ρ ψ ψᵀ` to `sum`: a contact that passes the share `ρ` of a change of its drive to
/// its irreversible slip.
#[inline]
fn add_outer_scaled(sum: &mut [[f64; MODES]; MODES], sh: &[f64; MODES], rate: f64) {
    for m in 0..MODES {
        for l in 0..MODES {
            sum[m][l] += rate * sh[m] * sh[l];
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

/// What stays fixed through a run.
struct Setup<'a> {
    reduced: &'a ReducedStrand,
    geometry: ModeGeometry,
    /// Interfaces, mode amplitudes (interfaces × modes), contacts.
    ni: usize,
    nq: usize,
    nc: usize,
    /// The contacts' elastic slip (m) and stick stiffness per newton of normal force (1/m).
    gamma: f64,
    stick_per_m: f64,
    /// The contacts are Iwan banks (the Cattaneo–Mindlin law) with friction coefficient `mu`.
    iwan: bool,
    mu: f64,
    /// The stuck contacts nearer sliding than this (m of drive) are listed after a sample's
    /// first iteration; a later one that moves an interface's drives further steps them all.
    near_m: f64,
    /// The projections of the irreversible slips where the contacts are unloaded.
    origin: Vec<f64>,
    /// Every contact, in order.
    all: Vec<usize>,
    /// Step every contact in every iteration (the reference of the shortcut).
    step_all: bool,
}

impl Setup<'_> {
    /// Contact `c` at sample `k` of the block stepped from `plastic[c]` under the collective
    /// drives `w`: its irreversible slip, and its distance to sliding (−1 if it slid or is
    /// open); its part of `Σ ψ_m ψ_l` over the sliding contacts added to `slide`.
    #[inline]
    fn step(
        &self,
        tiles: &Tiles,
        (plastic, banks): (&[f64], &[IwanContact]),
        (c, k): (usize, usize),
        w: &[f64],
        slide: &mut [[[f64; MODES]; MODES]],
    ) -> (f64, f64) {
        let (geometry, gamma) = (&self.geometry, self.gamma);
        let r = tiles.at(c, k);
        let drive = r.drive_m + geometry.collective(c, w);
        if self.iwan {
            // a trial step of the bank: its state is committed once the sample has converged
            let mut bank = banks[c];
            let st = bank.step_with(drive, r.normal_force_n, r.k0, r.factor, self.mu);
            if st.yielded {
                let sum = &mut slide[geometry.interface[c]];
                add_outer_scaled(sum, &geometry.shapes[c], st.plastic_rate);
                return (st.plastic_m, -1.0);
            }
            return (st.plastic_m, st.distance_m);
        }
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
    }

    /// The margin within which a stuck contact `c` at sample `k` is stepped again.
    #[inline]
    fn margin(&self, tiles: &Tiles, c: usize, k: usize) -> f64 {
        let r = tiles.at(c, k);
        if self.iwan {
            // δ_s in drive units
            if r.k0 > 0.0 {
                let stick = stick_fraction() * r.k0;
                STICK_MARGIN * 1.5 * self.mu * r.normal_force_n / r.k0 * (1.0 + r.factor * stick)
            } else {
                0.0
            }
        } else {
            STICK_MARGIN * self.gamma * r.factor
        }
    }
}

/// The state carried from sample to sample.
struct State {
    /// Every contact's irreversible slip after the last solved sample.
    plastic: Vec<f64>,
    /// Every contact's Iwan bank after the last solved sample (none for Jenkins elements), and
    /// at the block's start.
    banks: Vec<IwanContact>,
    block_banks: Vec<IwanContact>,
    /// The interfaces' mode amplitudes.
    q: Vec<f64>,
    /// The modes' coupling amplitudes at the current sample's tension.
    amp: Vec<f64>,
    tiles: Tiles,
    /// The irreversible slips at the block's start and the converged collective drives.
    block_start: Vec<f64>,
    converged_w: Vec<f64>,
}

/// One sample's Newton iterations: their scratch.
struct Newton {
    /// The collective drives of the current iteration and of the first.
    w: Vec<f64>,
    w_first: Vec<f64>,
    /// The first iteration's projections of the irreversible slips.
    p_first: Vec<f64>,
    /// The first iteration's irreversible slips; each contact's distance to sliding then (m of
    /// drive; −1 if it slid or is open) and the contacts that slid, opened or were near sliding.
    first: Vec<f64>,
    distance: Vec<f64>,
    near: Vec<usize>,
    /// The later iterations' irreversible slips of the contacts they step, in contact order.
    trial: Vec<f64>,
    stepped: Vec<usize>,
}

impl Newton {
    fn new(setup: &Setup, plastic: &[f64]) -> Self {
        Self {
            w: vec![0.0; setup.nq],
            w_first: vec![0.0; setup.nq],
            p_first: vec![0.0; setup.nq],
            first: plastic.to_vec(),
            distance: vec![0.0; setup.nc],
            near: Vec::with_capacity(setup.nc),
            trial: plastic.to_vec(),
            stepped: Vec::with_capacity(setup.nc),
        }
    }

    /// The first iteration: every contact stepped; the projections of their irreversible
    /// slips.
    fn first_pass(
        &mut self,
        setup: &Setup,
        state: &State,
        k: usize,
        slide: &mut [[[f64; MODES]; MODES]],
    ) -> Vec<f64> {
        self.near.clear();
        self.p_first.iter_mut().for_each(|v| *v = 0.0);
        for c in 0..setup.nc {
            let committed = (state.plastic.as_slice(), state.banks.as_slice());
            let (s, d) = setup.step(&state.tiles, committed, (c, k), &self.w, slide);
            self.first[c] = s;
            self.distance[c] = d;
            if d < setup.near_m + setup.margin(&state.tiles, c, k) {
                self.near.push(c);
            }
            setup.geometry.add(&mut self.p_first, c, s);
        }
        setup.geometry.normalise(&mut self.p_first);
        self.w_first.copy_from_slice(&self.w);
        self.p_first.clone()
    }

    /// A later iteration: only the contacts whose state the change of their interface's
    /// collective drives since the first iteration may change (`|ψ_m| ≤ 1`) are stepped; the
    /// projections of the irreversible slips.
    fn later_pass(
        &mut self,
        setup: &Setup,
        state: &State,
        k: usize,
        slide: &mut [[[f64; MODES]; MODES]],
    ) -> Vec<f64> {
        // how far each interface's collective drive moved since the first iteration
        let reach: Vec<f64> = (0..setup.ni)
            .map(|i| {
                (0..MODES)
                    .map(|m| (self.w[i * MODES + m] - self.w_first[i * MODES + m]).abs())
                    .sum()
            })
            .collect();
        let candidates = if setup.step_all || reach.iter().any(|&r| r >= setup.near_m) {
            &setup.all
        } else {
            &self.near
        };
        self.stepped.clear();
        let mut change = vec![0.0; setup.nq];
        for &c in candidates {
            let (i, d) = (setup.geometry.interface[c], self.distance[c]);
            if setup.step_all || d < 0.0 || d <= reach[i] + setup.margin(&state.tiles, c, k) {
                let committed = (state.plastic.as_slice(), state.banks.as_slice());
                let (s, _) = setup.step(&state.tiles, committed, (c, k), &self.w, slide);
                self.trial[c] = s;
                self.stepped.push(c);
                setup.geometry.add(&mut change, c, s - self.first[c]);
            }
        }
        setup.geometry.normalise(&mut change);
        self.p_first
            .iter()
            .zip(&change)
            .map(|(a, b)| a + b)
            .collect()
    }

    /// The sample's irreversible slips after its last iteration `last`.
    fn commit(&self, last: usize, plastic: &mut [f64]) {
        if last == 0 {
            plastic.copy_from_slice(&self.first);
        } else {
            // the contacts the last iteration did not step stayed stuck
            for &c in &self.stepped {
                plastic[c] = self.trial[c];
            }
        }
    }
}

/// One Newton step on the mode amplitudes `q` from the residual `r`:
/// `(1 − ∂P/∂q) Δq = r`, `∂P_{I,m}/∂q_{J,l} = Σ_sliding ψ_m ψ_l a[I][J][l] / norm_{I,m}`.
fn newton_update(
    setup: &Setup,
    slide: &[[[f64; MODES]; MODES]],
    amp: &[f64],
    r: nalgebra::DVector<f64>,
    iteration: usize,
    q: &mut [f64],
) {
    let (ni, nq) = (setup.ni, setup.nq);
    let mut a = nalgebra::DMatrix::<f64>::identity(nq, nq);
    for i in 0..ni {
        for m in 0..MODES {
            let nm = setup.geometry.norm[i][m].max(f64::MIN_POSITIVE);
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

impl State {
    /// Every contact's row over the block of samples `span` (scaled loads), and the
    /// irreversible slips at its start.
    fn load_block(&mut self, setup: &Setup, span: &[(f64, f64)]) {
        let reduced = setup.reduced;
        let stick_per_m = setup.stick_per_m;
        let initial = reduced.cattaneo_mindlin.as_deref();
        self.tiles.tiles_mut().for_each(|(first, tile)| {
            for (j, law) in reduced.laws[first..].iter().take(TILE).enumerate() {
                let (g, r) = (law.compliance_m_per_n(), law.stick_ratio());
                let stiffness = initial.and_then(|k| k.get(first + j));
                for (k, &(x, y)) in span.iter().enumerate() {
                    let normal_force_n = law.normal_force_n(&force_features(x, y));
                    let (factor, k0) = match stiffness {
                        Some(s) => {
                            let k0 = s.at(normal_force_n);
                            (structure_compliance(g, r, k0), k0)
                        }
                        None => (slide_factor(normal_force_n, g, r, stick_per_m).1, 0.0),
                    };
                    tile[k * TILE + j] = Row {
                        drive_m: law.drive_m(x, y),
                        normal_force_n,
                        factor,
                        k0,
                    };
                }
            }
        });
        self.block_start.copy_from_slice(&self.plastic);
        self.block_banks.copy_from_slice(&self.banks);
    }

    /// Every Iwan bank stepped to sample `k` of the block under the converged collective
    /// drives `w`: the sample's committed states and irreversible slips (the Newton passes
    /// step trial copies, and skip the contacts certain to stay stuck, whose stretches still
    /// move with their slip).
    fn commit_banks(&mut self, setup: &Setup, k: usize, w: &[f64]) {
        let (tiles, geometry, mu) = (&self.tiles, &setup.geometry, setup.mu);
        self.banks
            .par_iter_mut()
            .zip(self.plastic.par_iter_mut())
            .enumerate()
            .for_each(|(c, (bank, plastic))| {
                let r = tiles.at(c, k);
                let drive = r.drive_m + geometry.collective(c, w);
                *plastic = bank
                    .step_with(drive, r.normal_force_n, r.k0, r.factor, mu)
                    .plastic_m;
            });
    }

    /// Solves sample `k` of the block for the mode amplitudes: the last iteration, or `None`
    /// if Newton's method did not converge.
    fn solve_sample(&mut self, setup: &Setup, newton: &mut Newton, k: usize) -> Option<usize> {
        for iteration in 0..MODE_ITERATIONS {
            collective_drives(&self.amp, &self.q, setup.ni, &mut newton.w);
            let mut slide = vec![[[0.0; MODES]; MODES]; setup.ni];
            let p = if iteration == 0 {
                newton.first_pass(setup, self, k, &mut slide)
            } else {
                newton.later_pass(setup, self, k, &mut slide)
            };
            let mut r = nalgebra::DVector::<f64>::zeros(setup.nq);
            for im in 0..setup.nq {
                r[im] = p[im] - setup.origin[im] - self.q[im];
            }
            if r.iter().all(|v| v.abs() <= MODE_TOLERANCE_M) {
                return Some(iteration);
            }
            newton_update(setup, &slide, &self.amp, r, iteration, &mut self.q);
        }
        None
    }

    /// The block's samples, up to sample `k` of the block, stepped again from the block's
    /// start with the converged collective drives into the contacts' counters, side by side;
    /// the first `from` of them are the initialisation's and only move the contacts.
    fn flush_block(
        &self,
        setup: &Setup,
        counters: &mut [Counter],
        k: usize,
        from: usize,
        keep_series: &(dyn Fn(usize) -> bool + Sync),
    ) -> Result<(), ReducedError> {
        let (geometry, nq) = (&setup.geometry, setup.nq);
        let (gamma, stick_per_m, mu) = (setup.gamma, setup.stick_per_m, setup.mu);
        let (converged_w, plastic) = (&self.converged_w, &self.plastic);
        let (banks, block_banks) = (&self.banks, &self.block_banks);
        counters
            .par_chunks_mut(TILE)
            .zip(self.block_start.par_chunks(TILE))
            .zip(self.tiles.tiles())
            .enumerate()
            .try_for_each(|(t, ((counters, starts), tile))| {
                for (j, (counter, &start)) in counters.iter_mut().zip(starts).enumerate() {
                    let c = t * TILE + j;
                    let mut st = JenkinsState {
                        plastic_slip_m: start,
                    };
                    let mut bank = block_banks.get(c).copied();
                    for (kk, w) in converged_w.chunks_exact(nq).take(k + 1).enumerate() {
                        let r = tile[kk * TILE + j];
                        let drive = r.drive_m + geometry.collective(c, w);
                        let (slip, tangential) = match bank.as_mut() {
                            Some(b) => {
                                let s = b.step_with(drive, r.normal_force_n, r.k0, r.factor, mu);
                                (s.slip_m, s.force_n)
                            }
                            None => st.step_factored(
                                drive,
                                r.normal_force_n,
                                stick_per_m * r.normal_force_n,
                                r.factor,
                                gamma,
                            ),
                        };
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
                    match bank {
                        Some(b) => debug_assert_eq!(Some(&b), banks.get(c), "contact {c}"),
                        None => debug_assert_eq!(st.plastic_slip_m, plastic[c], "contact {c}"),
                    }
                }
                Ok::<(), ReducedError>(())
            })
    }
}

/// Every contact through the history, coupled by the interfaces' collective modes
/// ([`ModeCoupling`]): at every sample, the mode amplitudes `q` solve `q = P(s_p(q))`, the
/// projections of the contacts' irreversible slips after the step taken with the drives
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
pub(super) fn run_coupled(
    reduced: &ReducedStrand,
    coupling: &ModeCoupling,
    h: &Scaled,
    slip_gate_m: f64,
    keep_series: &(dyn Fn(usize) -> bool + Sync),
    step_all: bool,
) -> Result<Vec<(ContactRecord, Vec<ContactSample>)>, ReducedError> {
    let nc = reduced.laws.len();
    let ni = coupling.interfaces();
    let gamma = reduced.elastic_slip_m;
    let geometry = ModeGeometry::new(reduced, ni);
    let (x0, y0) = h.initial.start;
    let plastic: Vec<f64> = reduced
        .laws
        .iter()
        .map(|law| JenkinsState::unloaded(law.drive_m(x0, y0)).plastic_slip_m)
        .collect();
    let iwan = reduced.cattaneo_mindlin.is_some();
    let banks: Vec<IwanContact> = if iwan {
        plastic.iter().map(|&s| IwanContact::unloaded(s)).collect()
    } else {
        Vec::new()
    };
    let setup = Setup {
        reduced,
        ni,
        nq: ni * MODES,
        nc,
        gamma,
        stick_per_m: reduced.friction_coefficient / gamma,
        iwan,
        mu: reduced.friction_coefficient,
        // Iwan banks: a tenth of a micrometre of drive (their slip onsets are 0.2-6 µm)
        near_m: if iwan { 1e-7 } else { 0.1 * gamma },
        origin: geometry.project(&plastic),
        geometry,
        all: (0..nc).collect(),
        step_all,
    };
    let mut counters = counters(h, nc, slip_gate_m, keep_series)?;
    let mut newton = Newton::new(&setup, &plastic);
    let mut state = State {
        q: vec![0.0; setup.nq],
        amp: Vec::new(),
        tiles: Tiles::new(nc),
        block_start: plastic.clone(),
        converged_w: vec![0.0; setup.nq * BLOCK],
        plastic,
        block_banks: banks.clone(),
        banks,
    };
    let steps = h.initial.path.len();
    let points: Vec<(f64, f64)> = h.initial.path.iter().chain(&h.loads).copied().collect();
    for (n, &(x, _)) in points.iter().enumerate() {
        let k = n % BLOCK;
        if k == 0 {
            state.load_block(&setup, &points[n..(n + BLOCK).min(points.len())]);
        }
        coupling.at(x, &mut state.amp);
        let Some(last) = state.solve_sample(&setup, &mut newton, k) else {
            return Err(ReducedError::Calibration {
                reason: format!(
                    "the interfaces' collective modes did not converge in {MODE_ITERATIONS} \
                     iterations at sample {} (scaled loads {x:.4}, {:.4})",
                    n.saturating_sub(steps),
                    points[n].1
                ),
            });
        };
        if setup.iwan {
            state.commit_banks(&setup, k, &newton.w);
        } else {
            newton.commit(last, &mut state.plastic);
        }
        state.converged_w[k * setup.nq..(k + 1) * setup.nq].copy_from_slice(&newton.w);
        if k + 1 == BLOCK || n + 1 == points.len() {
            let from = steps.saturating_sub(n - k).min(k + 1);
            state.flush_block(&setup, &mut counters, k, from, keep_series)?;
        }
    }
    Ok(counters
        .into_iter()
        .zip(&reduced.sites)
        .map(|(mut counter, site)| {
            counter.accumulator.finish(&mut counter.cycles);
            (
                ContactRecord {
                    interface: site.interface,
                    theta_rad: site.theta_rad,
                    z_m: site.z_m,
                    max_normal_force_n: counter.max_normal,
                    cycles: counter.cycles,
                },
                counter.series,
            )
        })
        .collect())
}

/// Every contact's empty counter, with room for its series where one is kept.
fn counters(
    h: &Scaled,
    nc: usize,
    slip_gate_m: f64,
    keep_series: &(dyn Fn(usize) -> bool + Sync),
) -> Result<Vec<Counter>, ReducedError> {
    (0..nc)
        .map(|c| {
            Ok(Counter {
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
            })
        })
        .collect()
}
