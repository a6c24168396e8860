//! Periodic end conditions of the strand model (seed Sec. 2.3, Eqs. 12-13), applied by
//! elimination.
//!
//! The core wire is fully imposed by the section motion (ε, κ) ([`super::loading`]), so its
//! points C are known functions of the load, with positions x_C = c(z) and rotations R_C = R(z).
//! In every helical layer, wire 0 is the reference wire; its phase puts its z = 0 end at the
//! outer arc (θ = π/2, the profile's default phase).
//! - A reference-wire end at the outer arc, Q, is anchored: it keeps its place in the cross
//!   section and the section's rotation, x_Q = map(X_Q), Λ_Q = R(z_Q) (fully prescribed).
//! - Every other wire end P follows the point R of the reference wire at the same angle θ,
//!   relative to the core (Eq. 12), and the rotation of its cross section (Eq. 13):
//!   R(z_P)ᵀ (x_P − c(z_P)) = R(z_R)ᵀ (x_R − c(z_R)) + e₀,   Λ_P = R(z_P),
//!   where x_R = N_a x_a + N_b x_b interpolates the element of the reference wire containing R
//!   (linear in z between its nodes a, b) and e₀ is the reference mismatch of that interpolation
//!   (the chord sag, zero when R is a node), so that the reference configuration satisfies the
//!   constraint exactly. R is the point at angle θ_P nearest mid-length (inner layers, whose lay
//!   length is shorter than the model, have several) whose element has no eliminated end; when
//!   the model length is not exactly a lay length, the reference wire's far end is eliminated
//!   too, and its R, one lay length back, may lie just outside the model (linear extrapolation
//!   of the first element).
//!
//! Because C_P, C_R are prescribed, the constraint is affine in the unknowns:
//!   x_P = c(z_P) + A (N_a x_a + N_b x_b − c(z_R)) + R(z_P) e₀,   A = R(z_P) R(z_R)ᵀ,
//! so its linearisation δx_P = A (N_a δx_a + N_b δx_b) is exact: the eliminated system
//! K_red = Tᵀ K T, r_red = Tᵀ r (T the map from the reduced unknowns to the extended ones) is
//! the consistent tangent of the reduced problem and Newton keeps its quadratic convergence
//! (the seed's partial linearisation is not needed). No interior outer-arc point is coupled
//! (seed Sec. 2.3: it created artefacts).
//!
//! Assembly runs on the extended pattern (every unknown but the core, the anchored ends and the
//! end rotations, P translations included) and is reduced entry by entry with a plan computed
//! once ([`PeriodicEnds::reduce`]). Units: m, rad.

use nalgebra::{Matrix3, Vector3};

use super::loading::SectionMotion;
use super::mesh::StrandMesh;
use super::model::StrandModelError;
use super::profile::Strand;
use crate::beam::frame::{DofMap, FrameState, NodeId, NODE_DOFS};
use crate::linalg::{Equation, PatternError, SparsePattern, Storage};

/// Which DOFs of every node are prescribed: the core, the anchored ends, the end rotations.
pub type Prescription = Vec<[bool; NODE_DOFS]>;

/// One eliminated wire end P (module docs).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct EndConstraint {
    /// The node P.
    pub node: usize,
    /// Its reference axial coordinate (m).
    pub z_p_m: f64,
    /// Reference axial coordinate of R (m).
    pub z_r_m: f64,
    /// Nodes a, b of the reference-wire element containing R.
    pub masters: [usize; 2],
    /// Interpolation weights N_a, N_b.
    pub weights: [f64; 2],
    /// Reference mismatch e₀ in the section frame (m).
    pub offset_m: Vector3<f64>,
}

impl EndConstraint {
    /// A = R(z_P) R(z_R)ᵀ under `motion`.
    pub fn transfer(&self, motion: &SectionMotion) -> Matrix3<f64> {
        motion.rotation(self.z_p_m) * motion.rotation(self.z_r_m).transpose()
    }

    /// Position of P that satisfies the constraint for the current master positions.
    pub fn position(&self, motion: &SectionMotion, positions: &[Vector3<f64>]) -> Vector3<f64> {
        let x_r = self.weights[0] * positions[self.masters[0]]
            + self.weights[1] * positions[self.masters[1]];
        motion.axis_point(self.z_p_m)
            + self.transfer(motion) * (x_r - motion.axis_point(self.z_r_m))
            + motion.rotation(self.z_p_m) * self.offset_m
    }
}

