//! Batch rainflow counting, ASTM E1049-85 §5.4.4 (three-point method, half cycles kept) and
//! §5.4.5 (histories that repeat).
//!
//! On the sequence of reversals (see [`super::reversals`]), with X the most recent range and Y
//! the range before it:
//! - X < Y: read the next reversal;
//! - X ≥ Y and Y contains the starting point S: count Y as a half cycle, drop S;
//! - X ≥ Y otherwise: count Y as one cycle, drop both its points.
//!
//! At the end of the history every range left (the residue) counts as a half cycle. In the
//! repeating variant the history is rotated to start (and end) at the reversal of largest
//! magnitude, which closes every range into a full cycle and leaves no residue.
//!
//! Each [`Cycle`] carries its range `|b − a|`, mean `(a + b)/2`, count (0.5 or 1.0) and the sample
//! indices of its two points in time order (for a repeating history a cycle that wraps round
//! the end has `end_index < start_index`). Units are those of the history.
//!
//! The counter keeps its buffers between calls ([`RainflowCounter::count_into`]) and never
//! allocates per sample.

use serde::{Deserialize, Serialize};

use super::error::FrettingError;
use super::reversals::{first_non_finite, Reversal, ReversalDetector};

/// One counted rainflow cycle or half cycle.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct Cycle {
    /// Range |b − a| (unit of the history).
    pub range: f64,
    /// Mean (a + b)/2 (unit of the history).
    pub mean: f64,
    /// 0.5 for a half cycle, 1.0 for a full cycle.
    pub count: f64,
    /// Sample index of the earlier point of the counted range.
    pub start_index: usize,
    /// Sample index of the later point of the counted range.
    pub end_index: usize,
}

impl Cycle {
    /// The cycle formed by the range from `a` to `b` with weight `count`.
    #[inline(always)]
    pub(crate) fn from_points(a: Reversal, b: Reversal, count: f64) -> Self {
        Self {
            range: (b.value - a.value).abs(),
            mean: 0.5 * (a.value + b.value),
            count,
            start_index: a.index,
            end_index: b.index,
        }
    }

    /// Half the range.
    pub fn amplitude(&self) -> f64 {
        0.5 * self.range
    }

    /// True for a half cycle.
    pub fn is_half(&self) -> bool {
        self.count < 1.0
    }
}

/// Options of the rainflow count (validated, with `Default`).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct RainflowOptions {
    /// Hysteresis gate (unit of the history, ≥ 0): ripples not larger than this are ignored.
    pub hysteresis_gate: f64,
    /// Treat the history as one period of a repeating signal (ASTM E1049-85 §5.4.5).
    pub repeating: bool,
}

impl Default for RainflowOptions {
    fn default() -> Self {
        Self {
            hysteresis_gate: 0.0,
            repeating: false,
        }
    }
}

impl RainflowOptions {
    /// Checks the options.
    pub fn validate(&self) -> Result<(), FrettingError> {
        ReversalDetector::new(self.hysteresis_gate).map(|_| ())
    }
}

/// Batch rainflow counter with reusable buffers.
#[derive(Debug, Clone)]
pub struct RainflowCounter {
    options: RainflowOptions,
    stack: Vec<Reversal>,
    reversals: Vec<Reversal>,
}

impl RainflowCounter {
    /// A counter with validated options.
    pub fn new(options: RainflowOptions) -> Result<Self, FrettingError> {
        options.validate()?;
        Ok(Self {
            options,
            stack: Vec::new(),
            reversals: Vec::new(),
        })
    }

    /// The options in use.
    pub fn options(&self) -> &RainflowOptions {
        &self.options
    }

    /// Counts `history` and appends its cycles to `out` (in the order they close).
    pub fn count_into(
        &mut self,
        history: &[f64],
        out: &mut Vec<Cycle>,
    ) -> Result<(), FrettingError> {
        if let Some((index, value)) = first_non_finite(history) {
            return Err(FrettingError::NonFiniteSample { index, value });
        }
        if self.options.repeating {
            self.count_repeating(history, out)
        } else {
            self.count_linear(history, out)
        }
    }

    fn count_linear(&mut self, history: &[f64], out: &mut Vec<Cycle>) -> Result<(), FrettingError> {
        let count = extract_into(history, self.options.hysteresis_gate, &mut self.reversals);
        let stack = &mut self.stack;
        stack.clear();
        for &r in &self.reversals[..count] {
            push_three_point(stack, r, out);
        }
        // ASTM E1049-85 §5.4.4 step 6: the residue counts as half cycles.
        out.extend(
            stack
                .windows(2)
                .map(|w| Cycle::from_points(w[0], w[1], 0.5)),
        );
        Ok(())
    }

