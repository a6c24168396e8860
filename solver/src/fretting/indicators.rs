//! Fretting indicators of a slip cycle: regime, Ruiz-type products, fretting S-N damage.
//!
//! - Regime. Mindlin's gross-slip limit of a circular Hertz contact of radius a under normal
//!   force P and friction coefficient μ (Johnson 1985, §7.2, eq. 7.42 at Q = μP):
//!   `δ* = 3 μ P / (16 G* a)`, `1/G* = (2 − ν₁)/G₁ + (2 − ν₂)/G₂`, δ the tangential displacement
//!   amplitude. For the elliptic contact of crossed wires the equivalent radius √(ab) is used (an
//!   approximation: the elliptic Mindlin-Deresiewicz solution differs by a few percent for the
//!   axis ratios of strand contacts). A cycle of slip amplitude δₐ = range/2 is gross slip if
//!   δₐ ≥ δ*, else partial slip; Mindlin has no finite stick range, so "stick" needs a threshold:
//!   a fraction of δ* ([`RegimeCriterion::Mindlin`], default 0: never) or absolute amplitudes
//!   ([`RegimeCriterion::Amplitude`], e.g. a Vingsbo-Söderberg fretting map).
//! - Ruiz et al. (1984), Int. J. Mech. Sci. 26: `F1 = τ δ` (frictional work density, N/m) and
//!   `F2 = σ_T τ δ` (Pa·N/m) with τ the surface shear traction, δ the slip amplitude and σ_T the
//!   tangential (here wire axial) stress. τ is taken as the largest tangential force of the
//!   cycle over the Hertz area at the cycle's normal force, τ = |f_T|max/(πab).
//! - Fretting S-N law ([`FrettingSnLaw`]): no standard gives one for inter-wire fretting in
//!   spiral strands. The default is an assumption, stated as such: the DNV-OS-E301 spiral-rope
//!   T-N curve (a_D = 1.7e17, m = 4.8, stress range in MPa) applied to the wire's axial stress
//!   range over the cycle, on the ground that the strand tests behind that curve fail by
//!   inter-wire fretting. A Ruiz-based power law is the alternative when calibration data exist.
//!
//! Units: m, N, Pa; damage is dimensionless (Miner fraction).

use serde::{Deserialize, Serialize};

use super::cycles::SlipCycle;
use super::error::{non_negative, positive, FrettingError};
use super::histogram::ForceMeasure;
use crate::contact::hertz::{HertzContact, HertzModel};

/// Fretting regime of one cycle.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
pub enum FrettingRegime {
    /// No slip of consequence.
    Stick,
    /// Slip in an annulus around a stuck centre.
    PartialSlip,
    /// The whole contact slides.
    GrossSlip,
}

/// How the regime of a cycle is decided.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub enum RegimeCriterion {
    /// Mindlin: gross slip when δₐ ≥ δ*, stick when δₐ < `stick_fraction` · δ*.
    Mindlin {
        /// Fraction of δ* below which a cycle counts as stick (0 ≤ f < 1).
        stick_fraction: f64,
    },
    /// Fixed slip-amplitude thresholds (m).
    Amplitude {
        /// Below this amplitude: stick (m).
        stick_below_m: f64,
        /// From this amplitude: gross slip (m).
        gross_from_m: f64,
    },
}

impl Default for RegimeCriterion {
    fn default() -> Self {
        Self::Mindlin {
            stick_fraction: 0.0,
        }
    }
}

/// Fretting S-N law: cycles to failure N from a cycle's load, damage = count / N.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub enum FrettingSnLaw {
    /// N = a_D · (Δσ / 1 MPa)^(−m) on the wire's axial stress range.
    StressRange {
        /// Intercept a_D (cycles at 1 MPa).
        intercept: f64,
        /// Inverse slope m.
        slope: f64,
    },
    /// N = N_ref · (F2 / F2_ref)^(−m) on the Ruiz product F2.
    Ruiz {
        /// Cycles to failure at the reference F2.
        reference_cycles: f64,
        /// Reference F2 (Pa·N/m).
        reference_f2: f64,
        /// Inverse slope m.
        slope: f64,
    },
}

