//! A reduced strand response, calibrated on the FE model, for the strand stage at campaign scale
//! (the paper's aim of making "the large number of simulations required by a fatigue life
//! estimate" affordable, its abstract and Sec. 2.2).
//!
//! # Model
//!
//! The strand is quasi-static and rate-independent, with Coulomb friction at the contacts. Each
//! contact `c` of the FE model becomes one Jenkins element (a spring in series with a Coulomb
//! slider) that obeys the FE model's own tangential law, loaded through the rest of the strand,
//! which is reduced to a drive and a compliance:
//!
//! - structure: `s + g f_T + r s_e = d(ε, κ)`, with the drive
//!   `d = Σ_k φ_k(x) (a_k + b_k y + c_k y² + e_k y³)` in the scaled loads `x = (ε − ε₀)/ε_h`,
//!   `y = (κ − κ₀)/κ_h` ([`LoadScaling`]), `φ_k` the hat functions of the tension on the bottom
//!   of the range, the design's six tension levels and the midpoints between them (the slip per
//!   unit curvature piecewise linear in the tension, cubic in the curvature), `g ≥ 0` the
//!   compliance through which the strand around the contact answers its tangential force, and
//!   `r ≥ 0` a part of that answer in proportion to the contact's elastic slip `s_e` rather
//!   than to its force: where the tension, and with it `f_N`, is small, a contact's force is
//!   small but the neighbours it leans on still give way (the sliding rate over the stick rate
//!   is `1 + g k + r`, `k = μ f_N / γ_e`);
//! - contact (the elastic-slip law of `crate::contact::laws`, the paper's Sec. 2.1): the slip
//!   `s = s_e + s_p`, elastic part `s_e` with `f_T = (μ f_N / γ_e) s_e`, `|s_e| ≤ γ_e`, and an
//!   irreversible part `s_p` that moves only while the contact slides;
//! - normal force: `f_N(x, y)`, quadratic in the scaled loads, clipped at zero.
//!
//! `s` and `f_T` are the FE model's slip and tangential force along the outer wire
//! ([`crate::strand::history::monitors`]). The response to a closed load cycle is then a
//! Masing-type hysteresis loop set by the cycle's range and by the normal force that the
//! tension sets, and in the stick regime (`|s_e| < γ_e` throughout, most contacts of mild sea
//! states) it is linear in the loads.
//!
//! # Calibration
//!
//! [`calibrate`] drives the FE model through a designed load history ([`design`]: curvature,
//! tension and combined cycles of decreasing amplitude at several tension levels over the
//! requested [`LoadRange`], then small probe cycles in curvature and tension at a grid of
//! curvatures on every level), made of independent chains that run side by side, one FE run
//! each, and fits per contact, by linear least squares weighted by the
//! inverse square of each sample's cycle amplitude ([`design`], [`fit`]): `f_N` on the six
//! quadratic load features at every sample, and the drive, `g` and `r` on the structure
//! equation written for the increment from one sample to the next of the same chain, with the
//! FE's `s`, `f_T` and `s_e = f_T / k`
//! (the Jenkins element answers the drive's changes, never its level; `r`, then `g` too, is
//! refitted at zero if the fit makes either negative). Wire axial forces
//! of the monitor channels are fitted like `f_N`. The calibration then replays the designed
//! history through the reduced model and reports, per layer interface, its in-sample error
//! against the FE run ([`CalibrationReport`]).
//!
//! # Use
//!
//! [`run_reduced`] turns a `(t, ε, κ)` history into the outputs of an FE history run
//! ([`crate::strand::history::HistoryResult`]: one [`crate::fretting::ContactRecord`] per contact
//! with every slip cycle and its forces, the monitor series), in seconds, along the load path
//! that FE run solves (its turning points, [`crate::strand::history::reduce::samples_on_path`]).
//! A sample outside the calibrated range (beyond `RANGE_SLACK` of it) is refused with the
//! range, never extrapolated. The first sample is reached along the FE initialisation's path:
//! every contact starts unloaded tangentially in the straight strand at a small tension
//! ([`ReducedStrand::initial_strain_fraction`] of the first, not below the calibrated range),
//! follows the drive to the first curvature at that tension, then to the first tension. The
//! state this leaves (which contacts slid while the strand was bent at a small tension, with
//! little normal force) sets how each contact answers a change of tension afterwards.
//!
//! # Collective modes
//!
//! A contact's own answer to its sliding is small (a few percent of the slip, measured on the
//! FE model), but a pattern of sliding over a whole layer interface moves the layers
//! themselves: a uniform slip of every contact of an interface comes back as 70-96 % of itself,
//! a cos θ or sin θ pattern as 1-64 %, rising with the tension, and the neighbouring
//! interfaces answer a bending pattern by up to a quarter of it, in opposition. The contacts
//! are therefore coupled through the projections `q` of each interface's irreversible slips on
//! the modes uniform, cos θ, sin θ ([`ModeCoupling`]): the drive of a contact of interface `I`
//! gains `Σ_J Σ_m a[I][J][m](x) ψ_m(θ) q_{J,m}`, with the amplifications `a` measured on the
//! FE model at seven tensions (`modes.rs`) and their answer taken off the FE slips before the
//! contact laws are fitted. A run solves the amplitudes at every sample by Newton's method.
//!
//! Under the Cattaneo–Mindlin law a calibration measures no modes and its contacts run alone:
//! there the irreversible slip s − f_T/k that would feed the modes is the micro-slip of every
//! contact in partial slip, local to its crossing, and the reduced response follows the FE
//! model closer without them (docs/reduced-strand.md).
//!
//! What it leaves out, by construction: the interaction of contacts beyond `g`, `r` and the
//! interfaces' three modes (higher patterns round the strand, and neighbours along a wire).
//! Its error against
//! the FE model is measured on held-out histories (docs/reduced-strand.md), not assumed.
//!
//! Units: m, N, 1/m.

