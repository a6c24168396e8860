//! The worker loop (ARCHITECTURE.md, "Data flow of a campaign"): claim a job, run it, heartbeat,
//! complete.
//!
//! [`run`] takes its store, artifact store, settings and a shutdown signal as arguments (the
//! `moorfret worker` / `moorfret-worker` binaries wire SIGTERM/SIGINT to it). Per job:
//!
//! 1. a job whose cache key matches a done job (any campaign) is completed from it;
//! 2. otherwise the stage runs on a blocking thread ([`execute`]) while a tokio task renews
//!    the lease every `heartbeat_interval_ms`;
//! 3. results are stored by [`Store::complete`] in one transaction guarded by the lease token
//!    (a worker whose lease was swept away discards its results); failures are reported as
//!    transient (retried with backoff) or permanent (failed at once with the diagnostic);
//! 4. on a shutdown signal the running job's lease is released without consuming an attempt
//!    and the loop returns.
//!
//! Between claims the worker sweeps expired leases back to the queue, so crashed workers' jobs
//! are picked up by the survivors without any coordinator.
//!
//! Every store call goes through the configured [`RetryPolicy`] (completion through
//! [`complete_with_retry`]; the strand stage's reads of its upstream results too), so a
//! database restart or a short network outage is waited out instead of ending the worker. The
//! heartbeat is the exception: it is repeated every interval anyway, so a failed one is logged
//! and the next beat tries again. With a [`WallTimeBudget`] only jobs whose expected cost fits
//! in the remaining wall time are claimed.

use std::collections::HashMap;
use std::sync::Arc;
use std::time::Duration;

use tokio::sync::watch;

use crate::failure::{permanent, transient};
use moorfret_campaign::{stored_inputs, CampaignInputs};
use moorfret_store::{
    complete_with_retry, ArtifactStore, CampaignId, ClaimFilter, FailureClass, FailureDisposition,
    JobFailure, JobKind, JobState, Lease, RetryPolicy, Store, StoreError, WallTimeBudget,
    WorkerInfo,
};

/// Settings of a worker.
#[derive(Debug, Clone)]
pub struct WorkerConfig {
    /// Job kinds this worker takes (all if empty).
    pub kinds: Vec<JobKind>,
    /// Pause between claims when nothing is ready.
    pub idle_poll: Duration,
    /// Return once no campaign has ready, running or blocked jobs left.
    pub exit_when_idle: bool,
    /// Wall time of this worker's allocation (batch schedulers): jobs expected to run past
    /// it are not claimed ([`moorfret_store::wall_time`]).
    pub wall_time: Option<WallTimeBudget>,
    /// How store calls are retried while the database is unreachable.
    pub retry: RetryPolicy,
}

impl Default for WorkerConfig {
    fn default() -> Self {
        Self {
            kinds: Vec::new(),
            idle_poll: Duration::from_millis(500),
            exit_when_idle: false,
            wall_time: None,
            retry: RetryPolicy::default(),
        }
    }
}

/// What a worker did.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct WorkerSummary {
    /// Jobs completed with fresh results.
    pub completed: u64,
    /// Jobs completed from the cache.
    pub cached: u64,
    /// Failure reports (transient and permanent).
    pub failed: u64,
    /// Results discarded because the lease was lost.
    pub lost: u64,
    /// Whether it stopped on the shutdown signal.
    pub stopped_by_signal: bool,
}

/// Identity of this process for the `workers` and `attempts` tables.
pub fn this_process() -> WorkerInfo {
    let host = std::fs::read_to_string("/proc/sys/kernel/hostname")
        .map(|h| h.trim().to_owned())
        .unwrap_or_else(|_| "unknown".into());
    WorkerInfo {
        host,
        pid: i64::from(std::process::id()),
        version: env!("CARGO_PKG_VERSION").to_owned(),
    }
}

/// Whether any campaign still has work that may become claimable (of `kinds`, all if empty).
async fn work_remains(
    store: &Store,
    retry: &RetryPolicy,
    kinds: &[JobKind],
) -> Result<bool, StoreError> {
    let open = |s: &JobState| matches!(s, JobState::Ready | JobState::Running | JobState::Blocked);
    for campaign in retry.run("list campaigns", || store.campaigns()).await? {
        if !kinds.is_empty() {
            let jobs = retry
                .run("list jobs", || store.jobs_of_campaign(campaign.id))
                .await?;
            if jobs
                .iter()
                .any(|j| kinds.contains(&j.kind) && open(&j.state))
            {
                return Ok(true);
            }
            continue;
        }
        let progress = retry
            .run("read progress", || store.progress(campaign.id))
            .await?;
        let open = progress
            .jobs_by_state
            .iter()
            .filter(|(s, _)| matches!(s, JobState::Ready | JobState::Running | JobState::Blocked))
            .map(|(_, n)| n)
            .sum::<i64>();
        if open > 0 {
            return Ok(true);
        }
    }
    Ok(false)
}