/// The wire ends of a strand mesh: anchored ends, constraints and the DOF prescription.
#[derive(Clone, Debug, PartialEq)]
pub struct EndLayout {
    /// Anchored ends Q (fully prescribed).
    pub anchored: Vec<usize>,
    /// Eliminated ends P.
    pub constraints: Vec<EndConstraint>,
    /// Prescribed DOFs per node (core included).
    pub prescription: Prescription,
}

/// Angle tolerance for an end to count as lying at the outer arc (rad).
const OUTER_ARC_TOLERANCE_RAD: f64 = 1e-6;

/// Anchored ends and constraints of `mesh` (module docs).
pub fn end_layout(strand: &Strand, mesh: &StrandMesh) -> Result<EndLayout, StrandModelError> {
    let wires = strand.wires();
    let length = strand.model_length_m;
    let mut prescription: Prescription = mesh
        .nodes
        .iter()
        .map(|n| [n.wire.0 == 0; NODE_DOFS])
        .collect();
    let mut anchored = Vec::new();
    let mut constraints = Vec::new();
    let at_outer_arc = |theta: f64| {
        let d = (theta - std::f64::consts::FRAC_PI_2).rem_euclid(2.0 * std::f64::consts::PI);
        d.min(2.0 * std::f64::consts::PI - d) < OUTER_ARC_TOLERANCE_RAD
    };
    for k in 0..strand.layers.len() {
        let reference = strand.first_wire_of_layer(k);
        let ref_nodes = mesh.wire_nodes[reference.0].clone();
        if ref_nodes.len() < 2 {
            continue;
        }
        let helix = wires[reference.0].helix;
        // the reference wire's ends at the outer arc are anchored; its other end, if any, is
        // eliminated like every other wire end and may not serve as a master point
        let free_ends: Vec<usize> = [ref_nodes.start, ref_nodes.end - 1]
            .into_iter()
            .filter(|&n| !at_outer_arc(helix.angle(mesh.nodes[n].z_m)))
            .collect();
        let ref_elements: Vec<(usize, usize)> = (ref_nodes.start..ref_nodes.end - 1)
            .map(|i| (i, i + 1))
            .collect();
        for w in wires.iter().filter(|w| w.layer == Some(k)) {
            let range = mesh.wire_nodes[w.id.0].clone();
            if range.len() < 2 {
                continue;
            }
            for node in [range.start, range.end - 1] {
                let z_p = mesh.nodes[node].z_m;
                let theta = w.helix.angle(z_p);
                if w.id == reference && !free_ends.contains(&node) {
                    anchored.push(node);
                    prescription[node] = [true; NODE_DOFS];
                    continue;
                }
                let master =
                    reference_point(mesh, &helix, &ref_elements, &free_ends, theta, length).ok_or(
                        StrandModelError::InvalidParameter {
                            field: "model_length_m",
                            value: length,
                            reason: "a wire end has no admissible point at its angle on the \
                                 reference wire of its layer",
                        },
                    )?;
                let (z_r, (a, b), weights) = master;
                let x_r = weights[0] * mesh.nodes[a].position + weights[1] * mesh.nodes[b].position;
                let x_p = mesh.nodes[node].position;
                let offset_m =
                    (x_p - Vector3::new(0.0, 0.0, z_p)) - (x_r - Vector3::new(0.0, 0.0, z_r));
                prescription[node] = [false, false, false, true, true, true];
                constraints.push(EndConstraint {
                    node,
                    z_p_m: z_p,
                    z_r_m: z_r,
                    masters: [a, b],
                    weights,
                    offset_m,
                });
            }
        }
    }
    for c in &constraints {
        if c.masters
            .iter()
            .any(|m| constraints.iter().any(|d| d.node == *m))
        {
            return Err(StrandModelError::InvalidParameter {
                field: "model_length_m",
                value: length,
                reason: "a periodic master point lies on an eliminated wire end",
            });
        }
    }
    Ok(EndLayout {
        anchored,
        constraints,
        prescription,
    })
}

