//! Newton-Raphson driver for quasi-static nonlinear problems r(u, λ) = 0 with load stepping
//! and cut-back.
//!
//! The load factor λ goes from the last committed value to the requested end in increments Δλ. In each step
//! the full Newton iteration K(uₖ) δu = −r(uₖ, λ), uₖ₊₁ = uₖ ⊕ δu runs until either
//! ‖r‖₂ ≤ atol + rtol · s, where s is the force scale the problem reports (typically
//! ‖λ f_ext‖₂), or the work of the correction has fallen to |δuₖ · rₖ| ≤ etol · |δu₀ · r₀|
//! (energy criterion, free of unit mixing between forces and moments, and reachable when stiff
//! axial terms put a round-off floor under the residual). A step that fails (iteration limit, non-finite
//! or exploding residual, an element that cannot be evaluated, a failed factorisation) is
//! rolled back to the last committed state and retried with Δλ × `cutback_factor`; steps that
//! converge in at most `easy_iterations` let Δλ grow by `growth_factor`. Below
//! `min_load_increment` the driver gives up with the data of the last failure.
//!
//! With `max_tangent_age` > 1 the driver runs a modified Newton iteration: it keeps the last
//! factorisation for up to that many iterations and only evaluates residuals, refactorising
//! early when an iteration contracts the residual by less than `reuse_contraction`. This pays
//! when factorising costs far more than assembling (large strand models).
//!
//! The problem owns its state and decides what "⊕" means (multiplicative rotation updates for
//! beams); history variables (friction) change only on [`NonlinearProblem::commit`].

use thiserror::Error;

use super::linear_solver::{LinalgError, LinearSolver};
use super::pattern::SparsePattern;

/// A nonlinear system the driver can solve.
pub trait NonlinearProblem {
    /// Error of the problem's own evaluation (an element that cannot be evaluated).
    type Error: std::error::Error + Clone + Send + Sync + 'static;

    /// Residual r = f_int − λ f_ext over the free equations into `residual` (zeroed by the
    /// caller) and, if asked, the tangent values on the driver's pattern into `tangent`
    /// (zeroed by the caller). Returns the force scale s of the convergence test.
    fn evaluate(
        &mut self,
        load_factor: f64,
        residual: &mut [f64],
        tangent: Option<&mut [f64]>,
    ) -> Result<f64, Self::Error>;

    /// Applies the iterative correction δu (solution of K δu = −r) to the trial state.
    fn apply_increment(&mut self, increment: &[f64]);

    /// Accepts the trial state as the converged state at `load_factor`.
    fn commit(&mut self, load_factor: f64);

    /// Discards the trial state and returns to the last committed one.
    fn restore(&mut self);

    /// Called at the start of every Newton iteration of a load step (0 for its first
    /// correction; a cut-back attempt starts again from 0), before the evaluation whose
    /// tangent the iteration factorises: a problem may use an iteration matrix that depends on
    /// it. The default does nothing.
    fn begin_iteration(&mut self, _iteration: usize) {}

    /// Weights W of the line-search merit ½ rᵀ W r, one per equation, making forces and
    /// moments commensurate (e.g. 1 for a force equation, 1/ℓ² for a moment equation with ℓ a
    /// length of the problem); `None` weighs every equation by 1.
    fn merit_weights(&self) -> Option<&[f64]> {
        None
    }

    /// A symmetric positive (semi-)definite surrogate of the tangent of the last evaluation
    /// with tangent, as values on the driver's pattern, for solvers that precondition with a
    /// symmetric factorisation ([`LinearSolver::factorize_preconditioned`]); `None`: the
    /// solver uses the tangent's own symmetric part.
    fn preconditioner(&self) -> Option<&[f64]> {
        None
    }
}

/// Parameters of the Newton driver.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct NewtonParams {
    /// Iterations allowed per load step.
    pub max_iterations: usize,
    /// Relative residual tolerance (against the problem's force scale).
    pub relative_tolerance: f64,
    /// Absolute residual tolerance (force units).
    pub absolute_tolerance: f64,
    /// Energy tolerance: converged once |δu·r| ≤ this × the step's first |δu·r|.
    pub energy_tolerance: f64,
    /// First load increment Δλ.
    pub initial_load_increment: f64,
    /// Smallest Δλ before giving up.
    pub min_load_increment: f64,
    /// Largest Δλ.
    pub max_load_increment: f64,
    /// Δλ multiplier after a failed step, in (0, 1).
    pub cutback_factor: f64,
    /// Δλ multiplier after an easy step, ≥ 1.
    pub growth_factor: f64,
    /// A step converging in at most this many iterations counts as easy.
    pub easy_iterations: usize,
    /// A residual this many times larger than the step's first one counts as divergence.
    pub divergence_ratio: f64,
    /// Iterations one factorisation may serve (1: full Newton).
    pub max_tangent_age: usize,
    /// With a reused factorisation, refactorise when ‖rₖ‖ > this × ‖rₖ₋₁‖.
    pub reuse_contraction: f64,
    /// Backtracking trials allowed on a Newton correction that does not decrease the merit
    /// ½ rᵀ W r enough (Armijo), see [`NonlinearProblem::merit_weights`] (0: plain Newton).
    pub line_search_trials: usize,
    /// Diagonal shift of the iteration matrix, as in pseudo-transient continuation (Kelley &
    /// Keyes 1998, *SIAM J. Numer. Anal.* 35(2)) with a Levenberg–Marquardt update of the
    /// shift: iteration k of a step factorises K + μ_k D instead of K, with D = |diag K|,
    /// μ_0 = this, μ_{k+1} = μ_k min(1/4, ‖r_{k+1}‖/‖r_k‖) after a full correction that
    /// lowered the residual and 4 μ_k otherwise (within [1e-3, 100] × this when raised; dropped once below 1e-10), so
    /// the shift vanishes in a few successful iterations and Newton's quadratic convergence
    /// returns. It limits the corrections along the nearly singular directions of a tangent
    /// far from the solution (frictional contacts that carry almost no normal force yet) and
    /// changes only the path of the iterations: the converged state solves r = 0 as before.
    /// 0: plain Newton.
    pub pseudo_transient_shift: f64,
    /// Inexact Newton (Dembo, Eisenstat & Steihaug 1982): iteration k asks the linear solver
    /// for a relative residual η_k only (`forcing_term`: this at the first iteration and as
    /// the upper bound of η_k, then Eisenstat & Walker's choice 2, never tighter than what
    /// brings the residual to the convergence tolerance), so the early corrections cost fewer
    /// Krylov iterations and the convergence stays superlinear; direct solvers solve exactly
    /// anyway. 0: solve to the linear solver's own tolerance.
    pub linear_forcing: f64,
}

