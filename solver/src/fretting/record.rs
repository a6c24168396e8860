//! What the strand stage hands to the fretting statistics: one record per inter-wire contact,
//! and the contact classes the damage inputs are reported in (`docs/damage.md`).
//!
//! A contact class is a layer interface × an angular position around the strand cross-section
//! relative to the bending plane. With the strand frame of [`crate::strand::loading`] (bending
//! about y, a fibre at angle θ from the neutral axis sees the bending strain κ R sin θ), θ = 0 or
//! π is the neutral axis and θ = ±π/2 the outer arcs (extreme fibres, tension and compression
//! side; one class, since curvature reverses sign within a sea state).
//!
//! Units: m, N, rad.

use serde::{Deserialize, Serialize};

use super::cycles::SlipCycle;

pub use moorfret_vocabulary::AngularPosition;

/// Layer interface × angular position.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord, Serialize, Deserialize)]
pub struct ContactClass {
    /// Layer interface: 0 for layer 1 on the core, i for layer i+1 on layer i.
    pub interface: usize,
    /// Angular position around the cross-section.
    pub position: AngularPosition,
}

/// The fretting history of one contact over one load history, reduced to what the statistics
/// need: where it is, how hard it was pressed, and its rainflow-counted slip cycles with the
/// forces over them (residue included as half cycles).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct ContactRecord {
    /// Layer interface: 0 for layer 1 on the core, i for layer i+1 on layer i.
    pub interface: usize,
    /// Angle from the bending neutral axis at the contact (rad), see the module docs.
    pub theta_rad: f64,
    /// Reference axial coordinate along the strand (m).
    pub z_m: f64,
    /// Largest normal force over the history (N).
    pub max_normal_force_n: f64,
    /// Slip cycles with the normal and tangential forces over each.
    pub cycles: Vec<SlipCycle>,
}

impl ContactRecord {
    /// The contact's class.
    pub fn class(&self) -> ContactClass {
        ContactClass {
            interface: self.interface,
            position: AngularPosition::of(self.theta_rad),
        }
    }

    /// Slip cycles counted (half cycles as 0.5).
    pub fn slip_cycle_count(&self) -> f64 {
        self.cycles.iter().map(|k| k.slip.count).sum()
    }

    /// Largest slip range of a counted cycle (m), 0 without cycles.
    pub fn max_slip_range_m(&self) -> f64 {
        self.cycles
            .iter()
            .map(|k| k.slip.range)
            .fold(0.0_f64, f64::max)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::f64::consts::PI;

    #[test]
    fn angular_classes_split_the_circle_into_bands_around_the_axes() {
        for theta in [0.0, PI, -PI, 0.3, PI - 0.3, 2.0 * PI + 0.1] {
            assert_eq!(
                AngularPosition::of(theta),
                AngularPosition::NeutralAxis,
                "{theta}"
            );
        }
        for theta in [PI / 2.0, -PI / 2.0, PI / 2.0 + 0.3, 1.5 * PI - 0.3] {
            assert_eq!(
                AngularPosition::of(theta),
                AngularPosition::OuterArc,
                "{theta}"
            );
        }
        for theta in [PI / 4.0, 3.0 * PI / 4.0, -PI / 4.0, 0.45, 1.1] {
            assert_eq!(
                AngularPosition::of(theta),
                AngularPosition::Between,
                "{theta}"
            );
        }
        // band edges: 22.5° belongs to the neutral axis, 67.5° to the outer arc
        assert_eq!(
            AngularPosition::of(PI / 8.0 - 1e-12),
            AngularPosition::NeutralAxis
        );
        assert_eq!(
            AngularPosition::of(PI / 8.0 + 1e-9),
            AngularPosition::Between
        );
        assert_eq!(
            AngularPosition::of(3.0 * PI / 8.0 + 1e-12),
            AngularPosition::OuterArc
        );
    }

    #[test]
    fn record_serialises_with_snake_case_positions() {
        let r = ContactRecord {
            interface: 2,
            theta_rad: PI / 2.0,
            z_m: 0.29,
            max_normal_force_n: 812.0,
            cycles: Vec::new(),
        };
        assert_eq!(
            r.class(),
            ContactClass {
                interface: 2,
                position: AngularPosition::OuterArc
            }
        );
        let json = serde_json::to_string(&r.class()).unwrap();
        assert_eq!(json, r#"{"interface":2,"position":"outer_arc"}"#);
        let back: ContactRecord =
            serde_json::from_str(&serde_json::to_string(&r).unwrap()).unwrap();
        assert_eq!(back, r);
    }
}
