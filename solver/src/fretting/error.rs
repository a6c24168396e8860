//! Errors of the fretting statistics: bad samples, bad parameters, infeasible contact input.
//!
//! Every variant carries the data needed to act on it (which field, which sample, which value).
//! All of them are permanent: retrying the same input gives the same error.

use thiserror::Error;

use crate::contact::hertz::HertzError;

/// Errors raised by rainflow counting, cycle statistics, Hertz contact and fretting indicators.
#[derive(Debug, Clone, PartialEq, Error)]
pub enum FrettingError {
    /// A sample of a history is NaN or infinite.
    #[error("sample {index} of the history is not finite ({value})")]
    NonFiniteSample {
        /// Zero-based sample index in the history.
        index: usize,
        /// The offending value.
        value: f64,
    },
    /// A side-channel sample (a contact force) is NaN or infinite.
    #[error("sample {index}: {channel} is not finite ({value})")]
    NonFiniteChannel {
        /// Zero-based sample index in the history.
        index: usize,
        /// Which channel (`normal_force_n`, `tangential_force_n`, …).
        channel: &'static str,
        /// The offending value.
        value: f64,
    },
    /// A parameter is outside its admissible range.
    #[error("parameter `{field}` = {value} is invalid: {reason}")]
    InvalidParameter {
        /// Name of the parameter (struct field path).
        field: &'static str,
        /// The rejected value.
        value: f64,
        /// Why it is rejected.
        reason: &'static str,
    },
    /// A histogram was asked to merge with one of different binning.
    #[error("histograms have different binning and cannot be merged")]
    HistogramMismatch,
    /// The Hertz contact of a layer interface could not be formed.
    #[error(transparent)]
    Hertz(#[from] HertzError),
}

/// Checks that `value` is finite and strictly positive.
pub(crate) fn positive(field: &'static str, value: f64) -> Result<f64, FrettingError> {
    if value.is_finite() && value > 0.0 {
        Ok(value)
    } else {
        Err(FrettingError::InvalidParameter {
            field,
            value,
            reason: "must be finite and > 0",
        })
    }
}

/// Checks that `value` is finite and not negative.
pub(crate) fn non_negative(field: &'static str, value: f64) -> Result<f64, FrettingError> {
    if value.is_finite() && value >= 0.0 {
        Ok(value)
    } else {
        Err(FrettingError::InvalidParameter {
            field,
            value,
            reason: "must be finite and >= 0",
        })
    }
}
