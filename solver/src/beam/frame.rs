//! A frame of corotational beams: the model (reference nodes and elements, immutable), the
//! state (current node positions and rotation matrices), the map from node DOFs to global
//! equations, and the assembly of internal forces and tangents into a [`SparsePattern`].
//!
//! Each node carries 6 DOFs [u_x, u_y, u_z, θ_x, θ_y, θ_z]: displacement (m) and spatial
//! rotation increment (rad), applied as x ← x + Δu, Λ ← exp(Δθ̂) Λ. Nodal rotations are
//! measured from the reference configuration (Λ = I there).

use nalgebra::{Matrix3, Vector3};
use rayon::prelude::*;
use thiserror::Error;

use super::corotational::{BeamError, CorotationalBeam, Matrix12, Vector12};
use super::rotation::exp_so3;
use super::section::BeamSection;
use crate::linalg::{Equation, PatternError, SparsePattern};

/// DOFs per node.
pub(crate) const NODE_DOFS: usize = 6;

/// Index of a node in a [`BeamFrame`].
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub struct NodeId(pub usize);

/// Index of an element in a [`BeamFrame`].
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub struct ElementId(pub usize);

/// Errors of frame construction and assembly.
#[derive(Debug, Clone, PartialEq, Error)]
pub enum FrameError {
    /// An element or constraint names a node that does not exist.
    #[error("node {node} does not exist (frame has {count} nodes)")]
    UnknownNode {
        /// The node index.
        node: usize,
        /// Number of nodes.
        count: usize,
    },
    /// An element cannot be built or evaluated.
    #[error("element {element}: {source}")]
    Element {
        /// Element index.
        element: usize,
        /// What went wrong.
        source: BeamError,
    },
    /// Equation numbering failed.
    #[error(transparent)]
    Pattern(#[from] PatternError),
}

/// One element of the frame.
#[derive(Debug, Clone, PartialEq)]
pub struct FrameElement {
    /// End nodes.
    pub nodes: [NodeId; 2],
    /// Reference geometry and stiffness.
    pub beam: CorotationalBeam,
}

/// Reference nodes and elements (immutable once built).
#[derive(Debug, Clone, Default)]
pub struct BeamFrame {
    reference: Vec<Vector3<f64>>,
    elements: Vec<FrameElement>,
}

impl BeamFrame {
    /// Frame with the given reference node positions (m) and no elements.
    pub fn new(reference_positions: Vec<Vector3<f64>>) -> Self {
        Self {
            reference: reference_positions,
            elements: Vec::new(),
        }
    }

    /// Adds a node, returning its id.
    pub(crate) fn add_node(&mut self, position: Vector3<f64>) -> NodeId {
        self.reference.push(position);
        NodeId(self.reference.len() - 1)
    }

    /// Adds an element between two existing nodes; `y_hint` orients the section's local y.
    pub(crate) fn add_element(
        &mut self,
        nodes: [NodeId; 2],
        y_hint: &Vector3<f64>,
        section: &BeamSection,
    ) -> Result<ElementId, FrameError> {
        for n in nodes {
            self.check_node(n)?;
        }
        let element = self.elements.len();
        let beam = CorotationalBeam::new(
            &self.reference[nodes[0].0],
            &self.reference[nodes[1].0],
            y_hint,
            section,
        )
        .map_err(|source| FrameError::Element { element, source })?;
        self.elements.push(FrameElement { nodes, beam });
        Ok(ElementId(element))
    }

    /// Chain of elements through consecutive new nodes at `points` (one element per segment).
    pub fn add_polyline(
        &mut self,
        points: &[Vector3<f64>],
        y_hint: &Vector3<f64>,
        section: &BeamSection,
    ) -> Result<Vec<NodeId>, FrameError> {
        let nodes: Vec<NodeId> = points.iter().map(|p| self.add_node(*p)).collect();
        for pair in nodes.windows(2) {
            self.add_element([pair[0], pair[1]], y_hint, section)?;
        }
        Ok(nodes)
    }

