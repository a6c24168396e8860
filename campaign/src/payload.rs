//! What a worker needs to run a campaign's jobs: the campaign's resolved inputs (stored with
//! the campaign, so a worker needs the store and nothing else: no campaign file, no data files
//! on its machine) and the small per-job payloads.
//!
//! Cache keys: sha256 of the job kind, the solver version, the sha256 of the inputs that decide
//! its results and the job payload. For a global job those inputs are the simulation settings,
//! hot spots, base case and floater ([`CampaignInputs::global_sha256`]); for the other jobs
//! they are every campaign input but names and free text ([`CampaignInputs::results_sha256`]),
//! and their payloads hold their upstream jobs' keys. Identical inputs are computed once, also across
//! campaigns in one database.

use moorfret_solver::floater::FloaterSpec;
use moorfret_solver::global::case::SeaStateSpec;
use moorfret_solver::global::CaseSpec;
use moorfret_solver::strand::profile::StrandProfile;
use serde::{Deserialize, Serialize};
use sha2::{Digest, Sha256};

use crate::screening::ScreenedHotSpot;
use crate::spec::CampaignSpec;

/// Version of the solver whose results the cache keys vouch for.
pub const SOLVER_VERSION: &str = env!("CARGO_PKG_VERSION");

/// Floater content of the base case.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case", deny_unknown_fields)]
pub enum FloaterContent {
    /// A rigid-body floater description.
    RigidBody(Box<FloaterSpec>),
    /// The text of a prescribed-motion table.
    PrescribedMotionCsv(String),
}

/// The campaign's inputs with every referenced file's content, as stored with the campaign.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct CampaignInputs {
    /// The campaign file.
    pub spec: CampaignSpec,
    /// The global base case, hot spots of the campaign.
    pub base_case: CaseSpec,
    /// Its floater.
    pub floater: FloaterContent,
    /// The strand profile, friction override applied.
    pub profile: StrandProfile,
    /// Axial stiffness EA of the rope at each hot spot (N): ε(t) = T(t) / EA.
    pub hot_spot_axial_stiffness_n: Vec<f64>,
    /// The hot spots found by screening, with their proxy (`"hot_spots": "auto"`); empty for
    /// listed hot spots.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub hot_spot_screening: Vec<ScreenedHotSpot>,
}

/// Input of a `global` job.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct GlobalPayload {
    /// Sea state index in the campaign.
    pub sea_state_index: usize,
    /// Significant wave height (m).
    pub hs_m: f64,
    /// Peak period (s).
    pub tp_s: f64,
    /// Seed index within the sea state.
    pub seed_index: usize,
    /// Seed of the wave realisation.
    pub seed: u64,
    /// An extra seed of `simulation.extra_seeds`: this realisation and its strand jobs run
    /// only if the first seeds' results select its sea state (`crate::seeds`), else they end
    /// at once with no results.
    #[serde(default, skip_serializing_if = "std::ops::Not::not")]
    pub extra_seed: bool,
    /// Wave heading of a directional sector (deg), when it differs from
    /// `simulation.heading_deg` ([`crate::sectors`]).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub heading_deg: Option<f64>,
}

impl GlobalPayload {
    /// The wave heading of this realisation (deg).
    pub fn heading_deg(&self, inputs: &CampaignInputs) -> f64 {
        self.heading_deg
            .unwrap_or(inputs.spec.simulation.heading_deg)
    }
}

/// Input of a `strand` job: one hot spot of one global realisation.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct StrandPayload {
    /// The realisation.
    pub global: GlobalPayload,
    /// Hot spot index in the campaign.
    pub hot_spot_index: usize,
    /// Cache key of the global job whose hot-spot series this job loads.
    pub global_cache_key: String,
    /// A `strand_reduced` job: cache key of the calibration job of its hot spot.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub calibration_cache_key: Option<String>,
    /// An FE job of an `auto` campaign: it runs only if the campaign's reduced results select
    /// its sea state (`crate::fidelity::select_fe_sea_states`), else it ends at once with no
    /// results.
    #[serde(default, skip_serializing_if = "std::ops::Not::not")]
    pub if_selected: bool,
}

