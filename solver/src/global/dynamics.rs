//! Coupled implicit dynamics of the floater and its lines (`docs/global-stage.md`): the time loop.
//!
//! Both the floater and every line use the generalised-α method with the same step h and
//! spectral radius ρ∞ (see [`crate::floater::dynamics`] and [`crate::mooring::dynamics`]); one
//! coupled step is solved by `coupling::coupled_step` (lines stepped with the trial
//! fairlead motion, floater Newton against the lines' condensed fairlead stiffness, passes until
//! the floater residual with the true line forces is below `tolerance`).
//!
//! Step cut-back: the case's Δt is the step of the output grid. A coupled step that fails (no
//! coupled convergence, or a line that fails even after its own halvings, as when the light rope
//! under the clump mass goes slack and snaps taut) is retried from the same committed state with
//! h/2, h/4, … up to `max_step_cuts` halvings; after a grid step completed without a failure the
//! step doubles again (one level per grid step), so the run returns to Δt. Sub-steps always end
//! exactly on the grid, so outputs stay on the requested times. If the smallest step still
//! fails, the run ends with an error naming the time, the step size, the pass count, the
//! residual and the failing line and node; no non-finite value is ever committed.
//!
//! Lines run in parallel on an explicit pool; each line's computation is independent and the
//! loads are summed in line order, so serial and parallel runs give identical numbers.

use std::time::Instant;

use nalgebra::{Matrix3, Vector6};

use super::coupling::{coupled_step, Alpha, FloaterStart, LineRun, StepContext, StepOutcome};
use super::error::GlobalError;
use super::mirror::MirrorMap;
use super::params::DynamicsParams;
use super::resolution::WaveResolution;
use super::results::{FloaterSeries, GlobalResult, HotSpotResult, LineResult, RunStats};
use super::sea::{FloaterSeaTable, LineSeaCache, PassSea, Ramp, RampedSea};
use super::system::{FloaterModel, GlobalModel, StaticEquilibrium};
use crate::floater::BodyState;
use crate::mooring::dynamics::{DynamicParams, LineIntegrator, LineState};
use crate::mooring::hotspot::{node_values, LineRecorder};
use crate::waves::{SeaKinematics, TableParams};

/// Largest distance (m) between a floater strip's point and the point its sea sample was taken
/// at for the sample to be reused by the floater iterations inside a coupling pass.
const FLOATER_SEA_HOLD_M: f64 = 0.05;

/// Roll, pitch, yaw (rad) of Λ = R_z(yaw) R_y(pitch) R_x(roll).
fn angles(rotation: &Matrix3<f64>) -> [f64; 3] {
    let (r, p, y) = nalgebra::Rotation3::from_matrix_unchecked(*rotation).euler_angles();
    [r, p, y]
}

/// Runs the coupled dynamics from the static equilibrium `eq` over the case's transient and
/// duration; `progress` is called with (t, t_end) after every step. Phases: the sea's
/// precomputed kinematics, the lines' integrators and recorders at rest, the time march with
/// its step cuts, the result.
pub fn run_dynamics(
    model: &GlobalModel,
    eq: &StaticEquilibrium,
    params: &DynamicsParams,
    pool: Option<&rayon::ThreadPool>,
    progress: impl FnMut(f64, f64),
) -> Result<GlobalResult, GlobalError> {
    let timing = &model.case.timing;
    let h = timing.time_step_s;
    let t_end = timing.transient_s + timing.duration_s;
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
    let clock = Instant::now();
    let kinematics = Kinematics::precompute(model, eq, params, pool, ramp, t_end + h, &mut stats)?;
    stats.precompute_s = clock.elapsed().as_secs_f64();
    let mut runs = line_runs(model, eq, params)?;
    let recorders = recorders(model, eq, &runs)?;
    let floater_source: &dyn SeaKinematics = match &kinematics.floater {
        Some(t) => t,
        None => &ramped,
    };
    let floater_sea = PassSea::new(floater_source, FLOATER_SEA_HOLD_M);
    let mirror = if params.mirror_lines {
        MirrorMap::of(model, eq)
    } else {
        MirrorMap::none(model.lines.len())
    };
    tracing::debug!(mirrored_lines = mirror.count(), "mirror pairs");
    let ctx = StepContext {
        model,
        caches: &kinematics.lines,
        mirror: &mirror,
        ramped: &ramped,
        floater_sea: &floater_sea,
        params,
        pool,
        scale: model.residual_scale(),
        alpha: Alpha::new(timing.spectral_radius),
    };
    let mut march = March {
        ctx: &ctx,
        eq,
        grid: OutputGrid::of(timing),
        now: FloaterStart {
            time_s: 0.0,
            body: eq.body,
            acc: Vector6::zeros(),
            alg: Vector6::zeros(),
        },
        level: 0,
        recorders,
        floater_series: FloaterSeries::default(),
        stats,
    };
    let clock = Instant::now();
    march.run(&mut runs, t_end, progress)?;
    let mut stats = march.stats;
    stats.dynamics_s = clock.elapsed().as_secs_f64();
    for run in &runs {
        let line = run.integrator.stats();
        stats.cut_steps += line.cut_steps;
        stats.line_stalled_attempts += line.stalled_attempts;
        stats.line_factorizations += line.factorizations;
        stats.line_assemblies += line.assemblies;
    }
    stats.cache_misses = kinematics.lines.iter().flatten().map(|c| c.misses()).sum();
    stats.floater_table_misses = kinematics.floater.as_ref().map_or(0, |t| t.misses());
    assemble(model, eq, march.recorders, march.floater_series, stats)
}

