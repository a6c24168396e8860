//! Run-in detection: where the mean slip of a contact stops drifting (DESIGN §4.5).
//!
//! The strand needs a run-in before its slip pattern stabilises: in the seed's Fig. 22 the
//! mean slip drifts for about the first 100 s of the sea state. The history is cut into
//! consecutive windows of `window_samples`; the reference is the mean over the final
//! `reference_fraction` of the record and the scale its standard deviation σ. The run-in ends at
//! the start of the first window from which every later window mean stays within
//! `tolerance_sigma · σ` of the reference. If that only happens inside the reference part
//! itself, or the reference part drifts by more than the tolerance between its halves, the
//! history never stabilised and this is reported (`end_index = None`), not hidden.
//!
//! Units: those of the history (slip in m); indices are zero-based samples.

use serde::{Deserialize, Serialize};

use super::error::{positive, FrettingError};

/// Parameters of the run-in detection (validated, with `Default`).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct RunInParams {
    /// Samples per window (a few load cycles long).
    pub window_samples: usize,
    /// Fraction of the record, at its end, taken as the stabilised reference (0 < f < 1).
    pub reference_fraction: f64,
    /// Band half-width around the reference mean, in reference standard deviations.
    pub tolerance_sigma: f64,
}

impl Default for RunInParams {
    fn default() -> Self {
        Self {
            window_samples: 500,
            reference_fraction: 0.25,
            tolerance_sigma: 0.1,
        }
    }
}

/// Where the run-in ended.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct RunIn {
    /// First sample after the run-in, `None` if the mean never stabilised.
    pub end_index: Option<usize>,
    /// Reference (stabilised) mean.
    pub reference_mean: f64,
    /// Tolerance band half-width used.
    pub tolerance: f64,
    /// Largest |window mean − reference| after the detected end (or over the reference part).
    pub residual_drift: f64,
}

/// Detects the end of the run-in of `history`.
pub fn detect_run_in(history: &[f64], params: &RunInParams) -> Result<RunIn, FrettingError> {
    positive("window_samples", params.window_samples as f64)?;
    positive("tolerance_sigma", params.tolerance_sigma)?;
    if !(params.reference_fraction > 0.0 && params.reference_fraction < 1.0) {
        return Err(FrettingError::InvalidParameter {
            field: "reference_fraction",
            value: params.reference_fraction,
            reason: "must lie in (0, 1)",
        });
    }
    if let Some((index, value)) = super::reversals::first_non_finite(history) {
        return Err(FrettingError::NonFiniteSample { index, value });
    }
    let w = params.window_samples;
    let windows = history.len() / w;
    // Whole windows only; the reference covers at least two of them.
    let ref_windows = ((windows as f64 * params.reference_fraction).round() as usize).max(2);
    if windows < ref_windows + 1 {
        return Err(FrettingError::InvalidParameter {
            field: "window_samples",
            value: w as f64,
            reason: "the history is too short for the reference and one more window",
        });
    }
    let means: Vec<f64> = (0..windows)
        .map(|k| mean(&history[k * w..(k + 1) * w]))
        .collect();
    let ref_start = windows - ref_windows;
    let reference = &history[ref_start * w..windows * w];
    let reference_mean = mean(reference);
    let sigma = (reference
        .iter()
        .map(|x| (x - reference_mean).powi(2))
        .sum::<f64>()
        / reference.len() as f64)
        .sqrt();
    // floored at the round-off of the window means, so that a constant history (a contact
    // that stays stuck) is stabilised rather than failed by the last bits of its sums
    let tolerance = (params.tolerance_sigma * sigma).max(1e-12 * reference_mean.abs());
    let half = ref_windows / 2;
    let drift_in_reference =
        (mean(&means[ref_start..ref_start + half]) - mean(&means[ref_start + half..windows])).abs();
    // Last window outside the band; the run-in ends after it.
    let last_out = means
        .iter()
        .rposition(|m| (m - reference_mean).abs() > tolerance);
    let first_in = last_out.map_or(0, |k| k + 1);
    let stabilised = drift_in_reference <= tolerance && first_in < ref_start;
    let tail = if stabilised { first_in } else { ref_start };
    let residual_drift = means[tail..]
        .iter()
        .map(|m| (m - reference_mean).abs())
        .fold(0.0, f64::max);
    Ok(RunIn {
        end_index: stabilised.then_some(first_in * w),
        reference_mean,
        tolerance,
        residual_drift,
    })
}

/// Run-in of a set of histories (the slip monitors of a strand): the latest end over them.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct SetRunIn {
    /// First sample after the run-in of every history, `None` if one never stabilised.
    pub end_index: Option<usize>,
    /// Histories examined.
    pub histories: usize,
    /// Index (in the set) of the history whose run-in ends last, or of the first one that
    /// never stabilised.
    pub governing: Option<usize>,
    /// Histories that never stabilised.
    pub unstable: usize,
    /// Largest `residual_drift / tolerance` over the set (≤ 1 when stabilised).
    pub worst_drift_ratio: f64,
}