mod calibrate;
pub mod compare;
pub mod design;
pub mod fit;
pub mod iwan;
pub(crate) mod modes;
mod run;

use serde::{Deserialize, Serialize};

use super::history::monitors::{ContactSite, MonitorChannel};
use super::history::{HistoryError, LoadSample};

pub use calibrate::{
    calibrate, calibration_design, fit_recorded, measure_modes, model_key, CalibrationOptions,
    RecordedSample,
};
#[cfg(test)]
use run::contact_series_stepping_all;
pub use run::{contact_series, run_reduced};

/// Version of the stored calibration and of the fit that made it; a file of another version is
/// refused. Part of the cache key of a calibration, so every change to the model, the design or
/// the fit bumps it.
pub(crate) const FORMAT_VERSION: u32 = 11;

/// Slack of the calibrated range, as a fraction of each channel's range: a sample this far
/// outside is still accepted (round-off of the tension-to-strain conversion).
pub(crate) const RANGE_SLACK: f64 = 0.01;

/// Errors of the reduced strand response.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum ReducedError {
    /// A sample lies outside the calibrated range.
    #[error(
        "load sample {index} (t = {time_s} s): {field} = {value:e} lies outside the calibrated \
         range [{low:e}, {high:e}]; calibrate the reduced strand over a range that covers it"
    )]
    OutOfRange {
        /// Sample index.
        index: usize,
        /// Its time (s).
        time_s: f64,
        /// `strain` or `curvature_per_m`.
        field: &'static str,
        /// The value.
        value: f64,
        /// Calibrated lower bound.
        low: f64,
        /// Calibrated upper bound.
        high: f64,
    },
    /// A sample is not usable at all (non-finite, time not increasing).
    #[error("load sample {index}: {field} = {value}: {reason}")]
    InvalidSample {
        /// Sample index.
        index: usize,
        /// Field.
        field: &'static str,
        /// Value.
        value: f64,
        /// Why.
        reason: String,
    },
    /// A setting or a range is invalid.
    #[error("reduced strand: {field} = {value}: {reason}")]
    InvalidSetting {
        /// Field.
        field: &'static str,
        /// Value.
        value: f64,
        /// Why.
        reason: String,
    },
    /// The calibration data do not match the model or the stored format.
    #[error("reduced strand calibration: {reason}")]
    Calibration {
        /// Why.
        reason: String,
    },
    /// The FE run of one chain of the calibration's design failed.
    #[error("FE calibration run, chain {chain} of the design: {source}")]
    History {
        /// The chain ([`design`] module docs).
        chain: usize,
        /// What went wrong.
        source: HistoryError,
    },
}

