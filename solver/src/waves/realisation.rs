//! Seeded random realisations of a Gaussian sea ([`IrregularSea`]) and single regular Airy waves
//! ([`RegularWave`]), both sampled through [`SeaKinematics`].
//!
//! Frequency grid: ωₙ = n Δω with Δω = 2π/T_repeat, so the realisation repeats exactly after
//! T_repeat ≥ the simulated duration (default: the smallest power of two of seconds, 2^m s, that
//! is ≥ the duration, e.g. 1024 s for 1000 s, which also makes FFT grids power-of-two sized).
//!
//! Band: the components n with ω_min ≤ nΔω ≤ ω_max, where [ω_min, ω_max] leaves out
//! (1 − `band_energy_fraction`)/2 of the formula's m0 on each side (default fraction 0.995: 0.25 %
//! cut below and above the band). The spectrum is then renormalised so that Σ S(ωₙ)Δω = Hs²/16
//! over the kept components, i.e. the cut energy is redistributed proportionally.
//!
//! Random amplitudes (a Gaussian sea, not the random-phase approximation):
//! aₙ = √(S(ωₙ)Δω) (Xₙ + i Yₙ), Xₙ, Yₙ independent standard normals, so E|aₙ|²/2 = S(ωₙ)Δω.
//! The normals come from ChaCha20 (`rand_chacha`, seeded by `seed_from_u64`, whose output stream
//! is fixed by the algorithm) through a Box–Muller transform written here, so the amplitudes do
//! not depend on the version of a distribution crate. The pair (Xₙ, Yₙ) is drawn in increasing n.
//! The uniform numbers are bit-identical everywhere; ln, sin and cos come from the platform's
//! math library, whose results agree to the last unit in the last place on mainstream targets.

use std::f64::consts::PI;

use nalgebra::{Complex, Vector3};
use rand::{RngCore, SeedableRng};
use rand_chacha::ChaCha20Rng;

use super::dispersion::wavenumber;
use super::error::{finite, positive, WavesError};
use super::kinematics::{AiryField, WaveComponent};
use super::sea::{FluidKinematics, SeaKinematics};
use super::spectrum::Jonswap;

/// How the repeat period of a realisation is chosen.
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize, serde::Deserialize)]
pub enum RepeatPeriod {
    /// Smallest 2^m seconds (m ≥ 0) that is ≥ the duration.
    NextPowerOfTwo,
    /// Given repeat period (s), which must be ≥ the duration.
    Given(f64),
}

/// Parameters of an irregular-sea realisation.
#[derive(Debug, Clone, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct RealisationParams {
    /// Simulated duration the realisation must not repeat within (s).
    pub duration_s: f64,
    /// Repeat period choice.
    pub repeat_period: RepeatPeriod,
    /// Fraction of the spectrum's m0 inside the discretised band, in (0, 1).
    pub band_energy_fraction: f64,
    /// Seed of the ChaCha20 stream.
    pub seed: u64,
    /// Propagation heading β (rad, from +x towards +y).
    pub heading_rad: f64,
    /// Water depth (m).
    pub depth_m: f64,
    /// Water density (kg/m³).
    pub water_density_kg_m3: f64,
    /// Highest component frequency kept (rad/s): components of the band above it are dropped
    /// after the renormalisation, so the kept ones are exactly those of the uncut realisation
    /// (same amplitudes and phases) and the energy above the cut-off is removed, not
    /// redistributed; a cut-off below the whole band leaves a calm sea. `None` keeps the whole
    /// band.
    #[serde(default)]
    pub cut_off_rad_s: Option<f64>,
}

impl Default for RealisationParams {
    fn default() -> Self {
        Self {
            duration_s: 1000.0,
            repeat_period: RepeatPeriod::NextPowerOfTwo,
            band_energy_fraction: 0.995,
            seed: 0,
            heading_rad: 0.0,
            depth_m: 100.0,
            water_density_kg_m3: 1025.0,
            cut_off_rad_s: None,
        }
    }
}

impl RealisationParams {
    /// Repeat period (s) after validating the duration and the choice.
    pub(crate) fn repeat_period_s(&self) -> Result<f64, WavesError> {
        let duration = positive("duration_s", self.duration_s)?;
        match self.repeat_period {
            RepeatPeriod::NextPowerOfTwo => {
                let mut t = 1.0;
                while t < duration {
                    t *= 2.0;
                }
                Ok(t)
            }
            RepeatPeriod::Given(t) => {
                if t.is_finite() && t >= duration {
                    Ok(t)
                } else {
                    Err(WavesError::InvalidParameter {
                        field: "repeat_period_s",
                        value: t,
                        rule: ">= duration_s",
                    })
                }
            }
        }
    }
}

