//! The campaign file (`docs/campaign-files.md`): one JSON document that fully defines a campaign.
//!
//! serde with `deny_unknown_fields` everywhere and units in the field names. Referenced files
//! (scatter diagram, global base case, strand profiles) are paths relative to the campaign
//! file; [`super::resolve`] reads and hashes them. [`CampaignSpec::validate`] checks every value
//! and names the first offending one by its path (`simulation.duration_s must be > 0 (got -1)`).
//!
//! Shape:
//! ```json
//! { "name": "demo", "design_life_years": 25, "seed": 7,
//!   "scatter": {"path": "data/wsd.tsv", "reading": "joint_percent"},
//!   "global": {"case_path": "paper_case.json"},
//!   "simulation": {"transient_s": 50, "duration_s": 1000, "time_step_s": 0.1,
//!                  "output_interval_s": 0.1, "seeds_per_sea_state": 1, "gamma": 1.3},
//!   "hot_spots": [{"line": 1, "arc_length_m": 79}],
//!   "strand": {"profiles_path": "data/strand_profiles.json", "profile": "paper_six_layer"},
//!   "fatigue": {"run_in_s": 100} }
//! ```

use moorfret_solver::global::case::{GammaSpec, WindSpec};
use moorfret_solver::strand::history::{HistoryError, HistoryOptions};
use moorfret_solver::text::Num;
use serde::{Deserialize, Serialize};

use crate::error::CampaignError;
use crate::fatigue::FatigueSpec;
use crate::fidelity::{AutoFe, StrandFidelity};
use crate::screening::{HotSpots, ScreeningSpec, MAX_SCREENED_PER_SECTOR};
use crate::sectors::SectorSpec;
use crate::seeds::{ExtraSeeds, MAX_SEEDS_PER_SEA_STATE};
use crate::stiffness::AxialStiffnessRule;

/// A whole campaign.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct CampaignSpec {
    /// Free-text provenance.
    #[serde(rename = "_about", default, skip_serializing_if = "Option::is_none")]
    pub about: Option<String>,
    /// Unique campaign name in its database.
    pub name: String,
    /// Design life (years) the lifetime damage is reported for.
    pub design_life_years: f64,
    /// Design fatigue factor of the design check: the damage over the design life times this
    /// factor must not exceed 1 ([`crate::design`]); 5 (DNV-OS-E301) when absent.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub design_fatigue_factor: Option<f64>,
    /// Campaign seed: every realisation seed is drawn from it once, at planning.
    pub seed: u64,
    /// Scatter diagram and how its cells are read.
    pub scatter: ScatterSpec,
    /// Global base case whose sea state and timing are replaced per job.
    pub global: GlobalBaseSpec,
    /// Per-sea-state simulation settings.
    pub simulation: SimulationSpec,
    /// Hot spots (line id, arc length from the fairlead), or `"auto"`: one per line, found by
    /// a screening run when the campaign is resolved ([`crate::screening`]).
    pub hot_spots: HotSpots,
    /// Settings of the screening of `"hot_spots": "auto"`.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub hot_spot_screening: Option<ScreeningSpec>,
    /// Detailed strand model settings.
    pub strand: StrandSpec,
    /// Fretting and fatigue settings of the damage inputs.
    #[serde(default)]
    pub fatigue: FatigueSpec,
    /// Job settings.
    #[serde(default)]
    pub jobs: JobSettings,
}

/// Reads `text` as a `T`; an error names the field path at fault (`simulation.duration_s:
/// invalid type: …`) besides the line and column.
pub fn from_json_with_path<T: serde::de::DeserializeOwned>(text: &str) -> Result<T, String> {
    let mut de = serde_json::Deserializer::from_str(text);
    let value: T = serde_path_to_error::deserialize(&mut de).map_err(|e| {
        let path = e.path().to_string();
        let inner = e.into_inner();
        if path.is_empty() || path == "." {
            inner.to_string()
        } else {
            format!("field `{path}`: {inner}")
        }
    })?;
    de.end().map_err(|e| e.to_string())?;
    Ok(value)
}

/// Scatter diagram file and reading.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ScatterSpec {
    /// Path of the table (TSV/CSV, see `moorfret_solver::waves::scatter`), relative to the
    /// campaign file; absent when the climate is given as `sectors`.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub path: Option<String>,
    /// How the cells of `path` are read; absent with `sectors`.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub reading: Option<ScatterReading>,
    /// Directional sectors, each with its heading, share of the year and table
    /// ([`crate::sectors`]); instead of `path` and `reading`.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub sectors: Vec<SectorSpec>,
    /// What becomes of cells the wave model cannot carry ([`crate::sea_limits`]): refused
    /// (the default) or left out of the plan.
    #[serde(default, skip_serializing_if = "OutsideModel::is_refuse")]
    pub cells_outside_model: OutsideModel,
}

/// What becomes of scatter cells the wave model cannot carry.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum OutsideModel {
    /// The campaign is refused, naming every such cell.
    #[default]
    Refuse,
    /// The cells are left out of the plan (named at launch): their occurrence is neither
    /// planned nor covered.
    LeaveOut,
}

impl OutsideModel {
    fn is_refuse(&self) -> bool {
        *self == OutsideModel::Refuse
    }
}

/// How scatter-diagram cells become occurrence fractions of the year.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case", deny_unknown_fields)]
pub enum ScatterReading {
    /// Each cell is percent of the whole year (cells of all sectors sum to 100).
    JointPercent,
    /// Each cell is percent within one directional sector (the sector's cells sum to 100),
    /// and the sector occurs `share_percent` of the year.
    Sector {
        /// Share of the year of the sector (%).
        share_percent: f64,
    },
}

/// The global base case.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct GlobalBaseSpec {
    /// Path of a global case file (as for `moorfret run global`), relative to the campaign file.
    pub case_path: String,
}

