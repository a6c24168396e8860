//! Hertz theory for two elastic circular cylinders crossed at an angle (elliptical point contact),
//! and the Mindlin initial tangential stiffness of that contact.
//!
//! Geometry (Johnson, *Contact Mechanics*, 1985, §4.1): two bodies whose principal curvatures are
//! 1/r₁, 0 and 1/r₂, 0 (cylinders of radii r₁, r₂), with axes at angle α, have a gap
//! h = A x² + B y² near the first touching point, where
//!   A + B = ½ (1/r₁ + 1/r₂),
//!   B − A = ½ [1/r₁² + 1/r₂² + 2 cos(2α)/(r₁ r₂)]^{1/2}.
//! Elastic solution (Johnson 1985, §4.2, elliptical contact of semi-axes a ≥ b, eccentricity
//! e = (1 − b²/a²)^{1/2}, complete elliptic integrals K(e), E(e)):
//!   B/A = [(a/b)² E(e) − K(e)] / [K(e) − E(e)]            (fixes e),
//!   A   = 3 P [K(e) − E(e)] / (2π E* e² a³)                 (fixes a),
//!   δ   = 3 P K(e) / (2π a E*)                              (approach),
//! with 1/E* = (1 − ν₁²)/E₁ + (1 − ν₂²)/E₂. Since a ∝ P^{1/3}, P = K_H δ^{3/2} with a constant
//! K_H for given radii, angle and materials; computed once per contact. For α = 90° and r₁ = r₂ = r
//! the contact is circular and K_H = (4/3) E* r^{1/2} (sphere of radius r on a flat).
//!
//! Tangential stiffness (Mindlin 1949; Johnson 1985, §7.2): the initial tangential stiffness of a
//! contact of radius c is k_T = 8 G* c with 1/G* = (2 − ν₁)/G₁ + (2 − ν₂)/G₂; for the elliptical
//! contact the equivalent radius c = (a b)^{1/2} is used.
//!
//! Units: m, N, Pa; the crossing angle α in rad, α ∈ (0, π/2] (an obtuse angle is folded).

use std::f64::consts::PI;

/// Complete elliptic integrals of the first and second kind, K(e) and E(e), of modulus `e`
/// (0 ≤ e < 1), by the arithmetic-geometric mean.
pub(crate) fn elliptic_ke(e: f64) -> (f64, f64) {
    let mut a = 1.0;
    let mut b = (1.0 - e * e).sqrt();
    let mut c = e;
    let mut sum = 0.5 * c * c; // 2^{n-1} c_n², n = 0
    let mut pow2 = 0.5;
    for _ in 0..40 {
        if c.abs() < 1e-17 {
            break;
        }
        let an = 0.5 * (a + b);
        let bn = (a * b).sqrt();
        c = 0.5 * (a - b);
        a = an;
        b = bn;
        pow2 *= 2.0;
        sum += pow2 * c * c;
    }
    let k = PI / (2.0 * a);
    (k, k * (1.0 - sum))
}

/// Hertz constants of one crossed-cylinder contact.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct CrossedCylinders {
    /// K_H in P = K_H δ^{3/2} (N/m^{3/2}).
    pub force_coefficient: f64,
    /// Equivalent contact radius per P^{1/3}: c = (a b)^{1/2} = `radius_coefficient` · P^{1/3}
    /// (m/N^{1/3}).
    pub radius_coefficient: f64,
    /// Eccentricity e of the contact ellipse (0 for a circle).
    pub eccentricity: f64,
    /// Ratio B/A of the relative curvatures.
    pub curvature_ratio: f64,
}

