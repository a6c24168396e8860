//! Prescribed 6-DOF floater motion from a time table (model tests, another code).
//!
//! Input: CSV text with the header `time_s,surge_m,sway_m,heave_m,roll_rad,pitch_rad,yaw_rad`
//! and strictly increasing times. Every channel is interpolated by a natural cubic spline (C²:
//! position, velocity and acceleration continuous; the acceleration is zero at the two ends, so a
//! table should start and end with a short quiet lead). Orientation from the angles:
//! Λ = R_z(yaw) R_y(pitch) R_x(roll); spatial angular velocity
//! ω = ψ̇ ẑ + θ̇ R_z ŷ + φ̇ R_z R_y x̂ and its derivative α, both in global axes, as used by
//! `super::body`.

use nalgebra::{Matrix3, Rotation3, Vector3, Vector6};

use super::body::BodyState;
use super::error::FloaterError;

/// Column names expected in the header, in order.
pub const COLUMNS: [&str; 7] = [
    "time_s",
    "surge_m",
    "sway_m",
    "heave_m",
    "roll_rad",
    "pitch_rad",
    "yaw_rad",
];

/// Natural cubic spline through (tᵢ, yᵢ).
#[derive(Debug, Clone, PartialEq)]
struct CubicSpline {
    y: Vec<f64>,
    /// Second derivatives at the knots.
    m: Vec<f64>,
}

impl CubicSpline {
    fn new(t: &[f64], y: &[f64]) -> Self {
        let n = t.len();
        let mut m = vec![0.0; n];
        if n > 2 {
            // Tridiagonal system for the interior second derivatives (Thomas algorithm).
            let k = n - 2;
            let mut diag = vec![0.0; k];
            let mut rhs = vec![0.0; k];
            let mut upper = vec![0.0; k];
            for i in 0..k {
                let (h0, h1) = (t[i + 1] - t[i], t[i + 2] - t[i + 1]);
                diag[i] = (h0 + h1) / 3.0;
                upper[i] = h1 / 6.0;
                rhs[i] = (y[i + 2] - y[i + 1]) / h1 - (y[i + 1] - y[i]) / h0;
            }
            for i in 1..k {
                let lower = (t[i + 1] - t[i]) / 6.0;
                let w = lower / diag[i - 1];
                diag[i] -= w * upper[i - 1];
                rhs[i] -= w * rhs[i - 1];
            }
            m[k] = rhs[k - 1] / diag[k - 1];
            for i in (0..k - 1).rev() {
                m[i + 1] = (rhs[i] - upper[i] * m[i + 2]) / diag[i];
            }
        }
        Self { y: y.to_vec(), m }
    }

    /// Value, first and second derivative on interval `i` at `t`.
    fn eval(&self, times: &[f64], i: usize, t: f64) -> [f64; 3] {
        let (t0, t1) = (times[i], times[i + 1]);
        let h = t1 - t0;
        let (a, b) = (t1 - t, t - t0);
        let (m0, m1) = (self.m[i], self.m[i + 1]);
        let c0 = self.y[i] / h - m0 * h / 6.0;
        let c1 = self.y[i + 1] / h - m1 * h / 6.0;
        [
            m0 * a * a * a / (6.0 * h) + m1 * b * b * b / (6.0 * h) + c0 * a + c1 * b,
            -m0 * a * a / (2.0 * h) + m1 * b * b / (2.0 * h) - c0 + c1,
            (m0 * a + m1 * b) / h,
        ]
    }
}

/// Pose, velocities and accelerations at one instant.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PrescribedSample {
    /// Position, orientation and velocities.
    pub state: BodyState,
    /// Generalised acceleration (a, α), global axes.
    pub acceleration: Vector6<f64>,
}

/// A prescribed motion table with its interpolants.
#[derive(Debug, Clone, PartialEq)]
pub struct PrescribedMotion {
    times: Vec<f64>,
    channels: Vec<CubicSpline>,
}

