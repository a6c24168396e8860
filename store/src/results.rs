//! Result rows of strand jobs and what the result views return (README, "Results and queries";
//! `docs/damage.md`).
//!
//! A strand job turns its sea-state damage inputs (the worker's `damage_rows`) into
//! one [`DamageInput`] per T-N curve (table `damage_inputs`) and one [`ClassDamageInput`] per
//! contact class (table `class_damage_inputs`), stored with the job's completion
//! ([`super::JobResults`]). The views `sea_state_class_damage_inputs` and
//! `lifetime_class_damage` aggregate them; [`SeaStateClassDamage`] and [`LifetimeClassDamage`]
//! are their rows.

use moorfret_vocabulary::AngularPosition;
use serde::{Deserialize, Serialize};
use serde_json::Value;

use super::error::StoreError;

/// Damage accumulated by one realisation over its effective simulated time.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct DamageInput {
    /// Hot spot index in the campaign.
    pub hot_spot_index: i64,
    /// Damage measure (`tension_tn`, `fretting_sn`, …).
    pub measure: String,
    /// Seed index within the sea state.
    pub seed_index: i64,
    /// Simulated time after the run-in, s.
    pub effective_duration_s: f64,
    /// Miner damage over `effective_duration_s`.
    pub damage: f64,
    /// Supporting values (cycle counts, curve parameters).
    pub details: Value,
}

/// Damage inputs of one contact class from one strand job (`class_damage_inputs` row).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct ClassDamageInput {
    /// Hot spot index in the campaign.
    pub hot_spot_index: i64,
    /// Layer interface (0: core / layer 1, k: layer k / layer k+1).
    pub layer_interface: i64,
    /// Angular position class.
    pub angular_position: AngularPosition,
    /// Seed index within the sea state.
    pub seed_index: i64,
    /// Simulated time after the run-in (s).
    pub effective_duration_s: f64,
    /// Contacts in the class.
    pub contacts: i64,
    /// Largest fretting damage rate of a contact of the class (1/s).
    pub fretting_damage_rate_max_per_s: f64,
    /// Mean fretting damage rate over the contacts of the class (1/s).
    pub fretting_damage_rate_mean_per_s: f64,
    /// Stick cycles per hour, summed over the class.
    pub stick_cycles_per_hour: f64,
    /// Partial-slip cycles per hour, summed over the class.
    pub partial_slip_cycles_per_hour: f64,
    /// Gross-slip cycles per hour, summed over the class.
    pub gross_slip_cycles_per_hour: f64,
    /// Largest Ruiz F1 = τδ (N/m).
    pub ruiz_f1_max: f64,
    /// Largest Ruiz F2 = στδ (Pa·N/m).
    pub ruiz_f2_max: f64,
    /// Largest Hertz peak pressure (Pa).
    pub peak_pressure_max_pa: f64,
    /// Largest slip amplitude (m).
    pub slip_amplitude_max_m: f64,
    /// Cycles per hour over slip amplitude × normal force (`CycleHistogram` as JSON).
    pub histogram: Value,
    /// Largest damage rate of a contact of the class under the rope S-N law per slip cycle
    /// (1/s; `fretting_*` follow the campaign's fretting law).
    #[serde(default)]
    pub rope_tn_damage_rate_max_per_s: f64,
    /// Mean of that rate over the class (1/s).
    #[serde(default)]
    pub rope_tn_damage_rate_mean_per_s: f64,
    /// Largest gross-slip frictional power of a contact of the class (W).
    #[serde(default)]
    pub wear_power_max_w: f64,
}

/// Reads a stored angular position name.
pub(crate) fn parse_position(text: &str) -> Result<AngularPosition, StoreError> {
    [
        AngularPosition::NeutralAxis,
        AngularPosition::Between,
        AngularPosition::OuterArc,
    ]
    .into_iter()
    .find(|p| p.as_str() == text)
    .ok_or_else(|| StoreError::UnknownValue {
        field: "angular_position",
        value: text.to_owned(),
    })
}

