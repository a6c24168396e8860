//! Lines that are mirror images of each other about the vertical plane of the waves.
//!
//! A floater in a head or following sea (waves along ±x), with its rotor thrust along +x, is
//! loaded symmetrically about the x–z plane when its geometry is; lines laid symmetrically about
//! that plane (lines 1/2, 3/6 and 4/5 of the paper case) then move as mirror images, y → −y. The
//! coupled step solves one line of each such pair and writes the other's state, force and
//! condensed stiffness as the mirror image of the first's: half the line work, which is most of
//! a step's cost.
//!
//! The symmetry is not assumed, it is checked:
//!
//! - once, on the static equilibrium ([`MirrorMap::of`]): the sea runs along ±x (or is calm),
//!   and every unknown of line j equals the mirrored unknown of an earlier line i within
//!   [`STATIC_MIRROR_TOLERANCE_M`] (same mesh, mirrored fairlead and anchor, same static shape);
//! - at the start of every coupled step (`MirrorMap::holds_at`): each mirrored fairlead moves
//!   as the mirror image of its partner's (position, and velocity and acceleration over the
//!   step) within [`MIRROR_TOLERANCE_M`]. While a floater is out of the
//!   symmetry plane (an asymmetric hull, a prescribed sway), every line is solved, the mirrored
//!   ones from their (mirrored) states.
//!
//! Each line's force on the floater is linearised about the fairlead position it was computed
//! at (`super::coupling`), so a mirrored force applied at a fairlead within the tolerance of the
//! mirror point is corrected to first order.

use nalgebra::{Matrix3, Vector3};

use super::system::{GlobalModel, StaticEquilibrium};
use crate::mooring::dynamics::LineState;
use crate::mooring::trajectory::PointMotion;
use crate::mooring::LineModel;

/// Largest distance (m) between a line's static unknowns and the mirror image of its
/// partner's for the two to be mirror images: the static shapes of the paper case's mirrored
/// lines agree within 2e-8 m (each line's statics converge to their own tolerance), and lines
/// share their precomputed sea at this tolerance (`super::sea::SHARED_SERIES_TOLERANCE_M`).
pub(crate) const STATIC_MIRROR_TOLERANCE_M: f64 = super::sea::SHARED_SERIES_TOLERANCE_M;

/// Largest distance (m) between a fairlead's motion over a step and the mirror image of its
/// partner's for the step to write one line as the mirror image of the other. An offset of
/// 1e-7 m changes a line's force by at most 0.1 N (fairlead stiffness ≲ 1e6 N/m), a tenth of
/// the lines' force tolerance (1 N); the fairleads of the paper case's floater stay within
/// 2e-9 m of their mirror images (the static equilibrium's tolerance, then round-off).
pub(crate) const MIRROR_TOLERANCE_M: f64 = 1e-7;

/// The reflection y → −y of a fairlead position or force.
pub(crate) fn reflect(v: &Vector3<f64>) -> Vector3<f64> {
    Vector3::new(v.x, -v.y, v.z)
}

/// The reflection of a fairlead stiffness, S K S with S = diag(1, −1, 1).
pub(crate) fn reflect_stiffness(k: &Matrix3<f64>) -> Matrix3<f64> {
    let s = Matrix3::from_diagonal(&Vector3::new(1.0, -1.0, 1.0));
    s * k * s
}

/// Which lines are solved as the mirror image of another.
#[derive(Debug, Clone, PartialEq, Default)]
pub(crate) struct MirrorMap {
    /// For each line, the earlier line it mirrors.
    partner: Vec<Option<usize>>,
    /// The unknowns that are y components (positions and gradients) of the line mesh, which
    /// every paired line shares.
    y_dofs: Vec<usize>,
}

impl MirrorMap {
    /// No mirrored line.
    pub(crate) fn none(lines: usize) -> Self {
        MirrorMap {
            partner: vec![None; lines],
            y_dofs: Vec::new(),
        }
    }

