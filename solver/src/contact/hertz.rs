//! Hertz theory of the wire contacts: two elastic cylinders crossed at an angle (an elliptical
//! point contact), two parallel cylinders along a generator (a line contact), and the moduli of
//! Mindlin's tangential compliance. The strand model's contact laws and the fretting statistics
//! both read the contact from here.
//!
//! Crossed cylinders (Johnson, *Contact Mechanics*, 1985, §4.1-4.2). Cylinders of radii R₁, R₂
//! whose axes cross at the angle α have principal relative curvatures A ≤ B with
//!
//! ```text
//! A + B = ½ (1/R₁ + 1/R₂)
//! B − A = ½ √(1/R₁² + 1/R₂² + 2 cos 2α /(R₁R₂))
//! ```
//!
//! The contact is an ellipse of semi-axes a ≥ b (a along the direction of curvature A). With
//! k = b/a, e² = 1 − k², K(e), E(e) the complete elliptic integrals and E* the contact modulus
//! (1/E* = (1−ν₁²)/E₁ + (1−ν₂²)/E₂), Johnson eqs. (4.39)-(4.40) give
//!
//! ```text
//! B/A = [(a/b)² E − K] / [K − E]         (shape: depends on the geometry only)
//! A   = 3P (K − E) / (2π e² a³ E*)        (size: a ∝ P^(1/3))
//! p₀  = 3P / (2π a b),   δ = p₀ b K / E*  (peak pressure, mutual approach)
//! ```
//!
//! Since a ∝ P^(1/3), δ ∝ P^(2/3): the contact law P = K_H δ^(3/2) has one constant K_H per
//! geometry ([`HertzModel::force_coefficient`]); for equal radii at 90° the contact is circular
//! and K_H = (4/3) E* R^(1/2) (a sphere of radius R on a flat).
//!
//! K and E come from the arithmetic-geometric mean (exact to rounding), arranged so that
//! K − E = K·S with S = Σ 2ⁿ⁻¹ cₙ² summed directly: no cancellation near the circular case
//! (k → 1, where a = (3PR/4E*)^(1/3) with R = 1/(2A)) nor for slender ellipses.
//!
//! Tangential compliance (Mindlin 1949; Johnson 1985, §7.2): the initial tangential stiffness of
//! a contact of radius c is 8 G* c with 1/G* = (2 − ν₁)/G₁ + (2 − ν₂)/G₂; an elliptical contact
//! uses the radius of the circle of equal area, c = (a b)^(1/2).
//!
//! Units: m, N, Pa, rad. A non-positive normal force means an open contact (all sizes zero).

use std::f64::consts::PI;

use serde::{Deserialize, Serialize};
use thiserror::Error;

/// Why a Hertz contact could not be formed.
#[derive(Debug, Clone, PartialEq, Error)]
pub enum HertzError {
    /// A parameter is outside its admissible range.
    #[error("parameter `{field}` = {value} is invalid: {reason}")]
    InvalidParameter {
        /// Name of the parameter (struct field path).
        field: &'static str,
        /// The rejected value.
        value: f64,
        /// Why it is rejected.
        reason: &'static str,
    },
    /// The contact ellipse equation could not be solved for the given curvature ratio.
    #[error("Hertz contact ellipse not found for curvature ratio B/A = {ratio}: {reason}")]
    Ellipse {
        /// Ratio of principal relative curvatures B/A (≥ 1).
        ratio: f64,
        /// Why it failed.
        reason: &'static str,
    },
}

/// Checks that `value` is finite and strictly positive.
fn positive(field: &'static str, value: f64) -> Result<f64, HertzError> {
    if value.is_finite() && value > 0.0 {
        Ok(value)
    } else {
        Err(HertzError::InvalidParameter {
            field,
            value,
            reason: "must be finite and > 0",
        })
    }
}

/// Elastic constants of one body.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ElasticMaterial {
    /// Young's modulus (Pa).
    pub youngs_modulus_pa: f64,
    /// Poisson's ratio (−).
    pub poisson_ratio: f64,
}

