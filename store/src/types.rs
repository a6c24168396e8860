//! Typed identifiers and the closed sets stored as text: job state, job kind, attempt outcome.
//!
//! Ids are the database's integer keys wrapped so that a job id cannot be passed where a
//! campaign id is expected. States and kinds are enums with `Display`/`FromStr` giving the exact
//! text stored in the `jobs.state` and `jobs.kind` columns.

use serde::{Deserialize, Serialize};
use std::fmt;
use std::str::FromStr;

/// Text in a column that names no value of its enum.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
#[error("unknown value {value:?} in {field}")]
pub struct UnknownValue {
    /// Table and column.
    pub field: &'static str,
    /// The text found.
    pub value: String,
}

macro_rules! integer_id {
    ($(#[$doc:meta])* $name:ident) => {
        $(#[$doc])*
        #[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord, Hash, Serialize, Deserialize)]
        pub struct $name(pub i64);

        impl fmt::Display for $name {
            fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
                write!(f, "{}", self.0)
            }
        }
    };
}

integer_id!(
    /// Key of a row of `campaigns`.
    CampaignId
);
integer_id!(
    /// Key of a row of `sea_states`.
    SeaStateId
);
integer_id!(
    /// Key of a row of `jobs`.
    JobId
);
integer_id!(
    /// Key of a row of `attempts`.
    AttemptId
);

/// Identity of a worker process (a UUID, stored as text in `workers.id`).
#[derive(Debug, Clone, PartialEq, Eq, Hash, Serialize, Deserialize)]
pub struct WorkerId(pub String);

impl fmt::Display for WorkerId {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(&self.0)
    }
}

/// Secret of one claim: completion, failure and heartbeat succeed only while the job row still
/// holds this token (a UUID, stored as text in `jobs.lease_token`).
#[derive(Debug, Clone, PartialEq, Eq, Hash, Serialize, Deserialize)]
pub struct LeaseToken(pub String);

impl fmt::Display for LeaseToken {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(&self.0)
    }
}

