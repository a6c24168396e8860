//! Seeds where the damage is: `simulation.extra_seeds`, the rule that gives more random
//! realisations to the sea states carrying most of the damage.
//!
//! Every sea state runs `simulation.seeds_per_sea_state` (N) seeds. With
//! `"extra_seeds": {"seeds": S, "damage_share": q}`, the sea states that together hold the
//! share q of the *first-seed estimate* of the annual fretting damage of the governing contact
//! class run S seeds in all (S > N): the sea states are taken in decreasing order of their
//! share until the shares sum to q ([`crate::fidelity::select_by_damage_share`]), per hot spot.
//!
//! The first-seed estimate is what every sea state has once its N first seeds ran:
//! - `strand.fidelity = fe`: the FE strand results of seeds 0..N;
//! - `reduced` and `auto`: the reduced strand results of seeds 0..N. In `auto` they are also
//!   what picks the FE sea states, and they are there minutes before the FE results; the extra
//!   seeds of an `auto` campaign run the reduced strand response only (their FE cost would be
//!   that of the whole FE stage again per extra seed), so in a sea state that also ran FE the
//!   counted seeds mix the two fidelities (the seed views say `mixed`).
//!
//! The extra seeds' jobs are planned with the campaign (a global job per sea state and extra
//! seed, and its strand jobs), each gated: it depends on every first-seed strand job the
//! selection reads, and when it runs it recomputes the selection from the stored rows and ends
//! at once, with no rows, if its sea state is not selected (a global job: for no hot spot; a
//! strand job: for its hot spot). The selection is a pure function of stored rows, so every
//! gated job computes the same one, and a resume changes nothing.
//!
//! Seeds: the extra seeds' realisation seeds are drawn after every sea state's first N, so the
//! first N seeds of every sea state are those of the same campaign without the rule.
//!
//! With `reduced` and `auto`, the extra seeds run through the calibration of their hot spot,
//! fitted on the first seeds' load range widened by `strand.calibration_margin` (the extra
//! seeds' global jobs come after it); an extra realisation that leaves that range fails its
//! reduced job naming the range and the margin to raise.

use serde::{Deserialize, Serialize};

use crate::error::CampaignError;
use crate::fidelity::{select_by_damage_share, ClassDamageRate, Selection};

/// Most realisations per sea state (each one a global and a strand job per hot spot).
pub const MAX_SEEDS_PER_SEA_STATE: u32 = 1000;

/// `simulation.extra_seeds` (module docs).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ExtraSeeds {
    /// Seeds in all (first and extra) of every selected sea state; more than
    /// `simulation.seeds_per_sea_state`.
    pub seeds: u32,
    /// Share (0, 1] of the governing class's first-seed annual fretting damage that the
    /// selected sea states hold together.
    pub damage_share: f64,
}

impl ExtraSeeds {
    /// Checks the rule against the first seeds per sea state; errors name the field
    /// (`simulation.extra_seeds.…`).
    pub fn validate(&self, seeds_per_sea_state: u32) -> Result<(), CampaignError> {
        let invalid = |field: &str, value: String, reason: String| CampaignError::Invalid {
            field: format!("simulation.extra_seeds.{field}"),
            value,
            reason,
        };
        if self.seeds <= seeds_per_sea_state || self.seeds > MAX_SEEDS_PER_SEA_STATE {
            return Err(invalid(
                "seeds",
                self.seeds.to_string(),
                format!(
                    "must be more than simulation.seeds_per_sea_state ({seeds_per_sea_state}) \
                     and at most {MAX_SEEDS_PER_SEA_STATE}"
                ),
            ));
        }
        if !(self.damage_share.is_finite() && self.damage_share > 0.0 && self.damage_share <= 1.0) {
            return Err(invalid(
                "damage_share",
                self.damage_share.to_string(),
                "must be in (0, 1]".into(),
            ));
        }
        Ok(())
    }
}

