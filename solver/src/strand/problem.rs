//! Quasi-static equilibrium of the strand model under the imposed (ε, κ) path, as a
//! [`NonlinearProblem`] for the Newton driver.
//!
//! Residual r = f_beam + f_contact + f_tie over the free (helical wire) DOFs; there are no
//! applied loads, the problem is driven by the prescribed core motion and the tie targets.
//! When the driver asks for a load factor other than the trial one, every node first receives
//! the increment of the rigid section motion between the two load factors (predictor: the
//! plane-section, i.e. stick, solution), and the core nodes are set exactly. With a
//! [`SegmentPredictor`] the wire motion beyond the plane sections over the last load segment
//! follows, scaled by the share of that segment's load change the new load repeats (a secant
//! predictor; after a turning point the share is negative: a contact's Masing branch mirrors
//! its last one). Contact history changes only in [`NonlinearProblem::commit`] (converged
//! steps); [`NonlinearProblem::restore`] returns to the committed state. The force scale of the
//! convergence test is the Euclidean norm of the contact normal forces and tie forces.

use std::sync::Arc;

use nalgebra::Vector3;
use rayon::prelude::*;

use super::ends::{TieMatrix, TieVector};
use super::loading::{LoadPath, LoadSegment, SectionMotion};
use super::model::StrandModel;
use crate::beam::frame::{
    assemble_frame, assemble_frame_parallel, FrameError, FrameState, FrameWorkspace,
};
use crate::beam::rotation::{exp_so3, log_so3};
use crate::contact::{
    ContactHistory, ContactResponse, ElementMatrix, ElementVector, NodeKinematics,
};
use crate::linalg::{NonlinearProblem, SparsePattern};

/// How the load factor maps to the section motion.
#[derive(Debug, Clone, Copy, PartialEq)]
enum Program {
    /// Tension then bending, λ ∈ [0, 2].
    TwoStage(LoadPath),
    /// One straight (ε, κ) segment, λ ∈ [0, 1].
    Segment(LoadSegment),
}

impl Program {
    fn at(&self, load_factor: f64) -> SectionMotion {
        match self {
            Self::TwoStage(p) => p.at(load_factor),
            Self::Segment(s) => s.at(load_factor),
        }
    }
}

/// Trial and committed state of a strand run.
#[derive(Debug, Clone)]
pub struct StrandProblem<'a> {
    model: &'a StrandModel,
    path: Program,
    trial: FrameState,
    committed: FrameState,
    trial_load_factor: f64,
    committed_load_factor: f64,
    histories: Vec<ContactHistory>,
    responses: Vec<Option<ContactResponse>>,
    /// Scratch of the periodic elimination: extended residual, tangent values, increment,
    /// coefficients (empty without periodic ends).
    extended: ExtendedScratch,
    /// Symmetric positive semi-definite surrogate of the last tangent, on [`StrandModel::pattern`]
    /// (the preconditioner of [`crate::linalg::SplitSolver`]).
    surrogate: Vec<f64>,
    /// Element work on a thread pool ([`StrandProblem::with_threads`]); `None`: on the calling
    /// thread.
    parallel: Option<ParallelElements>,
    predictor: Option<SegmentPredictor>,
    /// Sliding stiffness of the first Newton correction of a step, as a fraction of each
    /// gross-slipping Cattaneo–Mindlin contact's k₀ ([`StrandProblem::with_sliding_stiffness`]).
    sliding_stiffness: f64,
    /// The fraction of the current Newton iteration.
    sliding_now: f64,
}

/// Thread pool and per-element buffers of the parallel element work: the kernels of the beams
/// and contacts run on the pool, their results are added on the calling thread in element
/// order, so the assembled system is the sequential one to the bit.
#[derive(Debug, Clone)]
struct ParallelElements {
    pool: Arc<rayon::ThreadPool>,
    frame: FrameWorkspace,
    contacts: Vec<ContactWork>,
}

/// Result of one contact element.
#[derive(Debug, Clone, Default)]
struct ContactWork {
    force: ElementVector,
    tangent: ElementMatrix,
    surrogate: ElementMatrix,
    response: Option<ContactResponse>,
}

