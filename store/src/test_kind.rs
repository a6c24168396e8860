//! Payload of the test-only job kind ([`super::JobKind::Test`]), used to exercise the queue.
//!
//! The payload tells the executing worker what to do: succeed, sleep then succeed, fail
//! transiently on its first attempts, fail permanently, or crash the worker process. Such jobs may store only a job-level
//! result; the store refuses result rows from them and the users' views exclude them.

use serde::{Deserialize, Serialize};

use super::model::{FailureKind, JobFailure};
use super::types::FailureClass;

/// What a test job does when run.
#[derive(Debug, Clone, PartialEq, Eq, Serialize, Deserialize)]
#[serde(tag = "action", rename_all = "snake_case", deny_unknown_fields)]
pub enum TestPayload {
    /// Succeeds at once.
    Succeed,
    /// Sleeps, then succeeds.
    Sleep {
        /// Sleep, ms.
        duration_ms: u64,
    },
    /// Fails transiently while its attempt number is at most `failing_attempts`.
    FailTransient {
        /// Number of leading attempts that fail.
        failing_attempts: i64,
    },
    /// Fails permanently.
    FailPermanent,
    /// Aborts the worker process while running (a crash; the lease then expires).
    Crash,
}

impl TestPayload {
    /// The failure this payload reports on `attempt` (1-based), or `None` if it succeeds.
    /// Sleeping and crashing are left to the caller, which owns the runtime and the process.
    pub fn failure_on_attempt(&self, attempt: i64) -> Option<JobFailure> {
        match self {
            TestPayload::Succeed | TestPayload::Sleep { .. } | TestPayload::Crash => None,
            TestPayload::FailTransient { failing_attempts } if attempt <= *failing_attempts => {
                Some(JobFailure {
                    kind: FailureKind::Transient,
                    error_class: FailureClass::TestTransient,
                    message: format!("test job fails transiently on attempt {attempt}"),
                })
            }
            TestPayload::FailTransient { .. } => None,
            TestPayload::FailPermanent => Some(JobFailure {
                kind: FailureKind::Permanent,
                error_class: FailureClass::TestPermanent,
                message: "test job fails permanently".into(),
            }),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn transient_payload_fails_only_on_its_leading_attempts() {
        let payload = TestPayload::FailTransient {
            failing_attempts: 2,
        };
        assert!(payload.failure_on_attempt(1).is_some());
        assert!(payload.failure_on_attempt(2).is_some());
        assert!(payload.failure_on_attempt(3).is_none());
    }

    #[test]
    fn payload_json_names_the_action() {
        let json = serde_json::to_value(TestPayload::Sleep { duration_ms: 5 }).unwrap();
        assert_eq!(
            json,
            serde_json::json!({"action": "sleep", "duration_ms": 5})
        );
        let back: TestPayload = serde_json::from_value(json).unwrap();
        assert_eq!(back, TestPayload::Sleep { duration_ms: 5 });
    }
}
