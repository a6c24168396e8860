//! Runs one claimed job on the calling (blocking) thread: decodes its payload and calls its
//! stage. Store reads a stage needs (the upstream series of a strand job) go through `rt`,
//! retried under the worker's [`RetryPolicy`].

use tokio::runtime::Handle;

use crate::context::StageContext;
use crate::failure::permanent;
use crate::gate::extra_seed_gate;
use crate::{global_stage, reduced_stage, strand_stage};
use moorfret_campaign::{CalibratePayload, CampaignInputs, GlobalPayload, StrandPayload};
use moorfret_store::{
    ArtifactStore, FailureClass, JobFailure, JobKind, JobResults, Lease, RetryPolicy, Store,
};

fn decode<T: serde::de::DeserializeOwned>(lease: &Lease) -> Result<T, JobFailure> {
    serde_json::from_value(lease.payload.clone()).map_err(|e| {
        permanent(
            FailureClass::BadPayload,
            format!("job {} ({}): payload: {e}", lease.job, lease.kind),
        )
    })
}

/// Runs the job of `lease`. `inputs` are its campaign's (absent for test jobs); `retry` is how
/// the stage's store reads are retried. A job of an extra seed first passes its gate
/// ([`crate::gate`]) and ends at once, with no rows, if its sea state is not selected.
pub fn execute(
    lease: &Lease,
    inputs: Option<&CampaignInputs>,
    store: &Store,
    retry: &RetryPolicy,
    artifacts: &ArtifactStore,
    rt: &Handle,
) -> Result<JobResults, JobFailure> {
    let need_inputs = || {
        inputs.ok_or_else(|| permanent(FailureClass::BadCampaign, "campaign inputs are missing"))
    };
    let context = |inputs| StageContext {
        inputs,
        lease,
        store,
        retry,
        artifacts,
        rt,
    };
    let gate = |inputs, global, hot_spot| extra_seed_gate(&context(inputs), global, hot_spot);
    match lease.kind {
        #[cfg(feature = "test-support")]
        JobKind::Test => run_test(lease),
        JobKind::Global => {
            let payload: GlobalPayload = decode(lease)?;
            if payload.extra_seed {
                if let Some(ended) = gate(need_inputs()?, &payload, None)? {
                    return Ok(ended);
                }
            }
            global_stage::run_global(need_inputs()?, &payload, artifacts)
        }
        JobKind::Strand => {
            let payload: StrandPayload = decode(lease)?;
            if payload.global.extra_seed {
                let hot_spot = Some(payload.hot_spot_index);
                if let Some(ended) = gate(need_inputs()?, &payload.global, hot_spot)? {
                    return Ok(ended);
                }
            }
            strand_stage::run_strand(&context(need_inputs()?), &payload)
        }
        JobKind::Calibrate => {
            let payload: CalibratePayload = decode(lease)?;
            reduced_stage::run_calibrate(&context(need_inputs()?), &payload)
        }
        JobKind::StrandReduced => {
            let payload: StrandPayload = decode(lease)?;
            if payload.global.extra_seed {
                let hot_spot = Some(payload.hot_spot_index);
                if let Some(ended) = gate(need_inputs()?, &payload.global, hot_spot)? {
                    return Ok(ended);
                }
            }
            reduced_stage::run_strand_reduced(&context(need_inputs()?), &payload)
        }
        // the store's test job kind when the store is built with its test support and this
        // crate without (a build of the store's and the worker's tests alone)
        #[allow(unreachable_patterns)]
        other => Err(permanent(
            FailureClass::BadPayload,
            format!("job kind {other} is not run by this worker build"),
        )),
    }
}

/// The test job kind: sleep, fail or crash as its payload says.
#[cfg(feature = "test-support")]
fn run_test(lease: &Lease) -> Result<JobResults, JobFailure> {
    use moorfret_store::TestPayload;
    let payload: TestPayload = decode(lease)?;
    match payload {
        TestPayload::Sleep { duration_ms } => {
            std::thread::sleep(std::time::Duration::from_millis(duration_ms));
        }
        TestPayload::Crash => {
            tracing::error!(job = %lease.job, "test job: aborting the worker process");
            std::process::abort();
        }
        _ => {}
    }
    if let Some(failure) = payload.failure_on_attempt(lease.attempt) {
        return Err(failure);
    }
    Ok(JobResults {
        result: serde_json::json!({ "test": payload }),
        ..JobResults::default()
    })
}
