//! Two-dimensional cycle histograms: slip amplitude × normal force.
//!
//! Bins are given by strictly increasing edges on each axis ([`BinEdges`], uniform or
//! geometric; geometric suits slip amplitudes that span decades of micrometres). Bin `k` holds
//! values in `[e_k, e_{k+1})`, the last bin also holds its upper edge. Values outside the edges
//! are counted in `out_of_range` rather than dropped, so the histogram total always equals the
//! count of the cycles fed to it.
//!
//! Units: slip amplitude (half the slip range) in m, normal force in N; counts are cycles
//! (half cycles add 0.5). Histograms with equal binning merge by addition (per seed, per sea
//! state, lifetime weighting through [`CycleHistogram::scaled`]).

use serde::{Deserialize, Serialize};

use super::cycles::SlipCycle;
use super::error::{positive, FrettingError};

/// Strictly increasing bin edges of one axis.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct BinEdges(Vec<f64>);

impl BinEdges {
    /// Edges given explicitly (at least two, finite, strictly increasing).
    pub fn new(edges: Vec<f64>) -> Result<Self, FrettingError> {
        if edges.len() < 2 {
            return Err(FrettingError::InvalidParameter {
                field: "edges.len",
                value: edges.len() as f64,
                reason: "at least two edges are needed",
            });
        }
        for w in edges.windows(2) {
            if !(w[0].is_finite() && w[1].is_finite() && w[1] > w[0]) {
                return Err(FrettingError::InvalidParameter {
                    field: "edges",
                    value: w[1],
                    reason: "edges must be finite and strictly increasing",
                });
            }
        }
        Ok(Self(edges))
    }

    /// `bins` equal bins from `min` to `max`.
    pub fn uniform(min: f64, max: f64, bins: usize) -> Result<Self, FrettingError> {
        let n = bins.max(1);
        Self::new(
            (0..=n)
                .map(|k| min + (max - min) * k as f64 / n as f64)
                .collect(),
        )
    }

    /// `bins` bins of equal ratio from `min` (> 0) to `max`.
    pub fn geometric(min: f64, max: f64, bins: usize) -> Result<Self, FrettingError> {
        positive("edges.min", min)?;
        let n = bins.max(1);
        let ratio = (max / min).ln();
        Self::new(
            (0..=n)
                .map(|k| min * (ratio * k as f64 / n as f64).exp())
                .collect(),
        )
    }

    /// The edges.
    pub fn edges(&self) -> &[f64] {
        &self.0
    }

    /// Number of bins.
    pub fn bins(&self) -> usize {
        self.0.len() - 1
    }

    /// The bin holding `x`, or `None` outside the edges.
    pub(crate) fn locate(&self, x: f64) -> Option<usize> {
        let e = &self.0;
        let last = *e.last()?;
        if !(x >= e[0] && x <= last) {
            return None;
        }
        // Number of edges ≤ x, minus one; the upper edge falls in the last bin.
        let k = e.partition_point(|&edge| edge <= x);
        Some((k - 1).min(self.bins() - 1))
    }
}

/// Which normal force of a cycle goes on the force axis.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize, Deserialize)]
pub enum ForceMeasure {
    /// The mean over the cycle's samples (default).
    #[default]
    Mean,
    /// The largest value over the cycle.
    Max,
}

/// Histogram of cycles over slip amplitude × normal force.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct CycleHistogram {
    slip_amplitude_m: BinEdges,
    normal_force_n: BinEdges,
    force_measure: ForceMeasure,
    /// Row-major counts: `counts[i * force_bins + j]` for slip bin i and force bin j.
    counts: Vec<f64>,
    out_of_range: f64,
}

impl CycleHistogram {
    /// An empty histogram.
    pub fn new(
        slip_amplitude_m: BinEdges,
        normal_force_n: BinEdges,
        force_measure: ForceMeasure,
    ) -> Self {
        let counts = vec![0.0; slip_amplitude_m.bins() * normal_force_n.bins()];
        Self {
            slip_amplitude_m,
            normal_force_n,
            force_measure,
            counts,
            out_of_range: 0.0,
        }
    }

    /// Adds `count` cycles at (slip amplitude, normal force).
    pub fn add(&mut self, slip_amplitude_m: f64, normal_force_n: f64, count: f64) {
        match (
            self.slip_amplitude_m.locate(slip_amplitude_m),
            self.normal_force_n.locate(normal_force_n),
        ) {
            (Some(i), Some(j)) => self.counts[i * self.normal_force_n.bins() + j] += count,
            _ => self.out_of_range += count,
        }
    }

    /// Adds one slip cycle with its count.
    pub fn add_cycle(&mut self, cycle: &SlipCycle) {
        let force = match self.force_measure {
            ForceMeasure::Mean => cycle.normal_force_n.mean,
            ForceMeasure::Max => cycle.normal_force_n.max,
        };
        self.add(cycle.slip_amplitude_m(), force, cycle.slip.count);
    }

    /// Count in slip bin `i`, force bin `j` (0 outside the grid).
    pub fn count(&self, i: usize, j: usize) -> f64 {
        if i < self.slip_amplitude_m.bins() && j < self.normal_force_n.bins() {
            self.counts[i * self.normal_force_n.bins() + j]
        } else {
            0.0
        }
    }

