//! Steady wind loads on the rotor and the wind speed that goes with a sea state.
//!
//! Rotor: thrust F(U) and aerodynamic torque Q(U) versus hub-height wind speed U by linear
//! interpolation in a table. Inside the operating range [U_cut-in, U_cut-out] (the table's first
//! and last wind speeds) the turbine produces; outside it is parked with feathered blades and the
//! rotor load is taken as zero (the drag of a parked rotor is neglected).
//!
//! Paper case (`docs/paper-campaign.md`): the NREL 5 MW reference turbine scaled to 3.6 MW by the
//! factor 0.72.
//! Thrust: the NREL 5 MW table of `campaigns/data/paper_case_lines.json` (rotor thrust in kN at
//! 3…25 m/s). Torque: the NREL 5 MW aerodynamic rotor torque built from the published turbine and
//! controller constants of Jonkman et al. (2009), NREL/TP-500-38060: rotor radius 63 m
//! (Table 1-1), peak power coefficient Cp = 0.482 at tip-speed ratio λ = 7.55 and zero pitch,
//! cut-in and rated rotor speeds 6.9 and 12.1 rpm (Table 1-1), rated mechanical power
//! 5.296610 MW (Ch. 7, generator-torque controller), air density 1.225 kg/m³. Below rated, the rotor follows λ = 7.55 with
//! its speed kept within [6.9, 12.1] rpm and Q = ½ρπR²U³Cp/Ω; the torque is capped at the rated
//! value 5.296610 MW / 12.1 rpm = 4.18 MN·m, which holds above rated wind speed (region 3, constant
//! power and speed). Below about 6 m/s, where the rotor speed is held at 6.9 rpm and λ exceeds its
//! optimum, Cp is lower than 0.482 and this torque is an upper estimate.
//!
//! Wind speed per sea state: either the fully developed sea relation Hs = 0.22 U²/g
//! (Pierson-Moskowitz) solved for U and capped to the operating range, or a table Hs → U with
//! linear interpolation (constant beyond its ends).
//!
//! Units: m/s, N, N·m, m.

use std::f64::consts::PI;

use super::dispersion::GRAVITY;
use super::error::{finite, non_negative, positive, WavesError};

/// NREL 5 MW rotor thrust (kN) at 3, 4, …, 25 m/s, as in `campaigns/data/paper_case_lines.json`
/// (it includes the rotor-weight component along the tilted shaft).
pub(crate) const NREL_5MW_THRUST_KN: [f64; 23] = [
    171.7, 215.9, 268.9, 330.3, 398.6, 478.0, 579.2, 691.5, 790.6, 690.0, 608.4, 557.9, 520.5,
    491.2, 467.7, 448.4, 432.3, 418.8, 406.7, 395.3, 385.1, 376.7, 369.3,
];
/// First wind speed of [`NREL_5MW_THRUST_KN`] (m/s), the cut-in speed.
pub(crate) const NREL_5MW_CUT_IN_M_S: f64 = 3.0;
/// Cut-out wind speed (m/s).
pub(crate) const NREL_5MW_CUT_OUT_M_S: f64 = 25.0;
/// Scale from the NREL 5 MW to the paper's 3.6 MW turbine.
pub const PAPER_TURBINE_SCALE: f64 = 0.72;

const RPM: f64 = 2.0 * PI / 60.0;
const ROTOR_RADIUS_M: f64 = 63.0;
const AIR_DENSITY: f64 = 1.225;
const CP_MAX: f64 = 0.482;
const TSR_OPTIMAL: f64 = 7.55;
const ROTOR_SPEED_MIN_RPM: f64 = 6.9;
const ROTOR_SPEED_RATED_RPM: f64 = 12.1;
const RATED_MECHANICAL_POWER_W: f64 = 5.296610e6;

