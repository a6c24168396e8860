//! Coupled implicit dynamics of the floater and its lines (DESIGN §4.2-4.3).
//!
//! Both the floater and every line use the generalised-α method with the same step h and
//! spectral radius ρ∞ (see [`crate::floater::dynamics`] and [`crate::mooring::dynamics`]). The
//! floater unknown of a step is its true acceleration ν̇_{n+1}; per coupling iteration:
//!
//! 1. the trial floater state gives each fairlead's position, velocity and acceleration at
//!    t_{n+1} ([`crate::floater::body::point_kinematics`]);
//! 2. each line is stepped from its state at t_n with that fairlead motion (full Newton on its
//!    banded system) and returns the force on the floater f_i and the condensed fairlead
//!    stiffness K_i of its iteration matrix S = K + γ'C + β'M;
//! 3. floater residual r = M(q) ν̇ − f(q, ν, t) − Σ F_i, with F_i = (f_i, r_i × f_i);
//! 4. Newton update of ν̇ with S_f = M − β'h² (∂f/∂q + Σ ∂F_i/∂q) − γ'h ∂f/∂ν, where ∂F_i/∂q
//!    comes from K_i ([`crate::floater::fairlead_load`]).
//!
//! This block Gauss–Seidel iteration with the exact Schur complement of every line is Newton's
//! method on the monolithic system, so it converges like Newton. The floater Jacobians ∂f/∂q,
//! ∂f/∂ν are evaluated once per step at the predictor (modified Newton for the floater part).
//! The step is converged when every line meets its force tolerance and the floater residual,
//! scaled by mg (forces) and 10 m·mg (moments), is below `tolerance`. A step that does not
//! converge ends the run with an error naming time, iteration count and residual (or the line
//! and node that failed); no non-finite value is ever committed.
//!
//! Lines run in parallel on an explicit pool; each line's computation is independent and the
//! loads are summed in line order, so serial and parallel runs give identical numbers.

use std::time::Instant;

use nalgebra::{Matrix3, Matrix6, Vector3, Vector6};

use super::error::GlobalError;
use super::motion::StepMotion;
use super::results::{FloaterSeries, GlobalResult, HotSpotResult, LineResult, RunStats};
use super::sea::{LineSeaCache, Ramp, RampedSea};
use super::system::{for_lines, FloaterModel, GlobalModel, StaticEquilibrium};
use crate::beam::rotation::exp_so3;
use crate::floater::body::point_kinematics;
use crate::floater::{fairlead_load, BodyState};
use crate::mooring::dynamics::{DynamicParams, LineIntegrator, LineState};
use crate::mooring::hotspot::{node_values, LineRecorder};
use crate::mooring::trajectory::PointMotion;
use crate::waves::{SeaKinematics, SeriesParams};

/// Settings of the coupled dynamics.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct DynamicsParams {
    /// Scaled floater residual accepted.
    pub tolerance: f64,
    /// Coupling iterations per step.
    pub max_iterations: usize,
    /// Line integrator settings (its spectral radius is overridden by the case's).
    pub line: DynamicParams,
    /// Whether line kinematics are precomputed at the static quadrature points.
    pub precompute_line_kinematics: bool,
    /// Precomputation settings.
    pub series: SeriesParams,
    /// Distance beyond which a cached point is not used (m).
    pub guard_distance_m: f64,
}

