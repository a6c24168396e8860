//! Finite rotations: the exponential and logarithm of SO(3) and their tangent operators.
//!
//! Convention shared by the beams, the contact element and the strand constraints: a node's
//! orientation is a rotation matrix Λ that maps the reference (material) triad to the current
//! one, and an iterative or incremental rotation is a *spatial* rotation vector θ applied from
//! the left, Λ ← exp(θ̂) Λ. The variation of a rotation-dependent vector a = Λ A is therefore
//! δa = δθ × a.

use nalgebra::{Matrix3, Vector3};

/// Below this angle (rad) series expansions replace the closed forms, which lose digits.
const SMALL_ANGLE: f64 = 1e-4;

/// Skew-symmetric matrix v̂ such that v̂ w = v × w.
pub(crate) fn skew(v: &Vector3<f64>) -> Matrix3<f64> {
    Matrix3::new(0.0, -v.z, v.y, v.z, 0.0, -v.x, -v.y, v.x, 0.0)
}

/// Axial vector of the skew-symmetric part of `m` (inverse of `skew` on skew matrices).
pub fn axial(m: &Matrix3<f64>) -> Vector3<f64> {
    0.5 * Vector3::new(
        m[(2, 1)] - m[(1, 2)],
        m[(0, 2)] - m[(2, 0)],
        m[(1, 0)] - m[(0, 1)],
    )
}

/// Rodrigues' formula: exp(θ̂) as a rotation matrix, exact to round-off for any angle.
pub fn exp_so3(theta: &Vector3<f64>) -> Matrix3<f64> {
    let a = theta.norm();
    let (c1, c2) = if a < SMALL_ANGLE {
        let a2 = a * a;
        (
            1.0 - a2 / 6.0 + a2 * a2 / 120.0,
            0.5 - a2 / 24.0 + a2 * a2 / 720.0,
        )
    } else {
        (a.sin() / a, (1.0 - a.cos()) / (a * a))
    };
    let k = skew(theta);
    Matrix3::identity() + k * c1 + k * k * c2
}

/// Rotation vector θ with exp(θ̂) = r and |θ| ≤ π.
///
/// Goes through the unit quaternion (Shepperd's branch choice on the largest of w², x², y², z²)
/// and θ = 2 atan2(|v|, w) v/|v|, which keeps full relative precision for small angles, where
/// the arccos of the trace loses half the digits.
pub fn log_so3(r: &Matrix3<f64>) -> Vector3<f64> {
    let t = r.trace();
    let (w, v) = if t >= r[(0, 0)] && t >= r[(1, 1)] && t >= r[(2, 2)] {
        let w = 0.5 * (1.0 + t).max(0.0).sqrt();
        let f = 0.25 / w;
        (
            w,
            Vector3::new(
                (r[(2, 1)] - r[(1, 2)]) * f,
                (r[(0, 2)] - r[(2, 0)]) * f,
                (r[(1, 0)] - r[(0, 1)]) * f,
            ),
        )
    } else {
        // the largest diagonal entry picks the best-conditioned component
        let i = if r[(0, 0)] >= r[(1, 1)] && r[(0, 0)] >= r[(2, 2)] {
            0
        } else if r[(1, 1)] >= r[(2, 2)] {
            1
        } else {
            2
        };
        let j = (i + 1) % 3;
        let k = (i + 2) % 3;
        let vi = 0.5 * (1.0 + r[(i, i)] - r[(j, j)] - r[(k, k)]).max(0.0).sqrt();
        let f = 0.25 / vi;
        let mut v = Vector3::zeros();
        v[i] = vi;
        v[j] = (r[(j, i)] + r[(i, j)]) * f;
        v[k] = (r[(k, i)] + r[(i, k)]) * f;
        let w = (r[(k, j)] - r[(j, k)]) * f;
        (w, v)
    };
    let (w, v) = if w < 0.0 { (-w, -v) } else { (w, v) };
    let s = v.norm();
    if s == 0.0 {
        return Vector3::zeros();
    }
    v * (2.0 * s.atan2(w) / s)
}

