//! Periodic end conditions of the strand model (the paper's Sec. 2.3, Eqs. 12-13), applied by
//! elimination.
//!
//! The core wire is fully imposed by the section motion (ε, κ) ([`super::loading`]), so its
//! points C are known functions of the load, with positions x_C = c(z) and rotations R_C = R(z).
//! Under a constant (ε, κ) the state of a wire point depends only on its layer and its angle θ from
//! the bending axis (the paper's Sec. 2.3): the relative position R(z)ᵀ (x − c(z)) of every point
//! at the same θ in a layer is the same up to the rotation about the strand axis that carries one
//! angle to the other. In every helical layer, wire 0 is the reference wire; its phase puts its
//! z = 0 end at the outer arc (θ = π/2, the profile's default phase).
//! - A reference-wire end at the outer arc, Q, is anchored: it keeps its place in the cross
//!   section and the section's rotation, x_Q = map(X_Q), Λ_Q = R(z_Q) (fully prescribed).
//! - Every other far end P (z = L) follows the start ends S (z = 0) of its layer at the angles
//!   around its own, relative to the core (Eq. 12), and the rotation of its cross section
//!   (Eq. 13):
//!   R(z_P)ᵀ (x_P − c(z_P)) = Σ_S w_S T(θ_P − θ_S) R(z_S)ᵀ (x_S − c(z_S)) + e₀,   Λ_P = R(z_P),
//!   with T(φ) the rotation by φ about the strand axis, w_S the weights of the cubic
//!   interpolation in angle through the four start ends nearest θ_P ([`angular_interpolation`]),
//!   and e₀ the round-off of the reference configuration.
//! - With [`EndKind::PeriodicRotations`](super::model::EndKind::PeriodicRotations), the far
//!   end's rotation follows the start ends' instead of the section's: with the wire rotations
//!   relative to their section, Λ_S = exp(φ̂_S) R(z_S),
//!   Λ_P = exp(φ̂_P) R(z_P),   φ_P = Σ_S w_S A_S φ_S
//!   (A_S below). For a single start end at P's angle this is the transported rotation exactly,
//!   Λ_P = A_S Λ_S T(θ_P − θ_S)ᵀ. Eq. 13 holds every far end at the section's rotation while its
//!   start end turns freely; on the six-layer paper strand that raises the largest slip ranges
//!   of interfaces 2-5 within 50 mm of the seam by 19-44 % over the rest of the model, and the
//!   rotation tie by 1-7 % (`docs/notes/2026-11-29-seam-rotation-ties.md`).
//!
//! Why start ends and not, as in the paper, the point R of the reference wire at the angle θ_P:
//! the tie's reaction is the end force of P's wire (the wire tension), and a tie to an interior
//! point of the reference wire applies it there as a point load that the infinite strand does
//! not have. Where a far end and a start end of a wire share their angle and their point R, the
//! two loads cancel; in a layer whose lay length does not divide the model length (the inner
//! five layers of the paper strand) they do not, and the six-layer model in pure tension
//! carried reference-wire forces from −3.1 to +7.5 kN against 2.3-2.9 kN in the other wires.
//! A start end is a cut like P, so the reaction goes where the wire continues. With weights
//! that sum to 1 and every far end of a layer at the same angle from its nearest start ends,
//! every start end receives the full end force once: pure tension is carried over exactly,
//! and in bending the error is that of the cubic interpolation of the sin θ stick field,
//! O((2π/n)⁴) for a layer of n wires. A layer that closes on itself over the model length
//! (far end at a start end's angle: the outer layer, model length = its lay length) ties
//! every far end to the start end at its angle, the paper's tie.
//!
//! Because C_P, C_S are prescribed, the constraint is affine in the unknowns:
//!   x_P = c(z_P) + Σ_S w_S A_S (x_S − c(z_S)) + R(z_P) e₀,   A_S = R(z_P) T(θ_P − θ_S) R(z_S)ᵀ,
//! so its linearisation δx_P = Σ_S w_S A_S δx_S is exact: the eliminated system
//! K_red = Tᵀ K T, r_red = Tᵀ r (T the map from the reduced unknowns to the extended ones) is
//! the consistent tangent of the reduced problem, symmetric where the contact tangent is, and
//! Newton keeps its quadratic convergence (the paper's partial linearisation is not needed). No
//! interior outer-arc point is coupled (the paper's Sec. 2.3: it created artefacts). The rotation
//! tie is not affine: its spins are δθ_P = Σ_S H(φ_P) w_S A_S H(φ_S)⁻¹ δθ_S (H the tangent
//! operator of the exponential map, [`tangent_operator`]), and Tᵀ K T leaves out the term of
//! its second derivative times the far ends' moment residuals, which are small beside the
//! wires' bending stiffness.
//!
//! Assembly runs on the extended pattern (every unknown but the core, the anchored ends and,
//! under Eq. 13, the far ends' rotations; P translations included) and is reduced entry by entry with a plan computed
//! once ([`PeriodicEnds::reduce`]). Units: m, rad.

