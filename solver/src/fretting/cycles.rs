//! Per-contact slip cycles paired with the contact forces that act over them.
//!
//! A [`ContactCycleAccumulator`] consumes the samples `(slip, f_N, f_T)` of one contact one at a
//! time, rainflow-counts the slip (ASTM E1049-85 §5.4.4 through [`super::streaming`]) and emits
//! every closed slip cycle with the statistics (min, max, mean) of the normal and tangential
//! forces over the samples of the counted range, `start_index ..= end_index`.
//!
//! Units: slip in m (relative tangential displacement of the two wires at the contact), forces
//! in N. Normal force is compressive-positive; the tangential force keeps the sign of the contact
//! element's slip direction, so its mean over a cycle can be near zero while its peak magnitude
//! `max_abs()` is what loads the contact.
//!
//! The accumulator state is serialisable: checkpoint and resume give bit-identical cycles.

use serde::{Deserialize, Serialize};

use super::error::FrettingError;
use super::rainflow::Cycle;
use super::streaming::{SegmentSummary, StreamingRainflow};

/// One sample of a contact history.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct ContactSample {
    /// Relative tangential displacement (slip) along the monitored direction (m).
    pub slip_m: f64,
    /// Normal contact force, compression positive (N).
    pub normal_force_n: f64,
    /// Tangential (friction) force along the slip direction (N).
    pub tangential_force_n: f64,
}

/// Running statistics of one channel over a stretch of samples.
#[derive(Debug, Clone, Copy, Default, PartialEq, Serialize, Deserialize)]
pub(crate) struct ChannelSummary {
    samples: u64,
    sum: f64,
    min: f64,
    max: f64,
}

impl ChannelSummary {
    #[inline(always)]
    fn add(&mut self, x: f64) {
        if self.samples == 0 {
            self.min = x;
            self.max = x;
        } else {
            self.min = self.min.min(x);
            self.max = self.max.max(x);
        }
        self.samples += 1;
        self.sum += x;
    }

    fn merge(&mut self, other: &Self) {
        if other.samples == 0 {
            return;
        }
        if self.samples == 0 {
            *self = *other;
            return;
        }
        self.samples += other.samples;
        self.sum += other.sum;
        self.min = self.min.min(other.min);
        self.max = self.max.max(other.max);
    }

    fn stats(&self) -> ForceStats {
        let mean = if self.samples == 0 {
            0.0
        } else {
            self.sum / self.samples as f64
        };
        ForceStats {
            min: self.min,
            max: self.max,
            mean,
        }
    }
}

/// Summary of both force channels over a stretch of samples.
#[derive(Debug, Clone, Copy, Default, PartialEq, Serialize, Deserialize)]
pub(crate) struct ForceSummary {
    normal: ChannelSummary,
    tangential: ChannelSummary,
}

impl SegmentSummary for ForceSummary {
    /// (normal force, tangential force) in N.
    type Sample = (f64, f64);

    #[inline(always)]
    fn add(&mut self, sample: (f64, f64)) {
        self.normal.add(sample.0);
        self.tangential.add(sample.1);
    }

    fn merge(&mut self, other: &Self) {
        self.normal.merge(&other.normal);
        self.tangential.merge(&other.tangential);
    }
}

/// Minimum, maximum and mean of a force over a cycle (N).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct ForceStats {
    /// Smallest value (N).
    pub min: f64,
    /// Largest value (N).
    pub max: f64,
    /// Arithmetic mean over the samples (N).
    pub mean: f64,
}

impl ForceStats {
    /// Largest magnitude (N).
    pub(crate) fn max_abs(&self) -> f64 {
        self.min.abs().max(self.max.abs())
    }
}

/// A rainflow cycle of slip with the contact forces over it.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct SlipCycle {
    /// The slip cycle (range and mean in m, count 0.5 or 1, sample indices).
    pub slip: Cycle,
    /// Normal force over the samples `start_index ..= end_index` (N).
    pub normal_force_n: ForceStats,
    /// Tangential force over the same samples (N).
    pub tangential_force_n: ForceStats,
}

impl SlipCycle {
    /// Slip amplitude, half the slip range (m).
    pub(crate) fn slip_amplitude_m(&self) -> f64 {
        self.slip.amplitude()
    }

    fn new(slip: Cycle, summary: ForceSummary) -> Self {
        Self {
            slip,
            normal_force_n: summary.normal.stats(),
            tangential_force_n: summary.tangential.stats(),
        }
    }
}

