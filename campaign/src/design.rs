//! The design check's rule: the utilisation of a damage figure and the verdict it gives.
//!
//! Fatigue limit state of a mooring line (DNV-OS-E301, Position mooring, Ch.2 Sec.2, fatigue
//! limit state): the characteristic fatigue damage accumulated over the design life, d_C, times
//! the design fatigue factor γ_F must not exceed 1,
//!
//! ```text
//! u = γ_F · d_C = γ_F · D_year · T_design ≤ 1.
//! ```
//!
//! γ_F defaults to 5, the standard's factor for a line whose adjacent line accumulates at most
//! 0.8 of its damage (the standard raises it linearly to 8 when the two damages are equal; the
//! campaign's `design_fatigue_factor` sets another value, which is what to do for the adjacent
//! line rule, for an inspected line or for another standard). The standard's text was not at hand
//! when this was written: check the factor against the edition a project is designed to.
//!
//! A verdict needs the whole year: a figure whose sea states cover less of it can only fail
//! (damage only grows as sea states are added), never pass.

use serde::Serialize;

/// Default design fatigue factor γ_F (DNV-OS-E301 Ch.2 Sec.2, a line whose adjacent line
/// accumulates at most 0.8 of its damage).
pub const DEFAULT_DESIGN_FATIGUE_FACTOR: f64 = 5.0;

/// Least share of the year a damage figure must cover to pass.
pub const YEAR_COVERED_TO_PASS: f64 = 0.999;

/// Utilisation u = γ_F · D_year · T_design of an annual damage.
pub fn utilisation(annual_damage: f64, design_life_years: f64, design_fatigue_factor: f64) -> f64 {
    design_fatigue_factor * annual_damage * design_life_years
}

/// What a utilisation says about the design.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
#[serde(rename_all = "UPPERCASE")]
pub enum Verdict {
    /// u ≤ 1 over the whole year.
    Pass,
    /// u > 1 (already on the part of the year covered).
    Fail,
    /// u ≤ 1 on a part of the year only: sea states failed, were skipped or are not in the
    /// climate.
    Incomplete,
}

impl Verdict {
    /// The verdict of utilisation `u` on a figure covering `year_covered` (fraction) of the
    /// year.
    pub fn of(u: f64, year_covered: f64) -> Verdict {
        if u > 1.0 {
            Verdict::Fail
        } else if year_covered < YEAR_COVERED_TO_PASS {
            Verdict::Incomplete
        } else {
            Verdict::Pass
        }
    }

    /// The worse of two verdicts: fail, then incomplete, then pass.
    pub fn worse(self, other: Verdict) -> Verdict {
        use Verdict::*;
        match (self, other) {
            (Fail, _) | (_, Fail) => Fail,
            (Incomplete, _) | (_, Incomplete) => Incomplete,
            _ => Pass,
        }
    }

    /// Upper-case text for tables and the report.
    pub fn as_str(self) -> &'static str {
        match self {
            Verdict::Pass => "PASS",
            Verdict::Fail => "FAIL",
            Verdict::Incomplete => "INCOMPLETE",
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn utilisation_is_the_factored_damage_over_the_design_life() {
        // 1e-3 per year over 25 years with γ_F = 5: 0.125
        assert!((utilisation(1e-3, 25.0, 5.0) - 0.125).abs() < 1e-15);
        // a life of exactly γ_F · T_design years is utilisation 1
        assert!((utilisation(1.0 / 125.0, 25.0, 5.0) - 1.0).abs() < 1e-15);
    }

    #[test]
    fn a_verdict_passes_only_on_the_whole_year() {
        assert_eq!(Verdict::of(0.5, 1.0), Verdict::Pass);
        assert_eq!(Verdict::of(0.5, 0.435), Verdict::Incomplete);
        assert_eq!(Verdict::of(1.5, 0.435), Verdict::Fail);
        assert_eq!(Verdict::of(1.0, 1.0), Verdict::Pass);
        assert_eq!(
            Verdict::Pass.worse(Verdict::Incomplete),
            Verdict::Incomplete
        );
        assert_eq!(Verdict::Incomplete.worse(Verdict::Fail), Verdict::Fail);
    }
}
