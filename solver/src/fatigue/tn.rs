//! Tension-tension (T-N) fatigue curves of mooring components, the classical design check
//! that the fretting estimate is compared with.
//!
//! - DNV-OS-E301 *Position mooring* (2013; same values in DNVGL-OS-E301 2018), Ch.2 Sec.2 §6
//!   (fatigue limit state, characteristic capacity): `n_c(s) = a_D · s^(−m)` with s the nominal
//!   stress range in MPa (double amplitude of tension over the nominal area):
//!   studlink chain a_D = 1.2e11, m = 3.0; studless chain 6.0e10, 3.0; stranded (six-strand)
//!   rope 3.4e14, 4.0; spiral rope 1.7e17, 4.8.
//! - API RP 2SK *Design and analysis of stationkeeping systems for floating structures* (3rd
//!   ed., 2005), T-N curves `N · R^M = K` with R the tension range over the reference breaking
//!   strength (for wire rope its minimum breaking strength; for chain the strength of ORQ chain
//!   of the same diameter, as that edition specifies): common studlink chain M = 3.36,
//!   K = 370; six / multi-strand rope M = 4.09, log₁₀K = 3.20 − 2.79 Lm; spiral strand
//!   M = 5.05, log₁₀K = 3.25 − 3.43 Lm, Lm the mean load over the reference breaking strength.
//!
//! Nominal areas for the DNV curves: a chain link has two bars carrying the load, A = 2·πd²/4
//! with d the bar diameter ([`chain_nominal_area_m2`]); a rope uses its nominal diameter D,
//! A = πD²/4 ([`rope_nominal_area_m2`]). Units: tension in N, areas in m², stress ranges
//! converted to MPa inside.

use serde::{Deserialize, Serialize};

use super::error::{check, FatigueError};

/// Component families of DNV-OS-E301 Ch.2 Sec.2 §6.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
pub enum DnvComponent {
    /// Stud (studlink) chain.
    StudlinkChain,
    /// Studless chain.
    StudlessChain,
    /// Stranded (six-strand) rope.
    StrandedRope,
    /// Spiral (spiral-strand) rope.
    SpiralRope,
}

impl DnvComponent {
    /// Intercept a_D (cycles at 1 MPa) and inverse slope m.
    pub fn parameters(self) -> (f64, f64) {
        match self {
            Self::StudlinkChain => (1.2e11, 3.0),
            Self::StudlessChain => (6.0e10, 3.0),
            Self::StrandedRope => (3.4e14, 4.0),
            Self::SpiralRope => (1.7e17, 4.8),
        }
    }
}

/// Component families of the API RP 2SK T-N curves.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
pub enum ApiComponent {
    /// Common studlink chain.
    StudlinkChain,
    /// Six-strand or multi-strand wire rope.
    SixMultiStrandRope,
    /// Spiral-strand wire rope.
    SpiralStrandRope,
}

impl ApiComponent {
    /// Exponent M and constant K at mean load ratio `lm` (Lm only acts on wire rope).
    pub fn parameters(self, lm: f64) -> (f64, f64) {
        match self {
            Self::StudlinkChain => (3.36, 370.0),
            Self::SixMultiStrandRope => (4.09, 10f64.powf(3.20 - 2.79 * lm)),
            Self::SpiralStrandRope => (5.05, 10f64.powf(3.25 - 3.43 * lm)),
        }
    }
}

/// A T-N curve with the section data it needs.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub enum TnCurve {
    /// DNV-OS-E301: n = a_D · (ΔT / A / 1 MPa)^(−m).
    Dnv {
        /// Component family.
        component: DnvComponent,
        /// Nominal area A (m²).
        nominal_area_m2: f64,
    },
    /// API RP 2SK: N = K · (ΔT / RBS)^(−M).
    Api {
        /// Component family.
        component: ApiComponent,
        /// Reference breaking strength RBS (N).
        reference_breaking_strength_n: f64,
        /// Mean load over RBS, Lm (wire rope curves only; ignored for chain).
        mean_load_ratio: f64,
    },
}

/// Nominal area of a chain of bar diameter `d_m`: two bars, 2·πd²/4 (m²).
pub fn chain_nominal_area_m2(d_m: f64) -> f64 {
    2.0 * std::f64::consts::PI * d_m * d_m / 4.0
}

/// Nominal area of a rope of nominal diameter `d_m`: πD²/4 (m²).
pub fn rope_nominal_area_m2(d_m: f64) -> f64 {
    std::f64::consts::PI * d_m * d_m / 4.0
}

