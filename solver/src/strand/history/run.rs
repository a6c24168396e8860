//! The history run itself: sub-stepped Newton solves between the kept samples, interpolation
//! back to the original samples, streaming rainflow of every contact (see the parent module).

use std::time::Instant;

use super::checkpoint::HistoryCheckpoint;
use super::monitors::{
    contact_sample, contact_sites, default_channels, element_axial_force, MonitorChannel,
    MonitorTarget,
};
use super::recording::{Recorder, Snapshot};
use super::reduce::{chord_positions, history_scales, reduce_history_on_scale};
use super::timing::{TimedProblem, TimedSolver, WorkTimes};
use super::{
    motion_of, reference_problem, validate_samples, HistoryError, HistoryObserver, HistoryOptions,
    HistoryProgress, HistoryResult, HistoryStats, LoadSample,
};
use crate::linalg::{solve_load_path, NewtonParams, NewtonStats, NewtonWorkspace, SplitSolver};
use crate::strand::loading::{LoadSegment, SectionMotion};
use crate::strand::model::StrandModel;
use crate::strand::problem::{SegmentPredictor, StrandProblem};

/// The solver side: problem, factorisation, workspace, counts.
pub(super) struct Runner<'a> {
    model: &'a StrandModel,
    pub(super) problem: StrandProblem<'a>,
    solver: TimedSolver<SplitSolver>,
    workspace: NewtonWorkspace,
    newton: NewtonParams,
    max_strain: f64,
    max_curvature: f64,
    /// Whether each sub-step starts from an earlier one's wire motion (`HistoryOptions`).
    segment_predictor: bool,
    /// The wire motion of the last segment's first sub-step.
    first_substep: Option<SegmentPredictor>,
    pub(super) stats: HistoryStats,
}

impl<'a> Runner<'a> {
    pub(super) fn new(
        model: &'a StrandModel,
        options: &HistoryOptions,
    ) -> Result<Self, HistoryError> {
        Ok(Self {
            model,
            problem: reference_problem(model, options.threads)?
                .with_sliding_stiffness(options.sliding_stiffness),
            solver: TimedSolver {
                inner: model
                    .linear_solver_threads(options.threads, options.preconditioner_precision)?,
                times: WorkTimes::default(),
            },
            workspace: NewtonWorkspace::new(&model.pattern),
            newton: options.newton,
            max_strain: options.max_substep_strain,
            max_curvature: options.max_substep_curvature_per_m,
            segment_predictor: options
                .segment_predictor
                .unwrap_or_else(|| model.predicts_from_last_segment()),
            first_substep: None,
            stats: HistoryStats::default(),
        })
    }

    /// Drives the committed state to `to` in equal sub-steps within the limits; with
    /// `channels`, returns the snapshot after every sub-step.
    pub(super) fn advance(
        &mut self,
        to: SectionMotion,
        stage: &'static str,
        sample: usize,
        time_s: f64,
        channels: Option<&[MonitorChannel]>,
    ) -> Result<Vec<Snapshot>, HistoryError> {
        let from = self.problem.motion();
        let (de, dk) = (
            (to.strain - from.strain).abs(),
            (to.curvature_per_m - from.curvature_per_m).abs(),
        );
        let substeps = if de == 0.0 && dk == 0.0 {
            0
        } else {
            ((de / self.max_strain).max(dk / self.max_curvature).ceil() as usize).max(1)
        };
        let segment = LoadSegment { from, to };
        let weights = [1.0 / self.max_strain, 1.0 / self.max_curvature];
        let mut out = Vec::with_capacity(if channels.is_some() { substeps } else { 0 });
        for k in 1..=substeps {
            let start = self.problem.motion();
            let target = segment.at(k as f64 / substeps as f64);
            if self.segment_predictor && k == 1 {
                // a segment's first sub-step repeats the last segment's first one (mirrored
                // after a turning point: Masing), a later sub-step the one before it
                let first = self.first_substep.take().map(|p| p.anchored_at(start));
                self.problem.set_predictor(first);
            }
            let start_state = self
                .segment_predictor
                .then(|| self.problem.committed_state().clone());
            self.problem.start_segment(target);
            let mut stats = NewtonStats::default();
            let mut timed = TimedProblem {
                inner: &mut self.problem,
                times: WorkTimes::default(),
            };
            let solved = solve_load_path(
                &mut timed,
                0.0,
                1.0,
                &self.model.pattern,
                &mut self.solver,
                &self.newton,
                &mut self.workspace,
                &mut stats,
            );
            self.stats.work.assembly_s += timed.times.assembly_s;
            self.stats.add(&stats);
            solved.map_err(|source| HistoryError::Step {
                stage,
                sample,
                time_s,
                substep: k,
                substeps,
                from_strain: start.strain,
                from_curvature: start.curvature_per_m,
                to_strain: target.strain,
                to_curvature: target.curvature_per_m,
                source: Box::new(source),
            })?;
            if let Some(state) = start_state {
                let end = self.problem.committed_state();
                let p = SegmentPredictor::between(self.model, &state, end, start, target, weights);
                if k == 1 {
                    self.first_substep = Some(p.clone());
                }
                self.problem.set_predictor(Some(p));
            }
            if let Some(ch) = channels {
                out.push(self.snapshot(ch)?);
            }
        }
        Ok(out)
    }