/// Simulation settings applied to every sea state.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct SimulationSpec {
    /// Start-up time discarded from the outputs (s).
    pub transient_s: f64,
    /// Recorded duration after the transient (s).
    pub duration_s: f64,
    /// Time step of the global integration (s).
    pub time_step_s: f64,
    /// Sampling interval of the hot-spot series (s).
    pub output_interval_s: f64,
    /// Wave-load ramp within the transient (s); the base case's value (capped to the
    /// transient) when absent.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub wave_ramp_s: Option<f64>,
    /// Random realisations per sea state.
    pub seeds_per_sea_state: u32,
    /// More realisations for the sea states that carry most of the first seeds' damage
    /// ([`crate::seeds`]); none when absent.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub extra_seeds: Option<ExtraSeeds>,
    /// JONSWAP peak enhancement γ, or `"dnv"` for the DNV-RP-C205 default.
    pub gamma: GammaSpec,
    /// Wave heading (deg, from +x towards +y).
    #[serde(default)]
    pub heading_deg: f64,
    /// Wind (hub speed law and thrust); the base case's when absent.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub wind: Option<WindSpec>,
    /// Threads of one global job (lines in parallel).
    #[serde(default = "one_thread")]
    pub global_threads: usize,
    /// Least fraction of a sea state's spectral energy the wave cut-off must keep
    /// ([`crate::sea_limits`]; 0.5 when absent).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub min_wave_energy_kept: Option<f64>,
}

fn one_thread() -> usize {
    1
}

/// Detailed strand model settings.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct StrandSpec {
    /// Path of a strand profile file, relative to the campaign file: a map name → profile
    /// when `profile` is given, else a single profile.
    pub profiles_path: String,
    /// Name of the profile in that file.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub profile: Option<String>,
    /// End conditions of the helical wires.
    #[serde(default)]
    pub ends: StrandEnds,
    /// Inter-wire Coulomb friction coefficient, overriding the profile's.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub friction_coefficient: Option<f64>,
    /// Contact laws of the wire crossings: `regularised` (default: penalty normal law and
    /// elastic-slip Coulomb law, with `normal_penalty_n_per_m` and `elastic_slip_m`) or
    /// `contact_mechanics` (Hertz normal law at the crossings, line law on the core,
    /// Cattaneo–Mindlin tangential law with memory; no regularisation parameter).
    #[serde(default, skip_serializing_if = "StrandContactLaws::is_regularised")]
    pub contact_laws: StrandContactLaws,
    /// Contact normal penalty (N/m); `regularised` laws only, required with them.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub normal_penalty_n_per_m: Option<f64>,
    /// Elastic slip of the regularised friction law (m); `regularised` laws only, required
    /// with them.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub elastic_slip_m: Option<f64>,
    /// Stiffness along the sliding direction that the Newton iteration matrix gives every
    /// gross-slipping contact, as a fraction of its initial tangential stiffness (`run strand
    /// --sliding-stiffness`); `contact_mechanics` laws only (default: the solver's). It
    /// changes the path of the iterations, not the converged state.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub sliding_stiffness: Option<f64>,
    /// Sampling interval of the load history fed to the strand (s); a multiple of the
    /// global output interval.
    pub load_interval_s: f64,
    /// Wall time between checkpoints of a running strand job (s).
    #[serde(default = "default_checkpoint_interval")]
    pub checkpoint_interval_s: f64,
    /// History segments between two checkpoint opportunities (`run strand
    /// --checkpoint-every`); a checkpoint is written at the first opportunity once
    /// `checkpoint_interval_s` has passed.
    #[serde(
        default = "default_checkpoint_segments",
        skip_serializing_if = "is_default_checkpoint_segments"
    )]
    pub checkpoint_every_segments: usize,
    /// Turning-point tolerance of the load-history reduction, as a fraction of each channel's
    /// range (`run strand --turning-point-tolerance`; default: the solver's, 0.0025).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub turning_point_tolerance: Option<f64>,
    /// Lower bounds of the scales the turning-point tolerance is a fraction of (`run strand
    /// --turning-point-scale`; default: none, each channel's range).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub turning_point_scale: Option<TurningPointScale>,
    /// Threads of a strand job's element kernels and solves (`run strand --threads`).
    #[serde(default = "one_thread", skip_serializing_if = "is_one")]
    pub threads: usize,
    /// Strand model of the strand jobs: `fe` (default), `reduced` or `auto`
    /// ([`crate::fidelity`]).
    #[serde(default, skip_serializing_if = "StrandFidelity::is_fe")]
    pub fidelity: StrandFidelity,
    /// How `auto` picks the sea states that also run FE.
    #[serde(default, skip_serializing_if = "AutoFe::is_default")]
    pub auto_fe: AutoFe,
    /// Whether each strand job stores its full per-contact records (every slip cycle with its
    /// forces) as an artifact. The damage inputs and contact statistics are stored either way;
    /// the records of a 1000 s six-layer history take 0.2-0.5 GB.
    #[serde(default = "yes", skip_serializing_if = "is_true")]
    pub contact_records: bool,
    /// Margin of the reduced response's calibration range beyond the load range of the
    /// campaign's global results, on each side, as a fraction of that range.
    #[serde(
        default = "default_calibration_margin",
        skip_serializing_if = "is_default_calibration_margin"
    )]
    pub calibration_margin: f64,
    /// When the calibration of the reduced response starts (`reduced`, `auto`): once the
    /// first-seed global jobs of the sea states with Hs at least this fraction of the
    /// diagram's largest are done, over their load range widened by `calibration_margin`,
    /// side by side with the other global jobs. A check after every global job keeps that
    /// calibration if its range covers every global job's load that a calibration can serve
    /// (up to the strand's admissible fibre strain), and calibrates again over all of them if
    /// not. 0 waits for every global job (one calibration, no check).
    #[serde(
        default = "default_calibration_hs_fraction",
        skip_serializing_if = "is_default_calibration_hs_fraction"
    )]
    pub calibration_hs_fraction: f64,
    /// Threads of a `calibrate` job: its design's independent FE chains run side by side
    /// (the calibration does not depend on how many). Default: the cores this process may use
    /// (`std::thread::available_parallelism`, which honours CPU affinity and cgroup quotas).
    /// The calibration runs beside global jobs while they last, then alone on the critical
    /// path: every strand job waits for it.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub calibration_threads: Option<usize>,
    /// One calibration of the reduced response for every hot spot, over the union of their
    /// load ranges (the strand is the same at each hot spot; only its load range differs),
    /// instead of one per hot spot. A campaign with hot spots on many lines saves all but one
    /// calibration; the range is wider, so the reduced response's error against FE is
    /// measured on it (`docs/reduced-strand.md`).
    #[serde(default, skip_serializing_if = "is_false")]
    pub shared_calibration: bool,
    /// Mild sea states a hot spot skips (`reduced`, `auto`; [`crate::mild_seas`]): per hot spot,
    /// the first-seed sea states of the smallest fibre-strain measure whose tension-bending
    /// proxy together stays within this fraction of the hot spot's total are not run through the
    /// strand model; the design check charges the hot spot's damage by 1 / (1 − the skipped
    /// proxy share), the bound on what they hold. 0 (default) runs every sea state.
    #[serde(default, skip_serializing_if = "is_zero")]
    pub skip_mild_share: f64,
    /// EA of the tension → strain conversion ([`crate::stiffness`]): `strand_model` or
    /// `line_type`. A campaign file without it takes `strand_model`, and the resolved campaign
    /// stores that choice; stored inputs without it belong to campaigns planned before the
    /// setting existed, which converted with the line type's EA
    /// ([`StrandSpec::axial_stiffness_rule`]).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub axial_stiffness: Option<AxialStiffnessRule>,
}