impl TnCurve {
    /// Checks the section data.
    pub fn validate(&self) -> Result<(), FatigueError> {
        match *self {
            Self::Dnv {
                nominal_area_m2, ..
            } => {
                check(
                    "nominal_area_m2",
                    nominal_area_m2,
                    nominal_area_m2 > 0.0,
                    "must be > 0",
                )?;
            }
            Self::Api {
                reference_breaking_strength_n,
                mean_load_ratio,
                ..
            } => {
                check(
                    "reference_breaking_strength_n",
                    reference_breaking_strength_n,
                    reference_breaking_strength_n > 0.0,
                    "must be > 0",
                )?;
                check(
                    "mean_load_ratio",
                    mean_load_ratio,
                    (0.0..1.0).contains(&mean_load_ratio),
                    "must lie in [0, 1)",
                )?;
            }
        }
        Ok(())
    }

    /// Cycles to failure at tension range `tension_range_n` (N); infinite at zero range.
    pub(crate) fn cycles_to_failure(&self, tension_range_n: f64) -> f64 {
        let range = tension_range_n.abs();
        match *self {
            Self::Dnv {
                component,
                nominal_area_m2,
            } => {
                let (a_d, m) = component.parameters();
                let s_mpa = range / nominal_area_m2 * 1e-6;
                a_d * s_mpa.powf(-m)
            }
            Self::Api {
                component,
                reference_breaking_strength_n,
                mean_load_ratio,
            } => {
                let (m, k) = component.parameters(mean_load_ratio);
                k * (range / reference_breaking_strength_n).powf(-m)
            }
        }
    }

    /// Damage of `count` cycles at tension range `tension_range_n` (Miner fraction).
    pub fn damage(&self, tension_range_n: f64, count: f64) -> f64 {
        let n = self.cycles_to_failure(tension_range_n);
        if n.is_finite() {
            count / n
        } else {
            0.0
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn dnv_curves_follow_the_standard_parameters() {
        // 60.4 mm spiral strand of the paper case, 1 MN range: s = 1e6 / (π 0.0604²/4) = 349.0 MPa.
        let area = rope_nominal_area_m2(0.0604);
        let curve = TnCurve::Dnv {
            component: DnvComponent::SpiralRope,
            nominal_area_m2: area,
        };
        let s = 1e6 / area * 1e-6;
        assert!((s - 349.0).abs() < 0.1);
        let n = curve.cycles_to_failure(1e6);
        assert!((n / (1.7e17 * s.powf(-4.8)) - 1.0).abs() < 1e-14);
        // At s = 100 MPa the studlink chain curve gives 1.2e11 / 1e6 = 1.2e5 cycles.
        let chain = TnCurve::Dnv {
            component: DnvComponent::StudlinkChain,
            nominal_area_m2: 1.0,
        };
        assert!((chain.cycles_to_failure(100e6) - 1.2e5).abs() < 1e-6);
        let studless = TnCurve::Dnv {
            component: DnvComponent::StudlessChain,
            nominal_area_m2: 1.0,
        };
        assert!((studless.cycles_to_failure(100e6) - 6.0e4).abs() < 1e-6);
        let stranded = TnCurve::Dnv {
            component: DnvComponent::StrandedRope,
            nominal_area_m2: 1.0,
        };
        assert!((stranded.cycles_to_failure(100e6) - 3.4e6).abs() < 1e-4);
        assert_eq!(chain.damage(0.0, 10.0), 0.0);
    }

    #[test]
    fn api_curves_follow_the_standard_parameters() {
        // Chain: R = 0.1 → N = 370 · 0.1^−3.36.
        let chain = TnCurve::Api {
            component: ApiComponent::StudlinkChain,
            reference_breaking_strength_n: 1e7,
            mean_load_ratio: 0.2,
        };
        assert!((chain.cycles_to_failure(1e6) / (370.0 * 10f64.powf(3.36)) - 1.0).abs() < 1e-13);
        // Spiral strand at Lm = 0.3: log K = 3.25 − 1.029 = 2.221.
        let spiral = TnCurve::Api {
            component: ApiComponent::SpiralStrandRope,
            reference_breaking_strength_n: 3e6,
            mean_load_ratio: 0.3,
        };
        let expected = 10f64.powf(2.221) * 0.05f64.powf(-5.05);
        assert!((spiral.cycles_to_failure(1.5e5) / expected - 1.0).abs() < 1e-12);
        let six = TnCurve::Api {
            component: ApiComponent::SixMultiStrandRope,
            reference_breaking_strength_n: 3e6,
            mean_load_ratio: 0.3,
        };
        let expected = 10f64.powf(3.20 - 2.79 * 0.3) * 0.05f64.powf(-4.09);
        assert!((six.cycles_to_failure(1.5e5) / expected - 1.0).abs() < 1e-12);
    }

    #[test]
    fn chain_area_counts_both_bars() {
        assert!((chain_nominal_area_m2(0.1) - 2.0 * rope_nominal_area_m2(0.1)).abs() < 1e-18);
        let bad = TnCurve::Dnv {
            component: DnvComponent::SpiralRope,
            nominal_area_m2: 0.0,
        };
        assert!(matches!(
            bad.validate(),
            Err(FatigueError::InvalidParameter { .. })
        ));
    }
}