fn invalid(field: &'static str, value: f64, reason: impl Into<String>) -> ReducedError {
    ReducedError::InvalidSetting {
        field,
        value,
        reason: reason.into(),
    }
}

/// The load range a calibration covers: axial strain and curvature, lowest and highest.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct LoadRange {
    /// Lowest and highest axial strain.
    pub strain: [f64; 2],
    /// Lowest and highest curvature (1/m).
    pub curvature_per_m: [f64; 2],
}

impl LoadRange {
    /// The range of `samples` (`None` if there are none).
    pub fn of(samples: &[LoadSample]) -> Option<Self> {
        let first = samples.first()?;
        let mut r = Self {
            strain: [first.strain; 2],
            curvature_per_m: [first.curvature_per_m; 2],
        };
        for s in samples {
            r.strain = [r.strain[0].min(s.strain), r.strain[1].max(s.strain)];
            r.curvature_per_m = [
                r.curvature_per_m[0].min(s.curvature_per_m),
                r.curvature_per_m[1].max(s.curvature_per_m),
            ];
        }
        Some(r)
    }

    /// The smallest range holding both.
    pub fn union(self, other: Self) -> Self {
        Self {
            strain: [
                self.strain[0].min(other.strain[0]),
                self.strain[1].max(other.strain[1]),
            ],
            curvature_per_m: [
                self.curvature_per_m[0].min(other.curvature_per_m[0]),
                self.curvature_per_m[1].max(other.curvature_per_m[1]),
            ],
        }
    }

    /// The range widened by `margin` × its width on each side, strain kept ≥ 0.
    pub fn widened(self, margin: f64) -> Self {
        let w = |[lo, hi]: [f64; 2]| {
            let d = margin * (hi - lo);
            [lo - d, hi + d]
        };
        let mut r = Self {
            strain: w(self.strain),
            curvature_per_m: w(self.curvature_per_m),
        };
        r.strain[0] = r.strain[0].max(0.0);
        r
    }

    /// The range with its highest strain lowered so that every load of it keeps the fibre
    /// strain ε + |κ| D/2 at the surface of a strand of diameter `outer_diameter_m` within
    /// `max_fibre_strain` (the strand model's elastic range, which every FE run checks); `None`
    /// when no strain above the lowest is left.
    pub fn within_fibre_strain(self, max_fibre_strain: f64, outer_diameter_m: f64) -> Option<Self> {
        let bending = self.largest_bending_strain(outer_diameter_m);
        // a hair below the limit: the check of each load is `fibre > max`, with round-off
        let cap = (max_fibre_strain - bending) * (1.0 - 1e-9);
        let highest = self.strain[1].min(cap);
        (highest > self.strain[0]).then_some(Self {
            strain: [self.strain[0], highest],
            ..self
        })
    }

    /// The bending strain |κ| D/2 at the surface of a strand of diameter `outer_diameter_m` at
    /// the range's largest |κ|.
    pub fn largest_bending_strain(&self, outer_diameter_m: f64) -> f64 {
        self.curvature_per_m[0]
            .abs()
            .max(self.curvature_per_m[1].abs())
            * 0.5
            * outer_diameter_m
    }

    /// Whether `inner` lies within `self`.
    pub fn covers(&self, inner: &Self) -> bool {
        self.strain[0] <= inner.strain[0]
            && self.strain[1] >= inner.strain[1]
            && self.curvature_per_m[0] <= inner.curvature_per_m[0]
            && self.curvature_per_m[1] >= inner.curvature_per_m[1]
    }

    /// Whether a calibration over `self` serves every load of `loads` that a calibration over
    /// `calibration` (the range a new one would take: `loads` widened, its strain kept within
    /// the admissible fibre strain) could serve: the loads up to `calibration`'s highest
    /// strain lie within `self`. The loads beyond that strain take the wires beyond their
    /// elastic range and fail under any calibration.
    pub fn serves(&self, loads: &Self, calibration: &Self) -> bool {
        let mut served = *loads;
        served.strain[1] = served.strain[1].min(calibration.strain[1]);
        self.covers(&served)
    }

