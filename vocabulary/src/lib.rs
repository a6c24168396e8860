//! Names shared by the solver, which computes them, and the store, which keeps them, so that
//! the database crate does not depend on the solver.
//!
//! A contact class is a layer interface × an angular position around the strand cross-section
//! relative to the bending plane (`docs/damage.md`): with bending about y, a fibre at angle θ
//! from the neutral axis sees the bending strain κ R sin θ, so θ = 0 or π is the neutral axis
//! and θ = ±π/2 the outer arcs.

use serde::{Deserialize, Serialize};

/// Angular position class of a contact around the strand cross-section.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum AngularPosition {
    /// |sin θ| ≤ sin(half band): near the bending neutral axis.
    NeutralAxis,
    /// Between the two bands.
    Between,
    /// |cos θ| ≤ sin(half band): near an extreme fibre of the bent strand.
    OuterArc,
}

impl AngularPosition {
    /// Half width of the neutral-axis and outer-arc bands: 22.5°, so the circle splits into
    /// four 45° bands around the axes and four 45° sectors between them.
    pub const HALF_BAND_RAD: f64 = std::f64::consts::PI / 8.0;

    /// Class of a contact at angle `theta_rad` from the neutral axis (any real angle).
    pub fn of(theta_rad: f64) -> Self {
        let band = Self::HALF_BAND_RAD.sin();
        let (s, c) = theta_rad.sin_cos();
        if s.abs() <= band {
            Self::NeutralAxis
        } else if c.abs() <= band {
            Self::OuterArc
        } else {
            Self::Between
        }
    }

    /// Stable lower-case name, as stored and printed.
    pub fn as_str(self) -> &'static str {
        match self {
            Self::NeutralAxis => "neutral_axis",
            Self::Between => "between",
            Self::OuterArc => "outer_arc",
        }
    }
}

#[cfg(test)]
mod tests {
    use super::AngularPosition;
    use std::f64::consts::PI;

    #[test]
    fn the_bands_split_the_circle_into_eight_45_degree_arcs() {
        let deg = PI / 180.0;
        for (theta, class) in [
            (0.0, AngularPosition::NeutralAxis),
            (22.4 * deg, AngularPosition::NeutralAxis),
            (22.6 * deg, AngularPosition::Between),
            (67.4 * deg, AngularPosition::Between),
            (67.6 * deg, AngularPosition::OuterArc),
            (-90.0 * deg, AngularPosition::OuterArc),
            (180.0 * deg, AngularPosition::NeutralAxis),
            (-135.0 * deg, AngularPosition::Between),
        ] {
            assert_eq!(AngularPosition::of(theta), class, "theta {}", theta / deg);
        }
    }

    #[test]
    fn the_stored_names_are_the_serde_names() {
        for p in [
            AngularPosition::NeutralAxis,
            AngularPosition::Between,
            AngularPosition::OuterArc,
        ] {
            let json = serde_json::to_string(&p).expect("serialises");
            assert_eq!(json, format!("\"{}\"", p.as_str()));
        }
    }
}
