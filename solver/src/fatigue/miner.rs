//! Palmgren-Miner damage: D = Σ nᵢ / Nᵢ over rainflow cycles (half cycles count 0.5).
//!
//! - [`miner_damage`]: from rainflow cycles of tension (N);
//! - [`histogram_damage`]: from a range histogram `(range N, count)`;
//! - [`sea_state_tension_damage`]: from one simulated tension series T(t) of a sea state
//!   (after the transient), giving the damage of the simulated duration and its rate per second,
//!   which the lifetime aggregation ([`super::lifetime`]) scales to the design life.
//!
//! Units: tension in N, time in s; damage is dimensionless.

use serde::{Deserialize, Serialize};

use super::error::{check, FatigueError};
use super::tn::TnCurve;
use crate::fretting::rainflow::{Cycle, RainflowCounter, RainflowOptions};

/// Miner damage of rainflow cycles of tension.
pub fn miner_damage(cycles: &[Cycle], curve: &TnCurve) -> f64 {
    cycles.iter().map(|c| curve.damage(c.range, c.count)).sum()
}

/// Miner damage of a histogram of `(tension range N, count)`.
pub fn histogram_damage(bins: &[(f64, f64)], curve: &TnCurve) -> f64 {
    bins.iter()
        .map(|&(range, count)| curve.damage(range, count))
        .sum()
}

/// Damage of one simulated tension series.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct TensionDamage {
    /// Miner damage over the simulated duration.
    pub damage: f64,
    /// Effective simulated duration, (samples − 1) · Δt (s).
    pub duration_s: f64,
    /// Number of cycles counted (half cycles count 0.5).
    pub cycles: f64,
    /// Mean tension over the series (N).
    pub mean_tension_n: f64,
}

impl TensionDamage {
    /// Damage per second of simulated time (1/s).
    pub(crate) fn rate_per_s(&self) -> f64 {
        if self.duration_s > 0.0 {
            self.damage / self.duration_s
        } else {
            0.0
        }
    }
}

/// Rainflow-counts a tension series sampled every `dt_s` and sums its Miner damage.
///
/// For API wire-rope curves the caller sets the mean load ratio Lm of the curve (the sea
/// state's mean tension over the reference breaking strength, `mean_tension_n` is returned to
/// help); the series should start after the transient.
pub fn sea_state_tension_damage(
    tension_n: &[f64],
    dt_s: f64,
    curve: &TnCurve,
    options: &RainflowOptions,
) -> Result<TensionDamage, FatigueError> {
    check("dt_s", dt_s, dt_s > 0.0, "must be > 0")?;
    curve.validate()?;
    let mut cycles = Vec::new();
    RainflowCounter::new(*options)?.count_into(tension_n, &mut cycles)?;
    let mean = if tension_n.is_empty() {
        0.0
    } else {
        tension_n.iter().sum::<f64>() / tension_n.len() as f64
    };
    Ok(TensionDamage {
        damage: miner_damage(&cycles, curve),
        duration_s: tension_n.len().saturating_sub(1) as f64 * dt_s,
        cycles: cycles.iter().map(|c| c.count).sum(),
        mean_tension_n: mean,
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::fatigue::tn::{rope_nominal_area_m2, DnvComponent};

    fn spiral() -> TnCurve {
        TnCurve::Dnv {
            component: DnvComponent::SpiralRope,
            nominal_area_m2: rope_nominal_area_m2(0.0604),
        }
    }

    #[test]
    fn constant_amplitude_tension_gives_cycles_over_capacity() {
        // 100 whole periods of T = 2 MN + 0.5 MN sin(ωt), 40 samples per period, Δt = 0.25 s.
        let (periods, per) = (100, 40);
        let t: Vec<f64> = (0..=periods * per)
            .map(|i| 2e6 + 0.5e6 * (std::f64::consts::TAU * i as f64 / per as f64).sin())
            .collect();
        let curve = spiral();
        let repeating = RainflowOptions {
            repeating: true,
            ..Default::default()
        };
        let d = sea_state_tension_damage(&t[..t.len() - 1], 0.25, &curve, &repeating).unwrap();
        let one = 1.0 / curve.cycles_to_failure(1e6);
        assert_eq!(d.cycles, 100.0);
        assert!((d.damage / (100.0 * one) - 1.0).abs() < 1e-9);
        assert!((d.mean_tension_n - 2e6).abs() < 1e-6);
        // Open history: 99 full cycles of 1 MN plus two half cycles of 0.5 MN at the ends.
        let open = sea_state_tension_damage(&t, 0.25, &curve, &RainflowOptions::default()).unwrap();
        let expected = 99.5 * one + curve.damage(0.5e6, 1.0);
        assert!(
            (open.damage / expected - 1.0).abs() < 1e-9,
            "{} vs {expected}",
            open.damage
        );
        assert_eq!(open.duration_s, 1000.0);
        assert!((open.rate_per_s() - open.damage / 1000.0).abs() < 1e-30);
    }

    #[test]
    fn histogram_and_cycle_damage_agree() {
        let cycles = [
            Cycle {
                range: 1e6,
                mean: 0.0,
                count: 1.0,
                start_index: 0,
                end_index: 1,
            },
            Cycle {
                range: 3e5,
                mean: 0.0,
                count: 0.5,
                start_index: 1,
                end_index: 2,
            },
        ];
        let curve = spiral();
        let from_hist = histogram_damage(&[(1e6, 1.0), (3e5, 0.5)], &curve);
        assert_eq!(miner_damage(&cycles, &curve), from_hist);
    }

    #[test]
    fn bad_inputs_are_rejected() {
        let curve = spiral();
        let o = RainflowOptions::default();
        assert!(matches!(
            sea_state_tension_damage(&[1.0, 2.0], 0.0, &curve, &o),
            Err(FatigueError::InvalidParameter { .. })
        ));
        assert!(matches!(
            sea_state_tension_damage(&[1.0, f64::NAN], 0.1, &curve, &o),
            Err(FatigueError::Rainflow(_))
        ));
    }
}
