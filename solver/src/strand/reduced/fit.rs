//! Streaming least squares of the contact laws ([`super`] module docs).
//!
//! The samples of the calibration run are consumed one at a time into sums (normal equations),
//! so no time series of the ~8 000 contacts is kept. The load features are the same for every
//! contact, so their Gram matrices are shared: per contact only the right-hand sides, the
//! cross terms with its own tangential force and the sums of squares are kept.
//!
//! Fits, per contact, with `φ = [1, x, y, xy, x², y²]` and the drive features `ψ`
//! ([`drive_features`]):
//! - normal force: `f_N ≈ φ·n`, on every sample;
//! - structure: `Δs ≈ Δψ·d − g Δf_T − r Δs_e` on the increment `Δ` from one sample to the next,
//!   for the drive `d` (up to its level, which the Jenkins element never sees), the compliance
//!   `g` and the stick ratio `r`, with the FE's elastic slip `s_e = f_T / k`, `k = μ f_N / γ_e`
//!   (0 where the contact is open), `Δs` net of the interfaces' collective answer
//!   ([`super::ModeCoupling`]) to the FE's irreversible slips `s − s_e`; if that makes `g` or
//!   `r` negative (no physical meaning: the
//!   strand would push the contact along its own friction force), with `r = 0`, and if `g` is
//!   then still negative, with `g = r = 0`.
//!
//! Each system is solved after Jacobi scaling (columns to unit diagonal) with a relative ridge
//! of `RIDGE`, which only matters for a contact whose tangential force is (nearly) a linear
//! function of its slip and the loads — a contact that stuck through the whole calibration,
//! for which every `g` reproduces its stick response (the slip range is then
//! `Δd / (1 + g k + r)` with `Δd` fitted for that `g` and `r`).

use nalgebra::{DMatrix, DVector, SMatrix, SVector};

use super::{force_features, mode_shapes, ContactLaw, ModeCoupling, FORCE_FEATURES, MODES};
use crate::strand::history::monitors::ContactSite;

/// Relative ridge of the scaled normal equations.
pub(crate) const RIDGE: f64 = 1e-10;

type ForceGram = SMatrix<f64, FORCE_FEATURES, FORCE_FEATURES>;
type ForceVec = SVector<f64, FORCE_FEATURES>;

/// Sums of one force channel fitted on the force features.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
struct ForceSums {
    rhs: [f64; FORCE_FEATURES],
    yy: f64,
    sum: f64,
}

impl ForceSums {
    #[inline]
    fn add(&mut self, phi: &[f64; FORCE_FEATURES], y: f64, w: f64) {
        for (r, p) in self.rhs.iter_mut().zip(phi) {
            *r += w * p * y;
        }
        self.yy += w * y * y;
        self.sum += w * y;
    }

    fn merge(&mut self, other: &Self) {
        for (r, o) in self.rhs.iter_mut().zip(&other.rhs) {
            *r += o;
        }
        self.yy += other.yy;
        self.sum += other.sum;
    }
}

/// Tension knots of the drive's hat functions, `−1 + k/6`: the bottom of the range, where the
/// design's low-tension probes are ([`super::design::design_strain_floor`]), the midpoints of
/// the design's six tension levels ([`super::design::DesignParams`]), where its cycles run, and
/// the midpoints between the levels, where its tension probes between the levels run
/// ([`super::design::DesignParams::between_level_cycles`]). With knots at the levels only, the
/// drive is linear in the tension between them, and the stick answer to small tension cycles
/// there came out up to 46 % small at interfaces 3-5.
pub(crate) const TENSION_KNOTS: [f64; 12] = tension_knots();

/// `−1 + k/6` for `k = 0 … 11`: the bottom of the range, the six levels and the midpoints between
/// them.
const fn tension_knots() -> [f64; 12] {
    let mut knots = [0.0; 12];
    let mut k = 0;
    while k < knots.len() {
        knots[k] = -1.0 + k as f64 / 6.0;
        k += 1;
    }
    knots
}

/// Curvature powers of the drive: `1, y, y², y³`.
const CURVATURE_POWERS: usize = 4;

/// Load features of the drive: `ψ = φ_k(x) yʲ`, the hat functions `φ_k` of the tension on
/// [`TENSION_KNOTS`] (continued linearly beyond the outer knots, so they sum to one
/// everywhere) times the powers `j = 0 … 3` of the curvature.
pub(crate) const DRIVE_FEATURES: usize = TENSION_KNOTS.len() * CURVATURE_POWERS;

/// The interval `[k_i, k_i+1]` of [`TENSION_KNOTS`] that holds `x` (the outer ones continued)
/// and the position `t` of `x` in it: the hats `i` and `i + 1` are `1 − t` and `t`, the others
/// zero.
#[inline]
fn tension_interval(x: f64) -> (usize, f64) {
    let k = &TENSION_KNOTS;
    let i = k[1..k.len() - 1]
        .iter()
        .take_while(|&&knot| x > knot)
        .count();
    (i, (x - k[i]) / (k[i + 1] - k[i]))
}