impl Default for NewtonParams {
    fn default() -> Self {
        Self {
            max_iterations: 25,
            relative_tolerance: 1e-9,
            absolute_tolerance: 1e-12,
            energy_tolerance: 1e-20,
            initial_load_increment: 1.0,
            min_load_increment: 1e-6,
            max_load_increment: 1.0,
            cutback_factor: 0.5,
            growth_factor: 1.5,
            easy_iterations: 4,
            divergence_ratio: 1e8,
            max_tangent_age: 1,
            reuse_contraction: 0.25,
            line_search_trials: 0,
            pseudo_transient_shift: 0.0,
            linear_forcing: 0.0,
        }
    }
}

/// A Newton parameter out of its admissible range.
#[derive(Debug, Clone, PartialEq, Error)]
#[error("newton parameter {field} = {value}: {reason}")]
pub struct NewtonParamError {
    /// Parameter name.
    pub field: &'static str,
    /// Its value.
    pub value: f64,
    /// What is required.
    pub reason: &'static str,
}

impl NewtonParams {
    /// Checks every parameter.
    pub fn validated(self) -> Result<Self, NewtonParamError> {
        let check = |ok: bool, field, value, reason| {
            if ok {
                Ok(())
            } else {
                Err(NewtonParamError {
                    field,
                    value,
                    reason,
                })
            }
        };
        check(
            self.max_iterations >= 1,
            "max_iterations",
            self.max_iterations as f64,
            "must be ≥ 1",
        )?;
        check(
            self.relative_tolerance >= 0.0,
            "relative_tolerance",
            self.relative_tolerance,
            "must be ≥ 0",
        )?;
        check(
            self.absolute_tolerance >= 0.0,
            "absolute_tolerance",
            self.absolute_tolerance,
            "must be ≥ 0",
        )?;
        check(
            self.energy_tolerance >= 0.0,
            "energy_tolerance",
            self.energy_tolerance,
            "must be ≥ 0",
        )?;
        check(
            self.relative_tolerance > 0.0 || self.absolute_tolerance > 0.0,
            "relative_tolerance",
            self.relative_tolerance,
            "one tolerance must be > 0",
        )?;
        check(
            self.min_load_increment > 0.0,
            "min_load_increment",
            self.min_load_increment,
            "must be > 0",
        )?;
        check(
            self.initial_load_increment >= self.min_load_increment
                && self.initial_load_increment <= self.max_load_increment,
            "initial_load_increment",
            self.initial_load_increment,
            "must lie in [min_load_increment, max_load_increment]",
        )?;
        check(
            self.cutback_factor > 0.0 && self.cutback_factor < 1.0,
            "cutback_factor",
            self.cutback_factor,
            "must lie in (0, 1)",
        )?;
        check(
            self.growth_factor >= 1.0,
            "growth_factor",
            self.growth_factor,
            "must be ≥ 1",
        )?;
        check(
            self.max_tangent_age >= 1,
            "max_tangent_age",
            self.max_tangent_age as f64,
            "must be ≥ 1",
        )?;
        check(
            self.reuse_contraction > 0.0 && self.reuse_contraction < 1.0,
            "reuse_contraction",
            self.reuse_contraction,
            "must lie in (0, 1)",
        )?;
        check(
            self.pseudo_transient_shift >= 0.0 && self.pseudo_transient_shift.is_finite(),
            "pseudo_transient_shift",
            self.pseudo_transient_shift,
            "must be finite and ≥ 0",
        )?;
        check(
            (0.0..1.0).contains(&self.linear_forcing),
            "linear_forcing",
            self.linear_forcing,
            "must lie in [0, 1)",
        )?;
        check(
            self.divergence_ratio > 1.0,
            "divergence_ratio",
            self.divergence_ratio,
            "must be > 1",
        )?;
        Ok(self)
    }
}