impl Default for DynamicsParams {
    fn default() -> Self {
        Self {
            tolerance: 1e-7,
            max_iterations: 25,
            // Slack events of the light rope under the clump mass make the line's Newton
            // iterations piecewise smooth: allow more iterations and step cuts than a line
            // driven alone needs.
            line: DynamicParams {
                max_iterations: 30,
                max_halvings: 6,
                ..DynamicParams::default()
            },
            precompute_line_kinematics: true,
            series: SeriesParams {
                samples_per_shortest_period: 16.0,
                chebyshev_tolerance: 1e-8,
                max_chebyshev_nodes: 32,
                threads: 1,
            },
            guard_distance_m: 30.0,
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

/// Roll, pitch, yaw (rad) of Λ = R_z(yaw) R_y(pitch) R_x(roll).
fn angles(rotation: &Matrix3<f64>) -> [f64; 3] {
    let (r, p, y) = nalgebra::Rotation3::from_matrix_unchecked(*rotation).euler_angles();
    [r, p, y]
}

/// Per-line evolving data.
struct LineRun<'m> {
    integrator: LineIntegrator<'m>,
    state: LineState,
    trial: LineState,
    force: Vector3<f64>,
    stiffness: Matrix3<f64>,
}

/// Runs the coupled dynamics from the static equilibrium `eq` over the case's transient and
/// duration; `progress` is called with (t, t_end) after every step.
pub fn run_dynamics(
    model: &GlobalModel,
    eq: &StaticEquilibrium,
    params: &DynamicsParams,
    pool: Option<&rayon::ThreadPool>,
    mut progress: impl FnMut(f64, f64),
) -> Result<GlobalResult, GlobalError> {
    let timing = &model.case.timing;
    let h = timing.time_step_s;
    let t_end = timing.transient_s + timing.duration_s;
    let steps = (t_end / h).round() as usize;
    let ramp = Ramp {
        duration_s: timing.wave_ramp_s,
    };
    let ramped = RampedSea {
        sea: &model.sea,
        ramp,
    };
    let mut stats = RunStats {
        statics_iterations: eq.iterations,
        ..RunStats::default()
    };

    // Precomputed line kinematics.
    let clock = Instant::now();
    let caches: Vec<Option<LineSeaCache<'_>>> = if params.precompute_line_kinematics {
        let built = for_lines(model.lines.len(), pool, |k| {
            LineSeaCache::new(
                &eq.line_models[k],
                &eq.line_solutions[k].q,
                &model.sea,
                ramp,
                &params.series,
                params.guard_distance_m,
            )
        });
        built
            .into_iter()
            .map(|c| c.map(Some))
            .collect::<Result<_, _>>()?
    } else {
        model.lines.iter().map(|_| None).collect()
    };
    stats.precompute_s = clock.elapsed().as_secs_f64();

    let line_params = DynamicParams {
        spectral_radius: timing.spectral_radius,
        condense_fairlead: true,
        ..params.line
    };
    let mut runs = Vec::with_capacity(model.lines.len());
    for (k, lm) in eq.line_models.iter().enumerate() {
        let sol = &eq.line_solutions[k];
        let integrator = LineIntegrator::new(lm, line_params)
            .map_err(|e| GlobalError::from_line(model.lines[k].id, e))?;
        runs.push(LineRun {
            integrator,
            state: LineState::at_rest(sol, 0.0),
            trial: LineState::at_rest(sol, 0.0),
            force: sol.fairlead_force_n,
            stiffness: sol.fairlead_stiffness_n_per_m,
        });
    }

    // Recorders.
    let mut recorders = Vec::with_capacity(model.lines.len());
    for (k, l) in model.lines.iter().enumerate() {
        let spots: Vec<f64> = model
            .case
            .hot_spots
            .iter()
            .filter(|s| s.line == l.id)
            .map(|s| s.arc_length_m)
            .collect();
        let mut rec = LineRecorder::new(
            &eq.line_models[k],
            &spots,
            timing.output_interval_s,
            timing.transient_s,
        )
        .map_err(|e| GlobalError::from_line(l.id, e))?;
        rec.observe(
            &eq.line_models[k],
            0.0,
            &runs[k].state.q,
            &eq.line_solutions[k].fairlead_force_n,
        );
        recorders.push(rec);
    }
    let mut floater_series = FloaterSeries::default();
    let out_every = (timing.output_interval_s / h).round().max(1.0) as usize;
    let first_out = (timing.transient_s / h).round() as usize;
    let record_body = |step: usize, t: f64, body: &BodyState, s: &mut FloaterSeries| {
        if step >= first_out && (step - first_out) % out_every == 0 {
            s.time_s.push(t - timing.transient_s);
            let a = angles(&body.rotation);
            s.motion.push([
                body.position_m.x,
                body.position_m.y,
                body.position_m.z,
                a[0],
                a[1],
                a[2],
            ]);
        }
    };

    let scale = model.residual_scale();
    let rho = timing.spectral_radius;
    let am = (2.0 * rho - 1.0) / (rho + 1.0);
    let af = rho / (rho + 1.0);
    let gamma = 0.5 - am + af;
    let beta = 0.25 * (1.0 - am + af).powi(2);
    let ratio = (1.0 - af) / (1.0 - am);

    let mut body = eq.body;
    let mut acc = Vector6::zeros();
    let mut alg = Vector6::zeros();
    let mut t = 0.0;
    record_body(0, t, &body, &mut floater_series);
    let clock = Instant::now();
    for step in 0..steps {
        let t1 = if step + 1 == steps {
            t_end
        } else {
            (step + 1) as f64 * h
        };
        let h = t1 - t;
        let base_alg = (af * acc - am * alg) / (1.0 - am);
        let advance = |acc1: &Vector6<f64>| -> BodyState {
            let alg1 = base_alg + ratio * acc1;
            let dq = body.velocity6() * h + alg * (h * h * (0.5 - beta)) + alg1 * (h * h * beta);
            let nu1 = body.velocity6() + alg * (h * (1.0 - gamma)) + alg1 * (h * gamma);
            BodyState {
                position_m: body.position_m + dq.fixed_rows::<3>(0),
                rotation: exp_so3(&Vector3::from(dq.fixed_rows::<3>(3))) * body.rotation,
                velocity_m_per_s: nu1.fixed_rows::<3>(0).into_owned(),
                angular_velocity_rad_per_s: nu1.fixed_rows::<3>(3).into_owned(),
            }
        };
        let starts: Vec<PointMotion> = model
            .lines
            .iter()
            .map(|l| motion_of(&point_kinematics(&body, &acc, &l.body_point_m)))
            .collect();

        let (mut acc1, mut trial) = match &model.floater {
            FloaterModel::RigidBody(_) => (acc, advance(&acc)),
            FloaterModel::Prescribed(m) => {
                let s = m.sample(m.time_range().0 + t1)?;
                (s.acceleration, s.state)
            }
        };
        let floater_jac = match &model.floater {
            FloaterModel::RigidBody(f) => {
                let c = Instant::now();
                let j = f.load_jacobians(&trial, &ramped, t1, model.thrust_n);
                stats.floater_s += c.elapsed().as_secs_f64();
                Some(j)
            }
            FloaterModel::Prescribed(_) => None,
        };
        let mut converged = false;
        let mut residual = f64::INFINITY;
        let mut previous_residual = f64::INFINITY;
        let mut last_delta = Vector6::zeros();
        let mut iterations = 0;
        while iterations < params.max_iterations {
            iterations += 1;
            // Lines with the trial fairlead motion.
            let c = Instant::now();
            let ends: Vec<PointMotion> = model
                .lines
                .iter()
                .map(|l| motion_of(&point_kinematics(&trial, &acc1, &l.body_point_m)))
                .collect();
            let outcomes = {
                let runs_ref = &mut runs;
                let jobs: Vec<(usize, &mut LineRun<'_>)> =
                    runs_ref.iter_mut().enumerate().collect();
                let step_line = |(k, run): (usize, &mut LineRun<'_>)| {
                    run.trial.clone_from(&run.state);
                    let motion = StepMotion {
                        t0_s: t,
                        t1_s: t1,
                        start: starts[k],
                        end: ends[k],
                    };
                    let sea: &dyn SeaKinematics = match &caches[k] {
                        Some(c) => c,
                        None => &ramped,
                    };
                    run.integrator
                        .step(&mut run.trial, h, &motion, sea)
                        .map(|r| {
                            run.force = r.fairlead_force_n;
                            if let Some(s) = r.fairlead_stiffness_n_per_m {
                                run.stiffness = s;
                            }
                            r.iterations
                        })
                        .map_err(|e| GlobalError::from_line(model.lines[k].id, e))
                };
                match pool {
                    Some(p) => {
                        use rayon::prelude::*;
                        p.install(|| jobs.into_par_iter().map(step_line).collect::<Vec<_>>())
                    }
                    None => jobs.into_iter().map(step_line).collect::<Vec<_>>(),
                }
            };
            stats.lines_s += c.elapsed().as_secs_f64();
            for o in outcomes {
                stats.line_iterations += o?;
            }
            let (f, jac) = match (&model.floater, &floater_jac) {
                (FloaterModel::RigidBody(f), Some(j)) => (f, j),
                _ => {
                    converged = true;
                    break;
                }
            };
            let c = Instant::now();
            let mut r =
                f.mass_matrix(&trial) * acc1 - f.net_forces(&trial, &ramped, t1, model.thrust_n);
            let mut kq: Matrix6<f64> = jac.position;
            for (l, run) in model.lines.iter().zip(&runs) {
                let (load, dload) =
                    fairlead_load(&trial, &l.body_point_m, &run.force, &run.stiffness);
                r -= load;
                kq += dload;
            }
            residual = r.component_div(&scale).amax();
            if !residual.is_finite() {
                break;
            }
            if residual < params.tolerance {
                converged = true;
                stats.floater_s += c.elapsed().as_secs_f64();
                break;
            }
            // A line switching between slack and taut makes the coupled residual piecewise
            // smooth: when a correction increased the residual, take half of it back.
            if iterations > 2 && residual > previous_residual {
                last_delta *= 0.5;
                acc1 -= last_delta;
                trial = advance(&acc1);
                stats.floater_s += c.elapsed().as_secs_f64();
                continue;
            }
            previous_residual = residual;
            let s = f.mass_matrix(&trial)
                - kq * (beta * ratio * h * h)
                - jac.velocity * (gamma * ratio * h);
            let delta = s.lu().solve(&(-r));
            stats.floater_s += c.elapsed().as_secs_f64();
            match delta {
                Some(d) if d.iter().all(|x| x.is_finite()) => {
                    last_delta = d;
                    acc1 += d;
                    trial = advance(&acc1);
                }
                _ => break,
            }
        }
        stats.coupling_iterations += iterations;
        stats.max_coupling_iterations = stats.max_coupling_iterations.max(iterations);
        if !converged {
            return Err(GlobalError::StepDiverged {
                time_s: t1,
                iterations,
                residual,
                line: None,
                node: None,
            });
        }
        // Commit.
        alg = base_alg + ratio * acc1;
        acc = acc1;
        body = trial;
        t = t1;
        for run in runs.iter_mut() {
            std::mem::swap(&mut run.state, &mut run.trial);
        }
        if !body.position_m.iter().all(|x| x.is_finite()) {
            return Err(GlobalError::NonFinite {
                what: "floater position",
                time_s: t,
            });
        }
        for (k, rec) in recorders.iter_mut().enumerate() {
            rec.observe(&eq.line_models[k], t, &runs[k].state.q, &runs[k].force);
        }
        record_body(step + 1, t, &body, &mut floater_series);
        stats.steps += 1;
        progress(t, t_end);
    }
    stats.dynamics_s = clock.elapsed().as_secs_f64();
    for run in &runs {
        stats.cut_steps += run.integrator.stats().cut_steps;
    }
    stats.cache_misses = caches.iter().flatten().map(|c| c.misses()).sum();

    // Assemble the result.
    let mut lines = Vec::with_capacity(model.lines.len());
    let mut hot_spots = Vec::new();
    let mut time_s = Vec::new();
    for (k, rec) in recorders.into_iter().enumerate() {
        let out = rec.finish();
        let lm = &eq.line_models[k];
        let q = &eq.line_solutions[k].q;
        let n = lm.nodes().len();
        let (mut tn, mut kn) = (vec![0.0; n], vec![0.0; n]);
        node_values(lm, q, &mut tn, &mut kn);
        let id = model.lines[k].id;
        if k == 0 {
            time_s = out.time_s.iter().map(|x| x - timing.transient_s).collect();
        }
        for hs in out.hot_spots {
            hot_spots.push(HotSpotResult {
                line: id,
                arc_length_m: hs.arc_length_m,
                tension_n: hs.tension_n,
                curvature_per_m: hs.curvature_per_m,
            });
        }
        lines.push(LineResult {
            id,
            fairlead_tension_n: out.fairlead_tension_n,
            envelope: out.envelope,
            static_arc_length_m: lm.nodes().iter().map(|nd| nd.arc_length_m).collect(),
            static_position_m: (0..n)
                .map(|i| lm.position(q, crate::mooring::NodeId(i)).into())
                .collect(),
            static_tension_n: tn,
            static_curvature_per_m: kn,
            static_fairlead_force_n: eq.line_solutions[k].fairlead_force_n.into(),
        });
    }
    // Order hot spots as in the case.
    let order = |h: &HotSpotResult| {
        model
            .case
            .hot_spots
            .iter()
            .position(|s| s.line == h.line && s.arc_length_m == h.arc_length_m)
            .unwrap_or(usize::MAX)
    };
    hot_spots.sort_by_key(order);
    let result = GlobalResult {
        name: model.case.name.clone(),
        time_s,
        hot_spots,
        lines,
        floater: floater_series,
        static_body_position_m: eq.body.position_m.into(),
        static_body_angles_rad: angles(&eq.body.rotation),
        wind_speed_m_s: model.wind_speed_m_s,
        thrust_n: model.thrust_n,
        stats,
    };
    result.check_finite()?;
    Ok(result)
}