    /// Checks the bounds: finite, ordered, strain ≥ 0, and a strain range that is not empty
    /// (a calibration needs the tension to vary to separate its effect from the curvature's).
    pub fn validated(self) -> Result<Self, ReducedError> {
        for (field, [lo, hi]) in [
            ("range.strain", self.strain),
            ("range.curvature_per_m", self.curvature_per_m),
        ] {
            if !(lo.is_finite() && hi.is_finite()) {
                return Err(invalid(
                    field,
                    if lo.is_finite() { hi } else { lo },
                    "not finite",
                ));
            }
            if hi <= lo {
                return Err(invalid(
                    field,
                    hi - lo,
                    "the upper bound must exceed the lower",
                ));
            }
        }
        if self.strain[0] < 0.0 {
            return Err(invalid(
                "range.strain",
                self.strain[0],
                "negative: the strand would be in compression",
            ));
        }
        Ok(self)
    }

    /// The sample's first field outside the range widened by `RANGE_SLACK`, if any.
    pub fn check(&self, index: usize, s: &LoadSample) -> Result<(), ReducedError> {
        for (field, value, [lo, hi]) in [
            ("strain", s.strain, self.strain),
            ("curvature_per_m", s.curvature_per_m, self.curvature_per_m),
        ] {
            let slack = RANGE_SLACK * (hi - lo);
            if !(value >= lo - slack && value <= hi + slack) {
                return Err(ReducedError::OutOfRange {
                    index,
                    time_s: s.time_s,
                    field,
                    value,
                    low: lo,
                    high: hi,
                });
            }
        }
        Ok(())
    }
}

/// Affine map of the loads onto the scaled coordinates `x, y ∈ [−1, 1]` of a [`LoadRange`].
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct LoadScaling {
    /// Centre (ε₀, κ₀).
    pub centre: [f64; 2],
    /// Half widths (ε_h, κ_h), > 0.
    pub half: [f64; 2],
}

impl LoadScaling {
    /// The scaling of a validated range.
    pub fn of(range: &LoadRange) -> Self {
        let c = |[lo, hi]: [f64; 2]| (0.5 * (lo + hi), 0.5 * (hi - lo));
        let (e0, eh) = c(range.strain);
        let (k0, kh) = c(range.curvature_per_m);
        Self {
            centre: [e0, k0],
            half: [eh, kh],
        }
    }

    /// Scaled coordinates (x, y) of a load.
    #[inline]
    pub fn scaled(&self, strain: f64, curvature_per_m: f64) -> (f64, f64) {
        (
            (strain - self.centre[0]) / self.half[0],
            (curvature_per_m - self.centre[1]) / self.half[1],
        )
    }

    /// The load (ε, κ) of scaled coordinates (x, y).
    pub fn load(&self, x: f64, y: f64) -> (f64, f64) {
        (
            self.centre[0] + x * self.half[0],
            self.centre[1] + y * self.half[1],
        )
    }
}

/// Number of load features of the force fits.
pub(crate) const FORCE_FEATURES: usize = 6;

/// The quadratic load features `[1, x, y, x y, x², y²]` of the force fits.
#[inline]
pub(crate) fn force_features(x: f64, y: f64) -> [f64; FORCE_FEATURES] {
    [1.0, x, y, x * y, x * x, y * y]
}

fn dot<const N: usize>(a: &[f64; N], b: &[f64; N]) -> f64 {
    a.iter().zip(b).map(|(p, q)| p * q).sum()
}

/// The fitted law of one contact (module docs).
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct ContactLaw {
    /// Coefficients of `f_N` on `force_features` (N).
    pub normal: [f64; FORCE_FEATURES],
    /// Drive coefficients on `fit::drive_features`: hat function k of the tension times `yʲ`
    /// at index `4 k + j` (m), `k` counted from the lowest knot. Stored as a sequence.
    #[serde(with = "drive_sequence")]
    pub drive: [f64; fit::DRIVE_FEATURES],
    /// `[g, r]`: the compliance of the strand at the contact (m/N) and its stick ratio (the
    /// part of the strand's answer in proportion to the contact's elastic slip), both ≥ 0.
    pub compliance: [f64; 2],
}

/// The drive coefficients as a sequence of their count (serde's arrays stop at 32).
mod drive_sequence {
    use super::fit::DRIVE_FEATURES;
    use serde::{de::Error, Deserialize, Deserializer, Serializer};