/// Aerodynamic rotor torque (N·m) of the NREL 5 MW turbine at hub wind speed `wind_m_s` inside
/// its operating range, from the constants cited in the module documentation.
pub(crate) fn nrel_5mw_aero_torque_nm(wind_m_s: f64) -> f64 {
    let omega = (TSR_OPTIMAL * wind_m_s / ROTOR_RADIUS_M)
        .clamp(ROTOR_SPEED_MIN_RPM * RPM, ROTOR_SPEED_RATED_RPM * RPM);
    let power =
        0.5 * AIR_DENSITY * PI * ROTOR_RADIUS_M * ROTOR_RADIUS_M * wind_m_s.powi(3) * CP_MAX;
    let rated = RATED_MECHANICAL_POWER_W / (ROTOR_SPEED_RATED_RPM * RPM);
    (power / omega).min(rated)
}

/// Rotor thrust and torque versus hub wind speed.
#[derive(Debug, Clone, PartialEq)]
pub struct RotorTable {
    wind_m_s: Vec<f64>,
    thrust_n: Vec<f64>,
    torque_nm: Vec<f64>,
}

/// Steady rotor loads at one wind speed.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct RotorLoads {
    /// Thrust along the shaft (N).
    pub thrust_n: f64,
    /// Aerodynamic torque about the shaft (N·m).
    pub torque_nm: f64,
}

impl RotorTable {
    /// Table from wind speeds (strictly increasing, ≥ 0), thrusts (N, ≥ 0) and torques (N·m).
    pub fn new(
        wind_m_s: Vec<f64>,
        thrust_n: Vec<f64>,
        torque_nm: Vec<f64>,
    ) -> Result<Self, WavesError> {
        if wind_m_s.len() < 2 {
            return Err(WavesError::LengthMismatch {
                field: "wind_m_s",
                expected: 2,
                got: wind_m_s.len(),
            });
        }
        for (field, v) in [("thrust_n", &thrust_n), ("torque_nm", &torque_nm)] {
            if v.len() != wind_m_s.len() {
                return Err(WavesError::LengthMismatch {
                    field,
                    expected: wind_m_s.len(),
                    got: v.len(),
                });
            }
        }
        increasing("wind_m_s", &wind_m_s)?;
        if wind_m_s[0] < 0.0 {
            return Err(WavesError::InvalidParameter {
                field: "wind_m_s",
                value: wind_m_s[0],
                rule: ">= 0",
            });
        }
        for &t in &thrust_n {
            if !(t.is_finite() && t >= 0.0) {
                return Err(WavesError::InvalidParameter {
                    field: "thrust_n",
                    value: t,
                    rule: "finite and >= 0",
                });
            }
        }
        for &q in &torque_nm {
            finite("torque_nm", q)?;
        }
        Ok(Self {
            wind_m_s,
            thrust_n,
            torque_nm,
        })
    }

    /// The NREL 5 MW table (thrust from [`NREL_5MW_THRUST_KN`], torque from
    /// [`nrel_5mw_aero_torque_nm`]) with both scaled by `scale` (0.72 for the paper's turbine).
    pub(crate) fn nrel_5mw_scaled(scale: f64) -> Result<Self, WavesError> {
        let scale = positive("thrust_scale", scale)?;
        let wind: Vec<f64> = (0..NREL_5MW_THRUST_KN.len())
            .map(|i| NREL_5MW_CUT_IN_M_S + i as f64)
            .collect();
        let thrust = NREL_5MW_THRUST_KN.iter().map(|t| t * 1e3 * scale).collect();
        let torque = wind
            .iter()
            .map(|&u| nrel_5mw_aero_torque_nm(u) * scale)
            .collect();
        Self::new(wind, thrust, torque)
    }

    /// Operating range [cut-in, cut-out] (m/s).
    pub(crate) fn operating_range_m_s(&self) -> (f64, f64) {
        (self.wind_m_s[0], self.wind_m_s[self.wind_m_s.len() - 1])
    }