/// The hat functions of the tension at scaled tension `x`.
#[inline]
fn tension_hats(x: f64) -> [f64; TENSION_KNOTS.len()] {
    let mut h = [0.0; TENSION_KNOTS.len()];
    let (i, t) = tension_interval(x);
    h[i] = 1.0 - t;
    h[i + 1] = t;
    h
}

/// `Σ coefficients · drive_features(x, y)` over the two hat functions that are not zero at
/// `x`, in the same order: the same sum to the bit at a quarter of the work.
#[inline]
pub(crate) fn drive_dot(coefficients: &[f64; DRIVE_FEATURES], x: f64, y: f64) -> f64 {
    let (i, t) = tension_interval(x);
    let powers = [1.0, y, y * y, y * y * y];
    // as `Iterator::sum` of f64 starts
    let mut sum = -0.0;
    for (hat, h) in [(i, 1.0 - t), (i + 1, t)] {
        for (j, p) in powers.iter().enumerate() {
            sum += coefficients[hat * CURVATURE_POWERS + j] * (h * p);
        }
    }
    sum
}

/// The drive features at scaled loads (x, y).
#[inline]
pub(crate) fn drive_features(x: f64, y: f64) -> [f64; DRIVE_FEATURES] {
    let hats = tension_hats(x);
    let powers = [1.0, y, y * y, y * y * y];
    let mut f = [0.0; DRIVE_FEATURES];
    for (k, h) in hats.iter().enumerate() {
        for (j, p) in powers.iter().enumerate() {
            f[k * CURVATURE_POWERS + j] = h * p;
        }
    }
    f
}

/// Unknowns of the structure equation: the drive's coefficients, the compliance `g` and the
/// stick ratio `r`.
const DRIVE_UNKNOWNS: usize = DRIVE_FEATURES + 2;

/// Sums of one contact's structure equation `s = ψ·d − g f_T − r s_e`, with the force columns
/// `u = [−f_T, −s_e]`.
#[derive(Clone, Copy, Debug, PartialEq)]
struct DriveSums {
    /// Σ ψ_i u_j.
    psi_u: [[f64; 2]; DRIVE_FEATURES],
    /// Σ u_i u_j (00, 01, 11).
    uu: [f64; 3],
    /// Σ ψ s.
    psi_s: [f64; DRIVE_FEATURES],
    /// Σ u s.
    us: [f64; 2],
    /// Σ s².
    ss: f64,
    /// Σ s.
    s_sum: f64,
}

impl Default for DriveSums {
    fn default() -> Self {
        Self {
            psi_u: [[0.0; 2]; DRIVE_FEATURES],
            uu: [0.0; 3],
            psi_s: [0.0; DRIVE_FEATURES],
            us: [0.0; 2],
            ss: 0.0,
            s_sum: 0.0,
        }
    }
}

impl DriveSums {
    fn merge(&mut self, o: &Self) {
        for (a, b) in self.psi_u.iter_mut().zip(&o.psi_u) {
            a[0] += b[0];
            a[1] += b[1];
        }
        for (a, b) in self.uu.iter_mut().zip(&o.uu) {
            *a += b;
        }
        for (a, b) in self.psi_s.iter_mut().zip(&o.psi_s) {
            *a += b;
        }
        for (a, b) in self.us.iter_mut().zip(&o.us) {
            *a += b;
        }
        self.ss += o.ss;
        self.s_sum += o.s_sum;
    }
}

/// Fit of one channel: coefficients and the residual and spread sums of squares.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ForceFit {
    /// Coefficients on the force features.
    pub coefficients: [f64; FORCE_FEATURES],
    /// Σ residual².
    pub residual_ss: f64,
    /// Σ (y − ȳ)².
    pub spread_ss: f64,
}

/// Fit of one contact.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ContactFit {
    /// The law.
    pub law: ContactLaw,
    /// Σ slip residual² (m²).
    pub slip_residual_ss: f64,
    /// Σ (s − s̄)² (m²).
    pub slip_spread_ss: f64,
    /// Normal force fit sums (N²).
    pub normal_residual_ss: f64,
    /// Σ (f_N − f̄_N)² (N²).
    pub normal_spread_ss: f64,
    /// Whether `g` or `r` was refitted at zero.
    pub compliance_clamped: bool,
}

/// Accumulates the calibration samples of every contact and wire-element channel.
#[derive(Clone, Debug)]
pub struct FitAccumulator {
    force_gram: ForceGram,
    drive_gram: SMatrix<f64, DRIVE_FEATURES, DRIVE_FEATURES>,
    samples: usize,
    /// Σ w.
    weight: f64,
    normal: Vec<ForceSums>,
    drive: Vec<DriveSums>,
    elements: Vec<ForceSums>,
    /// Drive features of the previous sample.
    previous_load: Option<[f64; DRIVE_FEATURES]>,
    /// Every contact's (slip, tangential force, elastic slip) at the previous sample.
    previous_contacts: Vec<(f64, f64, f64)>,
    /// The contacts' stick stiffness, with which the stick part `s_e = f_T / k` of a slip
    /// is taken.
    stick: StickStiffness,
    /// The interfaces' collective modes, if any: their answer is taken off the FE slips
    /// before the contacts' own laws are fitted.
    modes: Option<ModeTerms>,
}