impl Default for ElasticMaterial {
    /// Wire steel, as in the paper case (`docs/paper-campaign.md`: E = 210 GPa, ν = 0.3).
    fn default() -> Self {
        Self {
            youngs_modulus_pa: 210e9,
            poisson_ratio: 0.3,
        }
    }
}

impl ElasticMaterial {
    fn validate(&self, field: &'static str) -> Result<(), HertzError> {
        positive(field, self.youngs_modulus_pa)?;
        if !(self.poisson_ratio > -1.0 && self.poisson_ratio < 0.5) {
            return Err(HertzError::InvalidParameter {
                field: "poisson_ratio",
                value: self.poisson_ratio,
                reason: "must lie in (-1, 0.5)",
            });
        }
        Ok(())
    }

    /// Shear modulus G = E / (2(1 + ν)) (Pa).
    pub fn shear_modulus_pa(&self) -> f64 {
        self.youngs_modulus_pa / (2.0 * (1.0 + self.poisson_ratio))
    }
}

/// Two crossed cylinders in contact (input model).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct CrossedCylinders {
    /// Radius of the first cylinder (m).
    pub radius_1_m: f64,
    /// Radius of the second cylinder (m).
    pub radius_2_m: f64,
    /// Angle between the two axes (rad), in (0, π); π/2 for perpendicular wires.
    pub crossing_angle_rad: f64,
    /// Material of the first cylinder.
    pub material_1: ElasticMaterial,
    /// Material of the second cylinder.
    pub material_2: ElasticMaterial,
}

impl CrossedCylinders {
    /// Two cylinders of one material, radii `r1`, `r2` (m), axes crossing at `angle_rad`.
    pub fn of_one_material(r1: f64, r2: f64, angle_rad: f64, material: ElasticMaterial) -> Self {
        Self {
            radius_1_m: r1,
            radius_2_m: r2,
            crossing_angle_rad: angle_rad,
            material_1: material,
            material_2: material,
        }
    }
}

/// Size and pressure of a Hertz contact under one normal force.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct HertzContact {
    /// Semi-major axis a (m).
    pub semi_major_m: f64,
    /// Semi-minor axis b (m).
    pub semi_minor_m: f64,
    /// Peak pressure p₀ (Pa).
    pub peak_pressure_pa: f64,
    /// Mutual approach of distant points δ (m).
    pub approach_m: f64,
}

impl HertzContact {
    /// Contact area π a b (m²).
    pub fn area_m2(&self) -> f64 {
        PI * self.semi_major_m * self.semi_minor_m
    }

    /// Radius of the circle of equal area, √(ab) (m).
    pub fn equivalent_radius_m(&self) -> f64 {
        (self.semi_major_m * self.semi_minor_m).sqrt()
    }
}

/// Complete elliptic integrals from the AGM: returns (K, S) with E = K (1 − S), for the
/// complementary modulus k' = √(1 − m). Also returns S/m (→ ½ as m → 0) without cancellation.
pub(crate) fn elliptic_k_and_s(k_comp: f64) -> (f64, f64, f64) {
    let m = (1.0 - k_comp) * (1.0 + k_comp);
    let (mut a, mut b) = (1.0_f64, k_comp);
    let mut c = m.sqrt();
    // S/m = Σ 2^(n−1) cₙ²/m, with c₀²/m = 1.
    let mut s_over_m = 0.5;
    let mut weight = 0.5;
    for _ in 0..60 {
        let a_next = 0.5 * (a + b);
        let c_next = c * c / (4.0 * a_next);
        b = (a * b).sqrt();
        a = a_next;
        weight *= 2.0;
        let term = if m > 0.0 {
            weight * c_next * c_next / m
        } else {
            0.0
        };
        s_over_m += term;
        c = c_next;
        if term <= 1e-17 * s_over_m && (a - b).abs() <= 1e-16 * a {
            break;
        }
    }
    let k = std::f64::consts::FRAC_PI_2 / a;
    (k, s_over_m * m, s_over_m)
}

