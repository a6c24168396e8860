//! MacCamy–Fuchs correction of the strip-theory inertia for large members.
//!
//! For a vertical circular cylinder of radius a in a linear wave of number k, the diffraction
//! solution (MacCamy & Fuchs 1954, Beach Erosion Board TM-69) gives the horizontal force per
//! unit length of the Morison inertia form with an effective coefficient
//!
//! ```text
//! C_M(ka) = 4 / (π (ka)² √(J₁'(ka)² + Y₁'(ka)²)),      C_M → 2 as ka → 0,
//! ```
//!
//! and a phase lead that strip theory cannot carry and which is neglected here. The correction
//! is applied for one representative wave period (e.g. the peak period of the sea state) as the
//! factor C_M(ka)/2 on the transverse Froude–Krylov + diffraction term of every member; the added
//! mass is unchanged. k follows from the finite-depth dispersion relation ω² = g k tanh(k d).
//! Bessel functions from their integral representations (Abramowitz & Stegun 9.1.21, 9.1.22 with
//! the sinh-substitution form of Y_n), integrated by composite Gauss–Legendre rules.

use std::f64::consts::PI;

/// Wave number (1/m) for angular frequency `omega` (rad/s) in depth `depth_m`, by Newton.
pub(crate) fn wave_number(omega: f64, depth_m: f64, gravity: f64) -> f64 {
    let deep = omega * omega / gravity;
    let mut k = deep.max((omega / (gravity * depth_m).sqrt()).min(10.0 * deep));
    for _ in 0..50 {
        let th = (k * depth_m).tanh();
        let f = gravity * k * th - omega * omega;
        let df = gravity * (th + k * depth_m * (1.0 - th * th));
        let dk = f / df;
        k -= dk;
        if dk.abs() < 1e-14 * k {
            break;
        }
    }
    k
}

/// 20-point Gauss–Legendre rule on [lo, hi] applied over `panels` panels.
fn integrate(f: impl Fn(f64) -> f64, lo: f64, hi: f64, panels: usize) -> f64 {
    const X: [f64; 10] = [
        0.076_526_521_133_497_33,
        0.227_785_851_141_645_08,
        0.373_706_088_715_419_56,
        0.510_867_001_950_827_1,
        0.636_053_680_726_515,
        0.746_331_906_460_150_8,
        0.839_116_971_822_218_8,
        0.912_234_428_251_326,
        0.963_971_927_277_913_8,
        0.993_128_599_185_094_9,
    ];
    const W: [f64; 10] = [
        0.152_753_387_130_725_85,
        0.149_172_986_472_603_75,
        0.142_096_109_318_382_05,
        0.131_688_638_449_176_63,
        0.118_194_531_961_518_42,
        0.101_930_119_817_240_44,
        0.083_276_741_576_704_75,
        0.062_672_048_334_109_06,
        0.040_601_429_800_386_94,
        0.017_614_007_139_152_12,
    ];
    let h = (hi - lo) / panels as f64;
    let mut sum = 0.0;
    for p in 0..panels {
        let c = lo + (p as f64 + 0.5) * h;
        for (x, w) in X.iter().zip(W.iter()) {
            sum += w * (f(c + 0.5 * h * x) + f(c - 0.5 * h * x));
        }
    }
    0.5 * h * sum
}

/// Bessel functions of the first and second kind of order n ∈ {0, 1} at x > 0.
pub(crate) fn bessel_jy(n: u32, x: f64) -> (f64, f64) {
    let nf = n as f64;
    let j = integrate(|t| (nf * t - x * t.sin()).cos(), 0.0, PI, 8) / PI;
    let y1 = integrate(|t| (x * t.sin() - nf * t).sin(), 0.0, PI, 8) / PI;
    // ∫₀^∞ (e^{nt} + (−1)ⁿ e^{−nt}) e^{−x sinh t} dt, truncated where the integrand is < 1e-18.
    let upper = ((40.0 / x).max(1.0)).asinh() + 1.0;
    let sign = if n % 2 == 0 { 1.0 } else { -1.0 };
    let y2 = integrate(
        |t| ((nf * t).exp() + sign * (-nf * t).exp()) * (-x * t.sinh()).exp(),
        0.0,
        upper,
        16,
    ) / PI;
    (j, y1 - y2)
}

/// MacCamy–Fuchs inertia coefficient C_M(ka) (2 in the long-wave limit).
pub fn inertia_coefficient(ka: f64) -> f64 {
    if ka < 1e-3 {
        return 2.0;
    }
    let (j0, y0) = bessel_jy(0, ka);
    let (j1, y1) = bessel_jy(1, ka);
    let dj1 = j0 - j1 / ka;
    let dy1 = y0 - y1 / ka;
    4.0 / (PI * ka * ka * (dj1 * dj1 + dy1 * dy1).sqrt())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn bessel_functions_match_tabulated_values() {
        // Abramowitz & Stegun, Table 9.1.
        let (j0, y0) = bessel_jy(0, 1.0);
        let (j1, y1) = bessel_jy(1, 1.0);
        assert!((j0 - 0.765_197_686_6).abs() < 1e-9);
        assert!((j1 - 0.440_050_585_7).abs() < 1e-9);
        assert!((y0 - 0.088_256_964_2).abs() < 1e-9);
        assert!((y1 + 0.781_212_821_3).abs() < 1e-9);
        let (j0, y0) = bessel_jy(0, 5.0);
        let (j1, y1) = bessel_jy(1, 5.0);
        assert!((j0 + 0.177_596_771_3).abs() < 1e-9);
        assert!((j1 + 0.327_579_137_6).abs() < 1e-9);
        assert!((y0 + 0.308_517_625_2).abs() < 1e-9);
        assert!((y1 - 0.147_863_143_4).abs() < 1e-9);
    }

    #[test]
    fn inertia_coefficient_tends_to_two_for_long_waves_and_falls_for_short_ones() {
        assert!((inertia_coefficient(0.01) - 2.0).abs() < 1e-3);
        // Small-argument expansion: J₁'(x) ≈ ½ − 3x²/16, Y₁'(x) ≈ 2/(πx²) + (ln(x/2) + γ + ½)/π
        // gives C_M(0.3) ≈ 2.071 (slightly above 2 before the diffraction fall-off).
        let x: f64 = 0.3;
        let dj = 0.5 - 3.0 * x * x / 16.0;
        let dy = 2.0 / (PI * x * x) + ((x / 2.0).ln() + 0.577_215_664_9 + 0.5) / PI;
        let series = 4.0 / (PI * x * x * (dj * dj + dy * dy).sqrt());
        assert!((inertia_coefficient(x) - series).abs() < 5e-3 * series);
        let mut last = inertia_coefficient(0.5);
        for i in 6..=30 {
            let c = inertia_coefficient(0.1 * i as f64);
            assert!(c < last, "C_M not decreasing at ka = {}", 0.1 * i as f64);
            last = c;
        }
    }

    #[test]
    fn wave_number_solves_the_dispersion_relation() {
        // Shared validation value (with g = 9.81): T = 10 s, d = 100 m → k = 0.04026863 1/m.
        let k = wave_number(2.0 * PI / 10.0, 100.0, 9.81);
        assert!((k - 0.040_268_63).abs() < 1e-8, "{k}");
    }
}