/// The stiffness `k` with which a contact sticks, by which the fit takes the stick part
/// `s_e = f_T / k` of its slip.
#[derive(Clone, Debug, PartialEq)]
pub enum StickStiffness {
    /// The elastic-slip law: `k = (μ / γ_e) f_N`, holding `μ / γ_e` (1/m).
    PerNewton(f64),
    /// The Cattaneo–Mindlin law: `k` the Iwan bank's stiffness in stick, a hair below each
    /// contact's `k₀(f_N)` (mesh contact order; [`super::iwan::stick_fraction`]).
    Initial(Vec<super::iwan::InitialStiffness>),
}

impl StickStiffness {
    /// `k` of contact `c` at normal force `f_n` (0 when open).
    #[inline]
    pub fn at(&self, c: usize, f_n: f64) -> f64 {
        if f_n <= 0.0 {
            return 0.0;
        }
        match self {
            Self::PerNewton(per_m) => per_m * f_n,
            Self::Initial(k0) => k0
                .get(c)
                .map_or(0.0, |k| super::iwan::stick_fraction() * k.at(f_n)),
        }
    }
}

/// What the fit needs of the interfaces' collective modes ([`ModeCoupling`]).
#[derive(Clone, Debug, PartialEq)]
pub(crate) struct ModeTerms {
    coupling: ModeCoupling,
    /// Interface of every contact.
    interface: Vec<usize>,
    /// Mode shapes at every contact.
    shape: Vec<[f64; MODES]>,
    /// Σ shape² over each interface's contacts.
    norm: Vec<[f64; MODES]>,
    /// The collective drive per interface and mode at the previous sample.
    previous: Vec<[f64; MODES]>,
    /// Scratch: the amplifications at the current tension.
    amplification: Vec<f64>,
}

impl ModeTerms {
    pub(crate) fn new(sites: &[ContactSite], coupling: Option<&ModeCoupling>) -> Option<Self> {
        let coupling = coupling?.clone();
        let interfaces = coupling.interfaces();
        let shape: Vec<[f64; MODES]> = sites.iter().map(|s| mode_shapes(s.theta_rad)).collect();
        let mut norm = vec![[0.0; MODES]; interfaces];
        for (s, sh) in sites.iter().zip(&shape) {
            if let Some(n) = norm.get_mut(s.interface) {
                for (n, v) in n.iter_mut().zip(sh) {
                    *n += v * v;
                }
            }
        }
        Some(Self {
            coupling,
            interface: sites.iter().map(|s| s.interface).collect(),
            shape,
            norm,
            previous: Vec::new(),
            amplification: Vec::new(),
        })
    }

    /// The collective drive per interface and mode, `Σ_J a[I][J][m] q_{J,m}`, of the
    /// irreversible slips `s − s_e` at scaled tension `x`.
    pub(crate) fn drive(
        &mut self,
        x: f64,
        irreversible: impl Iterator<Item = f64>,
    ) -> Vec<[f64; MODES]> {
        let n = self.norm.len();
        let mut q = vec![[0.0; MODES]; n];
        for ((sp, &i), sh) in irreversible.zip(&self.interface).zip(&self.shape) {
            if let Some(q) = q.get_mut(i) {
                for (a, v) in q.iter_mut().zip(sh) {
                    *a += v * sp;
                }
            }
        }
        for (a, nm) in q.iter_mut().zip(&self.norm) {
            for (v, nm) in a.iter_mut().zip(nm) {
                *v /= nm.max(f64::MIN_POSITIVE);
            }
        }
        self.coupling.at(x, &mut self.amplification);
        (0..n)
            .map(|i| {
                std::array::from_fn(|m| {
                    (0..n)
                        .map(|j| self.amplification[(i * n + j) * MODES + m] * q[j][m])
                        .sum()
                })
            })
            .collect()
    }
}

impl FitAccumulator {
    /// Empty sums for `contacts` contacts and `elements` wire-element channels of a model whose
    /// contacts stick with the stiffness `stick`.
    pub fn new(contacts: usize, elements: usize, stick: StickStiffness) -> Self {
        Self {
            force_gram: ForceGram::zeros(),
            drive_gram: SMatrix::zeros(),
            samples: 0,
            weight: 0.0,
            normal: vec![ForceSums::default(); contacts],
            drive: vec![DriveSums::default(); contacts],
            elements: vec![ForceSums::default(); elements],
            previous_load: None,
            previous_contacts: Vec::new(),
            stick,
            modes: None,
        }
    }

    /// The same sums with the interfaces' collective modes taken off the FE slips (none if
    /// `modes` is empty).
    pub(crate) fn with_modes(
        mut self,
        sites: &[ContactSite],
        modes: Option<&ModeCoupling>,
    ) -> Self {
        self.modes = ModeTerms::new(sites, modes);
        self
    }

    /// Samples consumed.
    pub fn samples(&self) -> usize {
        self.samples
    }

    /// Sum of their weights.
    pub fn weight(&self) -> f64 {
        self.weight
    }