/// Streaming slip-cycle counter of one contact.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct ContactCycleAccumulator {
    counter: StreamingRainflow<ForceSummary>,
}

impl ContactCycleAccumulator {
    /// An empty accumulator; `slip_gate_m` (≥ 0) filters slip ripples not larger than it.
    pub fn new(slip_gate_m: f64) -> Result<Self, FrettingError> {
        Ok(Self {
            counter: StreamingRainflow::new(slip_gate_m)?,
        })
    }

    /// Number of samples consumed.
    pub fn samples_seen(&self) -> usize {
        self.counter.samples_seen()
    }

    /// Feeds one sample; closed slip cycles are appended to `out`. Non-finite values are
    /// rejected (with the channel named) and leave the state unchanged.
    pub fn push(
        &mut self,
        sample: ContactSample,
        out: &mut Vec<SlipCycle>,
    ) -> Result<(), FrettingError> {
        let index = self.counter.samples_seen();
        for (channel, value) in [
            ("normal_force_n", sample.normal_force_n),
            ("tangential_force_n", sample.tangential_force_n),
        ] {
            if !value.is_finite() {
                return Err(FrettingError::NonFiniteChannel {
                    index,
                    channel,
                    value,
                });
            }
        }
        let forces = (sample.normal_force_n, sample.tangential_force_n);
        self.counter
            .push_with(sample.slip_m, forces, |c, s| out.push(SlipCycle::new(c, s)))
    }

    /// Appends the cycles left if the history ended now (residue as half cycles); the state is
    /// unchanged.
    pub fn finish(&self, out: &mut Vec<SlipCycle>) {
        self.counter
            .finish_with(|c, s| out.push(SlipCycle::new(c, s)));
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::fretting::rainflow::{count_cycles, RainflowOptions};

    fn history(n: usize) -> Vec<ContactSample> {
        (0..n)
            .map(|i| {
                let t = i as f64 * 0.37;
                ContactSample {
                    slip_m: 1e-6 * ((t).sin() + 0.4 * (2.3 * t).sin()),
                    normal_force_n: 500.0 + 50.0 * (0.5 * t).cos(),
                    tangential_force_n: 20.0 * (t + 0.3).sin(),
                }
            })
            .collect()
    }

    #[test]
    fn cycle_forces_equal_direct_statistics_over_the_counted_samples() {
        let h = history(400);
        let mut acc = ContactCycleAccumulator::new(0.0).unwrap();
        let mut cycles = Vec::new();
        for s in &h {
            acc.push(*s, &mut cycles).unwrap();
        }
        acc.finish(&mut cycles);
        let slips: Vec<f64> = h.iter().map(|s| s.slip_m).collect();
        let plain = count_cycles(&slips, &RainflowOptions::default()).unwrap();
        assert_eq!(cycles.iter().map(|c| c.slip).collect::<Vec<_>>(), plain);
        for c in &cycles {
            let span = &h[c.slip.start_index..=c.slip.end_index];
            let fnx = span.iter().map(|s| s.normal_force_n);
            let ftx = span.iter().map(|s| s.tangential_force_n);
            let max_n = fnx.clone().fold(f64::NEG_INFINITY, f64::max);
            let min_t = ftx.clone().fold(f64::INFINITY, f64::min);
            let mean_n = fnx.sum::<f64>() / span.len() as f64;
            let mean_t = ftx.sum::<f64>() / span.len() as f64;
            assert_eq!(c.normal_force_n.max, max_n);
            assert_eq!(c.tangential_force_n.min, min_t);
            assert!((c.normal_force_n.mean - mean_n).abs() <= 1e-12 * mean_n.abs());
            assert!((c.tangential_force_n.mean - mean_t).abs() <= 1e-12 * 20.0);
        }
    }

    #[test]
    fn non_finite_force_names_its_channel() {
        let mut acc = ContactCycleAccumulator::new(0.0).unwrap();
        let mut out = Vec::new();
        let bad = ContactSample {
            slip_m: 0.0,
            normal_force_n: 1.0,
            tangential_force_n: f64::NAN,
        };
        let err = acc.push(bad, &mut out).unwrap_err();
        assert!(matches!(
            err,
            FrettingError::NonFiniteChannel {
                index: 0,
                channel: "tangential_force_n",
                ..
            }
        ));
        assert_eq!(acc.samples_seen(), 0);
    }
}
