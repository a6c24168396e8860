//! Errors of the mooring-line finite-element model.
//!
//! Input errors name the offending field with its path (`segments[1].length_m`), solver errors
//! carry what is needed to act: line, time, node with the largest residual and residual norm.
//! Every variant here is deterministic (the same input fails the same way), so none is retryable.

use super::ids::NodeId;

/// Everything that can go wrong when building or solving a mooring line.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum LineError {
    /// A field of the input description is non-physical or inconsistent.
    #[error("{field} {reason} (got {value})")]
    InvalidInput {
        /// Path of the offending field, e.g. `segments[1].length_m`.
        field: String,
        /// Value found, formatted.
        value: String,
        /// What the value must satisfy, e.g. `must be > 0`.
        reason: String,
    },
    /// The banded iteration matrix has a (numerically) zero pivot.
    #[error("line `{line}`: singular iteration matrix at dof {dof} (pivot {pivot:e})")]
    SingularMatrix {
        /// Line name.
        line: String,
        /// Global degree of freedom where elimination broke down.
        dof: usize,
        /// Pivot value met.
        pivot: f64,
    },
    /// Static equilibrium was not reached.
    #[error(
        "line `{line}`: static equilibrium not reached after {iterations} iterations, residual \
         {residual_norm:e} N (largest at node {node})"
    )]
    StaticsDiverged {
        /// Line name.
        line: String,
        /// Newton iterations performed.
        iterations: usize,
        /// Infinity norm of the residual of the free degrees of freedom (N or N·m).
        residual_norm: f64,
        /// Node carrying the largest residual component.
        node: NodeId,
    },
    /// A time step failed even after the allowed step halvings.
    #[error(
        "line `{line}`: time step ending at t = {time_s} s did not converge after {halvings} \
         step halvings, residual {residual_norm:e} N (largest at node {node})"
    )]
    StepDiverged {
        /// Line name.
        line: String,
        /// Time (s) the failing sub-step was aiming at.
        time_s: f64,
        /// Number of step halvings tried.
        halvings: usize,
        /// Infinity norm of the residual at the last iteration (N or N·m), or infinity when the
        /// state became non-finite.
        residual_norm: f64,
        /// Node carrying the largest residual component.
        node: NodeId,
    },
    /// A requested output location is not on the line.
    #[error("line `{line}`: arc length {arc_length_m} m is outside [0, {length_m}] m")]
    ArcLengthOutOfRange {
        /// Line name.
        line: String,
        /// Requested arc length from the fairlead (m).
        arc_length_m: f64,
        /// Unstretched line length (m).
        length_m: f64,
    },
}

impl LineError {
    /// Whether retrying the same computation could succeed. Line errors are deterministic.
    pub fn is_retryable(&self) -> bool {
        false
    }

    pub(crate) fn invalid(field: impl Into<String>, value: impl ToString, reason: &str) -> Self {
        LineError::InvalidInput {
            field: field.into(),
            value: value.to_string(),
            reason: reason.to_string(),
        }
    }
}
