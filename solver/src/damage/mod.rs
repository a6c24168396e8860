//! Per-sea-state damage inputs of one (sea state, seed, hot spot): what a strand job stores and
//! the lifetime aggregation sums (`docs/damage.md`).
//!
//! From the contact records of the strand stage ([`ContactRecord`]) and the hot-spot tension
//! history that drove it, [`sea_state_damage_inputs`] gives
//!
//! - per contact class (layer interface × angular position, [`ContactClass`]): the histogram of
//!   slip cycles per hour (slip amplitude × normal force, summed over the contacts of the
//!   class), the fretting damage rate of the contacts (largest and mean over the class), the
//!   cycles per hour in each fretting regime (stick / partial slip / gross slip), the largest
//!   Ruiz products and the largest Hertz peak pressure;
//! - per T-N curve: the Miner damage of the hot-spot tension over the effective duration and its
//!   rate (DNV-OS-E301 or API RP 2SK, [`crate::fatigue::tn`]).
//!
//! Conventions and assumptions:
//! - The tension series is sampled like the contact histories: sample `k` of `tension_n` is the
//!   load of step `k` of the strand run, so a cycle's `start_index ..= end_index` addresses both.
//! - The first `run_in_samples` samples are the strand's run-in ([`super::runin`]): cycles that
//!   start inside it are dropped and the T-N count starts after it. The effective duration is
//!   `(samples − run_in_samples − 1) · Δt`, as [`crate::fatigue::sea_state_tension_damage`]
//!   counts it.
//! - Wire axial stress over a cycle (needed by the default fretting S-N law and Ruiz F2): the
//!   hot-spot tension spread uniformly over the strand's metallic area, σ = T / A_metal, its
//!   maximum and range over the cycle's samples. This nominal stress omits the wire bending
//!   stress; it is the stress measure of the strand tests behind the DNV spiral-rope curve.
//! - API RP 2SK wire-rope curves depend on the mean load: the configured `mean_load_ratio` is
//!   replaced by this sea state's mean tension over the reference breaking strength (API RP 2SK
//!   3rd ed. §7.5: Lm is the ratio of mean load to the reference breaking strength).
//!
//! Units: m, N, Pa, s; damage is a Miner fraction; rates are per second of simulated time.

use std::collections::BTreeMap;

use serde::{Deserialize, Serialize};
use thiserror::Error;

use crate::fatigue::{sea_state_tension_damage, FatigueError, TnCurve};
use crate::fretting::life::field::EllipseHotSpot;
use crate::fretting::life::{cycle_life, ContactStressLaw, CycleLoad};
use crate::fretting::rainflow::RainflowOptions;
use crate::fretting::FrettingError;
use crate::fretting::{evaluate_cycle, FrettingParams, FrettingRegime, WireStress};
use crate::fretting::{BinEdges, CycleHistogram};
use crate::fretting::{ContactClass, ContactRecord};
use crate::fretting::{CrossedCylinders, HertzModel};

/// Seconds per hour, for the per-hour figures.
const SECONDS_PER_HOUR: f64 = 3600.0;

/// Errors of the damage-input computation. All are permanent (bad input).
#[derive(Debug, Clone, PartialEq, Error)]
pub enum DamageInputsError {
    /// Bad fretting parameter, histogram edges or contact geometry.
    #[error(transparent)]
    Fretting(#[from] FrettingError),
    /// Bad T-N curve or tension series.
    #[error(transparent)]
    Fatigue(#[from] FatigueError),
    /// Inconsistent input, with the field and the reason.
    #[error("`{field}` is invalid: {reason}")]
    InvalidInput {
        /// Field path.
        field: String,
        /// Why.
        reason: String,
    },
}

fn invalid(field: impl Into<String>, reason: impl Into<String>) -> DamageInputsError {
    DamageInputsError::InvalidInput {
        field: field.into(),
        reason: reason.into(),
    }
}

/// A T-N curve under the measure name its damage is stored with (`tn_dnv_spiral_rope`, …).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct NamedTnCurve {
    /// Measure name.
    pub measure: String,
    /// The curve and its section data.
    pub curve: TnCurve,
}

/// Which law charges a fretting cycle with damage (`fretting_max` / `fretting_mean`); the
/// other one is computed beside it (`rope_tn_*` columns, or the contact-stress ones).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum FrettingLaw {
    /// Life to crack initiation of each crossing from its contact stress field
    /// ([`super::life`]).
    #[default]
    ContactStress,
    /// The rope-level S-N law of [`FrettingParams::sn_law`] charged per slip cycle (by default
    /// the DNV spiral-rope curve on the wire's nominal stress range): kept for comparison.
    RopeTnPerSlipCycle,
}

