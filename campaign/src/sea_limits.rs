//! The sea states the global stage can carry, checked for every non-zero cell of a scatter
//! diagram before anything is stored.
//!
//! A cell breaks the wave model's assumptions when
//!
//! - its waves are steeper than DNV-RP-C205 §3.5.5.4 allows for a sea state (S_p = 2π Hs /
//!   (g Tp²) above 1/15 for Tp ≤ 8 s, 1/25 for Tp ≥ 15 s, linear between): linear (Airy)
//!   waves of that steepness break;
//! - Hs exceeds [`MAX_HS_OVER_DEPTH`] = 0.6 of the water depth: depth-induced breaking.
//!   McCowan's limit H/d = 0.78 bounds a single (solitary) wave; the largest waves of a sea
//!   state are about twice its Hs, and in the surf zone the saturated sea keeps
//!   H_rms ≤ 0.42 d (Thornton & Guza 1983, J. Geophys. Res. 88(C10), 5925-5938), i.e.
//!   Hs = √2 H_rms ≤ 0.59 d: a sea state of Hs above 0.6 d has broken before it reaches the
//!   site;
//! - the global stage's frequency cut-off (`moorfret_solver::global::resolution`: the time
//!   step and the floater's kinematics table) keeps less than `simulation.min_wave_energy_kept`
//!   (0.5 by default) of the JONSWAP spectrum's variance m0: the loads of the rest of the sea
//!   are never computed, and a cell wholly above the cut-off would run in calm water.
//!
//! Such cells are refused, or left out of the plan with `scatter.cells_outside_model =
//! "leave_out"` (named at launch, with their occurrence, which is then neither planned nor
//! covered). A planned cell whose cut-off keeps less than [`FLAG_ENERGY_KEPT`] = 90 % of m0
//! (its kept waves carry less than √0.9 = 95 % of its Hs) is flagged: named at launch and
//! marked wherever its energy kept is shown (the `wave_energy_kept` of its stored sea state).
//! The waves dropped are shorter than 16 m (ω above 1.98 rad/s through the floater's table)
//! and load the moorings little, so the refusal threshold is lower than the flag: between the
//! two, the computed loads are those of the sea's longer waves, and the user is told how much
//! of the sea that is. The hot-spot series must also resolve the waves: the output and load
//! intervals take at least [`MIN_SAMPLES_PER_PEAK_PERIOD`] samples per peak period of every
//! planned cell.

use moorfret_solver::global::case::FloaterSource;
use moorfret_solver::global::WaveResolution;
use moorfret_solver::waves::{Jonswap, TableParams};

use crate::payload::CampaignInputs;

/// g (m/s²), as the wave model uses it.
const GRAVITY: f64 = 9.81;

/// Largest Hs over water depth: depth-induced breaking of a sea state (Thornton & Guza 1983,
/// H_rms ≤ 0.42 d, Hs ≈ √2 H_rms; McCowan's 0.78 bounds single waves, not Hs).
pub const MAX_HS_OVER_DEPTH: f64 = 0.6;
/// Default least fraction of a cell's spectral variance below the cut-off.
pub const DEFAULT_MIN_ENERGY_KEPT: f64 = 0.5;
/// A planned cell whose cut-off keeps less of m0 than this is flagged.
pub const FLAG_ENERGY_KEPT: f64 = 0.9;
/// Least samples of the hot-spot series per peak period of a planned cell.
pub const MIN_SAMPLES_PER_PEAK_PERIOD: f64 = 10.0;

/// Limiting steepness S_p = 2π Hs / (g Tp²) of DNV-RP-C205 §3.5.5.4 at peak period `tp_s`.
pub fn steepness_limit(tp_s: f64) -> f64 {
    let (steep, gentle) = (1.0 / 15.0, 1.0 / 25.0);
    if tp_s <= 8.0 {
        steep
    } else if tp_s >= 15.0 {
        gentle
    } else {
        steep + (gentle - steep) * (tp_s - 8.0) / 7.0
    }
}

/// What the wave model makes of one sea state.
#[derive(Debug, Clone, PartialEq)]
pub struct CellLimits {
    /// Significant wave height (m).
    pub hs_m: f64,
    /// Peak period (s).
    pub tp_s: f64,
    /// Fraction of the spectrum's variance at or below the run's cut-off.
    pub energy_kept: f64,
    /// The run's cut-off (rad/s).
    pub cut_off_rad_s: f64,
    /// Steepness S_p = 2π Hs / (g Tp²).
    pub steepness: f64,
    /// Hs over the water depth.
    pub hs_over_depth: f64,
    /// Why the model cannot carry the sea state (empty when it can).
    pub faults: Vec<String>,
    /// What the model carries only in part, for a sea state planned all the same (empty when
    /// nothing): a cut-off that keeps less than [`FLAG_ENERGY_KEPT`] of the energy.
    pub flags: Vec<String>,
}

impl CellLimits {
    /// Significant wave height of the waves the run keeps, Hs √(energy kept) (m).
    pub fn kept_hs_m(&self) -> f64 {
        self.hs_m * self.energy_kept.sqrt()
    }
}

