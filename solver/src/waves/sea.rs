//! The interface every consumer of water kinematics goes through: [`SeaKinematics`] gives the
//! particle velocity, acceleration and dynamic pressure at a point and instant, and the surface
//! elevation. [`StillWater`] is the calm-sea implementation.
//!
//! Units: m, s, Pa. Global frame z up, still water level z = 0. Points above the instantaneous
//! free surface are dry and get zero kinematics.

use nalgebra::Vector3;

/// Water particle kinematics at one point and instant.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct FluidKinematics {
    /// Particle velocity (m/s).
    pub velocity: Vector3<f64>,
    /// Particle acceleration (m/s²).
    pub acceleration: Vector3<f64>,
    /// Dynamic pressure, hydrostatic part excluded (Pa).
    pub dynamic_pressure_pa: f64,
}

/// A wave field that can be sampled anywhere in the water column.
///
/// Points above the instantaneous free surface are dry: implementations return zero kinematics
/// there.
pub trait SeaKinematics: Sync {
    /// Kinematics at point `x` (m, global frame) and time `t` (s).
    fn kinematics(&self, x: &Vector3<f64>, t: f64) -> FluidKinematics;
    /// Free-surface elevation (m) above still water at horizontal position (x, y) and time t.
    fn elevation(&self, x: f64, y: f64, t: f64) -> f64;
}

/// Calm water: no waves, no current.
#[derive(Debug, Clone, Copy, Default)]
pub struct StillWater;

impl SeaKinematics for StillWater {
    fn kinematics(&self, _x: &Vector3<f64>, _t: f64) -> FluidKinematics {
        FluidKinematics::default()
    }
    fn elevation(&self, _x: f64, _y: f64, _t: f64) -> f64 {
        0.0
    }
}
