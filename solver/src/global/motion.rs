//! Fairlead motion over one coupled time step, handed to a line integrator.
//!
//! The line needs its fairlead position, velocity and acceleration at the end of the step (and
//! at intermediate times when it cuts the step). Within [t₀, t₁] the motion is the quintic
//! Hermite interpolant that matches position, velocity and acceleration at both ends, so the
//! end values are reproduced exactly and a cut step sees a smooth, consistent path.

use nalgebra::Vector3;

use crate::mooring::trajectory::{FairleadMotion, PointMotion};

/// Quintic Hermite path of a point over one step.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct StepMotion {
    /// Start time (s).
    pub t0_s: f64,
    /// End time (s).
    pub t1_s: f64,
    /// Kinematics at the start.
    pub start: PointMotion,
    /// Kinematics at the end.
    pub end: PointMotion,
}

impl FairleadMotion for StepMotion {
    fn at(&self, t_s: f64) -> PointMotion {
        let h = self.t1_s - self.t0_s;
        if h.is_nan() || h <= 0.0 || t_s >= self.t1_s {
            return self.end;
        }
        if t_s <= self.t0_s {
            return self.start;
        }
        let u = (t_s - self.t0_s) / h;
        // Quintic Hermite basis for p0, v0 h, a0 h², p1, v1 h, a1 h² and its derivatives in u.
        let (u2, u3, u4, u5) = (u * u, u * u * u, u.powi(4), u.powi(5));
        let b = [
            1.0 - 10.0 * u3 + 15.0 * u4 - 6.0 * u5,
            u - 6.0 * u3 + 8.0 * u4 - 3.0 * u5,
            0.5 * u2 - 1.5 * u3 + 1.5 * u4 - 0.5 * u5,
            10.0 * u3 - 15.0 * u4 + 6.0 * u5,
            -4.0 * u3 + 7.0 * u4 - 3.0 * u5,
            0.5 * u3 - u4 + 0.5 * u5,
        ];
        let db = [
            -30.0 * u2 + 60.0 * u3 - 30.0 * u4,
            1.0 - 18.0 * u2 + 32.0 * u3 - 15.0 * u4,
            u - 4.5 * u2 + 6.0 * u3 - 2.5 * u4,
            30.0 * u2 - 60.0 * u3 + 30.0 * u4,
            -12.0 * u2 + 28.0 * u3 - 15.0 * u4,
            1.5 * u2 - 4.0 * u3 + 2.5 * u4,
        ];
        let ddb = [
            -60.0 * u + 180.0 * u2 - 120.0 * u3,
            -36.0 * u + 96.0 * u2 - 60.0 * u3,
            1.0 - 9.0 * u + 18.0 * u2 - 10.0 * u3,
            60.0 * u - 180.0 * u2 + 120.0 * u3,
            -24.0 * u + 84.0 * u2 - 60.0 * u3,
            3.0 * u - 12.0 * u2 + 10.0 * u3,
        ];
        let c: [Vector3<f64>; 6] = [
            self.start.position_m,
            self.start.velocity_m_s * h,
            self.start.acceleration_m_s2 * h * h,
            self.end.position_m,
            self.end.velocity_m_s * h,
            self.end.acceleration_m_s2 * h * h,
        ];
        let mut p = Vector3::zeros();
        let mut v = Vector3::zeros();
        let mut a = Vector3::zeros();
        for k in 0..6 {
            p += c[k] * b[k];
            v += c[k] * db[k];
            a += c[k] * ddb[k];
        }
        PointMotion {
            position_m: p,
            velocity_m_s: v / h,
            acceleration_m_s2: a / (h * h),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn motion() -> StepMotion {
        let pm = |p: [f64; 3], v: [f64; 3], a: [f64; 3]| PointMotion {
            position_m: Vector3::from(p),
            velocity_m_s: Vector3::from(v),
            acceleration_m_s2: Vector3::from(a),
        };
        StepMotion {
            t0_s: 2.0,
            t1_s: 2.5,
            start: pm([1.0, 2.0, -14.0], [0.3, -0.1, 0.2], [1.0, 0.5, -2.0]),
            end: pm([1.2, 1.9, -13.9], [0.5, 0.0, 0.1], [-1.0, 0.2, 0.4]),
        }
    }

    #[test]
    fn step_motion_matches_the_end_values() {
        let m = motion();
        for (t, e) in [(2.0 + 1e-12, m.start), (2.5 - 1e-12, m.end)] {
            let g = m.at(t);
            assert!((g.position_m - e.position_m).norm() < 1e-9);
            assert!((g.velocity_m_s - e.velocity_m_s).norm() < 1e-9);
            assert!((g.acceleration_m_s2 - e.acceleration_m_s2).norm() < 1e-8);
        }
    }

    #[test]
    fn step_motion_rates_match_central_differences() {
        let m = motion();
        let h = 1e-5;
        for t in [2.1, 2.27, 2.43] {
            let v = (m.at(t + h).position_m - m.at(t - h).position_m) / (2.0 * h);
            let a = (m.at(t + h).velocity_m_s - m.at(t - h).velocity_m_s) / (2.0 * h);
            assert!(
                (v - m.at(t).velocity_m_s).norm() < 1e-7,
                "{v} vs {}",
                m.at(t).velocity_m_s
            );
            assert!((a - m.at(t).acceleration_m_s2).norm() < 1e-5);
        }
    }
}
