//! Validation of a load history and its reduction to the points the solver has to visit.
//!
//! The strand response is quasi-static and rate-independent, so only the path in the (ε, κ)
//! plane matters. The history is reduced to
//! 1. the turning points of each channel (ε and κ), found with the hysteresis gate of
//!    [`crate::fretting::reversals`] set to `tolerance` × the channel's range, plus the first and
//!    last samples;
//! 2. between two kept points, the sample farthest from the straight chord (in coordinates
//!    scaled by each channel's range) as long as that distance exceeds `tolerance`
//!    (Ramer-Douglas-Peucker), so that the straight segments the solver follows stay within
//!    `tolerance` of the recorded path.
//!
//! Every original sample then gets a position s ∈ [0, 1] along its segment (projection on the
//! chord, made non-decreasing), through which solver results are interpolated back onto the
//! original time axis.

use super::{HistoryError, LoadSample};
use crate::fretting::ReversalDetector;

/// Distances from a chord below this (fraction of the channel ranges) are round-off: a
/// straight stretch is one segment even with a zero tolerance.
const CHORD_FLOOR: f64 = 1e-9;

/// Scale of each channel: its range over the history (1 for a constant channel), at least
/// `floor` (strain, curvature in 1/m; 0: no floor).
fn channel_scales(samples: &[LoadSample], floor: [f64; 2]) -> [f64; 2] {
    let range = |f: &dyn Fn(&LoadSample) -> f64| {
        let (lo, hi) = samples
            .iter()
            .map(f)
            .fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), x| {
                (lo.min(x), hi.max(x))
            });
        let r = hi - lo;
        if r > 0.0 && r.is_finite() {
            r
        } else {
            1.0
        }
    };
    let [e, k] = [range(&|s| s.strain), range(&|s| s.curvature_per_m)];
    let at_least = |r: f64, f: f64| {
        if f > 0.0 && f.is_finite() {
            r.max(f)
        } else {
            r
        }
    };
    [at_least(e, floor[0]), at_least(k, floor[1])]
}

fn scaled(s: &LoadSample, scales: &[f64; 2]) -> [f64; 2] {
    [s.strain / scales[0], s.curvature_per_m / scales[1]]
}

/// Distance of `p` from the segment a-b.
fn distance_to_segment(p: [f64; 2], a: [f64; 2], b: [f64; 2]) -> f64 {
    let (dx, dy) = (b[0] - a[0], b[1] - a[1]);
    let len2 = dx * dx + dy * dy;
    let t = if len2 > 0.0 {
        (((p[0] - a[0]) * dx + (p[1] - a[1]) * dy) / len2).clamp(0.0, 1.0)
    } else {
        0.0
    };
    let (ex, ey) = (p[0] - a[0] - t * dx, p[1] - a[1] - t * dy);
    (ex * ex + ey * ey).sqrt()
}

/// Indices of the samples the solver visits, increasing, first and last included.
/// `tolerance` is a fraction of each channel's range (≥ 0; 0 keeps every sample that is off
/// the chords by more than 1e-9 of the ranges).
pub fn reduce_history(samples: &[LoadSample], tolerance: f64) -> Result<Vec<usize>, HistoryError> {
    reduce_history_on_scale(samples, tolerance, [0.0; 2])
}

