//! A strand model driven through a load history (the paper's Sec. 3.3; `docs/strand-runs.md`).
//!
//! [`run_history`] takes samples (t, ε, κ) of the hot spot's imposed axial strain and curvature
//! and:
//! 1. validates them ([`validate_samples`]: finite, increasing time, ε ≥ 0, and a fibre strain
//!    ε + |κ| D/2 at the strand's outer surface within [`HistoryOptions::max_fibre_strain`]),
//!    refusing the first bad sample with its index;
//! 2. initialises as the paper's Sec. 3.3, in three steps that limit the initial contact forces:
//!    a small tension ε_s = `initial_strain_fraction` · ε₀, then ε_s with the initial curvature
//!    κ₀, then (ε₀, κ₀);
//! 3. reduces the history to its turning points within `turning_point_tolerance` ([`reduce`])
//!    and follows the straight (ε, κ) segments between them in sub-steps no larger than
//!    `max_substep_strain` / `max_substep_curvature_per_m`, each solved by the Newton driver with
//!    its own cut-back ([`crate::linalg::solve_load_path`]);
//! 4. maps the results back onto the original time axis: every original sample gets its
//!    position along its segment and the contact samples and monitors are interpolated linearly
//!    between the sub-step results;
//! 5. feeds every contact's (slip, f_N, f_T) sample by sample to its streaming rainflow counter
//!    ([`crate::fretting::ContactCycleAccumulator`]), so no full-field time series is stored, and
//!    returns one [`ContactRecord`] per contact (residue counted as half cycles) with the monitor
//!    series ([`monitors`], slip convention there) and the work statistics.
//!
//! The tension history of a mooring line becomes a strain history through ε = T / EA with EA
//! measured on the model itself ([`stiffness::measure_axial_stiffness_n`],
//! [`stiffness::samples_from_tension`]). Units: s, m, 1/m, N.

pub mod checkpoint;
pub mod monitors;
pub mod reduce;
pub mod stiffness;
pub mod timing;

use serde::{Deserialize, Serialize};

use self::monitors::MonitorSeries;
use super::loading::{LoadPath, SectionMotion};
use super::model::StrandModel;
use super::problem::StrandProblem;
use crate::beam::frame::FrameError;
use crate::fretting::{ContactRecord, ContactSample, FrettingError};
use crate::linalg::newton::NewtonParamError;
use crate::linalg::{
    FactorPrecision, LinalgError, NewtonError, NewtonParams, NewtonStats, SplitStats,
};

/// One sample of the imposed history.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct LoadSample {
    /// Time (s).
    pub time_s: f64,
    /// Axial strain ε of the strand axis.
    pub strain: f64,
    /// Curvature κ about the fixed bending axis (1/m).
    pub curvature_per_m: f64,
}

impl LoadSample {
    /// Bending strain |κ| D/2 at the surface of a strand of diameter `outer_diameter_m`: with
    /// the axial strain, the fibre strain every history run holds within
    /// [`HistoryOptions::max_fibre_strain`].
    pub fn bending_strain(&self, outer_diameter_m: f64) -> f64 {
        self.curvature_per_m.abs() * (0.5 * outer_diameter_m)
    }
}

