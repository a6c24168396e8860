//! The designed load history of a calibration ([`super`] module docs).
//!
//! In the scaled coordinates `x` (tension) and `y` (curvature) of the range, both in [−1, 1],
//! the design is a set of independent *chains*, each solved by an FE run of its own from the
//! FE initialisation, so that they run side by side on as many threads as are given (the fit
//! sums their samples; no increment spans two chains). Every chain starts at the smallest
//! curvature, where the FE initialisation is cheap. At each of [`DesignParams::tension_levels`]
//! tension levels at the midpoints of equal bins of the tension range, one chain visits:
//! 1. curvature cycles about the range's centre at fixed tension, `y = ±A` for every amplitude
//!    of [`DesignParams::amplitudes`] (largest first, [`DesignParams::cycles`] each): loops of
//!    every size below the largest, as a rainflow-counted sea state has them;
//! 2. tension cycles at fixed curvature, `x = x_j ± A` (clipped to the range) for every
//!    amplitude of [`DesignParams::tension_amplitudes`] (the whole tension range is stroked by
//!    the combined cycles and the corners);
//! 3. combined cycles, tension and curvature in phase and in opposition, for the largest two
//!    amplitudes (a hot spot's tension and curvature move together or against each other);
//! 4. the corners of the range;
//! 5. at a grid of curvatures, small probe cycles in curvature and tension
//!    ([`DesignParams::probe_curvatures`], [`DesignParams::probe_cycles`] each), which most
//!    contacts answer in stick;
//! 6. below the highest level, the same grid of curvatures at the tension midway to the next
//!    level, last curvature first, with small tension cycles there
//!    ([`DesignParams::between_level_cycles`]): the drive has a tension knot there
//!    (`fit::TENSION_KNOTS`), and the stick answer to tension between the levels is not the
//!    levels' answers interpolated.
//!
//! One more chain goes round the corners of the range, then makes the same probes at a
//! near-slack tension ([`design_strain_floor`]), each reached by a short tension stroke down
//! from the strokes' floor ([`stroke_strain_floor`]), below which no other stroke goes. Every
//! straight stretch is sampled at the sub-steps the FE history run will solve
//! (`ceil(max(|Δε|/Δε_max, |Δκ|/Δκ_max))` equal parts), so the calibration sees every solved
//! state and nothing interpolated. Times are one second apart.

use super::{LoadRange, LoadScaling};
use crate::strand::history::{HistoryOptions, LoadSample};

/// Settings of the designed history.
#[derive(Clone, Debug, PartialEq)]
pub struct DesignParams {
    /// Tension levels, at the midpoints of equal bins of the range (≥ 2).
    pub tension_levels: usize,
    /// Cycle amplitudes as fractions of the half range, largest first, each in (0, 1].
    pub amplitudes: Vec<f64>,
    /// Cycles per amplitude (≥ 1).
    pub cycles: usize,
    /// Amplitudes of the tension cycles at fixed curvature, as fractions of the half range,
    /// largest first, each in (0, 1]. The whole tension range is stroked by the corners and
    /// the combined cycles.
    pub tension_amplitudes: Vec<f64>,
    /// Curvatures (scaled, in (−1, 1)) of the probes: at every tension level and each of
    /// these curvatures, small curvature and tension cycles of amplitude
    /// [`DesignParams::probe_amplitude`], which most contacts answer in stick.
    pub probe_curvatures: Vec<f64>,
    /// Amplitude of the probes' cycles, as a fraction of the half range.
    pub probe_amplitude: f64,
    /// Curvature and tension cycles of each probe at the tension levels (≥ 1; the
    /// low-tension probes make [`DesignParams::cycles`]). Most contacts answer a probe in
    /// stick, where a second cycle repeats the first.
    pub probe_cycles: usize,
    /// Tension cycles of the probes between the levels ([`between_levels`]), at every probe
    /// curvature (0: none). They go straight on from one curvature to the next, without
    /// returning to the middle tension first.
    pub between_level_cycles: usize,
}

