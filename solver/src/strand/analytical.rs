//! Analytical strand references used to verify the FE strand model.
//!
//! (1) Costello's theory of a simple straight strand (Costello 1997, *Theory of Wire Rope*, Ch. 3):
//!    a straight core of radius R₁ and m helical wires of radius R₂ on helix radius r₂ = R₁ + R₂
//!    with helix angle α₂ = π/2 − β (measured from the cross-section plane), axial strain ε and no
//!    strand rotation. Linearised kinematics (wire strain ξ₂, helix-angle change Δα₂, radius
//!    change Δr₂ from the Poisson contraction of core and wires):
//!      ε = ξ₂ + Δα₂ cot α₂,
//!      0 = r₂ τ_s = ξ₂ cot α₂ − Δα₂ − (Δr₂/r₂) cot α₂,
//!      Δr₂ = −ν (R₁ ε + R₂ ξ₂);
//!    changes of wire curvature and twist
//!      Δκ₂ = −2 sin α₂ cos α₂ Δα₂ / r₂ − cos²α₂ Δr₂ / r₂²,
//!      Δτ₂ = (1 − 2 sin²α₂) Δα₂ / r₂ − sin α₂ cos α₂ Δr₂ / r₂²;
//!    wire tension T₂ = E π R₂² ξ₂, bending moment G₂ = E (π R₂⁴/4) Δκ₂, twisting moment
//!    H₂ = G (π R₂⁴/2) Δτ₂, shear N₂ = H₂ κ₂ − G₂ τ₂ (κ₂ = cos²α₂/r₂, τ₂ = sin α₂ cos α₂/r₂);
//!    strand force F = E π R₁² ε + m (T₂ sin α₂ + N₂ cos α₂).
//! (2) Helical wire of a bent strand (the paper's Sec. 2.2 and [11] therein): with no slip, the
//!    axial force of a wire at angular position φ varies by ΔF = EA cos²β R κ sin φ; it starts to
//!    slip at κ_b = μ sin β T / (EA cos²β R) (`docs/verification.md`).

use std::f64::consts::PI;

/// Input of Costello's simple straight strand.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SimpleStrand {
    /// Core wire radius R₁ (m).
    pub core_radius_m: f64,
    /// Helical wire radius R₂ (m).
    pub wire_radius_m: f64,
    /// Number of helical wires m.
    pub wires: usize,
    /// Lay angle β from the strand axis (rad).
    pub lay_angle_rad: f64,
    /// Young's modulus (Pa).
    pub young_modulus_pa: f64,
    /// Poisson's ratio.
    pub poisson_ratio: f64,
}

/// Costello's response of a simple straight strand in tension without rotation.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct AxialResponse {
    /// Axial strain of the helical wires ξ₂.
    pub wire_strain: f64,
    /// Change of helix angle Δα₂ (rad).
    pub helix_angle_change_rad: f64,
    /// Change of helix radius Δr₂ (m).
    pub helix_radius_change_m: f64,
    /// Helical wire tension T₂ (N).
    pub wire_tension_n: f64,
    /// Helical wire bending moment G₂ (N m).
    pub wire_bending_moment_n_m: f64,
    /// Helical wire twisting moment H₂ (N m).
    pub wire_twisting_moment_n_m: f64,
    /// Helical wire shear force N₂ (N).
    pub wire_shear_force_n: f64,
    /// Core force (N).
    pub core_force_n: f64,
    /// Strand axial force F (N).
    pub strand_force_n: f64,
}

impl SimpleStrand {
    /// Response to the axial strain `strain` with the strand ends prevented from rotating.
    pub fn axial_response(&self, strain: f64) -> AxialResponse {
        let (r1, r2w) = (self.core_radius_m, self.wire_radius_m);
        let r2 = r1 + r2w;
        let alpha = 0.5 * PI - self.lay_angle_rad;
        let (sa, ca) = alpha.sin_cos();
        let cot = ca / sa;
        let nu = self.poisson_ratio;
        // ε = ξ₂/sin²α₂ + cot²α₂ ν (R₁ ε + R₂ ξ₂)/r₂  (τ_s = 0 eliminated)
        let xi = strain * (1.0 - nu * cot * cot * r1 / r2)
            / (1.0 / (sa * sa) + nu * cot * cot * r2w / r2);
        let dr = -nu * (r1 * strain + r2w * xi);
        let da = cot * (xi - dr / r2);
        let e = self.young_modulus_pa;
        let g = e / (2.0 * (1.0 + nu));
        let area = PI * r2w * r2w;
        let inertia = 0.25 * PI * r2w.powi(4);
        let dkappa = -2.0 * sa * ca * da / r2 - ca * ca * dr / (r2 * r2);
        let dtau = (1.0 - 2.0 * sa * sa) * da / r2 - sa * ca * dr / (r2 * r2);
        let tension = e * area * xi;
        let bending = e * inertia * dkappa;
        let twisting = g * 2.0 * inertia * dtau;
        let shear = twisting * ca * ca / r2 - bending * sa * ca / r2;
        let core = e * PI * r1 * r1 * strain;
        AxialResponse {
            wire_strain: xi,
            helix_angle_change_rad: da,
            helix_radius_change_m: dr,
            wire_tension_n: tension,
            wire_bending_moment_n_m: bending,
            wire_twisting_moment_n_m: twisting,
            wire_shear_force_n: shear,
            core_force_n: core,
            strand_force_n: core + self.wires as f64 * (tension * sa + shear * ca),
        }
    }
}

/// Stick-state variation of a helical wire's axial force in a bent strand,
/// ΔF = EA cos²β R κ sin φ (N), φ the angular position from the neutral axis.
pub fn stick_force_variation(
    axial_stiffness_n: f64,
    lay_angle_rad: f64,
    helix_radius_m: f64,
    curvature_per_m: f64,
    angle_rad: f64,
) -> f64 {
    axial_stiffness_n
        * lay_angle_rad.cos().powi(2)
        * helix_radius_m
        * curvature_per_m
        * angle_rad.sin()
}

/// Friction-limited (full slip) variation of a helical wire's axial force in a bent strand far
/// past slip onset (κ ≫ κ_b): the wire slides everywhere except at the extremes φ = ±π/2, and
/// along its length s the force changes by the friction of its radial line load q = T sin²β/R,
/// dF/ds = ±μ q. With ds = R dφ / sin β the variation is a triangle wave in φ,
/// ΔF = (π/2) μ T sin β · tri(φ), tri(φ) = 2φ/π on [−π/2, π/2], 2(π − φ)/π beyond (N).
pub fn slip_force_variation(
    friction_coefficient: f64,
    lay_angle_rad: f64,
    tension_n: f64,
    angle_rad: f64,
) -> f64 {
    let phi = (angle_rad + 0.5 * PI).rem_euclid(2.0 * PI) - 0.5 * PI;
    let tri = if phi <= 0.5 * PI {
        2.0 * phi / PI
    } else {
        2.0 * (PI - phi) / PI
    };
    0.5 * PI * friction_coefficient * tension_n * lay_angle_rad.sin() * tri
}

/// Curvature at which a helical wire of tension T starts to slip,
/// κ_b = μ sin β T / (EA cos²β R) (1/m).
pub fn slip_onset_curvature(
    friction_coefficient: f64,
    lay_angle_rad: f64,
    tension_n: f64,
    axial_stiffness_n: f64,
    helix_radius_m: f64,
) -> f64 {
    friction_coefficient * lay_angle_rad.sin() * tension_n
        / (axial_stiffness_n * lay_angle_rad.cos().powi(2) * helix_radius_m)
}
