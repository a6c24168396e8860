//! Implicit time integration of the floater alone, with an optional linear mooring, for free
//! decay and wave-response tests; the coupled global stage uses the same [`Floater`] calls.
//!
//! Generalised-α method (Chung & Hulbert 1993, J. Appl. Mech. 60:371, in the two-acceleration form
//! of Arnold & Brüls 2007, Multibody Syst. Dyn. 18:185) on the Lie group of rigid motions: with the
//! true acceleration ν̇ and the algorithmic acceleration a,
//!
//! ```text
//! (1 − α_m) a_{n+1} + α_m a_n = (1 − α_f) ν̇_{n+1} + α_f ν̇_n
//! Δq = h ν_n + h² (½ − β) a_n + h² β a_{n+1},   x_{n+1} = x_n + Δq_x,  Λ_{n+1} = exp(Δq̂_θ) Λ_n
//! ν_{n+1} = ν_n + h (1 − γ) a_n + h γ a_{n+1}
//! M(q_{n+1}) ν̇_{n+1} = f(q_{n+1}, ν_{n+1}, t_{n+1}) + F_moor(q_{n+1})
//! ```
//!
//! α_m = (2ρ∞ − 1)/(ρ∞ + 1), α_f = ρ∞/(ρ∞ + 1), γ = ½ − α_m + α_f, β = ¼(1 − α_m + α_f)².
//! Newton on ν̇_{n+1} with the iteration matrix M − β' h² K_q − γ' h K_ν (β' = β(1−α_f)/(1−α_m),
//! γ' likewise), the Jacobians being evaluated once per step (modified Newton). The linear
//! mooring gives F_moor = F_0 − K (x, log Λ).

use nalgebra::{Matrix6, Vector3, Vector6};

use super::body::BodyState;
use super::error::FloaterError;
use super::model::Floater;
use crate::beam::rotation::{exp_so3, log_so3};
use crate::waves::SeaKinematics;

/// Linear mooring about the undisplaced position: F = preload − K (x, log Λ).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct LinearMooring {
    /// Stiffness about the reference point (N/m, N/rad, N m/m, N m/rad).
    pub stiffness: Matrix6<f64>,
    /// Load at the undisplaced position (N, N m), e.g. the vertical pretension.
    pub preload: Vector6<f64>,
}

impl Default for LinearMooring {
    fn default() -> Self {
        Self {
            stiffness: Matrix6::zeros(),
            preload: Vector6::zeros(),
        }
    }
}

impl LinearMooring {
    /// Mooring load for a state.
    pub fn force(&self, state: &BodyState) -> Vector6<f64> {
        let mut xi = Vector6::zeros();
        xi.fixed_rows_mut::<3>(0).copy_from(&state.position_m);
        xi.fixed_rows_mut::<3>(3)
            .copy_from(&log_so3(&state.rotation));
        self.preload - self.stiffness * xi
    }
}

/// Integration settings.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct IntegratorParams {
    /// Time step (s).
    pub time_step_s: f64,
    /// High-frequency spectral radius ρ∞ ∈ [0, 1].
    pub spectral_radius: f64,
    /// Newton iterations allowed per step.
    pub max_iterations: usize,
    /// Convergence threshold on the residual scaled by the weight (forces) and weight × 10 m
    /// (moments).
    pub tolerance: f64,
}

impl Default for IntegratorParams {
    fn default() -> Self {
        Self {
            time_step_s: 0.1,
            spectral_radius: 0.9,
            max_iterations: 25,
            tolerance: 1e-9,
        }
    }
}

/// Work counts of a run.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct IntegratorStats {
    /// Steps taken.
    pub steps: usize,
    /// Newton iterations over all steps.
    pub newton_iterations: usize,
    /// Jacobian evaluations.
    pub jacobian_evaluations: usize,
}

