//! The two-node small-sliding frictional contact element between two wire beams (the paper's
//! Eqs. 1-11).
//!
//! DOFs, in this order: [u₁(3), θ₁(3), u₂(3), θ₂(3)], with θᵢ spatial rotation increments
//! (`crate::beam::rotation`: Λ ← exp(θ̂) Λ). A node's current tangent is tᵢ = Λᵢ Tᵢ with Tᵢ the
//! material (reference) tangent, so δtᵢ = δθᵢ × tᵢ.
//!
//! Kinematics, with d = x₂ − x₁ and c = t₁·t₂:
//! - normal (Eq. 2) n = σ t₁ × t₂ / |t₁ × t₂|, σ = ±1 fixed so that n points from wire 1 to
//!   wire 2 in the reference configuration;
//! - normal gap (Eq. 3) g_N = d·n − (r₁ + r₂), contact when g_N < 0;
//! - sliding parameters of the closest points on the straight lines x₁ + ξ¹t₁, x₂ − ξ²t₂ (Eq. 1):
//!   ξ¹ = (d·t₁ − c d·t₂)/(1 − c²), ξ² = (d·t₂ − c d·t₁)/(1 − c²), so ξ¹t₁ + ξ²t₂ = P d with
//!   P = I − n⊗n;
//! - circumferential directors (Eqs. 7-8) nᵢ = R(Φᵢ^Δ) n₍ₙ₎ = Λᵢ Λᵢ,ₙᵀ n₍ₙ₎; the history keeps
//!   Nᵢ = Λᵢ,ₙᵀ n₍ₙ₎ in each node's material frame, so nᵢ = Λᵢ Nᵢ needs no logarithm;
//! - tangential gap increment (Eqs. 5, 6 with d₂ written with t₂, 9)
//!   g_T^Δ = (ξ¹ − ξ¹₍ₙ₎) t₁ + (ξ² − ξ²₍ₙ₎) t₂ − P (r₁ n₁ + r₂ n₂);
//! - elastic part mapped forward (Eqs. 10-11): the elastic gap of the last accepted step is
//!   stored by its components eᵢ on (t₁₍ₙ₎, t₂₍ₙ₎) and mapped to e₁ t₁ + e₂ t₂, so the trial gap is
//!   g_T = P (d − r₁ n₁ − r₂ n₂) − α₁ t₁ − α₂ t₂ with αᵢ = ξⁱ₍ₙ₎ − eᵢ (history constants).
//!
//! Forces: penalty-type potential, f_N = f_N(−g_N) ≥ 0 and f_T = k_T g_T (stick) or
//! f_T = μ f_N g_T/|g_T| (slip, radial return), see [`super::laws`]; with the Cattaneo–Mindlin
//! law f_T is the force of the Iwan elements of [`super::memory`] at the trial gap (μ f_N in
//! gross slip), and the history also keeps the elements' stretches. The internal force vector
//! (contribution to the residual r = f_int − f_ext) is f_int = −f_N ∂g_N/∂q + (∂g_T/∂q)ᵀ f_T, with
//!   ∂g_N/∂u₁ = −n, ∂g_N/∂u₂ = n, ∂g_N/∂θ₁ = t₁ × (t₂ × m), ∂g_N/∂θ₂ = t₂ × (m × t₁),
//!   m = (σ/|t₁ × t₂|) P d,
//! and, for the tangential part with φ = f_T (φ ⟂ n):
//!   u₁: −φ;  u₂: φ;
//!   θ₁: −r₁ n₁ × φ − (n·v) t₁ × (t₂ × m_φ) − α₁ t₁ × φ,
//!   θ₂: −r₂ n₂ × φ − (n·v) t₂ × (m_φ × t₁) − α₂ t₂ × φ,
//!   v = d − r₁ n₁ − r₂ n₂, m_φ = (σ/|t₁ × t₂|) φ.
//! The consistent tangent K = ∂f_int/∂q (12×12, non-symmetric in slip and whenever k_T depends on
//! f_N) is obtained by forward-mode differentiation of that same force ([`super::scalar`]).
//!
//! History (last accepted step) changes only through [`ContactHistory::accept`]; Newton
//! iterations evaluate trial values against a fixed history. Units: m, N, rad.