/// Tangent operator T(θ) of the exponential map in the spatial convention:
/// exp((θ + δθ)^) ≈ exp((T(θ) δθ)^) exp(θ̂), i.e. the spatial spin produced by a variation of the
/// rotation vector.
pub fn tangent_operator(theta: &Vector3<f64>) -> Matrix3<f64> {
    let a = theta.norm();
    let a2 = a * a;
    let (c1, c2) = if a < SMALL_ANGLE {
        (0.5 - a2 / 24.0, 1.0 / 6.0 - a2 / 120.0)
    } else {
        ((1.0 - a.cos()) / a2, (a - a.sin()) / (a2 * a))
    };
    let k = skew(theta);
    Matrix3::identity() + k * c1 + k * k * c2
}

/// Inverse of [`tangent_operator`]: the variation of the rotation vector produced by a spatial
/// spin. Valid for |θ| < 2π.
pub(crate) fn tangent_operator_inverse(theta: &Vector3<f64>) -> Matrix3<f64> {
    let a = theta.norm();
    let k = skew(theta);
    let c = if a < SMALL_ANGLE {
        1.0 / 12.0 + a * a / 720.0
    } else {
        let h = 0.5 * a;
        (1.0 - h / h.tan()) / (a * a)
    };
    Matrix3::identity() - 0.5 * k + k * k * c
}

#[cfg(test)]
mod tests {
    use super::*;

    fn sample_vectors() -> Vec<Vector3<f64>> {
        vec![
            Vector3::new(0.0, 0.0, 0.0),
            Vector3::new(1e-6, -2e-6, 3e-7),
            Vector3::new(0.3, -0.2, 0.5),
            Vector3::new(1.0, 2.0, -0.5),
            Vector3::new(0.0, 3.0, 0.0),
            Vector3::new(1e-9, 0.0, -2e-9),
            Vector3::new(-1.2, 2.0, 1.0),
            Vector3::new(0.0, 0.0, std::f64::consts::PI - 1e-7),
        ]
    }

    #[test]
    fn exp_is_orthogonal_and_log_inverts_it() {
        for th in sample_vectors() {
            let r = exp_so3(&th);
            assert!((r.transpose() * r - Matrix3::identity()).norm() < 1e-14);
            assert!((r.determinant() - 1.0).abs() < 1e-14);
            if th.norm() < std::f64::consts::PI {
                assert!((log_so3(&r) - th).norm() < 1e-12, "{th:?}");
            }
        }
    }

    #[test]
    fn tangent_operator_matches_finite_differences() {
        let h = 1e-6;
        for th in sample_vectors() {
            let t = tangent_operator(&th);
            let r0 = exp_so3(&th);
            for j in 0..3 {
                let mut e = Vector3::zeros();
                e[j] = h;
                let rp = exp_so3(&(th + e));
                let rm = exp_so3(&(th - e));
                // spatial spin: (dR/dθ_j) Rᵀ is skew with axial vector = column j of T
                let spin = axial(&((rp - rm) / (2.0 * h) * r0.transpose()));
                assert!((spin - t.column(j)).norm() < 1e-8, "θ = {th:?}, column {j}");
            }
            assert!((tangent_operator_inverse(&th) * t - Matrix3::identity()).norm() < 1e-10);
        }
    }

    #[test]
    fn log_of_a_half_turn_recovers_the_axis() {
        let axis = Vector3::new(1.0, -2.0, 2.0).normalize();
        let r = exp_so3(&(axis * std::f64::consts::PI));
        let th = log_so3(&r);
        assert!((th.norm() - std::f64::consts::PI).abs() < 1e-12);
        assert!((exp_so3(&th) - r).norm() < 1e-12);
    }
}