    /// Counts and times so far (a run resumed from a checkpoint starts from the checkpoint's
    /// counts, with a new solver).
    pub(super) fn stats(&self) -> HistoryStats {
        let mut stats = self.stats.clone();
        stats.work.factorisation_s += self.solver.times.factorisation_s;
        stats.work.solve_s += self.solver.times.solve_s;
        stats.linear = stats.linear + self.solver.inner.stats();
        stats
    }

    /// Snapshot of the committed state.
    pub(super) fn snapshot(&self, channels: &[MonitorChannel]) -> Result<Snapshot, HistoryError> {
        let state = self.problem.state();
        let responses = self.problem.responses();
        let contacts = (0..self.model.contacts.len())
            .map(|c| contact_sample(self.model, state, c, responses[c].as_ref()))
            .collect();
        let mut elements = Vec::new();
        for ch in channels {
            if let MonitorTarget::Element(e) = ch.target {
                elements.push(element_axial_force(self.model, state, e)?);
            }
        }
        Ok(Snapshot { contacts, elements })
    }
}

/// Runs `model` through `samples` (module docs of [`super`]).
pub fn run_history(
    model: &StrandModel,
    samples: &[LoadSample],
    options: &HistoryOptions,
    observer: &mut dyn HistoryObserver,
) -> Result<HistoryResult, HistoryError> {
    run_history_from(model, samples, options, None, observer)
}

