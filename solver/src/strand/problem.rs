//! Quasi-static equilibrium of the strand model under the imposed (ε, κ) path, as a
//! [`NonlinearProblem`] for the Newton driver.
//!
//! Residual r = f_beam + f_contact + f_tie over the free (helical wire) DOFs; there are no
//! applied loads, the problem is driven by the prescribed core motion and the tie targets.
//! When the driver asks for a load factor other than the trial one, every node first receives
//! the increment of the rigid section motion between the two load factors (predictor: the
//! plane-section, i.e. stick, solution), and the core nodes are set exactly. Contact history
//! changes only in [`NonlinearProblem::commit`] (converged steps); [`NonlinearProblem::restore`]
//! returns to the committed state. The force scale of the convergence test is the Euclidean norm
//! of the contact normal forces and tie forces.

use nalgebra::Vector3;

use super::ends::{TieMatrix, TieVector};
use super::loading::{LoadPath, SectionMotion};
use super::model::StrandModel;
use crate::beam::frame::{assemble_frame, FrameError, FrameState};
use crate::contact::{
    ContactHistory, ContactResponse, ElementMatrix, ElementVector, NodeKinematics,
};
use crate::linalg::NonlinearProblem;

/// Trial and committed state of a strand run.
#[derive(Debug, Clone)]
pub struct StrandProblem<'a> {
    model: &'a StrandModel,
    path: LoadPath,
    trial: FrameState,
    committed: FrameState,
    trial_load_factor: f64,
    committed_load_factor: f64,
    histories: Vec<ContactHistory>,
    responses: Vec<Option<ContactResponse>>,
}

impl<'a> StrandProblem<'a> {
    /// Problem in the reference configuration at λ = 0 with the model's initial histories.
    pub fn new(model: &'a StrandModel, path: LoadPath) -> Self {
        let state = FrameState::reference(&model.frame);
        Self {
            model,
            path,
            trial: state.clone(),
            committed: state,
            trial_load_factor: 0.0,
            committed_load_factor: 0.0,
            histories: model.initial_histories.clone(),
            responses: vec![None; model.contacts.len()],
        }
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

    /// Committed contact histories.
    pub fn histories(&self) -> &[ContactHistory] {
        &self.histories
    }

    /// Contact responses of the last evaluation (the committed state after a converged solve).
    pub fn responses(&self) -> &[Option<ContactResponse>] {
        &self.responses
    }

    fn kinematics(&self, node: usize) -> NodeKinematics {
        NodeKinematics {
            position: self.trial.positions[node],
            rotation: self.trial.rotations[node],
        }
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
        self.trial_load_factor = load_factor;
    }
}

impl NonlinearProblem for StrandProblem<'_> {
    type Error = FrameError;

    fn evaluate(
        &mut self,
        load_factor: f64,
        residual: &mut [f64],
        mut tangent: Option<&mut [f64]>,
    ) -> Result<f64, FrameError> {
        if load_factor != self.trial_load_factor {
            self.predict(load_factor);
        }
        let model = self.model;
        let pattern = &model.pattern;
        assemble_frame(
            &model.frame,
            &self.trial,
            pattern,
            0,
            residual,
            tangent.as_deref_mut(),
        )?;
        let mut scale2 = 0.0;
        let (mut fe, mut ke) = (ElementVector::zeros(), ElementMatrix::zeros());
        for (c, pair) in model.contacts.iter().enumerate() {
            let [a, b] = model.mesh.contacts[c].nodes;
            let (k1, k2) = (self.kinematics(a.0), self.kinematics(b.0));
            let pe = model.contact_pattern_element(c);
            let response = match tangent.as_deref_mut() {
                Some(values) => {
                    let r =
                        pair.residual_and_tangent(&self.histories[c], &k1, &k2, &mut fe, &mut ke);
                    pattern.add_element_matrix(values, pe, ke.as_slice());
                    r
                }
                None => pair.residual(&self.histories[c], &k1, &k2, &mut fe),
            };
            pattern.add_element_vector(residual, pe, fe.as_slice());
            scale2 += response.normal_force_n * response.normal_force_n;
            self.responses[c] = Some(response);
        }
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
            if let Some(values) = tangent.as_deref_mut() {
                pattern.add_element_matrix(values, pe, kt.as_slice());
            }
            scale2 += ft.fixed_rows::<3>(0).norm_squared();
        }
        Ok(scale2.sqrt())
    }

    fn apply_increment(&mut self, increment: &[f64]) {
        self.trial.apply_increment(&self.model.dofs, increment);
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
}

/// Axial force carried across the plane z = `z_m` of the reference configuration: the sum over
/// the elements spanning it of the z-component of their internal force at the end node beyond
/// the plane (N).
pub fn section_force_n(
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