/// The sea's kinematics computed before the time loop: per line at its nodes, and the
/// floater's table.
struct Kinematics<'m> {
    lines: Vec<Option<LineSeaCache<'m>>>,
    floater: Option<FloaterSeaTable<'m>>,
}

impl<'m> Kinematics<'m> {
    /// Precomputes what `params` asks for over [0, `t_last`].
    fn precompute(
        model: &'m GlobalModel,
        eq: &StaticEquilibrium,
        params: &DynamicsParams,
        pool: Option<&rayon::ThreadPool>,
        ramp: Ramp,
        t_last: f64,
        stats: &mut RunStats,
    ) -> Result<Self, GlobalError> {
        let lines: Vec<Option<LineSeaCache<'_>>> = if params.precompute_line_kinematics {
            LineSeaCache::for_lines(
                &eq.line_configurations(),
                &model.sea,
                ramp,
                &params.series,
                params.guard_distance_m,
                t_last,
                pool,
            )?
            .into_iter()
            .map(Some)
            .collect()
        } else {
            model.lines.iter().map(|_| None).collect()
        };
        // Tabulated floater kinematics, when the table resolves every component of the sea (a
        // table coarser than the one the model's cut-off was chosen for is not used: its values
        // would be wrong near the surface; the floater then samples the sea directly).
        let resolved = |t: &TableParams| {
            WaveResolution::default().table_limit_rad_s(t, model.sea.field().depth_m())
                >= model.wave_cut_off.highest_component_rad_s
        };
        let floater = match (&model.floater, &params.floater_table) {
            (FloaterModel::RigidBody(_), Some(table)) if !resolved(table) => {
                tracing::warn!(
                    spacing_m = table.spacing_along_m.max(table.spacing_stretched_m),
                    highest_rad_s = model.wave_cut_off.highest_component_rad_s,
                    "floater table too coarse for the sea: direct summation"
                );
                stats.floater_table_unresolved = true;
                None
            }
            (FloaterModel::RigidBody(f), Some(table)) => Some(FloaterSeaTable::new(
                f, &eq.body, &model.sea, ramp, t_last, table,
            )?),
            _ => None,
        };
        Ok(Self { lines, floater })
    }
}

/// Every line's integrator at rest in its static solution.
fn line_runs<'m>(
    model: &GlobalModel,
    eq: &'m StaticEquilibrium,
    params: &DynamicsParams,
) -> Result<Vec<LineRun<'m>>, GlobalError> {
    let line_params = DynamicParams {
        spectral_radius: model.case.timing.spectral_radius,
        condense_fairlead: true,
        ..params.line
    };
    let mut runs = Vec::with_capacity(model.lines.len());
    for (k, lm) in eq.line_models.iter().enumerate() {
        let sol = &eq.line_solutions[k];
        let integrator = LineIntegrator::new(lm, line_params)
            .map_err(|e| GlobalError::from_line(model.lines[k].id, e))?;
        let at = nalgebra::Vector3::new(sol.q[0], sol.q[1], sol.q[2]);
        runs.push(LineRun::new(
            integrator,
            LineState::at_rest(sol, 0.0),
            sol.fairlead_force_n,
            sol.fairlead_stiffness_n_per_m,
            at,
        ));
    }
    Ok(runs)
}