    fn check_node(&self, n: NodeId) -> Result<(), FrameError> {
        if n.0 < self.reference.len() {
            Ok(())
        } else {
            Err(FrameError::UnknownNode {
                node: n.0,
                count: self.reference.len(),
            })
        }
    }

    /// Number of nodes.
    pub fn node_count(&self) -> usize {
        self.reference.len()
    }

    /// Elements in order.
    pub fn elements(&self) -> &[FrameElement] {
        &self.elements
    }

    /// Reference position of every node.
    pub fn reference_positions(&self) -> &[Vector3<f64>] {
        &self.reference
    }
}

/// Current configuration of a frame.
#[derive(Debug, Clone, PartialEq)]
pub struct FrameState {
    /// Current node positions (m).
    pub positions: Vec<Vector3<f64>>,
    /// Current nodal rotations Λ (reference → current).
    pub rotations: Vec<Matrix3<f64>>,
}

impl FrameState {
    /// The undeformed configuration.
    pub fn reference(frame: &BeamFrame) -> Self {
        Self {
            positions: frame.reference.clone(),
            rotations: vec![Matrix3::identity(); frame.node_count()],
        }
    }

    /// x ← x + Δu, Λ ← exp(Δθ̂) Λ for every node, reading Δ from the free equations.
    pub fn apply_increment(&mut self, dofs: &DofMap, increment: &[f64]) {
        for (node, (x, lam)) in self
            .positions
            .iter_mut()
            .zip(self.rotations.iter_mut())
            .enumerate()
        {
            let mut d = [0.0; NODE_DOFS];
            let mut any = false;
            for (k, dk) in d.iter_mut().enumerate() {
                if let Some(i) = dofs.equations[node * NODE_DOFS + k].index() {
                    *dk = increment[i];
                    any = true;
                }
            }
            if any {
                *x += Vector3::new(d[0], d[1], d[2]);
                let th = Vector3::new(d[3], d[4], d[5]);
                if th.norm_squared() > 0.0 {
                    *lam = exp_so3(&th) * *lam;
                }
            }
        }
    }
}

/// Node DOF → global equation numbering (constrained DOFs eliminated).
#[derive(Debug, Clone, PartialEq)]
pub struct DofMap {
    equations: Vec<Equation>,
    free: usize,
}

impl DofMap {
    /// Numbers the DOFs of `node_count` nodes in node order, skipping those marked `true` in
    /// `constraints` (node, [u_x, u_y, u_z, θ_x, θ_y, θ_z]).
    pub fn new(
        node_count: usize,
        constraints: &[(NodeId, [bool; NODE_DOFS])],
    ) -> Result<Self, FrameError> {
        let mut fixed = vec![false; node_count * NODE_DOFS];
        for (node, mask) in constraints {
            if node.0 >= node_count {
                return Err(FrameError::UnknownNode {
                    node: node.0,
                    count: node_count,
                });
            }
            for (k, &m) in mask.iter().enumerate() {
                fixed[node.0 * NODE_DOFS + k] |= m;
            }
        }
        let mut free = 0;
        let mut equations = Vec::with_capacity(fixed.len());
        for f in fixed {
            if f {
                equations.push(Equation::CONSTRAINED);
            } else {
                equations.push(Equation::free(free)?);
                free += 1;
            }
        }
        Ok(Self { equations, free })
    }

    /// Number of free equations.
    pub fn free_count(&self) -> usize {
        self.free
    }

    /// Equation of DOF `local` (0..6) of `node`.
    pub fn equation(&self, node: NodeId, local: usize) -> Equation {
        self.equations[node.0 * NODE_DOFS + local]
    }