impl ContactWork {
    /// Contact `c` of `model` in `state`: its force and, if `with_tangent`, its tangent and
    /// symmetric surrogate ([`crate::contact::ContactPair::residual_tangent_and_surrogate`]).
    fn evaluate(
        &mut self,
        model: &StrandModel,
        state: &FrameState,
        histories: &[ContactHistory],
        c: usize,
        with_tangent: bool,
        sliding: f64,
    ) {
        let pair = &model.contacts[c];
        let [a, b] = model.mesh.contacts[c].nodes;
        let (k1, k2) = (kinematics(state, a.0), kinematics(state, b.0));
        self.response = Some(if with_tangent {
            pair.residual_tangent_and_surrogate(
                &histories[c],
                &k1,
                &k2,
                &mut self.force,
                &mut self.tangent,
                &mut self.surrogate,
                sliding,
            )
        } else {
            pair.residual(&histories[c], &k1, &k2, &mut self.force)
        });
    }

    /// Adds the evaluated contact (pattern element `pe`) to the tangent and surrogate, if
    /// given, and to the residual; its response.
    fn add_to(
        &self,
        pattern: &SparsePattern,
        pe: usize,
        residual: &mut [f64],
        tangent: &mut Option<(&mut [f64], &mut [f64])>,
    ) -> ContactResponse {
        if let Some((values, surrogate)) = tangent.as_mut() {
            pattern.add_element_matrix(values, pe, self.tangent.as_slice());
            pattern.add_element_matrix(surrogate, pe, self.surrogate.as_slice());
        }
        pattern.add_element_vector(residual, pe, self.force.as_slice());
        self.response.expect("contact evaluated before it is added")
    }
}

/// What the sliding stiffness of the Newton iteration matrix is multiplied by from one
/// correction to the next ([`StrandProblem::with_sliding_stiffness`]): 4e-3 of the first
/// correction's at the fifth, so the last corrections of a step are Newton's.
pub const SLIDING_STIFFNESS_DECAY: f64 = 0.25;

/// How the contacts changed between two evaluations: those whose state (open, stick, gross
/// slip) changed, those whose tangential force moved by more than
/// [`StateChanges::TANGENTIAL_MOVE_N`], and the largest move of the tangential force with its
/// contact.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub(super) struct StateChanges {
    pub(super) state_changes: usize,
    pub(super) tangential_moves: usize,
    pub(super) largest: (f64, usize),
}

impl StateChanges {
    /// A move of the tangential force that counts (N): ten times the residual tolerance of
    /// the history runs.
    pub(super) const TANGENTIAL_MOVE_N: f64 = 0.1;

    pub(super) fn add(
        &mut self,
        contact: usize,
        before: &ContactResponse,
        after: &ContactResponse,
    ) {
        if before.status != after.status {
            self.state_changes += 1;
        }
        let moved = (after.tangential_force - before.tangential_force).norm();
        if moved > Self::TANGENTIAL_MOVE_N {
            self.tangential_moves += 1;
        }
        if moved > self.largest.0 {
            self.largest = (moved, contact);
        }
    }
}

/// The secant predictor of a load segment: the wire motion beyond the plane sections over the
/// last segment, scaled by the share of that segment's load change the new load repeats
/// (negative after a turning point).
#[derive(Debug, Clone)]
pub(crate) struct SegmentPredictor {
    /// Section motion where the current segment started.
    start: SectionMotion,
    /// The last segment's change of (ε, κ), weighted.
    change: [f64; 2],
    weights: [f64; 2],
    positions: Vec<Vector3<f64>>,
    rotations: Vec<Vector3<f64>>,
}

impl SegmentPredictor {
    /// The wire motion beyond the plane sections of `model` between the committed states
    /// `start`, at section motion `from`, and `end`, at `to`; `weights` scale the strain and
    /// curvature changes to comparable units (the sub-step limits' inverses).
    pub(crate) fn between(
        model: &StrandModel,
        start: &FrameState,
        end: &FrameState,
        from: SectionMotion,
        to: SectionMotion,
        weights: [f64; 2],
    ) -> Self {
        let reference = model.frame.reference_positions();
        let mut positions = vec![Vector3::zeros(); reference.len()];
        let mut rotations = vec![Vector3::zeros(); reference.len()];
        for (i, x_ref) in reference.iter().enumerate() {
            if model.prescribed[i] {
                continue;
            }
            let z = x_ref.z;
            positions[i] =
                end.positions[i] - start.positions[i] - (to.map(x_ref) - from.map(x_ref));
            // end = exp(θ) R_to R_fromᵀ start, the plane-section predictor's composition
            let r = end.rotations[i]
                * start.rotations[i].transpose()
                * from.rotation(z)
                * to.rotation(z).transpose();
            rotations[i] = log_so3(&r);
        }
        Self {
            start: to,
            change: [
                (to.strain - from.strain) * weights[0],
                (to.curvature_per_m - from.curvature_per_m) * weights[1],
            ],
            weights,
            positions,
            rotations,
        }
    }

