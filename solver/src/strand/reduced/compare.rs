//! Per-interface fretting statistics of a set of contact records, and their comparison between
//! two runs of the same model (the reduced response against the FE run).
//!
//! Per layer interface: the largest slip range of a counted cycle, the accumulated slip
//! `Σ n Δs` over the cycles of range at least `min_range_m` (n = 1 for a full cycle, 0.5 for a
//! half), and the number `Σ n` of those cycles — the figures the strand stage's damage inputs
//! are built from.

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
    /// Relative difference of the largest slip range.
    pub max_slip_range_error: f64,
    /// Relative difference of the accumulated slip (0 if both are 0).
    pub accumulated_slip_error: f64,
    /// Relative difference of the cycle count (0 if both are 0).
    pub cycles_error: f64,
}

impl InterfaceComparison {
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
         slip (ref → cmp)       cycles (ref → cmp)";
}

/// One table row: the three figures in both runs and their relative differences.
impl std::fmt::Display for InterfaceComparison {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(
            f,
            "{:>9}  {:.3e} → {:.3e} m {:>+6.1}%   {:.3e} → {:.3e} m {:>+6.1}%   {:>9.1} → {:<9.1} \
             {:>+6.1}%",
            self.interface,
            self.reference.max_slip_range_m,
            self.compared.max_slip_range_m,
            100.0 * self.max_slip_range_error,
            self.reference.accumulated_slip_m,
            self.compared.accumulated_slip_m,
            100.0 * self.accumulated_slip_error,
            self.reference.cycles,
            self.compared.cycles,
            100.0 * self.cycles_error
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
        assert_eq!(c[1].cycles_error, -1.0);
    }
}