impl PrescribedMotion {
    /// Reads the CSV text; errors give the 1-based line and column.
    pub fn from_csv_str(text: &str) -> Result<Self, FloaterError> {
        let mut lines = text
            .lines()
            .enumerate()
            .filter(|(_, l)| !l.trim().is_empty());
        let (_, header) = lines.next().ok_or(FloaterError::MotionTable {
            line: 1,
            column: 1,
            reason: "empty table".into(),
        })?;
        let names: Vec<&str> = header.split(',').map(str::trim).collect();
        for (c, expected) in COLUMNS.iter().enumerate() {
            if names.get(c) != Some(expected) {
                return Err(FloaterError::MotionTable {
                    line: 1,
                    column: c + 1,
                    reason: format!(
                        "header must be {}; found '{}'",
                        COLUMNS.join(","),
                        names.get(c).unwrap_or(&"")
                    ),
                });
            }
        }
        if names.len() > COLUMNS.len() {
            return Err(FloaterError::MotionTable {
                line: 1,
                column: COLUMNS.len() + 1,
                reason: "unexpected extra column".into(),
            });
        }
        let mut rows: Vec<[f64; 7]> = Vec::new();
        for (k, line) in lines {
            let line_no = k + 1;
            let cells: Vec<&str> = line.split(',').map(str::trim).collect();
            if cells.len() != COLUMNS.len() {
                return Err(FloaterError::MotionTable {
                    line: line_no,
                    column: cells.len().min(COLUMNS.len()) + 1,
                    reason: format!("expected {} values, found {}", COLUMNS.len(), cells.len()),
                });
            }
            let mut row = [0.0; 7];
            for (c, cell) in cells.iter().enumerate() {
                row[c] = cell
                    .parse::<f64>()
                    .ok()
                    .filter(|v| v.is_finite())
                    .ok_or_else(|| FloaterError::MotionTable {
                        line: line_no,
                        column: c + 1,
                        reason: format!("'{cell}' is not a finite number"),
                    })?;
            }
            if let Some(prev) = rows.last() {
                if row[0] <= prev[0] {
                    return Err(FloaterError::MotionTable {
                        line: line_no,
                        column: 1,
                        reason: format!(
                            "time {} s does not increase (previous {} s)",
                            row[0], prev[0]
                        ),
                    });
                }
            }
            rows.push(row);
        }
        if rows.len() < 2 {
            return Err(FloaterError::MotionTable {
                line: 1 + rows.len(),
                column: 1,
                reason: "at least two time rows are needed".into(),
            });
        }
        let times: Vec<f64> = rows.iter().map(|r| r[0]).collect();
        let channels = (1..7)
            .map(|c| {
                let y: Vec<f64> = rows.iter().map(|r| r[c]).collect();
                CubicSpline::new(&times, &y)
            })
            .collect();
        Ok(Self { times, channels })
    }

    /// First and last time of the table (s).
    pub fn time_range(&self) -> (f64, f64) {
        (self.times[0], self.times[self.times.len() - 1])
    }

    /// Surge, sway, heave, roll, pitch, yaw and their first and second time derivatives at `t`.
    pub(crate) fn channels_at(&self, t: f64) -> Result<[[f64; 3]; 6], FloaterError> {
        let (start_s, end_s) = self.time_range();
        if !(t >= start_s && t <= end_s) {
            return Err(FloaterError::OutsideTimeRange {
                time_s: t,
                start_s,
                end_s,
            });
        }
        let i = self
            .times
            .partition_point(|&x| x <= t)
            .clamp(1, self.times.len() - 1)
            - 1;
        let mut out = [[0.0; 3]; 6];
        for (o, ch) in out.iter_mut().zip(self.channels.iter()) {
            *o = ch.eval(&self.times, i, t);
        }
        Ok(out)
    }

