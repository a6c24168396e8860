//! Linear (Airy) dispersion relation in finite depth, ω² = g k tanh(k d), solved for the
//! wavenumber k by Newton's method.
//!
//! With k₀ = ω²/g (deep-water wavenumber) and x = k d the relation reads F(x) = x tanh x − k₀d = 0.
//! F is increasing and convex for x > 0, so Newton from a point where F ≥ 0 converges
//! monotonically. The start is Fenton & McKee's (1990, Coastal Eng. 14) explicit approximation
//! x ≈ k₀d / tanh((k₀d)^¾)^⅔ (within 1.5 % everywhere) raised to the nearest point where F ≥ 0,
//! which covers the deep (x → k₀d) and shallow (x → √(k₀d)) limits alike.
//!
//! Units: ω in rad/s, d in m, k in rad/m. The module uses g = 9.81 m/s² (`GRAVITY`): the reference
//! k = 0.04026863 rad/m for T = 10 s, d = 100 m (`docs/verification.md`) is reproduced with 9.81 (k
//! = 0.040268631), not with standard gravity 9.80665 (k = 0.040282317, 3.4e-4 higher).

use super::error::{positive, WavesError};

/// Gravity used by the wave module (m/s²); the value the dispersion reference was computed with.
pub(crate) const GRAVITY: f64 = 9.81;
/// Standard gravity (m/s²), ISO 80000-3, for comparison.
pub const STANDARD_GRAVITY: f64 = 9.80665;

const MAX_ITERATIONS: usize = 50;
const TOLERANCE: f64 = 1e-15;

/// Wavenumber k (rad/m) of a linear wave of angular frequency `omega` (rad/s) in water of depth
/// `depth_m` (m), for gravity `g` (m/s²).
pub(crate) fn wavenumber_with_gravity(omega: f64, depth_m: f64, g: f64) -> Result<f64, WavesError> {
    let omega = positive("omega_rad_s", omega)?;
    let depth_m = positive("depth_m", depth_m)?;
    let g = positive("gravity_m_s2", g)?;
    let k0d = omega * omega / g * depth_m;
    let mut x = k0d / k0d.powf(0.75).tanh().powf(2.0 / 3.0);
    if !x.is_finite() {
        // k0d so small that the powers underflowed: shallow-water limit.
        x = k0d.sqrt();
    }
    let f = |x: f64| x * x.tanh() - k0d;
    // Make sure we start on the right of the root (F ≥ 0) so Newton is monotone.
    while f(x) < 0.0 {
        x *= 1.02;
    }
    let mut residual = f64::INFINITY;
    for iteration in 0..MAX_ITERATIONS {
        let th = x.tanh();
        let fx = x * th - k0d;
        residual = (fx / k0d).abs();
        if residual <= TOLERANCE {
            return Ok(x / depth_m);
        }
        let dfx = th + x * (1.0 - th * th);
        let step = fx / dfx;
        x -= step;
        if step.abs() <= 4.0 * f64::EPSILON * x {
            return Ok(x / depth_m);
        }
        if iteration == MAX_ITERATIONS - 1 {
            break;
        }
    }
    Err(WavesError::DispersionNotConverged {
        omega_rad_s: omega,
        depth_m,
        iterations: MAX_ITERATIONS,
        residual,
    })
}

/// Wavenumber k (rad/m) for angular frequency `omega` (rad/s) and depth `depth_m` (m), with
/// g = `GRAVITY`.
pub fn wavenumber(omega: f64, depth_m: f64) -> Result<f64, WavesError> {
    wavenumber_with_gravity(omega, depth_m, GRAVITY)
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::f64::consts::PI;

    #[test]
    fn ten_second_wave_in_hundred_metres_matches_reference_wavenumber() {
        let k = wavenumber(2.0 * PI / 10.0, 100.0).unwrap();
        // Reference given to 8 decimals: half a unit of the last digit is 1.2e-7 relative.
        assert!((k - 0.04026863).abs() / 0.04026863 < 1.2e-7, "k = {k}");
    }

    #[test]
    fn standard_gravity_does_not_reproduce_the_reference() {
        let k = wavenumber_with_gravity(2.0 * PI / 10.0, 100.0, STANDARD_GRAVITY).unwrap();
        assert!((k - 0.04026863).abs() / 0.04026863 > 1e-4, "k = {k}");
    }

    #[test]
    fn solution_satisfies_dispersion_relation_from_shallow_to_deep() {
        for &depth in &[0.01, 1.0, 10.0, 100.0, 1000.0, 1e5] {
            for &omega in &[1e-3, 0.05, 0.3, 1.0, 3.0, 10.0] {
                let k = wavenumber(omega, depth).unwrap();
                let lhs = GRAVITY * k * (k * depth).tanh();
                assert!(
                    (lhs - omega * omega).abs() <= 1e-13 * omega * omega,
                    "d={depth} w={omega}"
                );
            }
        }
    }

    #[test]
    fn deep_and_shallow_limits_are_recovered() {
        let omega = 2.0;
        let k_deep = wavenumber(omega, 1e4).unwrap();
        assert!((k_deep - omega * omega / GRAVITY).abs() < 1e-14 * k_deep);
        let depth = 1e-3;
        let k_shallow = wavenumber(0.01, depth).unwrap();
        let c = (GRAVITY * depth).sqrt();
        assert!((k_shallow - 0.01 / c).abs() / k_shallow < 1e-6);
    }

    #[test]
    fn non_positive_frequency_is_rejected() {
        let e = wavenumber(0.0, 100.0).unwrap_err();
        assert_eq!(e.to_string(), "omega_rad_s must be > 0, got 0");
    }
}
