//! Streaming rainflow counter: samples one at a time, a small stack, serialisable state.
//!
//! Same reversals ([`super::reversals::ReversalDetector`]) and the same three-point rule with
//! the starting-point case as the batch counter ([`super::rainflow`], ASTM E1049-85 §5.4.4),
//! so a history fed sample by sample gives exactly the batch cycles, in the same order. Memory is
//! the stack of unclosed reversals (for a stationary signal a few tens of points, bounded by
//! the number of distinct range levels), not the history.
//!
//! The counter can carry a per-segment summary `S` of side channels (e.g. the contact forces
//! that go with a slip history, `super::cycles`): every stack entry keeps the summary of the
//! samples since the previous entry, so that a cycle closing on points `a`, `b` is emitted with
//! the summary of the samples `a.index ..= b.index`. With `S = ()` this costs nothing.
//!
//! The whole state derives `Serialize`/`Deserialize`: a checkpoint restored and fed the rest of
//! the history gives bit-for-bit the cycles of an uninterrupted run.

use serde::{Deserialize, Serialize};

use super::error::FrettingError;
use super::rainflow::Cycle;
use super::reversals::{Reversal, ReversalDetector};

/// A summary of the side-channel samples over a stretch of the history.
pub trait SegmentSummary: Clone + Default {
    /// One side-channel sample.
    type Sample: Copy;
    /// Adds one sample to the summary.
    fn add(&mut self, sample: Self::Sample);
    /// Merges the summary of an adjacent stretch.
    fn merge(&mut self, other: &Self);
}

/// No side channel.
impl SegmentSummary for () {
    type Sample = ();
    #[inline(always)]
    fn add(&mut self, _sample: ()) {}
    #[inline(always)]
    fn merge(&mut self, _other: &()) {}
}

/// An unclosed reversal on the stack.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
struct Entry<S> {
    point: Reversal,
    /// Summary of the reversal sample alone.
    own: S,
    /// Summary of the samples after the previous entry up to and including this one.
    segment: S,
}

/// Streaming three-point rainflow counter with an optional side-channel summary `S`.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct StreamingRainflow<S = ()> {
    detector: ReversalDetector,
    stack: Vec<Entry<S>>,
    /// Summary of the pending extreme's sample.
    candidate_own: S,
    /// Samples after the last confirmed reversal up to and including the pending extreme.
    candidate_segment: S,
    /// Samples after the pending extreme.
    after_candidate: S,
    samples_seen: usize,
}

impl<S: SegmentSummary> StreamingRainflow<S> {
    /// An empty counter with hysteresis gate `gate` (unit of the history, ≥ 0).
    pub fn new(gate: f64) -> Result<Self, FrettingError> {
        Ok(Self {
            detector: ReversalDetector::new(gate)?,
            stack: Vec::new(),
            candidate_own: S::default(),
            candidate_segment: S::default(),
            after_candidate: S::default(),
            samples_seen: 0,
        })
    }

    /// Number of samples consumed so far (the index the next sample gets).
    pub(crate) fn samples_seen(&self) -> usize {
        self.samples_seen
    }

    /// Number of unclosed reversals held.
    pub fn stack_len(&self) -> usize {
        self.stack.len()
    }

    /// Feeds one sample with its side-channel data; every cycle it closes goes to `sink` with
    /// the summary of its samples. A non-finite value is rejected and leaves the state as it was.
    pub(crate) fn push_with(
        &mut self,
        value: f64,
        sample: S::Sample,
        mut sink: impl FnMut(Cycle, S),
    ) -> Result<(), FrettingError> {
        let index = self.samples_seen;
        if !value.is_finite() {
            return Err(FrettingError::NonFiniteSample { index, value });
        }
        self.samples_seen += 1;
        let mut own = S::default();
        own.add(sample);
        let confirmed = self.detector.push(index, value);
        if index == 0 {
            // The starting point: confirmed at once and also the first candidate.
            if let Some(point) = confirmed {
                self.stack.push(Entry {
                    point,
                    own: own.clone(),
                    segment: own,
                });
            }
            return Ok(());
        }
        let moved = self.detector.candidate().is_some_and(|c| c.index == index);
        if let Some(point) = confirmed {
            let entry = Entry {
                point,
                own: std::mem::take(&mut self.candidate_own),
                segment: std::mem::take(&mut self.candidate_segment),
            };
            self.push_entry(entry, &mut sink);
            // A confirmation always makes the current sample the new candidate.
            self.candidate_segment = std::mem::take(&mut self.after_candidate);
            self.candidate_segment.merge(&own);
            self.candidate_own = own;
        } else if moved {
            let after = std::mem::take(&mut self.after_candidate);
            self.candidate_segment.merge(&after);
            self.candidate_segment.merge(&own);
            self.candidate_own = own;
        } else {
            self.after_candidate.merge(&own);
        }
        Ok(())
    }

    /// Emits what the history would leave if it ended now: the pending extreme closes its
    /// ranges, then the residue counts as half cycles (ASTM E1049-85 §5.4.4 step 6). The state is
    /// not changed, so the stream can go on afterwards.
    pub(crate) fn finish_with(&self, mut sink: impl FnMut(Cycle, S)) {
        let mut tail = self.clone();
        if let Some(point) = self.detector.pending() {
            let entry = Entry {
                point,
                own: tail.candidate_own.clone(),
                segment: tail.candidate_segment.clone(),
            };
            tail.push_entry(entry, &mut sink);
        }
        for w in tail.stack.windows(2) {
            let mut summary = w[0].own.clone();
            summary.merge(&w[1].segment);
            sink(Cycle::from_points(w[0].point, w[1].point, 0.5), summary);
        }
    }

