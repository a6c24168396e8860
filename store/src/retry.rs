//! Riding out a database that goes away: retry store calls with capped exponential backoff.
//!
//! A PostgreSQL restart, a fail-over or a network cut makes store calls fail with connection
//! errors ([`StoreError::is_retryable`]); the pool reconnects by itself once the server answers
//! again, so the caller only has to wait and call again. The n-th retry waits
//! `delay(n) = min(initial · 2^(n-1), max)`; the calls stop after `give_up_after` has elapsed
//! since the first failure and the last error is returned. Errors that are not retryable
//! (lost lease, bad input) are returned at once.
//!
//! Completion needs one more step: when the connection breaks during `COMMIT`, the
//! transaction may have committed without the worker hearing so, and the retried call then
//! finds its token gone ([`StoreError::LeaseLost`]). [`complete_with_retry`] settles the
//! question by reading the outcome recorded for the claim's attempt.

use std::future::Future;
use std::sync::atomic::{AtomicBool, Ordering};
use std::time::Duration;

use tokio::time::Instant;

use super::campaign_store::Store;
use super::error::StoreError;
use super::model::{JobResults, Lease};
use super::types::AttemptOutcome;

/// How long and how often a store call is retried while the database is unreachable.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct RetryPolicy {
    /// Wait before the first retry.
    pub initial_delay: Duration,
    /// Longest wait between two tries.
    pub max_delay: Duration,
    /// Time after the first failure at which the caller gets the error.
    pub give_up_after: Duration,
}

impl Default for RetryPolicy {
    /// 0.1 s doubling to 10 s, for up to 15 min: a server restart costs a few seconds of
    /// waiting, a fail-over or maintenance window up to a quarter of an hour.
    fn default() -> Self {
        Self {
            initial_delay: Duration::from_millis(100),
            max_delay: Duration::from_secs(10),
            give_up_after: Duration::from_secs(15 * 60),
        }
    }
}

impl RetryPolicy {
    /// Checks the fields; returns the policy unchanged when valid.
    pub fn validated(self) -> Result<Self, StoreError> {
        if self.initial_delay.is_zero() {
            return Err(StoreError::InvalidParameter {
                field: "initial_delay",
                value: format!("{:?}", self.initial_delay),
                reason: "must be > 0",
            });
        }
        if self.max_delay < self.initial_delay {
            return Err(StoreError::InvalidParameter {
                field: "max_delay",
                value: format!("{:?}", self.max_delay),
                reason: "must be >= initial_delay",
            });
        }
        Ok(self)
    }

    /// Wait before the `retry`-th retry (1-based).
    pub fn delay(&self, retry: u32) -> Duration {
        let doublings = retry.saturating_sub(1).min(31);
        self.initial_delay
            .checked_mul(1_u32 << doublings)
            .map_or(self.max_delay, |d| d.min(self.max_delay))
    }

    /// Runs `call` until it succeeds, fails with an error that is not retryable, or the time
    /// allowed since the first failure has passed. `operation` names the call in the log.
    pub async fn run<T, F, Fut>(&self, operation: &str, mut call: F) -> Result<T, StoreError>
    where
        F: FnMut() -> Fut,
        Fut: Future<Output = Result<T, StoreError>>,
    {
        let mut first_failure: Option<Instant> = None;
        let mut retry = 0_u32;
        loop {
            match call().await {
                Ok(value) => {
                    if retry > 0 {
                        tracing::info!(operation, retries = retry, "store reachable again");
                    }
                    return Ok(value);
                }
                Err(err) if err.is_retryable() => {
                    let since = *first_failure.get_or_insert_with(Instant::now);
                    retry += 1;
                    let delay = self.delay(retry);
                    if since.elapsed() + delay > self.give_up_after {
                        tracing::error!(operation, retries = retry - 1, error = %err,
                            "store unreachable for too long; giving up");
                        return Err(err);
                    }
                    tracing::warn!(operation, retry, delay_ms = delay.as_millis() as u64,
                        error = %err, "store call failed; retrying");
                    tokio::time::sleep(delay).await;
                }
                Err(err) => return Err(err),
            }
        }
    }
}