/// [`reduce_history`] with the tolerance a fraction of each channel's range or of
/// `scale_floor` (strain, curvature in 1/m), whichever is larger: on the strand's own scale,
/// a history of small load changes is not resolved more finely than a large one.
pub fn reduce_history_on_scale(
    samples: &[LoadSample],
    tolerance: f64,
    scale_floor: [f64; 2],
) -> Result<Vec<usize>, HistoryError> {
    if samples.is_empty() {
        return Ok(Vec::new());
    }
    let scales = channel_scales(samples, scale_floor);
    let last = samples.len() - 1;
    let mut keep = vec![false; samples.len()];
    keep[0] = true;
    keep[last] = true;
    for (channel, scale) in scales.iter().enumerate() {
        let values: Vec<f64> = samples
            .iter()
            .map(|s| {
                if channel == 0 {
                    s.strain
                } else {
                    s.curvature_per_m
                }
            })
            .collect();
        let mut detector =
            ReversalDetector::new(tolerance * scale).map_err(|e| HistoryError::InvalidOption {
                field: "turning_point_tolerance",
                value: tolerance,
                reason: e.to_string(),
            })?;
        // confirmed reversals only: an extreme the history never left by more than the gate
        // is not a turning point (the last sample is kept anyway)
        for (i, v) in values.iter().enumerate() {
            if let Some(r) = detector.push(i, *v) {
                keep[r.index] = true;
            }
        }
    }
    let points: Vec<[f64; 2]> = samples.iter().map(|s| scaled(s, &scales)).collect();
    let corners: Vec<usize> = (0..samples.len()).filter(|&i| keep[i]).collect();
    // Ramer-Douglas-Peucker between consecutive corners, with an explicit stack
    let mut stack: Vec<(usize, usize)> = corners.windows(2).map(|w| (w[0], w[1])).collect();
    while let Some((a, b)) = stack.pop() {
        if b <= a + 1 {
            continue;
        }
        let (mut far, mut dmax) = (a, 0.0);
        for (i, p) in points.iter().enumerate().take(b).skip(a + 1) {
            let d = distance_to_segment(*p, points[a], points[b]);
            if d > dmax {
                dmax = d;
                far = i;
            }
        }
        if dmax > tolerance.max(CHORD_FLOOR) && far != a {
            keep[far] = true;
            stack.push((a, far));
            stack.push((far, b));
        }
    }
    Ok((0..samples.len()).filter(|&i| keep[i]).collect())
}

/// Position s ∈ [0, 1] of every sample of `samples[a..=b]` along the chord from `a` to `b`
/// (scaled coordinates as in [`reduce_history`]), non-decreasing, 0 at `a` and 1 at `b`.
pub(crate) fn chord_positions(
    samples: &[LoadSample],
    a: usize,
    b: usize,
    scales: &[f64; 2],
) -> Vec<f64> {
    let pa = scaled(&samples[a], scales);
    let pb = scaled(&samples[b], scales);
    let (dx, dy) = (pb[0] - pa[0], pb[1] - pa[1]);
    let len2 = dx * dx + dy * dy;
    let mut out = Vec::with_capacity(b - a + 1);
    let mut running: f64 = 0.0;
    for s in &samples[a..=b] {
        let p = scaled(s, scales);
        let t = if len2 > 0.0 {
            (((p[0] - pa[0]) * dx + (p[1] - pa[1]) * dy) / len2).clamp(0.0, 1.0)
        } else {
            1.0
        };
        running = running.max(t);
        out.push(running);
    }
    out[0] = 0.0;
    if let Some(l) = out.last_mut() {
        *l = 1.0;
    }
    out
}

/// The loads at which an FE history run with this reduction solves every sample: each sample
/// moved onto the straight segment between the kept points around it, at its chord position
/// ([`reduce_history_on_scale`], [`chord_positions`]), the time unchanged. With a zero
/// tolerance and no scale floor the samples are returned as they are (the FE run then keeps
/// every sample off a chord by more than round-off).
pub fn samples_on_path(
    samples: &[LoadSample],
    tolerance: f64,
    scale_floor: [f64; 2],
) -> Result<Vec<LoadSample>, HistoryError> {
    if tolerance == 0.0 && scale_floor == [0.0; 2] {
        return Ok(samples.to_vec());
    }
    let kept = reduce_history_on_scale(samples, tolerance, scale_floor)?;
    let scales = history_scales(samples);
    let mut path = samples.to_vec();
    for w in kept.windows(2) {
        let (a, b) = (w[0], w[1]);
        let (pa, pb) = (samples[a], samples[b]);
        for (i, t) in (a..=b).zip(chord_positions(samples, a, b, &scales)) {
            path[i].strain = pa.strain + t * (pb.strain - pa.strain);
            path[i].curvature_per_m =
                pa.curvature_per_m + t * (pb.curvature_per_m - pa.curvature_per_m);
        }
    }
    Ok(path)
}

/// The channel scales used by [`reduce_history`] and [`chord_positions`].
pub(crate) fn history_scales(samples: &[LoadSample]) -> [f64; 2] {
    channel_scales(samples, [0.0; 2])
}

#[cfg(test)]
mod tests {
    use super::*;

    fn history(values: &[(f64, f64)]) -> Vec<LoadSample> {
        values
            .iter()
            .enumerate()
            .map(|(i, &(e, k))| LoadSample {
                time_s: i as f64,
                strain: e,
                curvature_per_m: k,
            })
            .collect()
    }