/// The point R of the reference wire (`helix`, elements `elements` in increasing z) at angle
/// `theta` (mod 2π) nearest mid-length among the admissible ones: its element's nodes must not
/// be eliminated ends (`free_ends`), and it may lie up to one element beyond the wire's ends
/// (linear extrapolation: a model length slightly shorter than the lay length puts the point
/// matching the far end just before z = 0). Returns (z_R, element nodes, weights N_a, N_b).
fn reference_point(
    mesh: &StrandMesh,
    helix: &super::helix::Helix,
    elements: &[(usize, usize)],
    free_ends: &[usize],
    theta: f64,
    length: f64,
) -> Option<(f64, (usize, usize), [f64; 2])> {
    let rate = helix.rate_rad_per_m;
    if rate == 0.0 || elements.is_empty() {
        return None;
    }
    let period = (2.0 * std::f64::consts::PI / rate).abs();
    let z0 = (theta - helix.angle(0.0)) / rate;
    let z = |n: usize| mesh.nodes[n].z_m;
    let (first, last) = (elements[0], elements[elements.len() - 1]);
    let (lo, hi) = (2.0 * z(first.0) - z(first.1), 2.0 * z(last.1) - z(last.0));
    let turns = (length / period).ceil() as i64 + 2;
    let n0 = (-z0 / period).round() as i64;
    let mut best: Option<(f64, (usize, usize), [f64; 2])> = None;
    for n in (n0 - turns)..=(n0 + turns) {
        let z_r = z0 + n as f64 * period;
        if !(lo..=hi).contains(&z_r) {
            continue;
        }
        let element = elements
            .iter()
            .copied()
            .find(|&(a, b)| z(a) <= z_r && z_r <= z(b))
            .unwrap_or(if z_r < z(first.0) { first } else { last });
        if free_ends.contains(&element.0) || free_ends.contains(&element.1) {
            continue;
        }
        let (za, zb) = (z(element.0), z(element.1));
        let nb = if zb > za { (z_r - za) / (zb - za) } else { 0.0 };
        let better = best.is_none_or(|(zb_best, _, _)| {
            (z_r - 0.5 * length).abs() < (zb_best - 0.5 * length).abs()
        });
        if better {
            best = Some((z_r, element, [1.0 - nb, nb]));
        }
    }
    best
}

/// How an extended equation enters the reduced system: (reduced equation, coefficient slot).
type Expansion = Vec<(usize, usize)>;

/// The elimination of the eliminated ends: reduced pattern and the reduction plan.
#[derive(Clone, Debug)]
pub struct PeriodicEnds {
    /// Anchored ends, eliminated ends.
    pub layout: EndLayout,
    /// Pattern of the extended system (assembly).
    pub extended: SparsePattern,
    /// Expansion of every extended equation.
    expansions: Vec<Expansion>,
    /// Reduced nonzero of every extended nonzero when both its equations map one to one.
    direct: Vec<u32>,
    /// Other extended nonzeros: (extended nonzero, reduced nonzero, row slot, column slot).
    extra: Vec<(u32, u32, u32, u32)>,
}

/// Coefficient slot of constraint `d`, master side `s`, P component `m`, master component `c`.
fn slot(d: usize, s: usize, m: usize, c: usize) -> usize {
    1 + 18 * d + 9 * s + 3 * m + c
}