/// A recorder per line of its hot spots and envelope, with the static state observed at t = 0.
fn recorders(
    model: &GlobalModel,
    eq: &StaticEquilibrium,
    runs: &[LineRun<'_>],
) -> Result<Vec<LineRecorder>, GlobalError> {
    let timing = &model.case.timing;
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
    Ok(recorders)
}

/// The output grid of the floater's motions: every `out_every`-th step from `first_out` (the
/// end of the transient), with times counted from there.
struct OutputGrid {
    out_every: usize,
    first_out: usize,
    transient_s: f64,
}

impl OutputGrid {
    fn of(timing: &super::case::TimingSpec) -> Self {
        let h = timing.time_step_s;
        Self {
            out_every: (timing.output_interval_s / h).round().max(1.0) as usize,
            first_out: (timing.transient_s / h).round() as usize,
            transient_s: timing.transient_s,
        }
    }

    /// Records the floater's position and angles after grid step `step` if it is an output.
    fn record(&self, step: usize, t: f64, body: &BodyState, series: &mut FloaterSeries) {
        if step >= self.first_out && (step - self.first_out) % self.out_every == 0 {
            series.time_s.push(t - self.transient_s);
            let a = angles(&body.rotation);
            series.motion.push([
                body.position_m.x,
                body.position_m.y,
                body.position_m.z,
                a[0],
                a[1],
                a[2],
            ]);
        }
    }
}

/// The time march: the committed floater state, the current cut level (sub-steps of
/// h / 2^level), what is recorded and counted.
struct March<'c, 'm> {
    ctx: &'c StepContext<'m>,
    eq: &'m StaticEquilibrium,
    grid: OutputGrid,
    now: FloaterStart,
    level: usize,
    recorders: Vec<LineRecorder>,
    floater_series: FloaterSeries,
    stats: RunStats,
}

impl March<'_, '_> {
    /// Marches every grid step to `t_end`.
    fn run(
        &mut self,
        runs: &mut [LineRun<'_>],
        t_end: f64,
        mut progress: impl FnMut(f64, f64),
    ) -> Result<(), GlobalError> {
        let h = self.ctx.model.case.timing.time_step_s;
        let steps = (t_end / h).round() as usize;
        self.grid
            .record(0, self.now.time_s, &self.now.body, &mut self.floater_series);
        for step in 0..steps {
            let t_grid0 = step as f64 * h;
            let t_grid1 = if step + 1 == steps {
                t_end
            } else {
                (step + 1) as f64 * h
            };
            let clean = self.grid_step(runs, t_grid0, t_grid1)?;
            if clean && self.level > 0 {
                self.level -= 1;
            }
            self.grid.record(
                step + 1,
                self.now.time_s,
                &self.now.body,
                &mut self.floater_series,
            );
            progress(self.now.time_s, t_end);
        }
        Ok(())
    }

    /// One grid step from `t_grid0` to `t_grid1` in sub-steps at the current level, halving
    /// them on a failure; whether it completed without a cut.
    fn grid_step(
        &mut self,
        runs: &mut [LineRun<'_>],
        t_grid0: f64,
        t_grid1: f64,
    ) -> Result<bool, GlobalError> {
        let h_grid = t_grid1 - t_grid0;
        // Sub-steps done in this grid step, at the current level.
        let mut done = 0usize;
        let mut clean = true;
        loop {
            let parts = 1usize << self.level;
            if done >= parts {
                return Ok(clean);
            }
            let t1 = if done + 1 == parts {
                t_grid1
            } else {
                t_grid0 + h_grid * (done + 1) as f64 / parts as f64
            };
            match coupled_step(self.ctx, runs, &self.now, t1, &mut self.stats) {
                Ok(out) => {
                    self.commit(runs, out, t1)?;
                    done += 1;
                }
                Err(failure) => {
                    self.stats.coupling_iterations += failure.passes;
                    if self.level >= self.ctx.params.max_step_cuts {
                        let h_sub = h_grid / parts as f64;
                        tracing::warn!(
                            t = t1,
                            step_s = h_sub,
                            "coupled step failed at the smallest step"
                        );
                        return Err(failure.into_error(t1, self.level));
                    }
                    tracing::debug!(t = t1, level = self.level, "coupled step cut");
                    self.stats.cut_coupled_steps += 1;
                    clean = false;
                    self.level += 1;
                    done *= 2;
                    self.stats.deepest_cut = self.stats.deepest_cut.max(self.level);
                }
            }
        }
    }

    /// Commits a converged coupled step ending at `t1`: the floater, the lines' trial states,
    /// the recorders' observations.
    fn commit(
        &mut self,
        runs: &mut [LineRun<'_>],
        out: StepOutcome,
        t1: f64,
    ) -> Result<(), GlobalError> {
        self.stats.coupling_iterations += out.passes;
        self.stats.max_coupling_iterations = self.stats.max_coupling_iterations.max(out.passes);
        if !out.end.body.position_m.iter().all(|x| x.is_finite()) {
            return Err(GlobalError::NonFinite {
                what: "floater position",
                time_s: t1,
            });
        }
        self.now = out.end;
        for run in runs.iter_mut() {
            std::mem::swap(&mut run.state, &mut run.trial);
        }
        for (k, rec) in self.recorders.iter_mut().enumerate() {
            rec.observe(
                &self.eq.line_models[k],
                t1,
                &runs[k].state.q,
                &runs[k].force,
            );
        }
        self.stats.steps += 1;
        Ok(())
    }
}

/// The result: each line's recorded hot spots and envelope with its static state, the hot
/// spots in the case's order, the floater's series and the run's statistics.
fn assemble(
    model: &GlobalModel,
    eq: &StaticEquilibrium,
    recorders: Vec<LineRecorder>,
    floater: FloaterSeries,
    stats: RunStats,
) -> Result<GlobalResult, GlobalError> {
    let timing = &model.case.timing;
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
        floater,
        static_body_position_m: eq.body.position_m.into(),
        static_body_angles_rad: angles(&eq.body.rotation),
        wind_speed_m_s: model.wind_speed_m_s,
        thrust_n: model.thrust_n,
        wave_cut_off: model.wave_cut_off,
        stats,
    };
    result.check_finite()?;
    Ok(result)
}