    /// Adds one sample at scaled loads (x, y) with least-squares weight `w` (> 0): every
    /// contact's (slip, f_N, f_T) and every element channel's value. Slices shorter or longer
    /// than the sums are a caller's error and are ignored beyond the shorter length.
    pub fn add(&mut self, x: f64, y: f64, w: f64, contacts: &[(f64, f64, f64)], elements: &[f64]) {
        let phi = force_features(x, y);
        let psi = drive_features(x, y);
        let phi_v = ForceVec::from_column_slice(&phi);
        self.force_gram += w * phi_v * phi_v.transpose();
        self.samples += 1;
        self.weight += w;
        for (&(_, f_n, _), n) in contacts.iter().zip(&mut self.normal) {
            n.add(&phi, f_n, w);
        }
        for (e, &v) in self.elements.iter_mut().zip(elements) {
            e.add(&phi, v, w);
        }
        // the structure equation on the increment from the previous sample: the Jenkins
        // element answers the drive's changes, never its level
        let stick = &self.stick;
        let elastic = |c: usize, f_n: f64, f_t: f64| {
            let k = stick.at(c, f_n);
            if k > 0.0 {
                f_t / k
            } else {
                0.0
            }
        };
        // the collective modes' answer since the previous sample, per interface
        let mode_change = self.modes.as_mut().map(|m| {
            let w = m.drive(
                x,
                contacts
                    .iter()
                    .enumerate()
                    .map(|(c, v)| v.0 - elastic(c, v.1, v.2)),
            );
            let previous = std::mem::replace(&mut m.previous, w.clone());
            if previous.len() == w.len() {
                w.iter()
                    .zip(&previous)
                    .map(|(a, b)| std::array::from_fn(|k| a[k] - b[k]))
                    .collect()
            } else {
                vec![[0.0; MODES]; w.len()]
            }
        });
        let Some(previous) = self.previous_load.replace(psi) else {
            self.previous_contacts = contacts
                .iter()
                .enumerate()
                .map(|(c, v)| (v.0, v.2, elastic(c, v.1, v.2)))
                .collect();
            return;
        };
        let mut dpsi = [0.0; DRIVE_FEATURES];
        for ((d, a), b) in dpsi.iter_mut().zip(&psi).zip(&previous) {
            *d = a - b;
        }
        let psi_v = SVector::<f64, DRIVE_FEATURES>::from_column_slice(&dpsi);
        self.drive_gram += w * psi_v * psi_v.transpose();
        for (c, ((&(s, f_n, f_t), d), prev)) in contacts
            .iter()
            .zip(&mut self.drive)
            .zip(&mut self.previous_contacts)
            .enumerate()
        {
            let (ps, pf, pe) = *prev;
            let e = elastic(c, f_n, f_t);
            *prev = (s, f_t, e);
            let collective = match (&self.modes, &mode_change) {
                (Some(m), Some(change)) => {
                    let (i, sh) = (m.interface[c], &m.shape[c]);
                    change
                        .get(i)
                        .map_or(0.0, |w| w.iter().zip(sh).map(|(a, b)| a * b).sum::<f64>())
                }
                _ => 0.0,
            };
            let ds = s - ps - collective;
            let u = [-(f_t - pf), -(e - pe)];
            let (ws, wu) = (w * ds, [w * u[0], w * u[1]]);
            for ((pu, ps), p) in d.psi_u.iter_mut().zip(&mut d.psi_s).zip(&dpsi) {
                pu[0] += p * wu[0];
                pu[1] += p * wu[1];
                *ps += p * ws;
            }
            d.uu[0] += wu[0] * u[0];
            d.uu[1] += wu[0] * u[1];
            d.uu[2] += wu[1] * u[1];
            d.us[0] += wu[0] * ds;
            d.us[1] += wu[1] * ds;
            d.ss += ws * ds;
            d.s_sum += ws;
        }
    }

    /// Adds the sums of `other`, fitted on another run of the same model (another chain of the
    /// design): the samples of both, with no increment from one run's last sample to the
    /// other's first. Sums of a model with other contacts or channels are a caller's error and
    /// are merged up to the shorter length.
    pub fn merge(&mut self, other: &FitAccumulator) {
        self.force_gram += other.force_gram;
        self.drive_gram += other.drive_gram;
        self.samples += other.samples;
        self.weight += other.weight;
        for (a, b) in self.normal.iter_mut().zip(&other.normal) {
            a.merge(b);
        }
        for (a, b) in self.drive.iter_mut().zip(&other.drive) {
            a.merge(b);
        }
        for (a, b) in self.elements.iter_mut().zip(&other.elements) {
            a.merge(b);
        }
    }

    /// The fitted laws of every contact.
    pub(crate) fn contact_fits(&self) -> Vec<ContactFit> {
        let n = self.weight.max(f64::MIN_POSITIVE);
        let normal_solver = ScaledSolver::new(&self.force_gram);
        self.normal
            .iter()
            .zip(&self.drive)
            .map(|(ns, ds)| {
                let normal = self.force_fit(&normal_solver, ns);
                let (drive, compliance, slip_residual_ss, clamped) = self.drive_fit(ds);
                ContactFit {
                    law: ContactLaw {
                        normal: normal.coefficients,
                        drive,
                        compliance,
                    },
                    slip_residual_ss,
                    slip_spread_ss: (ds.ss - ds.s_sum * ds.s_sum / n).max(0.0),
                    normal_residual_ss: normal.residual_ss,
                    normal_spread_ss: normal.spread_ss,
                    compliance_clamped: clamped,
                }
            })
            .collect()
    }

