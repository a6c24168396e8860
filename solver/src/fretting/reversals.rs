//! Reversal (peak / valley) extraction with an optional hysteresis gate.
//!
//! A reversal is a sample where the history changes direction (ASTM E1049-85 §3.2.5). The first
//! sample of a history is always kept as a reversal (it is the starting point S of the
//! three-point rainflow method, ASTM E1049-85 §5.4.4) and so is the last extreme reached.
//!
//! The hysteresis gate `h ≥ 0` filters small ripples: an extreme is only confirmed as a reversal
//! once the history has moved back from it by strictly more than `h`. With `h = 0` every strict
//! change of direction is a reversal. Flat stretches (equal consecutive values) are not
//! reversals; the first sample of a flat extreme carries its index.
//!
//! Units are those of the history (slip in m, tension in N, …); indices are zero-based sample
//! positions in the history.

use serde::{Deserialize, Serialize};

use super::error::FrettingError;

/// A turning point of a history: its sample index and value.
#[derive(Debug, Clone, Copy, PartialEq, Default, Serialize, Deserialize)]
pub struct Reversal {
    /// Zero-based sample index in the history.
    pub index: usize,
    /// Value of the history at that sample.
    pub value: f64,
}

/// Direction of the history since the last confirmed reversal.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
enum Direction {
    /// Nothing has moved by more than the gate since the first sample.
    Unknown,
    /// Rising towards a peak.
    Up,
    /// Falling towards a valley.
    Down,
}

/// Incremental reversal detector: feed samples one at a time, get confirmed reversals back.
///
/// Small (three words of state), serialisable for checkpoints, shared by the batch and
/// streaming rainflow counters so that both see exactly the same reversals.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct ReversalDetector {
    gate: f64,
    direction: Direction,
    /// The pending extreme: the furthest point reached in the current direction.
    candidate: Option<Reversal>,
}

impl ReversalDetector {
    /// A detector with hysteresis gate `gate` (same unit as the history, ≥ 0).
    pub fn new(gate: f64) -> Result<Self, FrettingError> {
        if !(gate.is_finite() && gate >= 0.0) {
            return Err(FrettingError::InvalidParameter {
                field: "hysteresis_gate",
                value: gate,
                reason: "must be finite and >= 0",
            });
        }
        Ok(Self {
            gate,
            direction: Direction::Unknown,
            candidate: None,
        })
    }

    /// The hysteresis gate.
    pub fn gate(&self) -> f64 {
        self.gate
    }

    /// Feeds one sample; returns the reversal it confirms, if any.
    ///
    /// The first sample is returned at once (it is the starting point). Later reversals are
    /// returned when the history has moved back from them by more than the gate, so they
    /// always lie strictly before `index`.
    #[inline(always)]
    pub fn push(&mut self, index: usize, value: f64) -> Option<Reversal> {
        let point = Reversal { index, value };
        let Some(candidate) = self.candidate else {
            self.candidate = Some(point);
            return Some(point);
        };
        match self.direction {
            Direction::Up => {
                if value > candidate.value {
                    self.candidate = Some(point);
                    None
                } else if candidate.value - value > self.gate {
                    self.direction = Direction::Down;
                    self.candidate = Some(point);
                    Some(candidate)
                } else {
                    None
                }
            }
            Direction::Down => {
                if value < candidate.value {
                    self.candidate = Some(point);
                    None
                } else if value - candidate.value > self.gate {
                    self.direction = Direction::Up;
                    self.candidate = Some(point);
                    Some(candidate)
                } else {
                    None
                }
            }
            Direction::Unknown => {
                // The candidate is still the (already emitted) first sample.
                if value - candidate.value > self.gate {
                    self.direction = Direction::Up;
                    self.candidate = Some(point);
                } else if candidate.value - value > self.gate {
                    self.direction = Direction::Down;
                    self.candidate = Some(point);
                }
                None
            }
        }
    }

