//! Run-in detection: where the mean slip of a contact stops drifting (`docs/damage.md`).
//!
//! The strand needs a run-in before its slip pattern stabilises: in the paper's Fig. 22 the
//! mean slip drifts for about the first 100 s of the sea state. The history is cut into
//! consecutive windows of `window_samples`; the reference is the mean over the final
//! `reference_fraction` of the record and the scale its standard deviation σ. The run-in ends at
//! the start of the first window from which every later window mean stays within
//! `tolerance_sigma · σ` of the reference. If that only happens inside the reference part
//! itself, or the reference part drifts by more than the tolerance between its halves, the
//! history never stabilised and this is reported (`end_index = None`), not hidden.
//!
//! Against the load ([`detect_run_in_against_load`]): a contact that sticks, or slides in
//! stabilised loops, has a slip that follows the load, so its window means wander with the
//! load's own (the floater's slow drift, wave groups) and the plain criterion above would call
//! it never stabilised. The part of the slip that follows the load is therefore removed first:
//! s(t) − Σⱼ bⱼ Lⱼ(t), with the bⱼ the least-squares slopes of s on the loads Lⱼ (axial strain,
//! curvature) over the reference part. What is left is the slip the load does not explain,
//! whose drift is the run-in; its band is `tolerance_sigma` standard deviations of the slip
//! itself over the reference part.
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
    detect_run_in_against_load(history, &[], params)
}

