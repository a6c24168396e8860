//! The strand finite-element model (the paper's Sec. 2.2): every wire a chain of
//! corotational beams on the mesh nodes ([`super::mesh`]), a small-sliding frictional contact
//! element (the paper's Eqs. 1-11, [`crate::contact`]) at every detected contact, the core wire's
//! nodes fully imposed from (ε, κ) ([`super::loading`]) and the helical wires' end nodes tied to
//! the core end sections by penalty (`super::ends`, [`EndKind::PenaltyTies`]) or to the
//! reference wires by the periodic constraints of `super::periodic` ([`EndKind::Periodic`]).
//!
//! Frame nodes are the mesh nodes (same indices), frame elements the mesh elements. The global
//! pattern (full storage: the frictional contact tangent is not symmetric) holds, in order, the
//! frame elements, the contact elements and the end ties. Core DOFs are eliminated (prescribed).
//!
//! Contact radii: the outer wire of each pair is given an initial interference
//! `initial_interference_m` (a few nm) so that every contact is closed, with a normal
//! stiffness, in the reference configuration where the exact helices just touch (g_N = 0).
//! Units: m, N, rad.

use nalgebra::Vector3;

use super::contacts::{find_contacts, ContactKind, ContactSearchParameters};
use super::ends::EndTie;
use super::mesh::{build_mesh, MeshParameters, StrandMesh};
use super::periodic::{end_layout, PeriodicEnds};
use super::profile::Strand;
use crate::beam::frame::{BeamFrame, DofMap, NodeId, NODE_DOFS};
use crate::beam::section::BeamSection;
use crate::contact::{
    ContactHistory, ContactLaws, ContactPair, ContactParameters, NodeKinematics, NormalLaw,
    TangentialLaw,
};
use crate::linalg::{
    Equation, FactorPrecision, GmresParams, LinalgError, SparsePattern, SplitSolver, Storage,
};

pub use super::error::StrandModelError;

/// GMRES iterations a reused preconditioner may cost beyond a fresh one before the solver
/// refactorises ([`GmresParams::reuse_margin`]): one LDLᵀ factorisation costs about as much as
/// 20 preconditioned GMRES iterations on both the 1+6+1 and the six-layer strand
/// (`studies/src/bin/linear_solver_study.rs`), so ten extra iterations per solve are cheaper
/// than refactorising as long as the pattern of stick and slip holds.
pub const PRECONDITIONER_REUSE_MARGIN: usize = 10;

/// How the helical wire ends are held.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
pub enum EndKind {
    /// Penalty ties to the core end sections (the 1+6+1 benchmark, the paper's Sec. 2.2).
    #[default]
    PenaltyTies,
    /// Periodic multi-point constraints by elimination (the paper's Sec. 2.3, Eqs. 12-13): the far
    /// ends follow the start ends in position and the section in rotation.
    Periodic,
    /// As [`EndKind::Periodic`], with the far ends following the start ends in rotation too
    /// (`super::periodic`): no seam where the far ends are tied.
    PeriodicRotations,
}

/// Model-building parameters.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct StrandModelParameters {
    /// Meshing.
    pub mesh: MeshParameters,
    /// Contact detection.
    pub search: ContactSearchParameters,
    /// Contact laws (the friction coefficient and elastic constants are the strand's).
    pub contact: ContactLaws,
    /// End-tie translational penalty as a multiple of the wire's EA / (shortest element).
    pub end_penalty_factor: f64,
    /// Initial interference given to every contact (m).
    pub initial_interference_m: f64,
    /// End conditions of the helical wires.
    pub ends: EndKind,
}

impl Default for StrandModelParameters {
    fn default() -> Self {
        Self {
            mesh: MeshParameters::default(),
            search: ContactSearchParameters::default(),
            contact: ContactLaws::default(),
            end_penalty_factor: 1e3,
            initial_interference_m: 1e-9,
            ends: EndKind::PenaltyTies,
        }
    }
}

impl StrandModelParameters {
    /// The defaults with a penalty normal law of stiffness ε_N (N/m), an elastic-slip
    /// regularised Coulomb law with elastic slip γ_e (m), and the given end conditions: the
    /// contact regularisation of the paper's Sec. 2.2 (its 'vs_analytical' set is ε_N = 2e8 N/m,
    /// γ_e = 1e-7 m).
    pub fn penalty_contact(
        normal_penalty_n_per_m: f64,
        elastic_slip_m: f64,
        ends: EndKind,
    ) -> Self {
        Self {
            contact: ContactLaws {
                normal: NormalLaw::Penalty {
                    stiffness_n_per_m: normal_penalty_n_per_m,
                },
                tangential: TangentialLaw::ElasticSlip { elastic_slip_m },
            },
            ends,
            ..Self::default()
        }
    }

