//! The finite-element model of one mooring line: nodes from the fairlead (node 0) to the anchor
//! (last node), elements, sections and the degree-of-freedom map.
//!
//! Every node carries its position r (3 DOF). A node touched by a rope element also carries the
//! gradient r' = ∂r/∂s with respect to the unstretched arc length s (3 more DOF), shared by the
//! rope elements on both sides (C¹ continuity). A chain–rope joint is a pin: the bar uses the
//! joint position only, the rope gradient there stays free. The anchor position is fixed and the
//! fairlead position is prescribed; gradients at the ends stay free (pinned ends).
//!
//! DOFs are numbered node by node, so an element couples at most 12 consecutive unknowns and the
//! iteration matrix is banded with half-bandwidth ≤ 11.

use nalgebra::Vector3;

use super::error::LineError;
use super::section::{Section, SectionKind};
use super::spec::{Environment, LineEnds, LineSpec};

pub use super::ids::{ElementId, NodeId};

/// A node of the mesh.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Node {
    /// Unstretched arc length from the fairlead (m).
    pub arc_length_m: f64,
    /// First global DOF (position x); the gradient, if any, follows at `dof + 3`.
    pub dof: usize,
    /// Whether the node carries a gradient (touches a rope element).
    pub has_gradient: bool,
}

/// Element family.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum ElementKind {
    /// Hermite cable element (wire rope).
    Cable,
    /// Tension-only bar (chain).
    Bar,
}

/// An element of the mesh.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Element {
    /// Family.
    pub kind: ElementKind,
    /// End nodes, fairlead side first.
    pub nodes: [NodeId; 2],
    /// Unstretched length (m).
    pub length_m: f64,
    /// Arc length of the first node (m).
    pub arc_start_m: f64,
    /// Index of its segment (and section).
    pub segment: usize,
}

/// Immutable model of one line.
#[derive(Debug, Clone)]
pub struct LineModel {
    name: String,
    env: Environment,
    ends: LineEnds,
    sections: Vec<Section>,
    nodes: Vec<Node>,
    elements: Vec<Element>,
    dof_count: usize,
    half_bandwidth: usize,
    length_m: f64,
}

impl LineModel {
    /// Builds the mesh of `spec` between `ends` at the site `env`, after validating all input.
    pub fn new(
        name: impl Into<String>,
        spec: &LineSpec,
        ends: LineEnds,
        env: &Environment,
    ) -> Result<LineModel, LineError> {
        spec.validate()?;
        env.validate()?;
        for (field, p) in [("fairlead_m", ends.fairlead_m), ("anchor_m", ends.anchor_m)] {
            if !p.iter().all(|c| c.is_finite()) {
                return Err(LineError::invalid(
                    field,
                    format!("{p:?}"),
                    "must be finite",
                ));
            }
            if p.z < -env.water_depth_m - 1e-9 {
                return Err(LineError::invalid(
                    format!("{field}.z"),
                    p.z,
                    "must not be below the seabed",
                ));
            }
        }
        let length_m = spec.length_m();
        let span = (ends.fairlead_m - ends.anchor_m).norm();
        // A line stretched by more than 10 % is outside the small-strain section model.
        if span > 1.1 * length_m {
            return Err(LineError::invalid(
                "anchor_m",
                format!("{span} m from the fairlead"),
                &format!("must be within 1.1 × the line length ({length_m} m) of the fairlead"),
            ));
        }

        let sections: Vec<Section> = spec
            .segments
            .iter()
            .map(|s| Section::new(&spec.line_types[&s.line_type], s, env))
            .collect();

        // Elements and node arc lengths.
        let mut elements = Vec::new();
        let mut arcs = vec![0.0];
        let mut s0 = 0.0;
        for (k, seg) in spec.segments.iter().enumerate() {
            let le = seg.length_m / seg.elements as f64;
            let kind = match sections[k].kind {
                SectionKind::Rope => ElementKind::Cable,
                SectionKind::Chain => ElementKind::Bar,
            };
            for e in 0..seg.elements {
                let n = arcs.len() - 1;
                let arc_start = s0 + e as f64 * le;
                elements.push(Element {
                    kind,
                    nodes: [NodeId(n), NodeId(n + 1)],
                    length_m: le,
                    arc_start_m: arc_start,
                    segment: k,
                });
                arcs.push(arc_start + le);
            }
            s0 += seg.length_m;
        }
        let last = arcs.len() - 1;
        arcs[last] = length_m;

        let mut has_gradient = vec![false; arcs.len()];
        for e in &elements {
            if e.kind == ElementKind::Cable {
                has_gradient[e.nodes[0].0] = true;
                has_gradient[e.nodes[1].0] = true;
            }
        }
        let mut dof = 0;
        let nodes: Vec<Node> = arcs
            .iter()
            .zip(&has_gradient)
            .map(|(&s, &g)| {
                let n = Node {
                    arc_length_m: s,
                    dof,
                    has_gradient: g,
                };
                dof += if g { 6 } else { 3 };
                n
            })
            .collect();
        let half_bandwidth = elements
            .iter()
            .map(|e| {
                let b = &nodes[e.nodes[1].0];
                b.dof + if b.has_gradient { 5 } else { 2 } - nodes[e.nodes[0].0].dof
            })
            .max()
            .unwrap_or(0);

        Ok(LineModel {
            name: name.into(),
            env: env.clone(),
            ends,
            sections,
            nodes,
            elements,
            dof_count: dof,
            half_bandwidth,
            length_m,
        })
    }

