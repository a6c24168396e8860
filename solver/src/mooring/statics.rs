//! Static equilibrium of a line: f_int(q) − f_ext(q) = 0 for the free unknowns, the fairlead and
//! anchor positions given.
//!
//! Newton's method globalised by pseudo-transient continuation (Kelley & Keyes 1998): the step
//! solves (K + σ M) Δq = −R, with M the line's mass matrix (added mass included), so a large
//! shift σ (1/s²) moves the line like an overdamped dynamic step and a small one is Newton.
//! σ shrinks after full steps and grows when the step is not a descent direction or fails the
//! line search. Without friction or current the static problem is conservative, R = ∇Π, so
//! steps are backtracked on the potential energy Π (Armijo), or accepted when they reduce ‖R‖₂
//! (near the solution, where energy differences drown in round-off). This copes with slack chain
//! (zero stiffness in compression) and with crude starting shapes, and ends with quadratic
//! convergence once σ reaches zero.
//! Converged when the largest free residual component is below the force tolerance.

use nalgebra::{Matrix3, Vector3};

use super::assembly::{assemble, free_residual_max, potential_energy, StateView};
use super::error::LineError;
use super::line::LineModel;
use super::loads::Coefficients;
use super::workspace::LineWorkspace;

/// Starting shape of the static iterations.
#[derive(Debug, Clone, PartialEq)]
pub enum StaticStart {
    /// `LineModel::geometric_guess`: straight suspended part and straight part on the seabed.
    Geometric,
    /// Node positions (one per node, fairlead first), e.g. from the analytical catenary.
    Shape(Vec<Vector3<f64>>),
    /// A full state vector (positions and gradients), e.g. a previous equilibrium.
    State(Vec<f64>),
}

/// Settings of the static solver.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct StaticParams {
    /// Largest free residual component accepted at equilibrium (N, or N·m for gradients).
    pub force_tolerance_n: f64,
    /// Iteration limit.
    pub max_iterations: usize,
    /// Initial pseudo-transient shift σ (1/s²).
    pub initial_shift_per_s2: f64,
    /// Relative pivot threshold of the banded factorisation.
    pub tiny_pivot: f64,
}

impl Default for StaticParams {
    fn default() -> Self {
        StaticParams {
            force_tolerance_n: 1e-3,
            max_iterations: 300,
            initial_shift_per_s2: 1.0,
            tiny_pivot: 1e-13,
        }
    }
}

/// Work done by the static solver.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct StaticStats {
    /// Newton iterations (factorisations of a shifted or plain tangent).
    pub iterations: usize,
    /// Residual evaluations, line-search trials included.
    pub residual_evaluations: usize,
    /// Largest free residual component at the end (N).
    pub residual_norm: f64,
}

/// A static equilibrium.
#[derive(Debug, Clone, PartialEq)]
pub struct StaticSolution {
    /// State vector (positions and gradients).
    pub q: Vec<f64>,
    /// Force of the line on the floater at the fairlead (N).
    pub fairlead_force_n: Vector3<f64>,
    /// Condensed fairlead stiffness K_c (N/m): the force on the floater changes by −K_c dx.
    pub fairlead_stiffness_n_per_m: Matrix3<f64>,
    /// Work done.
    pub stats: StaticStats,
}

fn residual_2norm(model: &LineModel, r: &[f64]) -> f64 {
    r.iter()
        .enumerate()
        .filter(|(i, _)| !model.is_constrained(*i))
        .map(|(_, x)| x * x)
        .sum::<f64>()
        .sqrt()
}