impl Default for FrettingSnLaw {
    /// Assumption (see module doc): DNV-OS-E301 (2013) Ch.2 Sec.2 Table 6 spiral rope curve.
    fn default() -> Self {
        Self::StressRange {
            intercept: 1.7e17,
            slope: 4.8,
        }
    }
}

/// Parameters of the fretting indicators (validated, with `Default`).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct FrettingParams {
    /// Coulomb friction coefficient between wires (paper case: 0.12).
    pub friction_coefficient: f64,
    /// Regime criterion.
    pub regime: RegimeCriterion,
    /// Which normal force of the cycle sizes the contact.
    pub force_measure: ForceMeasure,
    /// Fretting S-N law.
    pub sn_law: FrettingSnLaw,
}

impl Default for FrettingParams {
    fn default() -> Self {
        Self {
            friction_coefficient: 0.12,
            regime: RegimeCriterion::default(),
            force_measure: ForceMeasure::Mean,
            sn_law: FrettingSnLaw::default(),
        }
    }
}

impl FrettingParams {
    /// Checks every parameter.
    pub fn validate(&self) -> Result<(), FrettingError> {
        positive("friction_coefficient", self.friction_coefficient)?;
        match self.regime {
            RegimeCriterion::Mindlin { stick_fraction } => {
                if !(0.0..1.0).contains(&stick_fraction) {
                    return Err(FrettingError::InvalidParameter {
                        field: "regime.stick_fraction",
                        value: stick_fraction,
                        reason: "must lie in [0, 1)",
                    });
                }
            }
            RegimeCriterion::Amplitude {
                stick_below_m,
                gross_from_m,
            } => {
                non_negative("regime.stick_below_m", stick_below_m)?;
                if !(gross_from_m.is_finite() && gross_from_m >= stick_below_m) {
                    return Err(FrettingError::InvalidParameter {
                        field: "regime.gross_from_m",
                        value: gross_from_m,
                        reason: "must be finite and >= stick_below_m",
                    });
                }
            }
        }
        match self.sn_law {
            FrettingSnLaw::StressRange { intercept, slope } => {
                positive("sn_law.intercept", intercept)?;
                positive("sn_law.slope", slope)?;
            }
            FrettingSnLaw::Ruiz {
                reference_cycles,
                reference_f2,
                slope,
            } => {
                positive("sn_law.reference_cycles", reference_cycles)?;
                positive("sn_law.reference_f2", reference_f2)?;
                positive("sn_law.slope", slope)?;
            }
        }
        Ok(())
    }
}

/// Mindlin's gross-slip displacement amplitude δ* = 3μP/(16 G* a) (m), a = √(ab).
pub(crate) fn mindlin_gross_slip_amplitude_m(
    friction_coefficient: f64,
    normal_force_n: f64,
    contact: &HertzContact,
    shear_contact_modulus_pa: f64,
) -> f64 {
    let a = contact.equivalent_radius_m();
    if a <= 0.0 || normal_force_n <= 0.0 {
        return 0.0;
    }
    3.0 * friction_coefficient * normal_force_n / (16.0 * shear_contact_modulus_pa * a)
}

/// Wire stress state over a cycle, supplied by the strand model (Pa).
#[derive(Debug, Clone, Copy, PartialEq, Default, Serialize, Deserialize)]
pub struct WireStress {
    /// Largest axial stress of the wire at the contact over the cycle (Pa).
    pub axial_max_pa: f64,
    /// Axial stress range of the wire over the cycle (Pa).
    pub axial_range_pa: f64,
}

/// Indicators of one slip cycle.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct CycleIndicators {
    /// The cycle's normal force that sizes the contact (per the force measure) (N).
    pub normal_force_n: f64,
    /// Hertz contact at the cycle's normal force.
    pub contact: HertzContact,
    /// Slip amplitude δₐ = range/2 (m).
    pub slip_amplitude_m: f64,
    /// Mindlin gross-slip amplitude δ* (m); 0 for an open contact.
    pub gross_slip_amplitude_m: f64,
    /// Regime.
    pub regime: FrettingRegime,
    /// Mean shear traction τ = |f_T|max/(πab) (Pa); 0 for an open contact.
    pub shear_traction_pa: f64,
    /// Ruiz F1 = τ δₐ (N/m).
    pub ruiz_f1: f64,
    /// Ruiz F2 = σ_axial,max τ δₐ (Pa·N/m).
    pub ruiz_f2: f64,
    /// Miner damage of this cycle (count / N).
    pub damage: f64,
}