/// Work counts of a Newton run (accumulated over calls).
#[derive(Debug, Clone, Default, PartialEq)]
pub struct NewtonStats {
    /// Accepted load steps.
    pub steps: usize,
    /// Rejected attempts (each followed by a cut-back).
    pub cutbacks: usize,
    /// Newton iterations (linear solves), accepted and rejected attempts together.
    pub iterations: usize,
    /// Numeric factorisations.
    pub factorisations: usize,
    /// Residual and tangent evaluations.
    pub evaluations: usize,
    /// Iterations of each accepted step.
    pub step_iterations: Vec<usize>,
    /// Load factor reached by each accepted step.
    pub load_factors: Vec<f64>,
    /// ‖r‖₂ at every evaluation of the accepted steps, in order.
    pub residual_history: Vec<f64>,
}

/// Why the driver gave up (after all cut-backs).
#[derive(Debug, Clone, PartialEq, Error)]
pub enum NewtonError<E: std::error::Error + 'static> {
    /// The parameters are invalid.
    #[error(transparent)]
    Params(#[from] NewtonParamError),
    /// The workspace was built for another system size.
    #[error("workspace for {workspace} equations, pattern has {pattern}")]
    SizeMismatch {
        /// Workspace size.
        workspace: usize,
        /// Pattern size.
        pattern: usize,
    },
    /// Newton did not converge even with the smallest load increment.
    #[error(
        "newton diverged at step {step}, iteration {iteration}: residual {residual:e} \
         (tolerance {tolerance:e}) at load factor {load_factor}"
    )]
    NewtonDiverged {
        /// Load step (accepted steps before it).
        step: usize,
        /// Iteration of the last attempt at which it was declared diverged.
        iteration: usize,
        /// Residual norm then.
        residual: f64,
        /// Tolerance it had to reach.
        tolerance: f64,
        /// Target load factor of the attempt.
        load_factor: f64,
    },
    /// The problem could not be evaluated even with the smallest load increment.
    #[error("evaluation failed at step {step}, iteration {iteration}, load factor {load_factor}: {source}")]
    Problem {
        /// Load step.
        step: usize,
        /// Iteration.
        iteration: usize,
        /// Target load factor of the attempt.
        load_factor: f64,
        /// The problem's error.
        source: E,
    },
    /// The linear solver failed even with the smallest load increment.
    #[error("linear solve failed at step {step}, iteration {iteration}, load factor {load_factor}: {source}")]
    Linear {
        /// Load step.
        step: usize,
        /// Iteration.
        iteration: usize,
        /// Target load factor of the attempt.
        load_factor: f64,
        /// The solver's error.
        source: LinalgError,
    },
}

/// Scratch vectors of the driver, sized once for a pattern.
#[derive(Debug, Clone)]
pub struct NewtonWorkspace {
    residual: Vec<f64>,
    increment: Vec<f64>,
    values: Vec<f64>,
    scratch: Vec<f64>,
    /// Position of every diagonal nonzero in the values (pseudo-transient shift).
    diagonal: Vec<usize>,
    /// Shifted copy of the problem's preconditioner surrogate.
    surrogate: Vec<f64>,
}

impl NewtonWorkspace {
    /// Workspace for systems on `pattern`.
    pub fn new(pattern: &SparsePattern) -> Self {
        Self {
            residual: vec![0.0; pattern.size()],
            increment: vec![0.0; pattern.size()],
            values: vec![0.0; pattern.nnz()],
            scratch: vec![0.0; pattern.size()],
            diagonal: (0..pattern.size())
                .map(|c| {
                    let range = pattern.col_ptr()[c]..pattern.col_ptr()[c + 1];
                    pattern.row_idx()[range.clone()]
                        .iter()
                        .position(|&r| r == c)
                        .map_or(usize::MAX, |k| range.start + k)
                })
                .collect(),
            surrogate: Vec::new(),
        }
    }

    /// Adds μ |K_ii| to every diagonal nonzero of the tangent in the workspace and, when the
    /// problem gives a preconditioner surrogate, to a copy of it in `self.surrogate`.
    fn shift_diagonal(&mut self, mu: f64, surrogate: Option<&[f64]>) {
        if let Some(p) = surrogate {
            self.surrogate.clear();
            self.surrogate.extend_from_slice(p);
        }
        for &k in &self.diagonal {
            if k == usize::MAX {
                continue;
            }
            let d = mu * self.values[k].abs();
            self.values[k] += d;
            if surrogate.is_some() {
                self.surrogate[k] += d;
            }
        }
    }

    /// Residual of the last evaluation.
    pub fn residual(&self) -> &[f64] {
        &self.residual
    }
}

enum Failure<E> {
    Diverged {
        iteration: usize,
        residual: f64,
        tolerance: f64,
    },
    Problem {
        iteration: usize,
        source: E,
    },
    Linear {
        iteration: usize,
        source: LinalgError,
    },
}