impl Default for DesignParams {
    fn default() -> Self {
        Self {
            tension_levels: 6,
            amplitudes: vec![1.0, 0.6, 0.35, 0.2, 0.1, 0.05, 0.02],
            cycles: 2,
            tension_amplitudes: vec![0.6, 0.35, 0.2, 0.1, 0.05, 0.02],
            probe_curvatures: vec![-0.75, -0.5, -0.25, 0.25, 0.5, 0.75],
            probe_amplitude: 0.05,
            probe_cycles: 2,
            between_level_cycles: 1,
        }
    }
}

/// Lowest tension of the design's strokes across the range, as a fraction of the range's
/// highest strain.
pub(crate) const STROKE_STRAIN_FRACTION: f64 = 0.1;

/// Tension of the low-tension probes, as a fraction of the range's highest strain.
pub(crate) const LOW_STRAIN_FRACTION: f64 = 0.03;

/// The lowest strain of the design's strokes across the range: the range's lowest, but not
/// below `STROKE_STRAIN_FRACTION` of its highest. A campaign's lowest tension is a near-slack
/// instant of its most severe sea state, where the strand barely presses its contacts: the FE
/// model converges there along a recorded history, in small steps, but not along the design's
/// large straight strokes.
pub(crate) fn stroke_strain_floor(range: &LoadRange) -> f64 {
    range.strain[0].max(STROKE_STRAIN_FRACTION * range.strain[1])
}

/// The lowest strain the designed history visits: the range's lowest, but not below
/// `LOW_STRAIN_FRACTION` of its highest. Between it and the strokes' floor
/// ([`stroke_strain_floor`]) the design has only small probe cycles, reached in short tension
/// strokes from the strokes' floor: at these near-slack tensions the contacts are soft and the
/// slip answers the tension most (a severe sea state's largest slip cycles reach down there).
/// Samples below it are run with the fitted laws continued (quadratic normal forces clipped at
/// zero).
pub fn design_strain_floor(range: &LoadRange) -> f64 {
    range.strain[0].max(LOW_STRAIN_FRACTION * range.strain[1])
}

/// How low in tension a calibration's FE runs go.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum LowestTension {
    /// Down to the near-slack probes at [`design_strain_floor`], and the collective modes
    /// from the lowest of [`super::modes::MODE_POINTS`].
    NearSlack,
    /// Down to the strokes' floor ([`stroke_strain_floor`]) and no lower, the modes' knots
    /// included: the contact-mechanics laws. Their Hertz normal law and Mindlin's initial
    /// stiffness `8 G* c ∝ f_N^(1/3)` leave the near-slack strand almost without stiffness,
    /// and the FE model does not converge there along the design's strokes (the modes'
    /// stroke to 1.5 % of the paper campaign's highest strain stalled at its first sample).
    /// Below the floor the reduced response holds its drive at the lowest fitted knot.
    StrokeFloor,
}

impl LowestTension {
    /// How low the calibration of a model goes: to the strokes' floor under the
    /// Cattaneo–Mindlin law, near slack under the others.
    pub fn of_law(cattaneo_mindlin: bool) -> Self {
        if cattaneo_mindlin {
            Self::StrokeFloor
        } else {
            Self::NearSlack
        }
    }

    /// The lowest strain of the design over `range`.
    pub fn strain(self, range: &LoadRange) -> f64 {
        match self {
            Self::NearSlack => design_strain_floor(range),
            Self::StrokeFloor => stroke_strain_floor(range),
        }
    }

    /// The lowest scaled tension of the modes' knots over `range`.
    pub fn mode_floor(self, range: &LoadRange) -> f64 {
        match self {
            Self::NearSlack => -1.0,
            Self::StrokeFloor => {
                LoadScaling::of(range)
                    .scaled(stroke_strain_floor(range), 0.0)
                    .0
            }
        }
    }
}

/// Scaled tension of level `j` of `levels`: the midpoint of the j-th of `levels` equal bins of
/// [−1, 1].
pub(crate) fn tension_level(j: usize, levels: usize) -> f64 {
    -1.0 + (2 * j + 1) as f64 / levels as f64
}