    /// The defaults with the contact-mechanics laws ([`ContactLaws::contact_mechanics`]: Hertz
    /// for the crossings at their own angle, the line law for the line contacts of layer 0 on
    /// the core, Cattaneo–Mindlin with memory) and the given end conditions.
    pub fn contact_mechanics(ends: EndKind) -> Self {
        Self {
            contact: ContactLaws::contact_mechanics(),
            ends,
            ..Self::default()
        }
    }

    /// Checks the model's own fields (mesh, search and contact are checked where used).
    pub fn validated(self) -> Result<Self, StrandModelError> {
        if !(self.end_penalty_factor > 0.0 && self.end_penalty_factor.is_finite()) {
            return Err(StrandModelError::InvalidParameter {
                field: "end_penalty_factor",
                value: self.end_penalty_factor,
                reason: "must be finite and > 0",
            });
        }
        if !(self.initial_interference_m >= 0.0 && self.initial_interference_m.is_finite()) {
            return Err(StrandModelError::InvalidParameter {
                field: "initial_interference_m",
                value: self.initial_interference_m,
                reason: "must be finite and >= 0",
            });
        }
        Ok(self)
    }
}

/// Length of wire each line contact (`ContactKind::CoreLine`) of an outer wire stands for, by
/// wire index: the wire's arc length over the model length divided by its number of line
/// contact points (they are spaced uniformly in arc length, `super::contacts`); 0 for a wire
/// without line contacts.
fn line_contact_lengths(strand: &Strand, mesh: &StrandMesh) -> Vec<f64> {
    let wires = strand.wires();
    let mut counts = vec![0usize; wires.len()];
    for mc in &mesh.contacts {
        if mc.kind == ContactKind::CoreLine {
            counts[mesh.nodes[mc.nodes[1].0].wire.0] += 1;
        }
    }
    wires
        .iter()
        .zip(&counts)
        .map(|(w, &n)| {
            if n == 0 {
                return 0.0;
            }
            let t = w.helix.tangent(0.0);
            let cos_lay = (t.z / t.norm()).abs();
            strand.model_length_m / cos_lay / n as f64
        })
        .collect()
}

/// Immutable strand model.
#[derive(Debug, Clone)]
pub struct StrandModel {
    /// Resolved geometry.
    pub strand: Strand,
    /// Mesh (nodes, wire elements, contact elements).
    pub mesh: StrandMesh,
    /// Beam frame on the mesh nodes.
    pub frame: BeamFrame,
    /// DOF numbering (core nodes prescribed).
    pub dofs: DofMap,
    /// Global pattern of the solved system: frame elements, contacts, ties (reduced by the
    /// periodic elimination when there is one).
    pub pattern: SparsePattern,
    /// Periodic end constraints and their elimination, if the ends are periodic.
    pub periodic: Option<PeriodicEnds>,
    /// Contact elements, in mesh contact order.
    pub contacts: Vec<ContactPair>,
    /// Their initial histories.
    pub initial_histories: Vec<ContactHistory>,
    /// End ties.
    pub ties: Vec<EndTie>,
    /// Wire sections, by wire index.
    pub sections: Vec<BeamSection>,
    /// Whether each node is fully prescribed (core, anchored periodic ends).
    pub prescribed: Vec<bool>,
    /// Line-search merit weight of every solved equation: 1 for a force, 1/r² for a moment of
    /// a wire of radius r (a moment imbalance M weighs like the force M/r at the wire surface,
    /// where the contacts act).
    pub merit_weights: Vec<f64>,
    /// The contact laws as the contacts use them: the given laws with the friction coefficient
    /// and elastic constants of the strand.
    pub contact_parameters: ContactParameters,
}

impl StrandModel {
    /// Whether a history run starts each sub-step from an earlier one's wire motion by default
    /// ([`super::history::HistoryOptions::segment_predictor`]): under the contact-mechanics
    /// tangential laws, whose compliance turns over the micrometre slips of a sub-step, so that
    /// Newton iterations started from the plane sections cross many of the contacts'
    /// stick-slip transitions (six-layer strand, first 100 s of the severe history: 630 Newton
    /// iterations against 848, the history 27 % faster); not under the elastic-slip law,
    /// whose iterations it does not reduce (387 against 391 there), so that its figures stay
    /// as they are (docs/notes/2026-12-05-secant-predictor.md).
    pub fn predicts_from_last_segment(&self) -> bool {
        !matches!(
            self.contact_parameters.tangential,
            TangentialLaw::ElasticSlip { .. }
        )
    }

