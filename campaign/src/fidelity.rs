//! Which strand model a campaign's strand jobs run (`strand.fidelity`), and how the `auto`
//! fidelity picks the sea states that also run the FE model.
//!
//! - `fe`: every (sea state, seed, hot spot) runs the strand FE model (minutes each).
//! - `reduced`: one calibration job per hot spot fits the reduced strand response
//!   (`moorfret_solver::strand::reduced`) on the FE model over the load range of every global
//!   job of the campaign; every strand job then runs the reduced response (seconds each).
//! - `auto`: as `reduced`, and the sea states carrying the largest share of the reduced
//!   estimate of annual fretting damage also run FE ([`AutoFe`], [`select_fe_sea_states`]).
//!   Where both ran, the FE result is the one counted and the pair is compared
//!   (`fidelity_comparison` view of the store).

use std::collections::BTreeMap;

use serde::{Deserialize, Serialize};

use crate::error::CampaignError;

/// Strand model of a campaign's strand jobs.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum StrandFidelity {
    /// The strand FE model for every job.
    #[default]
    Fe,
    /// The reduced strand response, calibrated once per hot spot, for every job.
    Reduced,
    /// Reduced for every job; FE as well for the sea states that carry most of the damage.
    Auto,
}

impl StrandFidelity {
    /// Whether the campaign calibrates and runs the reduced response.
    pub fn uses_reduced(self) -> bool {
        matches!(self, Self::Reduced | Self::Auto)
    }

    /// Whether `self` is the default (`fe`).
    pub fn is_fe(&self) -> bool {
        *self == Self::Fe
    }
}

/// How the `auto` fidelity picks the sea states that also run FE: in decreasing order of
/// their share of the reduced estimate of the annual fretting damage of the governing contact
/// class (the class with the largest annual damage), until `sea_states` are taken or their
/// shares sum to `damage_share`, whichever comes first.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct AutoFe {
    /// Most sea states that run FE (≥ 1).
    #[serde(default = "default_fe_sea_states")]
    pub sea_states: usize,
    /// Share of the annual fretting damage (0, 1] at which the selection stops.
    #[serde(default = "default_fe_damage_share")]
    pub damage_share: f64,
}

fn default_fe_sea_states() -> usize {
    2
}

fn default_fe_damage_share() -> f64 {
    1.0
}

impl Default for AutoFe {
    fn default() -> Self {
        Self {
            sea_states: default_fe_sea_states(),
            damage_share: default_fe_damage_share(),
        }
    }
}

impl AutoFe {
    /// Whether `self` is the default.
    pub fn is_default(&self) -> bool {
        *self == Self::default()
    }

    /// Checks the settings; errors name the field (`strand.auto_fe.…`).
    pub fn validate(&self) -> Result<(), CampaignError> {
        let invalid = |field: &str, value: String, reason: &str| CampaignError::Invalid {
            field: format!("strand.auto_fe.{field}"),
            value,
            reason: reason.to_owned(),
        };
        if self.sea_states == 0 {
            return Err(invalid("sea_states", "0".into(), "must be >= 1"));
        }
        if !(self.damage_share.is_finite() && self.damage_share > 0.0 && self.damage_share <= 1.0) {
            return Err(invalid(
                "damage_share",
                self.damage_share.to_string(),
                "must be in (0, 1]",
            ));
        }
        Ok(())
    }
}

