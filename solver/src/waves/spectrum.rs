//! JONSWAP wave spectrum as defined in DNV-RP-C205 (2010) §3.5.5.
//!
//! S_PM(ω) = 5/16 · Hs² · ωp⁴ · ω⁻⁵ · exp(−5/4 · (ω/ωp)⁻⁴)            (Pierson-Moskowitz)
//! S_J(ω)  = A_γ · S_PM(ω) · γ^exp(−½ ((ω − ωp)/(σ ωp))²),   A_γ = 1 − 0.287 ln γ
//!
//! with ωp = 2π/Tp, σ = 0.07 for ω ≤ ωp and 0.09 above. When γ is not given, DNV-RP-C205
//! §3.5.5.5 prescribes γ = 5 for Tp/√Hs ≤ 3.6, γ = 1 for Tp/√Hs ≥ 5 and
//! γ = exp(5.75 − 1.15 Tp/√Hs) between (Tp in s, Hs in m).
//!
//! The formula's zeroth moment is only approximately Hs²/16 (A_γ is a fit: 1.0024 × Hs²/16 for
//! γ = 3.3), and a discretised band holds less still. [`Jonswap::renormalised`] therefore scales
//! the density so that Σ S(ωₙ) Δω = Hs²/16 exactly over the grid actually used.
//!
//! Units: S in m²·s/rad, ω in rad/s (one-sided spectrum, m0 = ∫ S dω = variance of η).

use std::f64::consts::PI;

use super::error::{positive, WavesError};

/// How the JONSWAP peak-enhancement factor γ is chosen.
#[derive(Debug, Clone, Copy, PartialEq, Default, serde::Serialize, serde::Deserialize)]
pub enum PeakEnhancement {
    /// γ given explicitly; accepted in [1, 7], the range spanned by the DNV default rule.
    Given(f64),
    /// γ from Tp/√Hs by the DNV-RP-C205 §3.5.5.5 rule.
    #[default]
    DnvDefault,
}

/// Spectral width parameter below and above the peak (DNV-RP-C205 §3.5.5.1).
const SIGMA_BELOW: f64 = 0.07;
const SIGMA_ABOVE: f64 = 0.09;
/// Upper integration limit, in multiples of ωp, beyond which the ω⁻⁵ tail is integrated
/// analytically.
const TAIL_START: f64 = 30.0;
/// Integration intervals per ωp for the numerical moments.
const STEPS_PER_OMEGA_P: usize = 1000;

/// A JONSWAP spectrum with validated parameters and a scale factor (1 for the raw formula).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Jonswap {
    hs_m: f64,
    tp_s: f64,
    gamma: f64,
    omega_p: f64,
    a_gamma: f64,
    scale: f64,
}

/// DNV-RP-C205 §3.5.5.5 default γ from Tp/√Hs.
pub(crate) fn dnv_default_gamma(hs_m: f64, tp_s: f64) -> f64 {
    let r = tp_s / hs_m.sqrt();
    if r <= 3.6 {
        5.0
    } else if r >= 5.0 {
        1.0
    } else {
        (5.75 - 1.15 * r).exp()
    }
}

impl Jonswap {
    /// Spectrum for significant wave height `hs_m` (m) and peak period `tp_s` (s).
    pub fn new(hs_m: f64, tp_s: f64, peak: PeakEnhancement) -> Result<Self, WavesError> {
        let hs_m = positive("hs_m", hs_m)?;
        if !(hs_m * hs_m).is_normal() {
            // Hs² underflows: every density would be zero or subnormal and the band undefined.
            return Err(WavesError::InvalidParameter {
                field: "hs_m",
                value: hs_m,
                rule: "large enough that Hs² is a normal number (Hs > 1.5e-154 m)",
            });
        }
        let tp_s = positive("tp_s", tp_s)?;
        let gamma = match peak {
            PeakEnhancement::Given(g) => {
                if !(g.is_finite() && (1.0..=7.0).contains(&g)) {
                    return Err(WavesError::InvalidParameter {
                        field: "gamma",
                        value: g,
                        rule: "in [1, 7]",
                    });
                }
                g
            }
            PeakEnhancement::DnvDefault => dnv_default_gamma(hs_m, tp_s),
        };
        Ok(Self {
            hs_m,
            tp_s,
            gamma,
            omega_p: 2.0 * PI / tp_s,
            a_gamma: 1.0 - 0.287 * gamma.ln(),
            scale: 1.0,
        })
    }

