//! Records exchanged with the store: what is planned, what a claim hands out, what a job
//! returns, and what queries report.
//!
//! JSON values (`spec`, `payload`, result details) are `serde_json::Value`; the store keeps them
//! as text. Units are carried in field names.

use serde::{Deserialize, Serialize};
use serde_json::Value;

use super::results::{ClassDamageInput, DamageInput};
use super::types::{
    ArtifactRole, AttemptId, AttemptOutcome, CampaignId, CampaignState, FailureClass, JobId,
    JobKind, JobState, LeaseToken, SeaStateId, WorkerId,
};

/// A campaign to create: its name and resolved specification.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct NewCampaign {
    /// Unique name.
    pub name: String,
    /// Resolved specification (every file reference already hashed).
    pub spec: Value,
    /// sha256 (hex) of the resolved specification.
    pub spec_sha256: String,
}

/// A sea state of a campaign's plan.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct NewSeaState {
    /// Position in the campaign's list of sea states.
    pub index: i64,
    /// Significant wave height, m.
    pub hs_m: f64,
    /// Peak period, s.
    pub tp_s: f64,
    /// Fraction of the year this sea state occurs, in [0, 1].
    pub occurrence_fraction: f64,
    /// Random seeds of its realisations, drawn once at planning.
    pub seeds: Vec<u64>,
    /// Wave heading (deg, from +x towards +y).
    pub heading_deg: f64,
    /// Directional sector of the climate it belongs to; `None` for a climate of one table.
    pub sector: Option<String>,
    /// Fraction of its spectrum's variance m0 the global stage's wave cut-off keeps, computed
    /// at planning (`None` when not computed).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub wave_energy_kept: Option<f64>,
}

/// A job of a plan. Dependencies refer to jobs earlier in the same plan.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct PlannedJob {
    /// What the job computes.
    pub kind: JobKind,
    /// Sea state it belongs to, if any.
    pub sea_state: Option<SeaStateId>,
    /// Kind-specific input.
    pub payload: Value,
    /// Higher runs first.
    pub priority: i64,
    /// Estimated run time, s (a worker skips jobs longer than its remaining wall time).
    pub expected_cost_s: f64,
    /// Attempts before a transiently failing job is failed, ≥ 1.
    pub max_attempts: i64,
    /// Hash of every input deciding the result, if results may be shared.
    pub cache_key: Option<String>,
    /// Indices (into the plan) of the jobs that must be done first.
    pub depends_on: Vec<usize>,
}

impl PlannedJob {
    /// A job with default priority, cost and attempts, no cache key and no dependencies.
    pub fn new(kind: JobKind, payload: Value) -> Self {
        Self {
            kind,
            sea_state: None,
            payload,
            priority: 0,
            expected_cost_s: 0.0,
            max_attempts: 3,
            cache_key: None,
            depends_on: Vec::new(),
        }
    }
}

/// Who is claiming: recorded with every attempt.
#[derive(Debug, Clone, PartialEq, Eq, Serialize, Deserialize)]
pub struct WorkerInfo {
    /// Host name.
    pub host: String,
    /// Process id.
    pub pid: i64,
    /// Software version.
    pub version: String,
}

/// Which jobs a worker accepts.
#[derive(Debug, Clone, Default, PartialEq, Serialize, Deserialize)]
pub struct ClaimFilter {
    /// Only these kinds (all kinds if empty).
    pub kinds: Vec<JobKind>,
    /// Only jobs expected to finish within this time, s (no limit if `None`).
    pub max_expected_cost_s: Option<f64>,
}