use nalgebra::{Matrix3, SMatrix, SVector, Vector3};

use super::laws::{
    ContactError, ContactParameters, ResolvedLaws, ResolvedNormal, ResolvedTangential,
};
use super::memory::{self, TangentialMemory, IWAN_ELEMENTS};
use super::scalar::{director, point, Scalar, NDOF, V3};

/// Element force vector [u₁, θ₁, u₂, θ₂].
pub type ElementVector = SVector<f64, NDOF>;
/// Element tangent matrix.
pub type ElementMatrix = SMatrix<f64, NDOF, NDOF>;

/// Current position and orientation of a node.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct NodeKinematics {
    /// Position of the beam axis node (m).
    pub position: Vector3<f64>,
    /// Rotation Λ mapping the material triad to the current one.
    pub rotation: Matrix3<f64>,
}

impl NodeKinematics {
    /// A node at `position` with identity rotation.
    pub fn at(position: Vector3<f64>) -> Self {
        Self {
            position,
            rotation: Matrix3::identity(),
        }
    }
}

/// Stick, slip or separation.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, serde::Serialize, serde::Deserialize)]
pub enum ContactStatus {
    /// g_N ≥ 0: no force.
    Open,
    /// Elastic tangential response.
    Stick,
    /// Coulomb sliding.
    Slip,
}

/// Immutable description of one contact: radii, material tangents, laws, normal orientation.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ContactPair {
    radius1_m: f64,
    radius2_m: f64,
    tangent1: Vector3<f64>,
    tangent2: Vector3<f64>,
    orientation: f64,
    laws: ResolvedLaws,
}

/// Contact history at the last accepted step.
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct ContactHistory {
    /// Contact normal n₍ₙ₎.
    pub normal: Vector3<f64>,
    /// n₍ₙ₎ in node 1's material frame, Λ₁,ₙᵀ n₍ₙ₎.
    pub normal_in_node1: Vector3<f64>,
    /// n₍ₙ₎ in node 2's material frame, Λ₂,ₙᵀ n₍ₙ₎.
    pub normal_in_node2: Vector3<f64>,
    /// Sliding parameters ξ¹₍ₙ₎, ξ²₍ₙ₎ (m).
    pub sliding_m: [f64; 2],
    /// Elastic tangential gap components on (t₁₍ₙ₎, t₂₍ₙ₎) (m).
    pub elastic_gap_m: [f64; 2],
    /// Total relative tangential displacement, components on (t₁₍ₙ₎, t₂₍ₙ₎) (m).
    pub total_slip_m: [f64; 2],
    /// Accumulated path length of Coulomb sliding (m).
    pub slip_path_m: f64,
    /// Status at the last accepted step.
    pub status: ContactStatus,
    /// Stretches of the Cattaneo–Mindlin law's Iwan elements (empty for the other laws).
    pub tangential_memory: TangentialMemory,
}

/// Result of one evaluation (trial values), with the history to store if the step is accepted.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ContactResponse {
    /// Stick / slip / open.
    pub status: ContactStatus,
    /// Current normal n.
    pub normal: Vector3<f64>,
    /// Normal gap g_N (m), negative in contact.
    pub normal_gap_m: f64,
    /// Normal force f_N ≥ 0 (N).
    pub normal_force_n: f64,
    /// Tangential force vector f_T (N), in the tangent plane.
    pub tangential_force: Vector3<f64>,
    /// |f_T| (N).
    pub tangential_force_n: f64,
    /// Trial tangential gap g_T (m).
    pub tangential_gap: Vector3<f64>,
    /// Relative tangential displacement over the step, g_T^Δ (m).
    pub slip_increment: Vector3<f64>,
    /// Total relative tangential displacement since the reference configuration (m).
    pub total_slip: Vector3<f64>,
    /// Coulomb (irreversible) part of the step's tangential displacement (m).
    pub sliding_increment: Vector3<f64>,
    /// Sliding parameters ξ¹, ξ² (m).
    pub sliding_m: [f64; 2],
    /// History to store when the step is accepted.
    pub next_history: ContactHistory,
}