    /// The fitted element channels.
    pub(crate) fn element_fits(&self) -> Vec<ForceFit> {
        let solver = ScaledSolver::new(&self.force_gram);
        self.elements
            .iter()
            .map(|e| self.force_fit(&solver, e))
            .collect()
    }

    fn force_fit(&self, solver: &ScaledSolver<FORCE_FEATURES>, s: &ForceSums) -> ForceFit {
        let rhs = ForceVec::from_column_slice(&s.rhs);
        let beta = solver.solve(&rhs);
        let n = self.weight.max(f64::MIN_POSITIVE);
        let residual_ss =
            (s.yy - 2.0 * beta.dot(&rhs) + (beta.transpose() * self.force_gram * beta)[0]).max(0.0);
        let mut coefficients = [0.0; FORCE_FEATURES];
        coefficients.copy_from_slice(beta.as_slice());
        ForceFit {
            coefficients,
            residual_ss,
            spread_ss: (s.yy - s.sum * s.sum / n).max(0.0),
        }
    }

    /// The drive, `[g, r]`, Σ residual², whether they were refitted (the free fit makes `g` or
    /// `r` negative: first `r = 0`, then `g = r = 0`).
    fn drive_fit(&self, d: &DriveSums) -> ([f64; DRIVE_FEATURES], [f64; 2], f64, bool) {
        let n = DRIVE_UNKNOWNS;
        let mut m = DMatrix::<f64>::zeros(n, n);
        let mut rhs = DVector::<f64>::zeros(n);
        for i in 0..DRIVE_FEATURES {
            for j in 0..DRIVE_FEATURES {
                m[(i, j)] = self.drive_gram[(i, j)];
            }
            for j in 0..2 {
                m[(i, DRIVE_FEATURES + j)] = d.psi_u[i][j];
                m[(DRIVE_FEATURES + j, i)] = d.psi_u[i][j];
            }
            rhs[i] = d.psi_s[i];
        }
        let (a, b) = (DRIVE_FEATURES, DRIVE_FEATURES + 1);
        m[(a, a)] = d.uu[0];
        m[(a, b)] = d.uu[1];
        m[(b, a)] = d.uu[1];
        m[(b, b)] = d.uu[2];
        rhs[a] = d.us[0];
        rhs[b] = d.us[1];
        let residual = |beta: &DVector<f64>| {
            (d.ss - 2.0 * beta.dot(&rhs) + (beta.transpose() * &m * beta)[0]).max(0.0)
        };
        let all: Vec<usize> = (0..n).collect();
        let g_only: Vec<usize> = (0..=DRIVE_FEATURES).collect();
        let neither: Vec<usize> = (0..DRIVE_FEATURES).collect();
        let has_force = d.uu[0] > 0.0;
        let candidates: [&[usize]; 3] = [&all, &g_only, &neither];
        for (k, idx) in candidates.iter().enumerate() {
            if !has_force && k < 2 {
                continue;
            }
            let beta = solve_subset(&m, &rhs, idx);
            let (g, r) = (beta[a], beta[b]);
            let admissible = beta.iter().all(|v| v.is_finite()) && g >= 0.0 && r >= 0.0;
            if admissible || idx.len() == DRIVE_FEATURES {
                let mut drive = [0.0; DRIVE_FEATURES];
                drive.copy_from_slice(&beta.as_slice()[..DRIVE_FEATURES]);
                continue_beyond_the_design(&mut drive, &self.drive_gram);
                return (drive, [g, r], residual(&beta), k > 0 && has_force);
            }
        }
        ([0.0; DRIVE_FEATURES], [0.0; 2], d.ss, false)
    }
}

/// Holds the drive constant in tension beyond the knots the design never reached: a knot
/// whose hat function no sample moved (its column of `gram` is zero, and the solve left its
/// coefficients at 0) takes the coefficients of the nearest knot the design reached, so that
/// the drive stays at its last fitted value instead of falling to 0 at that knot. Under the
/// contact-mechanics laws the design stops at the strokes' floor
/// ([`super::design::LowestTension::StrokeFloor`]), above the lowest knot.
fn continue_beyond_the_design(
    drive: &mut [f64; DRIVE_FEATURES],
    gram: &SMatrix<f64, DRIVE_FEATURES, DRIVE_FEATURES>,
) {
    let knots = TENSION_KNOTS.len();
    let reached = |k: usize| {
        (0..CURVATURE_POWERS)
            .any(|j| gram[(k * CURVATURE_POWERS + j, k * CURVATURE_POWERS + j)] > 0.0)
    };
    let Some(lowest) = (0..knots).find(|&k| reached(k)) else {
        return;
    };
    let highest = (0..knots).rev().find(|&k| reached(k)).unwrap_or(lowest);
    let copy = |drive: &mut [f64; DRIVE_FEATURES], to: usize, from: usize| {
        for j in 0..CURVATURE_POWERS {
            drive[to * CURVATURE_POWERS + j] = drive[from * CURVATURE_POWERS + j];
        }
    };
    for k in 0..lowest {
        copy(drive, k, lowest);
    }
    for k in highest + 1..knots {
        copy(drive, k, highest);
    }
}

