//! Per-interface fretting statistics of a set of contact records, and their comparison between
//! two runs of the same model (the reduced response against the FE run).
//!
//! Per layer interface: the largest slip range of a counted cycle, the accumulated slip
//! `Σ n Δs` over the cycles of range at least `min_range_m` (n = 1 for a full cycle, 0.5 for a
//! half), and the number `Σ n` of those cycles — the figures the strand stage's damage inputs
//! are built from.
//!
//! A count above a fixed threshold is steep where the threshold cuts the range distribution at a
//! handful of cycles: on the six-layer paper strand, scaling every FE slip range of the mild
//! sea state's interface 4 (23.5 cycles of at least 1 µm) by 1.01 raises the count by 17 %
//! (docs/reduced-strand.md). So the comparison also gives the count difference as a slip-range
//! difference ([`InterfaceComparison::cycles_as_range_error`]): the factor on the reference's
//! ranges at which the reference counts the compared run's cycles, minus one.

use std::collections::BTreeMap;

use serde::{Deserialize, Serialize};

use crate::fretting::ContactRecord;

/// Statistics of one layer interface.
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct InterfaceStatistics {
    /// Layer interface.
    pub interface: usize,
    /// Largest slip range of a counted cycle (m).
    pub max_slip_range_m: f64,
    /// Σ n Δs over the cycles with Δs ≥ the threshold (m).
    pub accumulated_slip_m: f64,
    /// Σ n over those cycles.
    pub cycles: f64,
}

/// Statistics per interface, in interface order; cycles starting before sample `from_sample`
/// are left out (a run-in).
pub(crate) fn interface_statistics(
    records: &[ContactRecord],
    min_range_m: f64,
    from_sample: usize,
) -> Vec<InterfaceStatistics> {
    let mut by: BTreeMap<usize, InterfaceStatistics> = BTreeMap::new();
    for r in records {
        let e = by.entry(r.interface).or_insert(InterfaceStatistics {
            interface: r.interface,
            ..InterfaceStatistics::default()
        });
        for k in r
            .cycles
            .iter()
            .filter(|k| k.slip.start_index >= from_sample)
        {
            e.max_slip_range_m = e.max_slip_range_m.max(k.slip.range);
            if k.slip.range >= min_range_m {
                e.accumulated_slip_m += k.slip.count * k.slip.range;
                e.cycles += k.slip.count;
            }
        }
    }
    by.into_values().collect()
}

/// One interface's statistics in two runs, and the relative differences `b / a − 1`.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct InterfaceComparison {
    /// Layer interface.
    pub interface: usize,
    /// Reference run (FE).
    pub reference: InterfaceStatistics,
    /// Compared run (reduced).
    pub compared: InterfaceStatistics,
    /// Relative difference of the largest slip range (+∞ where only the compared run has
    /// any: written `null` in JSON, which has no infinity).
    #[serde(with = "unbounded")]
    pub max_slip_range_error: f64,
    /// Relative difference of the accumulated slip (0 if both are 0, +∞ as above).
    #[serde(with = "unbounded")]
    pub accumulated_slip_error: f64,
    /// Relative difference of the cycle count (0 if both are 0, +∞ as above).
    #[serde(with = "unbounded")]
    pub cycles_error: f64,
    /// The count difference as a slip-range difference: `f − 1` for the factor `f` on every
    /// reference cycle's range at which the reference's count above the threshold reaches the
    /// compared run's ([`count_as_range_factor`]); `None` where no factor does (the compared
    /// run counts more cycles than the reference has at all).
    #[serde(default)]
    pub cycles_as_range_error: Option<f64>,
}

/// A relative difference in JSON: a number, or `null` for +∞ (a reference of 0 against a
/// compared value that is not), which JSON cannot write. serde_json would write `null` for it
/// anyway and then refuse to read it back, so that a stored calibration whose replay has such
/// an interface could not be loaded.
mod unbounded {
    use serde::{Deserialize, Deserializer, Serializer};

    pub(super) fn serialize<S: Serializer>(x: &f64, s: S) -> Result<S::Ok, S::Error> {
        if x.is_finite() {
            s.serialize_f64(*x)
        } else {
            s.serialize_none()
        }
    }

    pub(super) fn deserialize<'de, D: Deserializer<'de>>(d: D) -> Result<f64, D::Error> {
        Ok(Option::<f64>::deserialize(d)?.unwrap_or(f64::INFINITY))
    }
}

impl InterfaceComparison {
    /// [`InterfaceComparison::cycles_as_range_error`] as a signed percentage, `—` if none.
    pub fn cycles_as_range_label(&self) -> String {
        self.cycles_as_range_error
            .map_or_else(|| "—".to_string(), |e| format!("{:+.1}%", 100.0 * e))
    }