impl PeriodicEnds {
    /// Builds the elimination for `layout`, the extended DOF map and the extended element
    /// equations; returns it with the reduced pattern.
    pub fn new(
        layout: EndLayout,
        dofs: &DofMap,
        element_equations: &[Vec<Equation>],
    ) -> Result<(Self, SparsePattern), PatternError> {
        let extended = SparsePattern::new(dofs.free_count(), Storage::Full, element_equations)?;
        let n_ext = dofs.free_count();
        // dependent extended equations: (constraint, component)
        let mut dependent = vec![None; n_ext];
        for (d, c) in layout.constraints.iter().enumerate() {
            for m in 0..3 {
                if let Some(e) = dofs.equation(NodeId(c.node), m).index() {
                    dependent[e] = Some((d, m));
                }
            }
        }
        let mut reduced_of = vec![usize::MAX; n_ext];
        let mut n_red = 0;
        for (e, dep) in dependent.iter().enumerate() {
            if dep.is_none() {
                reduced_of[e] = n_red;
                n_red += 1;
            }
        }
        let expansions: Vec<Expansion> = (0..n_ext)
            .map(|e| match dependent[e] {
                None => vec![(reduced_of[e], 0)],
                Some((d, m)) => {
                    let c = &layout.constraints[d];
                    let mut out = Vec::with_capacity(6);
                    for (s, &node) in c.masters.iter().enumerate() {
                        for comp in 0..3 {
                            if let Some(me) = dofs.equation(NodeId(node), comp).index() {
                                out.push((reduced_of[me], slot(d, s, m, comp)));
                            }
                        }
                    }
                    out
                }
            })
            .collect();
        let reduced_elements: Vec<Vec<Equation>> = element_equations
            .iter()
            .map(|eqs| {
                let mut out: Vec<Equation> = Vec::new();
                for eq in eqs {
                    match eq.index() {
                        None => out.push(*eq),
                        Some(e) => {
                            for &(r, _) in &expansions[e] {
                                let q = Equation::free(r).expect("reduced equation fits");
                                if !out.contains(&q) {
                                    out.push(q);
                                }
                            }
                        }
                    }
                }
                out
            })
            .collect();
        let reduced = SparsePattern::new(n_red, Storage::Full, &reduced_elements)?;
        let locate = |row: usize, col: usize| -> u32 {
            let (cp, ri) = (reduced.col_ptr(), reduced.row_idx());
            let rows = &ri[cp[col]..cp[col + 1]];
            let k = rows
                .binary_search(&row)
                .expect("reduced pattern holds every expanded entry");
            (cp[col] + k) as u32
        };
        let mut direct = vec![u32::MAX; extended.nnz()];
        let mut extra = Vec::new();
        let (cp, ri) = (extended.col_ptr(), extended.row_idx());
        for col in 0..n_ext {
            for k in cp[col]..cp[col + 1] {
                let row = ri[k];
                let (er, ec) = (&expansions[row], &expansions[col]);
                if dependent[row].is_none() && dependent[col].is_none() {
                    direct[k] = locate(er[0].0, ec[0].0);
                    continue;
                }
                for &(r, sr) in er {
                    for &(c, sc) in ec {
                        extra.push((k as u32, locate(r, c), sr as u32, sc as u32));
                    }
                }
            }
        }
        Ok((
            Self {
                layout,
                extended,
                expansions,
                direct,
                extra,
            },
            reduced,
        ))
    }

    /// Coefficients of every slot under `motion` (slot 0 is 1).
    pub fn coefficients(&self, motion: &SectionMotion, out: &mut Vec<f64>) {
        out.clear();
        out.resize(1 + 18 * self.layout.constraints.len(), 0.0);
        out[0] = 1.0;
        for (d, c) in self.layout.constraints.iter().enumerate() {
            let a = c.transfer(motion);
            for s in 0..2 {
                for m in 0..3 {
                    for comp in 0..3 {
                        out[slot(d, s, m, comp)] = c.weights[s] * a[(m, comp)];
                    }
                }
            }
        }
    }

    /// r_red = Tᵀ r_ext and, if given, K_red = Tᵀ K_ext T (outputs zeroed by the caller).
    pub fn reduce(
        &self,
        coefficients: &[f64],
        residual: &[f64],
        reduced_residual: &mut [f64],
        tangent: Option<(&[f64], &mut [f64])>,
    ) {
        for (e, exp) in self.expansions.iter().enumerate() {
            for &(r, s) in exp {
                reduced_residual[r] += coefficients[s] * residual[e];
            }
        }
        if let Some((values, reduced)) = tangent {
            for (k, &t) in self.direct.iter().enumerate() {
                if t != u32::MAX {
                    reduced[t as usize] += values[k];
                }
            }
            for &(k, t, sr, sc) in &self.extra {
                reduced[t as usize] +=
                    coefficients[sr as usize] * coefficients[sc as usize] * values[k as usize];
            }
        }
    }

    /// Reduced equation of an independent extended equation (`None` for a dependent one).
    pub fn reduced_equation(&self, extended: usize) -> Option<usize> {
        match self.expansions.get(extended)?.as_slice() {
            [(r, 0)] => Some(*r),
            _ => None,
        }
    }

    /// Expands a reduced increment onto the extended equations (dependent entries 0: the
    /// eliminated ends are placed exactly by [`Self::enforce`] afterwards).
    pub fn expand(&self, reduced: &[f64], extended: &mut [f64]) {
        for (e, exp) in self.expansions.iter().enumerate() {
            extended[e] = match exp.as_slice() {
                [(r, 0)] => reduced[*r],
                _ => 0.0,
            };
        }
    }

    /// Places the eliminated ends on their constraint and sets their rotations to the section's.
    pub fn enforce(&self, motion: &SectionMotion, state: &mut FrameState) {
        for c in &self.layout.constraints {
            let x = c.position(motion, &state.positions);
            state.positions[c.node] = x;
            state.rotations[c.node] = motion.rotation(c.z_p_m);
        }
    }
}

#[cfg(test)]
#[path = "periodic_tests.rs"]
mod tests;
