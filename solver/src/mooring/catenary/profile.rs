//! Profile of a solved single-line catenary at any unstretched arc length: position, tension and
//! curvature (Jonkman 2007, NREL/TP-500-41958, Sec. 4.2, the x(s), z(s), T_e(s) relations).
//!
//! The public argument is the unstretched arc length s measured from the fairlead (the project
//! convention); internally σ = L − s is measured from the anchor. With L_B the laid length,
//! s₀ = L_B − H/(C_B w) and Λ = max(s₀, 0):
//!
//! - on the seabed (σ ≤ L_B): z = 0, T = max(H + C_B w (σ − L_B), 0),
//!   x = σ + C_B w/(2EA) [σ² − 2 s₀ σ + s₀ Λ] for σ ≥ s₀ (x = σ where the line is slack);
//! - suspended (σ > L_B), with the vertical tension V = V_F − w (L − σ):
//!   x = x₀ + H/w [asinh(V/H) − asinh(V₀/H)] + H (σ − σ₀)/EA,
//!   z = H/w [√(1+(V/H)²) − √(1+(V₀/H)²)] + (V₀ (σ − σ₀) + w (σ − σ₀)²/2)/EA,
//!   T = √(H² + V²),
//!
//! where σ₀ is where the suspended part starts (L_B, or 0 with V₀ = V_A when fully suspended) and
//! x₀ the horizontal position there. The curvature is that of the catenary per unit unstretched
//! length, κ = w H / T² (= dθ/ds for the line angle θ = atan(V/H)); per unit stretched length it
//! is smaller by the factor 1 + T/EA. It is zero on the seabed. Positions: x horizontal from the
//! anchor towards the fairlead, z up from the anchor (m).

use super::error::CatenaryError;
use super::single::{asinh_diff, sqrt_diff, CatenarySolution};

/// State of the line at one arc length.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ProfilePoint {
    /// Horizontal position from the anchor towards the fairlead (m).
    pub x_m: f64,
    /// Height above the anchor (m).
    pub z_m: f64,
    /// Horizontal component of the tension (N).
    pub horizontal_tension_n: f64,
    /// Vertical component of the tension, positive when the line rises towards the fairlead (N).
    pub vertical_tension_n: f64,
    /// Effective tension magnitude (N).
    pub tension_n: f64,
    /// Curvature w H / T² per unit unstretched length (1/m); zero on the seabed.
    pub curvature_per_m: f64,
    /// Whether the point lies on the seabed.
    pub on_seabed: bool,
}

impl CatenarySolution {
    /// Profile at the unstretched arc length `arc_length_m` measured from the fairlead, in
    /// [0, L].
    pub fn at_arc_length_from_fairlead(
        &self,
        arc_length_m: f64,
    ) -> Result<ProfilePoint, CatenaryError> {
        let c = &self.catenary;
        let (l, w, ea, cb) = (
            c.line.length_m,
            c.line.weight_n_per_m,
            c.line.axial_stiffness_n,
            c.seabed_friction,
        );
        if !(0.0..=l).contains(&arc_length_m) {
            return Err(CatenaryError::ArcLengthOutOfRange {
                arc_length_m,
                length_m: l,
            });
        }
        let h = self.horizontal_tension_n;
        let sigma = l - arc_length_m;
        let lb = self.laid_length_m;
        if lb > 0.0 && sigma <= lb {
            let tension_n = if cb == 0.0 {
                h
            } else {
                (h + cb * w * (sigma - lb)).max(0.0)
            };
            let x_m = if cb == 0.0 {
                sigma * (1.0 + h / ea)
            } else {
                let s0 = lb - h / (cb * w);
                if sigma <= s0 {
                    sigma
                } else {
                    sigma
                        + cb * w / (2.0 * ea)
                            * (sigma * sigma - 2.0 * s0 * sigma + s0 * s0.max(0.0))
                }
            };
            return Ok(ProfilePoint {
                x_m,
                z_m: 0.0,
                horizontal_tension_n: tension_n,
                vertical_tension_n: 0.0,
                tension_n,
                curvature_per_m: 0.0,
                on_seabed: true,
            });
        }
        // Suspended part, starting at σ₀ = L_B with V₀ = 0, or at the anchor with V₀ = V_A.
        let (sigma0, v0, x0) = if lb > 0.0 {
            let seabed = self.at_arc_length_from_fairlead(l - lb)?;
            (lb, 0.0, seabed.x_m)
        } else {
            (0.0, self.fairlead_vertical_tension_n - w * l, 0.0)
        };
        let ds = sigma - sigma0;
        let v = v0 + w * ds;
        let (a, b) = (v / h, v0 / h);
        let a_minus_b = w * ds / h;
        let x_m = x0 + h / w * asinh_diff(a, b, a_minus_b) + h * ds / ea;
        let z_m = h / w * sqrt_diff(a, b, a_minus_b) + (v0 * ds + 0.5 * w * ds * ds) / ea;
        let tension_n = h.hypot(v);
        Ok(ProfilePoint {
            x_m,
            z_m,
            horizontal_tension_n: h,
            vertical_tension_n: v,
            tension_n,
            curvature_per_m: w * h / (tension_n * tension_n),
            on_seabed: false,
        })
    }
}

