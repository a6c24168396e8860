//! Hertz contact of two crossed cylinders (two wires of adjacent layers at a trellis contact).
//!
//! Johnson, *Contact Mechanics* (1985), §4.2. Two cylinders of radii R₁, R₂ whose axes cross at
//! the angle α have principal relative curvatures A ≤ B with
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
//! K and E come from the arithmetic-geometric mean (exact to rounding), arranged so that
//! K − E = K·S with S = Σ 2ⁿ⁻¹ cₙ² summed directly: no cancellation near the circular case
//! (k → 1, where a = (3PR/4E*)^(1/3) with R = 1/(2A)) nor for slender ellipses. Units: m, N, Pa,
//! rad. A non-positive normal force means an open contact (all sizes zero).

use serde::{Deserialize, Serialize};

use super::error::{positive, FrettingError};

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
    fn validate(&self, field: &'static str) -> Result<(), FrettingError> {
        positive(field, self.youngs_modulus_pa)?;
        if !(self.poisson_ratio > -1.0 && self.poisson_ratio < 0.5) {
            return Err(FrettingError::InvalidParameter {
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
        std::f64::consts::PI * self.semi_major_m * self.semi_minor_m
    }

    /// Radius of the circle of equal area, √(ab) (m).
    pub(crate) fn equivalent_radius_m(&self) -> f64 {
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
    pub fn crossed_cylinders(c: &CrossedCylinders) -> Result<Self, FrettingError> {
        positive("radius_1_m", c.radius_1_m)?;
        positive("radius_2_m", c.radius_2_m)?;
        c.material_1.validate("material_1.youngs_modulus_pa")?;
        c.material_2.validate("material_2.youngs_modulus_pa")?;
        let angle = c.crossing_angle_rad;
        if !(angle > 0.0 && angle < std::f64::consts::PI) {
            return Err(FrettingError::InvalidParameter {
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
        let e_star = 1.0
            / ((1.0 - m1.poisson_ratio.powi(2)) / m1.youngs_modulus_pa
                + (1.0 - m2.poisson_ratio.powi(2)) / m2.youngs_modulus_pa);
        let g_star = 1.0
            / ((2.0 - m1.poisson_ratio) / m1.shear_modulus_pa()
                + (2.0 - m2.poisson_ratio) / m2.shear_modulus_pa());
        Self::from_curvatures(0.5 * (sum - diff), 0.5 * (sum + diff), e_star, g_star)
    }

    /// Solves the ellipse for principal relative curvatures `a_curv ≤ b_curv` (1/m).
    pub(crate) fn from_curvatures(
        a_curv: f64,
        b_curv: f64,
        e_star: f64,
        g_star: f64,
    ) -> Result<Self, FrettingError> {
        positive("curvature_a", a_curv)?;
        positive("contact_modulus_pa", e_star)?;
        positive("shear_contact_modulus_pa", g_star)?;
        let ratio = b_curv / a_curv;
        if !(ratio >= 1.0 && ratio.is_finite()) {
            return Err(FrettingError::HertzEllipse {
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
                return Err(FrettingError::HertzEllipse {
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
        let a_cubed_per_newton =
            3.0 * k * s_over_m / (2.0 * std::f64::consts::PI * a_curv * e_star);
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
    pub fn contact(&self, normal_force_n: f64) -> Result<HertzContact, FrettingError> {
        if !normal_force_n.is_finite() {
            return Err(FrettingError::InvalidParameter {
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
        let p0 = 3.0 * normal_force_n / (2.0 * std::f64::consts::PI * a * b);
        Ok(HertzContact {
            semi_major_m: a,
            semi_minor_m: b,
            peak_pressure_pa: p0,
            approach_m: p0 * b * self.elliptic_k / self.contact_modulus_pa,
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::f64::consts::{FRAC_PI_2, PI};

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
            Err(FrettingError::InvalidParameter {
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
            Err(FrettingError::InvalidParameter {
                field: "radius_1_m",
                ..
            })
        ));
    }
}
