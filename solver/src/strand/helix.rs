//! Exact helical centrelines of strand wires.
//!
//! A wire of a layer of helix radius R, lay angle β (from the strand axis z) and hand h (+1 right
//! / Z, −1 left / S) with phase φ has the centreline
//!   x(z) = (−R sin θ, R cos θ, z),  θ(z) = φ + ω z,  ω = h tan β / R  (rad/m),
//! parametrised by the axial coordinate z. θ is the angular position of the strand frame
//! (ARCHITECTURE.md, Conventions) for bending about y towards +x: θ = +π/2 at the outer arc (−x), 0
//! on the neutral axis (+y), −π/2 at the inner arc (+x); θ increases counter-clockwise about +z.
//! Arc length s = z / cos β; unit tangent t = (−R ω cos θ, −R ω sin θ, 1) cos β; principal normal n
//! = (sin θ, −cos θ, 0) (towards the axis); binormal b = t × n; curvature κ = sin²β / R, torsion τ
//! = h sin β cos β / R. The core is the straight helix R = 0 (θ = φ, t = e_z).

use nalgebra::Vector3;
use serde::{Deserialize, Serialize};

/// Hand of lay.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Hand {
    /// Right hand (Z): θ increases with z.
    Right,
    /// Left hand (S): θ decreases with z.
    Left,
}

impl Hand {
    /// +1 for right hand, −1 for left hand.
    pub fn sign(self) -> f64 {
        match self {
            Hand::Right => 1.0,
            Hand::Left => -1.0,
        }
    }
}

/// Centreline of one wire.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Helix {
    /// Helix radius R (m); 0 for the core.
    pub radius_m: f64,
    /// Lay angle β (rad); 0 for the core.
    pub lay_angle_rad: f64,
    /// Phase φ: angular position at z = 0 (rad).
    pub phase_rad: f64,
    /// Angular rate ω = dθ/dz (rad/m), signed by the hand.
    pub rate_rad_per_m: f64,
}

/// Frenet frame of a helix point.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Frame {
    /// Unit tangent.
    pub tangent: Vector3<f64>,
    /// Unit principal normal (towards the strand axis).
    pub normal: Vector3<f64>,
    /// Unit binormal t × n.
    pub binormal: Vector3<f64>,
}

impl Helix {
    /// The straight core centreline.
    pub fn straight() -> Self {
        Self {
            radius_m: 0.0,
            lay_angle_rad: 0.0,
            phase_rad: 0.0,
            rate_rad_per_m: 0.0,
        }
    }

    /// A helix of radius `radius_m`, lay angle `lay_angle_rad`, hand and phase.
    pub fn new(radius_m: f64, lay_angle_rad: f64, hand: Hand, phase_rad: f64) -> Self {
        Self {
            radius_m,
            lay_angle_rad,
            phase_rad,
            rate_rad_per_m: hand.sign() * lay_angle_rad.tan() / radius_m,
        }
    }

    /// Angular position θ(z) (rad), not wrapped.
    pub fn angle(&self, z: f64) -> f64 {
        self.phase_rad + self.rate_rad_per_m * z
    }

    /// Centreline point at axial coordinate z.
    pub fn position(&self, z: f64) -> Vector3<f64> {
        let th = self.angle(z);
        Vector3::new(-self.radius_m * th.sin(), self.radius_m * th.cos(), z)
    }

    /// Unit tangent (pointing towards +z).
    pub fn tangent(&self, z: f64) -> Vector3<f64> {
        let th = self.angle(z);
        let rw = self.radius_m * self.rate_rad_per_m;
        Vector3::new(-rw * th.cos(), -rw * th.sin(), 1.0) * self.lay_angle_rad.cos()
    }

    /// Frenet frame at z. For the core (no curvature) the normal is the inward radial direction
    /// at the phase angle, so the frame is still defined.
    pub fn frame(&self, z: f64) -> Frame {
        let th = self.angle(z);
        let tangent = self.tangent(z);
        let normal = Vector3::new(th.sin(), -th.cos(), 0.0);
        Frame {
            tangent,
            normal,
            binormal: tangent.cross(&normal),
        }
    }

    /// Arc length from z = 0 (m).
    pub(crate) fn arc_length(&self, z: f64) -> f64 {
        z / self.lay_angle_rad.cos()
    }

    /// Axial coordinate at arc length s (m).
    pub fn z_at_arc_length(&self, s: f64) -> f64 {
        s * self.lay_angle_rad.cos()
    }

    /// Curvature sin²β / R (1/m); 0 for the core.
    pub fn curvature(&self) -> f64 {
        self.radius_m * self.rate_rad_per_m.powi(2) * self.lay_angle_rad.cos().powi(2)
    }

    /// Torsion h sin β cos β / R (1/m); 0 for the core.
    pub fn torsion(&self) -> f64 {
        self.rate_rad_per_m * self.lay_angle_rad.cos().powi(2)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn tangent_is_the_normalised_derivative_and_frame_is_orthonormal() {
        let h = Helix::new(9.5e-3, 19f64.to_radians(), Hand::Left, 0.3);
        let (z, dz) = (0.041, 1e-6);
        let fd = (h.position(z + dz) - h.position(z - dz)) / (2.0 * dz);
        assert!((fd.normalize() - h.tangent(z)).norm() < 1e-9);
        assert!(
            (fd.norm() - 1.0 / h.lay_angle_rad.cos()).abs() < 1e-9,
            "ds/dz = 1/cos β"
        );
        let f = h.frame(z);
        for (a, b) in [
            (f.tangent, f.normal),
            (f.normal, f.binormal),
            (f.tangent, f.binormal),
        ] {
            assert!(a.dot(&b).abs() < 1e-14);
        }
        // Frenet: dt/ds = κ n, curvature sin²β/R.
        let dt = (h.tangent(z + dz) - h.tangent(z - dz)) / (2.0 * dz) * h.lay_angle_rad.cos();
        let kappa = h.lay_angle_rad.sin().powi(2) / h.radius_m;
        assert!((dt - kappa * f.normal).norm() < 1e-6 * kappa);
        assert!((h.curvature() - kappa).abs() < 1e-12 * kappa);
        // db/ds = −τ n, torsion h sin β cos β / R.
        let db = (h.frame(z + dz).binormal - h.frame(z - dz).binormal) / (2.0 * dz)
            * h.lay_angle_rad.cos();
        let tau = -h.lay_angle_rad.sin() * h.lay_angle_rad.cos() / h.radius_m;
        assert!((db + tau * f.normal).norm() < 1e-6 * tau.abs());
        assert!((h.torsion() - tau).abs() < 1e-12 * tau.abs());
    }

    #[test]
    fn one_lay_length_makes_one_turn() {
        let (r, beta) = (4.3e-3, 12f64.to_radians());
        let h = Helix::new(r, beta, Hand::Right, 0.0);
        let lay = 2.0 * std::f64::consts::PI * r / beta.tan();
        assert!((h.position(lay) - h.position(0.0) - Vector3::new(0.0, 0.0, lay)).norm() < 1e-15);
        assert!((h.arc_length(lay) - lay / beta.cos()).abs() < 1e-15);
        assert!((h.z_at_arc_length(h.arc_length(0.1)) - 0.1).abs() < 1e-15);
    }
}