    /// Pushes a confirmed reversal and closes what it closes (three-point rule).
    fn push_entry(&mut self, entry: Entry<S>, sink: &mut impl FnMut(Cycle, S)) {
        self.stack.push(entry);
        while self.stack.len() >= 3 {
            let l = self.stack.len();
            let (a, b, c) = (
                self.stack[l - 3].point,
                self.stack[l - 2].point,
                self.stack[l - 1].point,
            );
            if (c.value - b.value).abs() < (b.value - a.value).abs() {
                break;
            }
            let mut summary = self.stack[l - 3].own.clone();
            summary.merge(&self.stack[l - 2].segment);
            if l == 3 {
                sink(Cycle::from_points(a, b, 0.5), summary);
                self.stack.remove(0);
            } else {
                sink(Cycle::from_points(a, b, 1.0), summary);
                let last = self.stack.pop();
                let removed_b = self.stack.pop();
                let removed_a = self.stack.pop();
                if let (Some(mut last), Some(removed_b), Some(mut merged)) =
                    (last, removed_b, removed_a)
                {
                    merged.segment.merge(&removed_b.segment);
                    merged.segment.merge(&last.segment);
                    last.segment = merged.segment;
                    self.stack.push(last);
                }
            }
        }
    }
}

impl StreamingRainflow<()> {
    /// Feeds one sample; closed cycles are appended to `out`.
    pub fn push(&mut self, value: f64, out: &mut Vec<Cycle>) -> Result<(), FrettingError> {
        self.push_with(value, (), |c, ()| out.push(c))
    }

    /// Appends the cycles left if the history ended now (state unchanged).
    pub fn finish(&self, out: &mut Vec<Cycle>) {
        self.finish_with(|c, ()| out.push(c));
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::fretting::rainflow::{count_cycles, RainflowOptions};

    const ASTM: [f64; 9] = [-2.0, 1.0, -3.0, 5.0, -1.0, 3.0, -4.0, 4.0, -2.0];

    fn stream(history: &[f64], gate: f64) -> Vec<Cycle> {
        let mut s = StreamingRainflow::<()>::new(gate).unwrap();
        let mut out = Vec::new();
        for &x in history {
            s.push(x, &mut out).unwrap();
        }
        s.finish(&mut out);
        out
    }

    #[test]
    fn streaming_astm_example_equals_batch() {
        let batch = count_cycles(&ASTM, &RainflowOptions::default()).unwrap();
        assert_eq!(stream(&ASTM, 0.0), batch);
    }

    #[test]
    fn finish_leaves_the_stream_able_to_continue() {
        let mut s = StreamingRainflow::<()>::new(0.0).unwrap();
        let mut closed = Vec::new();
        for &x in &ASTM[..5] {
            s.push(x, &mut closed).unwrap();
        }
        let mut preview = Vec::new();
        s.finish(&mut preview);
        assert!(!preview.is_empty());
        for &x in &ASTM[5..] {
            s.push(x, &mut closed).unwrap();
        }
        s.finish(&mut closed);
        assert_eq!(
            closed,
            count_cycles(&ASTM, &RainflowOptions::default()).unwrap()
        );
    }

    #[test]
    fn non_finite_sample_is_rejected_without_changing_the_state() {
        let mut s = StreamingRainflow::<()>::new(0.0).unwrap();
        let mut out = Vec::new();
        s.push(1.0, &mut out).unwrap();
        let before = s.clone();
        let err = s.push(f64::NAN, &mut out).unwrap_err();
        assert!(matches!(
            err,
            FrettingError::NonFiniteSample { index: 1, .. }
        ));
        assert_eq!(s, before);
    }

    /// Counts the samples in each summary, to check the segment bookkeeping.
    #[derive(Debug, Clone, Default, PartialEq)]
    struct Indices(Vec<usize>);
    impl SegmentSummary for Indices {
        type Sample = usize;
        fn add(&mut self, sample: usize) {
            self.0.push(sample);
        }
        fn merge(&mut self, other: &Self) {
            self.0.extend_from_slice(&other.0);
        }
    }

    #[test]
    fn cycle_summaries_cover_exactly_the_samples_of_the_counted_range() {
        // Non-reversal points in between, a flat stretch and a gate.
        let h = [
            0.0, 1.0, 2.5, 2.0, 2.4, -1.0, -3.0, -3.0, 0.5, 4.0, 3.9, 1.0, 2.0, -0.5, 3.0, 1.0,
        ];
        for gate in [0.0, 0.45] {
            let mut s = StreamingRainflow::<Indices>::new(gate).unwrap();
            let mut got = Vec::new();
            for (i, &x) in h.iter().enumerate() {
                s.push_with(x, i, |c, ix| got.push((c, ix))).unwrap();
            }
            s.finish_with(|c, ix| got.push((c, ix)));
            assert!(!got.is_empty());
            for (c, ix) in got {
                let expected: Vec<usize> = (c.start_index..=c.end_index).collect();
                assert_eq!(ix.0, expected, "gate {gate}, cycle {c:?}");
            }
        }
    }
}
