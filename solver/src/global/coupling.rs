//! One coupled time step of the floater and its lines, t_n → t_{n+1} = t_n + h
//! (`docs/global-stage.md`).
//!
//! The floater unknown is its acceleration ν̇_{n+1} (generalised-α with the lines' h and ρ∞).
//! A step is a sequence of passes:
//!
//! 1. every line is stepped with the fairlead motion of the trial floater state: the first pass
//!    from the line's own predictor, later passes warm-started from the previous pass's end
//!    state moved to the new fairlead motion by the line's condensed response
//!    ([`LineIntegrator::shift_fairlead`]); each returns its force on the floater f_i and its
//!    condensed fairlead stiffness K_i = −∂f_i/∂x_p (from its latest factorisation);
//! 2. the floater residual r = M(q) ν̇ − f(q, ν, t) − Σ F_i with those forces decides
//!    convergence (scaled by mg for forces and 10 m·mg for moments);
//! 3. otherwise the floater is solved by Newton with every line force linearised about the
//!    position it was computed at, f_i(x) ≈ f_i − K_i (x − x_i): the lines are not re-stepped
//!    inside this loop, only the (cheap) rigid-body loads are re-evaluated. The floater
//!    Jacobians ∂f/∂q, ∂f/∂ν are those of the predictor.
//!
//! Because K_i is the exact Schur complement of line i (up to a reused factorisation), the
//! passes are Newton's method on the monolithic system; a pass whose warm start already meets
//! the line tolerance costs one residual assembly per line. A pass that increases the residual
//! (a line switching between slack and taut makes the coupled residual piecewise smooth) is
//! taken half back. A step that fails (no convergence within the allowed passes, or a line
//! that fails) is reported with its time, pass count, residual and failing line so the caller
//! can cut the step and retry; nothing is committed by this module.

use nalgebra::{Matrix3, Matrix6, Vector3, Vector6};

use super::error::GlobalError;
use super::mirror::{reflect, reflect_stiffness, MirrorMap};
use super::motion::StepMotion;
use super::params::DynamicsParams;
use super::results::RunStats;
use super::sea::{LineSeaCache, PassSea, RampedSea};
use super::system::{FloaterModel, GlobalModel};
use crate::beam::rotation::exp_so3;
use crate::floater::body::point_kinematics;
use crate::floater::model::LoadJacobians;
use crate::floater::{fairlead_load, BodyState, Floater};
use crate::mooring::dynamics::{LineIntegrator, LineState};
use crate::mooring::trajectory::PointMotion;
use crate::mooring::NodeId;
use crate::waves::SeaKinematics;

/// Per-line evolving data of a coupled run.
#[derive(Debug)]
pub(crate) struct LineRun<'m> {
    /// The line's integrator (workspace, factorisation, counters).
    pub(crate) integrator: LineIntegrator<'m>,
    /// Committed state at t_n.
    pub(crate) state: LineState,
    /// End state of the current pass.
    pub(crate) trial: LineState,
    /// Warm start of the next pass.
    guess: LineState,
    /// Force of the line on the floater at the end of the last pass (N).
    pub(crate) force: Vector3<f64>,
    /// Condensed fairlead stiffness of the last pass (N/m).
    pub(crate) stiffness: Matrix3<f64>,
    /// Fairlead position the force and stiffness belong to (m).
    at: Vector3<f64>,
}

impl<'m> LineRun<'m> {
    /// Run data starting from the static state `state` with force `force`, stiffness
    /// `stiffness` at fairlead position `at`.
    pub(crate) fn new(
        integrator: LineIntegrator<'m>,
        state: LineState,
        force: Vector3<f64>,
        stiffness: Matrix3<f64>,
        at: Vector3<f64>,
    ) -> Self {
        LineRun {
            integrator,
            trial: state.clone(),
            guess: state.clone(),
            state,
            force,
            stiffness,
            at,
        }
    }
}

/// Floater state at the start of a step.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct FloaterStart {
    /// Time (s).
    pub(crate) time_s: f64,
    /// Rigid-body state.
    pub(crate) body: BodyState,
    /// True acceleration ν̇.
    pub(crate) acc: Vector6<f64>,
    /// Algorithmic acceleration of the generalised-α method.
    pub(crate) alg: Vector6<f64>,
}

/// Generalised-α constants of the floater.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct Alpha {
    am: f64,
    af: f64,
    beta: f64,
    gamma: f64,
}