    /// The mirror pairs of the static equilibrium `eq` of `model` (see the module
    /// documentation).
    pub(crate) fn of(model: &GlobalModel, eq: &StaticEquilibrium) -> Self {
        let n = eq.line_models.len();
        let (_, dy) = model.sea.field().direction();
        if dy.abs() > 1e-12 && !model.case.sea_state.is_calm() {
            return Self::none(n);
        }
        let Some(first) = eq.line_models.first() else {
            return Self::none(n);
        };
        let y_dofs = y_dofs(first);
        let mut partner: Vec<Option<usize>> = vec![None; n];
        for j in 1..n {
            partner[j] = (0..j).find(|&i| {
                partner[i].is_none()
                    && !partner.contains(&Some(i))
                    && same_mesh(first, &eq.line_models[i])
                    && same_mesh(first, &eq.line_models[j])
                    && mirrored(&eq.line_solutions[i].q, &eq.line_solutions[j].q, &y_dofs)
            });
        }
        MirrorMap { partner, y_dofs }
    }

    /// Number of lines solved as a mirror image.
    pub(crate) fn count(&self) -> usize {
        self.partner.iter().flatten().count()
    }

    /// The line that line `k` mirrors, if any.
    pub(crate) fn partner(&self, k: usize) -> Option<usize> {
        self.partner.get(k).copied().flatten()
    }

    /// Whether, over a step of `h_s`, every mirrored fairlead of `fairleads` moves as the
    /// mirror image of its partner's: position, velocity × h and acceleration × h² each within
    /// [`MIRROR_TOLERANCE_M`] of the partner's reflected.
    pub(crate) fn holds_at(&self, fairleads: &[PointMotion], h_s: f64) -> bool {
        self.partner.iter().enumerate().all(|(j, p)| match p {
            Some(i) => {
                let (a, b) = (&fairleads[j], &fairleads[*i]);
                let far = |x: &Vector3<f64>, y: &Vector3<f64>, scale: f64| {
                    (x - reflect(y)).amax() * scale > MIRROR_TOLERANCE_M
                };
                !(far(&a.position_m, &b.position_m, 1.0)
                    || far(&a.velocity_m_s, &b.velocity_m_s, h_s)
                    || far(&a.acceleration_m_s2, &b.acceleration_m_s2, h_s * h_s))
            }
            None => true,
        })
    }

    /// Writes the mirror image of `from` into `to`.
    pub(crate) fn reflect_state(&self, from: &LineState, to: &mut LineState) {
        to.clone_from(from);
        for &d in &self.y_dofs {
            to.q[d] = -to.q[d];
            to.v[d] = -to.v[d];
            to.acc[d] = -to.acc[d];
            to.alg_acc[d] = -to.alg_acc[d];
        }
    }
}

/// The y unknowns of a line mesh: the second component of every node's position and gradient.
fn y_dofs(model: &LineModel) -> Vec<usize> {
    let mut out = Vec::new();
    for n in model.nodes() {
        out.push(n.dof + 1);
        if n.has_gradient {
            out.push(n.dof + 4);
        }
    }
    out
}

/// Whether two line models have the same mesh (node layout, arc lengths and unknowns).
fn same_mesh(a: &LineModel, b: &LineModel) -> bool {
    a.dof_count() == b.dof_count()
        && a.nodes().len() == b.nodes().len()
        && a.nodes().iter().zip(b.nodes()).all(|(p, q)| {
            p.dof == q.dof && p.has_gradient == q.has_gradient && p.arc_length_m == q.arc_length_m
        })
}

/// Whether `b` is the mirror image of `a` (y unknowns `y_dofs` negated) within the tolerance.
fn mirrored(a: &[f64], b: &[f64], y_dofs: &[usize]) -> bool {
    if a.len() != b.len() {
        return false;
    }
    let mut sign = vec![1.0; a.len()];
    for &d in y_dofs {
        if let Some(s) = sign.get_mut(d) {
            *s = -1.0;
        }
    }
    a.iter()
        .zip(b)
        .zip(&sign)
        .all(|((x, y), s)| (s * x - y).abs() <= STATIC_MIRROR_TOLERANCE_M)
}
