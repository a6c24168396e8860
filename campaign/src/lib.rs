//! # moorfret-campaign
//!
//! Campaign files (`docs/campaign-files.md`) and what a worker runs from: the contract between the
//! orchestrator, which reads and plans a campaign, and the workers, which run its jobs.
//!
//! - [`spec`]: the campaign file (serde, units in names) and its checks;
//! - [`fatigue`]: the fatigue settings (run-in, T-N curves, fretting damage law);
//! - [`fidelity`]: the strand model of the strand jobs (FE, reduced, auto) and the `auto`
//!   selection of the sea states that also run FE;
//! - [`seeds`]: the extra seeds of the sea states that carry most of the damage
//!   (`simulation.extra_seeds`) and their selection;
//! - [`stiffness`]: the EA of the strand jobs' tension → strain conversion and its cache;
//! - [`resolve`]: read and hash every referenced file, parse and check them; nothing is
//!   written anywhere for a bad campaign;
//! - [`payload`]: the stored campaign inputs and the per-job payloads workers run from, cache
//!   keys;
//! - [`error`]: the error type, [`CampaignError`].

pub mod design;
pub mod error;
pub mod fatigue;
pub mod fidelity;
pub mod mild_seas;
pub mod payload;
pub mod resolve;
pub mod screening;
pub mod sea_limits;
pub mod sectors;
pub mod seeds;
pub mod spec;
pub mod stiffness;

pub use error::CampaignError;
pub use payload::{CalibratePayload, CampaignInputs, GlobalPayload, StrandPayload};
pub use resolve::{resolve, ResolvedCampaign};
pub use spec::CampaignSpec;

/// The inputs stored with a campaign (`campaigns.spec_json`).
pub fn stored_inputs(spec: &serde_json::Value) -> Result<CampaignInputs, CampaignError> {
    let inputs = spec.get("inputs").cloned().unwrap_or_default();
    serde_json::from_value(inputs).map_err(|e| CampaignError::Json {
        message: format!("stored campaign inputs: {e}"),
    })
}