/// The least-squares solution of `m β = rhs` restricted to the unknowns `idx` (the others 0),
/// Jacobi-scaled with the relative ridge [`RIDGE`].
fn solve_subset(m: &DMatrix<f64>, rhs: &DVector<f64>, idx: &[usize]) -> DVector<f64> {
    let k = idx.len();
    let scale: Vec<f64> = idx
        .iter()
        .map(|&i| {
            let d = m[(i, i)];
            if d > 0.0 && d.is_finite() {
                1.0 / d.sqrt()
            } else {
                0.0
            }
        })
        .collect();
    let mut a = DMatrix::<f64>::from_fn(k, k, |p, q| scale[p] * m[(idx[p], idx[q])] * scale[q]);
    for p in 0..k {
        a[(p, p)] += RIDGE;
    }
    let r = DVector::<f64>::from_fn(k, |p, _| scale[p] * rhs[idx[p]]);
    let z = a
        .clone()
        .cholesky()
        .map(|c| c.solve(&r))
        .or_else(|| a.lu().solve(&r))
        .unwrap_or_else(|| DVector::zeros(k));
    let mut beta = DVector::<f64>::zeros(m.nrows());
    for (p, &i) in idx.iter().enumerate() {
        beta[i] = scale[p] * z[p];
    }
    beta
}

/// Jacobi-scaled, ridge-regularised solver of a symmetric positive semi-definite system.
struct ScaledSolver<const N: usize> {
    scale: SVector<f64, N>,
    inverse: SMatrix<f64, N, N>,
}

impl<const N: usize> ScaledSolver<N> {
    fn new(m: &SMatrix<f64, N, N>) -> Self {
        let scale = SVector::<f64, N>::from_fn(|i, _| {
            let d = m[(i, i)];
            if d > 0.0 && d.is_finite() {
                1.0 / d.sqrt()
            } else {
                0.0
            }
        });
        let mut a = SMatrix::<f64, N, N>::from_fn(|i, j| scale[i] * m[(i, j)] * scale[j]);
        for i in 0..N {
            a[(i, i)] += RIDGE;
        }
        let inverse = a
            .cholesky()
            .map(|c| c.inverse())
            .or_else(|| a.try_inverse())
            .unwrap_or_else(SMatrix::zeros);
        Self { scale, inverse }
    }