/// Checks the sea state (`hs_m`, `tp_s`) of `inputs`' campaign against the wave model's
/// assumptions; an `Err` is a sea state that is not a valid case at all.
pub fn check(inputs: &CampaignInputs, hs_m: f64, tp_s: f64) -> Result<CellLimits, String> {
    let case = inputs.case_for(hs_m, tp_s, 1);
    case.validate().map_err(|e| e.to_string())?;
    let depth = case.site.water_depth_m;
    let table = TableParams::default();
    let rigid = matches!(case.floater, FloaterSource::RigidBody { .. });
    let (cut_off, _, _) = WaveResolution::default().cut_off_rad_s(
        case.timing.time_step_s,
        rigid.then_some(&table),
        depth,
    );
    let peak = case.peak_enhancement().map_err(|e| e.to_string())?;
    let spectrum = Jonswap::new(hs_m, tp_s, peak).map_err(|e| e.to_string())?;
    let energy_kept = kept_fraction(&spectrum, cut_off);
    let steepness = 2.0 * std::f64::consts::PI * hs_m / (GRAVITY * tp_s * tp_s);
    let hs_over_depth = hs_m / depth;
    let min_kept = inputs
        .spec
        .simulation
        .min_wave_energy_kept
        .unwrap_or(DEFAULT_MIN_ENERGY_KEPT);
    let mut faults = Vec::new();
    if steepness > steepness_limit(tp_s) {
        faults.push(format!(
            "steepness 2π Hs/(g Tp²) = {steepness:.4} above DNV-RP-C205's limit {:.4} \
             (the waves break)",
            steepness_limit(tp_s)
        ));
    }
    if hs_over_depth > MAX_HS_OVER_DEPTH {
        faults.push(format!(
            "Hs is {hs_over_depth:.2} of the water depth {depth} m, above the depth-induced \
             breaking limit {MAX_HS_OVER_DEPTH} of a sea state (Thornton & Guza)"
        ));
    }
    if energy_kept < min_kept {
        faults.push(format!(
            "the wave cut-off {cut_off:.2} rad/s keeps {:.1} % of the spectrum's energy, less \
             than simulation.min_wave_energy_kept {:.1} %",
            100.0 * energy_kept,
            100.0 * min_kept
        ));
    }
    let mut flags = Vec::new();
    if energy_kept >= min_kept && energy_kept < FLAG_ENERGY_KEPT {
        flags.push(format!(
            "the wave cut-off {cut_off:.2} rad/s keeps {:.1} % of the spectrum's energy, less \
             than {:.0} %: its loads are those of waves of Hs {:.2} m instead of {} m",
            100.0 * energy_kept,
            100.0 * FLAG_ENERGY_KEPT,
            hs_m * energy_kept.sqrt(),
            hs_m
        ));
    }
    Ok(CellLimits {
        hs_m,
        tp_s,
        energy_kept,
        cut_off_rad_s: cut_off,
        steepness,
        hs_over_depth,
        faults,
        flags,
    })
}

/// ∫₀^ω_c S dω / m0, by composite Simpson on steps of ωp/200 (at most 30 ωp; the ω⁻⁵ tail
/// beyond holds less than 1e-6 of m0).
pub fn kept_fraction(spectrum: &Jonswap, cut_off_rad_s: f64) -> f64 {
    let wp = spectrum.peak_omega_rad_s();
    let top = cut_off_rad_s.min(30.0 * wp);
    if top <= 0.0 {
        return 0.0;
    }
    let n = 2 * ((top / (wp / 200.0)).ceil() as usize / 2 + 1);
    let h = top / n as f64;
    let mut sum = spectrum.formula_density(0.0) + spectrum.formula_density(top);
    for i in 1..n {
        let w = if i % 2 == 1 { 4.0 } else { 2.0 };
        sum += w * spectrum.formula_density(i as f64 * h);
    }
    let kept = sum * h / 3.0 / spectrum.formula_m0();
    if cut_off_rad_s >= 30.0 * wp {
        1.0
    } else {
        kept.clamp(0.0, 1.0)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use moorfret_solver::waves::PeakEnhancement;

    #[test]
    fn the_kept_fraction_is_the_spectrum_s_cumulative_law() {
        // γ = 1 is the Pierson-Moskowitz spectrum, whose cumulative law is exact:
        // F(ω) = exp(-5/4 (ωp/ω)⁴)
        let pm = |tp: f64| Jonswap::new(1.0, tp, PeakEnhancement::Given(1.0)).unwrap();
        for tp in [0.5, 3.0, 4.0, 11.0, 16.5] {
            let wp = 2.0 * std::f64::consts::PI / tp;
            let exact = (-1.25 * (wp / 1.98_f64).powi(4)).exp();
            let got = kept_fraction(&pm(tp), 1.98);
            assert!((got - exact).abs() < 1e-6, "Tp {tp}: {got} against {exact}");
        }
        // the paper's γ = 1.3 at Tp 3 s keeps about a fifth
        let k3 = kept_fraction(
            &Jonswap::new(1.0, 3.0, PeakEnhancement::Given(1.3)).unwrap(),
            1.98,
        );
        assert!((0.15..0.25).contains(&k3), "{k3}");
    }

    #[test]
    fn the_dnv_steepness_limit_runs_from_1_15_to_1_25() {
        assert_eq!(steepness_limit(5.0), 1.0 / 15.0);
        assert_eq!(steepness_limit(20.0), 1.0 / 25.0);
        assert!((steepness_limit(11.5) - 0.5 * (1.0 / 15.0 + 1.0 / 25.0)).abs() < 1e-12);
    }
}