/// Input of a `calibrate` job: the reduced strand response of one hot spot over the load range
/// of the campaign's global jobs.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct CalibratePayload {
    /// Hot spot index in the campaign.
    pub hot_spot_index: usize,
    /// Cache keys of the global jobs whose hot-spot series set the load range.
    pub global_cache_keys: Vec<String>,
    /// The other hot spots whose series also set the load range (`strand.shared_calibration`:
    /// one calibration serves them all).
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub shared_with: Vec<usize>,
    /// A check: cache key of the calibration job this one keeps if that calibration's range
    /// covers the load range of `global_cache_keys`; otherwise this job calibrates over it
    /// (`strand.calibration_hs_fraction`).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub check_of: Option<String>,
}

impl CampaignInputs {
    /// The base case with one sea state, seed and the campaign's timing, wind and hot spots,
    /// at the campaign's `simulation.heading_deg`.
    pub fn case_for(&self, hs_m: f64, tp_s: f64, seed: u64) -> CaseSpec {
        self.case_at(hs_m, tp_s, seed, self.spec.simulation.heading_deg)
    }

    /// The base case of a global job's realisation, at its heading.
    pub fn case_of(&self, payload: &GlobalPayload) -> CaseSpec {
        self.case_at(
            payload.hs_m,
            payload.tp_s,
            payload.seed,
            payload.heading_deg(self),
        )
    }

    /// The base case with one sea state, seed and heading (deg) and the campaign's timing,
    /// wind and hot spots.
    pub fn case_at(&self, hs_m: f64, tp_s: f64, seed: u64, heading_deg: f64) -> CaseSpec {
        let sim = &self.spec.simulation;
        let mut case = self.base_case.clone();
        case.name = format!("{}_hs{hs_m}_tp{tp_s}_seed{seed}", self.spec.name);
        case.sea_state = SeaStateSpec {
            hs_m,
            tp_s,
            gamma: sim.gamma.clone(),
            seed,
            heading_deg,
        };
        case.timing.transient_s = sim.transient_s;
        case.timing.duration_s = sim.duration_s;
        case.timing.time_step_s = sim.time_step_s;
        case.timing.output_interval_s = sim.output_interval_s;
        case.timing.wave_ramp_s = sim
            .wave_ramp_s
            .unwrap_or(case.timing.wave_ramp_s)
            .min(sim.transient_s);
        if let Some(wind) = &sim.wind {
            case.wind = wind.clone();
        }
        case.hot_spots = self.spec.hot_spots.to_vec();
        case
    }

    /// sha256 (hex) of every input that decides results: all but names and free text.
    pub fn results_sha256(&self) -> String {
        let mut copy = self.clone();
        copy.spec.name.clear();
        copy.spec.about = None;
        copy.spec.design_life_years = 0.0;
        copy.spec.design_fatigue_factor = None;
        copy.base_case.name.clear();
        copy.base_case.about = None;
        let text = serde_json::to_string(&copy).unwrap_or_default();
        hex::encode(Sha256::digest(text.as_bytes()))
    }
}

impl CampaignInputs {
    /// sha256 (hex) of the inputs that decide a global job's results: the simulation settings,
    /// the hot spots, the base case (names and free text cleared) and the floater. Strand,
    /// fatigue, scatter and job settings are left out, so campaigns that differ only there
    /// share their global jobs through the cache.
    pub fn global_sha256(&self) -> String {
        let mut case = self.base_case.clone();
        case.name.clear();
        case.about = None;
        // which sea states get extra seeds does not change any global result
        let mut simulation = self.spec.simulation.clone();
        simulation.extra_seeds = None;
        let text =
            serde_json::to_string(&(&simulation, &self.spec.hot_spots, &case, &self.floater))
                .unwrap_or_default();
        hex::encode(Sha256::digest(text.as_bytes()))
    }
}

/// Cache key of a job: sha256 of kind, solver version, campaign inputs hash and payload.
pub fn cache_key(kind: &str, inputs_sha256: &str, payload_json: &str) -> String {
    let mut h = Sha256::new();
    for part in [kind, SOLVER_VERSION, inputs_sha256, payload_json] {
        h.update(part.as_bytes());
        h.update([0]);
    }
    hex::encode(h.finalize())
}