    pub(super) fn serialize<S: Serializer>(
        drive: &[f64; DRIVE_FEATURES],
        serializer: S,
    ) -> Result<S::Ok, S::Error> {
        serializer.collect_seq(drive)
    }

    pub(super) fn deserialize<'de, D: Deserializer<'de>>(
        deserializer: D,
    ) -> Result<[f64; DRIVE_FEATURES], D::Error> {
        let values = Vec::<f64>::deserialize(deserializer)?;
        let count = values.len();
        values.try_into().map_err(|_| {
            D::Error::custom(format!(
                "drive: {count} coefficients where the law has {DRIVE_FEATURES}"
            ))
        })
    }
}

impl ContactLaw {
    /// Normal force at the features `f` (N, ≥ 0).
    #[inline]
    pub fn normal_force_n(&self, f: &[f64; FORCE_FEATURES]) -> f64 {
        dot(&self.normal, f).max(0.0)
    }

    /// Drive `d` at scaled loads (x, y) (m).
    #[inline]
    pub(crate) fn drive_m(&self, x: f64, y: f64) -> f64 {
        fit::drive_dot(&self.drive, x, y)
    }

    /// Compliance `g` (m/N, ≥ 0).
    #[inline]
    pub(crate) fn compliance_m_per_n(&self) -> f64 {
        self.compliance[0].max(0.0)
    }

    /// Stick ratio `r` (≥ 0).
    #[inline]
    pub(crate) fn stick_ratio(&self) -> f64 {
        self.compliance[1].max(0.0)
    }
}

/// The state of one contact's Jenkins element: its irreversible slip.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct JenkinsState {
    /// Irreversible slip `s_p` (m).
    pub plastic_slip_m: f64,
}

impl JenkinsState {
    /// The state in which the contact carries no tangential force under drive `d`.
    pub(crate) fn unloaded(drive_m: f64) -> Self {
        Self {
            plastic_slip_m: drive_m,
        }
    }

    /// Advances to drive `d` and normal force `f_N`: returns (slip, tangential force).
    /// `stick_per_n = μ / γ_e` (1/m), `elastic_slip_m = γ_e`, `g` the compliance, `r` the
    /// stick ratio.
    #[inline]
    pub(crate) fn step(
        &mut self,
        drive_m: f64,
        normal_force_n: f64,
        compliance_m_per_n: f64,
        stick_ratio: f64,
        stick_per_m: f64,
        elastic_slip_m: f64,
    ) -> (f64, f64) {
        let (k, factor) =
            slide_factor(normal_force_n, compliance_m_per_n, stick_ratio, stick_per_m);
        self.step_factored(drive_m, normal_force_n, k, factor, elastic_slip_m)
    }

    /// [`Self::step`] with the contact's stiffness `k` and [`slide_factor`] given.
    #[inline]
    pub(crate) fn step_factored(
        &mut self,
        drive_m: f64,
        normal_force_n: f64,
        k: f64,
        factor: f64,
        elastic_slip_m: f64,
    ) -> (f64, f64) {
        if normal_force_n <= 0.0 {
            // an open contact carries nothing and forgets its elastic slip, as the FE
            // element's history does: it closes again unloaded where it is
            self.plastic_slip_m = drive_m;
            return (drive_m, 0.0);
        }
        let elastic = self.advance(drive_m, factor, elastic_slip_m);
        (elastic + self.plastic_slip_m, k * elastic)
    }

    /// Advances a closed contact to drive `d`, `factor` its [`slide_factor`]: returns the
    /// elastic slip.
    #[inline]
    pub(crate) fn advance(&mut self, drive_m: f64, factor: f64, elastic_slip_m: f64) -> f64 {
        let mut elastic = (drive_m - self.plastic_slip_m) / factor;
        if elastic.abs() > elastic_slip_m {
            elastic = elastic_slip_m.copysign(elastic);
            self.plastic_slip_m = drive_m - elastic * factor;
        }
        elastic
    }
}

/// A closed contact's tangential stiffness `k = μ f_N / γ_e` and the ratio `1 + g k + r` of the
/// rate at which it slides to the rate at which it sticks, for normal force `f_N`,
/// compliance `g`, stick ratio `r` and `stick_per_m = μ / γ_e`.
#[inline]
pub(crate) fn slide_factor(
    normal_force_n: f64,
    compliance_m_per_n: f64,
    stick_ratio: f64,
    stick_per_m: f64,
) -> (f64, f64) {
    let k = stick_per_m * normal_force_n;
    (k, 1.0 + compliance_m_per_n * k + stick_ratio)
}