impl ContactHistory {
    /// Stores the trial state of an accepted step.
    pub fn accept(&mut self, response: &ContactResponse) {
        *self = response.next_history;
    }
}

struct Kernel<S> {
    force: [S; NDOF],
    gap: S,
    normal_force: S,
    gt: V3<S>,
    ft: V3<S>,
    n: V3<S>,
    /// k_T of the elastic-slip and Mindlin laws (0 under Cattaneo–Mindlin, whose stiffness is
    /// `tangent_plane`).
    kt: f64,
    /// The Cattaneo–Mindlin law's ∂f_T/∂g_T for the preconditioner (`None` for the others).
    tangent_plane: Option<Matrix3<f64>>,
    status: ContactStatus,
    /// Elastic gap and element stretches of the Cattaneo–Mindlin law.
    memory: Option<MemoryState>,
}

/// What the Cattaneo–Mindlin law keeps from a trial evaluation.
struct MemoryState {
    elastic: Vector3<f64>,
    stretches: [Vector3<f64>; IWAN_ELEMENTS - 1],
}

/// Components (a, b) of `v` on the non-orthogonal basis (t₁, t₂) of the tangent plane.
fn components(v: &Vector3<f64>, t1: &Vector3<f64>, t2: &Vector3<f64>) -> [f64; 2] {
    let c = t1.dot(t2);
    let den = 1.0 - c * c;
    let (v1, v2) = (v.dot(t1), v.dot(t2));
    [(v1 - c * v2) / den, (v2 - c * v1) / den]
}

impl ContactPair {
    /// Builds the contact between node 1 (wire radius `radius1_m`, material tangent `tangent1`)
    /// and node 2, in the reference configuration given by `node1`, `node2`, and returns it with
    /// its initial history (no elastic gap, no slip). The normal is oriented from wire 1 to
    /// wire 2 here and keeps that orientation.
    pub fn new(
        params: &ContactParameters,
        radius1_m: f64,
        radius2_m: f64,
        node1: &NodeKinematics,
        tangent1: &Vector3<f64>,
        node2: &NodeKinematics,
        tangent2: &Vector3<f64>,
    ) -> Result<(Self, ContactHistory), ContactError> {
        for (field, value) in [("radius1_m", radius1_m), ("radius2_m", radius2_m)] {
            if !(value > 0.0 && value.is_finite()) {
                return Err(ContactError::InvalidParameter {
                    field,
                    value,
                    reason: "must be finite and > 0",
                });
            }
        }
        for (field, t) in [("tangent1", tangent1), ("tangent2", tangent2)] {
            if !(t.norm() > 0.0 && t.norm().is_finite()) {
                return Err(ContactError::InvalidParameter {
                    field,
                    value: t.norm(),
                    reason: "must be a non-zero vector",
                });
            }
        }
        let (tm1, tm2) = (tangent1.normalize(), tangent2.normalize());
        let (t1, t2) = (node1.rotation * tm1, node2.rotation * tm2);
        let w = t1.cross(&t2);
        let s = w.norm();
        if s < 1e-6 {
            return Err(ContactError::ParallelTangents { sin_angle: s });
        }
        let d = node2.position - node1.position;
        let separation_m = d.dot(&w) / s;
        if separation_m.abs() <= 1e-12 * (radius1_m + radius2_m) {
            return Err(ContactError::UnorientedNormal { separation_m });
        }
        let orientation = separation_m.signum();
        let angle = s.atan2(t1.dot(&t2).abs());
        let laws = ResolvedLaws::new(params, radius1_m, radius2_m, angle)?;
        let pair = Self {
            radius1_m,
            radius2_m,
            tangent1: tm1,
            tangent2: tm2,
            orientation,
            laws,
        };
        let n = w * (orientation / s);
        let xi = components(&(d - n * n.dot(&d)), &t1, &t2);
        let history = ContactHistory {
            normal: n,
            normal_in_node1: node1.rotation.transpose() * n,
            normal_in_node2: node2.rotation.transpose() * n,
            sliding_m: xi,
            elastic_gap_m: [0.0; 2],
            total_slip_m: [0.0; 2],
            slip_path_m: 0.0,
            status: ContactStatus::Open,
            tangential_memory: TangentialMemory::default(),
        };
        Ok((pair, history))
    }