    /// The same wire motion for a sub-step that starts at section motion `start`.
    pub(crate) fn anchored_at(mut self, start: SectionMotion) -> Self {
        self.start = start;
        self
    }

    /// The wire motion beyond the plane sections: node displacements and rotation vectors.
    #[cfg(test)]
    pub(crate) fn wire_motion(&self) -> (&[Vector3<f64>], &[Vector3<f64>]) {
        (&self.positions, &self.rotations)
    }

    /// The share of the earlier sub-step's load change that the section motion `at` repeats
    /// from where the current sub-step started: the projection on that change, within ±1 (a
    /// larger sub-step than the earlier one gets no more than its wire motion, so that a small
    /// sub-step's motion is never amplified).
    pub(crate) fn share(&self, at: &SectionMotion) -> f64 {
        let d = [
            (at.strain - self.start.strain) * self.weights[0],
            (at.curvature_per_m - self.start.curvature_per_m) * self.weights[1],
        ];
        let n2 = self.change[0] * self.change[0] + self.change[1] * self.change[1];
        if n2 > 0.0 {
            ((d[0] * self.change[0] + d[1] * self.change[1]) / n2).clamp(-1.0, 1.0)
        } else {
            0.0
        }
    }
}

/// Buffers of the extended system assembled before the periodic elimination.
#[derive(Debug, Clone, Default)]
struct ExtendedScratch {
    residual: Vec<f64>,
    values: Vec<f64>,
    surrogate: Vec<f64>,
    increment: Vec<f64>,
    coefficients: Vec<f64>,
    zeros: Vec<f64>,
    discard: Vec<f64>,
}

impl<'a> StrandProblem<'a> {
    /// Problem in the reference configuration at λ = 0 with the model's initial histories.
    pub fn new(model: &'a StrandModel, path: LoadPath) -> Self {
        let state = FrameState::reference(&model.frame);
        Self {
            model,
            path: Program::TwoStage(path),
            trial: state.clone(),
            committed: state,
            trial_load_factor: 0.0,
            committed_load_factor: 0.0,
            histories: model.initial_histories.clone(),
            responses: vec![None; model.contacts.len()],
            extended: model
                .periodic
                .as_ref()
                .map_or_else(ExtendedScratch::default, |p| ExtendedScratch {
                    residual: vec![0.0; p.extended.size()],
                    values: vec![0.0; p.extended.nnz()],
                    surrogate: vec![0.0; p.extended.nnz()],
                    increment: vec![0.0; p.extended.size()],
                    coefficients: Vec::new(),
                    zeros: vec![0.0; p.extended.size()],
                    discard: vec![0.0; model.pattern.size()],
                }),
            surrogate: vec![0.0; model.pattern.nnz()],
            parallel: None,
            predictor: None,
            sliding_stiffness: 0.0,
            sliding_now: 0.0,
        }
    }

    /// Carries the wire motion beyond the plane sections of an earlier sub-step into the next
    /// one (see [`SegmentPredictor`]); `None`: the plane-section predictor alone.
    pub(crate) fn set_predictor(&mut self, predictor: Option<SegmentPredictor>) {
        self.predictor = predictor;
    }

    /// The element work (beams and contacts) on `threads` threads from now on (1: on the
    /// calling thread). The residuals and tangents do not depend on it, to the bit.
    pub(crate) fn with_threads(
        mut self,
        threads: usize,
    ) -> Result<Self, rayon::ThreadPoolBuildError> {
        self.parallel = if threads > 1 {
            let pool = rayon::ThreadPoolBuilder::new()
                .num_threads(threads)
                .build()?;
            Some(ParallelElements {
                pool: Arc::new(pool),
                frame: FrameWorkspace::new(&self.model.frame),
                contacts: vec![ContactWork::default(); self.model.contacts.len()],
            })
        } else {
            None
        };
        Ok(self)
    }