/// Errors of a history run.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum HistoryError {
    /// A history sample is refused.
    #[error("load history sample {index} (t = {time_s} s): {field} = {value}: {reason}")]
    InvalidSample {
        /// Sample index.
        index: usize,
        /// Its time (s).
        time_s: f64,
        /// Offending field.
        field: &'static str,
        /// Its value.
        value: f64,
        /// Why.
        reason: String,
    },
    /// An option is out of range.
    #[error("history option {field} = {value}: {reason}")]
    InvalidOption {
        /// Field.
        field: &'static str,
        /// Value.
        value: f64,
        /// Why.
        reason: String,
    },
    /// Invalid Newton settings.
    #[error(transparent)]
    Newton(#[from] NewtonParamError),
    /// Symbolic analysis of the pattern failed.
    #[error(transparent)]
    Linear(#[from] LinalgError),
    /// A load step failed after all cut-backs.
    #[error(
        "{stage}: step towards sample {sample} (t = {time_s} s), sub-step {substep}/{substeps} \
         from (ε = {from_strain:e}, κ = {from_curvature:e} 1/m) to (ε = {to_strain:e}, \
         κ = {to_curvature:e} 1/m): {source}"
    )]
    Step {
        /// "initialisation 1/3" … or "history".
        stage: &'static str,
        /// Sample the segment leads to.
        sample: usize,
        /// Its time (s).
        time_s: f64,
        /// Sub-step (1-based) and their number.
        substep: usize,
        /// Number of sub-steps of the segment.
        substeps: usize,
        /// Start of the sub-step.
        from_strain: f64,
        /// Start of the sub-step (1/m).
        from_curvature: f64,
        /// Target of the sub-step.
        to_strain: f64,
        /// Target of the sub-step (1/m).
        to_curvature: f64,
        /// Driver error (step, iteration, residual, load factor).
        source: Box<NewtonError<FrameError>>,
    },
    /// An element could not be evaluated while extracting results.
    #[error(transparent)]
    Frame(#[from] FrameError),
    /// A checkpoint cannot be written, read or used.
    #[error("history checkpoint: {reason}")]
    Checkpoint {
        /// Why.
        reason: String,
    },
    /// The observer asked to stop; the last checkpoint resumes the run.
    #[error("history run stopped on request after segment {segment} (t = {time_s} s)")]
    Stopped {
        /// Segments done.
        segment: usize,
        /// Time reached (s).
        time_s: f64,
    },
    /// The rainflow counter of a contact refused a sample.
    #[error("contact {contact}: {source}")]
    Fretting {
        /// Contact index.
        contact: usize,
        /// Cause.
        source: FrettingError,
    },
}

/// Settings of a history run.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct HistoryOptions {
    /// Turning-point tolerance as a fraction of each channel's range ([`reduce`]); 0 keeps
    /// every sample off the chords.
    pub turning_point_tolerance: f64,
    /// Lower bounds (strain, curvature in 1/m) of the channel scales the turning-point
    /// tolerance is a fraction of ([`reduce::reduce_history_on_scale`]); 0: each channel's range.
    pub turning_point_scale: [f64; 2],
    /// Largest strain change of one sub-step.
    pub max_substep_strain: f64,
    /// Largest curvature change of one sub-step (1/m).
    pub max_substep_curvature_per_m: f64,
    /// Newton settings of each sub-step (Δλ as a fraction of the sub-step).
    pub newton: NewtonParams,
    /// Hysteresis gate of the slip rainflow counters (m).
    pub slip_gate_m: f64,
    /// Small tension of the initialisation as a fraction of the first sample's strain, (0, 1].
    pub initial_strain_fraction: f64,
    /// Largest admissible fibre strain ε + |κ| D/2 at the strand's outer surface.
    pub max_fibre_strain: f64,
    /// Record the default monitors ([`monitors`]).
    pub default_monitors: bool,
    /// Hand a checkpoint to the observer every this many segments (0: never).
    pub checkpoint_interval_segments: usize,
    /// Pseudo-transient shift of the Newton iterations of the first initialisation stage (small
    /// tension from the reference state) and of the axial stiffness measurement
    /// ([`NewtonParams::pseudo_transient_shift`]; `newton`'s applies to everything else).
    pub initialisation_shift: f64,
    /// Threads of the element work (beams and contacts; the same results to the bit) and of the
    /// LDLᵀ factorisation of the linear solver (1: sequential; the same results to round-off).
    pub threads: usize,
    /// Precision in which the LDLᵀ preconditioner of the GMRES solves is applied
    /// ([`crate::linalg::SupernodalSolve`]).
    pub preconditioner_precision: FactorPrecision,
    /// Whether each sub-step starts from an earlier sub-step's wire motion beyond the plane
    /// sections, scaled by the share of its load change the new one repeats: a segment's first
    /// sub-step from the last segment's first one (mirrored after a turning point), a later
    /// sub-step from the one before it. `None`: under the contact-mechanics tangential laws
    /// only ([`StrandModel::predicts_from_last_segment`]).
    pub segment_predictor: Option<bool>,
    /// Stiffness along the sliding direction that the Newton iteration matrix gives every
    /// Cattaneo–Mindlin contact in gross slip at a step's first correction, as a fraction of
    /// its k₀, a quarter of it at each further correction; the residual and so the converged
    /// state are unchanged (`StrandProblem::with_sliding_stiffness`). 0: the consistent
    /// tangent. The other tangential laws ignore it. Default 0.1.
    pub sliding_stiffness: f64,
}