/// A claimed job and the lease that lets its worker report on it.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Lease {
    /// The job.
    pub job: JobId,
    /// Its campaign.
    pub campaign: CampaignId,
    /// Its sea state.
    pub sea_state: Option<SeaStateId>,
    /// What it computes.
    pub kind: JobKind,
    /// Its input.
    pub payload: Value,
    /// Counted attempt number (1 for the first; lost leases are not counted).
    pub attempt: i64,
    /// Attempt limit.
    pub max_attempts: i64,
    /// Cache key, if any.
    pub cache_key: Option<String>,
    /// The token guarding every report on this claim.
    pub token: LeaseToken,
    /// Lease end, ms since the epoch; renew by heartbeat before it.
    pub expires_at_ms: i64,
    /// Row of `attempts` recording this claim.
    pub attempt_id: AttemptId,
    /// The claiming worker.
    pub worker: WorkerId,
}

/// Results of a hot spot (extremes, ranges, load-history artifact hashes).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct HotSpotSummary {
    /// Hot spot index in the campaign.
    pub hot_spot_index: i64,
    /// Summary values.
    pub summary: Value,
}

/// Fretting statistics of one contact.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct ContactStatistics {
    /// Hot spot index in the campaign.
    pub hot_spot_index: i64,
    /// Contact index in the strand model.
    pub contact_index: i64,
    /// Layer interface (0: core / layer 1, k: layer k / layer k+1).
    pub layer_interface: i64,
    /// Angular position θ in the cross section, rad (+π/2 outer arc).
    pub angular_position_rad: f64,
    /// Rainflow histograms and fretting indicators.
    pub statistics: Value,
}

/// An artifact produced by a job.
#[derive(Debug, Clone, PartialEq, Eq, Serialize, Deserialize)]
pub struct JobArtifact {
    /// Role of the artifact for the job.
    pub role: ArtifactRole,
    /// sha256 (hex) of its content.
    pub sha256: String,
    /// Size in bytes.
    pub size_bytes: i64,
    /// Path relative to the artifact directory.
    pub path: String,
}

/// Everything a job hands back on completion; stored in one transaction.
#[derive(Debug, Clone, Default, PartialEq, Serialize, Deserialize)]
pub struct JobResults {
    /// Small job-level result (also hashed into `result_sha256`).
    pub result: Value,
    /// Per hot spot summaries.
    pub hot_spots: Vec<HotSpotSummary>,
    /// Per contact statistics.
    pub contacts: Vec<ContactStatistics>,
    /// Per realisation damage inputs.
    pub damage_inputs: Vec<DamageInput>,
    /// Per realisation damage inputs of each contact class (the worker's `damage_rows`).
    #[serde(default)]
    pub class_damage_inputs: Vec<ClassDamageInput>,
    /// Artifacts written beforehand.
    pub artifacts: Vec<JobArtifact>,
}

/// Whether a failure may go away by retrying.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
pub enum FailureKind {
    /// Retry after backoff while attempts remain.
    Transient,
    /// Fail now (bad input, divergence after every fallback).
    Permanent,
}

/// A failure report.
#[derive(Debug, Clone, PartialEq, Eq, Serialize, Deserialize)]
pub struct JobFailure {
    /// Retry or not.
    pub kind: FailureKind,
    /// Why it failed.
    pub error_class: FailureClass,
    /// Full diagnostic.
    pub message: String,
}

/// What happened to a job after a failure report.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
pub enum FailureDisposition {
    /// Back to ready, claimable from `not_before_ms`.
    Retry {
        /// Earliest next claim, ms since the epoch.
        not_before_ms: i64,
    },
    /// Failed for good; `dependents_failed` downstream jobs failed with it.
    Failed {
        /// Number of blocked jobs failed because they depended on it.
        dependents_failed: u64,
    },
}

/// What a sweep of expired leases did.
#[derive(Debug, Clone, Default, PartialEq, Eq, Serialize, Deserialize)]
pub struct SweepReport {
    /// Jobs returned to ready.
    pub requeued: Vec<JobId>,
    /// Jobs failed because they were lost `max_lost` times.
    pub failed: Vec<JobId>,
}

/// What cancelling a campaign did.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq, Serialize, Deserialize)]
pub struct CancelReport {
    /// Jobs moved to cancelled (running ones included; their workers lose their leases).
    pub jobs_cancelled: u64,
}