impl CrossedCylinders {
    /// Hertz constants for cylinders of radii `r1`, `r2` (m) with axes crossing at `angle_rad`,
    /// and the contact modulus `e_star` (Pa). Returns `None` when the angle is so small that the
    /// contact ellipse degenerates (B/A > 1e8, i.e. practically parallel cylinders).
    pub fn new(r1: f64, r2: f64, angle_rad: f64, e_star: f64) -> Option<Self> {
        let mut alpha = angle_rad.rem_euclid(PI);
        if alpha > 0.5 * PI {
            alpha = PI - alpha;
        }
        let (k1, k2) = (1.0 / r1, 1.0 / r2);
        let sum = 0.5 * (k1 + k2);
        let diff = 0.5
            * (k1 * k1 + k2 * k2 + 2.0 * k1 * k2 * (2.0 * alpha).cos())
                .max(0.0)
                .sqrt();
        let a_curv = 0.5 * (sum - diff);
        let b_curv = 0.5 * (sum + diff);
        if a_curv <= 0.0 || b_curv / a_curv > 1e8 {
            return None;
        }
        let ratio = b_curv / a_curv;
        if ratio - 1.0 < 1e-9 {
            // Circular contact of equivalent radius R = 1/(2A).
            let r_eq = 0.5 / a_curv;
            let a1 = (0.75 * r_eq / e_star).cbrt();
            let delta1 = a1 * a1 / r_eq;
            return Some(Self {
                force_coefficient: delta1.powf(-1.5),
                radius_coefficient: a1,
                eccentricity: 0.0,
                curvature_ratio: 1.0,
            });
        }
        let ratio_of = |e: f64| {
            let (k, ee) = elliptic_ke(e);
            (ee / (1.0 - e * e) - k) / (k - ee)
        };
        // B/A grows monotonically from 1 (e = 0) to ∞ (e → 1): bisection in e.
        let (mut lo, mut hi) = (0.0_f64, 1.0 - 1e-15);
        for _ in 0..200 {
            let mid = 0.5 * (lo + hi);
            if ratio_of(mid) < ratio {
                lo = mid;
            } else {
                hi = mid;
            }
            if hi - lo < 1e-15 {
                break;
            }
        }
        let e = 0.5 * (lo + hi);
        let (k, ee) = elliptic_ke(e);
        let a1 = (3.0 * (k - ee) / (2.0 * PI * e_star * e * e * a_curv)).cbrt();
        let delta1 = 3.0 * k / (2.0 * PI * a1 * e_star);
        Some(Self {
            force_coefficient: delta1.powf(-1.5),
            radius_coefficient: a1 * (1.0 - e * e).powf(0.25),
            eccentricity: e,
            curvature_ratio: ratio,
        })
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
    fn elliptic_integrals_match_tabulated_values() {
        // Abramowitz & Stegun Table 17.1, m = e² = 0.5: K = 1.854074677, E = 1.350643881.
        let (k, e) = elliptic_ke(0.5_f64.sqrt());
        assert!((k - 1.854_074_677_301_372).abs() < 1e-12);
        assert!((e - 1.350_643_881_047_675).abs() < 1e-12);
        let (k0, e0) = elliptic_ke(0.0);
        assert!((k0 - PI / 2.0).abs() < 1e-15 && (e0 - PI / 2.0).abs() < 1e-15);
    }

    #[test]
    fn equal_cylinders_crossed_at_right_angle_act_as_sphere_on_flat() {
        let (r, es) = (2.15e-3, contact_modulus(210e9, 0.3, 210e9, 0.3));
        let h = CrossedCylinders::new(r, r, 0.5 * PI, es).unwrap();
        let expect = 4.0 / 3.0 * es * r.sqrt();
        assert!((h.force_coefficient / expect - 1.0).abs() < 1e-12);
        assert_eq!(h.eccentricity, 0.0);
    }

    #[test]
    fn elliptical_solution_is_continuous_with_the_circular_limit() {
        let (r, es) = (2.3e-3, 115e9);
        let circ = CrossedCylinders::new(r, r, 0.5 * PI, es).unwrap();
        let near = CrossedCylinders::new(r, r, 0.5 * PI - 1e-4, es).unwrap();
        assert!(near.eccentricity > 0.0);
        assert!((near.force_coefficient / circ.force_coefficient - 1.0).abs() < 1e-6);
        assert!((near.radius_coefficient / circ.radius_coefficient - 1.0).abs() < 1e-6);
    }

    #[test]
    fn eccentricity_reproduces_the_curvature_ratio_and_curve_fits_of_brewe_and_hamrock() {
        // Crossing angle of adjacent strand layers (≈ 37°).
        let (r, es) = (2.3e-3, 115e9);
        let h = CrossedCylinders::new(r, r, 37f64.to_radians(), es).unwrap();
        let (k, ee) = elliptic_ke(h.eccentricity);
        let e2 = h.eccentricity * h.eccentricity;
        let ratio = (ee / (1.0 - e2) - k) / (k - ee);
        assert!((ratio / h.curvature_ratio - 1.0).abs() < 1e-9);
        // Brewe & Hamrock (1977) curve fits, accurate to about 1 %: a/b ≈ 1.0339 (B/A)^0.6360,
        // E(e) ≈ 1.0003 + 0.5968 A/B.
        let kappa = (1.0 / (1.0 - e2)).sqrt();
        let approx = 1.0339 * h.curvature_ratio.powf(0.6360);
        assert!(
            (kappa / approx - 1.0).abs() < 0.01,
            "a/b = {kappa}, approx {approx}"
        );
        let e_approx = 1.0003 + 0.5968 / h.curvature_ratio;
        assert!(
            (ee / e_approx - 1.0).abs() < 0.01,
            "E = {ee}, approx {e_approx}"
        );
    }
}