    /// The largest magnitude of the three relative differences.
    pub fn worst(&self) -> f64 {
        self.max_slip_range_error
            .abs()
            .max(self.accumulated_slip_error.abs())
            .max(self.cycles_error.abs())
    }
}

impl InterfaceComparison {
    /// Header of the [`std::fmt::Display`] rows.
    pub const HEADER: &'static str = "interface  max slip range (ref → cmp)        accumulated \
         slip (ref → cmp)       cycles (ref → cmp)           as range";
}

/// One table row: the three figures in both runs and their relative differences.
impl std::fmt::Display for InterfaceComparison {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(
            f,
            "{:>9}  {:.3e} → {:.3e} m {:>+6.1}%   {:.3e} → {:.3e} m {:>+6.1}%   {:>9.1} → {:<9.1} \
             {:>+6.1}%  {:>8}",
            self.interface,
            self.reference.max_slip_range_m,
            self.compared.max_slip_range_m,
            100.0 * self.max_slip_range_error,
            self.reference.accumulated_slip_m,
            self.compared.accumulated_slip_m,
            100.0 * self.accumulated_slip_error,
            self.reference.cycles,
            self.compared.cycles,
            100.0 * self.cycles_error,
            self.cycles_as_range_label()
        )
    }
}

/// `b / a − 1`, 0 if both are 0, +∞ if only `a` is.
pub fn relative_difference(a: f64, b: f64) -> f64 {
    if a == 0.0 {
        if b == 0.0 {
            0.0
        } else {
            f64::INFINITY
        }
    } else {
        b / a - 1.0
    }
}

/// The factor `f` on the slip ranges of `reference` (every cycle's range and count, in any
/// order) at which its count of cycles of range at least `min_range_m` reaches `count`: 1 if it
/// already does; above 1 the smallest factor at which it counts at least `count`, below 1 the
/// factor at which the first cycle that takes it beyond `count` drops out. `None` if `count`
/// exceeds every cycle of `reference` or the threshold is not positive.
pub fn count_as_range_factor(
    reference: &[(f64, f64)],
    min_range_m: f64,
    count: f64,
) -> Option<f64> {
    if !(min_range_m > 0.0 && count.is_finite()) {
        return None;
    }
    let mut cycles: Vec<(f64, f64)> = reference
        .iter()
        .copied()
        .filter(|&(range, n)| range > 0.0 && range.is_finite() && n > 0.0)
        .collect();
    cycles.sort_by(|a, b| b.0.total_cmp(&a.0));
    let counted: f64 = cycles
        .iter()
        .filter(|c| c.0 >= min_range_m)
        .map(|c| c.1)
        .sum();
    if counted == count {
        return Some(1.0);
    }
    // the counts at the factors that bring each cycle, largest range first, to the threshold
    let mut total = 0.0;
    for &(range, n) in &cycles {
        if count > counted {
            total += n;
            if total >= count {
                return Some(min_range_m / range);
            }
        } else if total + n > count {
            return Some(min_range_m / range);
        } else {
            total += n;
        }
    }
    None
}

/// Every cycle of the interface's records, from sample `from_sample` on, as (range, count).
fn interface_cycles(
    records: &[ContactRecord],
    interface: usize,
    from_sample: usize,
) -> Vec<(f64, f64)> {
    records
        .iter()
        .filter(|r| r.interface == interface)
        .flat_map(|r| r.cycles.iter())
        .filter(|k| k.slip.start_index >= from_sample)
        .map(|k| (k.slip.range, k.slip.count))
        .collect()
}

