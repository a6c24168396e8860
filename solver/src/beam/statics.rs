//! Static equilibrium of a beam frame under nodal loads, as a [`NonlinearProblem`] for the
//! Newton driver: r(u, λ) = f_int(u) − λ f_ext.
//!
//! Nodal loads are dead loads: forces (N) of fixed direction and spatial moments (N m) of fixed
//! axis, conjugate to the displacement and spatial spin DOFs. (A fixed-axis moment is
//! conservative only for rotations about that axis, as in plane problems.)

use nalgebra::Vector3;

use super::frame::{assemble_frame, BeamFrame, DofMap, FrameError, FrameState, NodeId};
use crate::linalg::{NonlinearProblem, SparsePattern};

/// Dead load at a node.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct NodalLoad {
    /// Loaded node.
    pub node: NodeId,
    /// Force (N).
    pub force_n: Vector3<f64>,
    /// Moment (N m).
    pub moment_nm: Vector3<f64>,
}

/// Frame statics: model references, trial and committed states, reference load vector.
#[derive(Debug, Clone)]
pub struct FrameStatics<'a> {
    frame: &'a BeamFrame,
    dofs: &'a DofMap,
    pattern: &'a SparsePattern,
    external: Vec<f64>,
    trial: FrameState,
    committed: FrameState,
    committed_load_factor: f64,
}

impl<'a> FrameStatics<'a> {
    /// Problem on `pattern` (built from `dofs.element_equations(frame)`), starting from the
    /// reference configuration at λ = 0.
    pub fn new(
        frame: &'a BeamFrame,
        dofs: &'a DofMap,
        pattern: &'a SparsePattern,
        loads: &[NodalLoad],
    ) -> Result<Self, FrameError> {
        let mut external = vec![0.0; dofs.free_count()];
        for load in loads {
            if load.node.0 >= frame.node_count() {
                return Err(FrameError::UnknownNode {
                    node: load.node.0,
                    count: frame.node_count(),
                });
            }
            for k in 0..3 {
                if let Some(i) = dofs.equation(load.node, k).index() {
                    external[i] += load.force_n[k];
                }
                if let Some(i) = dofs.equation(load.node, 3 + k).index() {
                    external[i] += load.moment_nm[k];
                }
            }
        }
        let state = FrameState::reference(frame);
        Ok(Self {
            frame,
            dofs,
            pattern,
            external,
            trial: state.clone(),
            committed: state,
            committed_load_factor: 0.0,
        })
    }

    /// Current (trial) configuration; equal to the committed one after a converged solve.
    pub fn state(&self) -> &FrameState {
        &self.trial
    }

    /// Load factor of the committed state.
    pub fn load_factor(&self) -> f64 {
        self.committed_load_factor
    }
}

impl NonlinearProblem for FrameStatics<'_> {
    type Error = FrameError;

    fn evaluate(
        &mut self,
        load_factor: f64,
        residual: &mut [f64],
        tangent: Option<&mut [f64]>,
    ) -> Result<f64, FrameError> {
        assemble_frame(self.frame, &self.trial, self.pattern, 0, residual, tangent)?;
        let mut load_norm2 = 0.0;
        for (r, f) in residual.iter_mut().zip(&self.external) {
            *r -= load_factor * f;
            load_norm2 += (load_factor * f) * (load_factor * f);
        }
        Ok(load_norm2.sqrt())
    }

    fn apply_increment(&mut self, increment: &[f64]) {
        self.trial.apply_increment(self.dofs, increment);
    }

    fn commit(&mut self, load_factor: f64) {
        self.committed.clone_from(&self.trial);
        self.committed_load_factor = load_factor;
    }

    fn restore(&mut self) {
        self.trial.clone_from(&self.committed);
    }
}