/// A contact class: layer interface and angular position name.
type Class = (i64, &'static str);

/// One strand result of one contact class: the input of [`select_fe_sea_states`] and of the
/// extra-seed rule (`crate::seeds`).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ClassDamageRate {
    /// Sea state index in the campaign.
    pub sea_state_index: i64,
    /// Its fraction of the year.
    pub occurrence_fraction: f64,
    /// Seed index within the sea state.
    pub seed_index: i64,
    /// Contact class: layer interface and angular position name.
    pub class: (i64, &'static str),
    /// Fretting damage rate of the class's most damaged contact (1/s).
    pub damage_rate_per_s: f64,
}

/// What a selection by damage share chose, and why.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Selection {
    /// The governing class: layer interface and angular position.
    pub class: Option<(i64, &'static str)>,
    /// Its annual damage (1/year; occurrence-weighted, seed means) in the rows.
    pub annual_damage: f64,
    /// The chosen sea states with their share of that damage, largest first.
    pub sea_states: Vec<(i64, f64)>,
}

impl Selection {
    /// Whether `sea_state_index` is among the chosen.
    pub fn contains(&self, sea_state_index: i64) -> bool {
        self.sea_states.iter().any(|&(s, _)| s == sea_state_index)
    }
}

/// The sea states that run FE under `rule` (module docs): deterministic for given rows
/// (ties go to the lower sea state index). Rows with a non-finite or negative rate count as
/// zero. With no damage at all, nothing is chosen.
pub fn select_fe_sea_states(rows: &[ClassDamageRate], rule: &AutoFe) -> Selection {
    select_by_damage_share(rows, rule.sea_states, rule.damage_share)
}

/// The sea states carrying the largest shares of the annual fretting damage of the governing
/// contact class in `rows` (the class with the largest occurrence-weighted sum of seed-mean
/// damage rates), in decreasing order of share, until `max_sea_states` are taken or their
/// shares sum to `damage_share`, whichever comes first. Deterministic for given rows in any
/// order (ties go to the lower sea state index, then the lower class); rows with a non-finite
/// or negative rate count as zero; sea states without damage are never chosen.
pub fn select_by_damage_share(
    rows: &[ClassDamageRate],
    max_sea_states: usize,
    damage_share: f64,
) -> Selection {
    // seed means per (class, sea state), then occurrence-weighted annual damage per class
    const YEAR_S: f64 = 31_557_600.0;
    // (class, sea state) → (occurrence, Σ rate over seeds, seeds)
    let mut sums: BTreeMap<(Class, i64), (f64, f64, usize)> = BTreeMap::new();
    for r in rows {
        let rate = if r.damage_rate_per_s.is_finite() && r.damage_rate_per_s > 0.0 {
            r.damage_rate_per_s
        } else {
            0.0
        };
        let e = sums
            .entry((r.class, r.sea_state_index))
            .or_insert((r.occurrence_fraction, 0.0, 0));
        e.1 += rate;
        e.2 += 1;
    }
    let mut per_class: BTreeMap<Class, Vec<(i64, f64)>> = BTreeMap::new();
    for ((class, sea_state), (occurrence, sum, n)) in sums {
        let annual = occurrence * YEAR_S * sum / n as f64;
        per_class
            .entry(class)
            .or_default()
            .push((sea_state, annual));
    }
    let governing = per_class
        .iter()
        .map(|(class, cells)| (*class, cells.iter().map(|c| c.1).sum::<f64>()))
        .filter(|(_, total)| *total > 0.0)
        .fold(
            None,
            |best: Option<((i64, &'static str), f64)>, c| match best {
                Some(b) if b.1 >= c.1 => Some(b),
                _ => Some(c),
            },
        );
    let Some((class, total)) = governing else {
        return Selection {
            class: None,
            annual_damage: 0.0,
            sea_states: Vec::new(),
        };
    };
    let mut cells = per_class.remove(&class).unwrap_or_default();
    cells.sort_by(|a, b| b.1.total_cmp(&a.1).then(a.0.cmp(&b.0)));
    let mut chosen = Vec::new();
    let mut covered = 0.0;
    for (sea_state, annual) in cells {
        if chosen.len() >= max_sea_states || covered >= damage_share * (1.0 - 1e-12) {
            break;
        }
        if annual <= 0.0 {
            break;
        }
        let share = annual / total;
        covered += share;
        chosen.push((sea_state, share));
    }
    Selection {
        class: Some(class),
        annual_damage: total,
        sea_states: chosen,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn row(sea_state: i64, occurrence: f64, seed: i64, class: i64, rate: f64) -> ClassDamageRate {
        ClassDamageRate {
            sea_state_index: sea_state,
            occurrence_fraction: occurrence,
            seed_index: seed,
            class: (class, "outer_arc"),
            damage_rate_per_s: rate,
        }
    }

    #[test]
    fn the_governing_class_and_its_largest_shares_are_chosen() {
        // class 1 governs (annual damage ∝ 0.5·4 + 0.3·1 + 0.2·1 = 2.5 against 0.5·1 = 0.5);
        // its sea states' shares: 0.8, 0.12, 0.08
        let rows = [
            row(0, 0.5, 0, 1, 4.0),
            row(1, 0.3, 0, 1, 1.0),
            row(2, 0.2, 0, 1, 1.0),
            row(0, 0.5, 0, 0, 1.0),
            row(2, 0.2, 0, 0, 0.0),
        ];
        let all = select_fe_sea_states(
            &rows,
            &AutoFe {
                sea_states: 10,
                damage_share: 1.0,
            },
        );
        assert_eq!(all.class, Some((1, "outer_arc")));
        let year = 31_557_600.0;
        assert!((all.annual_damage - 2.5 * year).abs() < 1e-9 * year);
        let ids: Vec<i64> = all.sea_states.iter().map(|s| s.0).collect();
        assert_eq!(ids, [0, 1, 2]);
        assert!((all.sea_states[0].1 - 0.8).abs() < 1e-12);
        assert!((all.sea_states[1].1 - 0.12).abs() < 1e-12);
        // the share rule stops once 80 % is covered, the count rule after one
        let share = select_fe_sea_states(
            &rows,
            &AutoFe {
                sea_states: 10,
                damage_share: 0.8,
            },
        );
        assert_eq!(share.sea_states.len(), 1);
        let share = select_fe_sea_states(
            &rows,
            &AutoFe {
                sea_states: 10,
                damage_share: 0.85,
            },
        );
        assert_eq!(share.sea_states.len(), 2);
        let count = select_fe_sea_states(
            &rows,
            &AutoFe {
                sea_states: 1,
                damage_share: 1.0,
            },
        );
        assert_eq!(count.sea_states.len(), 1);
        assert!(count.contains(0) && !count.contains(1));
    }

    #[test]
    fn seeds_are_averaged_and_ties_go_to_the_lower_index() {
        // sea state 3: seeds 2 and 0 → mean 1; sea state 1: one seed of 1 → a tie
        let rows = [
            row(3, 0.1, 0, 0, 2.0),
            row(3, 0.1, 1, 0, 0.0),
            row(1, 0.1, 0, 0, 1.0),
        ];
        let s = select_fe_sea_states(
            &rows,
            &AutoFe {
                sea_states: 1,
                damage_share: 1.0,
            },
        );
        assert_eq!(s.sea_states.len(), 1);
        assert_eq!(s.sea_states[0].0, 1);
        assert!((s.sea_states[0].1 - 0.5).abs() < 1e-12);
    }

    #[test]
    fn no_damage_chooses_nothing_and_bad_rates_count_as_zero() {
        let rows = [
            row(0, 0.5, 0, 0, 0.0),
            row(1, 0.5, 0, 0, f64::NAN),
            row(2, 0.5, 0, 0, -1.0),
        ];
        let s = select_fe_sea_states(&rows, &AutoFe::default());
        assert_eq!(s.class, None);
        assert!(s.sea_states.is_empty());
        assert!(select_fe_sea_states(&[], &AutoFe::default())
            .sea_states
            .is_empty());
    }

    #[test]
    fn settings_are_checked_by_field() {
        assert!(AutoFe::default().validate().is_ok());
        let e = AutoFe {
            sea_states: 0,
            damage_share: 1.0,
        }
        .validate()
        .unwrap_err();
        assert!(e.to_string().contains("strand.auto_fe.sea_states"), "{e}");
        for share in [0.0, 1.5, f64::NAN] {
            let e = AutoFe {
                sea_states: 1,
                damage_share: share,
            }
            .validate()
            .unwrap_err();
            assert!(e.to_string().contains("strand.auto_fe.damage_share"), "{e}");
        }
    }
}
