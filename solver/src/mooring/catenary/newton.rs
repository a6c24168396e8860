//! Damped Newton iteration on the two catenary unknowns (H, V_F), shared by the single-line and
//! the multi-segment solvers, with the validated solver parameters and the work counters.
//!
//! Each iteration solves the 2×2 system J Δ = -r by Cramer's rule, shortens the step so both
//! unknowns stay positive (they are tensions; at most 90 % of the current value is removed in one
//! step), then backtracks by halving until ½‖r‖² decreases with the Armijo factor 1e-4.
//! Convergence is on the fairlead position misfit, max(|r_x|, |r_z|) ≤ tolerance (m).

use super::error::{require_positive, CatenaryError};

/// Solver parameters for the analytical catenaries.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct CatenaryParams {
    /// Iteration cap of the Newton solve.
    pub max_iterations: usize,
    /// Tolerance on the fairlead misfit relative to the length scale max(L, chord) (-).
    pub relative_tolerance: f64,
    /// Largest mean axial strain the line may take to reach its fairlead (-): a chord longer than
    /// L·(1 + this) is reported as [`CatenaryError::TooShort`]. 0 means an inextensible line
    /// must be longer than its chord.
    pub max_axial_strain: f64,
}

impl Default for CatenaryParams {
    /// 100 iterations, 1e-11 relative tolerance, 5 % strain limit (beyond the breaking strain of
    /// steel chain and wire rope; taut synthetic lines work at a few percent).
    fn default() -> Self {
        Self {
            max_iterations: 100,
            relative_tolerance: 1e-11,
            max_axial_strain: 0.05,
        }
    }
}

impl CatenaryParams {
    /// Checks every field; returns the first bad one.
    pub fn validate(&self) -> Result<(), CatenaryError> {
        if self.max_iterations == 0 {
            return Err(CatenaryError::InvalidInput {
                field: "max_iterations".to_owned(),
                value: 0.0,
                reason: "must be >= 1",
            });
        }
        require_positive("relative_tolerance", self.relative_tolerance)?;
        if !(self.max_axial_strain.is_finite() && self.max_axial_strain >= 0.0) {
            return Err(CatenaryError::InvalidInput {
                field: "max_axial_strain".to_owned(),
                value: self.max_axial_strain,
                reason: "must be finite and >= 0",
            });
        }
        Ok(())
    }
}

/// Work done by one Newton solve.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct NewtonStats {
    /// Newton iterations (Jacobian solves) performed.
    pub iterations: usize,
    /// Residual and Jacobian evaluations, including rejected trial points.
    pub evaluations: usize,
    /// Step halvings performed by the line search.
    pub backtracks: usize,
    /// Final misfit max(|r_x|, |r_z|) (m).
    pub residual_m: f64,
}

/// Fairlead misfit `r` (m) and its Jacobian `J[i][j] = ∂r_i/∂u_j` at unknowns u = (H, V_F).
pub(crate) type Linearization = ([f64; 2], [[f64; 2]; 2]);

fn max_abs(r: [f64; 2]) -> f64 {
    r[0].abs().max(r[1].abs())
}

fn half_square(r: [f64; 2]) -> f64 {
    0.5 * (r[0] * r[0] + r[1] * r[1])
}

/// Solves r(u) = 0 from `start` for positive u = (H, V_F).
pub(crate) fn solve<F>(
    start: [f64; 2],
    tolerance_m: f64,
    max_iterations: usize,
    mut eval: F,
) -> Result<([f64; 2], NewtonStats), CatenaryError>
where
    F: FnMut([f64; 2]) -> Result<Linearization, CatenaryError>,
{
    let mut stats = NewtonStats::default();
    let mut u = start;
    let (mut r, mut jac) = eval(u)?;
    stats.evaluations += 1;
    let not_converged = |u: [f64; 2], r: [f64; 2], iterations: usize| CatenaryError::NotConverged {
        iterations,
        residual_m: max_abs(r),
        tolerance_m,
        horizontal_tension_n: u[0],
        vertical_tension_n: u[1],
    };
    loop {
        stats.residual_m = max_abs(r);
        if stats.residual_m <= tolerance_m {
            return Ok((u, stats));
        }
        if stats.iterations >= max_iterations {
            return Err(not_converged(u, r, stats.iterations));
        }
        stats.iterations += 1;
        let det = jac[0][0] * jac[1][1] - jac[0][1] * jac[1][0];
        let step = [
            (-r[0] * jac[1][1] + r[1] * jac[0][1]) / det,
            (-r[1] * jac[0][0] + r[0] * jac[1][0]) / det,
        ];
        if !(step[0].is_finite() && step[1].is_finite()) {
            return Err(not_converged(u, r, stats.iterations));
        }
        let mut alpha: f64 = 1.0;
        for i in 0..2 {
            if step[i] < 0.0 {
                alpha = alpha.min(0.9 * u[i] / -step[i]);
            }
        }
        let merit = half_square(r);
        let mut accepted = false;
        for _ in 0..60 {
            let trial = [u[0] + alpha * step[0], u[1] + alpha * step[1]];
            let (r_trial, jac_trial) = eval(trial)?;
            stats.evaluations += 1;
            if half_square(r_trial) <= merit * (1.0 - 2e-4 * alpha) {
                u = trial;
                r = r_trial;
                jac = jac_trial;
                accepted = true;
                break;
            }
            alpha *= 0.5;
            stats.backtracks += 1;
        }
        if !accepted {
            return Err(not_converged(u, r, stats.iterations));
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn newton_finds_the_positive_root_of_a_coupled_quadratic_system() {
        // r = (u0² + u1 − 7, u0 + u1² − 11) (Himmelblau's system) has the single root (2, 3) in
        // the positive quadrant.
        let (u, stats) = solve([10.0, 10.0], 1e-13, 50, |u| {
            Ok((
                [u[0] * u[0] + u[1] - 7.0, u[0] + u[1] * u[1] - 11.0],
                [[2.0 * u[0], 1.0], [1.0, 2.0 * u[1]]],
            ))
        })
        .unwrap();
        assert!((u[0] - 2.0).abs() < 1e-12 && (u[1] - 3.0).abs() < 1e-12);
        assert!(stats.iterations < 20, "{stats:?}");
    }

    #[test]
    fn newton_reports_the_last_iterate_when_there_is_no_root() {
        // r = (u0² + 1, u1 - 1): the first component never vanishes.
        let err = solve([1.0, 1.0], 1e-12, 30, |u| {
            Ok((
                [u[0] * u[0] + 1.0, u[1] - 1.0],
                [[2.0 * u[0], 0.0], [0.0, 1.0]],
            ))
        })
        .unwrap_err();
        match err {
            CatenaryError::NotConverged { residual_m, .. } => assert!(residual_m >= 1.0),
            other => panic!("unexpected {other:?}"),
        }
    }

    #[test]
    fn default_parameters_are_valid_and_bad_ones_are_named() {
        assert!(CatenaryParams::default().validate().is_ok());
        let bad = CatenaryParams {
            relative_tolerance: -1.0,
            ..CatenaryParams::default()
        };
        match bad.validate().unwrap_err() {
            CatenaryError::InvalidInput { field, .. } => assert_eq!(field, "relative_tolerance"),
            other => panic!("unexpected {other:?}"),
        }
    }
}