    /// Line name used in messages.
    pub fn name(&self) -> &str {
        &self.name
    }
    /// Site data.
    pub fn environment(&self) -> &Environment {
        &self.env
    }
    /// End points the model was built with.
    pub fn ends(&self) -> &LineEnds {
        &self.ends
    }
    /// Nodes, fairlead first.
    pub fn nodes(&self) -> &[Node] {
        &self.nodes
    }
    /// Elements, fairlead first.
    pub fn elements(&self) -> &[Element] {
        &self.elements
    }
    /// Section of an element.
    pub fn section(&self, e: &Element) -> &Section {
        &self.sections[e.segment]
    }
    /// Total number of unknowns, constrained ones included.
    pub fn dof_count(&self) -> usize {
        self.dof_count
    }
    /// Half-bandwidth of the iteration matrix.
    pub(crate) fn half_bandwidth(&self) -> usize {
        self.half_bandwidth
    }
    /// Unstretched length (m).
    pub fn length_m(&self) -> f64 {
        self.length_m
    }
    /// The three prescribed DOFs of the fairlead position.
    pub(crate) fn fairlead_dofs(&self) -> std::ops::Range<usize> {
        0..3
    }
    /// The three fixed DOFs of the anchor position.
    pub(crate) fn anchor_dofs(&self) -> std::ops::Range<usize> {
        let d = self.nodes[self.nodes.len() - 1].dof;
        d..d + 3
    }
    /// Whether a DOF is prescribed (fairlead or anchor position).
    pub(crate) fn is_constrained(&self, dof: usize) -> bool {
        dof < 3 || self.anchor_dofs().contains(&dof)
    }
    /// Node owning a DOF.
    pub(crate) fn node_of_dof(&self, dof: usize) -> NodeId {
        NodeId(
            self.nodes
                .partition_point(|n| n.dof <= dof)
                .saturating_sub(1),
        )
    }
    /// Global DOF bases of an element's vector coefficients: (rᵢ, r'ᵢ, rⱼ, r'ⱼ) for a cable,
    /// (rᵢ, rⱼ) for a bar (the last two entries unused).
    pub(crate) fn element_dofs(&self, e: &Element) -> [usize; 4] {
        let a = self.nodes[e.nodes[0].0].dof;
        let b = self.nodes[e.nodes[1].0].dof;
        match e.kind {
            ElementKind::Cable => [a, a + 3, b, b + 3],
            ElementKind::Bar => [a, b, 0, 0],
        }
    }
    /// Position of node `n` in the state vector `q`.
    pub fn position(&self, q: &[f64], n: NodeId) -> Vector3<f64> {
        let d = self.nodes[n.0].dof;
        Vector3::new(q[d], q[d + 1], q[d + 2])
    }
    /// Element containing arc length `s` (m) and the local coordinate ξ ∈ [0, 1] there.
    pub(crate) fn locate(&self, arc_length_m: f64) -> Result<(ElementId, f64), LineError> {
        if !(0.0..=self.length_m).contains(&arc_length_m) {
            return Err(LineError::ArcLengthOutOfRange {
                line: self.name.clone(),
                arc_length_m,
                length_m: self.length_m,
            });
        }
        let k = self
            .elements
            .partition_point(|e| e.arc_start_m + e.length_m < arc_length_m)
            .min(self.elements.len() - 1);
        let e = &self.elements[k];
        Ok((
            ElementId(k),
            ((arc_length_m - e.arc_start_m) / e.length_m).clamp(0.0, 1.0),
        ))
    }