/// [`Store::complete`] retried under `policy`. If a retry finds the lease gone after an earlier
/// try failed on the connection, the attempt's recorded outcome decides: `done` means the
/// earlier commit went through and the completion stands; anything else is a real
/// [`StoreError::LeaseLost`].
pub async fn complete_with_retry(
    store: &Store,
    lease: &Lease,
    results: &JobResults,
    policy: &RetryPolicy,
) -> Result<(), StoreError> {
    let connection_failed = AtomicBool::new(false);
    let outcome = policy
        .run("complete job", || async {
            let result = store.complete(lease, results).await;
            if matches!(&result, Err(err) if err.is_retryable()) {
                connection_failed.store(true, Ordering::Relaxed);
            }
            result
        })
        .await;
    match outcome {
        Err(StoreError::LeaseLost { .. }) if connection_failed.load(Ordering::Relaxed) => {
            let recorded = policy
                .run("read attempt outcome", || {
                    store.attempt_outcome(lease.attempt_id)
                })
                .await?;
            if recorded == Some(AttemptOutcome::Done) {
                tracing::info!(job = %lease.job, "completion committed before the connection broke");
                Ok(())
            } else {
                outcome
            }
        }
        other => other,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn unreachable() -> StoreError {
        StoreError::Database {
            operation: "claim job",
            source: sqlx::Error::Io(std::io::Error::from(std::io::ErrorKind::ConnectionRefused)),
        }
    }

    #[test]
    fn delay_doubles_from_the_initial_wait_and_stops_at_the_cap() {
        let policy = RetryPolicy {
            initial_delay: Duration::from_millis(100),
            max_delay: Duration::from_millis(1_000),
            give_up_after: Duration::from_secs(60),
        };
        let delays: Vec<u128> = (1..=6).map(|n| policy.delay(n).as_millis()).collect();
        assert_eq!(delays, vec![100, 200, 400, 800, 1_000, 1_000]);
        assert_eq!(policy.delay(u32::MAX), Duration::from_millis(1_000));
    }

    #[test]
    fn cap_below_the_initial_wait_is_refused() {
        let policy = RetryPolicy {
            max_delay: Duration::from_millis(10),
            ..RetryPolicy::default()
        };
        assert!(matches!(
            policy.validated(),
            Err(StoreError::InvalidParameter {
                field: "max_delay",
                ..
            })
        ));
    }

    fn quick() -> RetryPolicy {
        RetryPolicy {
            initial_delay: Duration::from_millis(1),
            max_delay: Duration::from_millis(4),
            give_up_after: Duration::from_millis(500),
        }
    }

    #[tokio::test]
    async fn connection_errors_are_retried_until_the_call_succeeds() {
        let mut calls = 0;
        let value = quick()
            .run("claim job", || {
                calls += 1;
                let n = calls;
                async move {
                    if n <= 3 {
                        Err(unreachable())
                    } else {
                        Ok(n)
                    }
                }
            })
            .await
            .unwrap();
        assert_eq!(value, 4);
    }

    #[tokio::test]
    async fn retrying_stops_when_the_allowed_time_has_passed() {
        let policy = RetryPolicy {
            give_up_after: Duration::from_millis(50),
            ..quick()
        };
        let mut calls = 0;
        let result: Result<(), _> = policy
            .run("heartbeat", || {
                calls += 1;
                async { Err(unreachable()) }
            })
            .await;
        assert!(matches!(result, Err(StoreError::Database { .. })));
        assert!(calls >= 2, "retried before giving up ({calls} calls)");
    }

    #[tokio::test]
    async fn errors_that_are_not_retryable_return_at_once() {
        let mut calls = 0;
        let result: Result<(), _> = quick()
            .run("complete job", || {
                calls += 1;
                async {
                    Err(StoreError::LeaseLost {
                        job: crate::JobId(1),
                        token: "t".into(),
                    })
                }
            })
            .await;
        assert!(matches!(result, Err(StoreError::LeaseLost { .. })));
        assert_eq!(calls, 1);
    }
}