    /// Thrust and torque at hub wind speed `wind_m_s`; zero outside the operating range (parked).
    pub fn loads(&self, wind_m_s: f64) -> RotorLoads {
        let (lo, hi) = self.operating_range_m_s();
        if !(wind_m_s >= lo && wind_m_s <= hi) {
            return RotorLoads::default();
        }
        RotorLoads {
            thrust_n: interpolate(&self.wind_m_s, &self.thrust_n, wind_m_s),
            torque_nm: interpolate(&self.wind_m_s, &self.torque_nm, wind_m_s),
        }
    }
}

/// Wind speed of a sea state.
#[derive(Debug, Clone, PartialEq, serde::Serialize, serde::Deserialize)]
pub enum WindLaw {
    /// U = √(g Hs / 0.22), capped to [min_m_s, max_m_s] (the operating range).
    FullyDevelopedSea {
        /// Lower cap (m/s).
        min_m_s: f64,
        /// Upper cap (m/s).
        max_m_s: f64,
    },
    /// Table Hs → U with linear interpolation, constant beyond the ends.
    Table {
        /// Significant wave heights (m), strictly increasing.
        hs_m: Vec<f64>,
        /// Wind speeds (m/s).
        wind_m_s: Vec<f64>,
    },
}

impl Default for WindLaw {
    fn default() -> Self {
        Self::FullyDevelopedSea {
            min_m_s: NREL_5MW_CUT_IN_M_S,
            max_m_s: NREL_5MW_CUT_OUT_M_S,
        }
    }
}

impl WindLaw {
    /// Hub wind speed (m/s) for significant wave height `hs_m` (0 for calm water).
    pub fn wind_speed_m_s(&self, hs_m: f64) -> Result<f64, WavesError> {
        let hs_m = non_negative("hs_m", hs_m)?;
        match self {
            Self::FullyDevelopedSea { min_m_s, max_m_s } => {
                if !(min_m_s.is_finite() && max_m_s.is_finite() && min_m_s <= max_m_s) {
                    return Err(WavesError::InvalidParameter {
                        field: "max_m_s",
                        value: *max_m_s,
                        rule: ">= min_m_s",
                    });
                }
                Ok((GRAVITY * hs_m / 0.22).sqrt().clamp(*min_m_s, *max_m_s))
            }
            Self::Table {
                hs_m: h,
                wind_m_s: u,
            } => {
                if h.is_empty() || h.len() != u.len() {
                    return Err(WavesError::LengthMismatch {
                        field: "wind_m_s",
                        expected: h.len().max(1),
                        got: u.len(),
                    });
                }
                increasing("hs_m", h)?;
                let x = hs_m.clamp(h[0], h[h.len() - 1]);
                Ok(interpolate(h, u, x))
            }
        }
    }
}

fn increasing(field: &'static str, v: &[f64]) -> Result<(), WavesError> {
    for w in v.windows(2) {
        if !w[0].is_finite() || !w[1].is_finite() || w[1] <= w[0] {
            return Err(WavesError::InvalidParameter {
                field,
                value: w[1],
                rule: "strictly increasing",
            });
        }
    }
    Ok(())
}