/// Precomputed contact of two crossed cylinders: the ellipse shape is solved once, the size
/// then scales with P^(1/3).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct HertzModel {
    /// Smaller principal relative curvature A (1/m).
    pub curvature_a: f64,
    /// Larger principal relative curvature B (1/m).
    pub curvature_b: f64,
    /// Contact modulus E* (Pa).
    pub contact_modulus_pa: f64,
    /// Shear contact modulus G* with 1/G* = (2−ν₁)/G₁ + (2−ν₂)/G₂ (Pa), for Mindlin.
    pub shear_contact_modulus_pa: f64,
    /// Axis ratio k = b/a.
    pub axis_ratio: f64,
    /// a³ / P (m³/N).
    a_cubed_per_newton: f64,
    /// K(e).
    elliptic_k: f64,
}

impl HertzModel {
    /// Solves the contact ellipse shape of two crossed cylinders.
    pub fn crossed_cylinders(c: &CrossedCylinders) -> Result<Self, HertzError> {
        positive("radius_1_m", c.radius_1_m)?;
        positive("radius_2_m", c.radius_2_m)?;
        c.material_1.validate("material_1.youngs_modulus_pa")?;
        c.material_2.validate("material_2.youngs_modulus_pa")?;
        let angle = c.crossing_angle_rad;
        if !(angle > 0.0 && angle < PI) {
            return Err(HertzError::InvalidParameter {
                field: "crossing_angle_rad",
                value: angle,
                reason: "must lie in (0, pi); parallel cylinders make a line contact",
            });
        }
        let (k1, k2) = (1.0 / c.radius_1_m, 1.0 / c.radius_2_m);
        let sum = 0.5 * (k1 + k2);
        let diff = 0.5
            * (k1 * k1 + k2 * k2 + 2.0 * k1 * k2 * (2.0 * angle).cos())
                .max(0.0)
                .sqrt();
        let (m1, m2) = (c.material_1, c.material_2);
        let (e1, nu1, e2, nu2) = (
            m1.youngs_modulus_pa,
            m1.poisson_ratio,
            m2.youngs_modulus_pa,
            m2.poisson_ratio,
        );
        let e_star = contact_modulus(e1, nu1, e2, nu2);
        let g_star = tangential_modulus(e1, nu1, e2, nu2);
        Self::from_curvatures(0.5 * (sum - diff), 0.5 * (sum + diff), e_star, g_star)
    }

    /// Solves the ellipse for principal relative curvatures `a_curv ≤ b_curv` (1/m).
    pub(crate) fn from_curvatures(
        a_curv: f64,
        b_curv: f64,
        e_star: f64,
        g_star: f64,
    ) -> Result<Self, HertzError> {
        positive("curvature_a", a_curv)?;
        positive("contact_modulus_pa", e_star)?;
        positive("shear_contact_modulus_pa", g_star)?;
        let ratio = b_curv / a_curv;
        if !(ratio >= 1.0 && ratio.is_finite()) {
            return Err(HertzError::Ellipse {
                ratio,
                reason: "B/A must be finite and >= 1",
            });
        }
        // g(k') = (a/b)²E − K over K − E = (1 − S/m)/((1 − m) S/m), decreasing in k'.
        let shape = |kp: f64| {
            let (_, _, s_over_m) = elliptic_k_and_s(kp);
            let m = (1.0 - kp) * (1.0 + kp);
            (1.0 - s_over_m) / ((1.0 - m) * s_over_m)
        };
        let kp = if ratio - 1.0 <= 1e-14 {
            1.0
        } else {
            // Bisection on ln k' over [1e-9, 1]; g(1e-9) ≈ 4e16 covers any real crossing.
            let (mut lo, mut hi) = ((1e-9_f64).ln(), 0.0_f64);
            if shape(lo.exp()) < ratio {
                return Err(HertzError::Ellipse {
                    ratio,
                    reason: "ellipse more slender than b/a = 1e-9",
                });
            }
            for _ in 0..200 {
                let mid = 0.5 * (lo + hi);
                if shape(mid.exp()) > ratio {
                    lo = mid;
                } else {
                    hi = mid;
                }
                if hi - lo < 1e-15 {
                    break;
                }
            }
            (0.5 * (lo + hi)).exp()
        };
        let (k, _, s_over_m) = elliptic_k_and_s(kp);
        // a³ = 3P (K − E) / (2π e² A E*), with (K − E)/e² = K · S/m.
        let a_cubed_per_newton = 3.0 * k * s_over_m / (2.0 * PI * a_curv * e_star);
        Ok(Self {
            curvature_a: a_curv,
            curvature_b: b_curv,
            contact_modulus_pa: e_star,
            shear_contact_modulus_pa: g_star,
            axis_ratio: kp,
            a_cubed_per_newton,
            elliptic_k: k,
        })
    }