    /// Cycles that fell outside the edges.
    pub fn out_of_range(&self) -> f64 {
        self.out_of_range
    }

    /// Total count, in and out of range.
    pub fn total(&self) -> f64 {
        self.counts.iter().sum::<f64>() + self.out_of_range
    }

    /// Slip amplitude edges (m).
    pub fn slip_edges(&self) -> &BinEdges {
        &self.slip_amplitude_m
    }

    /// Normal force edges (N).
    pub fn force_edges(&self) -> &BinEdges {
        &self.normal_force_n
    }

    /// Adds the counts of a histogram with the same binning.
    pub fn merge(&mut self, other: &Self) -> Result<(), FrettingError> {
        if self.slip_amplitude_m != other.slip_amplitude_m
            || self.normal_force_n != other.normal_force_n
            || self.force_measure != other.force_measure
        {
            return Err(FrettingError::HistogramMismatch);
        }
        for (a, b) in self.counts.iter_mut().zip(&other.counts) {
            *a += b;
        }
        self.out_of_range += other.out_of_range;
        Ok(())
    }

    /// A copy with every count multiplied by `factor` (e.g. occurrence × life / duration).
    pub fn scaled(&self, factor: f64) -> Self {
        let mut out = self.clone();
        out.counts.iter_mut().for_each(|c| *c *= factor);
        out.out_of_range *= factor;
        out
    }

    /// Non-empty bins as `(slip bin centre m, force bin centre N, count)`.
    pub fn nonzero_bins(&self) -> Vec<(f64, f64, f64)> {
        let (se, fe) = (self.slip_amplitude_m.edges(), self.normal_force_n.edges());
        let nf = self.normal_force_n.bins();
        self.counts
            .iter()
            .enumerate()
            .filter(|(_, &c)| c != 0.0)
            .map(|(k, &c)| {
                let (i, j) = (k / nf, k % nf);
                (0.5 * (se[i] + se[i + 1]), 0.5 * (fe[j] + fe[j + 1]), c)
            })
            .collect()
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::fretting::cycles::ForceStats;
    use crate::fretting::rainflow::Cycle;

    fn cycle(range: f64, fmean: f64, fmax: f64, count: f64) -> SlipCycle {
        SlipCycle {
            slip: Cycle {
                range,
                mean: 0.0,
                count,
                start_index: 0,
                end_index: 1,
            },
            normal_force_n: ForceStats {
                min: 0.0,
                max: fmax,
                mean: fmean,
            },
            tangential_force_n: ForceStats {
                min: 0.0,
                max: 0.0,
                mean: 0.0,
            },
        }
    }

    #[test]
    fn bins_are_closed_left_and_the_last_edge_belongs_to_the_last_bin() {
        let e = BinEdges::new(vec![0.0, 1.0, 2.0, 4.0]).unwrap();
        assert_eq!(e.locate(0.0), Some(0));
        assert_eq!(e.locate(0.999), Some(0));
        assert_eq!(e.locate(1.0), Some(1));
        assert_eq!(e.locate(4.0), Some(2));
        assert_eq!(e.locate(4.0001), None);
        assert_eq!(e.locate(-1e-9), None);
        assert_eq!(e.locate(f64::NAN), None);
    }

    #[test]
    fn geometric_edges_have_equal_ratios() {
        let e = BinEdges::geometric(1e-7, 1e-4, 3).unwrap();
        let r: Vec<f64> = e.edges().windows(2).map(|w| w[1] / w[0]).collect();
        for x in r {
            assert!((x - 10.0).abs() < 1e-9);
        }
        assert!(BinEdges::geometric(0.0, 1.0, 3).is_err());
        assert!(BinEdges::new(vec![0.0, 0.0]).is_err());
    }

    #[test]
    fn cycles_land_in_their_bins_and_the_total_is_conserved() {
        let slip = BinEdges::uniform(0.0, 4e-6, 4).unwrap();
        let force = BinEdges::uniform(0.0, 1000.0, 2).unwrap();
        let mut h = CycleHistogram::new(slip.clone(), force.clone(), ForceMeasure::Mean);
        h.add_cycle(&cycle(3e-6, 300.0, 900.0, 1.0)); // amplitude 1.5 µm → slip bin 1, force bin 0
        h.add_cycle(&cycle(3e-6, 300.0, 900.0, 0.5));
        h.add_cycle(&cycle(7e-6, 700.0, 900.0, 1.0)); // amplitude 3.5 µm → bin 3, force bin 1
        h.add_cycle(&cycle(1e-5, 700.0, 900.0, 0.5)); // amplitude 5 µm → out of range
        assert_eq!(h.count(1, 0), 1.5);
        assert_eq!(h.count(3, 1), 1.0);
        assert_eq!(h.out_of_range(), 0.5);
        assert_eq!(h.total(), 3.0);
        let mut by_max = CycleHistogram::new(slip, force, ForceMeasure::Max);
        by_max.add_cycle(&cycle(3e-6, 300.0, 900.0, 1.0));
        assert_eq!(by_max.count(1, 1), 1.0);
        assert_eq!(h.merge(&by_max), Err(FrettingError::HistogramMismatch));
        let mut twice = h.clone();
        twice.merge(&h).unwrap();
        assert_eq!(twice, h.scaled(2.0));
        assert_eq!(h.nonzero_bins().len(), 2);
    }
}
