//! Results of a global run and their summary: hot-spot series T(t), κ(t), fairlead tensions,
//! envelopes per line and node, floater motion series, static line shapes, work counts and
//! timings. Times of the series are measured from the end of the discarded transient.
//!
//! Summary statistics: extremes, range max − min and standard deviation (population, 1/N) of
//! the sampled series.

use serde::Serialize;

use super::error::GlobalError;
use super::resolution::WaveCutOff;
use crate::mooring::hotspot::Envelope;

/// T(t) and κ(t) at one hot spot.
#[derive(Debug, Clone, PartialEq)]
pub struct HotSpotResult {
    /// Line id.
    pub line: u32,
    /// Arc length from the fairlead (m).
    pub arc_length_m: f64,
    /// Tension samples (N).
    pub tension_n: Vec<f64>,
    /// Curvature samples (1/m).
    pub curvature_per_m: Vec<f64>,
}

/// Everything recorded for one line.
#[derive(Debug, Clone, PartialEq)]
pub struct LineResult {
    /// Line id.
    pub id: u32,
    /// Fairlead tension |F| at the sample times (N).
    pub fairlead_tension_n: Vec<f64>,
    /// Extremes over time at every node (after the transient).
    pub envelope: Envelope,
    /// Arc length of each node (m).
    pub static_arc_length_m: Vec<f64>,
    /// Static node positions (m).
    pub static_position_m: Vec<[f64; 3]>,
    /// Static node tension (N).
    pub static_tension_n: Vec<f64>,
    /// Static node curvature (1/m).
    pub static_curvature_per_m: Vec<f64>,
    /// Static force of the line on the floater (N).
    pub static_fairlead_force_n: [f64; 3],
}

/// Floater motion at the sample times.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct FloaterSeries {
    /// Times (s, from the end of the transient).
    pub time_s: Vec<f64>,
    /// Surge, sway, heave (m), roll, pitch, yaw (rad) of the reference point.
    pub motion: Vec<[f64; 6]>,
}

/// Work counts and timings.
#[derive(Debug, Clone, Copy, PartialEq, Default, Serialize)]
pub struct RunStats {
    /// Coupled statics Newton iterations.
    pub statics_iterations: usize,
    /// Time steps.
    pub steps: usize,
    /// Coupling passes (line solves) over all steps, failed attempts included.
    pub coupling_iterations: usize,
    /// Largest coupling pass count of a step.
    pub max_coupling_iterations: usize,
    /// Line Newton iterations (linear solves) over all lines and steps.
    pub line_iterations: usize,
    /// Factorisations of the line iteration matrices (modified Newton reuses them).
    pub line_factorizations: usize,
    /// Line residual assemblies (with or without the iteration matrix).
    pub line_assemblies: usize,
    /// Line steps that had to be cut.
    pub cut_steps: usize,
    /// Line Newton attempts given up for lack of progress (each followed by a step cut).
    pub line_stalled_attempts: usize,
    /// Line steps written as the mirror image of another line's instead of being solved
    /// (one per coupling pass and mirrored line).
    pub mirrored_line_steps: usize,
    /// Coupled steps that failed and were retried with half the step.
    pub cut_coupled_steps: usize,
    /// Deepest coupled step cut reached (the step was Δt / 2^deepest_cut).
    pub deepest_cut: usize,
    /// Evaluations of the floater residual (rigid-body loads).
    pub floater_evaluations: usize,
    /// Cached kinematics queries answered by direct summation.
    pub cache_misses: usize,
    /// Floater kinematics queries answered by direct summation because they fell outside the
    /// floater's table.
    pub floater_table_misses: usize,
    /// Whether the floater's table was left unused because it could not resolve the sea's
    /// shortest waves (the floater then sampled the sea by direct summation).
    pub floater_table_unresolved: bool,
    /// Wall time of the kinematics precomputation (s).
    pub precompute_s: f64,
    /// Wall time of the coupled statics (s), set by the caller.
    pub statics_s: f64,
    /// Wall time of the time loop (s).
    pub dynamics_s: f64,
    /// Of which: line steps (s).
    pub lines_s: f64,
    /// Of which: floater loads, Jacobians and updates (s).
    pub floater_s: f64,
}

