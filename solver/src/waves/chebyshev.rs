//! Chebyshev interpolation in the Wheeler-stretched height, used by [`super::series`] to turn
//! component sums evaluated at a few fixed heights into values at the time-varying stretched
//! height s(t) = (z + d) d/(d + η(t)).
//!
//! Nodes on [c − h, c + h]: sₘ = c + h cos((2m + 1)π/(2M)), m = 0 … M − 1 (Chebyshev points of the
//! first kind); values are combined by the barycentric formula with weights
//! (−1)ᵐ sin((2m + 1)π/(2M)) (Berrut & Trefethen 2004, SIAM Review 46). Interpolating a function
//! f with M such nodes errs by at most hᴹ max|f⁽ᴹ⁾| / (2ᴹ⁻¹ M!). Units: m.

use super::kinematics::{depth_profiles, WaveComponent};

/// Smallest Chebyshev node count M whose interpolation bound meets the tolerance, and that bound.
///
/// For a component, C(k, s) = cosh(ks)/sinh(kd) has |∂ᴹC/∂sᴹ| ≤ kᴹ C(k, s_hi) on the interval, so
/// Chebyshev interpolation with M nodes errs by at most (k h)ᴹ / (2ᴹ⁻¹ M!) · C(k, s_hi) (the same
/// holds for S ≤ C). Summing over the components with the acceleration weights |aₙ| ωₙ² (the
/// quantity that weights high frequencies most) and dividing by the RMS horizontal acceleration
/// at the lowest stretched height gives a conservative relative bound.
pub(crate) fn chebyshev_node_count(
    comps: &[WaveComponent],
    depth: f64,
    s_lo: f64,
    s_hi: f64,
    half: f64,
    tolerance: f64,
    max_nodes: usize,
) -> (usize, f64) {
    let mut terms: Vec<(f64, f64)> = Vec::with_capacity(comps.len());
    let mut rms2 = 0.0;
    for c in comps {
        let w = c.amplitude_m.norm() * c.omega_rad_s * c.omega_rad_s;
        let (c_lo, _) = depth_profiles(c.wavenumber_rad_m, s_lo, depth);
        let (c_hi, _) = depth_profiles(c.wavenumber_rad_m, s_hi, depth);
        rms2 += 0.5 * (w * c_lo).powi(2);
        // term(M) = 2 w C_hi (kh/2)^M / M!, started at M = 0.
        terms.push((2.0 * w * c_hi, 0.5 * c.wavenumber_rad_m * half));
    }
    let scale = rms2.sqrt();
    if scale.is_nan() || scale <= 0.0 || half == 0.0 {
        return (1, 0.0);
    }
    let mut current: Vec<f64> = terms.iter().map(|t| t.0).collect();
    let mut bound = f64::INFINITY;
    for m in 1..=max_nodes {
        let mut total = 0.0;
        for (v, t) in current.iter_mut().zip(&terms) {
            *v *= t.1 / m as f64;
            total += *v;
        }
        bound = total / scale;
        if bound <= tolerance {
            return (m, bound);
        }
    }
    (max_nodes, bound)
}

/// Lagrange basis values at x for Chebyshev nodes, by the barycentric formula.
pub(crate) fn barycentric_weights(nodes: &[f64], weights: &[f64], x: f64, out: &mut [f64]) {
    for (i, &s) in nodes.iter().enumerate() {
        if x == s {
            out.fill(0.0);
            out[i] = 1.0;
            return;
        }
    }
    let mut total = 0.0;
    for ((o, &s), &w) in out.iter_mut().zip(nodes).zip(weights) {
        *o = w / (x - s);
        total += *o;
    }
    for o in out.iter_mut() {
        *o /= total;
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn barycentric_interpolation_reproduces_exponentials_to_the_bound() {
        let (c, h, k, m) = (50.0, 6.0, 0.3, 14);
        let angle = |i: usize| (2 * i + 1) as f64 * std::f64::consts::PI / (2 * m) as f64;
        let nodes: Vec<f64> = (0..m).map(|i| c + h * angle(i).cos()).collect();
        let weights: Vec<f64> = (0..m)
            .map(|i| if i % 2 == 0 { 1.0 } else { -1.0 } * angle(i).sin())
            .collect();
        let f = |s: f64| (k * (s - 100.0)).exp();
        let mut bound = f(c + h);
        for i in 1..=m {
            bound *= k * h / (2.0 * i as f64);
        }
        bound *= 2.0;
        let mut l = vec![0.0; m];
        for i in 0..=200 {
            let s = c - h + 2.0 * h * i as f64 / 200.0;
            barycentric_weights(&nodes, &weights, s, &mut l);
            let p: f64 = l.iter().zip(&nodes).map(|(w, &sn)| w * f(sn)).sum();
            assert!((p - f(s)).abs() <= bound + 1e-15 * f(c + h), "s = {s}");
        }
    }
}
