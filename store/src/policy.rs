//! Queue policy: lease length, how often a lost job may be re-queued, retry backoff.
//!
//! Transient failures are retried after a capped exponential backoff,
//! `delay(n) = min(base · 2^(n-1), cap)` for the n-th failed attempt, so a job that keeps
//! failing does not spin the queue while a passing fault (full disk, busy node) clears.

use serde::{Deserialize, Serialize};

use super::error::StoreError;

/// Validated queue settings shared by every worker of a store.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct QueuePolicy {
    /// Lease granted by a claim or a heartbeat, ms (default 5 min).
    pub lease_ms: i64,
    /// How often a worker should heartbeat, ms (default 30 s); must be below `lease_ms`.
    pub heartbeat_interval_ms: i64,
    /// A job whose lease expired this many times is failed instead of re-queued.
    pub max_lost: i64,
    /// Backoff after the first transient failure, ms.
    pub backoff_base_ms: i64,
    /// Largest backoff, ms.
    pub backoff_cap_ms: i64,
}

impl Default for QueuePolicy {
    fn default() -> Self {
        Self {
            lease_ms: 300_000,
            heartbeat_interval_ms: 30_000,
            max_lost: 3,
            backoff_base_ms: 10_000,
            backoff_cap_ms: 600_000,
        }
    }
}

impl QueuePolicy {
    /// Checks every field; returns the policy unchanged when valid.
    pub fn validated(self) -> Result<Self, StoreError> {
        let positive = |field: &'static str, value: i64| {
            if value > 0 {
                Ok(())
            } else {
                Err(StoreError::InvalidParameter {
                    field,
                    value: value.to_string(),
                    reason: "must be > 0",
                })
            }
        };
        positive("lease_ms", self.lease_ms)?;
        positive("heartbeat_interval_ms", self.heartbeat_interval_ms)?;
        positive("max_lost", self.max_lost)?;
        positive("backoff_base_ms", self.backoff_base_ms)?;
        if self.heartbeat_interval_ms >= self.lease_ms {
            return Err(StoreError::InvalidParameter {
                field: "heartbeat_interval_ms",
                value: self.heartbeat_interval_ms.to_string(),
                reason: "must be shorter than lease_ms",
            });
        }
        if self.backoff_cap_ms < self.backoff_base_ms {
            return Err(StoreError::InvalidParameter {
                field: "backoff_cap_ms",
                value: self.backoff_cap_ms.to_string(),
                reason: "must be >= backoff_base_ms",
            });
        }
        Ok(self)
    }

    /// Delay before the job may run again after its `failed_attempts`-th transient failure.
    pub fn backoff_ms(&self, failed_attempts: i64) -> i64 {
        let doublings = u32::try_from((failed_attempts - 1).clamp(0, 62)).unwrap_or(62);
        self.backoff_base_ms
            .checked_mul(1_i64 << doublings)
            .map_or(self.backoff_cap_ms, |d| d.min(self.backoff_cap_ms))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn backoff_doubles_from_the_base_and_stops_at_the_cap() {
        let policy = QueuePolicy {
            backoff_base_ms: 1_000,
            backoff_cap_ms: 5_000,
            ..QueuePolicy::default()
        };
        let delays: Vec<i64> = (1..=5).map(|n| policy.backoff_ms(n)).collect();
        assert_eq!(delays, vec![1_000, 2_000, 4_000, 5_000, 5_000]);
        assert_eq!(policy.backoff_ms(200), 5_000);
    }

    #[test]
    fn heartbeat_not_shorter_than_the_lease_is_refused() {
        let policy = QueuePolicy {
            heartbeat_interval_ms: 300_000,
            ..QueuePolicy::default()
        };
        assert!(matches!(
            policy.validated(),
            Err(StoreError::InvalidParameter {
                field: "heartbeat_interval_ms",
                ..
            })
        ));
        assert!(QueuePolicy::default().validated().is_ok());
    }
}