/// The full result of a global run.
#[derive(Debug, Clone, PartialEq)]
pub struct GlobalResult {
    /// Case name.
    pub name: String,
    /// Sample times (s, from the end of the transient).
    pub time_s: Vec<f64>,
    /// Hot spots in the order of the case.
    pub hot_spots: Vec<HotSpotResult>,
    /// Lines in the order of the layout.
    pub lines: Vec<LineResult>,
    /// Floater motion.
    pub floater: FloaterSeries,
    /// Static position of the floater reference point (m).
    pub static_body_position_m: [f64; 3],
    /// Static roll, pitch, yaw (rad).
    pub static_body_angles_rad: [f64; 3],
    /// Hub wind speed (m/s).
    pub wind_speed_m_s: f64,
    /// Mean rotor thrust (N).
    pub thrust_n: f64,
    /// The frequency cut-off of the sea and what it kept.
    pub wave_cut_off: WaveCutOff,
    /// Work counts and timings.
    pub stats: RunStats,
}

/// Statistics of a series.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct SeriesSummary {
    /// Smallest value.
    pub min: f64,
    /// Largest value.
    pub max: f64,
    /// max − min.
    pub range: f64,
    /// Mean.
    pub mean: f64,
    /// Standard deviation (1/N).
    pub std: f64,
}

impl SeriesSummary {
    /// Statistics of `x` (zeros for an empty series).
    pub fn of(x: &[f64]) -> Self {
        if x.is_empty() {
            return Self {
                min: 0.0,
                max: 0.0,
                range: 0.0,
                mean: 0.0,
                std: 0.0,
            };
        }
        let n = x.len() as f64;
        let min = x.iter().copied().fold(f64::INFINITY, f64::min);
        let max = x.iter().copied().fold(f64::NEG_INFINITY, f64::max);
        let mean = x.iter().sum::<f64>() / n;
        let var = x.iter().map(|v| (v - mean) * (v - mean)).sum::<f64>() / n;
        Self {
            min,
            max,
            range: max - min,
            mean,
            std: var.sqrt(),
        }
    }
}

/// Summary of one hot spot.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct HotSpotSummary {
    /// Line id.
    pub line: u32,
    /// Arc length (m).
    pub arc_length_m: f64,
    /// Tension (N).
    pub tension_n: SeriesSummary,
    /// Curvature (1/m).
    pub curvature_per_m: SeriesSummary,
}

/// Summary of one line.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct LineSummary {
    /// Line id.
    pub line: u32,
    /// Static fairlead tension (N).
    pub static_fairlead_tension_n: f64,
    /// Fairlead tension (N).
    pub fairlead_tension_n: SeriesSummary,
    /// Largest tension anywhere on the line (N).
    pub max_tension_n: f64,
    /// Largest |κ| anywhere on the line (1/m) and its arc length (m).
    pub max_curvature_per_m: f64,
    /// Arc length of the largest |κ| (m).
    pub max_curvature_arc_length_m: f64,
    /// Largest |κ| range over the nodes (1/m) and its arc length (m).
    pub max_curvature_range_per_m: f64,
    /// Arc length of the largest |κ| range (m).
    pub max_curvature_range_arc_length_m: f64,
}

/// Summary of a run, as written to `summary.json`.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct GlobalSummary {
    /// Case name.
    pub name: String,
    /// Recorded duration (s).
    pub duration_s: f64,
    /// Samples per series.
    pub samples: usize,
    /// Hub wind speed (m/s).
    pub wind_speed_m_s: f64,
    /// Mean rotor thrust (N).
    pub thrust_n: f64,
    /// Static floater position (m) and angles (rad).
    pub static_body_position_m: [f64; 3],
    /// Static roll, pitch, yaw (rad).
    pub static_body_angles_rad: [f64; 3],
    /// The frequency cut-off of the sea the stage chose and what it kept.
    pub wave_cut_off: WaveCutOff,
    /// Hot spots.
    pub hot_spots: Vec<HotSpotSummary>,
    /// Lines.
    pub lines: Vec<LineSummary>,
    /// Floater surge, sway, heave (m), roll, pitch, yaw (rad).
    pub floater_motion: Vec<(String, SeriesSummary)>,
    /// Work counts and timings.
    pub stats: RunStats,
}