    /// Builds the model of `strand`.
    pub fn new(strand: &Strand, params: &StrandModelParameters) -> Result<Self, StrandModelError> {
        let params = params.validated()?;
        let contacts_found = find_contacts(strand, &params.search)?;
        let mesh = build_mesh(strand, &contacts_found, &params.mesh)?;
        let wires = strand.wires();
        let (e, nu) = (strand.young_modulus_pa, strand.poisson_ratio);
        let sections = wires
            .iter()
            .map(|w| {
                BeamSection::circle(w.radius_m, e, nu).map_err(|source| StrandModelError::Section {
                    wire: w.id.0,
                    source,
                })
            })
            .collect::<Result<Vec<_>, _>>()?;
        let mut frame = BeamFrame::new(mesh.nodes.iter().map(|n| n.position).collect());
        for el in &mesh.elements {
            let a = &mesh.nodes[el.nodes[0].0];
            let w = &wires[el.wire.0];
            // local y: radial direction of a helical wire, x for the straight core
            let hint = if w.layer.is_some() {
                Vector3::new(a.position.x, a.position.y, 0.0)
            } else {
                Vector3::x()
            };
            frame.add_element(
                [NodeId(el.nodes[0].0), NodeId(el.nodes[1].0)],
                &hint,
                &sections[el.wire.0],
            )?;
        }
        let layout = match params.ends {
            EndKind::PenaltyTies => None,
            EndKind::Periodic => Some(end_layout(strand, &mesh, false)?),
            EndKind::PeriodicRotations => Some(end_layout(strand, &mesh, true)?),
        };
        let prescription: Vec<[bool; NODE_DOFS]> = match &layout {
            Some(l) => l.prescription.clone(),
            None => mesh
                .nodes
                .iter()
                .map(|n| [n.wire.0 == 0; NODE_DOFS])
                .collect(),
        };
        let prescribed: Vec<bool> = prescription.iter().map(|p| p.iter().all(|&b| b)).collect();
        let constraints: Vec<(NodeId, [bool; NODE_DOFS])> = prescription
            .iter()
            .enumerate()
            .filter(|(_, p)| p.iter().any(|&b| b))
            .map(|(i, p)| (NodeId(i), *p))
            .collect();
        let dofs = DofMap::new(frame.node_count(), &constraints)?;

        let contact_params =
            ContactParameters::with_material(params.contact, strand.friction_coefficient, e, nu);
        contact_params
            .validate()
            .map_err(|source| StrandModelError::Contact {
                contact: 0,
                node1: 0,
                node2: 0,
                source,
            })?;
        let line_lengths = line_contact_lengths(strand, &mesh);
        let mut contacts = Vec::with_capacity(mesh.contacts.len());
        let mut initial_histories = Vec::with_capacity(mesh.contacts.len());
        for (c, mc) in mesh.contacts.iter().enumerate() {
            let [a, b] = mc.nodes;
            let (na, nb) = (&mesh.nodes[a.0], &mesh.nodes[b.0]);
            let (ra, rb) = (wires[na.wire.0].radius_m, wires[nb.wire.0].radius_m);
            // The contact-mechanics family: line contacts of layer 0 on the core get the line
            // law over their share of the wire, crossings Hertz at their own angle.
            let mut own = contact_params;
            if contact_params.normal == NormalLaw::ContactMechanics
                && mc.kind == ContactKind::CoreLine
            {
                own.normal = NormalLaw::Line {
                    length_m: line_lengths[nb.wire.0],
                };
            }
            let (pair, history) = ContactPair::new(
                &own,
                ra,
                rb + params.initial_interference_m,
                &NodeKinematics::at(na.position),
                &na.tangent,
                &NodeKinematics::at(nb.position),
                &nb.tangent,
            )
            .map_err(|source| StrandModelError::Contact {
                contact: c,
                node1: a.0,
                node2: b.0,
                source,
            })?;
            contacts.push(pair);
            initial_histories.push(history);
        }

        let h_min = mesh.stats.min_element_length_m.max(1e-12);
        let mut ties = Vec::new();
        for (w, range) in wires.iter().zip(mesh.wire_nodes.iter()) {
            if w.layer.is_none() || range.is_empty() || layout.is_some() {
                continue;
            }
            let s = &sections[w.id.0];
            let ku = params.end_penalty_factor * s.young_pa * s.area_m2 / h_min;
            let kr = params.end_penalty_factor * s.young_pa * s.inertia_y_m4 / h_min;
            for node in [range.start, range.end - 1] {
                let p = mesh.nodes[node].position;
                let radial = Vector3::new(p.x, p.y, 0.0);
                let norm = radial.norm();
                if norm <= 0.0 {
                    return Err(StrandModelError::InvalidParameter {
                        field: "helix_radius_m",
                        value: norm,
                        reason: "a helical wire node lies on the strand axis",
                    });
                }
                ties.push(EndTie {
                    node,
                    reference: p,
                    radial: radial / norm,
                    translation_penalty_n_per_m: ku,
                    rotation_penalty_nm_per_rad: kr,
                });
            }
        }

        let mut element_eqs: Vec<Vec<Equation>> = dofs
            .element_equations(&frame)
            .into_iter()
            .map(|e| e.to_vec())
            .collect();
        let dofs_ref = &dofs;
        let node_eqs = |n: usize| (0..NODE_DOFS).map(move |k| dofs_ref.equation(NodeId(n), k));
        for mc in &mesh.contacts {
            element_eqs.push(
                node_eqs(mc.nodes[0].0)
                    .chain(node_eqs(mc.nodes[1].0))
                    .collect(),
            );
        }
        for t in &ties {
            element_eqs.push(node_eqs(t.node).collect());
        }
        let (pattern, periodic) = match layout {
            None => (
                SparsePattern::new(dofs.free_count(), Storage::Full, &element_eqs)?,
                None,
            ),
            Some(l) => {
                let (p, reduced) = PeriodicEnds::new(l, &dofs, &element_eqs)?;
                (reduced, Some(p))
            }
        };
        let mut merit_weights = vec![1.0; pattern.size()];
        for (n, node) in mesh.nodes.iter().enumerate() {
            let r = wires[node.wire.0].radius_m;
            for k in 3..NODE_DOFS {
                let Some(e) = dofs.equation(NodeId(n), k).index() else {
                    continue;
                };
                let solved = match &periodic {
                    None => Some(e),
                    Some(p) => p.reduced_equation(e),
                };
                if let Some(i) = solved {
                    merit_weights[i] = 1.0 / (r * r);
                }
            }
        }
        Ok(Self {
            strand: strand.clone(),
            mesh,
            frame,
            dofs,
            pattern,
            periodic,
            contacts,
            initial_histories,
            ties,
            sections,
            prescribed,
            merit_weights,
            contact_parameters: contact_params,
        })
    }

