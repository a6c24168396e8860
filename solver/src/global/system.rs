//! The coupled floater–lines system and its static equilibrium.
//!
//! [`GlobalModel`] is the immutable input of a run: the case, the floater (a rigid body with
//! strip-theory hydrodynamics, or a prescribed motion), the line make-up and layout, the
//! realised irregular sea and the steady rotor thrust.
//!
//! Coupled statics (still water, mean thrust T along +x at the hub): Newton on the floater's six
//! DOF q = (x, θ) (spatial rotation increments, Λ ← exp(θ̂) Λ),
//!
//! ```text
//! R(q) = f_floater(q) + Σ_i F_i(q) = 0,     ∂R/∂q = ∂f_floater/∂q + Σ_i ∂F_i/∂q,
//! ```
//!
//! where each line i is solved statically with its fairlead at x_p = x + Λ p_b and returns its
//! fairlead force f_i and its condensed fairlead stiffness K_i (the Schur complement of the line
//! tangent onto the fairlead, see [`crate::mooring::workspace`]); F_i = (f_i, r × f_i) and
//! ∂F_i/∂q follow from [`crate::floater::fairlead_load`]. With the exact line condensation the
//! iteration is Newton's method on the whole system, so it converges quadratically. The
//! residual is scaled by the floater weight mg (forces) and 10 m × mg (moments).

use nalgebra::{Matrix6, Vector3, Vector6};
use rayon::prelude::*;

use super::case::{CaseSpec, FloaterSource};
use super::error::GlobalError;
use super::resolution::{WaveCutOff, WaveResolution};
use crate::beam::rotation::exp_so3;
use crate::floater::prescribed::PrescribedMotion;
use crate::floater::{fairlead_load, BodyState, Floater, FloaterSpec, JacobianSteps};
use crate::mooring::spec::{Environment, LineEnds, LineSpec};
use crate::mooring::statics::{solve_statics, StaticParams, StaticSolution, StaticStart};
use crate::mooring::workspace::LineWorkspace;
use crate::mooring::LineModel;
use crate::text::Num;
use crate::waves::{IrregularSea, Jonswap, RotorTable, StillWater, TableParams};

/// The parsed content of the case's floater file.
#[derive(Debug, Clone)]
pub enum FloaterInput {
    /// A floater description (rigid body).
    RigidBody(Box<FloaterSpec>),
    /// A prescribed motion table.
    Prescribed(PrescribedMotion),
}

/// How the floater moves.
#[derive(Debug, Clone)]
pub enum FloaterModel {
    /// Rigid body integrated with the lines.
    RigidBody(Box<Floater>),
    /// Motion prescribed by a table.
    Prescribed(PrescribedMotion),
}

/// One mooring line of the layout.
#[derive(Debug, Clone)]
pub struct LineDef {
    /// Line id.
    pub id: u32,
    /// Fairlead in body axes (m).
    pub body_point_m: Vector3<f64>,
    /// Anchor (global, m).
    pub anchor_m: Vector3<f64>,
}

/// Immutable input of a global run.
#[derive(Debug, Clone)]
pub struct GlobalModel {
    /// The validated case.
    pub case: CaseSpec,
    /// Floater model.
    pub floater: FloaterModel,
    /// Lines of the layout.
    pub lines: Vec<LineDef>,
    /// Line make-up shared by all lines.
    pub line_spec: LineSpec,
    /// Site data of the lines.
    pub environment: Environment,
    /// Realised sea, cut off at the highest frequency the run resolves.
    pub sea: IrregularSea,
    /// The frequency cut-off applied to the sea and what it kept (`super::resolution`).
    pub wave_cut_off: WaveCutOff,
    /// Hub wind speed (m/s).
    pub wind_speed_m_s: f64,
    /// Mean rotor thrust along +x at the hub (N).
    pub thrust_n: f64,
}