    fn solve(&self, rhs: &SVector<f64, N>) -> SVector<f64, N> {
        let z = self.inverse * rhs.component_mul(&self.scale);
        z.component_mul(&self.scale)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn an_exact_quadratic_force_is_recovered() {
        let truth = [120.0, 30.0, -12.0, 4.0, 2.5, -1.5];
        let mut acc = FitAccumulator::new(1, 1, StickStiffness::PerNewton(STICK));
        for i in 0..40 {
            let (x, y) = ((i as f64 * 0.37).sin(), (i as f64 * 0.91).cos());
            let f: f64 = force_features(x, y)
                .iter()
                .zip(&truth)
                .map(|(a, b)| a * b)
                .sum();
            acc.add(x, y, 1.0, &[(0.0, f, 0.0)], &[f]);
        }
        let fits = acc.contact_fits();
        for (a, b) in fits[0].law.normal.iter().zip(&truth) {
            assert!((a - b).abs() < 1e-6, "{a} vs {b}");
        }
        // exact data: what is left is the round-off of the normal equations
        assert!(fits[0].normal_residual_ss < 1e-8 * fits[0].normal_spread_ss);
        let e = acc.element_fits();
        assert!((e[0].coefficients[0] - 120.0).abs() < 1e-6);
    }

    /// `μ / γ_e` of the fit tests (1/m).
    const STICK: f64 = 0.12 / 1e-5;

    /// Sample `i` of a pseudo-random load path: the loads (x, y), the slip
    /// `s = ψ·drive − g f_T − r s_e` with `s_e = f_T / (STICK f_N)`, a normal force `f_N` that
    /// follows the tension and a tangential force `f_T` independent of the loads.
    fn structure_sample(
        i: usize,
        drive: &[f64],
        [g, r]: [f64; 2],
    ) -> (f64, f64, [(f64, f64, f64); 1]) {
        let (x, y) = ((i as f64 * 0.37).sin(), (i as f64 * 0.53).cos());
        let f_n = 100.0 + 30.0 * x;
        let f_t = 40.0 * (i as f64 * 1.7).sin();
        (
            x,
            y,
            [(structure_slip(x, y, f_n, f_t, drive, [g, r]), f_n, f_t)],
        )
    }

    /// The slip `s = ψ(x, y)·drive − g f_T − r s_e` with `s_e = f_T / (STICK f_N)`.
    fn structure_slip(x: f64, y: f64, f_n: f64, f_t: f64, drive: &[f64], [g, r]: [f64; 2]) -> f64 {
        let d: f64 = drive_features(x, y)
            .iter()
            .zip(drive)
            .map(|(p, q)| p * q)
            .sum();
        d - g * f_t - r * f_t / (STICK * f_n)
    }

    #[test]
    fn the_structure_equation_is_recovered_with_its_compliance() {
        // s = ψ·d − g f_T − r s_e with f_T independent of the loads and f_N varying with them:
        // the compliance, the stick ratio and the drive's changes are identifiable
        let truth: Vec<f64> = (0..DRIVE_FEATURES)
            .map(|i| 1e-6 * ((i as f64 * 1.3).sin() + 0.2))
            .collect();
        let (g, r) = (3e-8, 0.4);
        let mut acc = FitAccumulator::new(1, 0, StickStiffness::PerNewton(STICK));
        for i in 0..300 {
            let (x, y, c) = structure_sample(i, &truth, [g, r]);
            acc.add(x, y, 1.0, &c, &[]);
        }
        let fit = acc.contact_fits()[0];
        let rel = |p: f64, q: f64| (p - q).abs() / q.abs();
        // the increments fix the drive up to its level, which the Jenkins element never sees
        let drive = |c: &[f64], x: f64, y: f64| -> f64 {
            drive_features(x, y).iter().zip(c).map(|(p, q)| p * q).sum()
        };
        for i in 0..20 {
            let (x, y) = ((i as f64 * 0.71).sin(), (i as f64 * 0.29).cos());
            let fitted = drive(&fit.law.drive, x, y) - drive(&fit.law.drive, 0.1, -0.2);
            let truth = drive(&truth, x, y) - drive(&truth, 0.1, -0.2);
            assert!(
                (fitted - truth).abs() < 1e-5 * truth.abs().max(1e-7),
                "{fitted} vs {truth}"
            );
        }
        assert!(rel(fit.law.compliance[0], g) < 1e-6);
        assert!(rel(fit.law.compliance[1], r) < 1e-6);
        assert!(!fit.compliance_clamped);
        assert!(fit.slip_residual_ss < 1e-8 * fit.slip_spread_ss);
    }

    #[test]
    fn the_drive_is_held_beyond_the_tensions_the_design_reached() {
        // samples above x = -0.8 only (the strokes' floor of a range from slack): the lowest
        // knot's hat is never moved, and the drive below the knot at -5/6 stays at its value
        // there, where the fit inside the reached range is the free fit's
        let truth: Vec<f64> = (0..DRIVE_FEATURES)
            .map(|i| 1e-6 * ((i as f64 * 1.3).sin() + 0.2))
            .collect();
        let (g, r) = (3e-8, 0.4);
        let mut acc = FitAccumulator::new(1, 0, StickStiffness::PerNewton(STICK));
        for i in 0..400 {
            let (x, y, [(_, f_n, f_t)]) = structure_sample(i, &truth, [g, r]);
            let x = -0.8 + 0.9 * (x + 1.0);
            let s = structure_slip(x, y, f_n, f_t, &truth, [g, r]);
            acc.add(x, y, 1.0, &[(s, f_n, f_t)], &[]);
        }
        let fit = acc.contact_fits()[0];
        assert!((fit.law.compliance[0] - g).abs() < 1e-6 * g);
        assert!((fit.law.compliance[1] - r).abs() < 1e-6 * r);
        let truth_drive: [f64; DRIVE_FEATURES] = truth.clone().try_into().unwrap();
        let knot_1 = TENSION_KNOTS[1];
        for y in [-0.9, -0.3, 0.0, 0.4, 1.0] {
            let at_knot = drive_dot(&fit.law.drive, knot_1, y);
            for x in [-1.0, -0.95, -0.9, knot_1 - 1e-9] {
                let below = drive_dot(&fit.law.drive, x, y);
                assert!(
                    (below - at_knot).abs() <= 1e-12 * at_knot.abs().max(1e-12),
                    "drive at x = {x}, y = {y}: {below} against {at_knot} at the knot"
                );
            }
            // inside the reached range the drive's changes are the truth's
            let fitted = drive_dot(&fit.law.drive, -0.5, y) - drive_dot(&fit.law.drive, 0.3, y);
            let truth_d = drive_dot(&truth_drive, -0.5, y) - drive_dot(&truth_drive, 0.3, y);
            assert!(
                (fitted - truth_d).abs() < 1e-5 * truth_d.abs().max(1e-7),
                "{fitted} vs {truth_d}"
            );
        }
    }

    #[test]
    fn two_chains_merged_fit_as_one_without_the_jump_between_them() {
        // the structure equation holds up to a level that differs between two runs (each run
        // starts from its own initialisation): merged, their sums give the law exactly; fed
        // as one run, the jump between them would count as an increment and spoil it
        let truth: Vec<f64> = (0..DRIVE_FEATURES)
            .map(|i| 1e-6 * ((i as f64 * 0.7).cos() + 0.3))
            .collect();
        let g0 = 2e-8;
        let sample = |i: usize, level: f64| {
            let (x, y, [(s, f_n, f_t)]) = structure_sample(i, &truth, [g0, 0.0]);
            (x, y, [(level + s, f_n, f_t)])
        };
        let (mut a, mut b, mut one) = (
            FitAccumulator::new(1, 0, StickStiffness::PerNewton(STICK)),
            FitAccumulator::new(1, 0, StickStiffness::PerNewton(STICK)),
            FitAccumulator::new(1, 0, StickStiffness::PerNewton(STICK)),
        );
        for i in 0..300 {
            let (acc, level) = if i < 150 {
                (&mut a, 0.0)
            } else {
                (&mut b, 3e-6)
            };
            let (x, y, c) = sample(i, level);
            acc.add(x, y, 1.0, &c, &[]);
            one.add(x, y, 1.0, &c, &[]);
        }
        a.merge(&b);
        assert_eq!(a.samples(), 300);
        assert_eq!(a.weight(), 300.0);
        let (merged, single) = (a.contact_fits()[0], one.contact_fits()[0]);
        assert!((merged.law.compliance[0] - g0).abs() < 1e-6 * g0);
        assert!(merged.law.compliance[1].abs() < 1e-6);
        assert!(merged.slip_residual_ss < 1e-8 * merged.slip_spread_ss);
        assert!(single.slip_residual_ss > 1e-3 * single.slip_spread_ss);
        // the normal force has no increments: both give the same fit
        for (p, q) in merged.law.normal.iter().zip(&single.law.normal) {
            assert!((p - q).abs() < 1e-9 * q.abs().max(1.0), "{p} vs {q}");
        }
    }

    #[test]
    fn the_sparse_drive_is_the_dense_one_to_the_bit() {
        let coefficients: [f64; DRIVE_FEATURES] =
            std::array::from_fn(|k| ((k * 7919) % 113) as f64 * 1.37e-7 - 6.1e-6);
        for i in 0..=400 {
            let x = -1.3 + 2.6 * i as f64 / 400.0;
            for y in [-1.01, -0.5, 0.0, 0.3, 1.0] {
                let dense: f64 = coefficients
                    .iter()
                    .zip(&drive_features(x, y))
                    .map(|(a, b)| a * b)
                    .sum();
                assert_eq!(
                    drive_dot(&coefficients, x, y).to_bits(),
                    dense.to_bits(),
                    "x {x}, y {y}"
                );
            }
        }
        for knot in TENSION_KNOTS {
            let dense: f64 = coefficients
                .iter()
                .zip(&drive_features(knot, 0.7))
                .map(|(a, b)| a * b)
                .sum();
            assert_eq!(
                drive_dot(&coefficients, knot, 0.7).to_bits(),
                dense.to_bits()
            );
        }
    }

    #[test]
    fn the_tension_hats_sum_to_one_and_interpolate_linearly() {
        for i in 0..=40 {
            let x = -1.0 + 0.05 * i as f64;
            let h = tension_hats(x);
            assert!(
                (h.iter().sum::<f64>() - 1.0).abs() < 1e-14,
                "x = {x}: {h:?}"
            );
            // a linear function of x on the knots is reproduced everywhere, also beyond them
            let f: f64 = h
                .iter()
                .zip(&TENSION_KNOTS)
                .map(|(a, k)| a * (2.0 * k - 0.3))
                .sum();
            assert!((f - (2.0 * x - 0.3)).abs() < 1e-13, "x = {x}");
        }
        let mut at_knot = [0.0; TENSION_KNOTS.len()];
        at_knot[3] = 1.0;
        assert_eq!(tension_hats(-0.5), at_knot);
        let mut at_bottom = [0.0; TENSION_KNOTS.len()];
        at_bottom[0] = 1.0;
        assert_eq!(tension_hats(-1.0), at_bottom);
        // the knots are the bottom of the range, the default design's tension levels, where its
        // cycles run, and the midpoints between them, where its tension probes between the
        // levels run
        let levels = super::super::design::DesignParams::default().tension_levels;
        assert_eq!(2 * levels, TENSION_KNOTS.len());
        assert_eq!(TENSION_KNOTS[0], -1.0);
        for j in 0..levels {
            assert_eq!(
                super::super::design::tension_level(j, levels),
                TENSION_KNOTS[2 * j + 1]
            );
        }
        for j in 0..levels - 1 {
            assert_eq!(
                super::super::design::between_levels(j, levels),
                TENSION_KNOTS[2 * j + 2]
            );
        }
    }

    #[test]
    fn a_negative_compliance_is_refitted_at_zero() {
        // data made with g < 0: the fit falls back to the pure drive
        let mut acc = FitAccumulator::new(1, 0, StickStiffness::PerNewton(STICK));
        for i in 0..60 {
            let (x, y) = ((i as f64 * 0.37).sin(), (i as f64 * 0.53).cos());
            let f_t = 40.0 * (i as f64 * 1.7).sin();
            let s = 1e-6 * x + 4e-8 * f_t;
            acc.add(x, y, 1.0, &[(s, 100.0, f_t)], &[]);
        }
        let fit = acc.contact_fits()[0];
        assert_eq!(fit.law.compliance, [0.0, 0.0]);
        assert!(fit.compliance_clamped);
        assert!(fit.slip_residual_ss > 0.0);
    }
}