impl FrettingLaw {
    /// Stable name, as in campaign files.
    pub fn as_str(self) -> &'static str {
        match self {
            Self::ContactStress => "contact_stress",
            Self::RopeTnPerSlipCycle => "rope_tn_per_slip_cycle",
        }
    }
}

/// Settings of the damage inputs (part of a campaign's fretting and fatigue settings).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct DamageInputsConfig {
    /// Slip amplitude bin edges of the cycle histograms (m), increasing.
    pub slip_amplitude_edges_m: Vec<f64>,
    /// Normal force bin edges of the cycle histograms (N), increasing.
    pub normal_force_edges_n: Vec<f64>,
    /// Friction, regime criterion, force measure and fretting S-N law.
    pub fretting: FrettingParams,
    /// Crossed-cylinder geometry of the wires at each layer interface, indexed by interface.
    pub interfaces: Vec<CrossedCylinders>,
    /// Metallic area of the strand (m²): wire axial stress σ = T / A_metal.
    pub metallic_area_m2: f64,
    /// T-N curves evaluated on the hot-spot tension.
    pub tn_curves: Vec<NamedTnCurve>,
    /// The law whose damage is `fretting_damage_rate_*`.
    #[serde(default)]
    pub law: FrettingLaw,
    /// Constants of the contact-stress law.
    #[serde(default)]
    pub contact_stress: ContactStressLaw,
}

/// The hot-spot load history of one realisation.
#[derive(Debug, Clone, Copy)]
pub struct TensionHistory<'a> {
    /// Tension at every strand load step (N).
    pub tension_n: &'a [f64],
    /// Sample interval (s).
    pub dt_s: f64,
    /// Samples of run-in excluded from the statistics.
    pub run_in_samples: usize,
}

/// Cycles in each fretting regime.
#[derive(Debug, Clone, Copy, Default, PartialEq, Serialize, Deserialize)]
pub struct RegimeCounts {
    /// Stick.
    pub stick: f64,
    /// Partial slip.
    pub partial_slip: f64,
    /// Gross slip.
    pub gross_slip: f64,
}

impl RegimeCounts {
    fn add(&mut self, regime: FrettingRegime, count: f64) {
        match regime {
            FrettingRegime::Stick => self.stick += count,
            FrettingRegime::PartialSlip => self.partial_slip += count,
            FrettingRegime::GrossSlip => self.gross_slip += count,
        }
    }

    fn scaled(self, factor: f64) -> Self {
        Self {
            stick: self.stick * factor,
            partial_slip: self.partial_slip * factor,
            gross_slip: self.gross_slip * factor,
        }
    }
}