/// The sea states of one hot spot that run the extra seeds: from the class rows of that hot
/// spot's first-seed strand results (rows of later seeds, `seed_index >= first_seeds`, are left
/// out, so the answer does not depend on how far the extra seeds have got).
pub fn select_extra_seed_sea_states(
    rows: &[ClassDamageRate],
    first_seeds: u32,
    rule: &ExtraSeeds,
) -> Selection {
    let first: Vec<ClassDamageRate> = rows
        .iter()
        .filter(|r| r.seed_index >= 0 && r.seed_index < i64::from(first_seeds))
        .copied()
        .collect();
    select_by_damage_share(&first, usize::MAX, rule.damage_share)
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

    /// Four sea states; class 2 governs. Its annual damage per sea state ∝ occurrence × rate:
    /// 0.1·5 = 0.5, 0.4·1 = 0.4, 0.2·0.25 = 0.05, 0.3·(1/6) = 0.05 → shares 0.5, 0.4, 0.05,
    /// 0.05 of 1.0.
    fn rows() -> Vec<ClassDamageRate> {
        vec![
            row(0, 0.1, 0, 2, 5.0),
            row(1, 0.4, 0, 2, 1.0),
            row(2, 0.2, 0, 2, 0.25),
            row(3, 0.3, 0, 2, 1.0 / 6.0),
            // a class with less damage: ignored although it ranks sea state 3 first
            row(3, 0.3, 0, 0, 1.0),
            row(0, 0.1, 0, 0, 0.1),
        ]
    }

    #[test]
    fn the_sea_states_holding_the_share_of_the_governing_class_get_the_extra_seeds() {
        let rule = |share| ExtraSeeds {
            seeds: 3,
            damage_share: share,
        };
        let ids = |s: &Selection| s.sea_states.iter().map(|x| x.0).collect::<Vec<_>>();
        // 0.5 alone reaches 0.5; 0.8 needs the second (0.9); 0.92 the third; 1 all four
        assert_eq!(
            ids(&select_extra_seed_sea_states(&rows(), 1, &rule(0.5))),
            [0]
        );
        let s = select_extra_seed_sea_states(&rows(), 1, &rule(0.8));
        assert_eq!(s.class, Some((2, "outer_arc")));
        assert_eq!(ids(&s), [0, 1]);
        assert!((s.sea_states[0].1 - 0.5).abs() < 1e-12);
        assert!((s.sea_states[1].1 - 0.4).abs() < 1e-12);
        // sea states 2 and 3 tie at 0.05: the lower index comes first
        assert_eq!(
            ids(&select_extra_seed_sea_states(&rows(), 1, &rule(0.92))),
            [0, 1, 2]
        );
        assert_eq!(
            ids(&select_extra_seed_sea_states(&rows(), 1, &rule(1.0))),
            [0, 1, 2, 3]
        );
    }

    #[test]
    fn rows_of_the_extra_seeds_do_not_change_the_selection() {
        let rule = ExtraSeeds {
            seeds: 3,
            damage_share: 0.8,
        };
        let before = select_extra_seed_sea_states(&rows(), 1, &rule);
        let mut later = rows();
        // an extra seed of sea state 3 that would make it the largest share
        later.push(row(3, 0.3, 1, 2, 100.0));
        later.push(row(3, 0.3, 2, 2, 100.0));
        assert_eq!(select_extra_seed_sea_states(&later, 1, &rule), before);
        // with two first seeds, seed 1 counts: sea state 3's mean rate becomes ≈ 50.1
        let two = select_extra_seed_sea_states(&later, 2, &rule);
        assert_eq!(two.sea_states[0].0, 3);
    }

    #[test]
    fn bad_rules_are_refused_naming_the_field() {
        let field = |r: ExtraSeeds, n: u32| match r.validate(n) {
            Err(CampaignError::Invalid { field, .. }) => field,
            other => panic!("{r:?}: {other:?}"),
        };
        let ok = ExtraSeeds {
            seeds: 3,
            damage_share: 0.8,
        };
        assert!(ok.validate(1).is_ok());
        assert!(ok.validate(2).is_ok());
        for (seeds, n) in [(1, 1), (2, 3), (MAX_SEEDS_PER_SEA_STATE + 1, 1), (0, 1)] {
            assert_eq!(
                field(ExtraSeeds { seeds, ..ok }, n),
                "simulation.extra_seeds.seeds"
            );
        }
        for share in [0.0, -0.5, 1.01, f64::NAN, f64::INFINITY] {
            assert_eq!(
                field(
                    ExtraSeeds {
                        damage_share: share,
                        ..ok
                    },
                    1
                ),
                "simulation.extra_seeds.damage_share"
            );
        }
    }
}