/// Standard normal pairs from a ChaCha20 stream by the Box–Muller transform.
#[derive(Debug, Clone)]
pub struct NormalPairs {
    rng: ChaCha20Rng,
}

impl NormalPairs {
    /// Stream for `seed`.
    pub fn new(seed: u64) -> Self {
        Self {
            rng: ChaCha20Rng::seed_from_u64(seed),
        }
    }

    /// Uniform number in (0, 1] with 53 random bits.
    fn uniform_open0(&mut self) -> f64 {
        ((self.rng.next_u64() >> 11) + 1) as f64 * (1.0 / (1u64 << 53) as f64)
    }

    /// Next pair of independent standard normals.
    pub fn next_pair(&mut self) -> (f64, f64) {
        let u1 = self.uniform_open0();
        let u2 = self.uniform_open0();
        let r = (-2.0 * u1.ln()).sqrt();
        let (s, c) = (2.0 * PI * u2).sin_cos();
        (r * c, r * s)
    }
}

/// A seeded random realisation of a JONSWAP sea.
#[derive(Debug, Clone, PartialEq)]
pub struct IrregularSea {
    field: AiryField,
    /// The renormalised spectrum; `None` for a calm sea.
    spectrum: Option<Jonswap>,
    repeat_period_s: f64,
    d_omega: f64,
    band_rad_s: (f64, f64),
    /// Fraction of the renormalised band's m0 carried by the kept components.
    kept_m0_fraction: f64,
}

impl IrregularSea {
    /// Realisation of `spectrum` (its Hs, Tp, γ; its scale is ignored and recomputed) with
    /// `params`.
    pub fn new(spectrum: &Jonswap, params: &RealisationParams) -> Result<Self, WavesError> {
        let t_rep = params.repeat_period_s()?;
        let depth = positive("depth_m", params.depth_m)?;
        let rho = positive("water_density_kg_m3", params.water_density_kg_m3)?;
        let heading = finite("heading_rad", params.heading_rad)?;
        let cut_off = match params.cut_off_rad_s {
            Some(w) => positive("cut_off_rad_s", w)?,
            None => f64::INFINITY,
        };
        let d_omega = 2.0 * PI / t_rep;
        let (lo, hi) = spectrum.band(params.band_energy_fraction)?;
        // A band that is not finite, or wider than 10⁷ components (a duration of years), is
        // refused rather than allocated.
        let components_in_band = hi / d_omega;
        if !(lo.is_finite() && components_in_band.is_finite()) {
            return Err(WavesError::EmptyBand {
                omega_min_rad_s: lo,
                omega_max_rad_s: hi,
                d_omega_rad_s: d_omega,
            });
        }
        if components_in_band >= 1e7 {
            return Err(WavesError::BandTooWide {
                omega_min_rad_s: lo,
                omega_max_rad_s: hi,
                components: components_in_band.floor(),
                d_omega_rad_s: d_omega,
            });
        }
        let n_lo = ((lo / d_omega).ceil() as usize).max(1);
        let n_hi = components_in_band.floor() as usize;
        if n_hi < n_lo {
            return Err(WavesError::EmptyBand {
                omega_min_rad_s: lo,
                omega_max_rad_s: hi,
                d_omega_rad_s: d_omega,
            });
        }
        let omegas: Vec<f64> = (n_lo..=n_hi).map(|n| n as f64 * d_omega).collect();
        let spectrum = spectrum.renormalised(&omegas, d_omega)?;
        let mut normals = NormalPairs::new(params.seed);
        let mut components = Vec::with_capacity(omegas.len());
        let (mut kept_m0, mut band_m0) = (0.0, 0.0);
        for &omega in &omegas {
            // Drawn for every component of the band, so a cut leaves the others unchanged.
            let (x, y) = normals.next_pair();
            let scale = (spectrum.density(omega) * d_omega).sqrt();
            band_m0 += scale * scale;
            if omega > cut_off {
                continue;
            }
            kept_m0 += scale * scale;
            components.push(WaveComponent {
                omega_rad_s: omega,
                wavenumber_rad_m: wavenumber(omega, depth)?,
                amplitude_m: Complex::new(scale * x, scale * y),
            });
        }
        Ok(Self {
            field: AiryField::new(components, depth, heading, rho),
            spectrum: Some(spectrum),
            repeat_period_s: t_rep,
            d_omega,
            band_rad_s: (lo, hi),
            kept_m0_fraction: kept_m0 / band_m0,
        })
    }