/// Linear interpolation in (x, y) at `at`, with x increasing and x[0] ≤ at ≤ x[last].
fn interpolate(x: &[f64], y: &[f64], at: f64) -> f64 {
    let i = x.partition_point(|&v| v <= at).clamp(1, x.len() - 1);
    let (x0, x1) = (x[i - 1], x[i]);
    let u = (at - x0) / (x1 - x0);
    y[i - 1] + u * (y[i] - y[i - 1])
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn thrust_is_scaled_table_value_and_interpolated_between() {
        let t = RotorTable::nrel_5mw_scaled(PAPER_TURBINE_SCALE).unwrap();
        assert!((t.loads(11.0).thrust_n - 0.72 * 790.6e3).abs() < 1e-6);
        let mid = t.loads(11.5).thrust_n;
        assert!((mid - 0.72 * 0.5 * (790.6e3 + 690.0e3)).abs() < 1e-6);
        assert!((t.loads(25.0).thrust_n - 0.72 * 369.3e3).abs() < 1e-6);
    }

    #[test]
    fn rotor_is_parked_outside_the_operating_range() {
        let t = RotorTable::nrel_5mw_scaled(1.0).unwrap();
        assert_eq!(t.loads(2.99), RotorLoads::default());
        assert_eq!(t.loads(25.01), RotorLoads::default());
        assert_eq!(t.loads(f64::NAN), RotorLoads::default());
    }

    #[test]
    fn torque_reaches_rated_value_above_rated_wind() {
        // 5.296610 MW at 12.1 rpm: 4.18007 MN·m (Jonkman et al. 2009: rated generator torque
        // 43 093.55 N·m × gearbox ratio 97 = 4.18007 MN·m).
        let rated = 43_093.55 * 97.0;
        assert!((nrel_5mw_aero_torque_nm(15.0) - rated).abs() < 1e-4 * rated);
        assert!(nrel_5mw_aero_torque_nm(8.0) < rated);
        // Region 2 at 8 m/s: ½ρπR²U³Cp / (λU/R).
        let expected = 0.5 * 1.225 * PI * 63.0f64.powi(3) * 64.0 * 0.482 / 7.55;
        assert!((nrel_5mw_aero_torque_nm(8.0) - expected).abs() < 1e-9 * expected);
    }

    #[test]
    fn embedded_thrust_table_equals_the_campaign_data_file() {
        let text = include_str!(concat!(
            env!("CARGO_MANIFEST_DIR"),
            "/../campaigns/data/paper_case_lines.json"
        ));
        let v: serde_json::Value = serde_json::from_str(text).unwrap();
        let table = &v["nrel_5mw_rotor_thrust_kn_vs_wind_m_s"];
        let thrust: Vec<f64> = serde_json::from_value(table["thrust_kn"].clone()).unwrap();
        let wind: Vec<f64> = serde_json::from_value(table["wind_m_s"].clone()).unwrap();
        assert_eq!(thrust, NREL_5MW_THRUST_KN.to_vec());
        assert_eq!(wind[0], NREL_5MW_CUT_IN_M_S);
        assert_eq!(*wind.last().unwrap(), NREL_5MW_CUT_OUT_M_S);
    }

    #[test]
    fn fully_developed_sea_law_is_inverted_and_capped() {
        let law = WindLaw::default();
        let u = law.wind_speed_m_s(8.75).unwrap();
        assert!((0.22 * u * u / GRAVITY - 8.75).abs() < 1e-12);
        assert_eq!(law.wind_speed_m_s(0.1).unwrap(), 3.0);
        assert_eq!(law.wind_speed_m_s(50.0).unwrap(), 25.0);
    }

    #[test]
    fn wind_table_interpolates_and_holds_ends() {
        let law = WindLaw::Table {
            hs_m: vec![1.0, 3.0],
            wind_m_s: vec![5.0, 9.0],
        };
        assert_eq!(law.wind_speed_m_s(2.0).unwrap(), 7.0);
        assert_eq!(law.wind_speed_m_s(0.5).unwrap(), 5.0);
        assert_eq!(law.wind_speed_m_s(4.0).unwrap(), 9.0);
        let bad = WindLaw::Table {
            hs_m: vec![3.0, 1.0],
            wind_m_s: vec![5.0, 9.0],
        };
        assert_eq!(
            bad.wind_speed_m_s(2.0).unwrap_err().to_string(),
            "hs_m must be strictly increasing, got 1"
        );
    }

    #[test]
    fn bad_rotor_tables_are_rejected() {
        let e = RotorTable::new(vec![3.0, 4.0], vec![1.0], vec![1.0, 2.0]).unwrap_err();
        assert_eq!(e.to_string(), "thrust_n: expected 2 values, got 1");
        let e = RotorTable::new(vec![3.0, 3.0], vec![1.0, 1.0], vec![1.0, 2.0]).unwrap_err();
        assert!(matches!(
            e,
            WavesError::InvalidParameter {
                field: "wind_m_s",
                ..
            }
        ));
    }
}