/// Runs the worker loop until `shutdown` turns true (or, with `exit_when_idle`, until no work
/// remains).
pub async fn run(
    store: Store,
    artifacts: ArtifactStore,
    config: WorkerConfig,
    mut shutdown: watch::Receiver<bool>,
) -> Result<WorkerSummary, StoreError> {
    let retry = &config.retry;
    let identity = this_process();
    let worker = retry
        .run("register worker", || store.register_worker(&identity))
        .await?;
    tracing::info!(worker = %worker, "worker registered");
    let kinds = ClaimFilter {
        kinds: config.kinds.clone(),
        max_expected_cost_s: None,
    };
    let artifacts = Arc::new(artifacts);
    let mut inputs: HashMap<CampaignId, Arc<CampaignInputs>> = HashMap::new();
    let mut summary = WorkerSummary::default();
    loop {
        if *shutdown.borrow() {
            summary.stopped_by_signal = true;
            return Ok(summary);
        }
        let filter = match &config.wall_time {
            Some(budget) => budget.restrict(&kinds, std::time::Instant::now()),
            None => kinds.clone(),
        };
        let swept = retry
            .run("sweep expired leases", || store.sweep_expired())
            .await?;
        if !swept.requeued.is_empty() || !swept.failed.is_empty() {
            tracing::warn!(requeued = ?swept.requeued, failed = ?swept.failed, "expired leases swept");
        }
        let claimed = retry
            .run("claim job", || store.claim(&worker, &filter))
            .await?;
        let Some(lease) = claimed else {
            if config.exit_when_idle && !work_remains(&store, retry, &config.kinds).await? {
                return Ok(summary);
            }
            tokio::select! {
                _ = tokio::time::sleep(config.idle_poll) => {}
                _ = shutdown.changed() => {}
            }
            continue;
        };
        tracing::info!(job = %lease.job, kind = %lease.kind, attempt = lease.attempt, "claimed");
        if let Some(key) = &lease.cache_key {
            let cached = retry
                .run("look up cache", || store.lookup_cache(key))
                .await?;
            if let Some(source) = cached {
                let completed = retry
                    .run("complete job from cache", || {
                        store.complete_from_cache(&lease, source)
                    })
                    .await;
                match completed {
                    Ok(()) => {
                        summary.cached += 1;
                        tracing::info!(job = %lease.job, source = %source, "completed from cache");
                        continue;
                    }
                    Err(StoreError::LeaseLost { .. }) => {
                        summary.lost += 1;
                        continue;
                    }
                    Err(e) => return Err(e),
                }
            }
        }
        let campaign_inputs = match inputs_of(&store, retry, &mut inputs, &lease).await {
            Ok(i) => i,
            Err(failure) => {
                report_failure(&store, retry, &lease, &failure, &mut summary).await?;
                continue;
            }
        };
        let heartbeat = spawn_heartbeat(store.clone(), lease.clone());
        let job = tokio::task::spawn_blocking({
            let lease = lease.clone();
            let store = store.clone();
            let retry = retry.clone();
            let artifacts = Arc::clone(&artifacts);
            let handle = tokio::runtime::Handle::current();
            move || {
                crate::execute::execute(
                    &lease,
                    campaign_inputs.as_deref(),
                    &store,
                    &retry,
                    &artifacts,
                    &handle,
                )
            }
        });
        let outcome = tokio::select! {
            joined = job => joined.unwrap_or_else(|e| Err(transient(FailureClass::WorkerPanic, e))),
            _ = shutdown.changed() => {
                heartbeat.stop();
                let released = retry
                    .run("release lease", || store.release(&lease, "worker stopped by signal"))
                    .await;
                match released {
                    Ok(()) => tracing::info!(job = %lease.job, "lease released on shutdown"),
                    Err(e) => tracing::warn!(job = %lease.job, error = %e, "release failed"),
                }
                summary.stopped_by_signal = true;
                return Ok(summary);
            }
        };
        heartbeat.stop();
        match outcome {
            Ok(results) => match complete_with_retry(&store, &lease, &results, retry).await {
                Ok(()) => {
                    summary.completed += 1;
                    tracing::info!(job = %lease.job, "completed");
                }
                Err(StoreError::LeaseLost { .. }) => {
                    summary.lost += 1;
                    tracing::warn!(job = %lease.job, "lease lost: results discarded");
                }
                Err(e) => return Err(e),
            },
            Err(failure) => report_failure(&store, retry, &lease, &failure, &mut summary).await?,
        }
    }
}