/// [`run_history`], continued from `checkpoint` if given (same model, samples and options as
/// the run that wrote it; the results are identical to the bit to an uninterrupted run's).
pub fn run_history_from(
    model: &StrandModel,
    samples: &[LoadSample],
    options: &HistoryOptions,
    checkpoint: Option<&HistoryCheckpoint>,
    observer: &mut dyn HistoryObserver,
) -> Result<HistoryResult, HistoryError> {
    let options = options.validated()?;
    validate_samples(model, samples, &options)?;
    let Some(first) = samples.first() else {
        return Err(HistoryError::InvalidOption {
            field: "samples",
            value: 0.0,
            reason: "the load history is empty".into(),
        });
    };
    let t_start = Instant::now();
    let kept = reduce_history_on_scale(
        samples,
        options.turning_point_tolerance,
        options.turning_point_scale,
    )?;
    let scales = history_scales(samples);
    let mut runner = Runner::new(model, &options)?;
    let (mut recorder, mut previous, start) = match checkpoint {
        Some(cp) => {
            cp.check(
                samples.len(),
                &kept,
                model.frame.node_count(),
                model.contacts.len(),
            )?;
            let state = crate::beam::frame::FrameState {
                positions: cp.positions.clone(),
                rotations: cp.rotations.clone(),
            };
            let motion = SectionMotion {
                strain: cp.strain,
                curvature_per_m: cp.curvature_per_m,
            };
            runner.problem.resume(motion, state, cp.histories.clone());
            runner.stats = cp.stats.clone();
            (cp.recorder.clone(), cp.previous.clone(), cp.next_segment)
        }
        None => {
            let channels = if options.default_monitors {
                default_channels(model, &contact_sites(model))
            } else {
                Vec::new()
            };
            initialise(&mut runner, first, &options)?;
            runner.stats.initialisation_time_s = t_start.elapsed().as_secs_f64();
            runner.stats.initialisation_substeps = runner.stats.substeps;
            runner.stats.initialisation = runner.stats().initialisation_counts();
            let mut recorder = Recorder::new(model.contacts.len(), options.slip_gate_m, channels)?;
            let t_out = Instant::now();
            let previous = runner.snapshot(&recorder.monitors.channels)?;
            recorder.push(first, &previous)?;
            observer.sample(first, &previous.contacts, &previous.elements);
            runner.stats.output_time_s += t_out.elapsed().as_secs_f64();
            (recorder, previous, 0)
        }
    };
    let mut scratch = previous.clone();
    let segments = kept.len().saturating_sub(1);
    for segment in start..segments {
        let (a, b) = (kept[segment], kept[segment + 1]);
        let t_solve = Instant::now();
        let mut points = vec![previous];
        let solved = runner.advance(
            motion_of(&samples[b]),
            "history",
            b,
            samples[b].time_s,
            Some(&recorder.monitors.channels),
        )?;
        points.extend(solved);
        runner.stats.solve_time_s += t_solve.elapsed().as_secs_f64();
        let t_out = Instant::now();
        let positions = chord_positions(samples, a, b, &scales);
        let n = points.len() - 1;
        for (i, s) in (a + 1..=b).zip(positions.iter().skip(1)) {
            if n == 0 {
                recorder.push(&samples[i], &points[0])?;
                observer.sample(&samples[i], &points[0].contacts, &points[0].elements);
                continue;
            }
            let x = s * n as f64;
            let k = (x.floor() as usize).min(n - 1);
            Snapshot::blend(&points[k], &points[k + 1], x - k as f64, &mut scratch);
            recorder.push(&samples[i], &scratch)?;
            observer.sample(&samples[i], &scratch.contacts, &scratch.elements);
        }
        previous = points.pop().unwrap_or_else(|| scratch.clone());
        runner.stats.output_time_s += t_out.elapsed().as_secs_f64();
        let done = segment + 1;
        observer.progress(&HistoryProgress {
            segment: done,
            segments,
            sample: b,
            time_s: samples[b].time_s,
            elapsed_s: t_start.elapsed().as_secs_f64(),
        });
        let interval = options.checkpoint_interval_segments;
        if interval > 0 && done % interval == 0 && done < segments {
            let committed = runner.problem.committed_state();
            let motion = runner.problem.motion();
            observer.checkpoint(&HistoryCheckpoint {
                samples: samples.len(),
                kept_samples: kept.clone(),
                next_segment: done,
                strain: motion.strain,
                curvature_per_m: motion.curvature_per_m,
                positions: committed.positions.clone(),
                rotations: committed.rotations.clone(),
                histories: runner.problem.histories().to_vec(),
                previous: previous.clone(),
                recorder: recorder.clone(),
                stats: runner.stats(),
            });
        }
        if interval > 0 && done % interval == 0 {
            // a resumed run starts here with a new solver: keep the preconditioner history
            // of both runs alike from this point on
            runner.solver.inner.reset();
            // nor does it know the last segment's wire motion
            runner.problem.set_predictor(None);
            runner.first_substep = None;
        }
        if done < segments && observer.should_stop() {
            return Err(HistoryError::Stopped {
                segment: done,
                time_s: samples[b].time_s,
            });
        }
    }
    let t_out = Instant::now();
    let contacts = recorder.records(model);
    let mut stats = runner.stats();
    stats.samples = samples.len();
    stats.kept_samples = kept.len();
    stats.output_time_s += t_out.elapsed().as_secs_f64();
    stats.total_time_s += t_start.elapsed().as_secs_f64();
    Ok(HistoryResult {
        contacts,
        monitors: recorder.monitors,
        kept_samples: kept,
        stats,
    })
}

/// The paper's three-step initialisation (Sec. 3.3): small tension, small tension with the
/// initial curvature, initial tension and curvature.
fn initialise(
    runner: &mut Runner<'_>,
    first: &LoadSample,
    options: &HistoryOptions,
) -> Result<(), HistoryError> {
    let small = options.initial_strain_fraction * first.strain;
    let stages: [(&'static str, f64, f64); 3] = [
        ("initialisation 1/3 (small tension)", small, 0.0),
        (
            "initialisation 2/3 (small tension, initial curvature)",
            small,
            first.curvature_per_m,
        ),
        (
            "initialisation 3/3 (initial tension and curvature)",
            first.strain,
            first.curvature_per_m,
        ),
    ];
    // the first stage starts where the contacts carry almost no normal force: it has its own
    // pseudo-transient shift; the later stages start from loaded contacts. With the
    // Cattaneo-Mindlin law the small tension leaves the contacts a micro-slip range δ_s of a
    // few 0.1 µm (∝ f_N^{2/3}): the initial curvature slides nearly all of them, and every
    // stage keeps the shift (six-layer strand, first 100 s of the severe history: 81 s of
    // initialisation with it, 533 s and 12 cut-backs without; docs/contact-laws.md).
    let history_newton = runner.newton;
    let memory_laws = runner.model.contact_parameters.is_cattaneo_mindlin();
    for (i, (stage, strain, curvature_per_m)) in stages.into_iter().enumerate() {
        runner.newton = if i == 0 || memory_laws {
            options.initialisation_newton()
        } else {
            history_newton
        };
        let to = SectionMotion {
            strain,
            curvature_per_m,
        };
        let advanced = runner.advance(to, stage, 0, first.time_s, None);
        runner.newton = history_newton;
        advanced?;
    }
    Ok(())
}