/// Scaled tension midway between levels `j` and `j + 1` of `levels`.
pub(crate) fn between_levels(j: usize, levels: usize) -> f64 {
    -1.0 + (2 * j + 2) as f64 / levels as f64
}

/// A path's vertices in scaled coordinates: `(x, y, A)`, the stroke to `(x, y)` on a cycle of
/// amplitude `A` (the first vertex is where the FE run starts).
pub(crate) type Vertices = Vec<(f64, f64, f64)>;

/// The chains of the design in scaled coordinates (module docs), with every stroke's tension at
/// least `x_stroke_floor` and the low-tension probes at `x_low` (none if `x_low` is not below
/// `x_stroke_floor`). Chain 0 holds the corners and the low-tension probes, chain `1 + j` the
/// cycles, the corners and the probes of tension level `j`.
pub(crate) fn design_chains(
    params: &DesignParams,
    x_stroke_floor: f64,
    x_low: f64,
) -> Vec<Vertices> {
    let levels = params.tension_levels.max(2);
    let cycles = params.cycles.max(1);
    let probe_cycles = params.probe_cycles.max(1);
    let a = params.probe_amplitude;
    // every chain starts (and so initialises its FE run) at the smallest curvature: the FE
    // initialisation bends the strand at a tenth of the first tension, which at the range's
    // middle curvature costs minutes on the six-layer strand
    let mut corners: Vertices = CORNERS.to_vec();
    for vertex in &mut corners {
        vertex.0 = vertex.0.max(x_stroke_floor);
    }
    // the low-tension probes: down from the strokes' floor at each probe curvature, small
    // curvature and tension cycles there, back up
    if x_low < x_stroke_floor {
        for &yc in &params.probe_curvatures {
            corners.push((x_stroke_floor, yc, 1.0));
            let stroke = x_stroke_floor - x_low;
            corners.push((x_low, yc, stroke));
            // one-sided tension cycles: the probes sit at the bottom of the range
            let top = (x_low + 2.0 * a).min(x_stroke_floor);
            push_probe(&mut corners, (x_low, yc), a, cycles, [top, x_low]);
            corners.push((x_stroke_floor, yc, stroke));
        }
    }
    let mut chains = vec![corners];
    for j in 0..levels {
        // midpoints of `levels` equal bins: the extremes of the range are reached by the
        // largest cycles and the corners, not held (at the smallest tension of a campaign,
        // a near-slack instant, the strand barely carries its contacts and the FE crawls)
        let xj = tension_level(j, levels);
        let mut v = vec![(xj, -1.0, 1.0), (xj, 0.0, 1.0)];
        for &a in &params.amplitudes {
            for _ in 0..cycles {
                v.push((xj, a, a));
                v.push((xj, -a, a));
            }
        }
        v.push((xj, 0.0, 1.0));
        for &a in &params.tension_amplitudes {
            for _ in 0..cycles {
                v.push(((xj + a).min(1.0), 0.0, a));
                v.push(((xj - a).max(-1.0), 0.0, a));
            }
        }
        v.push((xj, 0.0, 1.0));
        for &a in params.amplitudes.iter().take(2) {
            for sign in [1.0, -1.0] {
                for _ in 0..cycles {
                    v.push(((xj + a).min(1.0), sign * a, a));
                    v.push(((xj - a).max(-1.0), -sign * a, a));
                }
            }
        }
        v.push((xj, 0.0, 1.0));
        v.extend(CORNERS);
        // the probes: the stick response away from the centre curvature, where the sea
        // states' hot spots spend their time, after the level's full-range cycles and the
        // corners
        for &yc in &params.probe_curvatures {
            v.push((xj, yc, 1.0));
            push_probe(&mut v, (xj, yc), a, probe_cycles, [xj + a, xj - a]);
        }
        // the tension probes midway to the next level, from the curvature the level's
        // probes end at
        if j + 1 < levels && params.between_level_cycles > 0 {
            let xm = between_levels(j, levels);
            for &yc in params.probe_curvatures.iter().rev() {
                v.push((xm, yc, 1.0));
                for _ in 0..params.between_level_cycles {
                    v.push((xm + a, yc, a));
                    v.push((xm - a, yc, a));
                }
            }
        }
        for vertex in &mut v {
            vertex.0 = vertex.0.max(x_stroke_floor);
        }
        chains.push(v);
    }
    chains
}