impl GlobalModel {
    /// Builds the model of `case` (validated here) with the floater content `floater`; the sea
    /// is realised for the case's transient plus duration, or `duration_s` when given, and cut
    /// off at the highest frequency that the case's time step and the default floater table
    /// ([`TableParams::default`], as in [`super::params::DynamicsParams::default`]) resolve
    /// ([`WaveResolution::default`], see `super::resolution`).
    pub fn new(
        case: &CaseSpec,
        floater: FloaterInput,
        duration_s: Option<f64>,
    ) -> Result<Self, GlobalError> {
        let mut case = case.clone();
        if let Some(d) = duration_s {
            case.timing.duration_s = d;
        }
        case.validate()?;
        let floater = match (&case.floater, floater) {
            (FloaterSource::RigidBody { .. }, FloaterInput::RigidBody(spec)) => {
                // The wave terms of ∂f/∂q are left out of the Jacobian: they cost 12 sea
                // evaluations per call and the coupled Newton converges without them.
                let f = Floater::from_spec(&spec)?.with_jacobian_steps(JacobianSteps {
                    include_wave_terms: false,
                    ..JacobianSteps::default()
                });
                FloaterModel::RigidBody(Box::new(f))
            }
            (FloaterSource::PrescribedMotion { csv_path }, FloaterInput::Prescribed(m)) => {
                // Simulation time is table time: the statics take the pose at t = 0 and the
                // run samples the table up to the end of the record.
                let (start_s, end_s) = m.time_range();
                let needed_s = case.timing.transient_s + case.timing.duration_s;
                if start_s > 0.0 || end_s < needed_s {
                    return Err(GlobalError::InvalidCase {
                        field: "floater.prescribed_motion.csv_path".into(),
                        value: csv_path.clone(),
                        reason: format!(
                            "covers t = {} to {} s; the run needs t = 0 to {} s (transient_s + \
                             duration_s; simulation time is the table's time)",
                            Num(start_s),
                            Num(end_s),
                            Num(needed_s)
                        ),
                    });
                }
                FloaterModel::Prescribed(m)
            }
            _ => {
                return Err(GlobalError::InvalidCase {
                    field: "floater".into(),
                    value: "mismatched content".into(),
                    reason: "content must match the kind named in the case".into(),
                })
            }
        };
        let lines = (0..case.mooring.lines.len())
            .map(|k| LineDef {
                id: case.mooring.lines[k].id,
                body_point_m: case.fairlead_body_point(k),
                anchor_m: case.anchor(k),
            })
            .collect();
        let s = &case.sea_state;
        let table = TableParams::default();
        let resolution = WaveResolution::default();
        let (cut_off, limit, table_limit) = resolution.cut_off_rad_s(
            case.timing.time_step_s,
            matches!(floater, FloaterModel::RigidBody(_)).then_some(&table),
            case.site.water_depth_m,
        );
        let realisation = case.realisation_params(Some(cut_off));
        let sea = if s.is_calm() {
            IrregularSea::calm(&realisation)?
        } else {
            let spectrum = Jonswap::new(s.hs_m, s.tp_s, case.peak_enhancement()?)?;
            IrregularSea::new(&spectrum, &realisation)?
        };
        let wave_cut_off = WaveCutOff::of(
            &sea,
            cut_off,
            limit,
            resolution.time_step_limit_rad_s(case.timing.time_step_s),
            table_limit,
        );
        tracing::debug!(%wave_cut_off, "sea realised");
        let w = &case.wind;
        let wind_speed_m_s = match (w.wind_speed_m_s, &w.law) {
            (Some(u), _) => u,
            (None, Some(law)) => law.wind_speed_m_s(s.hs_m)?,
            (None, None) => 0.0,
        };
        let table = match &w.thrust_table {
            Some(t) => RotorTable::new(
                t.wind_m_s.clone(),
                t.thrust_kn
                    .iter()
                    .map(|k| k * 1e3 * w.thrust_scale)
                    .collect(),
                vec![0.0; t.wind_m_s.len()],
            )?,
            None => RotorTable::nrel_5mw_scaled(w.thrust_scale)?,
        };
        let thrust_n = table.loads(wind_speed_m_s).thrust_n;
        Ok(Self {
            line_spec: case.line_spec(),
            environment: case.environment(),
            case,
            floater,
            lines,
            sea,
            wave_cut_off,
            wind_speed_m_s,
            thrust_n,
        })
    }

    /// Builds the finite-element model of line `k` with its fairlead at `fairlead_m`.
    pub(crate) fn line_model(
        &self,
        k: usize,
        fairlead_m: Vector3<f64>,
    ) -> Result<LineModel, GlobalError> {
        let l = &self.lines[k];
        LineModel::new(
            format!("line-{}", l.id),
            &self.line_spec,
            LineEnds {
                fairlead_m,
                anchor_m: l.anchor_m,
            },
            &self.environment,
        )
        .map_err(|e| GlobalError::from_line(l.id, e))
    }