    fn count_repeating(
        &mut self,
        history: &[f64],
        out: &mut Vec<Cycle>,
    ) -> Result<(), FrettingError> {
        let gate = self.options.hysteresis_gate;
        let mut detector = ReversalDetector::new(gate)?;
        self.reversals.clear();
        for (index, &value) in history.iter().enumerate() {
            self.reversals.extend(detector.push(index, value));
        }
        self.reversals.extend(detector.pending());
        if self.reversals.len() < 2 {
            return Ok(());
        }
        // Start at the reversal of largest magnitude (ASTM E1049-85 §5.4.5); ties → earliest.
        let start = self
            .reversals
            .iter()
            .enumerate()
            .fold((0, f64::NEG_INFINITY), |best, (k, r)| {
                if r.value.abs() > best.1 {
                    (k, r.value.abs())
                } else {
                    best
                }
            })
            .0;
        let n = self.reversals.len();
        // The junction end → start may not be a reversal: run the detector over the rotated,
        // closed sequence.
        let mut detector = ReversalDetector::new(gate)?;
        let stack = &mut self.stack;
        stack.clear();
        let rotated = (0..=n).map(|k| self.reversals[(start + k) % n]);
        for r in rotated {
            if let Some(r) = detector.push(r.index, r.value) {
                push_repeating(stack, r, out);
            }
        }
        if let Some(r) = detector.pending() {
            push_repeating(stack, r, out);
        }
        // Starting and ending at the global extreme leaves a single point; keep anything else
        // (only reachable through rounding) as half cycles rather than dropping it.
        out.extend(
            stack
                .windows(2)
                .map(|w| Cycle::from_points(w[0], w[1], 0.5)),
        );
        Ok(())
    }
}

/// Reversals of `history` into `buf` (grown to `history.len() + 1`, never shrunk, so repeated
/// calls do not allocate); returns how many were written.
///
/// The same rule as [`ReversalDetector`] written for speed: one pass, no data-dependent branch
/// in the loop (each pending extreme is written unconditionally and the length advances only
/// on a confirmed reversal). The streaming counter uses the detector itself, and the property
/// tests check that both give the same cycles.
fn extract_into(history: &[f64], gate: f64, buf: &mut Vec<Reversal>) -> usize {
    let n = history.len();
    if n == 0 {
        return 0;
    }
    if buf.len() < n + 1 {
        buf.resize(n + 1, Reversal::default());
    }
    let first = history[0];
    buf[0] = Reversal {
        index: 0,
        value: first,
    };
    // Before the first move larger than the gate the direction is unknown.
    let mut i = 1;
    while i < n && (history[i] - first).abs() <= gate {
        i += 1;
    }
    if i == n {
        return 1;
    }
    let mut dir = if history[i] > first { 1.0 } else { -1.0 };
    let mut cand = Reversal {
        index: i,
        value: history[i],
    };
    let mut len = 1;
    let buf = &mut buf[..n + 1];
    for (j, &x) in history.iter().enumerate().skip(i + 1) {
        // > 0: beyond the pending extreme; < −gate: turned back by more than the gate.
        let ext = (x - cand.value) * dir;
        let reverse = -ext > gate;
        let take = (ext > 0.0) | reverse;
        buf[len] = cand;
        len += reverse as usize;
        dir = if reverse { -dir } else { dir };
        cand = if take {
            Reversal { index: j, value: x }
        } else {
            cand
        };
    }
    buf[len] = cand;
    len + 1
}

/// One step of the three-point method with the starting-point rule (ASTM E1049-85 §5.4.4).
#[inline(always)]
fn push_three_point(stack: &mut Vec<Reversal>, r: Reversal, out: &mut Vec<Cycle>) {
    stack.push(r);
    while stack.len() >= 3 {
        let l = stack.len();
        let (a, b, c) = (stack[l - 3], stack[l - 2], stack[l - 1]);
        let y = (b.value - a.value).abs();
        let x = (c.value - b.value).abs();
        if x < y {
            break;
        }
        if l == 3 {
            // Y contains the starting point: half cycle, S moves to the second point of Y.
            out.push(Cycle::from_points(a, b, 0.5));
            stack[0] = b;
            stack[1] = c;
            stack.truncate(2);
        } else {
            out.push(Cycle::from_points(a, b, 1.0));
            stack[l - 3] = c;
            stack.truncate(l - 2);
        }
    }
}

/// One step of the three-point method without the starting-point rule (§5.4.5).
fn push_repeating(stack: &mut Vec<Reversal>, r: Reversal, out: &mut Vec<Cycle>) {
    stack.push(r);
    while stack.len() >= 3 {
        let l = stack.len();
        let (a, b, c) = (stack[l - 3], stack[l - 2], stack[l - 1]);
        if (c.value - b.value).abs() < (b.value - a.value).abs() {
            break;
        }
        out.push(Cycle::from_points(a, b, 1.0));
        stack[l - 3] = c;
        stack.truncate(l - 2);
    }
}

/// Counts the cycles of `history` (convenience wrapper around [`RainflowCounter`]).
pub fn count_cycles(
    history: &[f64],
    options: &RainflowOptions,
) -> Result<Vec<Cycle>, FrettingError> {
    let mut out = Vec::new();
    RainflowCounter::new(*options)?.count_into(history, &mut out)?;
    Ok(out)
}

/// Sum of the counts (half cycles count 0.5).
pub fn total_count(cycles: &[Cycle]) -> f64 {
    cycles.iter().map(|c| c.count).sum()
}

