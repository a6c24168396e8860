//! Lifetime damage from per-sea-state, per-seed results (`docs/damage.md`).
//!
//! ```text
//! D_life = Σ_s  p_s · (L / T_eff) · mean over seeds of D_s,seed
//! ```
//!
//! with p_s the occurrence fraction of sea state s (fraction of the year), L the design life in
//! seconds (Julian years of 365.25 days) and T_eff the effective simulated time of a seed (after
//! the transient). Seeds of unequal length are averaged as damage rates D/T_eff, which is the
//! same thing when they are equal.
//!
//! Sea states without any seed result contribute nothing and are left out of the covered
//! fraction Σ p_s (over sea states with results), which is always reported and never used to
//! rescale the damage. The result does not depend on the order of the input: contributions are
//! summed in the order of the sea-state identifiers and seeds, so shuffled input gives the same
//! bits.

use serde::{Deserialize, Serialize};

use super::error::{check, FatigueError};

/// Seconds in a Julian year (365.25 days).
pub const SECONDS_PER_YEAR: f64 = 365.25 * 86_400.0;

/// The result of one seed of one sea state.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct SeedDamage {
    /// Seed of the random wave realisation.
    pub seed: u64,
    /// Damage over the effective simulated time.
    pub damage: f64,
    /// Effective simulated time (after the transient) (s).
    pub effective_duration_s: f64,
}

/// All seed results of one sea state.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct SeaStateDamage {
    /// Identifier of the sea state (unique within the campaign).
    pub id: String,
    /// Occurrence as a fraction of the year (0 ≤ p ≤ 1).
    pub occurrence_fraction: f64,
    /// Seed results (may be empty while the campaign runs).
    pub seeds: Vec<SeedDamage>,
}

/// Contribution of one sea state to the lifetime damage.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct SeaStateContribution {
    /// Identifier of the sea state.
    pub id: String,
    /// Occurrence fraction of the year.
    pub occurrence_fraction: f64,
    /// Number of seeds averaged.
    pub seeds: usize,
    /// Mean damage rate over the seeds (1/s).
    pub mean_damage_rate_per_s: f64,
    /// Damage over the design life from this sea state.
    pub lifetime_damage: f64,
}

/// Lifetime damage with its coverage.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct LifetimeDamage {
    /// Design life (years).
    pub design_life_years: f64,
    /// Damage over the design life, Σ of the contributions (not rescaled for coverage).
    pub lifetime_damage: f64,
    /// Damage per year.
    pub annual_damage: f64,
    /// Σ occurrence of the sea states with at least one seed result.
    pub covered_fraction: f64,
    /// Σ occurrence of all sea states given, with or without results.
    pub listed_fraction: f64,
    /// Per sea state, in identifier order (only those with results).
    pub contributions: Vec<SeaStateContribution>,
}

impl LifetimeDamage {
    /// Life in years at which the damage reaches 1 (infinite without damage).
    pub fn fatigue_life_years(&self) -> f64 {
        if self.annual_damage > 0.0 {
            1.0 / self.annual_damage
        } else {
            f64::INFINITY
        }
    }
}