/// Drives `problem` from its committed load factor `start` to `end` (usually 0 → 1).
#[allow(clippy::too_many_arguments)]
pub fn solve_load_path<P: NonlinearProblem, S: LinearSolver>(
    problem: &mut P,
    start: f64,
    end: f64,
    pattern: &SparsePattern,
    solver: &mut S,
    params: &NewtonParams,
    workspace: &mut NewtonWorkspace,
    stats: &mut NewtonStats,
) -> Result<(), NewtonError<P::Error>> {
    let params = params.validated()?;
    if workspace.residual.len() != pattern.size() || workspace.values.len() != pattern.nnz() {
        return Err(NewtonError::SizeMismatch {
            workspace: workspace.residual.len(),
            pattern: pattern.size(),
        });
    }
    let mut lambda = start;
    let mut dlambda = params.initial_load_increment;
    while lambda < end - 1e-12 {
        let target = if lambda + dlambda > end - 1e-9 {
            end
        } else {
            lambda + dlambda
        };
        let history_len = stats.residual_history.len();
        match newton_step(problem, target, pattern, solver, &params, workspace, stats) {
            Ok(iterations) => {
                problem.commit(target);
                stats.steps += 1;
                stats.step_iterations.push(iterations);
                stats.load_factors.push(target);
                tracing::debug!(
                    step = stats.steps,
                    load_factor = target,
                    iterations,
                    "load step converged"
                );
                lambda = target;
                if iterations <= params.easy_iterations {
                    dlambda = (dlambda * params.growth_factor).min(params.max_load_increment);
                }
            }
            Err(failure) => {
                problem.restore();
                stats.residual_history.truncate(history_len);
                stats.cutbacks += 1;
                dlambda *= params.cutback_factor;
                tracing::debug!(
                    step = stats.steps,
                    load_factor = target,
                    next_increment = dlambda,
                    "load step cut back"
                );
                if dlambda < params.min_load_increment {
                    let step = stats.steps;
                    return Err(match failure {
                        Failure::Diverged {
                            iteration,
                            residual,
                            tolerance,
                        } => NewtonError::NewtonDiverged {
                            step,
                            iteration,
                            residual,
                            tolerance,
                            load_factor: target,
                        },
                        Failure::Problem { iteration, source } => NewtonError::Problem {
                            step,
                            iteration,
                            load_factor: target,
                            source,
                        },
                        Failure::Linear { iteration, source } => NewtonError::Linear {
                            step,
                            iteration,
                            load_factor: target,
                            source,
                        },
                    });
                }
            }
        }
    }
    Ok(())
}

/// Residual (and, if `with_tangent`, tangent) at the trial state: (‖r‖₂, force scale).
fn evaluate<P: NonlinearProblem>(
    problem: &mut P,
    load_factor: f64,
    ws: &mut NewtonWorkspace,
    with_tangent: bool,
    stats: &mut NewtonStats,
) -> Result<(f64, f64), P::Error> {
    ws.residual.iter_mut().for_each(|v| *v = 0.0);
    stats.evaluations += 1;
    let scale = if with_tangent {
        ws.values.iter_mut().for_each(|v| *v = 0.0);
        problem.evaluate(load_factor, &mut ws.residual, Some(&mut ws.values))?
    } else {
        problem.evaluate(load_factor, &mut ws.residual, None)?
    };
    let norm = ws.residual.iter().map(|v| v * v).sum::<f64>().sqrt();
    Ok((norm, scale))
}

/// Weighted merit ½ rᵀ W r of the residual in the workspace.
fn merit(residual: &[f64], weights: Option<&[f64]>) -> f64 {
    0.5 * match weights {
        Some(w) => residual.iter().zip(w).map(|(r, w)| w * r * r).sum::<f64>(),
        None => residual.iter().map(|r| r * r).sum::<f64>(),
    }
}

/// Backtracking line search after the full correction δu has been applied (Armijo on the
/// merit φ(a) = ½ r(u + a δu)ᵀ W r(u + a δu), whose slope at a = 0 is −2 φ(0) for the exact
/// tangent): the fraction a is accepted when φ(a) ≤ (1 − 2c a) φ(0), c = 1e-4; otherwise the
/// next fraction is the minimiser of the quadratic through φ(0), φ'(0) and φ(a), kept within
/// [0.1 a, 0.5 a]. Moving between fractions applies (a_new − a) δu, exact for the additive and
/// the left-multiplied rotation-vector updates along the same δu. After `line_search_trials`
/// rejected fractions the best one seen is kept. This is what breaks the two-cycles of full
/// Newton steps on frictional contact, where the slip direction g_T/|g_T| turns within one
/// correction. Returns the fraction kept.
fn line_search<P: NonlinearProblem>(
    problem: &mut P,
    load_factor: f64,
    phi0: f64,
    params: &NewtonParams,
    ws: &mut NewtonWorkspace,
    stats: &mut NewtonStats,
) -> SearchOutcome {
    const ARMIJO: f64 = 1e-4;
    let mut fraction = 1.0;
    let mut best = (f64::INFINITY, 1.0);
    for trial in 0..=params.line_search_trials {
        let evaluated = evaluate(problem, load_factor, ws, false, stats);
        let phi = match evaluated {
            Ok((norm, _)) if norm.is_finite() => merit(&ws.residual, problem.merit_weights()),
            _ => f64::INFINITY,
        };
        if phi < best.0 {
            best = (phi, fraction);
        }
        if phi <= (1.0 - 2.0 * ARMIJO * fraction) * phi0 {
            if trial > 0 {
                tracing::trace!(trial, fraction, merit_ratio = phi / phi0, "line search");
            }
            return SearchOutcome {
                fraction,
                residual: evaluated.ok(),
            };
        }
        let next = if trial == params.line_search_trials {
            best.1
        } else if phi.is_finite() {
            // φ(a) ≈ φ0 (1 − 2a) + c a² → minimiser a* = φ0 a² / (φ(a) − φ0 + 2 φ0 a)
            let q = phi0 * fraction * fraction / (phi - phi0 + 2.0 * phi0 * fraction);
            q.clamp(0.1 * fraction, 0.5 * fraction)
        } else {
            0.1 * fraction
        };
        if next != fraction {
            ws.scratch
                .iter_mut()
                .zip(&ws.increment)
                .for_each(|(s, d)| *s = (next - fraction) * d);
            problem.apply_increment(&ws.scratch);
            fraction = next;
        }
    }
    SearchOutcome {
        fraction,
        residual: None,
    }
}