    /// Significant wave height (m).
    pub fn hs_m(&self) -> f64 {
        self.hs_m
    }
    /// Peak period (s).
    pub fn tp_s(&self) -> f64 {
        self.tp_s
    }
    /// Peak-enhancement factor γ actually used.
    pub fn gamma(&self) -> f64 {
        self.gamma
    }
    /// Peak angular frequency ωp = 2π/Tp (rad/s).
    pub fn peak_omega_rad_s(&self) -> f64 {
        self.omega_p
    }
    /// Factor applied on top of the DNV formula (1 until renormalised).
    pub fn scale(&self) -> f64 {
        self.scale
    }

    /// The DNV-RP-C205 formula S_J(ω) (m²s/rad), without renormalisation. Zero for ω ≤ 0.
    pub fn formula_density(&self, omega: f64) -> f64 {
        if omega <= 0.0 {
            return 0.0;
        }
        let wp = self.omega_p;
        let x = wp / omega;
        let x4 = x * x * x * x;
        let s_pm = 5.0 / 16.0 * self.hs_m * self.hs_m * x4 / omega * (-1.25 * x4).exp();
        let sigma = if omega <= wp {
            SIGMA_BELOW
        } else {
            SIGMA_ABOVE
        };
        let r = (omega - wp) / (sigma * wp);
        self.a_gamma * s_pm * self.gamma.powf((-0.5 * r * r).exp())
    }

    /// Spectral density S(ω) = scale · S_J(ω) (m²s/rad).
    pub fn density(&self, omega: f64) -> f64 {
        self.scale * self.formula_density(omega)
    }

    /// Zeroth moment ∫₀^∞ S_J dω of the raw formula (m²), by composite Simpson up to 30 ωp plus
    /// the analytic ω⁻⁵ tail beyond (relative accuracy better than 1e-8).
    pub fn formula_m0(&self) -> f64 {
        let wp = self.omega_p;
        let n = 2 * ((TAIL_START as usize * STEPS_PER_OMEGA_P) / 2);
        let h = TAIL_START * wp / n as f64;
        let mut sum = self.formula_density(0.0) + self.formula_density(TAIL_START * wp);
        for i in 1..n {
            let w = if i % 2 == 1 { 4.0 } else { 2.0 };
            sum += w * self.formula_density(i as f64 * h);
        }
        sum * h / 3.0 + self.tail_beyond(TAIL_START * wp)
    }

    /// ∫_ω^∞ S_J dω for ω far above the peak, where S_J ≈ A_γ · 5/16 Hs² ωp⁴ ω⁻⁵.
    fn tail_beyond(&self, omega: f64) -> f64 {
        self.a_gamma * 5.0 / 64.0 * self.hs_m * self.hs_m * (self.omega_p / omega).powi(4)
    }

    /// Band [ω_min, ω_max] (rad/s) holding the fraction `kept` of the formula's m0, with equal
    /// shares (1 − kept)/2 left out below and above.
    pub fn band(&self, kept: f64) -> Result<(f64, f64), WavesError> {
        if !(kept.is_finite() && kept > 0.0 && kept < 1.0) {
            return Err(WavesError::InvalidParameter {
                field: "band_energy_fraction",
                value: kept,
                rule: "in (0, 1)",
            });
        }
        let wp = self.omega_p;
        let n = TAIL_START as usize * STEPS_PER_OMEGA_P;
        let h = TAIL_START * wp / n as f64;
        let total = self.formula_m0();
        let lo_target = 0.5 * (1.0 - kept) * total;
        let hi_target = total - lo_target;
        let (mut omega_min, mut omega_max) = (None, None);
        let mut cum = 0.0;
        let mut prev = self.formula_density(0.0);
        for i in 1..=n {
            let cur = self.formula_density(i as f64 * h);
            let step = 0.5 * (prev + cur) * h;
            let next = cum + step;
            // Linear interpolation of the cumulative integral inside the interval.
            let locate = |target: f64| (i - 1) as f64 * h + h * (target - cum) / step;
            if omega_min.is_none() && next >= lo_target {
                omega_min = Some(locate(lo_target));
            }
            if omega_max.is_none() && next >= hi_target {
                omega_max = Some(locate(hi_target));
                break;
            }
            cum = next;
            prev = cur;
        }
        // Upper edge beyond 30 ωp only for kept fractions extremely close to 1: use the tail law.
        let omega_max = omega_max.unwrap_or_else(|| {
            wp * (self.a_gamma * 5.0 / 64.0 * self.hs_m * self.hs_m / lo_target).powf(0.25)
        });
        Ok((omega_min.unwrap_or(0.0), omega_max))
    }