/// Evaluates the indicators of one slip cycle of a contact described by `model`.
pub fn evaluate_cycle(
    model: &HertzModel,
    params: &FrettingParams,
    cycle: &SlipCycle,
    stress: &WireStress,
) -> Result<CycleIndicators, FrettingError> {
    let normal = match params.force_measure {
        ForceMeasure::Mean => cycle.normal_force_n.mean,
        ForceMeasure::Max => cycle.normal_force_n.max,
    };
    let contact = model.contact(normal)?;
    let delta = cycle.slip_amplitude_m();
    let delta_star = mindlin_gross_slip_amplitude_m(
        params.friction_coefficient,
        normal,
        &contact,
        model.shear_contact_modulus_pa,
    );
    let regime = match params.regime {
        RegimeCriterion::Mindlin { stick_fraction } => {
            if delta >= delta_star {
                FrettingRegime::GrossSlip
            } else if delta < stick_fraction * delta_star {
                FrettingRegime::Stick
            } else {
                FrettingRegime::PartialSlip
            }
        }
        RegimeCriterion::Amplitude {
            stick_below_m,
            gross_from_m,
        } => {
            if delta >= gross_from_m {
                FrettingRegime::GrossSlip
            } else if delta < stick_below_m {
                FrettingRegime::Stick
            } else {
                FrettingRegime::PartialSlip
            }
        }
    };
    let area = contact.area_m2();
    let tau = if area > 0.0 {
        cycle.tangential_force_n.max_abs() / area
    } else {
        0.0
    };
    let f1 = tau * delta;
    let f2 = stress.axial_max_pa.max(0.0) * f1;
    let cycles_to_failure = match params.sn_law {
        FrettingSnLaw::StressRange { intercept, slope } => {
            let s_mpa = stress.axial_range_pa.abs() * 1e-6;
            intercept * s_mpa.powf(-slope)
        }
        FrettingSnLaw::Ruiz {
            reference_cycles,
            reference_f2,
            slope,
        } => reference_cycles * (f2 / reference_f2).powf(-slope),
    };
    // A zero load gives N = ∞ and no damage.
    let damage = if cycles_to_failure.is_finite() {
        cycle.slip.count / cycles_to_failure
    } else {
        0.0
    };
    Ok(CycleIndicators {
        normal_force_n: normal,
        contact,
        slip_amplitude_m: delta,
        gross_slip_amplitude_m: delta_star,
        regime,
        shear_traction_pa: tau,
        ruiz_f1: f1,
        ruiz_f2: f2,
        damage,
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::contact::hertz::{CrossedCylinders, ElasticMaterial};
    use crate::fretting::cycles::ForceStats;
    use crate::fretting::rainflow::Cycle;

    fn model() -> HertzModel {
        let m = ElasticMaterial::default();
        HertzModel::crossed_cylinders(&CrossedCylinders {
            radius_1_m: 2.3e-3,
            radius_2_m: 2.3e-3,
            crossing_angle_rad: std::f64::consts::FRAC_PI_2,
            material_1: m,
            material_2: m,
        })
        .unwrap()
    }

    fn cycle(range: f64, fn_mean: f64, ft_max: f64) -> SlipCycle {
        SlipCycle {
            slip: Cycle {
                range,
                mean: 0.0,
                count: 1.0,
                start_index: 0,
                end_index: 5,
            },
            normal_force_n: ForceStats {
                min: fn_mean,
                max: fn_mean,
                mean: fn_mean,
            },
            tangential_force_n: ForceStats {
                min: -ft_max,
                max: ft_max,
                mean: 0.0,
            },
        }
    }

    #[test]
    fn mindlin_limit_matches_the_closed_form_for_equal_steel_spheres() {
        // Perpendicular equal wires ≡ circular contact; identical materials:
        // δ* = 3μP(2 − ν)/(8 G a) (Johnson eq. 7.42 with both bodies).
        let h = model();
        let p = 400.0;
        let c = h.contact(p).unwrap();
        let g = ElasticMaterial::default().shear_modulus_pa();
        let expected = 3.0 * 0.12 * p * (2.0 - 0.3) / (8.0 * g * c.semi_major_m);
        let got = mindlin_gross_slip_amplitude_m(0.12, p, &c, h.shear_contact_modulus_pa);
        assert!((got / expected - 1.0).abs() < 1e-12);
        // Micrometre scale for strand wires: the size of the slips of interest.
        assert!(got > 1e-7 && got < 1e-5, "{got}");
    }

    #[test]
    fn regime_follows_the_gross_slip_limit() {
        let h = model();
        let params = FrettingParams {
            regime: RegimeCriterion::Mindlin {
                stick_fraction: 0.1,
            },
            ..Default::default()
        };
        let c = h.contact(400.0).unwrap();
        let ds = mindlin_gross_slip_amplitude_m(0.12, 400.0, &c, h.shear_contact_modulus_pa);
        let s = WireStress::default();
        let regime = |amp: f64| {
            evaluate_cycle(&h, &params, &cycle(2.0 * amp, 400.0, 30.0), &s)
                .unwrap()
                .regime
        };
        assert_eq!(regime(1.01 * ds), FrettingRegime::GrossSlip);
        assert_eq!(regime(0.5 * ds), FrettingRegime::PartialSlip);
        assert_eq!(regime(0.05 * ds), FrettingRegime::Stick);
    }

    #[test]
    fn ruiz_products_and_stress_range_damage_follow_their_definitions() {
        let h = model();
        let params = FrettingParams::default();
        let stress = WireStress {
            axial_max_pa: 500e6,
            axial_range_pa: 100e6,
        };
        let ind = evaluate_cycle(&h, &params, &cycle(4e-6, 400.0, 30.0), &stress).unwrap();
        let area = ind.contact.area_m2();
        assert!((ind.shear_traction_pa - 30.0 / area).abs() <= 1e-9 * ind.shear_traction_pa);
        assert!((ind.ruiz_f1 - ind.shear_traction_pa * 2e-6).abs() <= 1e-12 * ind.ruiz_f1);
        assert!((ind.ruiz_f2 - 500e6 * ind.ruiz_f1).abs() <= 1e-12 * ind.ruiz_f2);
        // 100 MPa on a_D = 1.7e17, m = 4.8: N = 1.7e17 / 100^4.8.
        let n = 1.7e17 / 100f64.powf(4.8);
        assert!((ind.damage * n - 1.0).abs() < 1e-12);
        let ruiz = FrettingParams {
            sn_law: FrettingSnLaw::Ruiz {
                reference_cycles: 1e6,
                reference_f2: ind.ruiz_f2,
                slope: 3.0,
            },
            ..params
        };
        let at_ref = evaluate_cycle(&h, &ruiz, &cycle(4e-6, 400.0, 30.0), &stress).unwrap();
        assert!((at_ref.damage - 1e-6).abs() < 1e-18);
    }

    #[test]
    fn open_contact_and_bad_parameters_are_handled() {
        let h = model();
        let ind = evaluate_cycle(
            &h,
            &FrettingParams::default(),
            &cycle(1e-6, 0.0, 0.0),
            &WireStress::default(),
        )
        .unwrap();
        assert_eq!((ind.shear_traction_pa, ind.damage), (0.0, 0.0));
        assert_eq!(ind.regime, FrettingRegime::GrossSlip);
        let bad = FrettingParams {
            friction_coefficient: -0.1,
            ..Default::default()
        };
        assert!(matches!(
            bad.validate(),
            Err(FrettingError::InvalidParameter {
                field: "friction_coefficient",
                ..
            })
        ));
        assert!(FrettingParams::default().validate().is_ok());
    }
}