/// Damage inputs of one contact class.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct ClassInputs {
    /// Layer interface × angular position.
    pub class: ContactClass,
    /// Contacts in the class.
    pub contacts: usize,
    /// Slip cycles per hour, summed over the contacts of the class.
    pub cycles_per_hour: CycleHistogram,
    /// Cycles per hour in each regime, summed over the contacts of the class.
    pub regime_cycles_per_hour: RegimeCounts,
    /// Largest fretting damage rate of a contact of the class (1/s).
    pub fretting_damage_rate_max_per_s: f64,
    /// Mean fretting damage rate over the contacts of the class (1/s).
    pub fretting_damage_rate_mean_per_s: f64,
    /// Largest Ruiz F1 = τδ of a cycle (N/m).
    pub ruiz_f1_max: f64,
    /// Largest Ruiz F2 = σ τ δ of a cycle (Pa·N/m).
    pub ruiz_f2_max: f64,
    /// Largest Hertz peak pressure of a cycle (Pa).
    pub peak_pressure_max_pa: f64,
    /// Largest slip amplitude of a cycle (m).
    pub slip_amplitude_max_m: f64,
    /// Largest damage rate of a contact of the class under the rope S-N law per slip cycle
    /// (1/s), whichever law `fretting_damage_rate_*` follows.
    #[serde(default)]
    pub rope_tn_damage_rate_max_per_s: f64,
    /// Mean of that rate over the contacts of the class (1/s).
    #[serde(default)]
    pub rope_tn_damage_rate_mean_per_s: f64,
    /// Largest damage rate of a contact of the class under the contact-stress law (1/s).
    #[serde(default)]
    pub contact_stress_damage_rate_max_per_s: f64,
    /// Mean of that rate over the contacts of the class (1/s).
    #[serde(default)]
    pub contact_stress_damage_rate_mean_per_s: f64,
    /// Largest frictional (wear) power of a contact of the class in gross slip, Σ 4μPδₐ over
    /// its gross-slip cycles per second (W).
    #[serde(default)]
    pub wear_power_max_w: f64,
}

/// T-N damage of the hot-spot tension under one curve.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct TensionInputs {
    /// Measure name of the curve.
    pub measure: String,
    /// The curve as evaluated (API: Lm of this sea state).
    pub curve: TnCurve,
    /// Miner damage over the effective duration.
    pub damage: f64,
    /// Damage per second (1/s).
    pub damage_rate_per_s: f64,
    /// Tension cycles counted (half cycles count 0.5).
    pub cycles: f64,
    /// Mean tension after the run-in (N).
    pub mean_tension_n: f64,
}

/// Damage inputs of one (sea state, seed, hot spot).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct SeaStateInputs {
    /// Simulated time after the run-in (s).
    pub effective_duration_s: f64,
    /// Run-in samples excluded.
    pub run_in_samples: usize,
    /// Per contact class, in class order.
    pub classes: Vec<ClassInputs>,
    /// Per T-N curve, in configuration order.
    pub tension: Vec<TensionInputs>,
}

/// Range maxima and minima in O(1) per query after an O(n log n) build (sparse table).
struct RangeExtrema {
    max: Vec<Vec<f64>>,
    min: Vec<Vec<f64>>,
}

impl RangeExtrema {
    fn new(x: &[f64]) -> Self {
        let (mut max, mut min) = (vec![x.to_vec()], vec![x.to_vec()]);
        let mut width = 1;
        while 2 * width <= x.len() {
            let (pmax, pmin) = (&max[max.len() - 1], &min[min.len() - 1]);
            let n = x.len() + 1 - 2 * width;
            let nmax = (0..n).map(|i| pmax[i].max(pmax[i + width])).collect();
            let nmin = (0..n).map(|i| pmin[i].min(pmin[i + width])).collect();
            max.push(nmax);
            min.push(nmin);
            width *= 2;
        }
        Self { max, min }
    }

    /// (min, max) over `lo ..= hi` (lo ≤ hi < n).
    fn query(&self, lo: usize, hi: usize) -> (f64, f64) {
        let level = (usize::BITS - 1 - (hi - lo + 1).leading_zeros()) as usize;
        let j = hi + 1 - (1 << level);
        (
            self.min[level][lo].min(self.min[level][j]),
            self.max[level][lo].max(self.max[level][j]),
        )
    }
}

struct ClassAccumulator {
    inputs: ClassInputs,
    rope_sum: f64,
    stress_sum: f64,
}