/// What a line search leaves: the fraction of the correction kept, and the residual norm and
/// force scale at the state it leaves when that state was the last one evaluated (the residual
/// is then in the workspace).
struct SearchOutcome {
    fraction: f64,
    residual: Option<(f64, f64)>,
}

/// Relative residual asked of the linear solve of a Newton iteration (Eisenstat & Walker 1996,
/// *Choosing the forcing terms in an inexact Newton method*, SIAM J. Sci. Comput. 17, choice 2
/// with γ = 0.9 and α = 2, with the safeguards of Kelley 2003, *Solving Nonlinear Equations
/// with Newton's Method*, SIAM, §3.2.3): `max` at the first iteration; then γ (‖r_k‖ /
/// ‖r_{k−1}‖)², which follows the quadratic convergence, kept above γ η_{k−1}² when that
/// exceeds 0.1 (so that one lucky contraction does not make η collapse), at most `max`; and
/// never below half the ratio `tolerance_ratio` = tolerance / ‖r_k‖ of the convergence test,
/// since a correction solved beyond that buys nothing: the next residual only has to pass the
/// test. `ratio` = ‖r_k‖ / ‖r_{k−1}‖ (`None` at the first iteration).
pub(crate) fn forcing_term(
    max: f64,
    previous: f64,
    ratio: Option<f64>,
    tolerance_ratio: f64,
) -> f64 {
    const GAMMA: f64 = 0.9;
    let eta = match ratio {
        None => max,
        Some(ratio) => {
            let carried = GAMMA * previous * previous;
            let eta = GAMMA * ratio * ratio;
            if carried > 0.1 { eta.max(carried) } else { eta }.min(max)
        }
    };
    eta.max(0.5 * tolerance_ratio)
}

/// Pseudo-transient shifts below this are dropped ([`NewtonParams::pseudo_transient_shift`]).
const PSEUDO_TRANSIENT_FLOOR: f64 = 1e-10;