    /// Pose, velocities and accelerations at `t` (error outside the table's range).
    pub fn sample(&self, t: f64) -> Result<PrescribedSample, FloaterError> {
        let c = self.channels_at(t)?;
        let [roll, pitch, yaw] = [c[3], c[4], c[5]];
        let rz = Rotation3::from_axis_angle(&Vector3::z_axis(), yaw[0]).into_inner();
        let ry = Rotation3::from_axis_angle(&Vector3::y_axis(), pitch[0]).into_inner();
        let rx = Rotation3::from_axis_angle(&Vector3::x_axis(), roll[0]).into_inner();
        let rotation: Matrix3<f64> = rz * ry * rx;
        let ez = Vector3::z();
        let ey = rz * Vector3::y();
        let ex = rz * ry * Vector3::x();
        let w_z = ez * yaw[1];
        let w_zy = w_z + ey * pitch[1];
        let omega = w_zy + ex * roll[1];
        let alpha = ez * yaw[2]
            + ey * pitch[2]
            + w_z.cross(&ey) * pitch[1]
            + ex * roll[2]
            + w_zy.cross(&ex) * roll[1];
        let state = BodyState {
            position_m: Vector3::new(c[0][0], c[1][0], c[2][0]),
            rotation,
            velocity_m_per_s: Vector3::new(c[0][1], c[1][1], c[2][1]),
            angular_velocity_rad_per_s: omega,
        };
        let acceleration = Vector6::new(c[0][2], c[1][2], c[2][2], alpha.x, alpha.y, alpha.z);
        Ok(PrescribedSample {
            state,
            acceleration,
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::beam::rotation::{axial, skew};

    fn table(f: impl Fn(f64) -> [f64; 6], dt: f64, n: usize) -> String {
        let mut s = COLUMNS.join(",") + "\n";
        for k in 0..=n {
            let t = k as f64 * dt;
            let v = f(t);
            s += &format!(
                "{t},{},{},{},{},{},{}\n",
                v[0], v[1], v[2], v[3], v[4], v[5]
            );
        }
        s
    }

    fn smooth(t: f64) -> [f64; 6] {
        let w = 2.0 * std::f64::consts::PI / 12.0;
        [
            2.0 * (w * t).sin(),
            0.5 * (w * t).cos(),
            1.0 * (0.7 * w * t).sin(),
            0.02 * (w * t).sin(),
            0.05 * (0.9 * w * t).cos(),
            0.03 * (1.1 * w * t).sin(),
        ]
    }

    #[test]
    fn spline_reproduces_a_smooth_motion_and_its_derivatives() {
        let motion = PrescribedMotion::from_csv_str(&table(smooth, 0.1, 600)).unwrap();
        let w = 2.0 * std::f64::consts::PI / 12.0;
        for &t in &[10.03, 30.0, 41.27] {
            let c = motion.channels_at(t).unwrap();
            assert!((c[0][0] - 2.0 * (w * t).sin()).abs() < 1e-7, "position");
            assert!((c[0][1] - 2.0 * w * (w * t).cos()).abs() < 1e-5, "velocity");
            assert!(
                (c[0][2] + 2.0 * w * w * (w * t).sin()).abs() < 1e-3,
                "acceleration"
            );
        }
    }

    #[test]
    fn angular_velocity_and_acceleration_match_differences_of_the_rotation() {
        let motion = PrescribedMotion::from_csv_str(&table(smooth, 0.05, 1200)).unwrap();
        let (t, h) = (23.4, 1e-4);
        let s = motion.sample(t).unwrap();
        let rp = motion.sample(t + h).unwrap();
        let rm = motion.sample(t - h).unwrap();
        // Spatial angular velocity: (dΛ/dt) Λᵀ = ω̂.
        let w_fd = axial(
            &((rp.state.rotation - rm.state.rotation) / (2.0 * h) * s.state.rotation.transpose()),
        );
        assert!(
            (w_fd - s.state.angular_velocity_rad_per_s).norm() < 1e-7,
            "{w_fd} vs {}",
            s.state.angular_velocity_rad_per_s
        );
        let a_fd =
            (rp.state.angular_velocity_rad_per_s - rm.state.angular_velocity_rad_per_s) / (2.0 * h);
        assert!((a_fd - s.acceleration.fixed_rows::<3>(3)).norm() < 1e-6);
        assert!((skew(&w_fd) - skew(&s.state.angular_velocity_rad_per_s)).norm() < 1e-6);
    }

    #[test]
    fn linear_motion_is_reproduced_exactly_with_zero_acceleration() {
        let motion =
            PrescribedMotion::from_csv_str(&table(|t| [t, -2.0 * t, 0.5, 0.0, 0.0, 0.0], 0.7, 9))
                .unwrap();
        let s = motion.sample(3.3).unwrap();
        assert!((s.state.position_m - Vector3::new(3.3, -6.6, 0.5)).norm() < 1e-12);
        assert!((s.state.velocity_m_per_s - Vector3::new(1.0, -2.0, 0.0)).norm() < 1e-12);
        assert!(s.acceleration.norm() < 1e-12);
    }

    #[test]
    fn sampling_outside_the_table_is_an_error() {
        let motion = PrescribedMotion::from_csv_str(&table(smooth, 1.0, 5)).unwrap();
        assert!(matches!(
            motion.sample(5.5),
            Err(FloaterError::OutsideTimeRange { .. })
        ));
        assert!(matches!(
            motion.sample(-0.1),
            Err(FloaterError::OutsideTimeRange { .. })
        ));
        assert!(motion.sample(5.0).is_ok());
    }

    #[test]
    fn bad_cells_are_reported_with_line_and_column() {
        let head = COLUMNS.join(",");
        let text = format!("{head}\n0,0,0,0,0,0,0\n1,0,0,x,0,0,0\n");
        assert_eq!(
            PrescribedMotion::from_csv_str(&text).unwrap_err(),
            FloaterError::MotionTable {
                line: 3,
                column: 4,
                reason: "'x' is not a finite number".into()
            }
        );
        let text = format!("{head}\n0,0,0,0,0,0,0\n1,0,0,0,0,0,0\n1,0,0,0,0,0,0\n");
        assert!(matches!(
            PrescribedMotion::from_csv_str(&text),
            Err(FloaterError::MotionTable {
                line: 4,
                column: 1,
                ..
            })
        ));
        let text = "time_s,surge_m,heave_m\n0,0,0\n";
        assert!(matches!(
            PrescribedMotion::from_csv_str(text),
            Err(FloaterError::MotionTable {
                line: 1,
                column: 3,
                ..
            })
        ));
        let text = format!("{head}\n0,0,0,0,0,0\n");
        assert!(matches!(
            PrescribedMotion::from_csv_str(&text),
            Err(FloaterError::MotionTable {
                line: 2,
                column: 7,
                ..
            })
        ));
    }
}
