//! Errors of the analytical catenary solvers.
//!
//! Every variant carries the numbers needed to act on it: the offending field and value, by how
//! much a line misses its fairlead, or the iteration and residual at which Newton gave up. All
//! catenary errors are deterministic for given input, so none is worth retrying
//! ([`CatenaryError::is_permanent`]).

use thiserror::Error;

/// Why a catenary could not be built or solved.
#[derive(Debug, Clone, PartialEq, Error)]
pub enum CatenaryError {
    /// An input quantity is outside its physical range (non-positive length, weight or axial
    /// stiffness, negative friction, non-finite span...).
    #[error("{field} = {value} is invalid: {reason}")]
    InvalidInput {
        /// Name of the quantity, with its unit (`length_m`, `segments[2].weight_n_per_m`).
        field: String,
        /// The value that was given.
        value: f64,
        /// What it must satisfy.
        reason: &'static str,
    },
    /// The line cannot reach the fairlead: the straight anchor-fairlead chord is longer than the
    /// line stretched to its strain limit.
    #[error(
        "line too short to reach the fairlead: chord {chord_m:.6} m exceeds the reach \
         {reach_m:.6} m (unstretched length {length_m:.6} m at the strain limit) by \
         {shortfall_m:.6} m"
    )]
    TooShort {
        /// Straight distance from anchor to fairlead.
        chord_m: f64,
        /// Total unstretched length of the line.
        length_m: f64,
        /// Unstretched length times (1 + strain limit).
        reach_m: f64,
        /// `chord_m - reach_m`: how much line is missing.
        shortfall_m: f64,
    },
    /// The fairlead is not above the anchor, so the whole line would lie on the seabed and no
    /// catenary carries it.
    #[error(
        "line lies entirely on the seabed: fairlead height above the anchor {vertical_span_m} m \
         must be > 0"
    )]
    LineOnSeabed {
        /// Height of the fairlead above the anchor.
        vertical_span_m: f64,
    },
    /// The line is longer than needed to hang vertically from the fairlead and lie straight to the
    /// anchor: its horizontal tension is zero and the laid part is slack, so the quasi-static
    /// catenary has no unique profile.
    #[error(
        "line is slack: {excess_length_m:.6} m longer than the hanging length {hanging_length_m:.6} \
         m plus the horizontal span; horizontal tension would be zero"
    )]
    SlackLine {
        /// Unstretched length that hangs vertically below the fairlead at zero horizontal tension.
        hanging_length_m: f64,
        /// Unstretched length left over once the hanging part and the horizontal span are taken.
        excess_length_m: f64,
    },
    /// Newton's method did not meet the tolerance on the fairlead position.
    #[error(
        "catenary Newton iteration did not converge after {iterations} iterations: residual \
         {residual_m:.3e} m > tolerance {tolerance_m:.3e} m at H = {horizontal_tension_n} N, \
         V_F = {vertical_tension_n} N"
    )]
    NotConverged {
        /// Iterations performed.
        iterations: usize,
        /// Largest component of the fairlead position misfit at the last iterate.
        residual_m: f64,
        /// Tolerance that was asked for.
        tolerance_m: f64,
        /// Horizontal tension at the last iterate.
        horizontal_tension_n: f64,
        /// Fairlead vertical tension at the last iterate.
        vertical_tension_n: f64,
    },
    /// A profile was requested outside the line.
    #[error("arc length {arc_length_m} m is outside the line [0, {length_m}] m")]
    ArcLengthOutOfRange {
        /// Requested unstretched arc length from the fairlead.
        arc_length_m: f64,
        /// Total unstretched length.
        length_m: f64,
    },
}

impl CatenaryError {
    /// Whether retrying with the same input can never succeed. Always true: the catenary is a
    /// deterministic computation without external resources.
    pub fn is_permanent(&self) -> bool {
        true
    }
}

/// Checks that `value` is finite and strictly positive.
pub(crate) fn require_positive(field: &str, value: f64) -> Result<(), CatenaryError> {
    if value.is_finite() && value > 0.0 {
        Ok(())
    } else {
        Err(CatenaryError::InvalidInput {
            field: field.to_owned(),
            value,
            reason: "must be finite and > 0",
        })
    }
}

/// Checks that `value` is finite and not negative.
pub(crate) fn require_non_negative(field: &str, value: f64) -> Result<(), CatenaryError> {
    if value.is_finite() && value >= 0.0 {
        Ok(())
    } else {
        Err(CatenaryError::InvalidInput {
            field: field.to_owned(),
            value,
            reason: "must be finite and >= 0",
        })
    }
}