fn yes() -> bool {
    true
}

fn is_true(b: &bool) -> bool {
    *b
}

fn is_false(b: &bool) -> bool {
    !*b
}

fn is_zero(x: &f64) -> bool {
    *x == 0.0
}

fn default_calibration_margin() -> f64 {
    0.05
}

fn is_default_calibration_margin(m: &f64) -> bool {
    *m == default_calibration_margin()
}

fn default_calibration_hs_fraction() -> f64 {
    0.5
}

fn is_default_calibration_hs_fraction(f: &f64) -> bool {
    *f == default_calibration_hs_fraction()
}

/// Contact laws of the strand model's wire crossings (`strand.contact_laws`).
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum StrandContactLaws {
    /// Penalty normal law and elastic-slip regularised Coulomb law (the paper's Sec. 2.1), with
    /// `normal_penalty_n_per_m` and `elastic_slip_m`.
    #[default]
    Regularised,
    /// Hertz normal law for crossed cylinders at their crossing angle, the line-contact law of
    /// layer 0 on the core, and the Cattaneo–Mindlin tangential law with memory.
    ContactMechanics,
}

impl StrandContactLaws {
    /// Whether `self` is the default (`regularised`).
    pub fn is_regularised(&self) -> bool {
        *self == Self::Regularised
    }
}

/// End conditions of the helical wires of the strand model.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum StrandEnds {
    /// Periodic constraints between the two ends (the paper's Sec. 2.3).
    #[default]
    Periodic,
    /// Periodic constraints with the far ends following the start ends in rotation too.
    PeriodicRotations,
    /// Penalty ties of the helical wire ends to the core end sections (the paper's Sec. 2.2).
    PenaltyTies,
}

impl StrandSpec {
    /// The tension → strain rule of a strand job: as the campaign stored it, or `line_type`
    /// for a campaign planned before the setting existed (see `axial_stiffness`).
    pub fn axial_stiffness_rule(&self) -> AxialStiffnessRule {
        self.axial_stiffness.unwrap_or(AxialStiffnessRule::LineType)
    }

    /// Threads of a `calibrate` job: `calibration_threads`, else the cores this process may
    /// use.
    pub fn calibration_threads(&self) -> usize {
        self.calibration_threads.unwrap_or_else(|| {
            std::thread::available_parallelism()
                .map_or(1, |n| n.get())
                .min(MAX_STRAND_THREADS)
        })
    }

    /// The solver settings of a strand job's history run ([`HistorySettings::options`]).
    pub fn history_options(&self) -> HistoryOptions {
        HistorySettings {
            threads: self.threads,
            turning_point_tolerance: self.turning_point_tolerance,
            turning_point_scale: self
                .turning_point_scale
                .map(|s| [s.strain, s.curvature_per_m]),
            checkpoint_interval_segments: self.checkpoint_every_segments,
            sliding_stiffness: self.sliding_stiffness,
        }
        .options()
    }
}

/// The settings of a strand history run that a campaign's strand settings and the options of
/// `moorfret run strand` give; everything else is the solver's default. The one way both build
/// their [`HistoryOptions`].
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct HistorySettings {
    /// Threads of the element kernels and the sparse solves.
    pub threads: usize,
    /// Turning-point tolerance (the solver's default when `None`).
    pub turning_point_tolerance: Option<f64>,
    /// Lower bounds of the tolerance's scales, strain and curvature (1/m) (the solver's default
    /// when `None`).
    pub turning_point_scale: Option<[f64; 2]>,
    /// History segments between two checkpoints handed to the observer (0: none).
    pub checkpoint_interval_segments: usize,
    /// The Newton matrix's sliding stiffness (the solver's default when `None`).
    pub sliding_stiffness: Option<f64>,
}