/// A row of the `sea_state_class_damage_inputs` view.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct SeaStateClassDamage {
    /// Index of the sea state in the campaign.
    pub sea_state_index: i64,
    /// Significant wave height (m).
    pub hs_m: f64,
    /// Peak period (s).
    pub tp_s: f64,
    /// Fraction of the year.
    pub occurrence_fraction: f64,
    /// Hot spot index.
    pub hot_spot_index: i64,
    /// Layer interface.
    pub layer_interface: i64,
    /// Angular position class.
    pub angular_position: AngularPosition,
    /// `fretting_max` or `fretting_mean`.
    pub measure: String,
    /// Seeds averaged.
    pub seeds: i64,
    /// Contacts in the class.
    pub contacts: i64,
    /// Seed-mean effective duration (s).
    pub effective_duration_s: f64,
    /// Seed-mean damage rate (1/s).
    pub damage_rate_per_s: f64,
    /// Seed-mean damage over the effective duration.
    pub damage_seed_mean: f64,
    /// Seed-to-seed standard deviation of the damage rate (1/s; n - 1 in the denominator);
    /// `None` for a single seed.
    pub damage_rate_sd: Option<f64>,
    /// Seed-mean stick cycles per hour.
    pub stick_cycles_per_hour: f64,
    /// Seed-mean partial-slip cycles per hour.
    pub partial_slip_cycles_per_hour: f64,
    /// Seed-mean gross-slip cycles per hour.
    pub gross_slip_cycles_per_hour: f64,
    /// Largest Ruiz F1 over the seeds (N/m).
    pub ruiz_f1_max: f64,
    /// Largest Ruiz F2 over the seeds (Pa·N/m).
    pub ruiz_f2_max: f64,
    /// Largest Hertz peak pressure (Pa).
    pub peak_pressure_max_pa: f64,
    /// Largest slip amplitude (m).
    pub slip_amplitude_max_m: f64,
    /// The strand model of the counted results: `fe`, `reduced`, or `mixed` (seeds of both).
    pub fidelity: String,
}

/// A row of the `fidelity_comparison` view: the reduced and the FE result of one contact class
/// where both ran for the same sea state, seed and hot spot.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct FidelityComparison {
    /// Index of the sea state in the campaign.
    pub sea_state_index: i64,
    /// Significant wave height (m).
    pub hs_m: f64,
    /// Peak period (s).
    pub tp_s: f64,
    /// Fraction of the year.
    pub occurrence_fraction: f64,
    /// Seed index within the sea state.
    pub seed_index: i64,
    /// Hot spot index.
    pub hot_spot_index: i64,
    /// Layer interface.
    pub layer_interface: i64,
    /// Angular position class.
    pub angular_position: AngularPosition,
    /// Fretting damage rate of the class's most damaged contact, reduced response (1/s).
    pub reduced_damage_rate_max_per_s: f64,
    /// The same from the FE model (1/s).
    pub fe_damage_rate_max_per_s: f64,
    /// Mean fretting damage rate over the class's contacts, reduced response (1/s).
    pub reduced_damage_rate_mean_per_s: f64,
    /// The same from the FE model (1/s).
    pub fe_damage_rate_mean_per_s: f64,
    /// Largest slip amplitude, reduced response (m).
    pub reduced_slip_amplitude_max_m: f64,
    /// The same from the FE model (m).
    pub fe_slip_amplitude_max_m: f64,
    /// Partial- and gross-slip cycles per hour, reduced response.
    pub reduced_slip_cycles_per_hour: f64,
    /// The same from the FE model.
    pub fe_slip_cycles_per_hour: f64,
}

/// A row of the `lifetime_class_damage` view.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct LifetimeClassDamage {
    /// Hot spot index.
    pub hot_spot_index: i64,
    /// Layer interface.
    pub layer_interface: i64,
    /// Angular position class.
    pub angular_position: AngularPosition,
    /// `fretting_max` or `fretting_mean`.
    pub measure: String,
    /// Σ occurrence × (year / T_eff) × seed-mean damage, per year.
    pub annual_damage: f64,
    /// Fraction of the year the contributing sea states cover.
    pub occurrence_covered: f64,
    /// Contributing sea states.
    pub sea_states: i64,
    /// The seed band of `annual_damage`.
    #[serde(flatten)]
    pub band: SeedBand,
}

/// A row of the `sea_state_damage_inputs` view (T-N and other per-hot-spot measures).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct SeaStateDamage {
    /// Index of the sea state in the campaign.
    pub sea_state_index: i64,
    /// Significant wave height (m).
    pub hs_m: f64,
    /// Peak period (s).
    pub tp_s: f64,
    /// Fraction of the year.
    pub occurrence_fraction: f64,
    /// Hot spot index.
    pub hot_spot_index: i64,
    /// Measure name.
    pub measure: String,
    /// Seeds averaged.
    pub seeds: i64,
    /// Seed-mean damage over the effective duration.
    pub damage_seed_mean: f64,
    /// Seed-mean effective duration (s).
    pub effective_duration_s: f64,
    /// Seed-mean damage rate (1/s).
    pub damage_rate_per_s: f64,
    /// Seed-to-seed standard deviation of the damage rate (1/s; n - 1 in the denominator);
    /// `None` for a single seed.
    pub damage_rate_sd: Option<f64>,
    /// The strand model of the counted results: `fe`, `reduced`, or `mixed` (seeds of both).
    pub fidelity: String,
}

