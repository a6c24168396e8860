//! Failure reports of the stages: a class, a message, and whether retrying can help; and the
//! one-line text of an error with its causes, as the binaries print it.

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

/// `err` and its causes joined by ": ", each said once: a cause whose text the message already
/// holds (an error that prints its source and also reports it as its source) is skipped.
pub fn error_text(err: &anyhow::Error) -> String {
    let mut text = String::new();
    for cause in err.chain() {
        let part = cause.to_string();
        if text.contains(&part) {
            continue;
        }
        if !text.is_empty() {
            text.push_str(": ");
        }
        text.push_str(&part);
    }
    text
}

#[cfg(test)]
mod tests {
    use super::*;

    #[derive(Debug, thiserror::Error)]
    #[error("sea state: {0}")]
    struct Wrapping(#[from] Inner);

    #[derive(Debug, thiserror::Error)]
    #[error("no wave component in the band")]
    struct Inner;

    #[test]
    fn each_cause_is_said_once() {
        let err = anyhow::Error::from(Wrapping(Inner)).context("in case file c.json");
        assert_eq!(
            error_text(&err),
            "in case file c.json: sea state: no wave component in the band"
        );
        assert_eq!(format!("{err:#}").matches("no wave").count(), 2);
    }
}