/// Solves the static equilibrium of `model` from `start`.
pub fn solve_statics(
    model: &LineModel,
    start: &StaticStart,
    params: &StaticParams,
    ws: &mut LineWorkspace,
) -> Result<StaticSolution, LineError> {
    let mut q = match start {
        StaticStart::Geometric => model.state_from_positions(&model.geometric_guess())?,
        StaticStart::Shape(p) => model.state_from_positions(p)?,
        StaticStart::State(q) => {
            if q.len() != model.dof_count() {
                return Err(LineError::invalid(
                    "start state",
                    format!("{} values", q.len()),
                    &format!("must have {} values", model.dof_count()),
                ));
            }
            q.clone()
        }
    };
    // The prescribed positions are those of the model's ends.
    let ends = *model.ends();
    q[0..3].copy_from_slice(ends.fairlead_m.as_slice());
    let a = model.anchor_dofs().start;
    q[a..a + 3].copy_from_slice(ends.anchor_m.as_slice());

    let mut stats = StaticStats::default();
    let mut sigma = params.initial_shift_per_s2;
    // Statics allocates its zero rates once per call; it is not in the time loop.
    let zeros = vec![0.0; model.dof_count()];
    let still = Coefficients::default();
    let ws_water = std::mem::take(&mut ws.water);
    assemble(
        model,
        view(&q, &zeros),
        &ws_water,
        still,
        false,
        &mut ws.residual,
        None,
    );
    stats.residual_evaluations += 1;
    let mut norm = residual_2norm(model, &ws.residual);
    let outcome = loop {
        let (worst, rmax) = free_residual_max(model, &ws.residual);
        stats.residual_norm = rmax;
        if rmax < params.force_tolerance_n {
            break Ok(());
        }
        if stats.iterations >= params.max_iterations || !rmax.is_finite() {
            break Err(LineError::StaticsDiverged {
                line: model.name().to_string(),
                iterations: stats.iterations,
                residual_norm: rmax,
                node: model.node_of_dof(worst),
            });
        }
        stats.iterations += 1;
        // Shifted tangent: the inertia terms with q̈ = 0 add σ M to the matrix only.
        let coef = Coefficients {
            axial_damping_ratio: 0.0,
            beta_p: sigma,
            gamma_p: 0.0,
        };
        assemble(
            model,
            view(&q, &zeros),
            &ws_water,
            coef,
            sigma > 0.0,
            &mut ws.residual,
            Some(&mut ws.matrix),
        );
        if ws.prepare_and_factorize(model, params.tiny_pivot).is_err() {
            sigma = (sigma * 4.0).max(1e-3);
            continue;
        }
        ws.solve_correction();
        // Directional derivative of the potential energy along the step (R = ∇Π).
        let slope: f64 = ws.rhs.iter().zip(&ws.residual).map(|(d, r)| d * r).sum();
        if slope.is_nan() || slope >= 0.0 {
            sigma = (sigma * 4.0).max(1e-3);
            assemble(
                model,
                view(&q, &zeros),
                &ws_water,
                still,
                false,
                &mut ws.residual,
                None,
            );
            stats.residual_evaluations += 1;
            continue;
        }
        let energy = potential_energy(model, &q);
        let mut alpha = 1.0;
        let mut accepted = false;
        for _ in 0..8 {
            for (t, (qi, dq)) in ws.trial_q.iter_mut().zip(q.iter().zip(&ws.rhs)) {
                *t = qi + alpha * dq;
            }
            assemble(
                model,
                view(&ws.trial_q, &zeros),
                &ws_water,
                still,
                false,
                &mut ws.residual,
                None,
            );
            stats.residual_evaluations += 1;
            let trial = residual_2norm(model, &ws.residual);
            let trial_energy = potential_energy(model, &ws.trial_q);
            // Armijo decrease of the potential energy, or (near the solution, where energy
            // differences drown in round-off) a decrease of the residual.
            if trial.is_finite() && (trial_energy <= energy + 1e-4 * alpha * slope || trial < norm)
            {
                norm = trial;
                accepted = true;
                break;
            }
            alpha *= 0.5;
        }
        if accepted {
            q.copy_from_slice(&ws.trial_q);
            if alpha == 1.0 {
                sigma = if sigma < 1e-6 { 0.0 } else { sigma / 4.0 };
            }
        } else {
            sigma = (sigma * 4.0).max(1e-3);
            assemble(
                model,
                view(&q, &zeros),
                &ws_water,
                still,
                false,
                &mut ws.residual,
                None,
            );
            stats.residual_evaluations += 1;
        }
    };
    let solution = outcome.and_then(|()| {
        // Fairlead force and condensed stiffness of the plain tangent at equilibrium.
        assemble(
            model,
            view(&q, &zeros),
            &ws_water,
            still,
            false,
            &mut ws.residual,
            Some(&mut ws.matrix),
        );
        let reaction = Vector3::new(ws.residual[0], ws.residual[1], ws.residual[2]);
        ws.prepare_and_factorize(model, params.tiny_pivot)?;
        let k = ws.condense_fairlead(model);
        Ok(StaticSolution {
            q: q.clone(),
            fairlead_force_n: -reaction,
            fairlead_stiffness_n_per_m: k,
            stats,
        })
    });
    ws.water = ws_water;
    solution
}

fn view<'a>(q: &'a [f64], zeros: &'a [f64]) -> StateView<'a> {
    StateView {
        q,
        v: zeros,
        a: zeros,
    }
}