impl Alpha {
    /// Constants for spectral radius ρ∞.
    pub(crate) fn new(rho: f64) -> Self {
        let am = (2.0 * rho - 1.0) / (rho + 1.0);
        let af = rho / (rho + 1.0);
        Alpha {
            am,
            af,
            gamma: 0.5 - am + af,
            beta: 0.25 * (1.0 - am + af).powi(2),
        }
    }
}

/// What a step needs besides the evolving data.
pub(crate) struct StepContext<'a> {
    pub(crate) model: &'a GlobalModel,
    pub(crate) caches: &'a [Option<LineSeaCache<'a>>],
    /// Lines solved as the mirror image of another while the floater stays symmetric.
    pub(crate) mirror: &'a MirrorMap,
    pub(crate) ramped: &'a RampedSea<'a, crate::waves::IrregularSea>,
    /// The floater's sea samples, held over the inner iterations of a pass.
    pub(crate) floater_sea: &'a PassSea<'a>,
    pub(crate) params: &'a DynamicsParams,
    pub(crate) pool: Option<&'a rayon::ThreadPool>,
    pub(crate) scale: Vector6<f64>,
    pub(crate) alpha: Alpha,
}

/// A converged coupled step (not yet committed).
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct StepOutcome {
    /// Floater state at t_{n+1}.
    pub(crate) end: FloaterStart,
    /// Passes used.
    pub(crate) passes: usize,
}

/// Why a coupled step failed.
#[derive(Debug, Clone, PartialEq)]
pub(crate) struct StepFailure {
    /// Passes done.
    pub(crate) passes: usize,
    /// Last scaled floater residual (or the line residual in N when a line failed).
    pub(crate) residual: f64,
    /// Line that failed and its node with the largest residual, if a line failed.
    pub(crate) line: Option<(u32, Option<NodeId>)>,
    /// The line's own error, when it was not a divergence.
    pub(crate) error: Option<GlobalError>,
}

impl StepFailure {
    /// The error reported when no further cut is allowed.
    pub(crate) fn into_error(self, time_s: f64, step_cuts: usize) -> GlobalError {
        if let Some(e) = self.error {
            return e;
        }
        GlobalError::StepDiverged {
            time_s,
            step_cuts,
            iterations: self.passes,
            residual: self.residual,
            line: self.line.map(|l| l.0),
            node: self.line.and_then(|l| l.1),
        }
    }
}

fn motion_of(k: &crate::floater::PointKinematics) -> PointMotion {
    PointMotion {
        position_m: k.position_m,
        velocity_m_s: k.velocity_m_per_s,
        acceleration_m_s2: k.acceleration_m_per_s2,
    }
}

/// Fairlead kinematics of every line for a floater state and acceleration.
fn fairlead_motions(model: &GlobalModel, body: &BodyState, acc: &Vector6<f64>) -> Vec<PointMotion> {
    model
        .lines
        .iter()
        .map(|l| motion_of(&point_kinematics(body, acc, &l.body_point_m)))
        .collect()
}

/// The generalised-α update of the floater from `start` over `h` for a trial acceleration.
fn advance(start: &FloaterStart, a: &Alpha, h: f64, acc1: &Vector6<f64>) -> BodyState {
    let base_alg = (a.af * start.acc - a.am * start.alg) / (1.0 - a.am);
    let alg1 = base_alg + acc1 * ((1.0 - a.af) / (1.0 - a.am));
    let nu0 = start.body.velocity6();
    let dq = nu0 * h + start.alg * (h * h * (0.5 - a.beta)) + alg1 * (h * h * a.beta);
    let nu1 = nu0 + start.alg * (h * (1.0 - a.gamma)) + alg1 * (h * a.gamma);
    BodyState {
        position_m: start.body.position_m + dq.fixed_rows::<3>(0),
        rotation: exp_so3(&Vector3::from(dq.fixed_rows::<3>(3))) * start.body.rotation,
        velocity_m_per_s: nu1.fixed_rows::<3>(0).into_owned(),
        angular_velocity_rad_per_s: nu1.fixed_rows::<3>(3).into_owned(),
    }
}