/// In-sample quality of one layer interface's fit on the calibration run.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct InterfaceFit {
    /// Layer interface.
    pub interface: usize,
    /// Contacts.
    pub contacts: usize,
    /// Root mean square of the residual of the slip increments in the least-squares fit over
    /// the interface's contacts and samples, weighted as the fit (m).
    pub slip_rms_residual_m: f64,
    /// Root mean square of the slip increments about each contact's mean increment (m), the
    /// scale of the residual.
    pub slip_rms_m: f64,
    /// Root mean square of the normal-force residual (N).
    pub normal_rms_residual_n: f64,
    /// Root mean square of the normal force about each contact's mean (N).
    pub normal_rms_n: f64,
    /// Contacts whose stick ratio, or compliance and stick ratio, were refitted at zero (the free
    /// fit made one of them negative).
    pub compliance_clamped: usize,
}

/// How the calibration went: what it ran and how well the reduced model reproduces its own
/// calibration run (in-sample; the held-out error is measured separately).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct CalibrationReport {
    /// Samples of the designed history, all chains.
    pub design_samples: usize,
    /// FE sub-steps solved, all chains (initialisations included).
    pub fe_substeps: usize,
    /// Newton iterations of the FE runs, all chains.
    pub fe_iterations: usize,
    /// Wall time of the calibration: the FE runs, side by side, and the fit (s).
    pub fe_wall_time_s: f64,
    /// What each chain of the design cost ([`design`] module docs), in chain order.
    #[serde(default)]
    pub chains: Vec<ChainCost>,
    /// Wall time from the calibration's start until the interfaces' collective modes were
    /// measured, beside the first chains (s; part of `fe_wall_time_s`).
    #[serde(default)]
    pub modes_wall_time_s: f64,
    /// Least-squares fits per interface.
    pub fits: Vec<InterfaceFit>,
    /// The designed history replayed through the reduced model against the FE run.
    pub replay: Vec<compare::InterfaceComparison>,
}

/// The FE run of one chain of the calibration's design.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct ChainCost {
    /// Designed samples.
    pub samples: usize,
    /// FE sub-steps solved (initialisation included).
    pub substeps: usize,
    /// Newton iterations.
    pub iterations: usize,
    /// Wall time (s).
    pub wall_time_s: f64,
}

/// A reduced strand response: the fitted laws of every contact of one FE model, the range they
/// were calibrated over and the monitor channels (module docs).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct ReducedStrand {
    /// `FORMAT_VERSION` of the stored calibration.
    pub format: u32,
    /// Content address of the FE model and settings it was calibrated on, set by the caller
    /// (empty if none): a stored calibration is used only on the model of the same key.
    #[serde(default)]
    pub model_key: String,
    /// Coulomb friction coefficient μ of the model's contacts.
    pub friction_coefficient: f64,
    /// Elastic slip γ_e of the model's tangential law (m).
    pub elastic_slip_m: f64,
    /// Fraction of the first tension at which the FE initialisation bends the strand
    /// (`HistoryOptions::initial_strain_fraction` of the calibration): the reduced run starts
    /// along the same path.
    pub initial_strain_fraction: f64,
    /// Calibrated load range.
    pub range: LoadRange,
    /// Scaling of the loads used by the fits.
    pub scaling: LoadScaling,
    /// Where every contact sits, mesh contact order.
    pub sites: Vec<ContactSite>,
    /// Fitted law of every contact, mesh contact order.
    pub laws: Vec<ContactLaw>,
    /// Monitor channels of the FE run (no values).
    pub channels: Vec<MonitorChannel>,
    /// Fitted axial force of every wire-element channel, in channel order (contact channels
    /// skipped), on `force_features` (N).
    pub element_fits: Vec<[f64; FORCE_FEATURES]>,
    /// How the calibration went.
    pub calibration: CalibrationReport,
    /// Collective modes of the layer interfaces ([`ModeCoupling`]); none: every contact
    /// answers alone.
    #[serde(default)]
    pub modes: Option<ModeCoupling>,
    /// With the FE model's Cattaneo–Mindlin law: every contact's initial tangential stiffness
    /// k₀(f_N), mesh contact order, and the contacts are Iwan banks ([`iwan`]); none: the
    /// elastic-slip law of `elastic_slip_m` (one Jenkins element per contact).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub cattaneo_mindlin: Option<Vec<iwan::InitialStiffness>>,
}