/// Integrates the floater from `initial` over `duration_s` in `sea`, with constant rotor thrust
/// `wind_thrust_n` and the linear mooring; `record` is called with (t, state) at t = 0 and after
/// every step.
#[allow(clippy::too_many_arguments)]
pub fn integrate<S: SeaKinematics + ?Sized>(
    floater: &Floater,
    mooring: &LinearMooring,
    sea: &S,
    wind_thrust_n: f64,
    initial: &BodyState,
    duration_s: f64,
    params: &IntegratorParams,
    mut record: impl FnMut(f64, &BodyState),
) -> Result<IntegratorStats, FloaterError> {
    if !(params.time_step_s.is_finite() && params.time_step_s > 0.0) {
        return Err(FloaterError::field(
            "time_step_s",
            params.time_step_s,
            "must be > 0",
        ));
    }
    if !(duration_s.is_finite() && duration_s >= 0.0) {
        return Err(FloaterError::field(
            "duration_s",
            duration_s,
            "must be >= 0",
        ));
    }
    if params.max_iterations == 0 {
        return Err(FloaterError::field("max_iterations", 0, "must be >= 1"));
    }
    let h = params.time_step_s;
    let rho = params.spectral_radius.clamp(0.0, 1.0);
    let am = (2.0 * rho - 1.0) / (rho + 1.0);
    let af = rho / (rho + 1.0);
    let gamma = 0.5 - am + af;
    let beta = 0.25 * (1.0 - am + af).powi(2);
    let ratio = (1.0 - af) / (1.0 - am);

    let mg = floater.mass_properties().mass_kg * floater.gravity();
    let scale = Vector6::new(mg, mg, mg, 10.0 * mg, 10.0 * mg, 10.0 * mg);
    let rhs =
        |s: &BodyState, t: f64| floater.net_forces(s, sea, t, wind_thrust_n) + mooring.force(s);

    let mut state = *initial;
    let mut t = 0.0;
    let mut acc = floater
        .mass_matrix(&state)
        .lu()
        .solve(&rhs(&state, t))
        .ok_or(FloaterError::SingularMatrix {
            what: "mass",
            step: 0,
        })?;
    let mut alg = acc;
    let mut stats = IntegratorStats::default();
    record(t, &state);

    let steps = (duration_s / h).round() as usize;
    for step in 0..steps {
        let t1 = t + h;
        let base_alg = (af * acc - am * alg) / (1.0 - am);
        let mut acc1 = acc;
        let advance = |acc1: &Vector6<f64>| {
            let alg1 = base_alg + ratio * acc1;
            let dq = state.velocity6() * h + alg * (h * h * (0.5 - beta)) + alg1 * (h * h * beta);
            let nu1 = state.velocity6() + alg * (h * (1.0 - gamma)) + alg1 * (h * gamma);
            BodyState {
                position_m: state.position_m + dq.fixed_rows::<3>(0),
                rotation: exp_so3(&Vector3::from(dq.fixed_rows::<3>(3))) * state.rotation,
                velocity_m_per_s: nu1.fixed_rows::<3>(0).into_owned(),
                angular_velocity_rad_per_s: nu1.fixed_rows::<3>(3).into_owned(),
            }
        };
        let mut iteration_matrix = None;
        let mut converged = false;
        let mut residual_norm = f64::INFINITY;
        let mut trial = advance(&acc1);
        for it in 0..params.max_iterations {
            let r = floater.mass_matrix(&trial) * acc1 - rhs(&trial, t1);
            residual_norm = r.component_div(&scale).amax();
            stats.newton_iterations += 1;
            if residual_norm < params.tolerance && it > 0 {
                converged = true;
                break;
            }
            if iteration_matrix.is_none() {
                let jac = floater.load_jacobians(&trial, sea, t1, wind_thrust_n);
                stats.jacobian_evaluations += 1;
                let kq = jac.position - mooring.stiffness;
                let s = floater.mass_matrix(&trial)
                    - kq * (beta * ratio * h * h)
                    - jac.velocity * (gamma * ratio * h);
                iteration_matrix = Some(s.lu());
            }
            let lu = iteration_matrix
                .as_ref()
                .ok_or(FloaterError::SingularMatrix {
                    what: "iteration",
                    step,
                })?;
            let delta = lu.solve(&(-r)).ok_or(FloaterError::SingularMatrix {
                what: "iteration",
                step,
            })?;
            acc1 += delta;
            trial = advance(&acc1);
        }
        if !converged {
            return Err(FloaterError::NewtonDiverged {
                step,
                time_s: t1,
                iterations: params.max_iterations,
                residual: residual_norm,
            });
        }
        alg = base_alg + ratio * acc1;
        acc = acc1;
        state = trial;
        t = t1;
        stats.steps += 1;
        record(t, &state);
    }
    Ok(stats)
}

/// Static equilibrium of the floater under gravity, buoyancy, rotor thrust and the linear
/// mooring in still water, by Newton iterations with the position Jacobian; returns the state
/// at rest and the number of iterations.
pub fn static_equilibrium(
    floater: &Floater,
    mooring: &LinearMooring,
    wind_thrust_n: f64,
    initial: &BodyState,
    tolerance: f64,
    max_iterations: usize,
) -> Result<(BodyState, usize), FloaterError> {
    let calm = crate::waves::StillWater;
    let mg = floater.mass_properties().mass_kg * floater.gravity();
    let scale = Vector6::new(mg, mg, mg, 10.0 * mg, 10.0 * mg, 10.0 * mg);
    let mut state = BodyState {
        velocity_m_per_s: Vector3::zeros(),
        angular_velocity_rad_per_s: Vector3::zeros(),
        ..*initial
    };
    let mut residual = f64::INFINITY;
    for it in 0..max_iterations {
        let f = floater.net_forces(&state, &calm, 0.0, wind_thrust_n) + mooring.force(&state);
        residual = f.component_div(&scale).amax();
        if residual < tolerance {
            return Ok((state, it));
        }
        let k = floater
            .load_jacobians(&state, &calm, 0.0, wind_thrust_n)
            .position
            - mooring.stiffness;
        let dq = k.lu().solve(&(-f)).ok_or(FloaterError::SingularMatrix {
            what: "static stiffness",
            step: it,
        })?;
        state.position_m += dq.fixed_rows::<3>(0);
        state.rotation = exp_so3(&Vector3::from(dq.fixed_rows::<3>(3))) * state.rotation;
    }
    Err(FloaterError::NewtonDiverged {
        step: 0,
        time_s: 0.0,
        iterations: max_iterations,
        residual,
    })
}