/// Newton iterations at a fixed load factor; returns the iteration count on convergence.
fn newton_step<P: NonlinearProblem, S: LinearSolver>(
    problem: &mut P,
    load_factor: f64,
    pattern: &SparsePattern,
    solver: &mut S,
    params: &NewtonParams,
    ws: &mut NewtonWorkspace,
    stats: &mut NewtonStats,
) -> Result<usize, Failure<P::Error>> {
    let mut first = f64::NAN;
    let mut first_energy = f64::NAN;
    let mut previous = f64::INFINITY;
    let mut age = usize::MAX;
    // pseudo-transient shift and what the last correction achieved
    let mut mu = params.pseudo_transient_shift;
    let mut full_step = true;
    // forcing term and residual of the last linear solve
    let (mut eta, mut solved_norm) = (params.linear_forcing, f64::NAN);
    // residual norm and force scale of the current state when the line search left them
    let mut searched: Option<(f64, f64)> = None;
    for iteration in 0..=params.max_iterations {
        if let Some((norm, scale)) = searched.take() {
            // converged at the state the line search accepted: no tangent needed there
            let tolerance = params.absolute_tolerance + params.relative_tolerance * scale;
            if norm <= tolerance {
                stats.residual_history.push(norm);
                tracing::trace!(
                    load_factor,
                    iteration,
                    residual = norm,
                    tolerance,
                    "Newton iteration, converged at the line search's residual"
                );
                return Ok(iteration);
            }
        }
        problem.begin_iteration(iteration);
        let mut fresh = iteration == 0 || age >= params.max_tangent_age;
        let (mut norm, mut scale) = evaluate(problem, load_factor, ws, fresh, stats)
            .map_err(|source| Failure::Problem { iteration, source })?;
        if !fresh && norm > params.reuse_contraction * previous {
            // the old factorisation no longer contracts well enough: fresh tangent
            fresh = true;
            (norm, scale) = evaluate(problem, load_factor, ws, true, stats)
                .map_err(|source| Failure::Problem { iteration, source })?;
        }
        if iteration > 0 && mu > 0.0 {
            mu = if norm < previous && full_step {
                // at least as fast as the residual falls, so that the shift is O(‖r‖) and
                // the convergence stays quadratic near the root
                mu * (norm / previous).min(0.25)
            } else {
                (4.0 * mu).max(1e-3 * params.pseudo_transient_shift)
            }
            .min(1e2 * params.pseudo_transient_shift);
        }
        previous = norm;
        stats.residual_history.push(norm);
        let tolerance = params.absolute_tolerance + params.relative_tolerance * scale;
        tracing::trace!(
            load_factor,
            iteration,
            residual = norm,
            tolerance,
            fresh,
            "Newton iteration"
        );
        if norm <= tolerance {
            return Ok(iteration);
        }
        if iteration == 0 {
            first = norm;
        }
        if !norm.is_finite()
            || norm > params.divergence_ratio * first
            || iteration == params.max_iterations
        {
            return Err(Failure::Diverged {
                iteration,
                residual: norm,
                tolerance,
            });
        }
        if fresh {
            stats.factorisations += 1;
            let factorised = if mu > PSEUDO_TRANSIENT_FLOOR {
                let surrogate = problem.preconditioner();
                let shifted_surrogate = surrogate.is_some();
                ws.shift_diagonal(mu, surrogate);
                let surrogate = shifted_surrogate.then_some(ws.surrogate.as_slice());
                solver.factorize_preconditioned(pattern, &ws.values, surrogate)
            } else {
                solver.factorize_preconditioned(pattern, &ws.values, problem.preconditioner())
            };
            factorised.map_err(|source| Failure::Linear { iteration, source })?;
            age = 0;
        }
        age += 1;
        ws.increment
            .iter_mut()
            .zip(&ws.residual)
            .for_each(|(d, r)| *d = -r);
        if params.linear_forcing > 0.0 {
            let ratio = (iteration > 0).then(|| norm / solved_norm);
            eta = forcing_term(params.linear_forcing, eta, ratio, tolerance / norm);
            solver.set_forcing(Some(eta));
        }
        solved_norm = norm;
        let solved = solver.solve_in_place(&mut ws.increment);
        if params.linear_forcing > 0.0 {
            solver.set_forcing(None);
        }
        solved.map_err(|source| Failure::Linear { iteration, source })?;
        stats.iterations += 1;
        problem.apply_increment(&ws.increment);
        let energy = ws
            .increment
            .iter()
            .zip(&ws.residual)
            .map(|(d, r)| d * r)
            .sum::<f64>()
            .abs();
        if iteration == 0 {
            first_energy = energy;
        } else if energy <= params.energy_tolerance * first_energy {
            return Ok(iteration + 1);
        }
        if params.line_search_trials > 0 {
            let phi0 = merit(&ws.residual, problem.merit_weights());
            let outcome = line_search(problem, load_factor, phi0, params, ws, stats);
            full_step = outcome.fraction == 1.0;
            searched = outcome.residual;
        }
    }
    // the loop returns at iteration == max_iterations at the latest
    Err(Failure::Diverged {
        iteration: params.max_iterations,
        residual: f64::NAN,
        tolerance: 0.0,
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::linalg::cholesky::{CholeskyKind, SparseCholesky};
    use crate::linalg::pattern::{Equation, Storage};
    use faer::Par;

    #[derive(Debug, Clone, PartialEq, thiserror::Error)]
    #[error("spring overstretched: u = {u}")]
    struct Overstretched {
        u: f64,
    }

    /// Hardening spring k u + c u³ = λ F, which refuses trial states with u > u_max (as an
    /// element refuses a too-large rotation).
    struct Spring {
        u: f64,
        committed: f64,
        force: f64,
        u_max: f64,
    }

    impl Spring {
        /// Unloaded spring (u = 0) under `force` at full load, refusing u > `u_max`.
        fn at_rest(force: f64, u_max: f64) -> Self {
            Self {
                u: 0.0,
                committed: 0.0,
                force,
                u_max,
            }
        }
    }

    impl NonlinearProblem for Spring {
        type Error = Overstretched;
        fn evaluate(
            &mut self,
            lambda: f64,
            r: &mut [f64],
            k: Option<&mut [f64]>,
        ) -> Result<f64, Overstretched> {
            if self.u > self.u_max {
                return Err(Overstretched { u: self.u });
            }
            r[0] = 2.0 * self.u + 5.0 * self.u.powi(3) - lambda * self.force;
            if let Some(k) = k {
                k[0] = 2.0 + 15.0 * self.u * self.u;
            }
            Ok(lambda * self.force)
        }
        fn apply_increment(&mut self, d: &[f64]) {
            self.u += d[0];
        }
        fn commit(&mut self, _: f64) {
            self.committed = self.u;
        }
        fn restore(&mut self) {
            self.u = self.committed;
        }
    }

    fn run(
        spring: &mut Spring,
        params: &NewtonParams,
    ) -> (Result<(), NewtonError<Overstretched>>, NewtonStats) {
        let p = SparsePattern::new(1, Storage::Upper, &[[Equation::free(0).unwrap()]]).unwrap();
        let mut solver = SparseCholesky::new(&p, CholeskyKind::Llt, Par::Seq).unwrap();
        let mut ws = NewtonWorkspace::new(&p);
        let mut stats = NewtonStats::default();
        let r = solve_load_path(
            spring,
            0.0,
            1.0,
            &p,
            &mut solver,
            params,
            &mut ws,
            &mut stats,
        );
        (r, stats)
    }

    #[test]
    fn hardening_spring_converges_quadratically_in_one_step() {
        let mut s = Spring::at_rest(7.0, 10.0);
        let (r, stats) = run(&mut s, &NewtonParams::default());
        r.unwrap();
        // exact root of 5u³ + 2u − 7 = 0 is u = 1
        assert!((s.u - 1.0).abs() < 1e-12);
        assert_eq!(stats.steps, 1);
        assert_eq!(stats.step_iterations, vec![8]);
        assert_eq!(stats.factorisations, stats.iterations);
        // quadratic convergence: r_{k+1} ≤ C r_k² near the root (C ≈ f''/(2f'²) ≈ 0.2 here)
        let h = &stats.residual_history;
        let n = h.len();
        assert!(h[n - 2] <= 1.0 * h[n - 3] * h[n - 3], "{h:?}");
    }

    #[test]
    fn forcing_terms_follow_eisenstat_walker_choice_2_with_the_safeguards() {
        let close = |a: f64, b: f64| (a - b).abs() <= 1e-15 * b.abs();
        // first iteration: the bound itself
        assert_eq!(forcing_term(0.01, 0.01, None, 1e-6), 0.01);
        // residual down by 100: γ (1e-2)² = 9e-5
        assert!(close(forcing_term(0.01, 0.01, Some(1e-2), 1e-9), 9e-5));
        // a slow contraction is capped by the bound
        assert_eq!(forcing_term(0.01, 0.01, Some(0.5), 1e-9), 0.01);
        // γ η_{k−1}² = 0.225 > 0.1 is carried over, then capped
        assert_eq!(forcing_term(1.0, 0.5, Some(1e-3), 1e-9), 0.225);
        assert_eq!(forcing_term(0.01, 0.5, Some(1e-3), 1e-9), 0.01);
        // close to convergence: half of tolerance / ‖r‖, even above the bound
        assert!(close(forcing_term(0.01, 0.01, Some(1e-2), 5e-3), 2.5e-3));
        assert!(close(forcing_term(0.01, 0.01, Some(1e-2), 0.4), 0.2));
    }

    /// Chain of n hardening springs k (u_i − u_{i−1}) + c u_i³ with a skew coupling
    /// s (u_{i+1} − u_{i−1}) (non-symmetric tangent) and end loads.
    struct SkewChain {
        u: Vec<f64>,
        committed: Vec<f64>,
        /// Full-storage pattern of the chain's elements ([`chain_pattern`]).
        pattern: SparsePattern,
    }

    impl SkewChain {
        const K: f64 = 50.0;
        const C: f64 = 30.0;
        const SKEW: f64 = 8.0;

        fn residual(&self, i: usize, lambda: f64) -> f64 {
            let n = self.u.len();
            let at = |j: Option<usize>| j.map_or(0.0, |j| self.u[j]);
            let (l, r) = (i.checked_sub(1), (i + 1 < n).then_some(i + 1));
            Self::K * (2.0 * self.u[i] - at(l) - at(r))
                + Self::C * self.u[i].powi(3)
                + Self::SKEW * (at(r) - at(l))
                - lambda * (1.0 + (i % 3) as f64)
        }
    }

    impl NonlinearProblem for SkewChain {
        type Error = Overstretched;
        fn evaluate(
            &mut self,
            lambda: f64,
            r: &mut [f64],
            k: Option<&mut [f64]>,
        ) -> Result<f64, Overstretched> {
            let n = self.u.len();
            for (i, ri) in r.iter_mut().enumerate() {
                *ri = self.residual(i, lambda);
            }
            if let Some(k) = k {
                // element e couples (e, e + 1), column-major 2 × 2 blocks; a node's diagonal
                // 2K + 3C u² comes from the two elements touching it (both halves at the ends)
                for e in 0..n - 1 {
                    let mut block = [0.0; 4];
                    block[0] = Self::K
                        + if e == 0 {
                            Self::K + 3.0 * Self::C * self.u[0].powi(2)
                        } else {
                            0.0
                        };
                    let last = if e + 2 == n { Self::K } else { 0.0 };
                    block[3] = Self::K + last + 3.0 * Self::C * self.u[e + 1].powi(2);
                    // ∂r_{e+1}/∂u_e = −K − S, ∂r_e/∂u_{e+1} = −K + S
                    block[1] = -Self::K - Self::SKEW;
                    block[2] = -Self::K + Self::SKEW;
                    self.pattern.add_element_matrix(k, e, &block);
                }
            }
            Ok(lambda * 3.0)
        }
        fn apply_increment(&mut self, d: &[f64]) {
            self.u.iter_mut().zip(d).for_each(|(u, d)| *u += d);
        }
        fn commit(&mut self, _: f64) {
            self.committed.clone_from(&self.u);
        }
        fn restore(&mut self) {
            self.u.clone_from(&self.committed);
        }
    }

    fn chain_pattern(n: usize) -> SparsePattern {
        let elements: Vec<Vec<Equation>> = (1..n)
            .map(|i| vec![Equation::free(i - 1).unwrap(), Equation::free(i).unwrap()])
            .collect();
        SparsePattern::new(n, Storage::Full, &elements).unwrap()
    }

    #[test]
    fn inexact_newton_reaches_the_same_root_with_fewer_krylov_iterations() {
        use crate::linalg::{GmresParams, SplitSolver};
        let n = 400;
        let p = chain_pattern(n);
        let solve = |linear_forcing: f64| {
            let mut chain = SkewChain {
                u: vec![0.0; n],
                committed: vec![0.0; n],
                pattern: p.clone(),
            };
            let params = NewtonParams {
                linear_forcing,
                ..NewtonParams::default()
            };
            let mut solver = SplitSolver::new(&p, GmresParams::default()).unwrap();
            let mut ws = NewtonWorkspace::new(&p);
            let mut stats = NewtonStats::default();
            solve_load_path(
                &mut chain,
                0.0,
                1.0,
                &p,
                &mut solver,
                &params,
                &mut ws,
                &mut stats,
            )
            .unwrap();
            (chain.u, stats.iterations, solver.stats().iterations)
        };
        let (exact, newton_exact, krylov_exact) = solve(0.0);
        let (inexact, newton_inexact, krylov_inexact) = solve(0.01);
        // both satisfy the same residual test; the roots agree to its size over the stiffness
        let scale = exact.iter().fold(0.0_f64, |m, u| m.max(u.abs()));
        let diff = exact
            .iter()
            .zip(&inexact)
            .fold(0.0_f64, |m, (a, b)| m.max((a - b).abs()));
        assert!(diff <= 1e-5 * scale, "{diff:e} of {scale:e}");
        assert!(
            krylov_inexact * 2 < krylov_exact,
            "{krylov_inexact} vs {krylov_exact} GMRES iterations"
        );
        assert!(
            newton_inexact <= newton_exact + 2,
            "{newton_inexact} vs {newton_exact} Newton iterations"
        );
    }

    #[test]
    fn reused_factorisation_converges_to_the_same_root_with_fewer_factorisations() {
        let mut s = Spring::at_rest(7.0, 10.0);
        let params = NewtonParams {
            max_tangent_age: 50,
            initial_load_increment: 0.25,
            max_load_increment: 0.25,
            max_iterations: 60,
            ..Default::default()
        };
        let (r, stats) = run(&mut s, &params);
        r.unwrap();
        // converged to ‖r‖ ≤ 1e-9 · 7 N on a tangent of 17 N/m: |u − 1| ≲ 4e-10
        assert!((s.u - 1.0).abs() < 1e-9, "{}", s.u);
        assert!(stats.factorisations < stats.iterations, "{stats:?}");
    }

    #[test]
    fn pseudo_transient_shift_keeps_the_iterates_in_bounds_and_converges_to_the_same_root() {
        // plain Newton's first iterate from u = 0 is 7/2, beyond u_max = 1.2 (cut-backs, see
        // the test below); with K + μ₀|K|, μ₀ = 4, it is 7/10, and μ falls by 4 per successful
        // iteration, so the last iterations are Newton's again
        let mut s = Spring::at_rest(7.0, 1.2);
        let params = NewtonParams {
            pseudo_transient_shift: 4.0,
            ..NewtonParams::default()
        };
        let (r, stats) = run(&mut s, &params);
        r.unwrap();
        // converged to ‖r‖ ≤ 1e-9 · 7 N on a tangent of 17 N/m: |u − 1| ≲ 4e-10
        assert!((s.u - 1.0).abs() < 1e-9, "{}", s.u);
        assert_eq!(stats.cutbacks, 0, "{stats:?}");
        assert_eq!(stats.steps, 1);
        let h = &stats.residual_history;
        let n = h.len();
        assert!(h[n - 2] <= 1.0 * h[n - 3] * h[n - 3], "{h:?}");
        // an invalid shift is refused by name
        let bad = NewtonParams {
            pseudo_transient_shift: -1.0,
            ..NewtonParams::default()
        };
        assert_eq!(bad.validated().unwrap_err().field, "pseudo_transient_shift");
        let bad = NewtonParams {
            linear_forcing: 1.0,
            ..NewtonParams::default()
        };
        assert_eq!(bad.validated().unwrap_err().field, "linear_forcing");
    }

    #[test]
    fn refused_trial_states_trigger_cutbacks_until_the_path_is_followed() {
        // the first Newton iterate from u = 0 at full load overshoots u_max
        let mut s = Spring::at_rest(7.0, 1.2);
        let (r, stats) = run(&mut s, &NewtonParams::default());
        r.unwrap();
        assert!((s.u - 1.0).abs() < 1e-12);
        assert!(stats.cutbacks >= 1);
        assert_eq!(*stats.load_factors.last().unwrap(), 1.0);
    }

    #[test]
    fn non_converging_step_is_cut_back_then_reported_with_step_iteration_and_residual() {
        // two Newton iterations never reach ‖r‖ ≤ 1e-9 · λ F on the cubic spring: every attempt
        // fails, Δλ is halved 1 → 0.5 → 0.25 → 0.125 → 0.0625 < min, and the last attempt
        // (target λ = 0.125) is reported
        let mut s = Spring::at_rest(7.0, 10.0);
        let (r, stats) = run(
            &mut s,
            &NewtonParams {
                max_iterations: 2,
                min_load_increment: 0.1,
                ..Default::default()
            },
        );
        assert_eq!(stats.cutbacks, 4);
        assert_eq!(stats.steps, 0);
        match r {
            Err(NewtonError::NewtonDiverged {
                step,
                iteration,
                residual,
                tolerance,
                load_factor,
            }) => {
                assert_eq!(step, 0);
                assert_eq!(iteration, 2);
                assert!(
                    residual.is_finite() && residual > tolerance,
                    "{residual} {tolerance}"
                );
                assert_eq!(load_factor, 0.125);
            }
            other => panic!("unexpected {other:?}"),
        }
        // the state is rolled back to the last committed one
        assert_eq!(s.u, 0.0);
    }

    #[test]
    fn impossible_problem_reports_the_failure_with_its_step() {
        let mut s = Spring::at_rest(7.0, 0.5);
        let (r, _) = run(
            &mut s,
            &NewtonParams {
                min_load_increment: 1e-3,
                ..Default::default()
            },
        );
        match r {
            Err(NewtonError::Problem {
                step, load_factor, ..
            }) => {
                assert!(step > 0);
                assert!(load_factor < 1.0);
            }
            other => panic!("unexpected {other:?}"),
        }
    }
}
