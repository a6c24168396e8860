//! Failure reports of the stages: a class, a message, and whether retrying can help.

use moorfret_store::{FailureClass, FailureKind, JobFailure};

/// A failure report for an error of class `class` that will not go away by retrying.
pub(crate) fn permanent(class: FailureClass, e: impl std::fmt::Display) -> JobFailure {
    JobFailure {
        kind: FailureKind::Permanent,
        error_class: class,
        message: e.to_string(),
    }
}

/// A failure report for an error of class `class` worth retrying.
pub(crate) fn transient(class: FailureClass, e: impl std::fmt::Display) -> JobFailure {
    JobFailure {
        kind: FailureKind::Transient,
        error_class: class,
        message: e.to_string(),
    }
}