    /// The Newton iteration matrix gives every Cattaneo–Mindlin contact in gross slip a
    /// stiffness along its sliding direction of `fraction` · k₀ at a step's first correction,
    /// [`SLIDING_STIFFNESS_DECAY`] times less at each further one (0: the consistent tangent).
    /// The residual is unchanged, so is the converged state; the corrections no longer carry
    /// lightly loaded sliding wires micrometres along their free directions, where every
    /// contact they cross would reverse
    /// (`docs/notes/2026-12-06-newton-stalls-under-cattaneo-mindlin.md`).
    pub(crate) fn with_sliding_stiffness(mut self, fraction: f64) -> Self {
        self.sliding_stiffness = fraction;
        self
    }

    /// Current (trial) configuration; the committed one after a converged solve.
    pub fn state(&self) -> &FrameState {
        &self.trial
    }

    /// Load factor of the committed state.
    pub fn load_factor(&self) -> f64 {
        self.committed_load_factor
    }

    /// Section motion of the committed state.
    pub fn motion(&self) -> SectionMotion {
        self.path.at(self.committed_load_factor)
    }

    /// Starts a straight load segment from the committed section motion to `to`: the load
    /// factor restarts at 0 (the committed state) and reaches `to` at 1, so that the Newton
    /// driver is called from 0 to 1 ([`crate::linalg::solve_load_path`]).
    pub fn start_segment(&mut self, to: SectionMotion) {
        let from = self.motion();
        self.restore();
        self.path = Program::Segment(LoadSegment { from, to });
        self.committed_load_factor = 0.0;
        self.trial_load_factor = 0.0;
    }

    /// Resumes at the saved committed `state`, contact `histories` and section `motion` (a
    /// checkpoint); the next segment starts from there.
    pub fn resume(
        &mut self,
        motion: SectionMotion,
        state: FrameState,
        histories: Vec<ContactHistory>,
    ) {
        self.path = Program::Segment(LoadSegment {
            from: motion,
            to: motion,
        });
        self.committed = state.clone();
        self.trial = state;
        self.histories = histories;
        self.responses.iter_mut().for_each(|r| *r = None);
        self.committed_load_factor = 0.0;
        self.trial_load_factor = 0.0;
    }

    /// Committed configuration.
    pub(crate) fn committed_state(&self) -> &FrameState {
        &self.committed
    }

    /// Committed contact histories.
    pub fn histories(&self) -> &[ContactHistory] {
        &self.histories
    }

    /// Contact responses of the last evaluation (the committed state after a converged solve).
    pub fn responses(&self) -> &[Option<ContactResponse>] {
        &self.responses
    }

    fn predict(&mut self, load_factor: f64) {
        let old = self.path.at(self.trial_load_factor);
        let new = self.path.at(load_factor);
        let reference = self.model.frame.reference_positions();
        for (i, x_ref) in reference.iter().enumerate() {
            let z = x_ref.z;
            if self.model.prescribed[i] {
                self.trial.positions[i] = new.map(x_ref);
                self.trial.rotations[i] = new.rotation(z);
            } else {
                self.trial.positions[i] += new.map(x_ref) - old.map(x_ref);
                self.trial.rotations[i] =
                    new.rotation(z) * old.rotation(z).transpose() * self.trial.rotations[i];
            }
        }
        if let Some(pr) = &self.predictor {
            let ds = pr.share(&new) - pr.share(&old);
            if ds != 0.0 {
                for (i, &prescribed) in self.model.prescribed.iter().enumerate() {
                    if !prescribed {
                        self.trial.positions[i] += pr.positions[i] * ds;
                        self.trial.rotations[i] =
                            exp_so3(&(pr.rotations[i] * ds)) * self.trial.rotations[i];
                    }
                }
            }
        }
        if let Some(p) = &self.model.periodic {
            p.enforce(&new, &mut self.trial);
        }
        self.trial_load_factor = load_factor;
    }
}