    /// Wire radii (r₁, r₂) (m).
    pub fn radii_m(&self) -> (f64, f64) {
        (self.radius1_m, self.radius2_m)
    }

    /// The resolved laws of this contact.
    pub fn laws(&self) -> &ResolvedLaws {
        &self.laws
    }

    /// Trial response and internal force vector (no tangent).
    pub fn residual(
        &self,
        history: &ContactHistory,
        node1: &NodeKinematics,
        node2: &NodeKinematics,
        force: &mut ElementVector,
    ) -> ContactResponse {
        let (t1, t2) = (
            node1.rotation * self.tangent1,
            node2.rotation * self.tangent2,
        );
        let (n1, n2) = (
            node1.rotation * history.normal_in_node1,
            node2.rotation * history.normal_in_node2,
        );
        let d = node2.position - node1.position;
        let k = self.kernel(
            history,
            V3::<f64>::cst(&d),
            V3::cst(&t1),
            V3::cst(&t2),
            V3::cst(&n1),
            V3::cst(&n2),
            0.0,
        );
        force.as_mut_slice().copy_from_slice(&k.force);
        self.respond(history, &k, node1, node2, &d, &t1, &t2)
    }

    /// Trial response, internal force vector and consistent tangent ∂f_int/∂q.
    pub fn residual_and_tangent(
        &self,
        history: &ContactHistory,
        node1: &NodeKinematics,
        node2: &NodeKinematics,
        force: &mut ElementVector,
        tangent: &mut ElementMatrix,
    ) -> ContactResponse {
        self.evaluate_with_tangent(history, node1, node2, force, tangent, None, 0.0)
    }

    /// As [`Self::residual_and_tangent`], plus a symmetric positive semi-definite surrogate of
    /// the tangent for preconditioning: P = k_N b_N b_Nᵀ + B_Tᵀ C B_T, with b_N = ∂g_N/∂q,
    /// B_T = ∂g_T/∂q, k_N = ∂f_N/∂(−g_N) and C = k_T I in stick, (μ f_N/|g_T|)(I − ĝ ĝᵀ) in
    /// slip (the symmetric part of the sliding law), 0 when open. It leaves out what makes the
    /// tangent non-symmetric or indefinite: the dependence of the friction force on the normal
    /// force (μ ∂f_N/∂g_N, as large as μ times the normal stiffness) and the curvature terms
    /// f_N ∂²g_N/∂q², f_T·∂²g_T/∂q² of the contact geometry.
    ///
    /// `sliding` > 0 stiffens the tangent (not the force, nor the surrogate) of a
    /// Cattaneo–Mindlin contact in gross slip along its sliding direction d by
    /// k_s = `sliding` · k₀: the tangent becomes ∂f_int/∂q + k_s (∂f_int/∂f_T) d dᵀ ∂g_T/∂q,
    /// as if the contact resisted its sliding with a fraction of its initial stiffness. A Newton
    /// iteration matrix, not a derivative ([`crate::linalg::NonlinearProblem::begin_iteration`]).
    #[allow(clippy::too_many_arguments)]
    pub(crate) fn residual_tangent_and_surrogate(
        &self,
        history: &ContactHistory,
        node1: &NodeKinematics,
        node2: &NodeKinematics,
        force: &mut ElementVector,
        tangent: &mut ElementMatrix,
        surrogate: &mut ElementMatrix,
        sliding: f64,
    ) -> ContactResponse {
        self.evaluate_with_tangent(
            history,
            node1,
            node2,
            force,
            tangent,
            Some(surrogate),
            sliding,
        )
    }

