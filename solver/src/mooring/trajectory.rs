//! Prescribed fairlead motion: position, velocity and acceleration at time t, supplied by the
//! floater (coupled runs), a measured time series, or the simple motions here.

use nalgebra::Vector3;

/// Kinematics of a point (m, m/s, m/s²).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PointMotion {
    /// Position (m).
    pub position_m: Vector3<f64>,
    /// Velocity (m/s).
    pub velocity_m_s: Vector3<f64>,
    /// Acceleration (m/s²).
    pub acceleration_m_s2: Vector3<f64>,
}

/// A prescribed trajectory of the fairlead.
pub trait FairleadMotion {
    /// Kinematics at time `t_s`.
    fn at(&self, t_s: f64) -> PointMotion;
}

impl<F: Fn(f64) -> PointMotion> FairleadMotion for F {
    fn at(&self, t_s: f64) -> PointMotion {
        self(t_s)
    }
}

/// A fairlead held at one point.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Stationary(pub Vector3<f64>);

impl FairleadMotion for Stationary {
    fn at(&self, _t_s: f64) -> PointMotion {
        PointMotion {
            position_m: self.0,
            velocity_m_s: Vector3::zeros(),
            acceleration_m_s2: Vector3::zeros(),
        }
    }
}

/// x(t) = mean + ramp(t) · amplitude · sin(2π t / T + φ), with the smooth ramp
/// ½ (1 − cos(π t / t_r)) over the first t_r seconds (1 afterwards), so the motion starts from
/// rest at `mean` when φ = 0.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct HarmonicMotion {
    /// Mean position (m).
    pub mean_m: Vector3<f64>,
    /// Amplitude vector (m).
    pub amplitude_m: Vector3<f64>,
    /// Period (s).
    pub period_s: f64,
    /// Phase (rad).
    pub phase_rad: f64,
    /// Ramp duration (s); 0 for none.
    pub ramp_s: f64,
}

impl FairleadMotion for HarmonicMotion {
    fn at(&self, t: f64) -> PointMotion {
        let w = 2.0 * std::f64::consts::PI / self.period_s;
        let (s, c) = (w * t + self.phase_rad).sin_cos();
        let (r, dr, ddr) = if self.ramp_s > 0.0 && t < self.ramp_s {
            let k = std::f64::consts::PI / self.ramp_s;
            (
                0.5 * (1.0 - (k * t).cos()),
                0.5 * k * (k * t).sin(),
                0.5 * k * k * (k * t).cos(),
            )
        } else {
            (1.0, 0.0, 0.0)
        };
        let f = r * s;
        let df = dr * s + r * w * c;
        let ddf = ddr * s + 2.0 * dr * w * c - r * w * w * s;
        PointMotion {
            position_m: self.mean_m + self.amplitude_m * f,
            velocity_m_s: self.amplitude_m * df,
            acceleration_m_s2: self.amplitude_m * ddf,
        }
    }
}

/// Straight move from `from` to `to` during [0, duration] with a smooth (cubic, zero end
/// velocities) profile, then at rest.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SmoothMove {
    /// Start point (m).
    pub from_m: Vector3<f64>,
    /// End point (m).
    pub to_m: Vector3<f64>,
    /// Duration (s).
    pub duration_s: f64,
}

impl FairleadMotion for SmoothMove {
    fn at(&self, t: f64) -> PointMotion {
        let d = self.to_m - self.from_m;
        let tau = (t / self.duration_s).clamp(0.0, 1.0);
        let inside = t > 0.0 && t < self.duration_s;
        let f = tau * tau * (3.0 - 2.0 * tau);
        let df = if inside {
            6.0 * tau * (1.0 - tau) / self.duration_s
        } else {
            0.0
        };
        let ddf = if inside {
            (6.0 - 12.0 * tau) / (self.duration_s * self.duration_s)
        } else {
            0.0
        };
        PointMotion {
            position_m: self.from_m + d * f,
            velocity_m_s: d * df,
            acceleration_m_s2: d * ddf,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn harmonic_motion_rates_match_finite_differences_through_the_ramp() {
        let m = HarmonicMotion {
            mean_m: Vector3::new(1.0, 2.0, -14.0),
            amplitude_m: Vector3::new(3.0, 0.0, 0.5),
            period_s: 12.0,
            phase_rad: 0.3,
            ramp_s: 20.0,
        };
        let h = 1e-4;
        for &t in &[1.0, 13.0, 30.0] {
            let v = (m.at(t + h).position_m - m.at(t - h).position_m) / (2.0 * h);
            let a = (m.at(t + h).velocity_m_s - m.at(t - h).velocity_m_s) / (2.0 * h);
            assert!((v - m.at(t).velocity_m_s).norm() < 1e-6);
            assert!((a - m.at(t).acceleration_m_s2).norm() < 1e-6);
        }
        assert_eq!(m.at(0.0).position_m, m.mean_m);
    }
}