impl NonlinearProblem for StrandProblem<'_> {
    type Error = FrameError;

    fn evaluate(
        &mut self,
        load_factor: f64,
        residual: &mut [f64],
        tangent: Option<&mut [f64]>,
    ) -> Result<f64, FrameError> {
        if load_factor != self.trial_load_factor {
            self.predict(load_factor);
        }
        let model = self.model;
        let with_tangent = tangent.is_some();
        let Some(periodic) = &model.periodic else {
            let mut surrogate = std::mem::take(&mut self.surrogate);
            if with_tangent {
                surrogate.fill(0.0);
            }
            let scale = self.assemble(
                load_factor,
                residual,
                tangent.map(|t| (t, surrogate.as_mut_slice())),
            );
            self.surrogate = surrogate;
            return scale;
        };
        let mut ext = std::mem::take(&mut self.extended);
        ext.residual.fill(0.0);
        if with_tangent {
            ext.values.fill(0.0);
            ext.surrogate.fill(0.0);
        }
        let scale = self.assemble(
            load_factor,
            &mut ext.residual,
            with_tangent.then_some((ext.values.as_mut_slice(), ext.surrogate.as_mut_slice())),
        );
        if scale.is_ok() {
            periodic.coefficients(
                &self.path.at(load_factor),
                &self.trial,
                &mut ext.coefficients,
            );
            periodic.reduce(
                &ext.coefficients,
                &ext.residual,
                residual,
                tangent.map(|t| (ext.values.as_slice(), t)),
            );
            if with_tangent {
                self.surrogate.fill(0.0);
                periodic.reduce(
                    &ext.coefficients,
                    &ext.zeros,
                    &mut ext.discard,
                    Some((ext.surrogate.as_slice(), self.surrogate.as_mut_slice())),
                );
            }
        }
        self.extended = ext;
        scale
    }

    fn apply_increment(&mut self, increment: &[f64]) {
        match &self.model.periodic {
            None => self.trial.apply_increment(&self.model.dofs, increment),
            Some(p) => {
                p.expand(increment, &mut self.extended.increment);
                self.trial
                    .apply_increment(&self.model.dofs, &self.extended.increment);
                p.enforce(&self.path.at(self.trial_load_factor), &mut self.trial);
            }
        }
    }

    fn commit(&mut self, load_factor: f64) {
        for (h, r) in self.histories.iter_mut().zip(&self.responses) {
            if let Some(r) = r {
                h.accept(r);
            }
        }
        self.committed.clone_from(&self.trial);
        self.committed_load_factor = load_factor;
        self.trial_load_factor = load_factor;
    }

    fn restore(&mut self) {
        self.trial.clone_from(&self.committed);
        self.trial_load_factor = self.committed_load_factor;
    }

    fn begin_iteration(&mut self, iteration: usize) {
        self.sliding_now =
            self.sliding_stiffness * SLIDING_STIFFNESS_DECAY.powi(iteration.min(64) as i32);
    }

    fn merit_weights(&self) -> Option<&[f64]> {
        Some(&self.model.merit_weights)
    }

    fn preconditioner(&self) -> Option<&[f64]> {
        Some(&self.surrogate)
    }
}