    /// The contact under normal force `normal_force_n` (N); zero sizes when P ≤ 0.
    pub fn contact(&self, normal_force_n: f64) -> Result<HertzContact, HertzError> {
        if !normal_force_n.is_finite() {
            return Err(HertzError::InvalidParameter {
                field: "normal_force_n",
                value: normal_force_n,
                reason: "must be finite",
            });
        }
        if normal_force_n <= 0.0 {
            return Ok(HertzContact {
                semi_major_m: 0.0,
                semi_minor_m: 0.0,
                peak_pressure_pa: 0.0,
                approach_m: 0.0,
            });
        }
        let a = (self.a_cubed_per_newton * normal_force_n).cbrt();
        let b = self.axis_ratio * a;
        let p0 = 3.0 * normal_force_n / (2.0 * PI * a * b);
        Ok(HertzContact {
            semi_major_m: a,
            semi_minor_m: b,
            peak_pressure_pa: p0,
            approach_m: p0 * b * self.elliptic_k / self.contact_modulus_pa,
        })
    }

    /// Ratio B/A of the principal relative curvatures (1 for a circular contact).
    pub fn curvature_ratio(&self) -> f64 {
        self.curvature_b / self.curvature_a
    }

    /// K_H of the normal law P = K_H δ^(3/2) (N/m^(3/2)): the approach under 1 N is
    /// δ₁ = p₀ b K/E*, and δ ∝ P^(2/3).
    pub fn force_coefficient(&self) -> f64 {
        let a = self.a_cubed_per_newton.cbrt();
        let b = self.axis_ratio * a;
        let approach_per_newton =
            3.0 / (2.0 * PI * a * b) * b * self.elliptic_k / self.contact_modulus_pa;
        approach_per_newton.powf(-1.5)
    }

    /// Equivalent contact radius per P^(1/3): c = (a b)^(1/2) = `radius_coefficient` · P^(1/3)
    /// (m/N^(1/3)).
    pub fn radius_coefficient(&self) -> f64 {
        self.a_cubed_per_newton.cbrt() * self.axis_ratio.sqrt()
    }
}

/// Two elastic cylinders of radii R₁, R₂ with parallel axes touching along a generator over a
/// length ℓ (a line contact; Johnson 1985, §4.2 and §5.3). With the load per unit length
/// q = P/ℓ, the contact half-width b = (4 q R/(π E*))^{1/2}, 1/R = 1/R₁ + 1/R₂, and the approach
/// of the two axes (Johnson 1985, eq. 5.36, written for two bodies of the same material through
/// E*)
///   δ = q/(π E*) [ln(4R₁/b) + ln(4R₂/b) − 1] = q/(π E*) [ln(C/q) − 1],  C = 4π E* (R₁ + R₂).
/// Unlike the point contact, δ is not a power of q: P(δ) is found by Newton's method per
/// evaluation, and dP/dδ = π E* ℓ/(ln(C/q) − 2). The law holds while b ≪ R (q ≪ C); beyond
/// q = C e⁻³ (never reached by steel wires: b would exceed the radii) it is continued linearly.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct LineContact {
    /// E* (Pa).
    pub e_star: f64,
    /// ℓ (m).
    pub length_m: f64,
    /// C = 4π E* (R₁ + R₂) (N/m).
    pub c_n_per_m: f64,
}

