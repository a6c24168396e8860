//! The highest wave frequency a global run can represent, chosen by the stage from the sea state,
//! the time step and the floater's kinematics table, and recorded with the results.
//!
//! Two limits apply to a wave component of angular frequency ω and wavenumber k
//! (ω² = g k tanh kd):
//!
//! - the time step h: the loads are sampled once per step and the response integrated with
//!   generalised-α; a component needs at least `steps_per_period` steps per period,
//!   ω ≤ ω_h = 2π / (n h) (16 steps: 3.9 rad/s for h = 0.1 s);
//! - the floater's kinematics table ([`crate::waves::table`]): quintic Lagrange interpolation
//!   with node spacing Δ errs by c₆ (k Δ)⁶ of a component's amplitude (c₆ = 4.9e-3), and the
//!   table's top nodes continue the depth profiles e^{k s} analytically up to 3 Δ above the
//!   still water level. Both are bounded only for k Δ ≤ `table_wavenumber_spacing` (κ = 1:
//!   error ≤ 4.9e-3 of the amplitude at the cut-off, continuation factor ≤ e³), i.e.
//!   k ≤ k_t = κ/Δ (0.4 rad/m for Δ = 2.5 m, ω_t = 1.98 rad/s, λ = 15.7 m). Beyond it the
//!   interpolation error grows as (kΔ)⁶: the table returns accelerations wrong by orders of
//!   magnitude near the surface, which is what made the short-period cells of the paper
//!   diagram diverge.
//!
//! The run keeps the components with ω ≤ ω_c = min(ω_h, ω_t) (ω_t only when the floater
//! samples the sea through a table) and drops the others without redistributing their energy
//! ([`crate::waves::RealisationParams::cut_off_rad_s`]); the kept components are exactly those
//! of the uncut realisation. The dropped waves are shorter than 16 m: on the floater, strip
//! theory with the long-wave inertia coefficient overstates their diffraction force by more than
//! 4× already at the cut-off for the 12 m columns of the OC4 semi-submersible (MacCamy–Fuchs
//! C_M(ka)/2 = 0.21 at ka = 2.4), and they decay by e^{−k z} ≤ 4e-3 above the fairleads 14 m
//! down. The choice, the band and the fraction of the spectrum's variance kept are recorded in
//! [`WaveCutOff`], which the run summary carries.

use serde::Serialize;

use crate::waves::dispersion::GRAVITY;
use crate::waves::{IrregularSea, TableParams};

/// Resolution rules the stage applies to the sea state.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct WaveResolution {
    /// Least time steps per wave period n.
    pub steps_per_period: f64,
    /// Largest k Δ of a component sampled through the floater's kinematics table (κ).
    pub table_wavenumber_spacing: f64,
}

impl Default for WaveResolution {
    fn default() -> Self {
        Self {
            steps_per_period: 16.0,
            table_wavenumber_spacing: 1.0,
        }
    }
}

/// Which limit set the cut-off.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum CutOffLimit {
    /// The whole band of the spectrum is below both limits: nothing was cut.
    None,
    /// The time step.
    TimeStep,
    /// The node spacing of the floater's kinematics table.
    FloaterTable,
}

/// The frequency cut-off of a run and what it kept.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct WaveCutOff {
    /// Highest frequency kept ω_c (rad/s).
    pub cut_off_rad_s: f64,
    /// Which limit set ω_c (`none` when the band lies below it).
    pub limited_by: CutOffLimit,
    /// Time-step limit ω_h (rad/s).
    pub time_step_limit_rad_s: f64,
    /// Table limit ω_t (rad/s), when the floater samples the sea through a table.
    pub table_limit_rad_s: Option<f64>,
    /// Upper edge of the spectrum's band before the cut (rad/s).
    pub band_upper_rad_s: f64,
    /// Highest frequency of a kept component (rad/s; 0 when none is kept).
    pub highest_component_rad_s: f64,
    /// Components kept.
    pub components: usize,
    /// Fraction of the spectrum's variance Hs²/16 kept.
    pub kept_m0_fraction: f64,
    /// Significant wave height of the kept components, 4 √(kept m0) (m).
    pub kept_hs_m: f64,
}

impl WaveResolution {
    /// Time-step limit ω_h = 2π / (n h) (rad/s).
    pub(crate) fn time_step_limit_rad_s(&self, time_step_s: f64) -> f64 {
        2.0 * std::f64::consts::PI / (self.steps_per_period * time_step_s)
    }

    /// Table limit ω_t (rad/s) for a table of resolution `table` in water of depth `depth_m`:
    /// the frequency of k_t = κ / max(Δx, Δσ).
    pub(crate) fn table_limit_rad_s(&self, table: &TableParams, depth_m: f64) -> f64 {
        let spacing = table.spacing_along_m.max(table.spacing_stretched_m);
        let k = self.table_wavenumber_spacing / spacing;
        (GRAVITY * k * (k * depth_m).tanh()).sqrt()
    }