impl StrandProblem<'_> {
    /// Residual, and if asked the tangent and its symmetric surrogate (beams and ties as they
    /// are, contacts by [`crate::contact::ContactPair::residual_tangent_and_surrogate`]), of
    /// every element on the model's assembly pattern; the force scale.
    fn assemble(
        &mut self,
        load_factor: f64,
        residual: &mut [f64],
        mut tangent: Option<(&mut [f64], &mut [f64])>,
    ) -> Result<f64, FrameError> {
        let model = self.model;
        let pattern = model.assembly_pattern();
        let with_tangent = tangent.is_some();
        let (trial, histories) = (&self.trial, &self.histories);
        let sliding = self.sliding_now;
        let frame_tangent = tangent.as_mut().map(|(t, _)| &mut **t);
        match self.parallel.as_mut() {
            Some(parallel) => {
                assemble_frame_parallel(
                    &parallel.pool,
                    &model.frame,
                    trial,
                    pattern,
                    0,
                    residual,
                    frame_tangent,
                    &mut parallel.frame,
                )?;
                parallel.pool.install(|| {
                    parallel
                        .contacts
                        .par_iter_mut()
                        .enumerate()
                        .for_each(|(c, w)| {
                            w.evaluate(model, trial, histories, c, with_tangent, sliding)
                        });
                });
            }
            None => assemble_frame(&model.frame, trial, pattern, 0, residual, frame_tangent)?,
        }
        if let Some((t, s)) = tangent.as_mut() {
            s.copy_from_slice(t);
        }
        // contacts added in contact order, evaluated above on the pool or here one by one
        let mut scale2 = 0.0;
        // what the contacts did since the previous evaluation, at trace level only (where a
        // Newton step stalls: `docs/notes/2026-12-06-newton-stalls-under-cattaneo-mindlin.md`)
        let mut changes = tracing::enabled!(tracing::Level::TRACE).then(StateChanges::default);
        let mut scratch = ContactWork::default();
        for c in 0..model.contacts.len() {
            let w = match self.parallel.as_ref() {
                Some(parallel) => &parallel.contacts[c],
                None => {
                    scratch.evaluate(
                        model,
                        &self.trial,
                        &self.histories,
                        c,
                        with_tangent,
                        sliding,
                    );
                    &scratch
                }
            };
            let response = w.add_to(
                pattern,
                model.contact_pattern_element(c),
                residual,
                &mut tangent,
            );
            scale2 += response.normal_force_n * response.normal_force_n;
            if let (Some(changes), Some(before)) = (changes.as_mut(), &self.responses[c]) {
                changes.add(c, before, &response);
            }
            self.responses[c] = Some(response);
        }
        if let Some(changes) = changes {
            tracing::trace!(
                with_tangent,
                state_changes = changes.state_changes,
                tangential_moves = changes.tangential_moves,
                largest_move_contact = changes.largest.1,
                largest_move_n = changes.largest.0,
                "contacts against the previous evaluation"
            );
        }
        self.assemble_ties(load_factor, residual, tangent, scale2)
    }

    /// Tie forces and tangents, added to `residual` and `tangent`; the force scale from the
    /// sum of squares `scale2` of the elements before.
    fn assemble_ties(
        &self,
        load_factor: f64,
        residual: &mut [f64],
        mut tangent: Option<(&mut [f64], &mut [f64])>,
        mut scale2: f64,
    ) -> Result<f64, FrameError> {
        let model = self.model;
        let pattern = model.assembly_pattern();
        let motion = self.path.at(load_factor);
        let (mut ft, mut kt) = (TieVector::zeros(), TieMatrix::zeros());
        for (t, tie) in model.ties.iter().enumerate() {
            tie.force_and_tangent(
                &motion,
                &self.trial.positions[tie.node],
                &self.trial.rotations[tie.node],
                &mut ft,
                &mut kt,
            );
            let pe = model.tie_pattern_element(t);
            pattern.add_element_vector(residual, pe, ft.as_slice());
            if let Some((values, surrogate)) = tangent.as_mut() {
                pattern.add_element_matrix(values, pe, kt.as_slice());
                pattern.add_element_matrix(surrogate, pe, kt.as_slice());
            }
            scale2 += ft.fixed_rows::<3>(0).norm_squared();
        }
        Ok(scale2.sqrt())
    }
}

/// Position and rotation of `node` in `state`.
fn kinematics(state: &FrameState, node: usize) -> NodeKinematics {
    NodeKinematics {
        position: state.positions[node],
        rotation: state.rotations[node],
    }
}

/// Axial force carried across the plane z = `z_m` of the reference configuration: the sum over
/// the elements spanning it of the z-component of their internal force at the end node beyond
/// the plane (N).
pub(crate) fn section_force_n(
    model: &StrandModel,
    state: &FrameState,
    z_m: f64,
) -> Result<f64, FrameError> {
    let mut total = 0.0;
    let mut fe = crate::beam::corotational::Vector12::zeros();
    let reference = model.frame.reference_positions();
    for (e, el) in model.frame.elements().iter().enumerate() {
        let [a, b] = el.nodes;
        if !(reference[a.0].z <= z_m && reference[b.0].z > z_m) {
            continue;
        }
        el.beam
            .internal_force(
                &state.positions[a.0],
                &state.positions[b.0],
                &state.rotations[a.0],
                &state.rotations[b.0],
                &mut fe,
            )
            .map_err(|source| FrameError::Element { element: e, source })?;
        total += Vector3::new(fe[6], fe[7], fe[8]).z;
    }
    Ok(total)
}
