//! End coupling of the helical wires to the core end sections (the paper's Sec. 2.2), by penalty.
//!
//! An end node of a helical wire follows the rigid motion of its plane end section
//! ([`super::loading::SectionMotion`]) except for its radial displacement and its rotation about
//! the radial direction, which stay free. With the section's current radial direction
//! r = R_sec e_r (e_r the reference radial unit vector of the node) and Q = I − r ⊗ r, the tie
//! adds the penalty forces
//!   f_u = k_u Q (x − x_sec),        f_θ = k_θ Q ψ,   ψ = log(Λ R_secᵀ),
//! to the node's residual, with the consistent tangent blocks k_u Q and k_θ Q T⁻¹(ψ), where
//! T⁻¹(ψ) = ∂ψ/∂θ for a spatial spin ([`tangent_operator_inverse`]); Q does not depend on the
//! node DOFs. Units: N/m, N m/rad.

use nalgebra::{Matrix3, SMatrix, SVector, Vector3};

use super::loading::SectionMotion;
use crate::beam::rotation::{log_so3, tangent_operator_inverse};

/// Tie force vector [f_u, f_θ].
pub(crate) type TieVector = SVector<f64, 6>;
/// Tie tangent.
pub(crate) type TieMatrix = SMatrix<f64, 6, 6>;

/// Penalty tie of one helical-wire end node to its end section.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct EndTie {
    /// Tied node (index in the strand mesh / frame).
    pub node: usize,
    /// Reference position of the node (m).
    pub reference: Vector3<f64>,
    /// Reference radial unit vector (x-y plane).
    pub radial: Vector3<f64>,
    /// Translational penalty k_u (N/m).
    pub translation_penalty_n_per_m: f64,
    /// Rotational penalty k_θ (N m/rad).
    pub rotation_penalty_nm_per_rad: f64,
}

impl EndTie {
    /// Penalty force and tangent at node position `x` and rotation `lam` for the section motion
    /// `motion`.
    pub(crate) fn force_and_tangent(
        &self,
        motion: &SectionMotion,
        x: &Vector3<f64>,
        lam: &Matrix3<f64>,
        force: &mut TieVector,
        tangent: &mut TieMatrix,
    ) {
        let z = self.reference.z;
        let rsec = motion.rotation(z);
        let r = rsec * self.radial;
        let q = Matrix3::identity() - r * r.transpose();
        let du = x - motion.map(&self.reference);
        let psi = log_so3(&(lam * rsec.transpose()));
        let (ku, kr) = (
            self.translation_penalty_n_per_m,
            self.rotation_penalty_nm_per_rad,
        );
        let fu = q * du * ku;
        let fr = q * psi * kr;
        force.fixed_rows_mut::<3>(0).copy_from(&fu);
        force.fixed_rows_mut::<3>(3).copy_from(&fr);
        tangent.fill(0.0);
        tangent.fixed_view_mut::<3, 3>(0, 0).copy_from(&(q * ku));
        tangent
            .fixed_view_mut::<3, 3>(3, 3)
            .copy_from(&(q * tangent_operator_inverse(&psi) * kr));
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::beam::rotation::exp_so3;

    fn tie() -> EndTie {
        EndTie {
            node: 0,
            reference: Vector3::new(-4.3e-3, 0.0, 0.2),
            radial: Vector3::new(-1.0, 0.0, 0.0),
            translation_penalty_n_per_m: 1e9,
            rotation_penalty_nm_per_rad: 1e3,
        }
    }

    #[test]
    fn radial_displacement_and_radial_spin_carry_no_force() {
        let m = SectionMotion {
            strain: 1e-3,
            curvature_per_m: 1.0,
        };
        let t = tie();
        let r = m.rotation(0.2) * t.radial;
        let x = m.map(&t.reference) + r * 1e-5;
        let lam = exp_so3(&(r * 1e-3)) * m.rotation(0.2);
        let (mut f, mut k) = (TieVector::zeros(), TieMatrix::zeros());
        t.force_and_tangent(&m, &x, &lam, &mut f, &mut k);
        assert!(f.norm() < 1e-9 * 1e9 * 1e-5, "{f}");
    }

    #[test]
    fn tangent_matches_central_differences() {
        let m = SectionMotion {
            strain: 1e-3,
            curvature_per_m: 0.3,
        };
        let t = tie();
        let x0 = m.map(&t.reference) + Vector3::new(2e-6, -3e-6, 1e-6);
        let l0 = exp_so3(&Vector3::new(1e-4, -2e-4, 3e-4)) * m.rotation(0.2);
        let (mut f, mut k) = (TieVector::zeros(), TieMatrix::zeros());
        t.force_and_tangent(&m, &x0, &l0, &mut f, &mut k);
        for j in 0..6 {
            let h = 1e-6;
            let eval = |sgn: f64| {
                let mut d = Vector3::zeros();
                d[j % 3] = sgn * h;
                let (x, l) = if j < 3 {
                    (x0 + d, l0)
                } else {
                    (x0, exp_so3(&d) * l0)
                };
                let (mut f, mut k) = (TieVector::zeros(), TieMatrix::zeros());
                t.force_and_tangent(&m, &x, &l, &mut f, &mut k);
                f
            };
            let fd = (eval(1.0) - eval(-1.0)) / (2.0 * h);
            let scale = k[(j, j)].abs().max(1e-30);
            for i in 0..6 {
                assert!(
                    (fd[i] - k[(i, j)]).abs() < 1e-6 * scale.max(k[(i, i)].abs()),
                    "K[{i},{j}] = {} vs {}",
                    k[(i, j)],
                    fd[i]
                );
            }
        }
    }
}