/// Interface by interface comparison of `compared` against `reference` (same model).
pub fn compare_records(
    reference: &[ContactRecord],
    compared: &[ContactRecord],
    min_range_m: f64,
    from_sample: usize,
) -> Vec<InterfaceComparison> {
    let a = interface_statistics(reference, min_range_m, from_sample);
    let b = interface_statistics(compared, min_range_m, from_sample);
    a.iter()
        .map(|ra| {
            let rb = b
                .iter()
                .find(|x| x.interface == ra.interface)
                .copied()
                .unwrap_or(InterfaceStatistics {
                    interface: ra.interface,
                    ..InterfaceStatistics::default()
                });
            InterfaceComparison {
                interface: ra.interface,
                reference: *ra,
                compared: rb,
                max_slip_range_error: relative_difference(ra.max_slip_range_m, rb.max_slip_range_m),
                accumulated_slip_error: relative_difference(
                    ra.accumulated_slip_m,
                    rb.accumulated_slip_m,
                ),
                cycles_error: relative_difference(ra.cycles, rb.cycles),
                cycles_as_range_error: count_as_range_factor(
                    &interface_cycles(reference, ra.interface, from_sample),
                    min_range_m,
                    rb.cycles,
                )
                .map(|f| f - 1.0),
            }
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::fretting::{Cycle, ForceStats, SlipCycle};

    fn cycle(range: f64, count: f64, start: usize) -> SlipCycle {
        let f = ForceStats {
            min: 0.0,
            max: 1.0,
            mean: 0.5,
        };
        SlipCycle {
            slip: Cycle {
                range,
                mean: 0.0,
                count,
                start_index: start,
                end_index: start + 1,
            },
            normal_force_n: f,
            tangential_force_n: f,
        }
    }

    fn record(interface: usize, cycles: Vec<SlipCycle>) -> ContactRecord {
        ContactRecord {
            interface,
            theta_rad: 0.0,
            z_m: 0.0,
            max_normal_force_n: 1.0,
            cycles,
        }
    }

    #[test]
    fn statistics_count_cycles_above_the_threshold_after_the_run_in() {
        let recs = vec![
            record(
                0,
                vec![
                    cycle(2e-6, 1.0, 5),
                    cycle(0.5e-6, 1.0, 6),
                    cycle(3e-6, 0.5, 7),
                ],
            ),
            record(0, vec![cycle(9e-6, 1.0, 0)]),
            record(1, vec![cycle(1e-6, 1.0, 3)]),
        ];
        let s = interface_statistics(&recs, 1e-6, 2);
        assert_eq!(s.len(), 2);
        assert_eq!(s[0].max_slip_range_m, 3e-6);
        assert!((s[0].accumulated_slip_m - 3.5e-6).abs() < 1e-18);
        assert_eq!(s[0].cycles, 1.5);
        assert_eq!(s[1].cycles, 1.0);
        let c = compare_records(&recs, &recs[..1], 1e-6, 2);
        assert_eq!(c[0].worst(), 0.0);
        assert_eq!(c[0].cycles_as_range_error, Some(0.0));
        assert_eq!(c[1].cycles_error, -1.0);
        // interface 1 counts nothing in the compared run: the reference's one cycle of exactly
        // the threshold drops out below a factor of 1
        assert_eq!(c[1].cycles_as_range_error, Some(0.0));
    }

    #[test]
    fn a_count_difference_becomes_the_range_factor_that_makes_it() {
        // ranges 2.0, 1.5, 1.2, 1.0 (×1e-6), 0.8, 0.5 µm, one cycle each; threshold 1 µm: 4
        let t = 1e-6;
        let cycles: Vec<(f64, f64)> = [2.0, 0.5, 1.2, 0.8, 1.0, 1.5]
            .iter()
            .map(|r| (r * t, 1.0))
            .collect();
        let f = |count: f64| count_as_range_factor(&cycles, t, count);
        assert_eq!(f(4.0), Some(1.0));
        // five cycles: the 0.8 µm one reaches the threshold at a factor 1.25
        assert!((f(5.0).unwrap() - 1.25).abs() < 1e-12);
        assert!((f(6.0).unwrap() - 2.0).abs() < 1e-12);
        assert!((f(4.5).unwrap() - 1.25).abs() < 1e-12);
        // three: the 1.0 µm cycle drops out just below a factor 1; two: the 1.2 µm one below 1/1.2
        assert!((f(3.0).unwrap() - 1.0).abs() < 1e-12);
        assert!((f(2.0).unwrap() - 1.0 / 1.2).abs() < 1e-12);
        assert!((f(0.0).unwrap() - 0.5).abs() < 1e-12);
        // more cycles than the reference has, or no threshold: no factor
        assert_eq!(f(7.0), None);
        assert_eq!(count_as_range_factor(&cycles, 0.0, 4.0), None);
        // the factor applied to the reference's ranges gives the count (half cycles too)
        let halves: Vec<(f64, f64)> = cycles.iter().map(|&(r, _)| (r, 0.5)).collect();
        let factor = count_as_range_factor(&halves, t, 2.5).unwrap();
        let counted: f64 = halves
            .iter()
            .filter(|c| c.0 * factor >= t * (1.0 - 1e-12))
            .map(|c| c.1)
            .sum();
        assert_eq!(counted, 2.5);
    }
}

#[cfg(test)]
mod unbounded_tests {
    use super::*;

    /// An interface where only the compared run has cycles (+∞) goes to JSON and back: a
    /// calibration whose replay holds one must load again.
    #[test]
    fn an_infinite_relative_difference_survives_json() {
        let c = InterfaceComparison {
            interface: 2,
            reference: InterfaceStatistics::default(),
            compared: InterfaceStatistics {
                interface: 2,
                max_slip_range_m: 1.2e-6,
                accumulated_slip_m: 1.2e-6,
                cycles: 1.0,
            },
            max_slip_range_error: 0.25,
            accumulated_slip_error: f64::INFINITY,
            cycles_error: f64::INFINITY,
            cycles_as_range_error: None,
        };
        let text = serde_json::to_string(&c).unwrap();
        assert!(text.contains("\"cycles_error\":null"), "{text}");
        let back: InterfaceComparison = serde_json::from_str(&text).unwrap();
        assert_eq!(back, c);
    }
}