/// Steps every line over [t0, t1] to the fairlead motions `ends` (warm-started unless
/// `first`); with `mirroring`, the lines of `ctx.mirror` that mirror another are not solved but
/// take the mirror image of their partner's end state, force and stiffness. Returns the Newton
/// iterations of all lines.
#[allow(clippy::too_many_arguments)]
fn step_lines(
    ctx: &StepContext<'_>,
    runs: &mut [LineRun<'_>],
    starts: &[PointMotion],
    ends: &[PointMotion],
    t0: f64,
    t1: f64,
    first: bool,
    mirroring: bool,
) -> Result<usize, StepFailure> {
    let h = t1 - t0;
    let step_line = |(k, run): (usize, &mut LineRun<'_>)| {
        if mirroring && ctx.mirror.partner(k).is_some() {
            return Ok(0);
        }
        let motion = StepMotion {
            t0_s: t0,
            t1_s: t1,
            start: starts[k],
            end: ends[k],
        };
        let sea: &dyn SeaKinematics = match &ctx.caches[k] {
            Some(c) => c,
            None => ctx.ramped,
        };
        let guess = if first {
            None
        } else {
            run.guess.clone_from(&run.trial);
            run.integrator.shift_fairlead(&mut run.guess, h, &ends[k]);
            Some(&run.guess)
        };
        run.trial.clone_from(&run.state);
        let report = run
            .integrator
            .step_from(&mut run.trial, h, &motion, sea, guess);
        match report {
            Ok(r) => {
                run.force = r.fairlead_force_n;
                if let Some(s) = r.fairlead_stiffness_n_per_m {
                    run.stiffness = s;
                }
                run.at = ends[k].position_m;
                Ok(r.iterations)
            }
            Err(e) => Err((k, e)),
        }
    };
    let outcomes: Vec<_> = match ctx.pool {
        Some(p) => {
            use rayon::prelude::*;
            p.install(|| runs.par_iter_mut().enumerate().map(step_line).collect())
        }
        None => runs.iter_mut().enumerate().map(step_line).collect(),
    };
    if mirroring {
        reflect_partners(ctx.mirror, runs);
    }
    let mut iterations = 0;
    for o in outcomes {
        match o {
            Ok(i) => iterations += i,
            Err((k, e)) => {
                let id = ctx.model.lines[k].id;
                return Err(match GlobalError::from_line(id, e) {
                    GlobalError::StepDiverged { residual, node, .. } => StepFailure {
                        passes: 0,
                        residual,
                        line: Some((id, node)),
                        error: None,
                    },
                    other => StepFailure {
                        passes: 0,
                        residual: f64::NAN,
                        line: Some((id, None)),
                        error: Some(other),
                    },
                });
            }
        }
    }
    Ok(iterations)
}

/// Writes every mirrored line's end state, force, stiffness and fairlead position as the mirror
/// image of its partner's (partners come first in line order).
fn reflect_partners(mirror: &MirrorMap, runs: &mut [LineRun<'_>]) {
    for j in 0..runs.len() {
        let Some(i) = mirror.partner(j) else {
            continue;
        };
        let (before, after) = runs.split_at_mut(j);
        let (from, to) = (&before[i], &mut after[0]);
        mirror.reflect_state(&from.trial, &mut to.trial);
        to.force = reflect(&from.force);
        to.stiffness = reflect_stiffness(&from.stiffness);
        to.at = reflect(&from.at);
    }
}

/// Floater residual with every line force linearised about its last pass, and its Jacobian
/// with respect to the floater position.
fn floater_residual(
    ctx: &StepContext<'_>,
    floater: &Floater,
    jac: &LoadJacobians,
    runs: &[LineRun<'_>],
    trial: &BodyState,
    acc1: &Vector6<f64>,
    t1: f64,
) -> (Vector6<f64>, Matrix6<f64>) {
    let model = ctx.model;
    let mut r = floater.mass_matrix(trial) * acc1
        - floater.net_forces(trial, ctx.floater_sea, t1, model.thrust_n);
    let mut kq = jac.position;
    for (l, run) in model.lines.iter().zip(runs) {
        let x = trial.position_m + trial.rotation * l.body_point_m;
        let force = run.force - run.stiffness * (x - run.at);
        let (load, dload) = fairlead_load(trial, &l.body_point_m, &force, &run.stiffness);
        r -= load;
        kq += dload;
    }
    (r, kq)
}

/// Attempts the coupled step from `start` to `t1`. Line trial states hold the end states on
/// success; nothing else is modified apart from the counters in `stats`.
pub(crate) fn coupled_step(
    ctx: &StepContext<'_>,
    runs: &mut [LineRun<'_>],
    start: &FloaterStart,
    t1: f64,
    stats: &mut RunStats,
) -> Result<StepOutcome, StepFailure> {
    let model = ctx.model;
    let params = ctx.params;
    let a = ctx.alpha;
    let t0 = start.time_s;
    let h = t1 - t0;
    let ratio = (1.0 - a.af) / (1.0 - a.am);
    let starts = fairlead_motions(model, &start.body, &start.acc);
    // `ctx.mirror` is empty when `params.mirror_lines` is off.
    let mirroring = ctx.mirror.count() > 0 && ctx.mirror.holds_at(&starts, h);
    let (mut acc1, mut trial) = match &model.floater {
        FloaterModel::RigidBody(_) => (start.acc, advance(start, &a, h, &start.acc)),
        FloaterModel::Prescribed(m) => {
            let s = m.sample(t1).map_err(|e| StepFailure {
                passes: 0,
                residual: f64::NAN,
                line: None,
                error: Some(e.into()),
            })?;
            (s.acceleration, s.state)
        }
    };
    let floater = match &model.floater {
        FloaterModel::RigidBody(f) => {
            let c = std::time::Instant::now();
            // The sea samples of the Jacobian's evaluation are those of the first pass's
            // residual (same pose, same time): recorded here, replayed there.
            ctx.floater_sea.record();
            let jac = f.load_jacobians(&trial, ctx.floater_sea, t1, model.thrust_n);
            stats.floater_s += c.elapsed().as_secs_f64();
            Some((f, jac))
        }
        FloaterModel::Prescribed(_) => None,
    };
    let mut previous_residual = f64::INFINITY;
    let mut previous_acc = acc1;
    let mut residual = f64::INFINITY;
    let mut passes = 0;
    while passes < params.max_iterations {
        passes += 1;
        let ends = fairlead_motions(model, &trial, &acc1);
        let c = std::time::Instant::now();
        if mirroring {
            stats.mirrored_line_steps += ctx.mirror.count();
        }
        let lines = step_lines(ctx, runs, &starts, &ends, t0, t1, passes == 1, mirroring);
        stats.lines_s += c.elapsed().as_secs_f64();
        stats.line_iterations += lines.map_err(|f| StepFailure { passes, ..f })?;
        let Some((f, jac)) = &floater else {
            return Ok(StepOutcome {
                end: end_state(start, &a, t1, trial, acc1),
                passes,
            });
        };
        let c = std::time::Instant::now();
        // The pass residual samples the sea directly (the first pass replays the samples of
        // the Jacobian, taken at the same pose); the inner iterations reuse its samples.
        if passes == 1 {
            ctx.floater_sea.replay();
        } else {
            ctx.floater_sea.record();
        }
        let (mut r, mut kq) = floater_residual(ctx, f, jac, runs, &trial, &acc1, t1);
        ctx.floater_sea.replay();
        stats.floater_evaluations += 1;
        residual = r.component_div(&ctx.scale).amax();
        if !residual.is_finite() {
            stats.floater_s += c.elapsed().as_secs_f64();
            break;
        }
        if residual < params.tolerance {
            stats.floater_s += c.elapsed().as_secs_f64();
            return Ok(StepOutcome {
                end: end_state(start, &a, t1, trial, acc1),
                passes,
            });
        }
        if passes > 2 && residual > previous_residual {
            // Slack–taut switching: take half of the last pass's correction back.
            acc1 = previous_acc + (acc1 - previous_acc) * 0.5;
            trial = advance(start, &a, h, &acc1);
            stats.floater_s += c.elapsed().as_secs_f64();
            continue;
        }
        previous_residual = residual;
        previous_acc = acc1;
        // Floater Newton against the linearised line forces.
        for _ in 0..params.floater_iterations {
            let s = f.mass_matrix(&trial)
                - kq * (a.beta * ratio * h * h)
                - jac.velocity * (a.gamma * ratio * h);
            match s.lu().solve(&(-r)) {
                Some(d) if d.iter().all(|x| x.is_finite()) => acc1 += d,
                _ => break,
            }
            trial = advance(start, &a, h, &acc1);
            (r, kq) = floater_residual(ctx, f, jac, runs, &trial, &acc1, t1);
            stats.floater_evaluations += 1;
            if r.component_div(&ctx.scale).amax() < FLOATER_INNER_FRACTION * params.tolerance {
                break;
            }
        }
        stats.floater_s += c.elapsed().as_secs_f64();
    }
    Err(StepFailure {
        passes,
        residual,
        line: None,
        error: None,
    })
}

/// Inner floater iterations stop at this fraction of the coupled tolerance, so the pass
/// residual is dominated by the lines' nonlinearity.
const FLOATER_INNER_FRACTION: f64 = 0.1;

/// The floater state at t1 for the converged acceleration.
fn end_state(
    start: &FloaterStart,
    a: &Alpha,
    t1: f64,
    body: BodyState,
    acc1: Vector6<f64>,
) -> FloaterStart {
    let base_alg = (a.af * start.acc - a.am * start.alg) / (1.0 - a.am);
    FloaterStart {
        time_s: t1,
        body,
        acc: acc1,
        alg: base_alg + acc1 * ((1.0 - a.af) / (1.0 - a.am)),
    }
}