    /// Still water: no components, over the repeat period, depth and density of `params` (its
    /// seed, band and cut-off play no part).
    pub fn calm(params: &RealisationParams) -> Result<Self, WavesError> {
        let t_rep = params.repeat_period_s()?;
        let depth = positive("depth_m", params.depth_m)?;
        let rho = positive("water_density_kg_m3", params.water_density_kg_m3)?;
        let heading = finite("heading_rad", params.heading_rad)?;
        Ok(Self {
            field: AiryField::new(Vec::new(), depth, heading, rho),
            spectrum: None,
            repeat_period_s: t_rep,
            d_omega: 2.0 * PI / t_rep,
            band_rad_s: (0.0, 0.0),
            kept_m0_fraction: 1.0,
        })
    }

    /// The underlying component field.
    pub fn field(&self) -> &AiryField {
        &self.field
    }
    /// The spectrum as renormalised over the kept components; `None` for a calm sea.
    pub fn spectrum(&self) -> Option<&Jonswap> {
        self.spectrum.as_ref()
    }
    /// Significant wave height of the spectrum (m); 0 for a calm sea.
    pub fn hs_m(&self) -> f64 {
        self.spectrum.as_ref().map_or(0.0, Jonswap::hs_m)
    }
    /// Repeat period T_repeat (s).
    pub(crate) fn repeat_period_s(&self) -> f64 {
        self.repeat_period_s
    }
    /// Frequency step Δω = 2π/T_repeat (rad/s).
    pub fn d_omega_rad_s(&self) -> f64 {
        self.d_omega
    }
    /// Band [ω_min, ω_max] (rad/s) chosen from the spectrum before snapping to the grid.
    pub(crate) fn band_rad_s(&self) -> (f64, f64) {
        self.band_rad_s
    }
    /// Fraction of the spectrum's m0 (Hs²/16 over the band) carried by the kept components: 1
    /// without a cut-off.
    pub fn kept_m0_fraction(&self) -> f64 {
        self.kept_m0_fraction
    }
    /// Variance of η of this realisation over one repeat period, Σ|aₙ|²/2 (m²).
    pub fn realised_m0(&self) -> f64 {
        self.field
            .components()
            .iter()
            .map(|c| 0.5 * c.amplitude_m.norm_sqr())
            .sum()
    }
}

impl SeaKinematics for IrregularSea {
    fn kinematics(&self, x: &Vector3<f64>, t: f64) -> FluidKinematics {
        self.field.kinematics(x, t)
    }
    fn elevation(&self, x: f64, y: f64, t: f64) -> f64 {
        self.field.elevation(x, y, t)
    }
}

/// A regular linear (Airy) wave, η = H/2 cos(ω t − k x_β + φ).
#[derive(Debug, Clone, PartialEq)]
pub struct RegularWave {
    field: AiryField,
}

impl RegularWave {
    /// Wave of height `height_m` (crest to trough), period `period_s`, phase `phase_rad`,
    /// heading `heading_rad`, in depth `depth_m` of water of density `water_density_kg_m3`.
    pub fn new(
        height_m: f64,
        period_s: f64,
        phase_rad: f64,
        heading_rad: f64,
        depth_m: f64,
        water_density_kg_m3: f64,
    ) -> Result<Self, WavesError> {
        let height_m = positive("height_m", height_m)?;
        let period_s = positive("period_s", period_s)?;
        let phase_rad = finite("phase_rad", phase_rad)?;
        let heading_rad = finite("heading_rad", heading_rad)?;
        let depth_m = positive("depth_m", depth_m)?;
        let rho = positive("water_density_kg_m3", water_density_kg_m3)?;
        let omega = 2.0 * PI / period_s;
        let component = WaveComponent {
            omega_rad_s: omega,
            wavenumber_rad_m: wavenumber(omega, depth_m)?,
            amplitude_m: Complex::from_polar(0.5 * height_m, phase_rad),
        };
        Ok(Self {
            field: AiryField::new(vec![component], depth_m, heading_rad, rho),
        })
    }