/// A job row as stored.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct JobRecord {
    /// Id.
    pub id: JobId,
    /// Campaign.
    pub campaign: CampaignId,
    /// Sea state.
    pub sea_state: Option<SeaStateId>,
    /// Kind.
    pub kind: JobKind,
    /// State.
    pub state: JobState,
    /// Input.
    pub payload: Value,
    /// Counted attempts.
    pub attempt: i64,
    /// Attempt limit.
    pub max_attempts: i64,
    /// Times its lease expired.
    pub lost_count: i64,
    /// Current lease token, while running.
    pub lease_token: Option<String>,
    /// Lease end, while running.
    pub lease_expires_at_ms: Option<i64>,
    /// Worker holding or last holding it.
    pub worker: Option<WorkerId>,
    /// Priority.
    pub priority: i64,
    /// Cache key.
    pub cache_key: Option<String>,
    /// Job-level result, once done.
    pub result: Option<Value>,
    /// sha256 of the job-level result text, once done.
    pub result_sha256: Option<String>,
    /// Source of reused results, if completed from the cache.
    pub cached_from: Option<JobId>,
    /// Error class of the last failure.
    pub error_class: Option<FailureClass>,
    /// Diagnostic of the last failure.
    pub error_message: Option<String>,
    /// Earliest next claim, ms since the epoch.
    pub not_before_ms: i64,
}

/// An `attempts` row.
#[derive(Debug, Clone, PartialEq, Eq, Serialize, Deserialize)]
pub struct AttemptRecord {
    /// Id.
    pub id: AttemptId,
    /// Job.
    pub job: JobId,
    /// 1 for the first claim of the job, counting lost ones.
    pub claim_number: i64,
    /// Worker.
    pub worker: WorkerId,
    /// Host of the worker.
    pub host: String,
    /// Process id of the worker.
    pub pid: i64,
    /// Claim time, ms since the epoch.
    pub started_at_ms: i64,
    /// End time, if ended.
    pub ended_at_ms: Option<i64>,
    /// How it ended, if ended.
    pub outcome: Option<AttemptOutcome>,
}

/// Progress of a campaign (`campaign_progress` view).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct CampaignProgress {
    /// Campaign.
    pub campaign: CampaignId,
    /// Name.
    pub name: String,
    /// Jobs in total.
    pub jobs_total: i64,
    /// Jobs per state, in [`JobState::ALL`] order.
    pub jobs_by_state: Vec<(JobState, i64)>,
    /// Sum of the occurrence fractions of planned sea states.
    pub occurrence_planned: f64,
    /// Sum of the occurrence fractions of sea states whose jobs are all done.
    pub occurrence_covered: f64,
}

impl CampaignProgress {
    /// Jobs in `state`.
    pub fn count(&self, state: JobState) -> i64 {
        self.jobs_by_state
            .iter()
            .find(|(s, _)| *s == state)
            .map_or(0, |(_, n)| *n)
    }
}

/// Annual damage of one hot spot and measure (`lifetime_damage` view).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct LifetimeDamage {
    /// Hot spot index in the campaign.
    pub hot_spot_index: i64,
    /// Damage measure.
    pub measure: String,
    /// Σ occurrence × (year / T_eff) × seed-mean damage, per year.
    pub annual_damage: f64,
    /// Fraction of the year the contributing sea states cover.
    pub occurrence_covered: f64,
    /// Number of contributing sea states.
    pub sea_states: i64,
    /// The seed band of `annual_damage`.
    #[serde(flatten)]
    pub band: crate::results::SeedBand,
}

/// A `campaigns` row.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct CampaignRecord {
    /// Id.
    pub id: CampaignId,
    /// Unique name.
    pub name: String,
    /// Resolved specification.
    pub spec: Value,
    /// sha256 (hex) of the resolved specification.
    pub spec_sha256: String,
    /// Active or cancelled.
    pub state: CampaignState,
    /// Creation time, ms since the epoch.
    pub created_at_ms: i64,
}