    /// Scale of the floater residual: (mg, mg, mg, 10 m·mg, …); unit scale for a prescribed
    /// floater.
    pub fn residual_scale(&self) -> Vector6<f64> {
        match &self.floater {
            FloaterModel::RigidBody(f) => {
                let mg = f.mass_properties().mass_kg * f.gravity();
                Vector6::new(mg, mg, mg, 10.0 * mg, 10.0 * mg, 10.0 * mg)
            }
            FloaterModel::Prescribed(_) => Vector6::repeat(1.0),
        }
    }
}

/// Settings of the coupled statics.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct StaticsParams {
    /// Scaled floater residual accepted.
    pub tolerance: f64,
    /// Newton iterations allowed.
    pub max_iterations: usize,
    /// Largest translation per iteration (m).
    pub max_translation_m: f64,
    /// Largest rotation per iteration (rad).
    pub max_rotation_rad: f64,
    /// Settings of each line's statics.
    pub line: StaticParams,
}

impl Default for StaticsParams {
    fn default() -> Self {
        Self {
            tolerance: 1e-9,
            max_iterations: 30,
            max_translation_m: 5.0,
            max_rotation_rad: 0.05,
            line: StaticParams::default(),
        }
    }
}

/// The coupled static equilibrium.
#[derive(Debug, Clone)]
pub struct StaticEquilibrium {
    /// Floater pose at rest.
    pub body: BodyState,
    /// Line models built with their equilibrium fairleads.
    pub line_models: Vec<LineModel>,
    /// Line equilibria.
    pub line_solutions: Vec<StaticSolution>,
    /// Generalised fairlead loads on the floater, per line (N, N m).
    pub fairlead_loads: Vec<Vector6<f64>>,
    /// Floater loads other than the lines at equilibrium (N, N m).
    pub floater_load: Vector6<f64>,
    /// Newton iterations of the coupled statics.
    pub iterations: usize,
    /// Final scaled residual.
    pub residual: f64,
}

impl StaticEquilibrium {
    /// Every line model with its equilibrium nodal unknowns, in line order.
    pub fn line_configurations(&self) -> Vec<(&LineModel, &[f64])> {
        self.line_models
            .iter()
            .zip(&self.line_solutions)
            .map(|(m, s)| (m, s.q.as_slice()))
            .collect()
    }
}

/// Runs `f(k)` for every line, in parallel on `pool` when given; results in line order.
pub(crate) fn for_lines<T: Send>(
    n: usize,
    pool: Option<&rayon::ThreadPool>,
    f: impl Fn(usize) -> T + Sync + Send,
) -> Vec<T> {
    match pool {
        Some(p) => p.install(|| (0..n).into_par_iter().map(&f).collect()),
        None => (0..n).map(f).collect(),
    }
}

/// A thread pool of `threads` workers, or none for a serial run.
pub(crate) fn line_pool(threads: usize) -> Result<Option<rayon::ThreadPool>, GlobalError> {
    if threads <= 1 {
        return Ok(None);
    }
    rayon::ThreadPoolBuilder::new()
        .num_threads(threads)
        .build()
        .map(Some)
        .map_err(|e| GlobalError::InvalidCase {
            field: "threads".into(),
            value: threads.to_string(),
            reason: format!("could not start the thread pool: {e}"),
        })
}

/// Moves a previous line state so its fairlead sits at `fairlead_m`, blending the shift
/// linearly to zero at the anchor (a good start for the next static solve).
fn shifted_state(model: &LineModel, q: &[f64], fairlead_m: &Vector3<f64>) -> Vec<f64> {
    let shift = fairlead_m - model.position(q, crate::mooring::NodeId(0));
    let length = model.length_m();
    let mut out = q.to_vec();
    for n in model.nodes() {
        let w = 1.0 - n.arc_length_m / length;
        for j in 0..3 {
            out[n.dof + j] += w * shift[j];
        }
    }
    out
}