    /// The underlying one-component field.
    pub fn field(&self) -> &AiryField {
        &self.field
    }
}

impl SeaKinematics for RegularWave {
    fn kinematics(&self, x: &Vector3<f64>, t: f64) -> FluidKinematics {
        self.field.kinematics(x, t)
    }
    fn elevation(&self, x: f64, y: f64, t: f64) -> f64 {
        self.field.elevation(x, y, t)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::waves::spectrum::PeakEnhancement;

    fn sea(seed: u64) -> IrregularSea {
        let s = Jonswap::new(8.75, 16.5, PeakEnhancement::Given(1.3)).unwrap();
        IrregularSea::new(
            &s,
            &RealisationParams {
                seed,
                ..Default::default()
            },
        )
        .unwrap()
    }

    #[test]
    fn default_repeat_period_is_next_power_of_two_seconds() {
        let p = RealisationParams {
            duration_s: 1000.0,
            ..Default::default()
        };
        assert_eq!(p.repeat_period_s().unwrap(), 1024.0);
        let p = RealisationParams {
            duration_s: 1024.0,
            ..Default::default()
        };
        assert_eq!(p.repeat_period_s().unwrap(), 1024.0);
        let p = RealisationParams {
            repeat_period: RepeatPeriod::Given(500.0),
            ..Default::default()
        };
        assert_eq!(
            p.repeat_period_s().unwrap_err().to_string(),
            "repeat_period_s must be >= duration_s, got 500"
        );
    }

    #[test]
    fn realisation_repeats_after_the_repeat_period() {
        let s = sea(7);
        let t_rep = s.repeat_period_s();
        for &t in &[0.0, 13.7, 400.2] {
            let a = s.elevation(12.0, -5.0, t);
            let b = s.elevation(12.0, -5.0, t + t_rep);
            assert!((a - b).abs() < 1e-9);
        }
    }

    #[test]
    fn same_seed_gives_same_sea_and_other_seed_another() {
        assert_eq!(sea(3), sea(3));
        assert_ne!(
            sea(3).field().components()[10],
            sea(4).field().components()[10]
        );
    }

    #[test]
    fn box_muller_normals_have_unit_variance() {
        let mut g = NormalPairs::new(11);
        let n = 50_000;
        let (mut s1, mut s2) = (0.0, 0.0);
        for _ in 0..n {
            let (x, y) = g.next_pair();
            s1 += x + y;
            s2 += x * x + y * y;
        }
        let mean = s1 / (2 * n) as f64;
        let var = s2 / (2 * n) as f64 - mean * mean;
        // Standard errors: 1/√(2n) = 0.0032 for the mean, √(2/(2n)) = 0.0045 for the variance.
        assert!(mean.abs() < 4.0 * 0.0032, "mean {mean}");
        assert!((var - 1.0).abs() < 4.0 * 0.0045, "var {var}");
    }

    #[test]
    fn heading_rotates_the_field() {
        let s0 = sea(1);
        let s = Jonswap::new(8.75, 16.5, PeakEnhancement::Given(1.3)).unwrap();
        let s90 = IrregularSea::new(
            &s,
            &RealisationParams {
                seed: 1,
                heading_rad: PI / 2.0,
                ..Default::default()
            },
        )
        .unwrap();
        let k0 = s0.kinematics(&Vector3::new(30.0, 0.0, -10.0), 5.0);
        let k90 = s90.kinematics(&Vector3::new(0.0, 30.0, -10.0), 5.0);
        assert!((k0.velocity.x - k90.velocity.y).abs() < 1e-12);
        assert!(k90.velocity.x.abs() < 1e-12);
    }

    #[test]
    fn regular_wave_has_its_height_and_period() {
        let w = RegularWave::new(3.0, 8.0, 0.0, 0.0, 50.0, 1025.0).unwrap();
        assert!((w.elevation(0.0, 0.0, 0.0) - 1.5).abs() < 1e-14);
        assert!((w.elevation(0.0, 0.0, 4.0) + 1.5).abs() < 1e-12);
        assert_eq!(
            RegularWave::new(3.0, 0.0, 0.0, 0.0, 50.0, 1025.0)
                .unwrap_err()
                .to_string(),
            "period_s must be > 0, got 0"
        );
    }
}