/// Cycles aggregated by exactly equal range: `(range, total count)` sorted by range.
pub fn counts_by_range(cycles: &[Cycle]) -> Vec<(f64, f64)> {
    let mut sorted: Vec<(f64, f64)> = cycles.iter().map(|c| (c.range, c.count)).collect();
    sorted.sort_by(|a, b| a.0.total_cmp(&b.0));
    let mut out: Vec<(f64, f64)> = Vec::with_capacity(sorted.len());
    for (range, count) in sorted {
        match out.last_mut() {
            Some(last) if last.0 == range => last.1 += count,
            _ => out.push((range, count)),
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    const ASTM: [f64; 9] = [-2.0, 1.0, -3.0, 5.0, -1.0, 3.0, -4.0, 4.0, -2.0];

    #[test]
    fn astm_example_gives_the_published_ranges_and_counts() {
        // ASTM E1049-85 §5.4.4, Fig. 6 / Table 4 of the standard.
        let cycles = count_cycles(&ASTM, &RainflowOptions::default()).unwrap();
        let expected = [(3.0, 0.5), (4.0, 1.5), (6.0, 0.5), (8.0, 1.0), (9.0, 0.5)];
        assert_eq!(counts_by_range(&cycles), expected.to_vec());
        assert_eq!(total_count(&cycles), 4.0); // (9 reversals − 1)/2
    }

    #[test]
    fn astm_example_cycles_carry_means_and_indices() {
        let cycles = count_cycles(&ASTM, &RainflowOptions::default()).unwrap();
        // First event: X = |−3 − 1| ≥ Y = |1 − (−2)| with S in Y → half cycle −2 → 1.
        assert_eq!(
            cycles[0],
            Cycle {
                range: 3.0,
                mean: -0.5,
                count: 0.5,
                start_index: 0,
                end_index: 1
            }
        );
        // The full cycle −1 → 3 (samples 4, 5).
        let full4 = cycles
            .iter()
            .find(|c| c.range == 4.0 && c.count == 1.0)
            .unwrap();
        assert_eq!(
            (full4.mean, full4.start_index, full4.end_index),
            (1.0, 4, 5)
        );
        for c in &cycles {
            assert!(c.start_index < c.end_index);
            let (a, b) = (ASTM[c.start_index], ASTM[c.end_index]);
            assert_eq!(c.range, (b - a).abs());
            assert_eq!(c.mean, 0.5 * (a + b));
        }
    }

    #[test]
    fn repeating_astm_example_closes_into_four_full_cycles() {
        let options = RainflowOptions {
            repeating: true,
            ..Default::default()
        };
        let cycles = count_cycles(&ASTM, &options).unwrap();
        let expected = [(3.0, 1.0), (4.0, 1.0), (7.0, 1.0), (9.0, 1.0)];
        assert_eq!(counts_by_range(&cycles), expected.to_vec());
        assert!(cycles.iter().all(|c| c.count == 1.0));
        // The 9-range cycle runs from the peak 5 (sample 3) to the valley −4 (sample 6).
        let big = cycles.iter().find(|c| c.range == 9.0).unwrap();
        assert_eq!((big.start_index, big.end_index), (3, 6));
    }

    #[test]
    fn repeating_count_does_not_depend_on_where_the_period_starts() {
        let options = RainflowOptions {
            repeating: true,
            ..Default::default()
        };
        let base = counts_by_range(&count_cycles(&ASTM[..8], &options).unwrap());
        for shift in 1..8 {
            let mut h = ASTM[..8].to_vec();
            h.rotate_left(shift);
            assert_eq!(
                counts_by_range(&count_cycles(&h, &options).unwrap()),
                base,
                "shift {shift}"
            );
        }
    }

    #[test]
    fn short_histories_give_no_or_half_cycles() {
        let o = RainflowOptions::default();
        assert!(count_cycles(&[], &o).unwrap().is_empty());
        assert!(count_cycles(&[2.0], &o).unwrap().is_empty());
        let c = count_cycles(&[1.0, 4.0], &o).unwrap();
        assert_eq!(
            c,
            vec![Cycle {
                range: 3.0,
                mean: 2.5,
                count: 0.5,
                start_index: 0,
                end_index: 1
            }]
        );
        let r = RainflowOptions {
            repeating: true,
            ..o
        };
        assert_eq!(count_cycles(&[1.0, 4.0], &r).unwrap().len(), 1);
    }

    #[test]
    fn non_finite_samples_are_reported_with_their_index() {
        let err = count_cycles(&[0.0, 1.0, f64::INFINITY, 0.0], &RainflowOptions::default());
        assert!(matches!(
            err,
            Err(FrettingError::NonFiniteSample { index: 2, .. })
        ));
    }

    #[test]
    fn counter_buffers_are_reused_between_histories() {
        let mut counter = RainflowCounter::new(RainflowOptions::default()).unwrap();
        let mut out = Vec::new();
        counter.count_into(&ASTM, &mut out).unwrap();
        let first = out.clone();
        out.clear();
        counter.count_into(&ASTM, &mut out).unwrap();
        assert_eq!(out, first);
    }
}