impl Default for HistoryOptions {
    fn default() -> Self {
        Self {
            // six-layer strand, 100 s of the severe sea state's hot spot (t = 150-250 s, the
            // largest curvature cycles): against 0.001, every interface's largest slip range,
            // accumulated slip Σ n Δs and count of cycles above 1 µm within 0.43 % at 0.0025,
            // but accumulated slip off by up to 2.0 % and counts by up to 3.1 % at 0.005
            // (studies/src/bin/strand_history_tolerance.rs, README "Strand runs")
            turning_point_tolerance: 0.0025,
            turning_point_scale: [0.0; 2],
            max_substep_strain: 5e-4,
            max_substep_curvature_per_m: 5e-3,
            newton: NewtonParams {
                max_iterations: 30,
                easy_iterations: 8,
                relative_tolerance: 1e-6,
                // 1e-2 N: below 1e-5 of the wire forces (kN) and, through the tangential
                // stiffness μ f_N / γ_e of loaded contacts, below 1e-9 m of slip; above the
                // round-off floor of the residual set by the stiff end conditions, which the
                // relative test cannot reach at the small initial tension
                absolute_tolerance: 1e-2,
                energy_tolerance: 1e-16,
                max_load_increment: 1.0,
                initial_load_increment: 1.0,
                min_load_increment: 1e-4,
                // backtracking breaks the two-cycles of full Newton steps in which slip directions
                // turn (1+6+1 strand at κ = 1 1/m: one step instead of ~1 500)
                line_search_trials: 8,
                // no shift in the history sub-steps: there the contacts are loaded and the
                // shift only slows the convergence down (six-layer strand: 2-3 iterations per
                // sub-step without it, 6-7 with 0.01; the initialisation has its own, below)
                pseudo_transient_shift: 0.0,
                // GMRES to 1e-2 of the residual at first, tighter as it falls: the same
                // Newton iteration counts with fewer Krylov iterations (six-layer history
                // sub-steps 5.2 s instead of 8.7 s, studies/src/bin/strand_six_layer.rs)
                linear_forcing: 0.01,
                ..NewtonParams::default()
            },
            // two orders of magnitude below the micrometre slips of interest (the paper's Fig. 22)
            slip_gate_m: 1e-8,
            initial_strain_fraction: 0.1,
            // 0.8 × 1770 MPa / 200 GPa: proportional limit of grade-1770 rope wire (EN 10264-2)
            max_fibre_strain: 7e-3,
            default_monitors: true,
            checkpoint_interval_segments: 0,
            // the initialisation starts from contacts that carry almost no normal force: the
            // first corrections run along nearly free wire motions, and the six-layer tension
            // step with ε_N = 2e8 N/m stalls in line-search cuts without the shift; with 0.1
            // its first stage converges in 22 iterations, with 0.01 in 11-13
            // (studies/src/bin/strand_six_layer.rs)
            initialisation_shift: 0.01,
            threads: 1,
            // the six-layer strand's preconditioner solves in f32 take half the time and the
            // GMRES iterations do not change (2 706 against 2 707 over 100 s of the showcase
            // load; studies/src/bin/strand_history_tolerance.rs, README "Strand solver")
            preconditioner_precision: FactorPrecision::Single,
            segment_predictor: None,
            // the 1 000 s showcase in 2 171 s against the consistent tangent's 2 954 s (Newton
            // iterations 6 310 against 7 362, cut-backs 5 against 24), the largest slip ranges
            // per interface within 0.08 %; bending cycles of the 1+6+1 strand in gross slip
            // cost 8-28 % more iterations
            // (docs/notes/2026-12-06-newton-stalls-under-cattaneo-mindlin.md)
            sliding_stiffness: 0.1,
        }
    }
}

impl HistoryOptions {
    /// The Newton settings of the initialisation and of the axial stiffness measurement:
    /// `newton` with the initialisation's pseudo-transient shift.
    pub fn initialisation_newton(&self) -> NewtonParams {
        NewtonParams {
            pseudo_transient_shift: self.initialisation_shift,
            ..self.newton
        }
    }