async fn report_failure(
    store: &Store,
    retry: &RetryPolicy,
    lease: &Lease,
    failure: &JobFailure,
    summary: &mut WorkerSummary,
) -> Result<(), StoreError> {
    summary.failed += 1;
    match retry.run("fail job", || store.fail(lease, failure)).await {
        Ok(FailureDisposition::Retry { not_before_ms }) => {
            tracing::warn!(job = %lease.job, class = %failure.error_class,
                message = %failure.message, not_before_ms, "transient failure, will retry");
            Ok(())
        }
        Ok(FailureDisposition::Failed { dependents_failed }) => {
            tracing::error!(job = %lease.job, class = %failure.error_class,
                message = %failure.message, dependents_failed, "job failed");
            Ok(())
        }
        Err(StoreError::LeaseLost { .. }) => Ok(()),
        Err(e) => Err(e),
    }
}

/// The stored inputs of the lease's campaign (cached per campaign); `None` for test jobs.
async fn inputs_of(
    store: &Store,
    retry: &RetryPolicy,
    cache: &mut HashMap<CampaignId, Arc<CampaignInputs>>,
    lease: &Lease,
) -> Result<Option<Arc<CampaignInputs>>, JobFailure> {
    #[cfg(feature = "test-support")]
    if lease.kind == JobKind::Test {
        return Ok(None);
    }
    if let Some(i) = cache.get(&lease.campaign) {
        return Ok(Some(Arc::clone(i)));
    }
    let campaigns = retry
        .run("list campaigns", || store.campaigns())
        .await
        .map_err(|e| transient(FailureClass::Store, e))?;
    let record = campaigns
        .into_iter()
        .find(|c| c.id == lease.campaign)
        .ok_or_else(|| {
            permanent(
                FailureClass::UnknownCampaign,
                format!("campaign {}", lease.campaign),
            )
        })?;
    let inputs =
        Arc::new(stored_inputs(&record.spec).map_err(|e| permanent(FailureClass::BadCampaign, e))?);
    cache.insert(lease.campaign, Arc::clone(&inputs));
    Ok(Some(inputs))
}

/// The task renewing a running job's lease.
struct Heartbeat {
    stop: tokio::sync::oneshot::Sender<()>,
}

impl Heartbeat {
    /// Stops the renewals. A renewal under way is neither aborted nor awaited: aborting it could
    /// drop a write transaction between its `BEGIN IMMEDIATE` and its commit, leaving the
    /// database locked for the release or completion that follows; awaiting it would hold that
    /// release or completion behind a call that may be stuck in an outage, out of its retries.
    /// The renewal ends on its own; after the completion or release it matches no running
    /// lease and changes nothing.
    fn stop(self) {
        drop(self.stop);
    }
}

/// Renews the lease every heartbeat interval until stopped or the lease is lost.
fn spawn_heartbeat(store: Store, lease: Lease) -> Heartbeat {
    let every = Duration::from_millis(store.policy().heartbeat_interval_ms.unsigned_abs());
    let (stop, mut stopped) = tokio::sync::oneshot::channel::<()>();
    tokio::spawn(async move {
        loop {
            // Only the wait between renewals is interrupted, never a store call.
            tokio::select! {
                _ = tokio::time::sleep(every) => {}
                _ = &mut stopped => return,
            }
            let renewed = store.heartbeat(&lease).await;
            if !matches!(
                stopped.try_recv(),
                Err(tokio::sync::oneshot::error::TryRecvError::Empty)
            ) {
                // Stopped during the call: the job was completed or released meanwhile.
                return;
            }
            match renewed {
                Ok(_) => {}
                Err(StoreError::LeaseLost { .. }) => {
                    tracing::warn!(job = %lease.job, "lease lost during the run");
                    return;
                }
                Err(e) => tracing::warn!(job = %lease.job, error = %e, "heartbeat failed"),
            }
        }
    });
    Heartbeat { stop }
}