impl LineContact {
    /// The line contact of cylinders of radii `r1`, `r2` (m) over `length_m`, contact modulus
    /// `e_star` (Pa).
    pub fn new(r1: f64, r2: f64, length_m: f64, e_star: f64) -> Self {
        Self {
            e_star,
            length_m,
            c_n_per_m: 4.0 * std::f64::consts::PI * e_star * (r1 + r2),
        }
    }

    /// Approach δ (m) under the load per unit length q (N/m).
    pub fn approach_m(&self, q: f64) -> f64 {
        let q_lim = self.c_n_per_m * (-3.0f64).exp();
        let k = PI * self.e_star;
        if q <= 0.0 {
            0.0
        } else if q <= q_lim {
            q / k * ((self.c_n_per_m / q).ln() - 1.0)
        } else {
            q_lim / k * 2.0 + (q - q_lim) / k
        }
    }

    /// Contact force P (N), dP/dδ (N/m) and d²P/dδ² (N/m²) at the approach `pen` (m).
    pub fn force_stiffness_and_derivative(&self, pen: f64) -> (f64, f64, f64) {
        let (p, k) = self.force_and_stiffness(pen);
        let q = p / self.length_m;
        let l = (self.c_n_per_m / q).ln();
        if p <= 0.0 || l <= 3.0 {
            return (p, k, 0.0);
        }
        // dk/dδ = (dk/dq)(dq/dδ), k = π E* ℓ/(L − 2), L = ln(C/q), dq/dδ = π E*/(L − 2)
        let ke = PI * self.e_star;
        (p, k, ke * ke * self.length_m / (q * (l - 2.0).powi(3)))
    }

    /// Contact force P (N) and its derivative dP/dδ (N/m) at the approach `pen` (m).
    pub fn force_and_stiffness(&self, pen: f64) -> (f64, f64) {
        let k = PI * self.e_star;
        let c = self.c_n_per_m;
        let q_lim = c * (-3.0f64).exp();
        if pen <= 0.0 {
            return (0.0, 0.0);
        }
        let pen_lim = self.approach_m(q_lim);
        if pen >= pen_lim {
            return (
                (q_lim + (pen - pen_lim) * k) * self.length_m,
                k * self.length_m,
            );
        }
        // Fixed point q = k δ/(ln(C/q) − 1) to start (the logarithm varies slowly), then Newton.
        let mut q = k * pen / 20.0;
        for _ in 0..3 {
            q = (k * pen / ((c / q).ln() - 1.0)).min(q_lim);
        }
        for _ in 0..60 {
            let l = (c / q).ln();
            let f = q / k * (l - 1.0) - pen;
            let df = (l - 2.0) / k;
            let next = (q - f / df).clamp(0.5 * q, (2.0 * q).min(q_lim));
            let done = (next - q).abs() <= 1e-15 * q;
            q = next;
            if done {
                break;
            }
        }
        let stiffness = k / ((c / q).ln() - 2.0);
        (q * self.length_m, stiffness * self.length_m)
    }
}

/// Contact modulus E* of two elastic bodies: 1/E* = (1 − ν₁²)/E₁ + (1 − ν₂²)/E₂.
pub fn contact_modulus(e1: f64, nu1: f64, e2: f64, nu2: f64) -> f64 {
    1.0 / ((1.0 - nu1 * nu1) / e1 + (1.0 - nu2 * nu2) / e2)
}

