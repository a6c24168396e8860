//! What a stage of a claimed job needs beyond its payload.

use std::future::Future;

use tokio::runtime::Handle;

use crate::failure::transient;
use moorfret_campaign::CampaignInputs;
use moorfret_store::{
    ArtifactStore, FailureClass, JobFailure, Lease, RetryPolicy, Store, StoreError,
};

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

impl StageContext<'_> {
    /// Runs a store call on the runtime under the retry policy; a store that stays unreachable
    /// is a transient failure of the job. `operation` names the call in the log.
    pub fn store_call<T, F, Fut>(&self, operation: &str, call: F) -> Result<T, JobFailure>
    where
        F: FnMut() -> Fut,
        Fut: Future<Output = Result<T, StoreError>>,
    {
        self.rt
            .block_on(self.retry.run(operation, call))
            .map_err(|e| transient(FailureClass::Store, e))
    }
}