/// Detects the end of the run-in of `history` once the part of it that follows `loads` (each
/// as long as `history`) is removed (module docs). With no loads this is [`detect_run_in`].
pub fn detect_run_in_against_load(
    history: &[f64],
    loads: &[&[f64]],
    params: &RunInParams,
) -> Result<RunIn, FrettingError> {
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
    for load in loads {
        if load.len() != history.len() {
            return Err(FrettingError::InvalidParameter {
                field: "loads",
                value: load.len() as f64,
                reason: "a load series must have a sample per sample of the history",
            });
        }
        if let Some((index, value)) = super::reversals::first_non_finite(load) {
            return Err(FrettingError::NonFiniteSample { index, value });
        }
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
    let ref_start = windows - ref_windows;
    let reference = ref_start * w..windows * w;
    let sigma = std_dev(&history[reference.clone()]);
    let slopes = load_slopes(history, loads, reference.clone());
    let series: Vec<f64> = (0..history.len())
        .map(|i| history[i] - slopes.iter().zip(loads).map(|(b, l)| b * l[i]).sum::<f64>())
        .collect();
    let means: Vec<f64> = (0..windows)
        .map(|k| mean(&series[k * w..(k + 1) * w]))
        .collect();
    let reference_mean = mean(&series[reference]);
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

/// Least-squares slopes of `history` on `loads` over the samples `part` (centred normal
/// equations). A load that does not vary over `part` (beyond the round-off of its mean) gets
/// slope 0; if the loads are collinear there, every slope is 0 (the plain criterion).
fn load_slopes(history: &[f64], loads: &[&[f64]], part: std::ops::Range<usize>) -> Vec<f64> {
    let k = loads.len();
    if k == 0 {
        return Vec::new();
    }
    let y = &history[part.clone()];
    let my = mean(y);
    let centred: Vec<(f64, f64)> = loads
        .iter()
        .map(|l| {
            let x = &l[part.clone()];
            (mean(x), std_dev(x))
        })
        .collect();
    // scaled loads (x − mean)/σ; a constant load is left out (σ at round-off of its mean)
    let used: Vec<usize> = (0..k)
        .filter(|&j| centred[j].1 > 1e-10 * centred[j].0.abs() && centred[j].1 > 0.0)
        .collect();
    let n = used.len();
    let mut gram = nalgebra::DMatrix::<f64>::zeros(n, n);
    let mut rhs = nalgebra::DVector::<f64>::zeros(n);
    let mut z = vec![0.0; n];
    for i in part.clone() {
        for (zj, &j) in z.iter_mut().zip(&used) {
            *zj = (loads[j][i] - centred[j].0) / centred[j].1;
        }
        for a in 0..n {
            rhs[a] += z[a] * (history[i] - my);
            for b in 0..n {
                gram[(a, b)] += z[a] * z[b];
            }
        }
    }
    let mut slopes = vec![0.0; k];
    if let Some(solution) = gram.cholesky().map(|c| c.solve(&rhs)) {
        if solution.iter().all(|v| v.is_finite()) {
            for (a, &j) in used.iter().enumerate() {
                slopes[j] = solution[a] / centred[j].1;
            }
        }
    }
    slopes
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

/// The run-in of every history of `set` against `loads` ([`detect_run_in_against_load`]
/// each; no loads: [`detect_run_in`]): the set is stabilised once every history is, from the
/// latest of their ends. A history that never moves (σ = 0, a contact that stays stuck) is
/// stabilised from its last change.
pub fn detect_set_run_in(
    set: &[&[f64]],
    loads: &[&[f64]],
    params: &RunInParams,
) -> Result<SetRunIn, FrettingError> {
    let (mut latest, mut governing, mut unstable, mut worst) = (0, None, 0, 0.0_f64);
    for (k, history) in set.iter().enumerate() {
        let r = detect_run_in_against_load(history, loads, params)?;
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

/// Population standard deviation.
fn std_dev(x: &[f64]) -> f64 {
    let m = mean(x);
    (x.iter().map(|v| (v - m).powi(2)).sum::<f64>() / x.len() as f64).sqrt()
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::f64::consts::TAU;

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
        let r = detect_set_run_in(&set, &[], &params).unwrap();
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
        let r = detect_set_run_in(&set, &[], &params).unwrap();
        assert_eq!(r.end_index, None);
        assert_eq!((r.governing, r.unstable), (Some(1), 1));
        assert!(r.worst_drift_ratio > 1.0);
    }

    /// A load whose mean wanders (a 400 s swing, as a floater's slow drift) under 12 s waves,
    /// and a slip that follows it, plus a drift that falls linearly to 0 at `stop_s`.
    fn wandering(stop_s: f64, drift: f64) -> (Vec<f64>, Vec<f64>, Vec<f64>) {
        let (n, dt) = (10_000, 0.1);
        let time = |i: usize| i as f64 * dt;
        let strain: Vec<f64> = (0..n)
            .map(|i| {
                let t = time(i);
                1e-3 + 2e-4 * (TAU * t / 400.0).sin() + 1e-4 * (TAU * t / 12.0).sin()
            })
            .collect();
        let curvature: Vec<f64> = (0..n).map(|i| 3e-3 * (TAU * time(i) / 9.0).cos()).collect();
        let slip = (0..n)
            .map(|i| {
                let t = time(i);
                0.01 * strain[i] - 2e-4 * curvature[i] + drift * (1.0 - t / stop_s).max(0.0)
            })
            .collect();
        (slip, strain, curvature)
    }

    #[test]
    fn a_slip_that_follows_a_wandering_load_stabilises_where_its_own_drift_stops() {
        let params = RunInParams {
            window_samples: 500,
            reference_fraction: 0.25,
            tolerance_sigma: 0.25,
        };
        // a slip that only follows the load: the plain criterion calls it never stabilised
        // (its window means swing with the load's), against the load it has no run-in
        let (slip, strain, curvature) = wandering(1.0, 0.0);
        let loads = [strain.as_slice(), curvature.as_slice()];
        assert_eq!(detect_run_in(&slip, &params).unwrap().end_index, None);
        let r = detect_run_in_against_load(&slip, &loads, &params).unwrap();
        assert_eq!(r.end_index, Some(0));
        assert!(r.residual_drift < 1e-6 * r.tolerance, "{r:?}");

        // plus a drift of 10 bands that stops at 300 s: it leaves the band at
        // t = 300 (1 − 1/10) = 270 s, so the run-in ends with the first window (50 s) that
        // starts after the last one reaching into the drift above the band
        let (plain, _, _) = wandering(1.0, 0.0);
        let sigma = std_dev(&plain[7_500..]);
        let drift = 10.0 * 0.25 * sigma;
        let (slip, _, _) = wandering(300.0, drift);
        let r = detect_run_in_against_load(&slip, &loads, &params).unwrap();
        let end_s = r.end_index.unwrap() as f64 * 0.1;
        assert!((250.0..=300.0).contains(&end_s), "{end_s}");
        // the same slip without the load's part removed never stabilises
        assert_eq!(detect_run_in(&slip, &params).unwrap().end_index, None);

        // an endless drift still never stabilises, whatever the load explains
        let ramp: Vec<f64> = slip
            .iter()
            .enumerate()
            .map(|(i, x)| x + drift * i as f64 / 2_000.0)
            .collect();
        let r = detect_run_in_against_load(&ramp, &loads, &params).unwrap();
        assert_eq!(r.end_index, None);
        assert!(r.residual_drift > r.tolerance);
    }

    #[test]
    fn constant_or_mismatched_loads() {
        let params = RunInParams {
            window_samples: 120,
            ..Default::default()
        };
        // a constant load explains nothing: the plain result
        let h = drifting(10_000, 0.1, 20.0, 3e-6);
        let flat = vec![1e-3; 10_000];
        assert_eq!(
            detect_run_in_against_load(&h, &[flat.as_slice()], &params).unwrap(),
            detect_run_in(&h, &params).unwrap()
        );
        assert!(matches!(
            detect_run_in_against_load(&h, &[&flat[..10]], &params),
            Err(FrettingError::InvalidParameter { field: "loads", .. })
        ));
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
