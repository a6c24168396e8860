//! Errors of the wave module: rejected parameters (naming the field, the value and the rule it
//! broke) and numerical failures (with the data needed to reproduce them). All are permanent:
//! retrying with the same input gives the same error.

use thiserror::Error;

/// Why a wave computation was refused or failed.
#[derive(Debug, Clone, PartialEq, Error)]
pub enum WavesError {
    /// A parameter is out of its admissible range, e.g. `tp_s must be > 0, got -1`.
    #[error("{field} must be {rule}, got {}", crate::text::Num(*.value))]
    InvalidParameter {
        /// Name of the offending field (with its unit suffix).
        field: &'static str,
        /// The value that was given.
        value: f64,
        /// The rule it broke, e.g. `> 0`.
        rule: &'static str,
    },
    /// The dispersion relation did not converge (should not happen for finite positive input).
    #[error(
        "dispersion Newton iteration did not converge for omega = {omega_rad_s} rad/s, \
         depth = {depth_m} m after {iterations} iterations (relative residual {residual})"
    )]
    DispersionNotConverged {
        /// Angular frequency (rad/s).
        omega_rad_s: f64,
        /// Water depth (m).
        depth_m: f64,
        /// Iterations done.
        iterations: usize,
        /// Last relative residual |ω² − g k tanh(kd)| / ω².
        residual: f64,
    },
    /// The frequency band left no wave component on the discrete grid.
    #[error(
        "no wave component in the band [{}, {}] rad/s with d_omega = {} rad/s",
        crate::text::Num(*.omega_min_rad_s),
        crate::text::Num(*.omega_max_rad_s),
        crate::text::Num(*.d_omega_rad_s)
    )]
    EmptyBand {
        /// Lower band edge (rad/s).
        omega_min_rad_s: f64,
        /// Upper band edge (rad/s).
        omega_max_rad_s: f64,
        /// Grid spacing (rad/s).
        d_omega_rad_s: f64,
    },
    /// The band would need more components than a realisation holds.
    #[error(
        "the band [{}, {}] rad/s holds {} components at d_omega = {} rad/s, more than 10⁷: \
         shorten the duration (d_omega = 2π / repeat period)",
        crate::text::Num(*.omega_min_rad_s),
        crate::text::Num(*.omega_max_rad_s),
        crate::text::Num(*.components),
        crate::text::Num(*.d_omega_rad_s)
    )]
    BandTooWide {
        /// Lower band edge (rad/s).
        omega_min_rad_s: f64,
        /// Upper band edge (rad/s).
        omega_max_rad_s: f64,
        /// Components the band would hold.
        components: f64,
        /// Grid spacing (rad/s).
        d_omega_rad_s: f64,
    },
    /// The worker thread pool could not be created.
    #[error("could not create a thread pool: {reason}")]
    ThreadPool {
        /// The reason given by the thread-pool builder.
        reason: String,
    },
    /// A query of a kinematics table fell outside it: the coordinate, its value and the range
    /// of values whose interpolation stencil lies inside the table.
    #[error(
        "{coordinate} = {value} outside the kinematics table, which covers [{lower}, {upper}]"
    )]
    OutsideTable {
        /// The coordinate that left the table: `x_beta_m`, `stretched_height_m` or `time_s`.
        coordinate: &'static str,
        /// Its value (non-finite values included).
        value: f64,
        /// Lowest value with a full stencil.
        lower: f64,
        /// Highest value with a full stencil.
        upper: f64,
    },
    /// Two tables that must have equal lengths do not.
    #[error("{field}: expected {expected} values, got {got}")]
    LengthMismatch {
        /// Name of the offending field.
        field: &'static str,
        /// Required length.
        expected: usize,
        /// Given length.
        got: usize,
    },
}

/// Check `value > 0` and finite.
pub(crate) fn positive(field: &'static str, value: f64) -> Result<f64, WavesError> {
    if value.is_finite() && value > 0.0 {
        Ok(value)
    } else {
        Err(WavesError::InvalidParameter {
            field,
            value,
            rule: "> 0",
        })
    }
}

/// Check `value` finite and ≥ 0.
pub(crate) fn non_negative(field: &'static str, value: f64) -> Result<f64, WavesError> {
    if value.is_finite() && value >= 0.0 {
        Ok(value)
    } else {
        Err(WavesError::InvalidParameter {
            field,
            value,
            rule: ">= 0",
        })
    }
}

/// Check `value` finite.
pub(crate) fn finite(field: &'static str, value: f64) -> Result<f64, WavesError> {
    if value.is_finite() {
        Ok(value)
    } else {
        Err(WavesError::InvalidParameter {
            field,
            value,
            rule: "finite",
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn invalid_parameter_message_names_field_rule_and_value() {
        let e = positive("tp_s", -1.0).unwrap_err();
        assert_eq!(e.to_string(), "tp_s must be > 0, got -1");
    }
}