    #[test]
    fn monotone_straight_history_reduces_to_its_ends() {
        let h = history(
            &(0..20)
                .map(|i| (1e-3 + 1e-5 * i as f64, 1e-3 * i as f64))
                .collect::<Vec<_>>(),
        );
        assert_eq!(reduce_history(&h, 0.0).unwrap(), vec![0, 19]);
        let s = chord_positions(&h, 0, 19, &history_scales(&h));
        assert!((s[7] - 7.0 / 19.0).abs() < 1e-12);
    }

    #[test]
    fn turning_points_of_either_channel_are_kept() {
        // strain peaks at 3, curvature valley at 6
        let h = history(&[
            (1.0, 0.0),
            (2.0, -1.0),
            (3.0, -2.0),
            (4.0, -3.0),
            (3.0, -4.0),
            (2.0, -5.0),
            (1.0, -6.0),
            (0.5, -3.0),
            (0.0, 0.0),
        ]);
        let kept = reduce_history(&h, 0.01).unwrap();
        assert_eq!(kept, vec![0, 3, 6, 8]);
    }

    #[test]
    fn a_bend_in_the_path_without_a_turning_point_is_kept_above_the_tolerance() {
        // both channels increase, but curvature first, then strain: a corner at sample 5
        let mut v: Vec<(f64, f64)> = (0..=5).map(|i| (0.0, i as f64)).collect();
        v.extend((1..=5).map(|i| (i as f64, 5.0)));
        let h = history(&v);
        assert_eq!(reduce_history(&h, 0.05).unwrap(), vec![0, 5, 10]);
        // a ripple smaller than the tolerance is ignored
        let mut r = h.clone();
        r[7].curvature_per_m += 0.01;
        assert_eq!(reduce_history(&r, 0.05).unwrap(), vec![0, 5, 10]);
    }

    #[test]
    fn a_scale_floor_coarsens_only_histories_smaller_than_it() {
        // a bump of 2 % of the curvature range off a straight ramp of both channels (1.4 % of
        // the scaled diagonal): kept at a tolerance of 1 % of the ranges, dropped when the
        // curvature's scale is ten times its range, and the floor changes nothing when it lies
        // below the range
        let h: Vec<LoadSample> = (0..=20)
            .map(|i| LoadSample {
                time_s: i as f64,
                strain: 1e-3 * i as f64 / 20.0,
                curvature_per_m: 1e-3 * i as f64 / 20.0 + if i == 10 { 2e-5 } else { 0.0 },
            })
            .collect();
        let fine = reduce_history(&h, 0.01).unwrap();
        assert!(fine.contains(&10), "{fine:?}");
        assert_eq!(
            reduce_history_on_scale(&h, 0.01, [0.0, 1e-4]).unwrap(),
            fine
        );
        assert_eq!(
            reduce_history_on_scale(&h, 0.01, [0.0, 1e-2]).unwrap(),
            vec![0, 20]
        );
    }

    #[test]
    fn samples_on_the_path_lie_on_the_chords_between_the_kept_points() {
        // a wiggle of 0.1 % of the curvature range rides on two ramps: below a tolerance of
        // 1 %, the samples move onto the straight chords between the turning points, the
        // kept points stay where they are, the times too; a zero tolerance moves nothing
        let h: Vec<LoadSample> = (0..=40)
            .map(|i| {
                let ramp = if i <= 20 { i } else { 40 - i } as f64 / 20.0;
                LoadSample {
                    time_s: 0.5 * i as f64,
                    strain: 1e-3 + 2e-4 * ramp,
                    curvature_per_m: 1e-2 * ramp + if i % 2 == 1 { 1e-5 } else { 0.0 },
                }
            })
            .collect();
        let kept = reduce_history(&h, 0.01).unwrap();
        assert_eq!(kept, vec![0, 20, 40]);
        let path = samples_on_path(&h, 0.01, [0.0; 2]).unwrap();
        for (i, (p, s)) in path.iter().zip(&h).enumerate() {
            assert_eq!(p.time_s, s.time_s);
            if kept.contains(&i) {
                assert_eq!(p, s);
            }
            // on the chord: the curvature is the strain's linear function on both ramps
            let on_chord = 1e-2 * (p.strain - 1e-3) / 2e-4;
            assert!(
                (p.curvature_per_m - on_chord).abs() < 1e-12,
                "sample {i}: {p:?}"
            );
            assert!((p.curvature_per_m - s.curvature_per_m).abs() <= 1e-5 + 1e-12);
        }
        assert_eq!(samples_on_path(&h, 0.0, [0.0; 2]).unwrap(), h);
    }
}