    #[allow(clippy::too_many_arguments)]
    fn evaluate_with_tangent(
        &self,
        history: &ContactHistory,
        node1: &NodeKinematics,
        node2: &NodeKinematics,
        force: &mut ElementVector,
        tangent: &mut ElementMatrix,
        surrogate: Option<&mut ElementMatrix>,
        sliding: f64,
    ) -> ContactResponse {
        let (t1, t2) = (
            node1.rotation * self.tangent1,
            node2.rotation * self.tangent2,
        );
        let (n1, n2) = (
            node1.rotation * history.normal_in_node1,
            node2.rotation * history.normal_in_node2,
        );
        let d = node2.position - node1.position;
        let dd = point(&node2.position, 6) - point(&node1.position, 0);
        let k = self.kernel(
            history,
            dd,
            director(&t1, 3),
            director(&t2, 9),
            director(&n1, 3),
            director(&n2, 9),
            sliding,
        );
        for i in 0..NDOF {
            force[i] = k.force[i].v;
            for j in 0..NDOF {
                tangent[(i, j)] = k.force[i].d[j];
            }
        }
        if let Some(p) = surrogate {
            p.fill(0.0);
            if k.status != ContactStatus::Open {
                let pen = -k.gap.v;
                let kn = match self.laws.normal {
                    ResolvedNormal::Penalty(kp) => kp,
                    ResolvedNormal::Hertz(kh) => 1.5 * kh * pen.max(0.0).sqrt(),
                    ResolvedNormal::Line(l) => l.force_and_stiffness(pen).1,
                };
                let bn = SVector::<f64, NDOF>::from_column_slice(&k.gap.d);
                let bt = nalgebra::SMatrix::<f64, 3, NDOF>::from_fn(|i, j| k.gt.c[i].d[j]);
                let c = match (k.status, k.tangent_plane) {
                    (_, Some(c)) => c,
                    (ContactStatus::Slip, None) => {
                        let g = k.gt.val();
                        let gn = g.norm();
                        let u = g / gn;
                        if gn > 0.0 {
                            (Matrix3::identity() - u * u.transpose())
                                * (self.laws.friction_coefficient * k.normal_force.v / gn)
                        } else {
                            Matrix3::zeros()
                        }
                    }
                    _ => Matrix3::identity() * k.kt,
                };
                *p = bn * bn.transpose() * kn + bt.transpose() * c * bt;
            }
        }
        self.respond(history, &k, node1, node2, &d, &t1, &t2)
    }

    /// Normal gap and trial tangential gap at a configuration (used to verify the force against
    /// the gap functions it is the gradient of).
    pub fn gaps(
        &self,
        history: &ContactHistory,
        node1: &NodeKinematics,
        node2: &NodeKinematics,
    ) -> (f64, Vector3<f64>) {
        let (t1, t2) = (
            node1.rotation * self.tangent1,
            node2.rotation * self.tangent2,
        );
        let (n1, n2) = (
            node1.rotation * history.normal_in_node1,
            node2.rotation * history.normal_in_node2,
        );
        let d = node2.position - node1.position;
        let k = self.kernel(
            history,
            V3::<f64>::cst(&d),
            V3::cst(&t1),
            V3::cst(&t2),
            V3::cst(&n1),
            V3::cst(&n2),
            0.0,
        );
        (k.gap, k.gt.val())
    }

