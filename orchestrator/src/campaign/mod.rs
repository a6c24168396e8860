//! Campaigns (DESIGN §3.1-3.2): the campaign file, its resolution against the files it names,
//! and planning into sea states and jobs.
//!
//! - [`spec`]: the campaign file (serde, units in names) and its checks;
//! - [`resolve`]: read and hash every referenced file, parse and check them; nothing is
//!   written anywhere for a bad campaign;
//! - [`payload`]: the stored campaign inputs and the per-job payloads workers run from, cache
//!   keys;
//! - [`plan`]: scatter diagram → sea states (bin centres, seeds drawn once) → jobs;
//! - [`error`]: the error type, [`CampaignError`].
//!
//! [`create`] stores a resolved campaign with its whole plan in one transaction.

pub mod error;
pub mod fatigue;
pub mod payload;
pub mod plan;
pub mod resolve;
pub mod spec;

pub use error::CampaignError;
pub use payload::{CampaignInputs, GlobalPayload, StrandPayload};
pub use resolve::{resolve, ResolvedCampaign};
pub use spec::CampaignSpec;

use crate::store::{CampaignId, JobId, NewCampaign, Store, StoreError};

/// Stores `resolved` with its sea states and jobs in one transaction; returns the campaign and
/// its job ids.
pub async fn create(
    store: &Store,
    resolved: &ResolvedCampaign,
) -> Result<(CampaignId, Vec<JobId>), StoreError> {
    let inputs = &resolved.inputs;
    let (spec, spec_sha256) = resolved.stored_spec();
    let sea_states = plan::sea_states(
        &resolved.scatter,
        inputs.spec.scatter.reading,
        inputs.spec.simulation.seeds_per_sea_state,
        inputs.spec.seed,
    );
    let inputs_sha256 = inputs.results_sha256();
    let campaign = NewCampaign {
        name: inputs.spec.name.clone(),
        spec,
        spec_sha256,
    };
    store
        .create_planned_campaign(&campaign, &sea_states, |ids| {
            plan::jobs(inputs, &inputs_sha256, &sea_states, ids)
        })
        .await
}

/// The inputs stored with a campaign (`campaigns.spec_json`).
pub fn stored_inputs(spec: &serde_json::Value) -> Result<CampaignInputs, CampaignError> {
    let inputs = spec.get("inputs").cloned().unwrap_or_default();
    serde_json::from_value(inputs).map_err(|e| CampaignError::Json {
        message: format!("stored campaign inputs: {e}"),
    })
}