    /// Pattern the elements are assembled on: the extended one of the periodic elimination,
    /// else [`Self::pattern`].
    pub(crate) fn assembly_pattern(&self) -> &SparsePattern {
        self.periodic
            .as_ref()
            .map_or(&self.pattern, |p| &p.extended)
    }

    /// The linear solver of the model's Newton iterations: LDLᵀ of the tangent's symmetric
    /// surrogate preconditioning GMRES on the full (frictional, non-symmetric) tangent
    /// ([`SplitSolver`]), the factorisation kept over later tangents while GMRES needs at most
    /// [`PRECONDITIONER_REUSE_MARGIN`] iterations more than with a fresh one; symbolic
    /// analysis of [`Self::pattern`] done here, once.
    pub fn linear_solver(&self) -> Result<SplitSolver, LinalgError> {
        self.linear_solver_threads(1, FactorPrecision::Double)
    }

    /// [`Self::linear_solver`] with its LDLᵀ factorisation and solves on `threads` threads and
    /// the factor applied in `precision`.
    pub(crate) fn linear_solver_threads(
        &self,
        threads: usize,
        precision: FactorPrecision,
    ) -> Result<SplitSolver, LinalgError> {
        self.linear_solver_with(
            GmresParams {
                reuse_margin: Some(PRECONDITIONER_REUSE_MARGIN),
                preconditioner_precision: precision,
                ..GmresParams::default()
            },
            threads,
        )
    }

    /// [`Self::linear_solver`] with other GMRES settings, its LDLᵀ factorisation on `threads`
    /// threads.
    pub fn linear_solver_with(
        &self,
        params: GmresParams,
        threads: usize,
    ) -> Result<SplitSolver, LinalgError> {
        let par = if threads > 1 {
            faer::Par::rayon(threads)
        } else {
            faer::Par::Seq
        };
        SplitSolver::with_parallelism(&self.pattern, params, par)
    }

    /// Pattern element index of contact `c`.
    pub(crate) fn contact_pattern_element(&self, c: usize) -> usize {
        self.frame.elements().len() + c
    }

    /// Pattern element index of tie `t`.
    pub(crate) fn tie_pattern_element(&self, t: usize) -> usize {
        self.frame.elements().len() + self.contacts.len() + t
    }
}