#[cfg(test)]
mod tests {
    use super::super::newton::CatenaryParams;
    use super::super::single::{solve_catenary, Catenary, ElasticLine};
    use super::*;

    fn solved(cb: f64, horizontal_span_m: f64) -> CatenarySolution {
        let c = Catenary {
            line: ElasticLine {
                length_m: 500.0,
                weight_n_per_m: 800.0,
                axial_stiffness_n: 2.0e7,
            },
            horizontal_span_m,
            vertical_span_m: 200.0,
            seabed_friction: cb,
        };
        solve_catenary(&c, &CatenaryParams::default()).unwrap()
    }

    #[test]
    fn profile_ends_are_the_fairlead_and_the_anchor() {
        for (cb, span) in [(0.0, 400.0), (0.2, 400.0), (5.0, 400.0), (0.0, 455.0)] {
            let sol = solved(cb, span);
            let top = sol.at_arc_length_from_fairlead(0.0).unwrap();
            let bottom = sol.at_arc_length_from_fairlead(500.0).unwrap();
            assert!(
                (top.x_m - span).abs() < 1e-7 && (top.z_m - 200.0).abs() < 1e-7,
                "{top:?}"
            );
            assert!(
                bottom.x_m.abs() < 1e-9 && bottom.z_m.abs() < 1e-9,
                "{bottom:?}"
            );
            assert!((top.tension_n - sol.fairlead_tension_n()).abs() < 1e-6 * top.tension_n);
            assert!((bottom.tension_n - sol.anchor_tension_n()).abs() < 1e-6 * top.tension_n);
        }
    }

    #[test]
    fn profile_tangent_follows_the_tension_and_its_stretch() {
        // dx/ds = (H/T)(1 + T/EA), dz/ds = (V/T)(1 + T/EA) on the suspended part, and the line
        // angle θ = atan2(dz, dx) turns at dθ/ds = w H / T² (s unstretched).
        let sol = solved(0.2, 400.0);
        let ea = 2.0e7;
        let ds = 1e-3;
        for s in [10.0, 100.0, 200.0, 280.0] {
            let p = sol.at_arc_length_from_fairlead(s).unwrap();
            let up = sol.at_arc_length_from_fairlead(s - ds).unwrap();
            let down = sol.at_arc_length_from_fairlead(s + ds).unwrap();
            let stretch = 1.0 + p.tension_n / ea;
            let dx = (up.x_m - down.x_m) / (2.0 * ds);
            let dz = (up.z_m - down.z_m) / (2.0 * ds);
            assert!((dx - p.horizontal_tension_n / p.tension_n * stretch).abs() < 1e-7);
            assert!((dz - p.vertical_tension_n / p.tension_n * stretch).abs() < 1e-7);
            let angle = |a: &ProfilePoint, b: &ProfilePoint| (a.z_m - b.z_m).atan2(a.x_m - b.x_m);
            let theta_up = angle(&up, &p);
            let theta_down = angle(&p, &down);
            let kappa_fd = (theta_up - theta_down) / ds;
            assert!(
                (kappa_fd - p.curvature_per_m).abs() < 1e-4 * p.curvature_per_m,
                "s = {s}: κ = {} vs finite difference {kappa_fd}",
                p.curvature_per_m
            );
        }
    }

    #[test]
    fn laid_tension_falls_at_the_friction_rate_and_stays_non_negative() {
        let sol = solved(5.0, 400.0);
        let touchdown = 500.0 - sol.laid_length_m;
        let a = sol.at_arc_length_from_fairlead(touchdown + 1.0).unwrap();
        let b = sol.at_arc_length_from_fairlead(touchdown + 2.0).unwrap();
        assert!(a.on_seabed && b.on_seabed);
        assert!((a.tension_n - b.tension_n - 5.0 * 800.0).abs() < 1e-6);
        let anchor = sol.at_arc_length_from_fairlead(500.0).unwrap();
        assert_eq!(anchor.tension_n, 0.0);
    }

    #[test]
    fn arc_length_outside_the_line_is_an_error() {
        let sol = solved(0.0, 400.0);
        assert!(matches!(
            sol.at_arc_length_from_fairlead(500.1),
            Err(CatenaryError::ArcLengthOutOfRange { .. })
        ));
    }
}
