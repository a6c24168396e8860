//! Errors of the fatigue damage computations. All are permanent (bad input).

use thiserror::Error;

use crate::fretting::FrettingError;

/// Errors raised by T-N curves, Miner sums and lifetime aggregation.
#[derive(Debug, Clone, PartialEq, Error)]
pub enum FatigueError {
    /// A parameter is outside its admissible range.
    #[error("`{field}` = {value} is invalid: {reason}")]
    InvalidParameter {
        /// Field path of the parameter.
        field: String,
        /// The rejected value.
        value: f64,
        /// Why it is rejected.
        reason: &'static str,
    },
    /// The same sea state appears twice in a lifetime aggregation.
    #[error("sea state `{id}` appears more than once")]
    DuplicateSeaState {
        /// Identifier of the sea state.
        id: String,
    },
    /// The same seed appears twice within one sea state.
    #[error("seed {seed} appears more than once in sea state `{id}`")]
    DuplicateSeed {
        /// Identifier of the sea state.
        id: String,
        /// The repeated seed.
        seed: u64,
    },
    /// The occurrences add up to more than the whole year.
    #[error("occurrence fractions add up to {total} > 1")]
    OccurrenceExceedsYear {
        /// Sum of the occurrence fractions.
        total: f64,
    },
    /// Rainflow counting of a tension series failed.
    #[error("rainflow count of the tension series failed: {0}")]
    Rainflow(#[from] FrettingError),
}

pub(crate) fn check(
    field: &str,
    value: f64,
    ok: bool,
    reason: &'static str,
) -> Result<f64, FatigueError> {
    if ok && value.is_finite() {
        Ok(value)
    } else {
        Err(FatigueError::InvalidParameter {
            field: field.to_string(),
            value,
            reason,
        })
    }
}