    /// Checks every field.
    pub fn validated(self) -> Result<Self, HistoryError> {
        let check = |ok: bool, field: &'static str, value: f64, reason: &str| {
            if ok {
                Ok(())
            } else {
                Err(HistoryError::InvalidOption {
                    field,
                    value,
                    reason: reason.to_string(),
                })
            }
        };
        let t = self.turning_point_tolerance;
        check(
            (0.0..1.0).contains(&t),
            "turning_point_tolerance",
            t,
            "must lie in [0, 1)",
        )?;
        for (field, v) in [
            ("turning_point_scale.strain", self.turning_point_scale[0]),
            (
                "turning_point_scale.curvature_per_m",
                self.turning_point_scale[1],
            ),
        ] {
            check(
                v >= 0.0 && v.is_finite(),
                field,
                v,
                "must be finite and ≥ 0",
            )?;
        }
        let (de, dk) = (self.max_substep_strain, self.max_substep_curvature_per_m);
        check(
            de > 0.0 && de.is_finite(),
            "max_substep_strain",
            de,
            "must be finite and > 0",
        )?;
        check(
            dk > 0.0 && dk.is_finite(),
            "max_substep_curvature_per_m",
            dk,
            "must be finite and > 0",
        )?;
        let g = self.slip_gate_m;
        check(
            g >= 0.0 && g.is_finite(),
            "slip_gate_m",
            g,
            "must be finite and ≥ 0",
        )?;
        let f = self.initial_strain_fraction;
        check(
            f > 0.0 && f <= 1.0,
            "initial_strain_fraction",
            f,
            "must lie in (0, 1]",
        )?;
        let m = self.max_fibre_strain;
        check(
            m > 0.0 && m.is_finite(),
            "max_fibre_strain",
            m,
            "must be finite and > 0",
        )?;
        check(
            self.initialisation_shift >= 0.0 && self.initialisation_shift.is_finite(),
            "initialisation_shift",
            self.initialisation_shift,
            "must be finite and ≥ 0",
        )?;
        check(
            self.sliding_stiffness >= 0.0 && self.sliding_stiffness.is_finite(),
            "sliding_stiffness",
            self.sliding_stiffness,
            "must be finite and ≥ 0",
        )?;
        check(
            self.threads >= 1,
            "threads",
            self.threads as f64,
            "must be ≥ 1",
        )?;
        self.newton.validated()?;
        Ok(self)
    }
}

/// Progress of a run, reported after every segment.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct HistoryProgress {
    /// Segments done.
    pub segment: usize,
    /// Segments in all.
    pub segments: usize,
    /// Last original sample covered.
    pub sample: usize,
    /// Its time (s).
    pub time_s: f64,
    /// Wall time since the start (s).
    pub elapsed_s: f64,
}

/// Receives progress reports and checkpoints of a run, and may stop it.
pub trait HistoryObserver {
    /// Called after every segment; the default does nothing.
    fn progress(&mut self, _progress: &HistoryProgress) {}

    /// Called every [`HistoryOptions::checkpoint_interval_segments`] segments with the complete
    /// state; the default drops it.
    fn checkpoint(&mut self, _checkpoint: &checkpoint::HistoryCheckpoint) {}

    /// Called with the solved (or interpolated) state of every original sample, in order: the
    /// sample, every contact's (slip, f_N, f_T) in mesh contact order, and the wire-element
    /// monitor values (monitor channel order, contact channels skipped). The default does
    /// nothing; the reduced strand's calibration ([`crate::strand::reduced`]) learns from it.
    fn sample(&mut self, _sample: &LoadSample, _contacts: &[ContactSample], _elements: &[f64]) {}

    /// Asked after every segment (after the checkpoint, if any); `true` ends the run with
    /// [`HistoryError::Stopped`]. The default never stops.
    fn should_stop(&mut self) -> bool {
        false
    }
}

/// An observer that ignores everything.
#[derive(Clone, Copy, Debug, Default)]
pub struct NoObserver;

impl HistoryObserver for NoObserver {}

/// Work counts and wall times of a history run.
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct HistoryStats {
    /// Original samples.
    pub samples: usize,
    /// Samples kept by the turning-point reduction.
    pub kept_samples: usize,
    /// Solved sub-steps (initialisation included).
    pub substeps: usize,
    /// Accepted Newton load steps.
    pub newton_steps: usize,
    /// Rejected attempts (cut-backs).
    pub cutbacks: usize,
    /// Newton iterations (linear solves).
    pub iterations: usize,
    /// Numeric factorisations.
    pub factorisations: usize,
    /// Residual evaluations.
    pub evaluations: usize,
    /// Wall time of the initialisation (s).
    pub initialisation_time_s: f64,
    /// Sub-steps of the initialisation (included in `substeps`).
    #[serde(default)]
    pub initialisation_substeps: usize,
    /// The initialisation's share of the counts above (included in them): what the history
    /// alone cost is the difference.
    #[serde(default)]
    pub initialisation: InitialisationCounts,
    /// Wall time of the Newton solves of the history (s).
    pub solve_time_s: f64,
    /// Wall time of result extraction, interpolation and rainflow counting (s).
    pub output_time_s: f64,
    /// Total wall time (s).
    pub total_time_s: f64,
    /// Split of the Newton work: assembly, factorisation, solves (s).
    pub work: timing::WorkTimes,
    /// Work of the linear solver: GMRES solves and iterations, LDLᵀ factorisations of the
    /// preconditioner, reuses of an earlier one, refreshes, LU fallbacks.
    #[serde(default)]
    pub linear: SplitStats,
}