    #[allow(clippy::too_many_arguments)]
    fn kernel<S: Scalar>(
        &self,
        h: &ContactHistory,
        d: V3<S>,
        t1: V3<S>,
        t2: V3<S>,
        n1: V3<S>,
        n2: V3<S>,
        sliding: f64,
    ) -> Kernel<S> {
        let (r1, r2) = (self.radius1_m, self.radius2_m);
        let w = t1.cross(&t2);
        let sig_over_s = S::cst(self.orientation) / w.norm();
        let n = w.scale(sig_over_s);
        let dn = d.dot(&n);
        let gap = dn + (-(r1 + r2));
        let v = d - n1.scalef(r1) - n2.scalef(r2);
        let nv = n.dot(&v);
        let a1 = h.sliding_m[0] - h.elastic_gap_m[0];
        let a2 = h.sliding_m[1] - h.elastic_gap_m[1];
        let gt = v - n.scale(nv) - t1.scalef(a1) - t2.scalef(a2);
        let zero = S::cst(0.0);
        if gap.val() >= 0.0 {
            let z = V3::new(zero, zero, zero);
            return Kernel {
                force: [zero; NDOF],
                gap,
                normal_force: zero,
                gt,
                ft: z,
                n,
                kt: 0.0,
                tangent_plane: None,
                status: ContactStatus::Open,
                memory: None,
            };
        }
        let pen = -gap;
        // The line law's stiffness dF_N/dp as a scalar of its own (the Cattaneo–Mindlin initial
        // stiffness of a line contact is proportional to it).
        let mut line_stiffness = None;
        let fnorm = match self.laws.normal {
            ResolvedNormal::Penalty(k) => pen * k,
            ResolvedNormal::Hertz(k) => pen.powf(1.5) * k,
            ResolvedNormal::Line(l) => {
                let p0 = pen.val();
                let (f, k, dk) = l.force_stiffness_and_derivative(p0);
                line_stiffness = Some(pen * dk + (k - dk * p0));
                pen * k + (f - k * p0)
            }
        };
        let mu = self.laws.friction_coefficient;
        let k0 = match self.laws.tangential {
            ResolvedTangential::CattaneoMindlinPoint(c) => Some(fnorm.powf(1.0 / 3.0) * c),
            ResolvedTangential::CattaneoMindlinLine(ratio) => Some(match line_stiffness {
                Some(k) => k * ratio,
                // a penalty or Hertz normal law: its own tangent stiffness
                None => match self.laws.normal {
                    ResolvedNormal::Penalty(k) => S::cst(k * ratio),
                    _ => pen.sqrt() * (1.5 * ratio) * self.hertz_coefficient(),
                },
            }),
            _ => None,
        };
        let (ft, status, kt, tangent_plane, memory) = if let Some(k0) = k0 {
            let m = &h.tangential_memory;
            let trial = memory::evaluate(m, h.elastic_gap_m, &gt, &t1, &t2, fnorm, k0, mu);
            let state = MemoryState {
                elastic: trial.elastic,
                stretches: trial.stretches,
            };
            let status = if trial.slip {
                ContactStatus::Slip
            } else {
                ContactStatus::Stick
            };
            let plane = Some(trial.jacobian);
            let force = if trial.slip && sliding > 0.0 {
                // k_s (d · (g_T − g_T⁰)) d: zero in value, k_s d dᵀ in the derivative
                let f0 = trial.force.val();
                let d = f0 / f0.norm().max(f64::MIN_POSITIVE);
                let g0 = gt.val();
                let along = (gt.c[0] + (-g0[0])) * d[0]
                    + (gt.c[1] + (-g0[1])) * d[1]
                    + (gt.c[2] + (-g0[2])) * d[2];
                let ks = sliding * k0.val();
                trial.force
                    + V3::new(
                        along * (ks * d[0]),
                        along * (ks * d[1]),
                        along * (ks * d[2]),
                    )
            } else {
                trial.force
            };
            (force, status, 0.0, plane, Some(state))
        } else {
            let kt = match self.laws.tangential {
                ResolvedTangential::ElasticSlip(ge) => fnorm * (mu / ge),
                ResolvedTangential::Mindlin(c) => fnorm.powf(1.0 / 3.0) * c,
                _ => unreachable!("the Cattaneo-Mindlin laws are evaluated above"),
            };
            let limit = fnorm * mu;
            let gt_norm = gt.norm().val();
            let (ft, status) = if kt.val() * gt_norm <= limit.val() {
                (gt.scale(kt), ContactStatus::Stick)
            } else {
                (gt.scale(limit / gt.norm()), ContactStatus::Slip)
            };
            (ft, status, kt.val(), None, None)
        };
        // Normal and tangential terms share their structure: with
        // M = (σ/|t₁ × t₂|)(f_N P d + (n·v) f_T) and φ = f_T,
        //   θ₁: −t₁ × (t₂ × M) − (r₁ n₁ + α₁ t₁) × φ,
        //   θ₂: −t₂ × (M × t₁) − (r₂ n₂ + α₂ t₂) × φ,
        //   u₁: f_N n − φ,  u₂: −u₁.
        let pd = d - n.scale(dn);
        let big_m = (pd.scale(fnorm) + ft.scale(nv)).scale(sig_over_s);
        let th1 = -(t1.cross(&t2.cross(&big_m))) - (n1.scalef(r1) + t1.scalef(a1)).cross(&ft);
        let th2 = -(t2.cross(&big_m.cross(&t1))) - (n2.scalef(r2) + t2.scalef(a2)).cross(&ft);
        let u1 = n.scale(fnorm) - ft;
        let u2 = -u1;
        let mut force = [zero; NDOF];
        force[0..3].copy_from_slice(&u1.c);
        force[3..6].copy_from_slice(&th1.c);
        force[6..9].copy_from_slice(&u2.c);
        force[9..12].copy_from_slice(&th2.c);
        Kernel {
            force,
            gap,
            normal_force: fnorm,
            gt,
            ft,
            n,
            kt,
            tangent_plane,
            status,
            memory,
        }
    }