impl HistorySettings {
    /// The solver's history options (not validated: [`HistoryOptions::validated`]).
    pub fn options(&self) -> HistoryOptions {
        let defaults = HistoryOptions::default();
        HistoryOptions {
            checkpoint_interval_segments: self.checkpoint_interval_segments,
            threads: self.threads,
            turning_point_tolerance: self
                .turning_point_tolerance
                .unwrap_or(defaults.turning_point_tolerance),
            turning_point_scale: self
                .turning_point_scale
                .unwrap_or(defaults.turning_point_scale),
            sliding_stiffness: self.sliding_stiffness.unwrap_or(defaults.sliding_stiffness),
            ..defaults
        }
    }
}

/// Load scale of the turning-point tolerance on the strand's own scale
/// ([`HistoryOptions::turning_point_scale`]).
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct TurningPointScale {
    /// Axial strain.
    pub strain: f64,
    /// Curvature (1/m).
    pub curvature_per_m: f64,
}

impl StrandEnds {
    /// The solver's end condition.
    pub fn end_kind(self) -> moorfret_solver::strand::model::EndKind {
        use moorfret_solver::strand::model::EndKind;
        match self {
            Self::Periodic => EndKind::Periodic,
            Self::PeriodicRotations => EndKind::PeriodicRotations,
            Self::PenaltyTies => EndKind::PenaltyTies,
        }
    }
}

fn default_checkpoint_interval() -> f64 {
    120.0
}

/// Segments between checkpoint opportunities, as `run strand --checkpoint-every`.
pub const DEFAULT_CHECKPOINT_SEGMENTS: usize = 8;

fn default_checkpoint_segments() -> usize {
    DEFAULT_CHECKPOINT_SEGMENTS
}

fn is_default_checkpoint_segments(n: &usize) -> bool {
    *n == DEFAULT_CHECKPOINT_SEGMENTS
}

fn is_one(n: &usize) -> bool {
    *n == 1
}

/// Most threads a strand job or `run strand` uses.
pub const MAX_STRAND_THREADS: usize = 256;

/// Most time steps of a global run (10⁸: about 116 days at 0.1 s).
pub const MAX_GLOBAL_STEPS: f64 = 1e8;

/// Largest wire-on-wire friction coefficient accepted.
pub const MAX_FRICTION_COEFFICIENT: f64 = 2.0;

/// Job settings.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct JobSettings {
    /// Attempts before a transiently failing job is failed.
    #[serde(default = "default_attempts")]
    pub max_attempts: i64,
}

fn default_attempts() -> i64 {
    3
}

impl Default for JobSettings {
    fn default() -> Self {
        Self {
            max_attempts: default_attempts(),
        }
    }
}

fn invalid(field: impl Into<String>, value: impl std::fmt::Display, reason: &str) -> CampaignError {
    CampaignError::Invalid {
        field: field.into(),
        value: value.to_string(),
        reason: reason.to_owned(),
    }
}

fn positive(field: &str, v: f64) -> Result<(), CampaignError> {
    if v.is_finite() && v > 0.0 {
        Ok(())
    } else {
        Err(invalid(field, v, "must be > 0"))
    }
}

fn non_negative(field: &str, v: f64) -> Result<(), CampaignError> {
    if v.is_finite() && v >= 0.0 {
        Ok(())
    } else {
        Err(invalid(field, v, "must be >= 0"))
    }
}

impl CampaignSpec {
    /// Parses a campaign file's text; unknown fields and wrong types are errors that give the
    /// line, column and field.
    pub fn from_json_str(text: &str) -> Result<Self, CampaignError> {
        from_json_with_path(text).map_err(|message| CampaignError::Json { message })
    }