fn argmax(x: &[f64]) -> usize {
    let mut best = 0;
    for (i, v) in x.iter().enumerate() {
        if *v > x[best] {
            best = i;
        }
    }
    best
}

impl GlobalResult {
    /// Error if any output value is non-finite.
    pub fn check_finite(&self) -> Result<(), GlobalError> {
        let t_end = self.time_s.last().copied().unwrap_or(0.0);
        let series_ok = self.hot_spots.iter().all(|h| {
            h.tension_n
                .iter()
                .chain(&h.curvature_per_m)
                .all(|v| v.is_finite())
        }) && self
            .lines
            .iter()
            .all(|l| l.fairlead_tension_n.iter().all(|v| v.is_finite()))
            && self.floater.motion.iter().flatten().all(|v| v.is_finite());
        if series_ok {
            Ok(())
        } else {
            Err(GlobalError::NonFinite {
                what: "output series",
                time_s: t_end,
            })
        }
    }

    /// Summary statistics.
    pub fn summary(&self) -> GlobalSummary {
        let names = [
            "surge_m",
            "sway_m",
            "heave_m",
            "roll_rad",
            "pitch_rad",
            "yaw_rad",
        ];
        let floater_motion = (0..6)
            .map(|j| {
                let x: Vec<f64> = self.floater.motion.iter().map(|m| m[j]).collect();
                (names[j].to_string(), SeriesSummary::of(&x))
            })
            .collect();
        GlobalSummary {
            name: self.name.clone(),
            duration_s: self.time_s.last().copied().unwrap_or(0.0),
            samples: self.time_s.len(),
            wind_speed_m_s: self.wind_speed_m_s,
            thrust_n: self.thrust_n,
            static_body_position_m: self.static_body_position_m,
            static_body_angles_rad: self.static_body_angles_rad,
            wave_cut_off: self.wave_cut_off,
            hot_spots: self
                .hot_spots
                .iter()
                .map(|h| HotSpotSummary {
                    line: h.line,
                    arc_length_m: h.arc_length_m,
                    tension_n: SeriesSummary::of(&h.tension_n),
                    curvature_per_m: SeriesSummary::of(&h.curvature_per_m),
                })
                .collect(),
            lines: self
                .lines
                .iter()
                .map(|l| {
                    let e = &l.envelope;
                    let kmax = argmax(&e.curvature_max_per_m);
                    let range = e.curvature_range_per_m();
                    let rmax = argmax(&range);
                    let f = l.static_fairlead_force_n;
                    LineSummary {
                        line: l.id,
                        static_fairlead_tension_n: (f[0] * f[0] + f[1] * f[1] + f[2] * f[2]).sqrt(),
                        fairlead_tension_n: SeriesSummary::of(&l.fairlead_tension_n),
                        max_tension_n: e
                            .tension_max_n
                            .iter()
                            .copied()
                            .fold(f64::NEG_INFINITY, f64::max),
                        max_curvature_per_m: e
                            .curvature_max_per_m
                            .get(kmax)
                            .copied()
                            .unwrap_or(0.0),
                        max_curvature_arc_length_m: e
                            .arc_length_m
                            .get(kmax)
                            .copied()
                            .unwrap_or(0.0),
                        max_curvature_range_per_m: range.get(rmax).copied().unwrap_or(0.0),
                        max_curvature_range_arc_length_m: e
                            .arc_length_m
                            .get(rmax)
                            .copied()
                            .unwrap_or(0.0),
                    }
                })
                .collect(),
            floater_motion,
            stats: self.stats,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn series_summary_of_a_known_series() {
        let s = SeriesSummary::of(&[1.0, 3.0, 2.0, 6.0]);
        assert_eq!((s.min, s.max, s.range, s.mean), (1.0, 6.0, 5.0, 3.0));
        assert!((s.std - (14.0f64 / 4.0).sqrt()).abs() < 1e-15);
    }
}