    /// The 12 equations of every element of `frame`, in element order.
    pub fn element_equations(&self, frame: &BeamFrame) -> Vec<[Equation; 12]> {
        frame
            .elements
            .iter()
            .map(|e| {
                let mut eqs = [Equation::CONSTRAINED; 12];
                for (k, n) in e.nodes.iter().enumerate() {
                    eqs[6 * k..6 * k + 6]
                        .copy_from_slice(&self.equations[n.0 * NODE_DOFS..(n.0 + 1) * NODE_DOFS]);
                }
                eqs
            })
            .collect()
    }
}

/// Adds the internal forces of all elements to `residual` and, if given, their tangents to
/// `tangent` (values on `pattern`, where frame element e is pattern element
/// `first_pattern_element + e`).
pub fn assemble_frame(
    frame: &BeamFrame,
    state: &FrameState,
    pattern: &SparsePattern,
    first_pattern_element: usize,
    residual: &mut [f64],
    mut tangent: Option<&mut [f64]>,
) -> Result<(), FrameError> {
    let mut fe = Vector12::zeros();
    let mut ke = Matrix12::zeros();
    for (e, el) in frame.elements.iter().enumerate() {
        let [a, b] = el.nodes;
        let (xa, xb) = (&state.positions[a.0], &state.positions[b.0]);
        let (la, lb) = (&state.rotations[a.0], &state.rotations[b.0]);
        let pe = first_pattern_element + e;
        let result = match tangent.as_deref_mut() {
            Some(values) => el
                .beam
                .internal_force_and_tangent(xa, xb, la, lb, &mut fe, &mut ke)
                .map(|()| pattern.add_element_matrix(values, pe, ke.as_slice())),
            None => el.beam.internal_force(xa, xb, la, lb, &mut fe),
        };
        result.map_err(|source| FrameError::Element { element: e, source })?;
        pattern.add_element_vector(residual, pe, fe.as_slice());
    }
    Ok(())
}

/// Per-element force and tangent buffers for [`assemble_frame_parallel`].
#[derive(Debug, Clone)]
pub struct FrameWorkspace {
    forces: Vec<Vector12>,
    tangents: Vec<Matrix12>,
}

impl FrameWorkspace {
    /// Buffers for every element of `frame`.
    pub fn new(frame: &BeamFrame) -> Self {
        Self {
            forces: vec![Vector12::zeros(); frame.elements.len()],
            tangents: vec![Matrix12::zeros(); frame.elements.len()],
        }
    }
}

/// Same result as [`assemble_frame`], bit for bit: the element kernels run on `pool`, then the
/// element results are added in element order on the calling thread.
#[allow(clippy::too_many_arguments)]
pub fn assemble_frame_parallel(
    pool: &rayon::ThreadPool,
    frame: &BeamFrame,
    state: &FrameState,
    pattern: &SparsePattern,
    first_pattern_element: usize,
    residual: &mut [f64],
    tangent: Option<&mut [f64]>,
    workspace: &mut FrameWorkspace,
) -> Result<(), FrameError> {
    let with_tangent = tangent.is_some();
    let FrameWorkspace { forces, tangents } = workspace;
    if forces.len() != frame.elements.len() {
        *forces = vec![Vector12::zeros(); frame.elements.len()];
        *tangents = vec![Matrix12::zeros(); frame.elements.len()];
    }
    pool.install(|| {
        forces
            .par_iter_mut()
            .zip(tangents.par_iter_mut())
            .zip(frame.elements.par_iter())
            .enumerate()
            .try_for_each(|(e, ((fe, ke), el))| {
                let [a, b] = el.nodes;
                let (xa, xb) = (&state.positions[a.0], &state.positions[b.0]);
                let (la, lb) = (&state.rotations[a.0], &state.rotations[b.0]);
                if with_tangent {
                    el.beam.internal_force_and_tangent(xa, xb, la, lb, fe, ke)
                } else {
                    el.beam.internal_force(xa, xb, la, lb, fe)
                }
                .map_err(|source| FrameError::Element { element: e, source })
            })
    })?;
    for (e, fe) in forces.iter().enumerate() {
        pattern.add_element_vector(residual, first_pattern_element + e, fe.as_slice());
    }
    if let Some(values) = tangent {
        for (e, ke) in tangents.iter().enumerate() {
            pattern.add_element_matrix(values, first_pattern_element + e, ke.as_slice());
        }
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::linalg::Storage;

    /// Three-element bent frame, root clamped, in a generic deformed state.
    fn sample() -> (BeamFrame, DofMap, SparsePattern, FrameState) {
        let section = BeamSection::circle(0.01, 210e9, 0.3).unwrap();
        let mut frame = BeamFrame::default();
        let pts = [
            Vector3::new(0.0, 0.0, 0.0),
            Vector3::new(0.1, 0.0, 0.0),
            Vector3::new(0.2, 0.02, 0.0),
            Vector3::new(0.28, 0.05, 0.03),
        ];
        let nodes = frame.add_polyline(&pts, &Vector3::z(), &section).unwrap();
        let dofs = DofMap::new(frame.node_count(), &[(nodes[0], [true; 6])]).unwrap();
        let pattern = SparsePattern::new(
            dofs.free_count(),
            Storage::Full,
            &dofs.element_equations(&frame),
        )
        .unwrap();
        let mut state = FrameState::reference(&frame);
        let du: Vec<f64> = (0..dofs.free_count())
            .map(|i| {
                1e-3 * ((i as f64 * 1.7).sin()
                    + if i % 6 >= 3 { 40.0 } else { 0.0 } * (i as f64).cos())
            })
            .collect();
        state.apply_increment(&dofs, &du);
        (frame, dofs, pattern, state)
    }

    #[test]
    fn assembled_tangent_matches_central_differences_of_assembled_residual() {
        let (frame, dofs, pattern, state) = sample();
        let n = dofs.free_count();
        let mut r = vec![0.0; n];
        let mut values = vec![0.0; pattern.nnz()];
        assemble_frame(&frame, &state, &pattern, 0, &mut r, Some(&mut values)).unwrap();
        let residual_at = |d: &[f64]| {
            let mut s = state.clone();
            s.apply_increment(&dofs, d);
            let mut out = vec![0.0; n];
            assemble_frame(&frame, &s, &pattern, 0, &mut out, None).unwrap();
            out
        };
        // dense copy of the assembled tangent
        let mut k = vec![vec![0.0; n]; n];
        for (j, kj) in k.iter_mut().enumerate() {
            let mut e = vec![0.0; n];
            e[j] = 1.0;
            pattern.mul_vec(&values, &e, kj);
        }
        for j in 0..n {
            let h = if j % 6 < 3 { 1e-8 } else { 1e-7 };
            let mut d = vec![0.0; n];
            d[j] = h;
            let rp = residual_at(&d);
            d[j] = -h;
            let rm = residual_at(&d);
            for i in 0..n {
                let fd = (rp[i] - rm[i]) / (2.0 * h);
                // entries mix N/m, N/rad and N m/rad: compare against the matching diagonal scale
                let scale = (k[i][i].abs() * k[j][j].abs()).sqrt();
                assert!(
                    (fd - k[j][i]).abs() < 1e-6 * scale,
                    "K[{i},{j}] = {} vs {fd}",
                    k[j][i]
                );
            }
        }
    }

    #[test]
    fn parallel_assembly_equals_serial_assembly_bit_for_bit() {
        let (frame, dofs, pattern, state) = sample();
        let n = dofs.free_count();
        let (mut r1, mut r2) = (vec![0.0; n], vec![0.0; n]);
        let (mut k1, mut k2) = (vec![0.0; pattern.nnz()], vec![0.0; pattern.nnz()]);
        assemble_frame(&frame, &state, &pattern, 0, &mut r1, Some(&mut k1)).unwrap();
        let pool = rayon::ThreadPoolBuilder::new()
            .num_threads(2)
            .build()
            .unwrap();
        let mut ws = FrameWorkspace::new(&frame);
        assemble_frame_parallel(
            &pool,
            &frame,
            &state,
            &pattern,
            0,
            &mut r2,
            Some(&mut k2),
            &mut ws,
        )
        .unwrap();
        assert_eq!(r1, r2);
        assert_eq!(k1, k2);
    }

    #[test]
    fn constraint_on_a_missing_node_is_reported() {
        assert_eq!(
            DofMap::new(2, &[(NodeId(5), [true; 6])]),
            Err(FrameError::UnknownNode { node: 5, count: 2 })
        );
    }
}