/// Number of collective modes of a layer interface: its contacts' irreversible slips uniform,
/// and in proportion to cos θ and sin θ of their angle from the neutral axis.
pub(crate) const MODES: usize = 3;

/// The shapes of the collective modes at angle `theta_rad` from the neutral axis.
#[inline]
pub(crate) fn mode_shapes(theta_rad: f64) -> [f64; MODES] {
    [1.0, theta_rad.cos(), theta_rad.sin()]
}

/// The collective answer of the layer interfaces to their contacts' sliding: a pattern of
/// irreversible slip over an interface moves the layers themselves, so every contact of
/// interface `I` slips by `Σ_J Σ_m a[I][J][m] ψ_m(θ) q_{J,m}` on top of its own answer, with
/// `q_{J,m}` the projection of interface `J`'s irreversible slips on mode `m`
/// ([`mode_shapes`]). Measured on the FE model by imposing each pattern on every contact of
/// an interface at once, at a few tensions; linear in the scaled tension between them.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct ModeCoupling {
    /// Scaled tensions of the measurements, increasing.
    pub knots: Vec<f64>,
    /// `amplification[k][I][J][m]` at knot `k` (dimensionless).
    pub amplification: Vec<Vec<Vec<[f64; MODES]>>>,
}

/// The number of layer interfaces of the contacts at `sites`.
fn interface_count(sites: &[ContactSite]) -> usize {
    sites.iter().map(|s| s.interface + 1).max().unwrap_or(0)
}

impl ModeCoupling {
    /// Checks a stored coupling against the model's `interfaces`: knots finite and increasing,
    /// one square table per knot, amplifications finite, and every interface's own below one
    /// (a mode that answered its own slip whole would be a mechanism).
    fn check(&self, interfaces: usize) -> Result<(), ReducedError> {
        let bad = |reason: String| ReducedError::Calibration { reason };
        if self.knots.is_empty() || self.knots.len() != self.amplification.len() {
            return Err(bad(format!(
                "modes: {} knots for {} amplification tables",
                self.knots.len(),
                self.amplification.len()
            )));
        }
        if !self.knots.iter().all(|k| k.is_finite()) || self.knots.windows(2).any(|w| w[1] <= w[0])
        {
            return Err(bad("modes: the knots must be finite and increase".into()));
        }
        for (k, table) in self.amplification.iter().enumerate() {
            if table.len() != interfaces || table.iter().any(|row| row.len() != interfaces) {
                return Err(bad(format!(
                    "modes: the table at knot {k} is not {interfaces} × {interfaces}"
                )));
            }
            for (i, row) in table.iter().enumerate() {
                for (j, a) in row.iter().enumerate() {
                    if a.iter().any(|v| !v.is_finite())
                        || (i == j && a.iter().any(|v| v.abs() >= 1.0))
                    {
                        return Err(bad(format!(
                            "modes: amplification of interface {i} by {j} at knot {k} is {a:?}: \
                             not finite, or an own amplification of 1 or more"
                        )));
                    }
                }
            }
        }
        Ok(())
    }

    /// Number of interfaces.
    pub(crate) fn interfaces(&self) -> usize {
        self.amplification.first().map_or(0, Vec::len)
    }

    /// `a[I][J][m]` at scaled tension `x`, flattened as `(I · n + J) · MODES + m`.
    pub(crate) fn at(&self, x: f64, out: &mut Vec<f64>) {
        let n = self.interfaces();
        out.clear();
        out.resize(n * n * MODES, 0.0);
        let k = &self.knots;
        if k.is_empty() {
            return;
        }
        let (i, t) = if x <= k[0] || k.len() == 1 {
            (0, 0.0)
        } else if x >= k[k.len() - 1] {
            (k.len() - 2, 1.0)
        } else {
            let i = k.iter().take_while(|&&v| v <= x).count() - 1;
            (i, (x - k[i]) / (k[i + 1] - k[i]))
        };
        let j = (i + 1).min(k.len() - 1);
        for a in 0..n {
            for b in 0..n {
                for m in 0..MODES {
                    let lo = self.amplification[i][a][b][m];
                    let hi = self.amplification[j][a][b][m];
                    out[(a * n + b) * MODES + m] = lo + t * (hi - lo);
                }
            }
        }
    }
}