/// The run-in of every history of `set` ([`detect_run_in`] each): the set is stabilised once
/// every history is, from the latest of their ends. A history that never moves (σ = 0, a
/// contact that stays stuck) is stabilised from its last change.
pub fn detect_set_run_in(set: &[&[f64]], params: &RunInParams) -> Result<SetRunIn, FrettingError> {
    let (mut latest, mut governing, mut unstable, mut worst) = (0, None, 0, 0.0_f64);
    for (k, history) in set.iter().enumerate() {
        let r = detect_run_in(history, params)?;
        if r.tolerance > 0.0 {
            worst = worst.max(r.residual_drift / r.tolerance);
        }
        match r.end_index {
            None => {
                if unstable == 0 {
                    governing = Some(k);
                }
                unstable += 1;
            }
            Some(end) if unstable == 0 && (governing.is_none() || end > latest) => {
                latest = end;
                governing = Some(k);
            }
            Some(_) => {}
        }
    }
    Ok(SetRunIn {
        end_index: (unstable == 0).then_some(latest),
        histories: set.len(),
        governing,
        unstable,
        worst_drift_ratio: worst,
    })
}

fn mean(x: &[f64]) -> f64 {
    x.iter().sum::<f64>() / x.len() as f64
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Slip oscillation around a mean that relaxes exponentially from `offset` to 0.
    fn drifting(n: usize, dt: f64, tau: f64, offset: f64) -> Vec<f64> {
        (0..n)
            .map(|i| {
                let t = i as f64 * dt;
                1e-6 * (std::f64::consts::TAU * t / 12.0).sin() + offset * (-t / tau).exp()
            })
            .collect()
    }

    #[test]
    fn drift_that_dies_out_is_detected_where_it_enters_the_band() {
        // 1000 s at 10 Hz, drift 3 µm with τ = 20 s. The window means leave the band
        // 0.1 σ = 0.1 · 1e-6/√2 once 3e-6 e^(−t/20) < 7.07e-8, i.e. t > 75 s.
        let h = drifting(10_000, 0.1, 20.0, 3e-6);
        let params = RunInParams {
            window_samples: 120,
            ..Default::default()
        };
        let r = detect_run_in(&h, &params).unwrap();
        let end_s = r.end_index.unwrap() as f64 * 0.1;
        assert!(end_s > 60.0 && end_s < 96.0, "{end_s}");
        assert!(r.residual_drift <= r.tolerance);
    }

    #[test]
    fn stationary_history_has_no_run_in_and_endless_drift_never_stabilises() {
        let params = RunInParams {
            window_samples: 120,
            ..Default::default()
        };
        let steady = drifting(10_000, 0.1, 20.0, 0.0);
        assert_eq!(detect_run_in(&steady, &params).unwrap().end_index, Some(0));
        let ramp: Vec<f64> = steady
            .iter()
            .enumerate()
            .map(|(i, x)| x + 1e-9 * i as f64)
            .collect();
        let r = detect_run_in(&ramp, &params).unwrap();
        assert_eq!(r.end_index, None);
        assert!(r.residual_drift > r.tolerance);
    }

    #[test]
    fn a_set_ends_its_run_in_with_its_latest_history_and_never_if_one_never_does() {
        let params = RunInParams {
            window_samples: 120,
            ..Default::default()
        };
        // drifts that die out at different times (τ = 10 s and 20 s) and a stuck contact
        let early = drifting(10_000, 0.1, 10.0, 3e-6);
        let late = drifting(10_000, 0.1, 20.0, 3e-6);
        let stuck = vec![2e-7; 10_000];
        let set = [early.as_slice(), late.as_slice(), stuck.as_slice()];
        let r = detect_set_run_in(&set, &params).unwrap();
        let late_end = detect_run_in(&late, &params).unwrap().end_index;
        let early_end = detect_run_in(&early, &params).unwrap().end_index;
        assert!(early_end < late_end, "{early_end:?} {late_end:?}");
        assert_eq!(r.end_index, late_end);
        assert_eq!(r.governing, Some(1));
        assert_eq!((r.histories, r.unstable), (3, 0));
        assert!(r.worst_drift_ratio <= 1.0);
        // one endless drift: the set never stabilises, and that history is named
        let ramp: Vec<f64> = (0..10_000).map(|i| 1e-9 * i as f64).collect();
        let set = [early.as_slice(), ramp.as_slice(), late.as_slice()];
        let r = detect_set_run_in(&set, &params).unwrap();
        assert_eq!(r.end_index, None);
        assert_eq!((r.governing, r.unstable), (Some(1), 1));
        assert!(r.worst_drift_ratio > 1.0);
    }

    #[test]
    fn too_short_history_is_rejected() {
        let r = detect_run_in(&[0.0; 100], &RunInParams::default());
        assert!(matches!(
            r,
            Err(FrettingError::InvalidParameter {
                field: "window_samples",
                ..
            })
        ));
    }
}
