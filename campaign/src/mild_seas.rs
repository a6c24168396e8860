//! Mild sea states a hot spot skips (`strand.skip_mild_share`).
//!
//! A long-term climate holds many sea states too mild to matter for fatigue: a whole-year
//! campaign on every line runs most of its strand jobs on them. Per hot spot, each first-seed
//! global result i gives a fibre-strain measure and a tension-bending proxy:
//!
//! ```text
//! x_i = σ_T,i / EA + (D / 2) σ_κ,i
//! P_i = w_i x_i^m / T_p,i,   m = 4.8
//! ```
//!
//! σ_T and σ_κ the standard deviations of the hot spot's tension and curvature over the run,
//! EA the strand's axial stiffness, D its outer diameter (so x bounds the standard deviation of
//! the strand's outer-fibre strain), w the sea state's fraction of the year, 1/T_p standing for
//! its rate of load cycles and m the inverse slope of the spiral-rope T-N curve
//! ([`crate::screening::PROXY_EXPONENT`]). With several first seeds a sea state takes the
//! largest x of its seeds. The sea states are taken in increasing x (ties by index) and
//! skipped while the proxy they hold together stays within the share s of the hot spot's total.
//!
//! **The bound.** Let sea state i's damage rate be `w_i / T_p,i · x_i^m · g(x_i)` with g
//! non-decreasing: any damage per cycle that grows with the load at least as fast as x^m (a
//! power law of exponent ≥ m, a threshold law). With x* the largest skipped measure, every
//! skipped sea state has x ≤ x* and every run one x ≥ x*, so
//!
//! ```text
//! D_skipped ≤ g(x*) P_S,   D_run ≥ g(x*) P_R   ⇒   D_skipped + D_run ≤ D_run / (1 − q)
//! ```
//!
//! with q = P_S / (P_S + P_R) ≤ s, the proxy share actually skipped. The design check charges
//! each hot spot's damage by that factor. Taking the sea states in order of x, not of P,
//! is what makes the bound hold: a rare severe sea state has a small proxy and is never skipped
//! before a milder one. What the bound assumes (that one scalar of the load orders the damage
//! of the sea states, and that 1/T_p orders their cycle rates) is stated in
//! `docs/design-check.md`.

use serde::{Deserialize, Serialize};

use crate::screening::PROXY_EXPONENT;

/// The largest share of a hot spot's proxy that `strand.skip_mild_share` may skip.
pub const MAX_SKIP_SHARE: f64 = 0.1;

/// One first-seed global result at one hot spot: the input of [`mild_sea_states`].
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SeaStateLoad {
    /// Sea state index in the campaign.
    pub sea_state_index: i64,
    /// Its fraction of the year.
    pub occurrence_fraction: f64,
    /// Its peak period (s).
    pub tp_s: f64,
    /// The fibre-strain measure x (module docs).
    pub measure: f64,
}

impl SeaStateLoad {
    /// x from the hot spot's tension and curvature standard deviations (N, 1/m), the strand's
    /// EA (N) and outer diameter (m).
    pub fn fibre_strain_measure(
        tension_std_n: f64,
        curvature_std_per_m: f64,
        ea_n: f64,
        outer_diameter_m: f64,
    ) -> f64 {
        tension_std_n / ea_n + 0.5 * outer_diameter_m * curvature_std_per_m
    }

    /// The proxy P (module docs); `None` for a measure, period or occurrence that is not a
    /// finite non-negative number (a positive period).
    fn proxy(&self) -> Option<f64> {
        let ok = self.measure.is_finite()
            && self.measure >= 0.0
            && self.tp_s.is_finite()
            && self.tp_s > 0.0
            && self.occurrence_fraction.is_finite()
            && self.occurrence_fraction >= 0.0;
        let p = self.occurrence_fraction * self.measure.powf(PROXY_EXPONENT) / self.tp_s;
        (ok && p.is_finite()).then_some(p)
    }
}

/// The sea states a hot spot skips, and what they hold.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct MildSeas {
    /// The share allowed (`strand.skip_mild_share`).
    pub share: f64,
    /// Skipped sea state indices, ascending.
    pub skipped: Vec<i64>,
    /// q: the skipped sea states' share of the hot spot's proxy (≤ `share`).
    pub proxy_share: f64,
    /// Their fraction of the year.
    pub occurrence_fraction: f64,
    /// The largest skipped fibre-strain measure x* (0 when none is skipped).
    pub largest_skipped_measure: f64,
    /// Sea states considered.
    pub sea_states: usize,
}

impl MildSeas {
    /// Whether `sea_state_index` is skipped.
    pub fn skips(&self, sea_state_index: i64) -> bool {
        self.skipped.binary_search(&sea_state_index).is_ok()
    }

    /// The bound on the hot spot's damage over the damage of the sea states run
    /// ([`damage_factor`] of its proxy share).
    pub fn damage_factor(&self) -> f64 {
        damage_factor(self.proxy_share)
    }