    /// The current pending extreme, also before the first move larger than the gate (then it is
    /// the first sample, already returned by [`Self::push`]).
    pub(crate) fn candidate(&self) -> Option<Reversal> {
        self.candidate
    }

    /// The last extreme, which becomes a reversal if the history ends now (`None` if nothing
    /// has moved by more than the gate since the first sample). Does not change the state.
    pub fn pending(&self) -> Option<Reversal> {
        match self.direction {
            Direction::Unknown => None,
            Direction::Up | Direction::Down => self.candidate,
        }
    }
}

/// Extracts the reversals of `history` with hysteresis gate `gate`.
///
/// Errors on a non-finite sample or an invalid gate.
pub fn extract_reversals(history: &[f64], gate: f64) -> Result<Vec<Reversal>, FrettingError> {
    let mut detector = ReversalDetector::new(gate)?;
    let mut out = Vec::new();
    for (index, &value) in history.iter().enumerate() {
        if !value.is_finite() {
            return Err(FrettingError::NonFiniteSample { index, value });
        }
        if let Some(r) = detector.push(index, value) {
            out.push(r);
        }
    }
    out.extend(detector.pending());
    Ok(out)
}

/// Index and value of the first non-finite sample, if any.
pub(crate) fn first_non_finite(history: &[f64]) -> Option<(usize, f64)> {
    // A non-short-circuiting fold vectorises; the position is only searched on failure.
    if history.iter().fold(true, |ok, x| ok & x.is_finite()) {
        return None;
    }
    history
        .iter()
        .position(|x| !x.is_finite())
        .map(|i| (i, history[i]))
}

#[cfg(test)]
mod tests {
    use super::*;

    fn values(r: &[Reversal]) -> Vec<f64> {
        r.iter().map(|r| r.value).collect()
    }

    #[test]
    fn astm_example_is_already_a_sequence_of_reversals() {
        let h = [-2.0, 1.0, -3.0, 5.0, -1.0, 3.0, -4.0, 4.0, -2.0];
        let r = extract_reversals(&h, 0.0).unwrap();
        assert_eq!(values(&r), h.to_vec());
        assert_eq!(
            r.iter().map(|r| r.index).collect::<Vec<_>>(),
            (0..9).collect::<Vec<_>>()
        );
    }

    #[test]
    fn intermediate_and_flat_points_are_not_reversals() {
        let h = [0.0, 0.5, 1.0, 1.0, 0.2, -1.0, -1.0, -1.0, 0.3, 2.0];
        let r = extract_reversals(&h, 0.0).unwrap();
        assert_eq!(values(&r), vec![0.0, 1.0, -1.0, 2.0]);
        // The first sample of a flat extreme carries the index.
        assert_eq!(
            r.iter().map(|r| r.index).collect::<Vec<_>>(),
            vec![0, 2, 5, 9]
        );
    }

    #[test]
    fn gate_removes_ripples_smaller_than_the_gate() {
        let h = [0.0, 3.0, 2.5, 2.9, -2.0, -1.6, -2.1, 1.0];
        let r = extract_reversals(&h, 0.5).unwrap();
        assert_eq!(values(&r), vec![0.0, 3.0, -2.1, 1.0]);
        let r0 = extract_reversals(&h, 0.0).unwrap();
        assert_eq!(r0.len(), h.len());
    }

    #[test]
    fn constant_history_has_only_its_start() {
        let r = extract_reversals(&[1.0; 5], 0.0).unwrap();
        assert_eq!(values(&r), vec![1.0]);
        assert!(extract_reversals(&[], 0.0).unwrap().is_empty());
    }

    #[test]
    fn non_finite_sample_and_negative_gate_are_rejected() {
        let err = extract_reversals(&[0.0, 1.0, f64::NAN], 0.0).unwrap_err();
        assert!(matches!(
            err,
            FrettingError::NonFiniteSample { index: 2, .. }
        ));
        assert!(matches!(
            ReversalDetector::new(-1.0),
            Err(FrettingError::InvalidParameter {
                field: "hysteresis_gate",
                ..
            })
        ));
    }
}