/// Mindlin tangential modulus G*: 1/G* = (2 − ν₁)/G₁ + (2 − ν₂)/G₂ with G = E / (2(1 + ν)).
pub fn tangential_modulus(e1: f64, nu1: f64, e2: f64, nu2: f64) -> f64 {
    let g1 = e1 / (2.0 * (1.0 + nu1));
    let g2 = e2 / (2.0 * (1.0 + nu2));
    1.0 / ((2.0 - nu1) / g1 + (2.0 - nu2) / g2)
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::f64::consts::FRAC_PI_2;

    fn steel_wires(r1: f64, r2: f64, angle: f64) -> HertzModel {
        let m = ElasticMaterial::default();
        HertzModel::crossed_cylinders(&CrossedCylinders {
            radius_1_m: r1,
            radius_2_m: r2,
            crossing_angle_rad: angle,
            material_1: m,
            material_2: m,
        })
        .unwrap()
    }

    #[test]
    fn agm_elliptic_integrals_match_abramowitz_stegun_table_17_1() {
        // A&S Table 17.1 at m = 0.5 (k' = √0.5) and m = 0.9.
        let (k, s, _) = elliptic_k_and_s(0.5_f64.sqrt());
        assert!((k - 1.854_074_677_301_372).abs() < 1e-14);
        assert!((k * (1.0 - s) - 1.350_643_881_047_675).abs() < 1e-14);
        let (k, s, _) = elliptic_k_and_s(0.1_f64.sqrt());
        assert!((k - 2.578_092_113_348_173).abs() < 1e-13);
        assert!((k * (1.0 - s) - 1.104_774_732_704_073).abs() < 1e-13);
        let (k, s, _) = elliptic_k_and_s(1.0);
        assert_eq!((k, s), (FRAC_PI_2, 0.0));
    }

    #[test]
    fn equal_perpendicular_cylinders_give_the_circular_hertz_contact() {
        // Johnson §4.2: equal radii at 90° ≡ sphere of radius R on a flat: a = (3PR/4E*)^(1/3),
        // p0 = 3P/(2πa²), δ = a²/R.
        let (r, p) = (2.3e-3, 500.0);
        let c = steel_wires(r, r, FRAC_PI_2).contact(p).unwrap();
        let e_star = 210e9 / (2.0 * (1.0 - 0.09));
        let a = (3.0 * p * r / (4.0 * e_star)).cbrt();
        assert!((c.semi_major_m / a - 1.0).abs() < 1e-12);
        assert!((c.semi_minor_m / a - 1.0).abs() < 1e-12);
        assert!((c.peak_pressure_pa / (3.0 * p / (2.0 * PI * a * a)) - 1.0).abs() < 1e-12);
        assert!((c.approach_m / (a * a / r) - 1.0).abs() < 1e-12);
    }

    #[test]
    fn strand_contact_matches_an_independent_high_precision_solution() {
        // Wires of 2.3 and 2.6 mm radius crossing at 35°, P = 800 N, steel: reference values
        // from a 30-digit solution of Johnson eqs. (4.39)-(4.40) (mpmath: ellipk/ellipe with an
        // Illinois root search on ln k), B/A = 10.10521469832709.
        let h = steel_wires(2.3e-3, 2.6e-3, 35f64.to_radians());
        assert!((h.curvature_b / h.curvature_a / 10.105_214_698_327_09 - 1.0).abs() < 1e-13);
        assert!((h.axis_ratio / 0.220_787_548_104_937_7 - 1.0).abs() < 1e-10);
        let c = h.contact(800.0).unwrap();
        assert!((c.semi_major_m / 5.599_589_440_459_96e-4 - 1.0).abs() < 1e-10);
        assert!((c.semi_minor_m / 1.236_319_622_953_455e-4 - 1.0).abs() < 1e-10);
        assert!((c.peak_pressure_pa / 5.517_526_465_887_587e9 - 1.0).abs() < 1e-10);
        assert!((c.approach_m / 1.726_608_386_938_877e-5 - 1.0).abs() < 1e-10);
    }

    #[test]
    fn ellipse_shape_agrees_with_brewe_hamrock_curve_fits() {
        // Brewe & Hamrock (1977), J. Lubr. Technol. 99: a/b ≈ 1.0339 (B/A)^0.636,
        // K ≈ 1.5277 + 0.6023 ln(B/A); fits of a few percent accuracy for 1 ≤ B/A ≤ 100 (a/b
        // within 3.1 %, K within 1 % over 1.5-50 by the exact solution above).
        for angle_deg in [20.0_f64, 30.0, 45.0, 60.0, 75.0] {
            let h = steel_wires(2.3e-3, 2.6e-3, angle_deg.to_radians());
            let ratio = h.curvature_b / h.curvature_a;
            let fit_k = 1.0 / (1.0339 * ratio.powf(0.636));
            assert!(
                (h.axis_ratio / fit_k - 1.0).abs() < 0.035,
                "{angle_deg}: {} vs {fit_k}",
                h.axis_ratio
            );
            let fit_kk = 1.5277 + 0.6023 * ratio.ln();
            assert!((h.elliptic_k / fit_kk - 1.0).abs() < 0.01, "{angle_deg}");
        }
    }

    /// Normal surface displacement (both bodies) under the Hertz pressure at an interior point,
    /// by integrating the Boussinesq kernel p/(π E* ρ) in polar coordinates about the point. The
    /// radial integral of the elliptic pressure is done in closed form, the angular one by the
    /// trapezoidal rule (smooth and periodic: converges geometrically).
    fn boussinesq_displacement(c: &HertzContact, e_star: f64, x0: f64, y0: f64) -> f64 {
        let (a, b, p0) = (c.semi_major_m, c.semi_minor_m, c.peak_pressure_pa);
        let n = 4000;
        let mut sum = 0.0;
        for k in 0..n {
            let phi = 2.0 * PI * k as f64 / n as f64;
            let (s, co) = phi.sin_cos();
            let alpha = co * co / (a * a) + s * s / (b * b);
            let beta = 2.0 * (x0 * co / (a * a) + y0 * s / (b * b));
            let gamma = 1.0 - x0 * x0 / (a * a) - y0 * y0 / (b * b);
            let disc = (beta * beta + 4.0 * alpha * gamma).sqrt();
            let (r_out, r_in) = (
                (-beta + disc) / (2.0 * alpha),
                (-beta - disc) / (2.0 * alpha),
            );
            let (mid, half) = (0.5 * (r_out + r_in), 0.5 * (r_out - r_in));
            // ∫₀^R √(h² − (ρ − mid)²) dρ.
            let integral = 0.5
                * (half * half * FRAC_PI_2
                    + mid * (half * half - mid * mid).max(0.0).sqrt()
                    + half * half * (mid / half).asin());
            sum += p0 * alpha.sqrt() * integral;
        }
        sum * (2.0 * PI / n as f64) / (PI * e_star)
    }

    #[test]
    fn elliptic_pressure_reproduces_the_hertz_gap_by_boussinesq_integration() {
        // Inside the contact the surfaces must conform: u(0,0) = δ and
        // u(0,0) − u(x,y) = A x² + B y² (Johnson §3.4 / §4.2).
        let h = steel_wires(2.3e-3, 2.3e-3, 35f64.to_radians());
        let c = h.contact(800.0).unwrap();
        assert!(c.semi_major_m > 2.0 * c.semi_minor_m);
        let e = h.contact_modulus_pa;
        let u0 = boussinesq_displacement(&c, e, 0.0, 0.0);
        assert!(
            (u0 / c.approach_m - 1.0).abs() < 1e-6,
            "{u0} vs {}",
            c.approach_m
        );
        for (fx, fy) in [(0.5, 0.0), (0.0, 0.6), (0.4, 0.4)] {
            let (x, y) = (fx * c.semi_major_m, fy * c.semi_minor_m);
            let drop = u0 - boussinesq_displacement(&c, e, x, y);
            let expected = h.curvature_a * x * x + h.curvature_b * y * y;
            assert!(
                (drop / expected - 1.0).abs() < 1e-5,
                "({fx},{fy}): {drop} vs {expected}"
            );
        }
    }

    #[test]
    fn contact_size_scales_with_the_cube_root_of_the_load_and_opens_at_zero() {
        let h = steel_wires(2.3e-3, 2.6e-3, 0.6);
        let (c1, c8) = (h.contact(100.0).unwrap(), h.contact(800.0).unwrap());
        assert!((c8.semi_major_m / c1.semi_major_m - 2.0).abs() < 1e-12);
        assert!((c8.peak_pressure_pa / c1.peak_pressure_pa - 2.0).abs() < 1e-12);
        assert_eq!(h.contact(-5.0).unwrap().peak_pressure_pa, 0.0);
        assert!(h.contact(f64::NAN).is_err());
    }

    #[test]
    fn invalid_geometry_is_rejected_with_the_field_name() {
        let m = ElasticMaterial::default();
        let bad = CrossedCylinders {
            radius_1_m: 1e-3,
            radius_2_m: 1e-3,
            crossing_angle_rad: 0.0,
            material_1: m,
            material_2: m,
        };
        assert!(matches!(
            HertzModel::crossed_cylinders(&bad),
            Err(HertzError::InvalidParameter {
                field: "crossing_angle_rad",
                ..
            })
        ));
        let bad = CrossedCylinders {
            radius_1_m: -1e-3,
            crossing_angle_rad: 1.0,
            ..bad
        };
        assert!(matches!(
            HertzModel::crossed_cylinders(&bad),
            Err(HertzError::InvalidParameter {
                field: "radius_1_m",
                ..
            })
        ));
    }
    #[test]
    fn line_contact_inverts_johnsons_approach_and_differentiates_it() {
        let (r1, r2, len, es) = (2.6e-3, 2.3e-3, 5e-3, 115.4e9);
        let l = LineContact::new(r1, r2, len, es);
        for q in [10.0, 1e3, 1e5, 1e6] {
            let delta = l.approach_m(q);
            // the two-logarithm form of Johnson's eq. 5.36
            let b = (4.0 * q * (r1 * r2 / (r1 + r2)) / (PI * es)).sqrt();
            let direct = q / (PI * es) * ((4.0 * r1 / b).ln() + (4.0 * r2 / b).ln() - 1.0);
            assert!((delta / direct - 1.0).abs() < 1e-12, "{delta} vs {direct}");
            let (p, k) = l.force_and_stiffness(delta);
            assert!((p / (q * len) - 1.0).abs() < 1e-12, "{p} vs {}", q * len);
            let h = 1e-6 * delta;
            let fd = (l.force_and_stiffness(delta + h).0 - l.force_and_stiffness(delta - h).0)
                / (2.0 * h);
            assert!((k / fd - 1.0).abs() < 1e-6, "{k} vs {fd}");
            let (_, _, dk) = l.force_stiffness_and_derivative(delta);
            let fd2 = (l.force_and_stiffness(delta + h).1 - l.force_and_stiffness(delta - h).1)
                / (2.0 * h);
            assert!((dk / fd2 - 1.0).abs() < 1e-5, "{dk} vs {fd2}");
        }
    }

    #[test]
    fn equal_cylinders_crossed_at_right_angle_give_the_sphere_on_flat_force_coefficient() {
        // K_H = (4/3) E* R^(1/2), and c = a = (3R/4E*)^(1/3) P^(1/3) (Johnson §4.2).
        let r = 2.15e-3;
        let h = steel_wires(r, r, FRAC_PI_2);
        let es = contact_modulus(210e9, 0.3, 210e9, 0.3);
        assert!((h.force_coefficient() / (4.0 / 3.0 * es * r.sqrt()) - 1.0).abs() < 1e-12);
        assert!((h.radius_coefficient() / (0.75 * r / es).cbrt() - 1.0).abs() < 1e-12);
        assert_eq!(h.curvature_ratio(), 1.0);
    }

    #[test]
    fn force_and_radius_coefficients_reproduce_the_contact_at_any_load() {
        // P = K_H δ^(3/2) and (ab)^(1/2) = c₁ P^(1/3) against the ellipse solved at that load,
        // on the strand's crossing (35°) and close to the circular limit.
        for angle in [35f64.to_radians(), FRAC_PI_2 - 1e-4] {
            let h = steel_wires(2.3e-3, 2.6e-3, angle);
            for p in [0.5, 80.0, 2_000.0] {
                let c = h.contact(p).unwrap();
                let from_law = h.force_coefficient() * c.approach_m.powf(1.5);
                assert!(
                    (from_law / p - 1.0).abs() < 1e-12,
                    "{angle}, {p}: {from_law}"
                );
                let radius = h.radius_coefficient() * p.cbrt();
                assert!((radius / c.equivalent_radius_m() - 1.0).abs() < 1e-12);
            }
        }
    }
}