    /// State vector from node positions: gradients are set to the unit chord directions
    /// (averaged at interior nodes). `positions` has one entry per node.
    pub(crate) fn state_from_positions(
        &self,
        positions: &[Vector3<f64>],
    ) -> Result<Vec<f64>, LineError> {
        if positions.len() != self.nodes.len() {
            return Err(LineError::invalid(
                "start shape",
                format!("{} points", positions.len()),
                &format!("must give one point per node ({})", self.nodes.len()),
            ));
        }
        if let Some(i) = positions
            .iter()
            .position(|p| !p.iter().all(|c| c.is_finite()))
        {
            return Err(LineError::invalid(
                format!("start shape[{i}]"),
                "non-finite",
                "must be finite",
            ));
        }
        let mut q = vec![0.0; self.dof_count];
        let last = self.nodes.len() - 1;
        for (i, (node, p)) in self.nodes.iter().zip(positions).enumerate() {
            q[node.dof..node.dof + 3].copy_from_slice(p.as_slice());
            if node.has_gradient {
                let before = (i > 0)
                    .then(|| (p - positions[i - 1]).try_normalize(1e-12))
                    .flatten();
                let after = (i < last)
                    .then(|| (positions[i + 1] - p).try_normalize(1e-12))
                    .flatten();
                let t = match (before, after) {
                    (Some(a), Some(b)) => (a + b).try_normalize(1e-12).unwrap_or(b),
                    (Some(a), None) => a,
                    (None, Some(b)) => b,
                    (None, None) => Vector3::x(),
                };
                q[node.dof + 3..node.dof + 6].copy_from_slice(t.as_slice());
            }
        }
        Ok(q)
    }

    /// A simple geometric guess of the static shape: a straight suspended part from the fairlead
    /// to a touchdown point and a straight part on the seabed to the anchor, with the unstretched
    /// length conserved (or the straight chord when the line is taut).
    pub(crate) fn geometric_guess(&self) -> Vec<Vector3<f64>> {
        let f = self.ends.fairlead_m;
        let a = self.ends.anchor_m;
        let l = self.length_m;
        let mut dh = a - f;
        dh.z = 0.0;
        let x = dh.norm();
        let h = f.z - a.z;
        let chord = (x * x + h * h).sqrt();
        let e = dh.try_normalize(1e-12).unwrap_or_else(Vector3::x);
        // Touchdown at horizontal distance d from the fairlead: √(d² + h²) + (X − d) = L.
        let touchdown = if l <= chord || l <= x {
            a
        } else {
            let d = ((h * h - (l - x) * (l - x)) / (2.0 * (l - x))).clamp(0.0, x);
            Vector3::new(f.x + e.x * d, f.y + e.y * d, a.z)
        };
        let l1 = (touchdown - f).norm().min(l);
        self.nodes
            .iter()
            .map(|n| {
                let s = n.arc_length_m;
                if s <= l1 && l1 > 0.0 {
                    f + (touchdown - f) * (s / l1)
                } else if l > l1 {
                    touchdown + (a - touchdown) * ((s - l1) / (l - l1))
                } else {
                    a
                }
            })
            .collect()
    }
}