/// How far the seeds leave a lifetime figure uncertain (views of migration 0004): the annual
/// damage D = Σ_c p_c · year · mean_c over the sea states c has the standard error
/// SE = √(Σ_c (p_c · year)² s_c² / n_c) over the sea states with n_c ≥ 2 seeds (s_c their
/// sample standard deviation); a sea state with one seed adds no spread and is counted in
/// `sea_states_without_spread`. The band is D ± 2 SE (the lower end floored at 0), about 95 %
/// when the effective degrees of freedom (Welch–Satterthwaite) are large; with few, a
/// Student-t factor above 2 applies (`effective_dof` says how many).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct SeedBand {
    /// Standard error of the annual damage from the seed spread (1/year).
    pub annual_damage_se: f64,
    /// D − 2 SE, not below 0 (1/year).
    pub annual_damage_low: f64,
    /// D + 2 SE (1/year).
    pub annual_damage_high: f64,
    /// Welch–Satterthwaite degrees of freedom of SE: (Σ v_c)² / Σ v_c² / (n_c − 1) with
    /// v_c = (p_c · year)² s_c² / n_c; `None` without spread.
    pub effective_dof: Option<f64>,
    /// Sea states with two seeds or more.
    pub sea_states_with_spread: i64,
    /// Sea states with one seed.
    pub sea_states_without_spread: i64,
}

impl SeedBand {
    /// The band of `annual_damage` from the view's `annual_damage_variance` (Σ v_c) and
    /// `annual_damage_variance_dof_sum` (Σ v_c² / (n_c − 1)). A negative variance (round-off
    /// of a zero spread) counts as zero.
    pub fn new(
        annual_damage: f64,
        variance: f64,
        dof_sum: f64,
        sea_states_with_spread: i64,
        sea_states_without_spread: i64,
    ) -> Self {
        let se = variance.max(0.0).sqrt();
        let effective_dof =
            (sea_states_with_spread > 0 && dof_sum > 0.0).then(|| variance * variance / dof_sum);
        Self {
            annual_damage_se: se,
            annual_damage_low: (annual_damage - 2.0 * se).max(0.0),
            annual_damage_high: annual_damage + 2.0 * se,
            effective_dof,
            sea_states_with_spread,
            sea_states_without_spread,
        }
    }
}

/// The standard deviation of a variance column (`None` for NULL; negative round-off → 0).
pub fn standard_deviation(variance: Option<f64>) -> Option<f64> {
    variance.map(|v| v.max(0.0).sqrt())
}

/// A sea state of a campaign with the state of its jobs.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct SeaStateStatus {
    /// Row id.
    pub sea_state_id: i64,
    /// Index in the campaign.
    pub sea_state_index: i64,
    /// Significant wave height (m).
    pub hs_m: f64,
    /// Peak period (s).
    pub tp_s: f64,
    /// Fraction of the year.
    pub occurrence_fraction: f64,
    /// Jobs planned.
    pub jobs_total: i64,
    /// Jobs done.
    pub jobs_done: i64,
    /// Jobs failed.
    pub jobs_failed: i64,
    /// Wave heading (deg); `None` in stores written before directional climates.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub heading_deg: Option<f64>,
    /// Directional sector; `None` for a climate of one table.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub sector: Option<String>,
    /// Fraction of the spectrum's variance the wave cut-off keeps, stored at planning; `None`
    /// in stores written before it was stored.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub wave_energy_kept: Option<f64>,
}

/// A `contact_statistics` row with its sea state.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct ContactRow {
    /// Index of the sea state in the campaign.
    pub sea_state_index: i64,
    /// Job that wrote the row.
    pub job_id: i64,
    /// Hot spot index.
    pub hot_spot_index: i64,
    /// Contact index in the strand model.
    pub contact_index: i64,
    /// Layer interface.
    pub layer_interface: i64,
    /// Angle from the bending neutral axis (rad).
    pub angular_position_rad: f64,
    /// Statistics as stored.
    pub statistics: Value,
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_band_is_two_standard_errors_wide_and_never_below_zero() {
        // Var = 4 → SE = 2; one sea state with 3 seeds: Σ v² / (n − 1) = 16 / 2 → 2 dof
        let b = SeedBand::new(10.0, 4.0, 8.0, 1, 2);
        assert_eq!(
            (
                b.annual_damage_se,
                b.annual_damage_low,
                b.annual_damage_high
            ),
            (2.0, 6.0, 14.0)
        );
        assert_eq!(b.effective_dof, Some(2.0));
        // a spread larger than half the damage: the lower end stops at zero
        let wide = SeedBand::new(1.0, 4.0, 8.0, 1, 0);
        assert_eq!(
            (wide.annual_damage_low, wide.annual_damage_high),
            (0.0, 5.0)
        );
        // no sea state with two seeds: no spread, no degrees of freedom
        let none = SeedBand::new(1.0, 0.0, 0.0, 0, 3);
        assert_eq!((none.annual_damage_se, none.effective_dof), (0.0, None));
        assert_eq!(
            (none.annual_damage_low, none.annual_damage_high),
            (1.0, 1.0)
        );
        // round-off below zero counts as no spread
        assert_eq!(SeedBand::new(1.0, -1e-30, 0.0, 1, 0).annual_damage_se, 0.0);
        assert_eq!(standard_deviation(Some(9.0)), Some(3.0));
        assert_eq!(standard_deviation(None), None);
    }
}