/// Damage inputs of one (sea state, seed, hot spot); see the module docs.
pub fn sea_state_damage_inputs(
    records: &[ContactRecord],
    history: &TensionHistory<'_>,
    config: &DamageInputsConfig,
) -> Result<SeaStateInputs, DamageInputsError> {
    config.fretting.validate()?;
    config.contact_stress.validate()?;
    let area = config.metallic_area_m2;
    if !(area.is_finite() && area > 0.0) {
        return Err(invalid("metallic_area_m2", format!("{area} must be > 0")));
    }
    if !(history.dt_s.is_finite() && history.dt_s > 0.0) {
        return Err(invalid("dt_s", format!("{} must be > 0", history.dt_s)));
    }
    let tension = history.tension_n;
    if let Some(k) = tension.iter().position(|t| !t.is_finite()) {
        return Err(invalid(format!("tension_n[{k}]"), "is not finite"));
    }
    if tension.len() < history.run_in_samples + 2 {
        return Err(invalid(
            "tension_n",
            format!(
                "{} samples leave no time after a run-in of {} samples",
                tension.len(),
                history.run_in_samples
            ),
        ));
    }
    let duration = (tension.len() - history.run_in_samples - 1) as f64 * history.dt_s;
    let per_hour = SECONDS_PER_HOUR / duration;
    let empty = CycleHistogram::new(
        BinEdges::new(config.slip_amplitude_edges_m.clone())?,
        BinEdges::new(config.normal_force_edges_n.clone())?,
        config.fretting.force_measure,
    );
    let models = config
        .interfaces
        .iter()
        .map(HertzModel::crossed_cylinders)
        .collect::<Result<Vec<_>, _>>()
        .map_err(FrettingError::from)?;
    let nu = config.contact_stress.material().poisson_ratio;
    let shapes: Vec<_> = models
        .iter()
        .map(|m| EllipseHotSpot::shared(m.axis_ratio, nu))
        .collect();
    let extrema = RangeExtrema::new(tension);
    let mut classes: BTreeMap<ContactClass, ClassAccumulator> = BTreeMap::new();
    for (r, record) in records.iter().enumerate() {
        let model = models.get(record.interface).ok_or_else(|| {
            invalid(
                format!("records[{r}].interface"),
                format!(
                    "{} has no geometry in `interfaces` ({} given)",
                    record.interface,
                    models.len()
                ),
            )
        })?;
        let class = classes
            .entry(record.class())
            .or_insert_with(|| ClassAccumulator {
                inputs: ClassInputs {
                    class: record.class(),
                    contacts: 0,
                    cycles_per_hour: empty.clone(),
                    regime_cycles_per_hour: RegimeCounts::default(),
                    fretting_damage_rate_max_per_s: 0.0,
                    fretting_damage_rate_mean_per_s: 0.0,
                    ruiz_f1_max: 0.0,
                    ruiz_f2_max: 0.0,
                    peak_pressure_max_pa: 0.0,
                    slip_amplitude_max_m: 0.0,
                    rope_tn_damage_rate_max_per_s: 0.0,
                    rope_tn_damage_rate_mean_per_s: 0.0,
                    contact_stress_damage_rate_max_per_s: 0.0,
                    contact_stress_damage_rate_mean_per_s: 0.0,
                    wear_power_max_w: 0.0,
                },
                rope_sum: 0.0,
                stress_sum: 0.0,
            });
        let out = &mut class.inputs;
        out.contacts += 1;
        let (mut rope_damage, mut stress_damage, mut wear) = (0.0, 0.0, 0.0);
        for (c, cycle) in record.cycles.iter().enumerate() {
            let (lo, hi) = (cycle.slip.start_index, cycle.slip.end_index);
            if lo < history.run_in_samples {
                continue;
            }
            if hi >= tension.len() || lo > hi {
                return Err(invalid(
                    format!("records[{r}].cycles[{c}]"),
                    format!(
                        "samples {lo}..={hi} do not lie in the tension series of {} samples",
                        tension.len()
                    ),
                ));
            }
            let (t_min, t_max) = extrema.query(lo, hi);
            let stress = WireStress {
                axial_max_pa: t_max / area,
                axial_range_pa: (t_max - t_min) / area,
            };
            let ind = evaluate_cycle(model, &config.fretting, cycle, &stress)?;
            rope_damage += ind.damage;
            let t = &cycle.tangential_force_n;
            let life = cycle_life(
                model,
                &shapes[record.interface],
                config.fretting.friction_coefficient,
                &config.contact_stress,
                &CycleLoad {
                    normal_force_n: ind.normal_force_n,
                    tangential_amplitude_n: 0.5 * (t.max - t.min),
                    slip_amplitude_m: ind.slip_amplitude_m,
                    bulk_max_pa: stress.axial_max_pa,
                    bulk_min_pa: stress.axial_max_pa - stress.axial_range_pa,
                },
            )?;
            stress_damage += cycle.slip.count / life.cycles_to_initiation;
            wear += cycle.slip.count * life.wear_energy_j;
            out.cycles_per_hour.add_cycle(cycle);
            let regime = match config.law {
                FrettingLaw::ContactStress => life.regime,
                FrettingLaw::RopeTnPerSlipCycle => ind.regime,
            };
            out.regime_cycles_per_hour.add(regime, cycle.slip.count);
            out.ruiz_f1_max = out.ruiz_f1_max.max(ind.ruiz_f1);
            out.ruiz_f2_max = out.ruiz_f2_max.max(ind.ruiz_f2);
            out.peak_pressure_max_pa = out.peak_pressure_max_pa.max(ind.contact.peak_pressure_pa);
            out.slip_amplitude_max_m = out.slip_amplitude_max_m.max(ind.slip_amplitude_m);
        }
        let (rope, stress) = (rope_damage / duration, stress_damage / duration);
        out.rope_tn_damage_rate_max_per_s = out.rope_tn_damage_rate_max_per_s.max(rope);
        out.contact_stress_damage_rate_max_per_s =
            out.contact_stress_damage_rate_max_per_s.max(stress);
        out.wear_power_max_w = out.wear_power_max_w.max(wear / duration);
        class.rope_sum += rope;
        class.stress_sum += stress;
    }
    let classes = classes
        .into_values()
        .map(|acc| {
            let mut inputs = acc.inputs;
            let n = inputs.contacts as f64;
            inputs.rope_tn_damage_rate_mean_per_s = acc.rope_sum / n;
            inputs.contact_stress_damage_rate_mean_per_s = acc.stress_sum / n;
            (
                inputs.fretting_damage_rate_max_per_s,
                inputs.fretting_damage_rate_mean_per_s,
            ) = match config.law {
                FrettingLaw::ContactStress => (
                    inputs.contact_stress_damage_rate_max_per_s,
                    inputs.contact_stress_damage_rate_mean_per_s,
                ),
                FrettingLaw::RopeTnPerSlipCycle => (
                    inputs.rope_tn_damage_rate_max_per_s,
                    inputs.rope_tn_damage_rate_mean_per_s,
                ),
            };
            inputs.cycles_per_hour = inputs.cycles_per_hour.scaled(per_hour);
            inputs.regime_cycles_per_hour = inputs.regime_cycles_per_hour.scaled(per_hour);
            inputs
        })
        .collect();
    let after = &tension[history.run_in_samples..];
    let mean_tension = after.iter().sum::<f64>() / after.len() as f64;
    let tension = config
        .tn_curves
        .iter()
        .enumerate()
        .map(|(k, named)| tension_inputs(k, named, after, history.dt_s, mean_tension))
        .collect::<Result<Vec<_>, _>>()?;
    Ok(SeaStateInputs {
        effective_duration_s: duration,
        run_in_samples: history.run_in_samples,
        classes,
        tension,
    })
}

fn tension_inputs(
    k: usize,
    named: &NamedTnCurve,
    tension_n: &[f64],
    dt_s: f64,
    mean_tension_n: f64,
) -> Result<TensionInputs, DamageInputsError> {
    let mut curve = named.curve;
    if let TnCurve::Api {
        reference_breaking_strength_n,
        ref mut mean_load_ratio,
        ..
    } = curve
    {
        let lm = mean_tension_n / reference_breaking_strength_n;
        if !(0.0..1.0).contains(&lm) {
            return Err(invalid(
                format!("tn_curves[{k}].curve"),
                format!("mean tension {mean_tension_n} N over the reference breaking strength is {lm}, outside [0, 1)"),
            ));
        }
        *mean_load_ratio = lm;
    }
    let d = sea_state_tension_damage(tension_n, dt_s, &curve, &RainflowOptions::default())?;
    Ok(TensionInputs {
        measure: named.measure.clone(),
        curve,
        damage: d.damage,
        damage_rate_per_s: d.rate_per_s(),
        cycles: d.cycles,
        mean_tension_n: d.mean_tension_n,
    })
}

#[cfg(test)]
mod tests;