/// Aggregates per-sea-state, per-seed damages over a design life of `design_life_years`.
pub fn lifetime_damage(
    sea_states: &[SeaStateDamage],
    design_life_years: f64,
) -> Result<LifetimeDamage, FatigueError> {
    check(
        "design_life_years",
        design_life_years,
        design_life_years > 0.0,
        "must be > 0",
    )?;
    let life_s = design_life_years * SECONDS_PER_YEAR;
    let mut order: Vec<&SeaStateDamage> = sea_states.iter().collect();
    order.sort_by(|a, b| a.id.cmp(&b.id));
    for w in order.windows(2) {
        if w[0].id == w[1].id {
            return Err(FatigueError::DuplicateSeaState {
                id: w[0].id.clone(),
            });
        }
    }
    let mut contributions = Vec::new();
    let (mut covered, mut listed, mut total) = (0.0, 0.0, 0.0);
    for s in order {
        let p = s.occurrence_fraction;
        check(
            &format!("sea_states[{}].occurrence_fraction", s.id),
            p,
            (0.0..=1.0).contains(&p),
            "must lie in [0, 1]",
        )?;
        listed += p;
        let mut seeds: Vec<&SeedDamage> = s.seeds.iter().collect();
        seeds.sort_by_key(|d| d.seed);
        for w in seeds.windows(2) {
            if w[0].seed == w[1].seed {
                return Err(FatigueError::DuplicateSeed {
                    id: s.id.clone(),
                    seed: w[0].seed,
                });
            }
        }
        let mut rate_sum = 0.0;
        for d in &seeds {
            let field = |name: &str| format!("sea_states[{}].seeds[{}].{name}", s.id, d.seed);
            check(&field("damage"), d.damage, d.damage >= 0.0, "must be >= 0")?;
            check(
                &field("effective_duration_s"),
                d.effective_duration_s,
                d.effective_duration_s > 0.0,
                "must be > 0",
            )?;
            rate_sum += d.damage / d.effective_duration_s;
        }
        if seeds.is_empty() {
            continue;
        }
        let mean_rate = rate_sum / seeds.len() as f64;
        let lifetime = p * life_s * mean_rate;
        covered += p;
        total += lifetime;
        contributions.push(SeaStateContribution {
            id: s.id.clone(),
            occurrence_fraction: p,
            seeds: seeds.len(),
            mean_damage_rate_per_s: mean_rate,
            lifetime_damage: lifetime,
        });
    }
    if listed > 1.0 + 1e-9 {
        return Err(FatigueError::OccurrenceExceedsYear { total: listed });
    }
    Ok(LifetimeDamage {
        design_life_years,
        lifetime_damage: total,
        annual_damage: total / design_life_years,
        covered_fraction: covered,
        listed_fraction: listed,
        contributions,
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use rand::seq::SliceRandom;
    use rand::SeedableRng;

    fn state(id: &str, p: f64, damages: &[(u64, f64)]) -> SeaStateDamage {
        SeaStateDamage {
            id: id.into(),
            occurrence_fraction: p,
            seeds: damages
                .iter()
                .map(|&(seed, damage)| SeedDamage {
                    seed,
                    damage,
                    effective_duration_s: 10_800.0,
                })
                .collect(),
        }
    }

    #[test]
    fn reference_vector_gives_the_published_annual_damage() {
        // docs/damage.md: occurrences 0.30 and 0.13758, T_eff = 10 800 s, damages 1e-6 and 4e-6,
        // design life 1 year → 2.48463504e-3.
        let s = [
            state("a", 0.30, &[(1, 1e-6)]),
            state("b", 0.13758, &[(1, 4e-6)]),
        ];
        let life = lifetime_damage(&s, 1.0).unwrap();
        assert!(
            (life.annual_damage / 2.484_635_04e-3 - 1.0).abs() < 1e-12,
            "{}",
            life.annual_damage
        );
        assert!((life.covered_fraction - 0.43758).abs() < 1e-15);
        assert_eq!(life.contributions.len(), 2);
        let twenty = lifetime_damage(&s, 20.0).unwrap();
        assert!((twenty.lifetime_damage / (20.0 * life.lifetime_damage) - 1.0).abs() < 1e-14);
        assert!((twenty.annual_damage / life.annual_damage - 1.0).abs() < 1e-14);
    }

    #[test]
    fn seeds_are_averaged_and_missing_results_reduce_coverage_without_rescaling() {
        let s = [
            state("a", 0.30, &[(1, 1e-6), (2, 3e-6)]),
            state("b", 0.13758, &[(1, 4e-6)]),
            state("c", 0.2, &[]),
        ];
        let life = lifetime_damage(&s, 1.0).unwrap();
        let expected = SECONDS_PER_YEAR / 10_800.0 * (0.30 * 2e-6 + 0.13758 * 4e-6);
        assert!((life.annual_damage / expected - 1.0).abs() < 1e-12);
        assert!((life.covered_fraction - 0.43758).abs() < 1e-15);
        assert!((life.listed_fraction - 0.63758).abs() < 1e-15);
    }

    #[test]
    fn result_is_identical_for_shuffled_input() {
        let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(11);
        let mut s: Vec<SeaStateDamage> = (0..40)
            .map(|k| {
                let seeds: Vec<(u64, f64)> = (0..5)
                    .map(|j| (j, 1e-7 * (1.0 + ((k * 7 + j as usize) % 13) as f64)))
                    .collect();
                state(&format!("hs{k:02}"), 0.015 + 0.0003 * k as f64, &seeds)
            })
            .collect();
        let reference = lifetime_damage(&s, 25.0).unwrap();
        for _ in 0..10 {
            s.shuffle(&mut rng);
            for st in &mut s {
                st.seeds.shuffle(&mut rng);
            }
            let again = lifetime_damage(&s, 25.0).unwrap();
            assert_eq!(
                again.lifetime_damage.to_bits(),
                reference.lifetime_damage.to_bits()
            );
            assert_eq!(again, reference);
        }
    }

    #[test]
    fn inconsistent_input_is_rejected() {
        let dup = [state("a", 0.1, &[(1, 1e-6)]), state("a", 0.2, &[(1, 1e-6)])];
        assert!(matches!(
            lifetime_damage(&dup, 1.0),
            Err(FatigueError::DuplicateSeaState { .. })
        ));
        let dup_seed = [state("a", 0.1, &[(1, 1e-6), (1, 2e-6)])];
        assert!(matches!(
            lifetime_damage(&dup_seed, 1.0),
            Err(FatigueError::DuplicateSeed { seed: 1, .. })
        ));
        let over = [state("a", 0.7, &[(1, 1e-6)]), state("b", 0.7, &[(1, 1e-6)])];
        assert!(matches!(
            lifetime_damage(&over, 1.0),
            Err(FatigueError::OccurrenceExceedsYear { .. })
        ));
        let negative = [state("a", 0.1, &[(1, -1e-6)])];
        assert!(matches!(
            lifetime_damage(&negative, 1.0),
            Err(FatigueError::InvalidParameter { .. })
        ));
        assert!(lifetime_damage(&[], 0.0).is_err());
    }
}
