//! Lateral clearance between neighbouring wires of one helical layer.
//!
//! n wires of radius r on helix radius R with lay angle β: neighbours differ in phase by
//! Δ = 2π/n and share the pitch p = R / tan β per radian. Their axes are
//! x₁(u) = (R cos u, R sin u, p u), x₂(v) = (R cos(v + Δ), R sin(v + Δ), p v), whose squared
//! distance depends only on w = u − v:
//!   D²(w) = 2R² (1 − cos(w − Δ)) + p² w².
//! At its minimum the connecting segment is perpendicular to both axes, so the surfaces of the two
//! circular wires (section normal to the helix) are closest there and the clearance is
//!   c = min_w D(w) − 2r   (negative: overlap).
//! The minimiser lies in [0, Δ]; it is bracketed by sampling and refined by golden section.
//!
//! Costello (1997, *Theory of Wire Rope*, Ch. 2) approximates the section of a wire in the plane
//! normal to the strand axis by an ellipse of semi-axes r and r / cos β and obtains the helix
//! radius at which neighbours touch, R_touch = r [1 + cot²(π/n) / cos²β]^{1/2}; this is provided
//! for comparison ([`costello_touching_radius`]).

use std::f64::consts::PI;

fn distance2(w: f64, r_helix: f64, pitch: f64, delta: f64) -> f64 {
    2.0 * r_helix * r_helix * (1.0 - (w - delta).cos()) + pitch * pitch * w * w
}

/// Minimum surface gap between neighbouring wires of a layer (m); +∞ for a single wire.
pub(crate) fn lateral_clearance(
    wires: usize,
    wire_radius_m: f64,
    helix_radius_m: f64,
    lay_angle_rad: f64,
) -> f64 {
    if wires < 2 {
        return f64::INFINITY;
    }
    let delta = 2.0 * PI / wires as f64;
    let pitch = helix_radius_m / lay_angle_rad.tan();
    let f = |w: f64| distance2(w, helix_radius_m, pitch, delta);
    const SAMPLES: usize = 64;
    let h = delta / SAMPLES as f64;
    let best = (0..=SAMPLES)
        .min_by(|&a, &b| f(a as f64 * h).total_cmp(&f(b as f64 * h)))
        .unwrap_or(0);
    let (mut lo, mut hi) = (
        (best as f64 - 1.0).max(0.0) * h,
        (best as f64 + 1.0).min(SAMPLES as f64) * h,
    );
    let g = 0.5 * (5f64.sqrt() - 1.0);
    for _ in 0..100 {
        let (a, b) = (hi - g * (hi - lo), lo + g * (hi - lo));
        if f(a) < f(b) {
            hi = b;
        } else {
            lo = a;
        }
    }
    f(0.5 * (lo + hi)).sqrt() - 2.0 * wire_radius_m
}

/// Costello's (1997) approximate helix radius at which n wires of radius r and lay angle β touch.
#[cfg(test)]
pub(crate) fn costello_touching_radius(
    wires: usize,
    wire_radius_m: f64,
    lay_angle_rad: f64,
) -> f64 {
    let cot = 1.0 / (PI / wires as f64).tan();
    wire_radius_m * (1.0 + cot * cot / lay_angle_rad.cos().powi(2)).sqrt()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn straight_wires_have_the_polygon_clearance() {
        // β → 0: parallel wires, centre distance = chord 2R sin(π/n).
        let (n, r, rh) = (6, 1e-3, 3e-3);
        let c = lateral_clearance(n, r, rh, 1e-9);
        assert!((c - (2.0 * rh * (PI / n as f64).sin() - 2.0 * r)).abs() < 1e-12);
    }

    #[test]
    fn exact_touching_radius_is_close_to_costello_ellipse_approximation() {
        for (n, beta_deg) in [(6, 12.0), (11, 19.0), (35, 16.82), (5, 20.0)] {
            let (r, beta) = (2.3e-3, f64::to_radians(beta_deg));
            let approx = costello_touching_radius(n, r, beta);
            // Bisection on the exact clearance for the touching radius.
            let (mut lo, mut hi) = (r, 10.0 * approx);
            for _ in 0..200 {
                let mid = 0.5 * (lo + hi);
                if lateral_clearance(n, r, mid, beta) < 0.0 {
                    lo = mid;
                } else {
                    hi = mid;
                }
            }
            let exact = 0.5 * (lo + hi);
            assert!(
                (exact / approx - 1.0).abs() < 0.02,
                "n = {n}: exact {exact}, Costello {approx}"
            );
        }
    }
}