impl ReducedStrand {
    /// The lowest strain its calibration's design visited: below it the fitted laws are
    /// continued (the drive held at its lowest fitted knot, the normal forces' quadratics
    /// clipped at zero). Under the Cattaneo–Mindlin law the design stops at the strokes' floor
    /// ([`design::LowestTension::StrokeFloor`]).
    pub fn lowest_designed_strain(&self) -> f64 {
        design::LowestTension::of_law(self.cattaneo_mindlin.is_some()).strain(&self.range)
    }

    /// A stored calibration read from its JSON and checked ([`ReducedStrand::validated`]); a
    /// file of another format is refused as such before its fields are read (their shapes
    /// change between formats).
    pub fn from_json(text: &[u8]) -> Result<Self, ReducedError> {
        #[derive(Deserialize)]
        struct Header {
            format: u32,
        }
        let bad = |e: serde_json::Error| ReducedError::Calibration {
            reason: format!("not a reduced strand calibration: {e}"),
        };
        let header: Header = serde_json::from_slice(text).map_err(bad)?;
        if header.format != FORMAT_VERSION {
            return Err(ReducedError::Calibration {
                reason: format!(
                    "format {} is not the supported {FORMAT_VERSION}; calibrate again",
                    header.format
                ),
            });
        }
        serde_json::from_slice::<Self>(text)
            .map_err(bad)?
            .validated()
    }

    /// Checks what a stored calibration must hold before use: its format, one law per site,
    /// finite parameters.
    pub fn validated(self) -> Result<Self, ReducedError> {
        if self.format != FORMAT_VERSION {
            return Err(ReducedError::Calibration {
                reason: format!(
                    "format {} is not the supported {FORMAT_VERSION}; calibrate again",
                    self.format
                ),
            });
        }
        if self.laws.len() != self.sites.len() {
            return Err(ReducedError::Calibration {
                reason: format!(
                    "{} contact laws for {} contacts",
                    self.laws.len(),
                    self.sites.len()
                ),
            });
        }
        let range = self.range.validated()?;
        let mu = self.friction_coefficient;
        if !(mu.is_finite() && mu >= 0.0) {
            return Err(invalid(
                "friction_coefficient",
                mu,
                "must be finite and ≥ 0",
            ));
        }
        match &self.cattaneo_mindlin {
            None => {
                let ge = self.elastic_slip_m;
                if !(ge.is_finite() && ge > 0.0) {
                    return Err(invalid("elastic_slip_m", ge, "must be finite and > 0"));
                }
            }
            Some(stiffness) => {
                if stiffness.len() != self.sites.len() {
                    return Err(ReducedError::Calibration {
                        reason: format!(
                            "cattaneo_mindlin: {} initial stiffnesses for {} contacts",
                            stiffness.len(),
                            self.sites.len()
                        ),
                    });
                }
                if let Some(c) = stiffness.iter().position(|k| !k.is_valid()) {
                    return Err(ReducedError::Calibration {
                        reason: format!(
                            "cattaneo_mindlin: contact {c}: the initial stiffness's \
                             coefficients must be finite and > 0"
                        ),
                    });
                }
            }
        }
        let f = self.initial_strain_fraction;
        if !(f > 0.0 && f <= 1.0) {
            return Err(invalid("initial_strain_fraction", f, "must lie in (0, 1]"));
        }
        if let Some(m) = &self.modes {
            m.check(interface_count(&self.sites))?;
        }
        for (c, law) in self.laws.iter().enumerate() {
            let finite = law
                .normal
                .iter()
                .chain(&law.drive)
                .chain(&law.compliance)
                .all(|v| v.is_finite());
            if !finite {
                return Err(ReducedError::Calibration {
                    reason: format!("contact {c}: a fitted coefficient is not finite or g < 0"),
                });
            }
        }
        Ok(Self { range, ..self })
    }
}

#[cfg(test)]
mod tests;
