//! Imposed strand kinematics: axial strain ε and curvature κ with a fixed bending axis
//! (the paper's Sec. 2.2; the strand frame of ARCHITECTURE.md, Conventions).
//!
//! The strand axis is z; bending is about y with κ > 0 bending the axis towards +x. A material
//! point of reference coordinates X = (X, Y, Z) belongs to the cross section at Z, which moves
//! rigidly (plane sections, no Poisson contraction):
//!   s = (1 + ε) Z                         (stretched arc length of the axis),
//!   φ = κ s                               (section rotation about y),
//!   c(s) = (2 sin²(φ/2)/κ, 0, sin φ/κ)    (bent axis; c = (0, 0, s) for κ = 0),
//!   x = c(s) + R_y(φ) (X, Y, 0).
//! A fibre at X stretches by (1 + ε)(1 − κ X) − 1, so x = −R sin θ (θ = π/2 the outer arc)
//! sees ε + κ R sin θ to first order. Units: m, 1/m, rad.
//!
//! [`LoadPath`] maps a load factor λ to (ε, κ): λ ∈ [0, 1] raises ε at κ = 0, λ ∈ [1, 2]
//! raises κ at the full ε. `LoadSegment` maps λ ∈ [0, 1] linearly from one (ε, κ) to another
//! (one step of a load history, [`super::history`]).

use nalgebra::{Matrix3, Vector3};

/// Rigid cross-section motion of a strand under axial strain and curvature.
#[derive(Clone, Copy, Debug, PartialEq, Default)]
pub struct SectionMotion {
    /// Axial strain ε of the strand axis.
    pub strain: f64,
    /// Curvature κ about y (1/m), positive towards +x.
    pub curvature_per_m: f64,
}

impl SectionMotion {
    /// Rotation angle φ = κ (1 + ε) Z of the section at reference axial coordinate `z_m` (rad).
    pub(crate) fn angle_rad(&self, z_m: f64) -> f64 {
        self.curvature_per_m * (1.0 + self.strain) * z_m
    }

    /// Rotation of the section at `z_m`, R_y(φ).
    pub fn rotation(&self, z_m: f64) -> Matrix3<f64> {
        let (s, c) = self.angle_rad(z_m).sin_cos();
        Matrix3::new(c, 0.0, s, 0.0, 1.0, 0.0, -s, 0.0, c)
    }

    /// Current position of the axis point of reference coordinate `z_m`.
    pub(crate) fn axis_point(&self, z_m: f64) -> Vector3<f64> {
        let s = (1.0 + self.strain) * z_m;
        let k = self.curvature_per_m;
        if k == 0.0 {
            return Vector3::new(0.0, 0.0, s);
        }
        let phi = k * s;
        let h = (0.5 * phi).sin();
        Vector3::new(2.0 * h * h / k, 0.0, phi.sin() / k)
    }

    /// Current position of the material point of reference position `reference`.
    pub fn map(&self, reference: &Vector3<f64>) -> Vector3<f64> {
        let z = reference.z;
        self.axis_point(z) + self.rotation(z) * Vector3::new(reference.x, reference.y, 0.0)
    }
}

/// Two-stage loading: tension first, then bending at constant tension.
#[derive(Clone, Copy, Debug, PartialEq, Default)]
pub struct LoadPath {
    /// Final axial strain ε.
    pub strain: f64,
    /// Final curvature κ (1/m).
    pub curvature_per_m: f64,
}

impl LoadPath {
    /// Section motion at load factor λ (λ ≤ 1: λ ε, κ = 0; λ > 1: ε, (λ − 1) κ; clamped to 2).
    pub fn at(&self, load_factor: f64) -> SectionMotion {
        let l = load_factor.clamp(0.0, 2.0);
        if l <= 1.0 {
            SectionMotion {
                strain: l * self.strain,
                curvature_per_m: 0.0,
            }
        } else {
            SectionMotion {
                strain: self.strain,
                curvature_per_m: (l - 1.0) * self.curvature_per_m,
            }
        }
    }
}

/// Straight segment in the (ε, κ) plane: λ ∈ [0, 1] from `from` to `to`.
#[derive(Clone, Copy, Debug, PartialEq, Default)]
pub(crate) struct LoadSegment {
    /// Section motion at λ = 0.
    pub from: SectionMotion,
    /// Section motion at λ = 1.
    pub to: SectionMotion,
}

impl LoadSegment {
    /// Section motion at load factor λ (clamped to [0, 1]); exactly `to` at λ = 1.
    pub(crate) fn at(&self, load_factor: f64) -> SectionMotion {
        let l = load_factor.clamp(0.0, 1.0);
        if l == 1.0 {
            return self.to;
        }
        SectionMotion {
            strain: self.from.strain + l * (self.to.strain - self.from.strain),
            curvature_per_m: self.from.curvature_per_m
                + l * (self.to.curvature_per_m - self.from.curvature_per_m),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn fibre_strain_matches_strain_plus_curvature_times_distance() {
        let m = SectionMotion {
            strain: 1e-3,
            curvature_per_m: 0.5,
        };
        let r = 8.6e-3;
        // fibre at x = −r (θ = π/2, outer arc): stretched by ≈ ε + κ r
        let (z0, z1) = (0.1, 0.1 + 1e-4);
        let a = m.map(&Vector3::new(-r, 0.0, z0));
        let b = m.map(&Vector3::new(-r, 0.0, z1));
        let strain = (b - a).norm() / (z1 - z0) - 1.0;
        let exact = (1.0 + 1e-3) * (1.0 + 0.5 * r) - 1.0;
        assert!((strain - exact).abs() < 1e-9, "{strain} vs {exact}");
    }

    #[test]
    fn bent_axis_has_the_imposed_curvature_and_bends_towards_positive_x() {
        let m = SectionMotion {
            strain: 0.0,
            curvature_per_m: 2.0,
        };
        let p = m.axis_point(0.3);
        assert!(p.x > 0.0);
        // points lie on the circle of radius 1/κ centred at (1/κ, 0, 0)
        let centre = Vector3::new(0.5, 0.0, 0.0);
        assert!(((p - centre).norm() - 0.5).abs() < 1e-14);
        // section normal stays tangent to the axis
        let t = (m.axis_point(0.3 + 1e-7) - m.axis_point(0.3 - 1e-7)) / 2e-7;
        let n = m.rotation(0.3) * Vector3::z();
        assert!((t.normalize() - n).norm() < 1e-8);
    }

    #[test]
    fn load_path_applies_tension_then_bending() {
        let p = LoadPath {
            strain: 1e-3,
            curvature_per_m: 1.0,
        };
        assert_eq!(p.at(0.5).strain, 5e-4);
        assert_eq!(p.at(0.5).curvature_per_m, 0.0);
        assert_eq!(p.at(1.5).strain, 1e-3);
        assert_eq!(p.at(1.5).curvature_per_m, 0.5);
    }
}