    /// Checks every value that does not need the referenced files.
    pub fn validate(&self) -> Result<(), CampaignError> {
        let name_ok = !self.name.is_empty()
            && self
                .name
                .chars()
                .all(|c| c.is_ascii_alphanumeric() || "-_.".contains(c));
        if !name_ok {
            return Err(invalid(
                "name",
                &self.name,
                "must be non-empty ASCII letters, digits, '-', '_' or '.'",
            ));
        }
        positive("design_life_years", self.design_life_years)?;
        if let Some(f) = self.design_fatigue_factor {
            if !(f.is_finite() && f >= 1.0) {
                return Err(invalid(
                    "design_fatigue_factor",
                    Num(f),
                    "must be a finite number >= 1",
                ));
            }
        }
        self.scatter.validate(self.simulation.heading_deg)?;
        let s = &self.simulation;
        non_negative("simulation.transient_s", s.transient_s)?;
        positive("simulation.duration_s", s.duration_s)?;
        positive("simulation.time_step_s", s.time_step_s)?;
        positive("simulation.output_interval_s", s.output_interval_s)?;
        if s.time_step_s > s.output_interval_s * (1.0 + 1e-9) {
            return Err(invalid(
                "simulation.time_step_s",
                Num(s.time_step_s),
                &format!(
                    "must not exceed simulation.output_interval_s ({} s): every output sample \
                     needs a step",
                    Num(s.output_interval_s)
                ),
            ));
        }
        if let Some(ramp) = s.wave_ramp_s {
            non_negative("simulation.wave_ramp_s", ramp)?;
            if ramp > s.transient_s {
                return Err(invalid(
                    "simulation.wave_ramp_s",
                    Num(ramp),
                    &format!(
                        "must not exceed simulation.transient_s ({} s): the waves would still \
                         be ramping up in the recorded part",
                        Num(s.transient_s)
                    ),
                ));
            }
        }
        if let Some(kept) = s.min_wave_energy_kept {
            if !(kept.is_finite() && (0.0..=1.0).contains(&kept)) {
                return Err(invalid(
                    "simulation.min_wave_energy_kept",
                    Num(kept),
                    "must be in [0, 1]",
                ));
            }
        }
        match &s.gamma {
            GammaSpec::Value(g) if !(g.is_finite() && (1.0..=7.0).contains(g)) => {
                return Err(invalid(
                    "simulation.gamma",
                    Num(*g),
                    "must be in [1, 7] or \"dnv\"",
                ));
            }
            GammaSpec::Rule(r) if !r.eq_ignore_ascii_case("dnv") => {
                return Err(invalid(
                    "simulation.gamma",
                    r,
                    "must be a number in [1, 7] or \"dnv\"",
                ));
            }
            _ => {}
        }
        let steps = (s.transient_s + s.duration_s) / s.time_step_s;
        if steps > MAX_GLOBAL_STEPS {
            // Blame what is out of the ordinary: the longer time span when the two are too
            // long even at a coarse step of 0.1 s, or else the step.
            let (field, value) = if (s.transient_s + s.duration_s) / 0.1 > MAX_GLOBAL_STEPS {
                if s.transient_s > s.duration_s {
                    ("simulation.transient_s", s.transient_s)
                } else {
                    ("simulation.duration_s", s.duration_s)
                }
            } else {
                ("simulation.time_step_s", s.time_step_s)
            };
            return Err(invalid(
                field,
                Num(value),
                &format!(
                    "gives {} time steps over simulation.transient_s + simulation.duration_s, \
                     more than {}",
                    Num(steps.floor()),
                    Num(MAX_GLOBAL_STEPS)
                ),
            ));
        }
        if !(1..=MAX_SEEDS_PER_SEA_STATE).contains(&s.seeds_per_sea_state) {
            return Err(invalid(
                "simulation.seeds_per_sea_state",
                s.seeds_per_sea_state,
                &format!("must be from 1 to {MAX_SEEDS_PER_SEA_STATE}"),
            ));
        }
        if let Some(extra) = &s.extra_seeds {
            extra.validate(s.seeds_per_sea_state)?;
        }
        if !(1..=MAX_STRAND_THREADS).contains(&s.global_threads) {
            return Err(invalid(
                "simulation.global_threads",
                s.global_threads,
                &format!("must be from 1 to {MAX_STRAND_THREADS}"),
            ));
        }
        if !self.hot_spots.is_auto() && self.hot_spots.is_empty() {
            return Err(invalid(
                "hot_spots",
                "[]",
                "needs at least one hot spot, or \"auto\"",
            ));
        }
        if let Some(sc) = &self.hot_spot_screening {
            if !self.hot_spots.is_auto() {
                return Err(invalid(
                    "hot_spot_screening",
                    "{…}",
                    "applies to \"hot_spots\": \"auto\" only (the hot spots are listed)",
                ));
            }
            if !(1..=MAX_SCREENED_PER_SECTOR).contains(&sc.sea_states_per_sector) {
                return Err(invalid(
                    "hot_spot_screening.sea_states_per_sector",
                    sc.sea_states_per_sector,
                    &format!("must be from 1 to {MAX_SCREENED_PER_SECTOR}"),
                ));
            }
            if let Some(d) = sc.duration_s {
                if !(d.is_finite() && d > 0.0) {
                    return Err(invalid(
                        "hot_spot_screening.duration_s",
                        d,
                        "must be a finite number > 0",
                    ));
                }
            }
        }
        for (i, h) in self.hot_spots.iter().enumerate() {
            non_negative(&format!("hot_spots[{i}].arc_length_m"), h.arc_length_m)?;
            if let Some(k) = self.hot_spots[..i].iter().position(|o| o == h) {
                return Err(invalid(
                    format!("hot_spots[{i}]"),
                    format!("line {}, {} m", h.line, h.arc_length_m),
                    &format!("repeats hot_spots[{k}]"),
                ));
            }
        }
        let st = &self.strand;
        if let Some(mu) = st.friction_coefficient {
            if !(mu.is_finite() && (0.0..=MAX_FRICTION_COEFFICIENT).contains(&mu)) {
                return Err(invalid(
                    "strand.friction_coefficient",
                    Num(mu),
                    &format!(
                        "must be in [0, {MAX_FRICTION_COEFFICIENT}] (steel wires on steel: \
                         about 0.1 to 0.8)"
                    ),
                ));
            }
        }
        for (field, value) in [
            ("strand.normal_penalty_n_per_m", st.normal_penalty_n_per_m),
            ("strand.elastic_slip_m", st.elastic_slip_m),
        ] {
            match (st.contact_laws, value) {
                (StrandContactLaws::Regularised, Some(v)) => positive(field, v)?,
                (StrandContactLaws::Regularised, None) => {
                    return Err(invalid(
                        field,
                        "missing",
                        "is required with strand.contact_laws \"regularised\" (the default)",
                    ))
                }
                (StrandContactLaws::ContactMechanics, Some(v)) => {
                    return Err(invalid(
                        field,
                        Num(v),
                        "is not used by strand.contact_laws \"contact_mechanics\" (its laws \
                         have no regularisation): remove it",
                    ))
                }
                (StrandContactLaws::ContactMechanics, None) => {}
            }
        }
        if let (StrandContactLaws::Regularised, Some(v)) = (st.contact_laws, st.sliding_stiffness) {
            return Err(invalid(
                "strand.sliding_stiffness",
                Num(v),
                "is used by strand.contact_laws \"contact_mechanics\" only (it acts on the \
                 Cattaneo–Mindlin contacts): remove it",
            ));
        }
        if st.contact_laws == StrandContactLaws::ContactMechanics && st.fidelity.uses_reduced() {
            return Err(invalid(
                "strand.fidelity",
                format!("{:?}", st.fidelity).to_lowercase(),
                "the reduced strand response under the contact-mechanics laws is not yet within \
                 10 % of the FE model per contact class (docs/contact-laws.md); \
                 strand.contact_laws \"contact_mechanics\" needs fidelity \"fe\"",
            ));
        }
        positive("strand.load_interval_s", st.load_interval_s)?;
        let ratio = st.load_interval_s / s.output_interval_s;
        if ratio < 1.0 - 1e-9 || (ratio - ratio.round()).abs() > 1e-6 {
            return Err(invalid(
                "strand.load_interval_s",
                st.load_interval_s,
                "must be a whole multiple of simulation.output_interval_s",
            ));
        }
        if st.load_interval_s > s.duration_s {
            return Err(invalid(
                "strand.load_interval_s",
                Num(st.load_interval_s),
                &format!(
                    "must not exceed simulation.duration_s ({} s): the strand would get no load \
                     step",
                    Num(s.duration_s)
                ),
            ));
        }
        positive("strand.checkpoint_interval_s", st.checkpoint_interval_s)?;
        if st.checkpoint_every_segments == 0 {
            return Err(invalid(
                "strand.checkpoint_every_segments",
                0,
                "must be >= 1",
            ));
        }
        st.history_options().validated().map_err(|e| match e {
            HistoryError::InvalidOption {
                field,
                value,
                reason,
            } => invalid(format!("strand.{field}"), value, &reason),
            e => invalid("strand", "history settings", &e.to_string()),
        })?;
        st.auto_fe.validate()?;
        if !(st.calibration_margin.is_finite() && (0.0..=1.0).contains(&st.calibration_margin)) {
            return Err(invalid(
                "strand.calibration_margin",
                st.calibration_margin,
                "must be in [0, 1]",
            ));
        }
        let f = st.calibration_hs_fraction;
        if !(f.is_finite() && (0.0..=1.0).contains(&f)) {
            return Err(invalid(
                "strand.calibration_hs_fraction",
                f,
                "must be in [0, 1]",
            ));
        }
        let share = st.skip_mild_share;
        if !(share.is_finite() && (0.0..=crate::mild_seas::MAX_SKIP_SHARE).contains(&share)) {
            return Err(invalid(
                "strand.skip_mild_share",
                share,
                &format!("must be in [0, {}]", crate::mild_seas::MAX_SKIP_SHARE),
            ));
        }
        if share > 0.0 && !st.fidelity.uses_reduced() {
            return Err(invalid(
                "strand.skip_mild_share",
                share,
                "skips reduced strand jobs only: needs strand.fidelity reduced or auto",
            ));
        }
        if !(1..=MAX_STRAND_THREADS).contains(&st.threads) {
            return Err(invalid(
                "strand.threads",
                st.threads,
                &format!("must be from 1 to {MAX_STRAND_THREADS}"),
            ));
        }
        if let Some(n) = st.calibration_threads {
            if !(1..=MAX_STRAND_THREADS).contains(&n) {
                return Err(invalid(
                    "strand.calibration_threads",
                    n,
                    &format!("must be from 1 to {MAX_STRAND_THREADS}"),
                ));
            }
        }
        self.fatigue
            .validate(self.simulation.duration_s, self.strand.load_interval_s)?;
        if self.jobs.max_attempts < 1 {
            return Err(invalid(
                "jobs.max_attempts",
                self.jobs.max_attempts,
                "must be >= 1",
            ));
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use moorfret_solver::global::case::HotSpotSpec;

    fn demo_spec(fatigue: serde_json::Value) -> CampaignSpec {
        let path = concat!(env!("CARGO_MANIFEST_DIR"), "/../campaigns/demo.json");
        let mut spec: serde_json::Value =
            serde_json::from_str(&std::fs::read_to_string(path).unwrap()).unwrap();
        spec["fatigue"] = fatigue;
        CampaignSpec::from_json_str(&spec.to_string()).unwrap()
    }

    #[test]
    fn bad_fatigue_settings_are_refused_naming_the_field() {
        assert!(demo_spec(serde_json::json!({})).validate().is_ok());
        let cases = [
            (serde_json::json!({"run_in_s": 29.5}), "fatigue.run_in_s"),
            (serde_json::json!({"run_in_s": -1.0}), "fatigue.run_in_s"),
            (
                serde_json::json!({"run_in_detection": {"window_s": 0.1}}),
                "fatigue.run_in_detection.window_s",
            ),
            (
                serde_json::json!({"run_in_detection": {"reference_fraction": 1.0}}),
                "fatigue.run_in_detection.reference_fraction",
            ),
            (
                serde_json::json!({"run_in_detection": {"tolerance_sigma": 0.0}}),
                "fatigue.run_in_detection.tolerance_sigma",
            ),
            (
                serde_json::json!({"slip_amplitude_edges_m": [0.0, 2e-6, 1e-6]}),
                "fatigue.slip_amplitude_edges_m",
            ),
            (
                serde_json::json!({"tn_curves": [{"measure": "fretting_max", "curve": {"Dnv":
                    {"component": "SpiralRope", "nominal_area_m2": 2.9e-3}}}]}),
                "fatigue.tn_curves[0].measure",
            ),
            (
                serde_json::json!({"tn_curves": [{"measure": "tn", "curve": {"Dnv":
                    {"component": "SpiralRope", "nominal_area_m2": 0.0}}}]}),
                "fatigue.tn_curves[0].curve",
            ),
        ];
        for (fatigue, field) in cases {
            match demo_spec(fatigue.clone()).validate() {
                Err(CampaignError::Invalid { field: f, .. }) => assert_eq!(f, field, "{fatigue}"),
                other => panic!("{fatigue}: {other:?}"),
            }
        }
    }

    #[test]
    fn the_strand_ends_read_as_the_solver_end_conditions_and_an_unknown_one_is_refused() {
        use moorfret_solver::strand::model::EndKind;
        let spec = demo_spec(serde_json::json!({}));
        let with = |ends: &str| {
            let mut v = serde_json::to_value(&spec).unwrap();
            v["strand"]["ends"] = serde_json::json!(ends);
            CampaignSpec::from_json_str(&v.to_string())
        };
        for (text, kind) in [
            ("periodic", EndKind::Periodic),
            ("periodic_rotations", EndKind::PeriodicRotations),
            ("penalty_ties", EndKind::PenaltyTies),
        ] {
            assert_eq!(with(text).unwrap().strand.ends.end_kind(), kind, "{text}");
        }
        let err = with("periodic_rotation").unwrap_err().to_string();
        assert!(err.contains("periodic_rotations"), "{err}");
    }

    #[test]
    fn the_contact_laws_are_regularised_by_default_and_contact_mechanics_has_no_regularisation() {
        let path = concat!(env!("CARGO_MANIFEST_DIR"), "/../campaigns/paper.json");
        let text = std::fs::read_to_string(path).unwrap();
        let file: serde_json::Value = serde_json::from_str(&text).unwrap();
        let spec = CampaignSpec::from_json_str(&text).unwrap();
        assert_eq!(spec.strand.contact_laws, StrandContactLaws::Regularised);
        // an existing file serialises as before: same strand fields, same values
        let again = serde_json::to_value(&spec).unwrap();
        assert_eq!(again["strand"].get("contact_laws"), None);
        for field in ["normal_penalty_n_per_m", "elastic_slip_m"] {
            assert_eq!(again["strand"][field], file["strand"][field], "{field}");
        }
        let with = |strand: serde_json::Value| {
            let mut v = serde_json::to_value(&spec).unwrap();
            for (k, x) in strand.as_object().unwrap() {
                if x.is_null() {
                    v["strand"].as_object_mut().unwrap().remove(k);
                } else {
                    v["strand"][k] = x.clone();
                }
            }
            CampaignSpec::from_json_str(&v.to_string())
        };
        let cm = with(serde_json::json!({"contact_laws": "contact_mechanics",
            "normal_penalty_n_per_m": null, "elastic_slip_m": null, "fidelity": "fe"}))
        .unwrap();
        assert!(cm.validate().is_ok());
        assert_eq!(
            serde_json::to_value(&cm).unwrap()["strand"]["contact_laws"],
            "contact_mechanics"
        );
        let field = |s: CampaignSpec| match s.validate() {
            Err(CampaignError::Invalid { field, reason, .. }) => (field, reason),
            other => panic!("{other:?}"),
        };
        let (f, why) = field(
            with(
                serde_json::json!({"contact_laws": "contact_mechanics", "fidelity": "fe",
                "normal_penalty_n_per_m": null}),
            )
            .unwrap(),
        );
        assert_eq!(f, "strand.elastic_slip_m");
        assert!(why.contains("not used"), "{why}");
        let (f, why) = field(
            with(
                serde_json::json!({"contact_laws": "contact_mechanics", "fidelity": "auto",
                "normal_penalty_n_per_m": null, "elastic_slip_m": null}),
            )
            .unwrap(),
        );
        assert_eq!(f, "strand.fidelity");
        assert!(why.contains("not yet within 10 %"), "{why}");
        assert!(why.contains("needs fidelity \"fe\""), "{why}");
        let (f, why) = field(with(serde_json::json!({"elastic_slip_m": null})).unwrap());
        assert_eq!(f, "strand.elastic_slip_m");
        assert!(why.contains("required"), "{why}");
        let err = with(serde_json::json!({"contact_laws": "hertz"}))
            .unwrap_err()
            .to_string();
        assert!(
            err.contains("regularised") && err.contains("contact_mechanics"),
            "{err}"
        );
        // the Newton matrix's sliding stiffness: the contact-mechanics laws' option, bounded,
        // carried to the history options
        let cm_with = |sliding: serde_json::Value| {
            with(serde_json::json!({"contact_laws": "contact_mechanics",
                "normal_penalty_n_per_m": null, "elastic_slip_m": null, "fidelity": "fe",
                "sliding_stiffness": sliding}))
            .unwrap()
        };
        let set = cm_with(serde_json::json!(0.3));
        assert!(set.validate().is_ok());
        assert_eq!(set.strand.history_options().sliding_stiffness, 0.3);
        assert_eq!(
            cm.strand.history_options().sliding_stiffness,
            HistoryOptions::default().sliding_stiffness
        );
        let (f, why) = field(cm_with(serde_json::json!(-0.1)));
        assert_eq!(f, "strand.sliding_stiffness");
        assert!(!why.is_empty());
        let (f, why) = field(with(serde_json::json!({"sliding_stiffness": 0.1})).unwrap());
        assert_eq!(f, "strand.sliding_stiffness");
        assert!(why.contains("contact_mechanics"), "{why}");
    }

    #[test]
    fn seeds_threads_and_repeated_hot_spots_are_bounded() {
        let spec = demo_spec(serde_json::json!({}));
        let field = |s: CampaignSpec| match s.validate() {
            Err(CampaignError::Invalid { field, .. }) => field,
            other => panic!("{other:?}"),
        };
        let mut s = spec.clone();
        s.simulation.seeds_per_sea_state = u32::MAX;
        assert_eq!(field(s), "simulation.seeds_per_sea_state");
        let mut s = spec.clone();
        s.simulation.global_threads = 100_000;
        assert_eq!(field(s), "simulation.global_threads");
        let mut s = spec.clone();
        s.strand.calibration_threads = Some(0);
        assert_eq!(field(s), "strand.calibration_threads");
        let mut s = spec.clone();
        let twice = vec![s.hot_spots[0].clone(), s.hot_spots[0].clone()];
        s.hot_spots = HotSpots::Listed(twice);
        assert_eq!(field(s), "hot_spots[1]");
        let mut s = spec.clone();
        s.simulation.gamma = GammaSpec::Value(0.5);
        assert_eq!(field(s), "simulation.gamma");
        let mut s = spec.clone();
        s.simulation.gamma = GammaSpec::Rule("high".into());
        assert_eq!(field(s), "simulation.gamma");
        let mut s = spec.clone();
        s.simulation.time_step_s = 1e-9;
        assert_eq!(field(s), "simulation.time_step_s");
        let mut s = spec.clone();
        s.simulation.duration_s = 1e308;
        assert_eq!(field(s), "simulation.duration_s");
        let mut s = spec.clone();
        s.strand.friction_coefficient = Some(1e6);
        assert_eq!(field(s), "strand.friction_coefficient");
        let mut s = spec.clone();
        s.strand.load_interval_s = 100.0 * s.simulation.output_interval_s.max(1.0);
        s.simulation.duration_s = 30.0;
        assert_eq!(field(s), "strand.load_interval_s");
        let mut s = spec;
        let mut listed = s.hot_spots.to_vec();
        listed.push(HotSpotSpec {
            line: 1,
            arc_length_m: 80.0,
        });
        s.hot_spots = HotSpots::Listed(listed);
        assert!(s.validate().is_ok());
    }

    #[test]
    fn the_extra_seed_rule_is_optional_checked_by_field_and_absent_from_files_without_it() {
        let spec = demo_spec(serde_json::json!({}));
        assert_eq!(spec.simulation.extra_seeds, None);
        let text = serde_json::to_string(&spec).unwrap();
        assert!(!text.contains("extra_seeds"), "{text}");
        let with = |extra: serde_json::Value| {
            let mut v = serde_json::to_value(&spec).unwrap();
            v["simulation"]["extra_seeds"] = extra;
            CampaignSpec::from_json_str(&v.to_string())
        };
        let ok = with(serde_json::json!({"seeds": 3, "damage_share": 0.8})).unwrap();
        assert!(ok.validate().is_ok());
        assert_eq!(
            ok.simulation.extra_seeds,
            Some(ExtraSeeds {
                seeds: 3,
                damage_share: 0.8
            })
        );
        for (extra, field) in [
            (
                serde_json::json!({"seeds": 1, "damage_share": 0.8}),
                "simulation.extra_seeds.seeds",
            ),
            (
                serde_json::json!({"seeds": 3, "damage_share": 0.0}),
                "simulation.extra_seeds.damage_share",
            ),
            (
                serde_json::json!({"seeds": 3, "damage_share": 1.2}),
                "simulation.extra_seeds.damage_share",
            ),
        ] {
            match with(extra.clone()).unwrap().validate() {
                Err(CampaignError::Invalid { field: f, .. }) => assert_eq!(f, field, "{extra}"),
                other => panic!("{extra}: {other:?}"),
            }
        }
        // both fields are required, unknown ones refused, negative counts a type error
        for extra in [
            serde_json::json!({"seeds": 3}),
            serde_json::json!({"seeds": 3, "damage_share": 0.8, "share": 1}),
            serde_json::json!({"seeds": -3, "damage_share": 0.8}),
        ] {
            let e = with(extra.clone()).unwrap_err().to_string();
            assert!(e.contains("valid campaign"), "{extra}: {e}");
        }
    }

    #[test]
    fn bad_fidelity_settings_are_refused_naming_the_field() {
        let with = |strand: serde_json::Value| {
            let mut spec = serde_json::to_value(demo_spec(serde_json::json!({}))).unwrap();
            for (k, v) in strand.as_object().unwrap() {
                spec["strand"][k] = v.clone();
            }
            CampaignSpec::from_json_str(&spec.to_string())
        };
        let ok = with(serde_json::json!({"fidelity": "auto", "auto_fe": {"sea_states": 3}}));
        let ok = ok.unwrap();
        assert!(ok.validate().is_ok());
        assert_eq!(ok.strand.auto_fe.damage_share, 1.0);
        let cases = [
            (
                serde_json::json!({"auto_fe": {"sea_states": 0}}),
                "strand.auto_fe.sea_states",
            ),
            (
                serde_json::json!({"auto_fe": {"damage_share": 1.5}}),
                "strand.auto_fe.damage_share",
            ),
            (
                serde_json::json!({"calibration_margin": -0.1}),
                "strand.calibration_margin",
            ),
            (
                serde_json::json!({"calibration_hs_fraction": 1.5}),
                "strand.calibration_hs_fraction",
            ),
            (
                serde_json::json!({"calibration_hs_fraction": -0.2}),
                "strand.calibration_hs_fraction",
            ),
            (
                serde_json::json!({"skip_mild_share": 0.2, "fidelity": "reduced"}),
                "strand.skip_mild_share",
            ),
            (
                serde_json::json!({"skip_mild_share": -0.01, "fidelity": "auto"}),
                "strand.skip_mild_share",
            ),
            (
                serde_json::json!({"skip_mild_share": 0.01}),
                "strand.skip_mild_share",
            ),
            (
                serde_json::json!({"turning_point_scale": {"strain": 1e-4, "curvature_per_m": -1.0}}),
                "strand.turning_point_scale.curvature_per_m",
            ),
        ];
        for (strand, field) in cases {
            match with(strand.clone()).unwrap().validate() {
                Err(CampaignError::Invalid { field: f, .. }) => assert_eq!(f, field, "{strand}"),
                other => panic!("{strand}: {other:?}"),
            }
        }
        // an unknown fidelity is a parse error that names the value and the choices
        let e = with(serde_json::json!({"fidelity": "fast"}))
            .unwrap_err()
            .to_string();
        assert!(e.contains("fast") && e.contains("reduced"), "{e}");
        // the strand-scale tolerance reaches the history options
        let scaled = with(serde_json::json!({
            "turning_point_scale": {"strain": 1e-4, "curvature_per_m": 2.5e-3}
        }))
        .unwrap();
        assert!(scaled.validate().is_ok());
        assert_eq!(
            scaled.strand.history_options().turning_point_scale,
            [1e-4, 2.5e-3]
        );
    }
}