    /// Cut-off ω_c for a run with step `time_step_s` whose floater samples the sea through
    /// `table` (if any), in water of depth `depth_m`, and the limit that set it.
    pub fn cut_off_rad_s(
        &self,
        time_step_s: f64,
        table: Option<&TableParams>,
        depth_m: f64,
    ) -> (f64, CutOffLimit, Option<f64>) {
        let step = self.time_step_limit_rad_s(time_step_s);
        let tab = table.map(|t| self.table_limit_rad_s(t, depth_m));
        match tab {
            Some(t) if t < step => (t, CutOffLimit::FloaterTable, tab),
            _ => (step, CutOffLimit::TimeStep, tab),
        }
    }
}

impl WaveCutOff {
    /// Record of the realisation `sea` made with the cut-off `cut_off_rad_s` set by `limit`.
    pub fn of(
        sea: &IrregularSea,
        cut_off_rad_s: f64,
        limit: CutOffLimit,
        time_step_limit_rad_s: f64,
        table_limit_rad_s: Option<f64>,
    ) -> Self {
        let band_upper = sea.band_rad_s().1;
        let comps = sea.field().components();
        let m0 = sea.hs_m().powi(2) / 16.0 * sea.kept_m0_fraction();
        Self {
            cut_off_rad_s,
            limited_by: if band_upper <= cut_off_rad_s {
                CutOffLimit::None
            } else {
                limit
            },
            time_step_limit_rad_s,
            table_limit_rad_s,
            band_upper_rad_s: band_upper,
            highest_component_rad_s: comps.last().map_or(0.0, |c| c.omega_rad_s),
            components: comps.len(),
            kept_m0_fraction: sea.kept_m0_fraction(),
            kept_hs_m: 4.0 * m0.sqrt(),
        }
    }
}

impl std::fmt::Display for WaveCutOff {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        let by = match self.limited_by {
            CutOffLimit::None => "none",
            CutOffLimit::TimeStep => "step",
            CutOffLimit::FloaterTable => "table",
        };
        write!(
            f,
            "cut {:.2} rad/s ({by}), {} comps, m0 {:.3}",
            self.cut_off_rad_s, self.components, self.kept_m0_fraction
        )
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::waves::{Jonswap, PeakEnhancement, RealisationParams};

    #[test]
    fn the_paper_table_and_step_give_the_documented_limits() {
        let r = WaveResolution::default();
        let (w, limit, tab) = r.cut_off_rad_s(0.1, Some(&TableParams::default()), 100.0);
        assert_eq!(limit, CutOffLimit::FloaterTable);
        assert_eq!(tab, Some(w));
        // k = 0.4 rad/m in 100 m of water (deep): ω = √(g k) = 1.981 rad/s.
        assert!((w - (GRAVITY * 0.4).sqrt()).abs() < 1e-6, "{w}");
        assert!((r.time_step_limit_rad_s(0.1) - 3.927).abs() < 1e-3);
        // Without a table only the step limits.
        let (w, limit, tab) = r.cut_off_rad_s(0.1, None, 100.0);
        assert_eq!((limit, tab), (CutOffLimit::TimeStep, None));
        assert!((w - 3.927).abs() < 1e-3);
    }

    #[test]
    fn the_record_says_what_was_kept() {
        let realise = |tp: f64, cut: f64| {
            let s = Jonswap::new(1.0, tp, PeakEnhancement::Given(1.3)).unwrap();
            let p = RealisationParams {
                duration_s: 200.0,
                seed: 4,
                cut_off_rad_s: Some(cut),
                ..Default::default()
            };
            IrregularSea::new(&s, &p).unwrap()
        };
        // A long-period sea lies below the cut-off: nothing cut.
        let long = realise(16.5, 1.98);
        let rec = WaveCutOff::of(&long, 1.98, CutOffLimit::FloaterTable, 3.9, Some(1.98));
        assert_eq!(rec.limited_by, CutOffLimit::None);
        assert_eq!(rec.kept_m0_fraction, 1.0);
        assert!((rec.kept_hs_m - 1.0).abs() < 1e-12);
        // A short-period one loses its high-frequency part, which is not redistributed.
        let short = realise(4.0, 1.98);
        let rec = WaveCutOff::of(&short, 1.98, CutOffLimit::FloaterTable, 3.9, Some(1.98));
        assert_eq!(rec.limited_by, CutOffLimit::FloaterTable);
        assert!(rec.highest_component_rad_s <= 1.98);
        assert!(rec.kept_m0_fraction > 0.0 && rec.kept_m0_fraction < 0.9);
        assert!((rec.kept_hs_m - rec.kept_m0_fraction.sqrt()).abs() < 1e-12);
        let m0: f64 = short.realised_m0();
        assert!(m0 < 0.9 / 16.0, "{m0}");
    }
}