/// Defines a text-backed enum with its `Display`, `FromStr` and list of all values. A value
/// written `Variant => "text" if cfg(…)` exists only where the condition holds.
macro_rules! text_enum {
    ($(#[$doc:meta])* $name:ident, $field:literal { $($(#[$vdoc:meta])* $variant:ident => $text:literal $(if cfg($cfg:meta))?),+ $(,)? }) => {
        $(#[$doc])*
        #[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Serialize, Deserialize)]
        #[serde(rename_all = "snake_case")]
        pub enum $name {
            $($(#[$vdoc])* $(#[cfg($cfg)])? $variant),+
        }

        impl $name {
            /// Every value, in declaration order.
            pub const ALL: &'static [$name] = &[$($(#[cfg($cfg)])? $name::$variant),+];

            /// The text stored in the database.
            pub fn as_str(self) -> &'static str {
                match self {
                    $($(#[cfg($cfg)])? $name::$variant => $text),+
                }
            }
        }

        impl fmt::Display for $name {
            fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
                f.write_str(self.as_str())
            }
        }

        impl FromStr for $name {
            type Err = UnknownValue;

            fn from_str(text: &str) -> Result<Self, Self::Err> {
                match text {
                    $($(#[cfg($cfg)])? $text => Ok($name::$variant),)+
                    other => Err(UnknownValue {
                        field: $field,
                        value: other.to_owned(),
                    }),
                }
            }
        }
    };
}

text_enum!(
    /// Life cycle of a job: `blocked → ready → running → done`, plus `failed` and `cancelled`.
    JobState, "jobs.state" {
        /// Waits for at least one dependency that is not done.
        Blocked => "blocked",
        /// May be claimed (once `not_before` has passed).
        Ready => "ready",
        /// Leased by a worker.
        Running => "running",
        /// Finished; its results are stored.
        Done => "done",
        /// Deterministic error, attempts exhausted, lost too often, or an upstream job failed.
        Failed => "failed",
        /// Its campaign was cancelled.
        Cancelled => "cancelled",
    }
);

impl JobState {
    /// Whether the job will never change state again.
    pub fn is_terminal(self) -> bool {
        matches!(
            self,
            JobState::Done | JobState::Failed | JobState::Cancelled
        )
    }
}

text_enum!(
    /// What a job computes.
    JobKind, "jobs.kind" {
        /// Floater and mooring lines for one (sea state, seed): T(t), κ(t) at the hot spots.
        Global => "global",
        /// Detailed strand model for one (sea state, seed, hot spot) on its global load history.
        Strand => "strand",
        /// The reduced strand response of one hot spot calibrated on its FE model over the
        /// load range of every global job of the campaign.
        Calibrate => "calibrate",
        /// The reduced strand response for one (sea state, seed, hot spot).
        StrandReduced => "strand_reduced",
        /// Queue exercise only (sleep, succeed, fail); never reaches users' results. Built with
        /// the `test-support` feature only.
        Test => "test" if cfg(feature = "test-support"),
    }
);

text_enum!(
    /// How one claim of a job ended (`attempts.outcome`).
    AttemptOutcome, "attempts.outcome" {
        /// Completed with fresh results.
        Done => "done",
        /// Completed by reusing the results of a done job with the same cache key.
        Cached => "cached",
        /// Failed with an error worth retrying.
        TransientFailure => "transient_failure",
        /// Failed deterministically.
        PermanentFailure => "permanent_failure",
        /// The lease expired without completion (worker crashed, hung or was cut off).
        Lost => "lost",
        /// The campaign was cancelled while the job ran.
        Cancelled => "cancelled",
    }
);

text_enum!(
    /// Whether a campaign still runs.
    CampaignState, "campaigns.state" {
        /// Jobs may be claimed.
        Active => "active",
        /// Every unfinished job was cancelled.
        Cancelled => "cancelled",
    }
);

text_enum!(
    /// Why a job failed (`jobs.error_class`): the stage's failure reports, and the store's own
    /// verdicts on lost and orphaned jobs.
    FailureClass, "jobs.error_class" {
        /// The campaign row named by a job does not exist.
        UnknownCampaign => "unknown_campaign",
        /// The campaign's stored inputs cannot be read.
        BadCampaign => "bad_campaign",
        /// The job's payload cannot be read.
        BadPayload => "bad_payload",
        /// The global case built from the campaign and the sea state is invalid.
        InvalidCase => "invalid_case",
        /// The global stage did not converge after every step cut-back.
        GlobalDiverged => "global_diverged",
        /// The global stage produced a non-finite value.
        GlobalNonFinite => "global_non_finite",
        /// The strand model built from the campaign is invalid.
        InvalidStrand => "invalid_strand",
        /// The strand history run failed.
        StrandHistory => "strand_history",
        /// The damage inputs could not be computed.
        DamageInputs => "damage_inputs",
        /// The results could not be serialised.
        SerialiseResults => "serialise_results",
        /// The upstream job's results are missing.
        UpstreamMissing => "upstream_missing",
        /// A stored artifact cannot be read as what it should hold.
        BadArtifact => "bad_artifact",
        /// Reading or writing the artifact directory failed.
        ArtifactIo => "artifact_io",
        /// The store could not be reached.
        Store => "store",
        /// The stage panicked.
        WorkerPanic => "worker_panic",
        /// A job it depends on failed.
        UpstreamFailed => "upstream_failed",
        /// Its lease expired too many times.
        Lost => "lost",
        /// The test job kind's transient failure.
        TestTransient => "test_transient" if cfg(feature = "test-support"),
        /// The test job kind's permanent failure.
        TestPermanent => "test_permanent" if cfg(feature = "test-support"),
    }
);

/// What an artifact is to the job that stored it: the text of `job_artifacts.role`. The stored
/// texts are those of earlier versions, so existing stores read; a text this version does not
/// know (another build's, a test's) is kept as it is ([`ArtifactRole::Other`]).
#[derive(Debug, Clone, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub enum ArtifactRole {
    /// A global job's T(t), κ(t) series of hot spot `i` (`moorfret_solver::global::series`),
    /// `hot_spot_<i>_series`.
    HotSpotSeries(usize),
    /// A strand job's per-contact records (JSON), `contact_records`.
    ContactRecords,
    /// A strand job's checkpoint (its pointer file names the newest), `checkpoint`.
    Checkpoint,
    /// A calibration job's reduced strand response, `reduced_strand`.
    ReducedStrand,
    /// Any other text, as stored.
    Other(String),
}

impl ArtifactRole {
    const SERIES_PREFIX: &'static str = "hot_spot_";
    const SERIES_SUFFIX: &'static str = "_series";

    /// The stored text.
    pub fn as_str(&self) -> std::borrow::Cow<'static, str> {
        use std::borrow::Cow;
        match self {
            Self::HotSpotSeries(i) => {
                Cow::Owned(format!("{}{i}{}", Self::SERIES_PREFIX, Self::SERIES_SUFFIX))
            }
            Self::ContactRecords => Cow::Borrowed("contact_records"),
            Self::Checkpoint => Cow::Borrowed("checkpoint"),
            Self::ReducedStrand => Cow::Borrowed("reduced_strand"),
            Self::Other(text) => Cow::Owned(text.clone()),
        }
    }

    /// The role of a stored text (never fails: an unknown text is [`ArtifactRole::Other`]).
    pub fn parse(text: &str) -> Self {
        match text {
            "contact_records" => Self::ContactRecords,
            "checkpoint" => Self::Checkpoint,
            "reduced_strand" => Self::ReducedStrand,
            _ => text
                .strip_prefix(Self::SERIES_PREFIX)
                .and_then(|t| t.strip_suffix(Self::SERIES_SUFFIX))
                .filter(|i| i.bytes().all(|b| b.is_ascii_digit()))
                .and_then(|i| i.parse().ok())
                .filter(|&i: &usize| Self::HotSpotSeries(i).as_str() == text)
                .map_or_else(|| Self::Other(text.to_owned()), Self::HotSpotSeries),
        }
    }

    /// The hot spot of a series artifact.
    pub fn hot_spot_series(&self) -> Option<usize> {
        match self {
            Self::HotSpotSeries(i) => Some(*i),
            _ => None,
        }
    }
}

impl fmt::Display for ArtifactRole {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(&self.as_str())
    }
}

impl FromStr for ArtifactRole {
    type Err = std::convert::Infallible;

    fn from_str(text: &str) -> Result<Self, Self::Err> {
        Ok(Self::parse(text))
    }
}

impl Serialize for ArtifactRole {
    fn serialize<S: serde::Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
        s.serialize_str(&self.as_str())
    }
}

impl<'de> Deserialize<'de> for ArtifactRole {
    fn deserialize<D: serde::Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        Ok(Self::parse(&String::deserialize(d)?))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_state_and_kind_round_trips_through_its_text() {
        for state in JobState::ALL {
            assert_eq!(state.as_str().parse::<JobState>().unwrap(), *state);
        }
        for kind in JobKind::ALL {
            assert_eq!(kind.to_string().parse::<JobKind>().unwrap(), *kind);
        }
        for outcome in AttemptOutcome::ALL {
            assert_eq!(
                outcome.as_str().parse::<AttemptOutcome>().unwrap(),
                *outcome
            );
        }
    }

    #[test]
    fn unknown_text_names_the_column_and_the_value() {
        match "sleeping".parse::<JobState>() {
            Err(UnknownValue { field, value }) => {
                assert_eq!(field, "jobs.state");
                assert_eq!(value, "sleeping");
            }
            other => panic!("unexpected {other:?}"),
        }
    }

    #[test]
    fn artifact_roles_read_and_write_their_stored_texts() {
        for (role, text) in [
            (ArtifactRole::HotSpotSeries(0), "hot_spot_0_series"),
            (ArtifactRole::HotSpotSeries(12), "hot_spot_12_series"),
            (ArtifactRole::ContactRecords, "contact_records"),
            (ArtifactRole::Checkpoint, "checkpoint"),
            (ArtifactRole::ReducedStrand, "reduced_strand"),
        ] {
            assert_eq!(role.as_str(), text);
            assert_eq!(ArtifactRole::parse(text), role);
            let json = serde_json::to_string(&role).unwrap();
            assert_eq!(json, format!("\"{text}\""));
            assert_eq!(serde_json::from_str::<ArtifactRole>(&json).unwrap(), role);
        }
        // texts of no known role are kept as they are, to be written back unchanged
        for text in [
            "hotspots.csv",
            "hot_spot_x_series",
            "hot_spot_01_series",
            "hot_spot__series",
        ] {
            assert_eq!(ArtifactRole::parse(text), ArtifactRole::Other(text.into()));
            assert_eq!(ArtifactRole::parse(text).as_str(), text);
        }
        assert_eq!(
            ArtifactRole::parse("hot_spot_3_series").hot_spot_series(),
            Some(3)
        );
        assert_eq!(ArtifactRole::Checkpoint.hot_spot_series(), None);
    }
}
