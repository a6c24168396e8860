//! Errors of the floater module: invalid descriptions, prescribed-motion input problems and
//! solver failures, each carrying the data needed to act on it.

use thiserror::Error;

/// Everything that can go wrong when building or running a floater model.
#[derive(Debug, Error, Clone, PartialEq)]
pub enum FloaterError {
    /// The floater description could not be parsed as JSON.
    #[error("floater description is not valid JSON: {message}")]
    Json {
        /// Parser message, with line and column.
        message: String,
    },
    /// A field of the floater description has an unacceptable value.
    #[error("{field} = {value} is invalid: {reason}")]
    InvalidField {
        /// Path of the field, e.g. `members[2].diameter_m`.
        field: String,
        /// The offending value, as written.
        value: String,
        /// Why it is rejected.
        reason: String,
    },
    /// A cell of a prescribed-motion table could not be read.
    #[error("prescribed motion, line {line}, column {column}: {reason}")]
    MotionTable {
        /// 1-based line number in the text (the header is line 1).
        line: usize,
        /// 1-based column number (1 = `time_s`).
        column: usize,
        /// What is wrong.
        reason: String,
    },
    /// A prescribed motion was sampled outside the time range of its table.
    #[error("prescribed motion sampled at t = {time_s} s, outside [{start_s}, {end_s}] s")]
    OutsideTimeRange {
        /// Requested time (s).
        time_s: f64,
        /// First time of the table (s).
        start_s: f64,
        /// Last time of the table (s).
        end_s: f64,
    },
    /// The implicit integrator's Newton iterations did not converge.
    #[error("floater Newton iterations diverged at step {step} (t = {time_s} s) after {iterations} iterations, residual {residual:e}")]
    NewtonDiverged {
        /// Step index (0-based).
        step: usize,
        /// Time at the end of the step (s).
        time_s: f64,
        /// Iterations performed.
        iterations: usize,
        /// Last scaled residual norm.
        residual: f64,
    },
    /// A 6×6 system (mass or iteration matrix) could not be factorised.
    #[error("singular {what} matrix at step {step}")]
    SingularMatrix {
        /// Which matrix.
        what: &'static str,
        /// Step index (0-based).
        step: usize,
    },
}

impl FloaterError {
    /// Whether retrying the same computation can succeed (never for this module: all its errors
    /// are deterministic consequences of the input).
    pub fn is_retryable(&self) -> bool {
        false
    }

    pub(crate) fn field(
        field: impl Into<String>,
        value: impl ToString,
        reason: impl Into<String>,
    ) -> Self {
        FloaterError::InvalidField {
            field: field.into(),
            value: value.to_string(),
            reason: reason.into(),
        }
    }
}