/// Work counts of a history run's initialisation ([`HistoryStats::initialisation`]).
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct InitialisationCounts {
    /// Accepted Newton load steps.
    pub newton_steps: usize,
    /// Rejected attempts (cut-backs).
    pub cutbacks: usize,
    /// Newton iterations (linear solves).
    pub iterations: usize,
    /// Residual evaluations.
    pub evaluations: usize,
    /// Work of the linear solver.
    pub linear: SplitStats,
}

impl HistoryStats {
    /// The counts so far as the initialisation's.
    fn initialisation_counts(&self) -> InitialisationCounts {
        InitialisationCounts {
            newton_steps: self.newton_steps,
            cutbacks: self.cutbacks,
            iterations: self.iterations,
            evaluations: self.evaluations,
            linear: self.linear,
        }
    }

    fn add(&mut self, s: &NewtonStats) {
        self.substeps += 1;
        self.newton_steps += s.steps;
        self.cutbacks += s.cutbacks;
        self.iterations += s.iterations;
        self.factorisations += s.factorisations;
        self.evaluations += s.evaluations;
    }
}

/// Result of a history run.
#[derive(Clone, Debug, PartialEq)]
pub struct HistoryResult {
    /// One record per contact, mesh contact order.
    pub contacts: Vec<ContactRecord>,
    /// Monitor series on the original time axis.
    pub monitors: MonitorSeries,
    /// Indices of the samples the solver visited.
    pub kept_samples: Vec<usize>,
    /// Work counts and timings.
    pub stats: HistoryStats,
}

/// Checks every sample (module docs); the first bad one is reported with its index.
pub fn validate_samples(
    model: &StrandModel,
    samples: &[LoadSample],
    options: &HistoryOptions,
) -> Result<(), HistoryError> {
    let diameter_m = model.strand.outer_diameter_m();
    let mut previous = f64::NEG_INFINITY;
    for (index, s) in samples.iter().enumerate() {
        let bad = |field, value, reason: String| HistoryError::InvalidSample {
            index,
            time_s: s.time_s,
            field,
            value,
            reason,
        };
        for (field, v) in [
            ("time_s", s.time_s),
            ("strain", s.strain),
            ("curvature_per_m", s.curvature_per_m),
        ] {
            if !v.is_finite() {
                return Err(bad(field, v, "not a finite number".into()));
            }
        }
        if s.time_s <= previous {
            return Err(bad(
                "time_s",
                s.time_s,
                "times must increase strictly".into(),
            ));
        }
        previous = s.time_s;
        if s.strain < 0.0 {
            return Err(bad(
                "strain",
                s.strain,
                "negative: the strand would be in compression".into(),
            ));
        }
        let bending = s.bending_strain(diameter_m);
        let fibre = s.strain + bending;
        if fibre > options.max_fibre_strain {
            // Blamed on the larger of the two parts.
            let (field, value) = if s.strain >= bending {
                ("strain", s.strain)
            } else {
                ("curvature_per_m", s.curvature_per_m)
            };
            return Err(bad(
                field,
                value,
                format!(
                    "fibre strain ε + |κ| D/2 = {fibre:.3e} at the strand surface exceeds the \
                     admissible {:.3e}",
                    options.max_fibre_strain
                ),
            ));
        }
    }
    Ok(())
}

mod recording;
mod run;

pub use run::{run_history, run_history_from};

/// The section motion of a sample.
fn motion_of(s: &LoadSample) -> SectionMotion {
    SectionMotion {
        strain: s.strain,
        curvature_per_m: s.curvature_per_m,
    }
}

/// Empty problem of `model` in the reference configuration, its element work on `threads`
/// threads.
fn reference_problem(
    model: &StrandModel,
    threads: usize,
) -> Result<StrandProblem<'_>, HistoryError> {
    StrandProblem::new(model, LoadPath::default())
        .with_threads(threads)
        .map_err(|e| HistoryError::InvalidOption {
            field: "threads",
            value: threads as f64,
            reason: format!("no thread pool: {e}"),
        })
}

#[cfg(test)]
mod tests;