use nalgebra::{Matrix3, Vector3};

use super::error::StrandModelError;
use super::loading::SectionMotion;
use super::mesh::StrandMesh;
use super::profile::Strand;
use crate::beam::frame::{DofMap, FrameState, NodeId, NODE_DOFS};
use crate::beam::rotation::{exp_so3, log_so3, tangent_operator, tangent_operator_inverse};
use crate::linalg::{Equation, PatternError, SparsePattern, Storage};

/// Which DOFs of every node are prescribed: the core, the anchored ends and, under Eq. 13, the
/// far ends' rotations.
pub(crate) type Prescription = Vec<[bool; NODE_DOFS]>;

/// One start end S that an eliminated end interpolates (module docs).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Master {
    /// The node S.
    pub node: usize,
    /// Its reference axial coordinate (m).
    pub z_m: f64,
    /// Interpolation weight w(θ_P − θ_S).
    pub weight: f64,
    /// Rotation about the strand axis that carries S's angle to P's, θ_P − θ_S (rad).
    pub turn_rad: f64,
}

/// One eliminated wire end P (module docs).
#[derive(Clone, Debug, PartialEq)]
pub struct EndConstraint {
    /// The node P.
    pub node: usize,
    /// Its reference axial coordinate (m).
    pub z_p_m: f64,
    /// The start ends of P's layer it interpolates.
    pub masters: Vec<Master>,
    /// Reference mismatch e₀ in the section frame (m): round-off of the interpolation.
    pub offset_m: Vector3<f64>,
}

/// Rotation by `angle` about the strand axis.
fn turn(angle: f64) -> Matrix3<f64> {
    let (s, c) = angle.sin_cos();
    Matrix3::new(c, -s, 0.0, s, c, 0.0, 0.0, 0.0, 1.0)
}

impl EndConstraint {
    /// A_S = R(z_P) T(θ_P − θ_S) R(z_S)ᵀ of master `s` under `motion`.
    pub(crate) fn transfer(&self, s: usize, motion: &SectionMotion) -> Matrix3<f64> {
        let m = &self.masters[s];
        motion.rotation(self.z_p_m) * turn(m.turn_rad) * motion.rotation(m.z_m).transpose()
    }

    /// Rotation vector φ_P of P relative to its section that the rotation tie gives for the
    /// current master rotations (module docs).
    fn rotation_vector(&self, motion: &SectionMotion, rotations: &[Matrix3<f64>]) -> Vector3<f64> {
        let mut phi = Vector3::zeros();
        for (s, m) in self.masters.iter().enumerate() {
            let relative = rotations[m.node] * motion.rotation(m.z_m).transpose();
            phi += m.weight * (self.transfer(s, motion) * log_so3(&relative));
        }
        phi
    }