/// The corners of the range, from the lowest tension and curvature round.
const CORNERS: [(f64, f64, f64); 5] = [
    (-1.0, -1.0, 1.0),
    (1.0, -1.0, 1.0),
    (1.0, 1.0, 1.0),
    (-1.0, 1.0, 1.0),
    (-1.0, -1.0, 1.0),
];

/// A probe about `(x, yc)`: `cycles` curvature cycles `yc ± a`, then `cycles` tension cycles
/// between the two tensions of `tension`, back to `(x, yc)`.
fn push_probe(v: &mut Vertices, (x, yc): (f64, f64), a: f64, cycles: usize, tension: [f64; 2]) {
    for _ in 0..cycles {
        v.push((x, yc + a, a));
        v.push((x, yc - a, a));
    }
    v.push((x, yc, a));
    for _ in 0..cycles {
        v.push((tension[0], yc, a));
        v.push((tension[1], yc, a));
    }
    v.push((x, yc, a));
}

/// The designed history over `range` as its chains, each sampled at the sub-steps of
/// `options` and run by an FE run of its own.
pub fn design_history(
    range: &LoadRange,
    params: &DesignParams,
    options: &HistoryOptions,
) -> Vec<Vec<LoadSample>> {
    split_weights(design_history_weighted(
        range,
        params,
        options,
        LowestTension::NearSlack,
    ))
    .0
}

/// The samples and the weights of weighted chains, each chain by chain.
pub(crate) fn split_weights(
    weighted: Vec<Vec<(LoadSample, f64)>>,
) -> (Vec<Vec<LoadSample>>, Vec<Vec<f64>>) {
    weighted
        .into_iter()
        .map(|chain| chain.into_iter().unzip())
        .unzip()
}

/// [`design_history`] with the least-squares weight of every sample: 1/A² for a sample on a
/// stroke of a cycle of amplitude A, so that the small cycles, which most contacts of a mild
/// sea state see in stick, weigh in the fit like the large sliding ones relative to their size.
/// Every chain's times are its sample indices, in seconds.
pub(crate) fn design_history_weighted(
    range: &LoadRange,
    params: &DesignParams,
    options: &HistoryOptions,
    lowest: LowestTension,
) -> Vec<Vec<(LoadSample, f64)>> {
    let scaling = LoadScaling::of(range);
    let x_stroke_floor = scaling.scaled(stroke_strain_floor(range), 0.0).0;
    let x_low = scaling.scaled(lowest.strain(range), 0.0).0;
    design_chains(params, x_stroke_floor, x_low)
        .iter()
        .map(|vertices| sampled(&scaling, vertices, options))
        .collect()
}