/// Solves every line statically for the fairleads of `body`; returns models and solutions.
fn solve_lines(
    model: &GlobalModel,
    body: &BodyState,
    previous: Option<&[StaticSolution]>,
    params: &StaticParams,
    pool: Option<&rayon::ThreadPool>,
) -> Result<(Vec<LineModel>, Vec<StaticSolution>), GlobalError> {
    let results = for_lines(model.lines.len(), pool, |k| {
        let fairlead = body.point_position(&model.lines[k].body_point_m);
        let lm = model.line_model(k, fairlead)?;
        let start = match previous {
            Some(p) => StaticStart::State(shifted_state(&lm, &p[k].q, &fairlead)),
            None => StaticStart::Geometric,
        };
        let mut ws = LineWorkspace::new(&lm);
        let sol = solve_statics(&lm, &start, params, &mut ws)
            .map_err(|e| GlobalError::from_line(model.lines[k].id, e))?;
        Ok::<_, GlobalError>((lm, sol))
    });
    let mut models = Vec::with_capacity(results.len());
    let mut sols = Vec::with_capacity(results.len());
    for r in results {
        let (m, s) = r?;
        models.push(m);
        sols.push(s);
    }
    Ok((models, sols))
}

/// Coupled static equilibrium of the floater with all lines under the mean thrust.
pub fn solve_coupled_statics(
    model: &GlobalModel,
    params: &StaticsParams,
    pool: Option<&rayon::ThreadPool>,
) -> Result<StaticEquilibrium, GlobalError> {
    let floater = match &model.floater {
        FloaterModel::RigidBody(f) => f,
        FloaterModel::Prescribed(m) => {
            let body = m.sample(0.0)?.state;
            let body = BodyState {
                velocity_m_per_s: Vector3::zeros(),
                angular_velocity_rad_per_s: Vector3::zeros(),
                ..body
            };
            let (line_models, line_solutions) =
                solve_lines(model, &body, None, &params.line, pool)?;
            let fairlead_loads = loads_of(model, &body, &line_solutions)
                .into_iter()
                .map(|(f, _)| f)
                .collect();
            return Ok(StaticEquilibrium {
                body,
                line_models,
                line_solutions,
                fairlead_loads,
                floater_load: Vector6::zeros(),
                iterations: 0,
                residual: 0.0,
            });
        }
    };
    let scale = model.residual_scale();
    let mut body = BodyState::at_rest();
    let mut previous: Option<Vec<StaticSolution>> = None;
    let mut residual = f64::INFINITY;
    for it in 0..=params.max_iterations {
        let (line_models, sols) =
            solve_lines(model, &body, previous.as_deref(), &params.line, pool)?;
        let loads = loads_of(model, &body, &sols);
        let own = floater.net_forces(&body, &StillWater, 0.0, model.thrust_n);
        let total: Vector6<f64> = loads.iter().fold(own, |acc, (f, _)| acc + f);
        residual = total.component_div(&scale).amax();
        tracing::debug!(iteration = it, residual, "coupled statics");
        if !residual.is_finite() {
            break;
        }
        if residual < params.tolerance {
            return Ok(StaticEquilibrium {
                body,
                line_models,
                fairlead_loads: loads.iter().map(|(f, _)| *f).collect(),
                line_solutions: sols,
                floater_load: own,
                iterations: it,
                residual,
            });
        }
        if it == params.max_iterations {
            break;
        }
        let jac = floater
            .load_jacobians(&body, &StillWater, 0.0, model.thrust_n)
            .position;
        let k: Matrix6<f64> = loads.iter().fold(jac, |acc, (_, k)| acc + k);
        let mut dq = k
            .lu()
            .solve(&(-total))
            .ok_or(GlobalError::StaticsDiverged {
                iterations: it,
                residual,
            })?;
        let t = dq.fixed_rows::<3>(0).norm() / params.max_translation_m;
        let r = dq.fixed_rows::<3>(3).norm() / params.max_rotation_rad;
        let limit = t.max(r);
        if limit > 1.0 {
            dq /= limit;
        }
        body.position_m += dq.fixed_rows::<3>(0);
        body.rotation = exp_so3(&Vector3::from(dq.fixed_rows::<3>(3))) * body.rotation;
        previous = Some(sols);
    }
    Err(GlobalError::StaticsDiverged {
        iterations: params.max_iterations,
        residual,
    })
}

/// Generalised fairlead loads and their position Jacobians for line solutions at `body`.
fn loads_of(
    model: &GlobalModel,
    body: &BodyState,
    sols: &[StaticSolution],
) -> Vec<(Vector6<f64>, Matrix6<f64>)> {
    model
        .lines
        .iter()
        .zip(sols)
        .map(|(l, s)| {
            fairlead_load(
                body,
                &l.body_point_m,
                &s.fairlead_force_n,
                &s.fairlead_stiffness_n_per_m,
            )
        })
        .collect()
}