    fn none(share: f64, sea_states: usize) -> MildSeas {
        MildSeas {
            share,
            skipped: Vec::new(),
            proxy_share: 0.0,
            occurrence_fraction: 0.0,
            largest_skipped_measure: 0.0,
            sea_states,
        }
    }
}

/// 1 / (1 − q): the bound on a hot spot's damage over the damage of the sea states it ran, when
/// the skipped ones hold the share q of its proxy.
pub fn damage_factor(proxy_share: f64) -> f64 {
    1.0 / (1.0 - proxy_share)
}

/// The mild sea states of one hot spot under share `share` (module docs). Deterministic for
/// given loads in any order. Nothing is skipped when `share` is not in (0, [`MAX_SKIP_SHARE`]],
/// when the total proxy is zero, or when any load's proxy is not a finite number (a sea state
/// that cannot be measured cannot be bounded).
pub fn mild_sea_states(loads: &[SeaStateLoad], share: f64) -> MildSeas {
    // one entry per sea state: its largest measure over the seeds
    let mut per_sea_state: Vec<SeaStateLoad> = Vec::with_capacity(loads.len());
    for l in loads {
        match per_sea_state
            .iter_mut()
            .find(|s| s.sea_state_index == l.sea_state_index)
        {
            Some(s) if s.measure.is_nan() || l.measure.is_nan() => s.measure = f64::NAN,
            Some(s) => s.measure = s.measure.max(l.measure),
            None => per_sea_state.push(*l),
        }
    }
    let n = per_sea_state.len();
    if !(share > 0.0 && share <= MAX_SKIP_SHARE) {
        return MildSeas::none(share, n);
    }
    // in the order of x (ties by index), which also fixes the order of the sums
    per_sea_state.sort_by(|a, b| {
        a.measure
            .total_cmp(&b.measure)
            .then(a.sea_state_index.cmp(&b.sea_state_index))
    });
    let Some(proxies) = per_sea_state
        .iter()
        .map(SeaStateLoad::proxy)
        .collect::<Option<Vec<f64>>>()
    else {
        return MildSeas::none(share, n);
    };
    let total: f64 = proxies.iter().sum();
    if !(total > 0.0 && total.is_finite()) {
        return MildSeas::none(share, n);
    }
    let mut out = MildSeas::none(share, n);
    let mut skipped_proxy = 0.0;
    for (s, &p) in per_sea_state.iter().zip(&proxies) {
        if skipped_proxy + p > share * total {
            break;
        }
        skipped_proxy += p;
        out.skipped.push(s.sea_state_index);
        out.occurrence_fraction += s.occurrence_fraction;
        out.largest_skipped_measure = s.measure;
    }
    out.skipped.sort_unstable();
    out.proxy_share = skipped_proxy / total;
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    fn load(index: i64, w: f64, tp: f64, x: f64) -> SeaStateLoad {
        SeaStateLoad {
            sea_state_index: index,
            occurrence_fraction: w,
            tp_s: tp,
            measure: x,
        }
    }

    /// Four equally likely sea states of measures 1 to 4: proxies 1, 2^4.8, 3^4.8, 4^4.8
    /// (1, 27.86, 195.07, 776.05; total 999.97). 3 % skips the first two (2.886 %), 2 % only
    /// the first (0.10 %).
    #[test]
    fn the_mildest_are_skipped_up_to_the_share() {
        let loads: Vec<_> = (1..=4).map(|i| load(i, 0.25, 8.0, i as f64)).collect();
        let total: f64 = (1..=4).map(|i| (i as f64).powf(4.8)).sum();
        assert!((total - 999.97).abs() < 0.01, "{total}");
        let m = mild_sea_states(&loads, 0.03);
        assert_eq!(m.skipped, [1, 2]);
        assert!((m.proxy_share - (1.0 + 2f64.powf(4.8)) / total).abs() < 1e-15);
        assert!((m.proxy_share - 0.028859).abs() < 1e-6);
        assert_eq!(
            (m.occurrence_fraction, m.largest_skipped_measure),
            (0.5, 2.0)
        );
        assert!((m.damage_factor() - 1.0 / (1.0 - m.proxy_share)).abs() < 1e-15);
        assert!(m.skips(2) && !m.skips(3));
        let m = mild_sea_states(&loads, 0.02);
        assert_eq!(m.skipped, [1]);
        // input order does not matter
        let reversed: Vec<_> = loads.iter().rev().copied().collect();
        assert_eq!(
            mild_sea_states(&reversed, 0.03),
            mild_sea_states(&loads, 0.03)
        );
    }

    /// A rare severe sea state holds a tiny proxy, smaller than the share, yet is not skipped:
    /// the milder frequent one before it in the order of x does not fit.
    #[test]
    fn a_rare_severe_sea_state_is_never_skipped_before_a_milder_one() {
        let loads = [load(0, 0.9, 8.0, 1.0), load(1, 1e-9, 12.0, 10.0)];
        let p_severe = 1e-9 * 10f64.powf(4.8) / 12.0;
        let total = 0.9 / 8.0 + p_severe;
        assert!(
            p_severe / total < 0.01,
            "the severe one alone would fit the share"
        );
        let m = mild_sea_states(&loads, 0.01);
        assert!(m.skipped.is_empty(), "{m:?}");
        assert_eq!(m.damage_factor(), 1.0);
    }

    /// The bound on synthetic climates: for damage rates w/T_p · x^m · g(x) with g
    /// non-decreasing (power laws of exponent 4.8, 6 and 10, and a threshold law), the skipped
    /// sea states' damage never exceeds q / (1 − q) of the damage run, and q ≤ s.
    #[test]
    fn the_skipped_damage_is_bounded_for_every_steeper_law() {
        // a deterministic linear congruential sequence in [0, 1)
        let mut state = 0x2545_f491_4f6c_dd1d_u64;
        let mut next = move || {
            state = state
                .wrapping_mul(6_364_136_223_846_793_005)
                .wrapping_add(1_442_695_040_888_963_407);
            (state >> 11) as f64 / (1u64 << 53) as f64
        };
        type Law = (&'static str, fn(f64) -> f64);
        let laws: [Law; 4] = [
            ("x^4.8", |_| 1.0),
            ("x^6", |x| x.powf(1.2)),
            ("x^10", |x| x.powf(5.2)),
            ("threshold", |x| if x > 2e-4 { 1.0 } else { 0.0 }),
        ];
        for climate in 0..50 {
            let loads: Vec<SeaStateLoad> = (0..60)
                .map(|i| {
                    let hs = 0.25 + 8.0 * next();
                    let x = 1e-4 * hs * (0.5 + next());
                    let w = (-hs / 1.5).exp() * next();
                    load(i, w, 4.0 + 14.0 * next(), x)
                })
                .collect();
            for share in [0.001, 0.01, 0.05, 0.1] {
                let m = mild_sea_states(&loads, share);
                assert!(m.proxy_share <= share, "{climate} {share}: {m:?}");
                for (name, g) in laws {
                    let damage = |l: &SeaStateLoad| {
                        l.occurrence_fraction / l.tp_s
                            * l.measure.powf(PROXY_EXPONENT)
                            * g(l.measure)
                    };
                    let (skipped, run): (Vec<_>, Vec<_>) =
                        loads.iter().partition(|l| m.skips(l.sea_state_index));
                    let d_skipped: f64 = skipped.iter().copied().map(&damage).sum();
                    let d_run: f64 = run.iter().copied().map(&damage).sum();
                    let bound = d_run * m.proxy_share / (1.0 - m.proxy_share);
                    assert!(
                        d_skipped <= bound * (1.0 + 1e-12),
                        "{climate} {share} {name}: skipped {d_skipped:e} > bound {bound:e}"
                    );
                }
            }
        }
    }

    /// Nothing is skipped without a share, without a proxy, or when a load cannot be measured;
    /// several seeds of a sea state count once, with their largest measure.
    #[test]
    fn degenerate_inputs_skip_nothing_and_seeds_count_once() {
        let loads = [load(0, 0.5, 8.0, 1.0), load(1, 0.5, 8.0, 3.0)];
        assert!(mild_sea_states(&loads, 0.0).skipped.is_empty());
        assert!(mild_sea_states(&loads, 0.2).skipped.is_empty());
        assert!(mild_sea_states(&loads, f64::NAN).skipped.is_empty());
        assert!(mild_sea_states(&[], 0.05).skipped.is_empty());
        let calm = [load(0, 0.5, 8.0, 0.0), load(1, 0.5, 8.0, 0.0)];
        assert!(mild_sea_states(&calm, 0.05).skipped.is_empty());
        for bad in [f64::NAN, f64::INFINITY, -1.0] {
            let loads = [load(0, 0.5, 8.0, 1.0), load(1, 0.5, 8.0, bad)];
            assert!(mild_sea_states(&loads, 0.1).skipped.is_empty(), "{bad}");
        }
        let zero_period = [load(0, 0.5, 0.0, 1.0), load(1, 0.5, 8.0, 3.0)];
        assert!(mild_sea_states(&zero_period, 0.1).skipped.is_empty());
        // sea state 0 has a second seed as strong as sea state 1: nothing is mild any more
        let seeds = [
            load(0, 0.5, 8.0, 1.0),
            load(1, 0.5, 8.0, 3.0),
            load(0, 0.5, 8.0, 3.0),
        ];
        let m = mild_sea_states(&seeds, 0.1);
        assert_eq!(m.sea_states, 2);
        assert!(m.skipped.is_empty(), "{m:?}");
        let m = mild_sea_states(&loads, 0.1);
        assert_eq!(m.skipped, [0]);
        assert!((m.proxy_share - 1.0 / (1.0 + 3f64.powf(4.8))).abs() < 1e-15);
    }
}