    /// K_H of a Hertz normal law (0 for the others).
    fn hertz_coefficient(&self) -> f64 {
        match self.laws.normal {
            ResolvedNormal::Hertz(k) => k,
            _ => 0.0,
        }
    }

    #[allow(clippy::too_many_arguments)]
    fn respond<S: Scalar>(
        &self,
        h: &ContactHistory,
        k: &Kernel<S>,
        node1: &NodeKinematics,
        node2: &NodeKinematics,
        d: &Vector3<f64>,
        t1: &Vector3<f64>,
        t2: &Vector3<f64>,
    ) -> ContactResponse {
        let n = k.n.val();
        let gt = k.gt.val();
        let ft = k.ft.val();
        let mapped_elastic = t1 * h.elastic_gap_m[0] + t2 * h.elastic_gap_m[1];
        let increment = gt - mapped_elastic;
        let total = t1 * h.total_slip_m[0] + t2 * h.total_slip_m[1] + increment;
        let elastic = match (k.status, &k.memory) {
            (ContactStatus::Open, _) => Vector3::zeros(),
            (_, Some(m)) => m.elastic,
            (ContactStatus::Stick, None) => gt,
            (ContactStatus::Slip, None) => ft / k.kt,
        };
        let mut tangential_memory = TangentialMemory::default();
        if let (ContactStatus::Stick | ContactStatus::Slip, Some(m)) = (k.status, &k.memory) {
            for (slot, e) in tangential_memory.stretches.iter_mut().zip(&m.stretches) {
                *slot = components(e, t1, t2);
            }
        }
        let sliding = match k.status {
            ContactStatus::Slip => gt - elastic,
            _ => Vector3::zeros(),
        };
        let xi = components(&(d - n * n.dot(d)), t1, t2);
        let next = ContactHistory {
            normal: n,
            normal_in_node1: node1.rotation.transpose() * n,
            normal_in_node2: node2.rotation.transpose() * n,
            sliding_m: xi,
            elastic_gap_m: components(&elastic, t1, t2),
            total_slip_m: components(&total, t1, t2),
            slip_path_m: h.slip_path_m + sliding.norm(),
            status: k.status,
            tangential_memory,
        };
        ContactResponse {
            status: k.status,
            normal: n,
            normal_gap_m: k.gap.val(),
            normal_force_n: k.normal_force.val(),
            tangential_force: ft,
            tangential_force_n: ft.norm(),
            tangential_gap: gt,
            slip_increment: increment,
            total_slip: total,
            sliding_increment: sliding,
            sliding_m: xi,
            next_history: next,
        }
    }
}