    /// Copy scaled so that Σ S(ωₙ)·Δω = Hs²/16 over the given grid.
    pub fn renormalised(&self, omegas: &[f64], d_omega: f64) -> Result<Self, WavesError> {
        let m0: f64 = omegas.iter().map(|&w| self.formula_density(w)).sum::<f64>() * d_omega;
        if m0.is_nan() || m0 <= 0.0 {
            return Err(WavesError::EmptyBand {
                omega_min_rad_s: omegas.first().copied().unwrap_or(0.0),
                omega_max_rad_s: omegas.last().copied().unwrap_or(0.0),
                d_omega_rad_s: d_omega,
            });
        }
        Ok(Self {
            scale: self.hs_m * self.hs_m / 16.0 / m0,
            ..*self
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn rel(a: f64, b: f64) -> f64 {
        (a - b).abs() / b.abs()
    }

    #[test]
    fn peak_density_matches_dnv_formula_reference_for_gamma_one_and_three_point_three() {
        // DNV-RP-C205 §3.5.5 (`docs/verification.md`): Hs = 2 m, Tp = 10 s.
        let s1 = Jonswap::new(2.0, 10.0, PeakEnhancement::Given(1.0)).unwrap();
        let s33 = Jonswap::new(2.0, 10.0, PeakEnhancement::Given(3.3)).unwrap();
        let wp = s1.peak_omega_rad_s();
        assert!(rel(s1.formula_density(wp), 0.569983) < 1e-5);
        assert!(rel(s33.formula_density(wp), 1.236428) < 1e-5);
    }

    #[test]
    fn pierson_moskowitz_m0_is_hs_squared_over_16() {
        let s = Jonswap::new(2.0, 10.0, PeakEnhancement::Given(1.0)).unwrap();
        assert!(
            rel(s.formula_m0(), 0.25) < 1e-8,
            "{}",
            s.formula_m0() / 0.25
        );
    }

    #[test]
    fn dnv_default_gamma_follows_the_three_regimes() {
        assert_eq!(dnv_default_gamma(4.0, 7.0), 5.0); // Tp/√Hs = 3.5
        assert_eq!(dnv_default_gamma(4.0, 10.0), 1.0); // 5.0
        assert!(rel(dnv_default_gamma(4.0, 8.0), (5.75f64 - 1.15 * 4.0).exp()) < 1e-15);
    }

    #[test]
    fn invalid_parameters_name_the_field() {
        let e = Jonswap::new(2.0, -1.0, PeakEnhancement::DnvDefault).unwrap_err();
        assert_eq!(e.to_string(), "tp_s must be > 0, got -1");
        let e = Jonswap::new(0.0, 10.0, PeakEnhancement::DnvDefault).unwrap_err();
        assert_eq!(e.to_string(), "hs_m must be > 0, got 0");
        let tiny = Jonswap::new(1e-160, 10.0, PeakEnhancement::Given(1.0)).unwrap_err();
        assert!(
            tiny.to_string().starts_with("hs_m must be large enough"),
            "{tiny}"
        );
        let e = Jonswap::new(2.0, 10.0, PeakEnhancement::Given(0.5)).unwrap_err();
        assert_eq!(e.to_string(), "gamma must be in [1, 7], got 0.5");
        let e = Jonswap::new(f64::NAN, 10.0, PeakEnhancement::DnvDefault).unwrap_err();
        assert!(matches!(
            e,
            WavesError::InvalidParameter { field: "hs_m", .. }
        ));
    }

    #[test]
    fn band_keeps_the_requested_energy_fraction() {
        let s = Jonswap::new(8.75, 16.5, PeakEnhancement::Given(1.3)).unwrap();
        let (lo, hi) = s.band(0.99).unwrap();
        assert!(lo < s.peak_omega_rad_s() && hi > s.peak_omega_rad_s());
        // Simpson over the band must give 99 % of the total.
        let n = 20_000;
        let h = (hi - lo) / n as f64;
        let mut sum = s.formula_density(lo) + s.formula_density(hi);
        for i in 1..n {
            sum += if i % 2 == 1 { 4.0 } else { 2.0 } * s.formula_density(lo + i as f64 * h);
        }
        let kept = sum * h / 3.0 / s.formula_m0();
        assert!((kept - 0.99).abs() < 1e-5, "kept {kept}");
    }

    #[test]
    fn renormalised_spectrum_has_exact_discrete_m0() {
        let s = Jonswap::new(2.0, 10.0, PeakEnhancement::Given(3.3)).unwrap();
        let dw = 0.01;
        let omegas: Vec<f64> = (30..300).map(|n| n as f64 * dw).collect();
        let r = s.renormalised(&omegas, dw).unwrap();
        let m0: f64 = omegas.iter().map(|&w| r.density(w)).sum::<f64>() * dw;
        assert!(rel(m0, 0.25) < 1e-13);
    }
}