/// The path through `vertices`, every stroke in the equal sub-steps of `options`, with the
/// weight of its cycle.
fn sampled(
    scaling: &LoadScaling,
    vertices: &[(f64, f64, f64)],
    options: &HistoryOptions,
) -> Vec<(LoadSample, f64)> {
    let mut out: Vec<(LoadSample, f64)> = Vec::new();
    let push =
        |strain: f64, curvature_per_m: f64, weight: f64, out: &mut Vec<(LoadSample, f64)>| {
            if let Some((last, _)) = out.last() {
                if last.strain == strain && last.curvature_per_m == curvature_per_m {
                    return;
                }
            }
            let time_s = out.len() as f64;
            out.push((
                LoadSample {
                    time_s,
                    strain,
                    curvature_per_m,
                },
                weight,
            ));
        };
    let Some(&(x0, y0, _)) = vertices.first() else {
        return out;
    };
    let (e0, k0) = scaling.load(x0, y0);
    push(e0, k0, 1.0, &mut out);
    let mut from = (e0, k0);
    for &(x, y, a) in &vertices[1..] {
        let to = scaling.load(x, y);
        let (de, dk) = ((to.0 - from.0).abs(), (to.1 - from.1).abs());
        let n = ((de / options.max_substep_strain)
            .max(dk / options.max_substep_curvature_per_m)
            .ceil() as usize)
            .max(1);
        let weight = 1.0 / (a * a);
        for k in 1..=n {
            let f = k as f64 / n as f64;
            let (e, c) = if k == n {
                to
            } else {
                (from.0 + f * (to.0 - from.0), from.1 + f * (to.1 - from.1))
            };
            push(e, c, weight, &mut out);
        }
        from = to;
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn below_the_strokes_floor_the_design_has_only_its_low_tension_probes() {
        // a range from the slack strand: the strokes stop at a tenth of the highest strain, the
        // low-tension probes go down to 3 % of it, at the probe curvatures only
        let range = LoadRange {
            strain: [0.0, 1.2e-3],
            curvature_per_m: [1e-3, 1.8e-2],
        };
        let params = DesignParams::default();
        let h: Vec<LoadSample> = design_history(&range, &params, &HistoryOptions::default())
            .into_iter()
            .flatten()
            .collect();
        let lowest = h.iter().map(|s| s.strain).fold(f64::INFINITY, f64::min);
        assert!(
            (lowest - LOW_STRAIN_FRACTION * 1.2e-3).abs() < 1e-15,
            "{lowest}"
        );
        let stroke_floor = stroke_strain_floor(&range);
        assert_eq!(stroke_floor, STROKE_STRAIN_FRACTION * 1.2e-3);
        let scaling = LoadScaling::of(&range);
        let below: Vec<f64> = h
            .iter()
            .filter(|s| s.strain < stroke_floor * (1.0 - 1e-12))
            .map(|s| scaling.scaled(s.strain, s.curvature_per_m).1)
            .collect();
        assert!(
            below.len() >= 6 * 6,
            "{} samples below the floor",
            below.len()
        );
        for y in below {
            assert!(
                params
                    .probe_curvatures
                    .iter()
                    .any(|yc| (y - yc).abs() <= params.probe_amplitude + 1e-12),
                "y = {y} below the strokes' floor is not at a probe"
            );
        }
    }

    #[test]
    fn under_the_contact_mechanics_laws_nothing_goes_below_the_strokes_floor() {
        // the same range from slack: the design and the modes' knots stop at a tenth of the
        // highest strain, where the design under the other laws still has every chain
        let range = LoadRange {
            strain: [0.0, 1.2e-3],
            curvature_per_m: [1e-3, 1.8e-2],
        };
        let params = DesignParams::default();
        let options = HistoryOptions::default();
        let floor = stroke_strain_floor(&range);
        let samples = |lowest| -> Vec<LoadSample> {
            design_history_weighted(&range, &params, &options, lowest)
                .into_iter()
                .flatten()
                .map(|(s, _)| s)
                .collect()
        };
        let (near_slack, stroke_floor) = (
            samples(LowestTension::NearSlack),
            samples(LowestTension::StrokeFloor),
        );
        let lowest = stroke_floor
            .iter()
            .map(|s| s.strain)
            .fold(f64::INFINITY, f64::min);
        assert!((lowest - floor).abs() < 1e-15, "{lowest} against {floor}");
        // what differs is the low-tension probes of the first chain, and only those
        let above = |h: &[LoadSample]| -> Vec<(f64, f64)> {
            h.iter()
                .filter(|s| s.strain >= floor * (1.0 - 1e-12))
                .map(|s| (s.strain, s.curvature_per_m))
                .collect()
        };
        assert!(stroke_floor.len() < near_slack.len());
        let (a, b) = (above(&near_slack), above(&stroke_floor));
        let first_chain_probes = a.len() - b.len();
        assert!(
            first_chain_probes > 0 && first_chain_probes < a.len() / 10,
            "{first_chain_probes}"
        );
        // the knots of the modes: the two below the floor merge into one at it
        let x_floor = LowestTension::StrokeFloor.mode_floor(&range);
        assert!((x_floor - (-0.8)).abs() < 1e-12, "{x_floor}");
        let knots = super::super::modes::mode_points(x_floor);
        assert_eq!(knots.len(), super::super::modes::MODE_POINTS.len() - 1);
        assert_eq!(knots[0], (x_floor, 0.0));
        assert_eq!(&knots[1..], &super::super::modes::MODE_POINTS[2..]);
        assert_eq!(
            super::super::modes::mode_points(LowestTension::NearSlack.mode_floor(&range)),
            super::super::modes::MODE_POINTS.to_vec()
        );
    }

    #[test]
    fn between_the_levels_the_design_probes_the_tension_at_every_probe_curvature() {
        let params = DesignParams::default();
        let levels = params.tension_levels;
        let a = params.probe_amplitude;
        let chains = design_chains(&params, -1.0, -1.0);
        for (j, chain) in chains[1..].iter().enumerate() {
            let at = |x: f64, y: f64| {
                chain
                    .iter()
                    .filter(|v| (v.0 - x).abs() < 1e-12 && (v.1 - y).abs() < 1e-12)
                    .count()
            };
            let xm = between_levels(j, levels);
            for &yc in &params.probe_curvatures {
                let (up, down) = (at(xm + a, yc), at(xm - a, yc));
                if j + 1 < levels {
                    assert_eq!((up, down), (1, 1), "level {j}, y = {yc}");
                    // tension cycles only: no curvature cycle about the midpoint
                    assert_eq!(at(xm, yc + a) + at(xm, yc - a), 0, "level {j}, y = {yc}");
                } else {
                    assert_eq!(up + down, 0, "the highest level has nothing above it");
                }
            }
            // a midpoint lies halfway between its levels
            if j + 1 < levels {
                let mid = 0.5 * (tension_level(j, levels) + tension_level(j + 1, levels));
                assert!((xm - mid).abs() < 1e-15);
            }
        }
        // none without cycles
        let none = DesignParams {
            between_level_cycles: 0,
            ..DesignParams::default()
        };
        let fewer: usize = design_chains(&none, -1.0, -1.0).iter().map(Vec::len).sum();
        let all: usize = chains.iter().map(Vec::len).sum();
        assert_eq!(
            all - fewer,
            (levels - 1) * params.probe_curvatures.len() * 3
        );
    }

    #[test]
    fn the_design_covers_the_range_and_stays_inside_it() {
        let range = LoadRange {
            strain: [2e-4, 1.2e-3],
            curvature_per_m: [1e-3, 1.8e-2],
        };
        let opts = HistoryOptions::default();
        let params = DesignParams::default();
        let chains = design_history(&range, &params, &opts);
        // the corners and low-tension probes, then one chain per tension level
        assert_eq!(chains.len(), 1 + params.tension_levels);
        let all: Vec<LoadSample> = chains.iter().flatten().copied().collect();
        let got = LoadRange::of(&all).expect("samples");
        assert!(design_strain_floor(&range) == range.strain[0]);
        for (a, b) in got
            .strain
            .iter()
            .zip(&range.strain)
            .chain(got.curvature_per_m.iter().zip(&range.curvature_per_m))
        {
            assert!(
                (a - b).abs() <= 1e-12 * b.abs().max(1e-3),
                "{got:?} vs {range:?}"
            );
        }
        for chain in &chains {
            // every chain starts at the smallest curvature, where the FE initialisation is cheap
            let k0 = range.curvature_per_m[0];
            assert!(
                (chain[0].curvature_per_m - k0).abs() <= 1e-12 * k0,
                "{:?}",
                chain[0]
            );
            assert_eq!(chain[0].time_s, 0.0);
            for w in chain.windows(2) {
                assert!(w[1].time_s > w[0].time_s);
                assert!(
                    (w[1].strain - w[0].strain).abs() <= opts.max_substep_strain * (1.0 + 1e-12)
                );
                assert!(
                    (w[1].curvature_per_m - w[0].curvature_per_m).abs()
                        <= opts.max_substep_curvature_per_m * (1.0 + 1e-12)
                );
            }
        }
    }
}
