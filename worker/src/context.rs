//! What a stage of a claimed job needs beyond its payload.

use tokio::runtime::Handle;

use moorfret_campaign::CampaignInputs;
use moorfret_store::{ArtifactStore, Lease, RetryPolicy, Store};

/// The campaign's inputs, the running job, the store and how its calls are retried, the
/// artifact store, and the runtime the store calls run on.
#[derive(Clone, Copy)]
pub struct StageContext<'a> {
    /// The campaign's inputs.
    pub inputs: &'a CampaignInputs,
    /// The running job.
    pub lease: &'a Lease,
    /// The store.
    pub store: &'a Store,
    /// How store calls are retried.
    pub retry: &'a RetryPolicy,
    /// The artifact store.
    pub artifacts: &'a ArtifactStore,
    /// The runtime the store calls run on.
    pub rt: &'a Handle,
}