    /// Position of P that satisfies the constraint for the current master positions.
    pub fn position(&self, motion: &SectionMotion, positions: &[Vector3<f64>]) -> Vector3<f64> {
        let mut x = motion.axis_point(self.z_p_m) + motion.rotation(self.z_p_m) * self.offset_m;
        for (s, m) in self.masters.iter().enumerate() {
            x += m.weight
                * (self.transfer(s, motion) * (positions[m.node] - motion.axis_point(m.z_m)));
        }
        x
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
    /// Whether the eliminated ends' rotations follow their start ends' (module docs) rather
    /// than their sections'.
    pub tied_rotations: bool,
}

/// Angle tolerance for an end to count as lying at the outer arc (rad).
const OUTER_ARC_TOLERANCE_RAD: f64 = 1e-6;

/// Points of the angular interpolation: the start ends nearest an eliminated end's angle, two
/// on either side (all of them in a layer of fewer than four wires).
pub(crate) const INTERPOLATION_POINTS: usize = 4;

/// Lagrange weights, at angle 0, of the interpolation through the angles `deltas` (rad, each
/// θ_S − θ_P wrapped to (−π, π]) of the [`INTERPOLATION_POINTS`] nearest of them, two on either
/// side; returns (index into `deltas`, weight). The weights sum to 1, so a field that is the
/// same at every angle (pure tension) is carried over exactly; the error in bending, whose
/// stick field varies as sin θ, is of order (2π/n)⁴ (cubic interpolation, n wires).
pub(crate) fn angular_interpolation(deltas: &[f64]) -> Vec<(usize, f64)> {
    use std::f64::consts::TAU;
    let n = deltas.len();
    let mut order: Vec<usize> = (0..n).collect();
    order.sort_by(|&a, &b| deltas[a].total_cmp(&deltas[b]));
    // (index, angle unwrapped around the eliminated end's, at 0)
    let chosen: Vec<(usize, f64)> = if n <= INTERPOLATION_POINTS {
        order.iter().map(|&i| (i, deltas[i])).collect()
    } else {
        let above = order.iter().position(|&i| deltas[i] >= 0.0).unwrap_or(n) as isize;
        let half = (INTERPOLATION_POINTS / 2) as isize;
        (0..INTERPOLATION_POINTS as isize)
            .map(|k| {
                let pos = above + k - half;
                let (at, shift) = if pos < 0 {
                    (pos + n as isize, -TAU)
                } else if pos >= n as isize {
                    (pos - n as isize, TAU)
                } else {
                    (pos, 0.0)
                };
                let i = order[at as usize];
                (i, deltas[i] + shift)
            })
            .collect()
    };
    chosen
        .iter()
        .map(|&(i, a)| {
            let w = chosen
                .iter()
                .filter(|&&(j, _)| j != i)
                .fold(1.0, |acc, &(_, b)| acc * (-b) / (a - b));
            (i, w)
        })
        .collect()
}

/// Anchored ends and constraints of `mesh` (module docs).
pub(crate) fn end_layout(
    strand: &Strand,
    mesh: &StrandMesh,
    tied_rotations: bool,
) -> Result<EndLayout, StrandModelError> {
    use std::f64::consts::{FRAC_PI_2, PI};
    let wires = strand.wires();
    let mut prescription: Prescription = mesh
        .nodes
        .iter()
        .map(|n| [n.wire.0 == 0; NODE_DOFS])
        .collect();
    let mut anchored = Vec::new();
    let mut constraints = Vec::new();
    let wrap = |x: f64| (x + PI).rem_euclid(2.0 * PI) - PI;
    let at_outer_arc = |theta: f64| wrap(theta - FRAC_PI_2).abs() < OUTER_ARC_TOLERANCE_RAD;
    for k in 0..strand.layers.len() {
        let reference = strand.first_wire_of_layer(k);
        let layer: Vec<_> = wires
            .iter()
            .filter(|w| w.layer == Some(k) && mesh.wire_nodes[w.id.0].len() >= 2)
            .collect();
        // the start ends S (z = 0) with their angles
        let starts: Vec<(usize, f64)> = layer
            .iter()
            .map(|w| {
                let node = mesh.wire_nodes[w.id.0].start;
                (node, w.helix.angle(mesh.nodes[node].z_m))
            })
            .collect();
        for (w, &(start, theta_s)) in layer.iter().zip(&starts) {
            let finish = mesh.wire_nodes[w.id.0].end - 1;
            let theta = w.helix.angle(mesh.nodes[finish].z_m);
            if w.id == reference {
                for (node, angle) in [(start, theta_s), (finish, theta)] {
                    if at_outer_arc(angle) {
                        anchored.push(node);
                        prescription[node] = [true; NODE_DOFS];
                    }
                }
                if at_outer_arc(theta) {
                    continue;
                }
            }
            let deltas: Vec<f64> = starts.iter().map(|&(_, t)| wrap(t - theta)).collect();
            let masters: Vec<Master> = angular_interpolation(&deltas)
                .into_iter()
                .map(|(i, weight)| Master {
                    node: starts[i].0,
                    z_m: mesh.nodes[starts[i].0].z_m,
                    weight,
                    turn_rad: -deltas[i],
                })
                .collect();
            let z_p = mesh.nodes[finish].z_m;
            let relative = |node: usize| {
                mesh.nodes[node].position - Vector3::new(0.0, 0.0, mesh.nodes[node].z_m)
            };
            let interpolated = masters.iter().fold(Vector3::zeros(), |acc, m| {
                acc + m.weight * (turn(m.turn_rad) * relative(m.node))
            });
            prescription[finish] = [
                false,
                false,
                false,
                !tied_rotations,
                !tied_rotations,
                !tied_rotations,
            ];
            constraints.push(EndConstraint {
                node: finish,
                z_p_m: z_p,
                masters,
                offset_m: relative(finish) - interpolated,
            });
        }
    }
    for c in &constraints {
        if c.masters
            .iter()
            .any(|m| constraints.iter().any(|d| d.node == m.node))
        {
            return Err(StrandModelError::InvalidParameter {
                field: "model_length_m",
                value: strand.model_length_m,
                reason: "a periodic master point lies on an eliminated wire end",
            });
        }
    }
    Ok(EndLayout {
        anchored,
        constraints,
        prescription,
        tied_rotations,
    })
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
    /// First coefficient slot of every constraint, and the slot count ([`slot_bases`]).
    slot_bases: (Vec<usize>, usize),
}

/// First coefficient slot of every constraint (slot 0 is the identity), and the slot count:
/// a 3 × 3 block per master for the translations, and with tied rotations another one per
/// master for the rotations after them.
fn slot_bases(layout: &EndLayout) -> (Vec<usize>, usize) {
    let blocks = if layout.tied_rotations { 2 } else { 1 };
    let mut bases = Vec::with_capacity(layout.constraints.len());
    let mut next = 1;
    for c in &layout.constraints {
        bases.push(next);
        next += 9 * blocks * c.masters.len();
    }
    (bases, next)
}

/// Coefficient slot of master `s`, P component `m`, master component `c` from `base`; P's
/// rotation components `m` = 3 … 5 take the rotation blocks after the `masters` translation
/// blocks, master components of the same kind.
fn slot(base: usize, masters: usize, s: usize, m: usize, c: usize) -> usize {
    if m < 3 {
        base + 9 * s + 3 * m + c
    } else {
        base + 9 * (masters + s) + 3 * (m - 3) + c
    }
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
        let tied = if layout.tied_rotations { 6 } else { 3 };
        for (d, c) in layout.constraints.iter().enumerate() {
            for m in 0..tied {
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
        let bases_and_count = slot_bases(&layout);
        let bases = &bases_and_count.0;
        let expansions: Vec<Expansion> = (0..n_ext)
            .map(|e| match dependent[e] {
                None => vec![(reduced_of[e], 0)],
                Some((d, m)) => {
                    let c = &layout.constraints[d];
                    let mut out = Vec::with_capacity(3 * c.masters.len());
                    let kind = if m < 3 { 0 } else { 3 };
                    for (s, master) in c.masters.iter().enumerate() {
                        for comp in 0..3 {
                            let equation = dofs.equation(NodeId(master.node), kind + comp);
                            if let Some(me) = equation.index() {
                                let at = slot(bases[d], c.masters.len(), s, m, comp);
                                out.push((reduced_of[me], at));
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
                slot_bases: bases_and_count,
            },
            reduced,
        ))
    }

    /// Coefficients of every slot under `motion` and, for tied rotations, at the master
    /// rotations of `state` (slot 0 is 1).
    pub fn coefficients(&self, motion: &SectionMotion, state: &FrameState, out: &mut Vec<f64>) {
        let (bases, count) = &self.slot_bases;
        out.clear();
        out.resize(*count, 0.0);
        out[0] = 1.0;
        for (d, c) in self.layout.constraints.iter().enumerate() {
            let n = c.masters.len();
            let h_p = self
                .layout
                .tied_rotations
                .then(|| tangent_operator(&c.rotation_vector(motion, &state.rotations)));
            for (s, master) in c.masters.iter().enumerate() {
                let a = master.weight * c.transfer(s, motion);
                let spins = h_p.map(|h_p| {
                    let relative =
                        state.rotations[master.node] * motion.rotation(master.z_m).transpose();
                    h_p * a * tangent_operator_inverse(&log_so3(&relative))
                });
                for (first, block) in [(0, Some(a)), (3, spins)] {
                    let Some(block) = block else { continue };
                    for m in 0..3 {
                        for comp in 0..3 {
                            out[slot(bases[d], n, s, first + m, comp)] = block[(m, comp)];
                        }
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
    pub(crate) fn reduced_equation(&self, extended: usize) -> Option<usize> {
        match self.expansions.get(extended)?.as_slice() {
            [(r, 0)] => Some(*r),
            _ => None,
        }
    }

    /// Expands a reduced increment onto the extended equations (dependent entries 0: the
    /// eliminated ends are placed exactly by [`Self::enforce`] afterwards).
    pub(crate) fn expand(&self, reduced: &[f64], extended: &mut [f64]) {
        for (e, exp) in self.expansions.iter().enumerate() {
            extended[e] = match exp.as_slice() {
                [(r, 0)] => reduced[*r],
                _ => 0.0,
            };
        }
    }

    /// Places the eliminated ends on their constraint and sets their rotations to the section's
    /// or, tied, to the one their start ends give.
    pub(crate) fn enforce(&self, motion: &SectionMotion, state: &mut FrameState) {
        for c in &self.layout.constraints {
            let x = c.position(motion, &state.positions);
            state.positions[c.node] = x;
            state.rotations[c.node] = if self.layout.tied_rotations {
                exp_so3(&c.rotation_vector(motion, &state.rotations)) * motion.rotation(c.z_p_m)
            } else {
                motion.rotation(c.z_p_m)
            };
        }
    }
}

#[cfg(test)]
#[path = "periodic_tests.rs"]
mod tests;
