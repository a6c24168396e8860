//! An irregular (ε, κ) load history for the strand studies: five incommensurate components per
//! channel around the wave periods of a sea state, tension and curvature out of phase.

use moorfret_solver::strand::history::LoadSample;

/// Samples every `dt_s` over `duration_s`: ε = `mean_strain` + `strain_amplitude` e(t),
/// κ = `curvature_amplitude` k(t), with e and k sums of unit sines of decreasing weight
/// (|e| ≲ 2.3, |k| ≲ 3.5).
pub fn irregular_history(
    duration_s: f64,
    dt_s: f64,
    mean_strain: f64,
    strain_amplitude: f64,
    curvature_amplitude: f64,
) -> Vec<LoadSample> {
    let comps = [
        (0.061, 0.3),
        (0.083, 1.1),
        (0.097, 2.0),
        (0.113, 0.7),
        (0.131, 2.9),
    ];
    let n = (duration_s / dt_s).round() as usize;
    (0..=n)
        .map(|i| {
            let t = dt_s * i as f64;
            let (mut e, mut k) = (0.0, 0.0);
            for (j, &(f, ph)) in comps.iter().enumerate() {
                let w = 2.0 * std::f64::consts::PI * f;
                e += (w * t + ph).sin() / (1.0 + j as f64);
                k += (w * t + 1.3 * ph + 0.8).sin() / (1.0 + 0.5 * j as f64);
            }
            LoadSample {
                time_s: t,
                strain: mean_strain + strain_amplitude * e,
                curvature_per_m: curvature_amplitude * k,
            }
        })
        .collect()
}
