//! Rigid-body kinematics and inertia of the floater.
//!
//! State: position x of the body reference point (global, m), orientation Λ (rotation matrix
//! mapping body axes to global axes, updated as Λ ← exp(θ̂) Λ with a *spatial* increment θ, the
//! convention of [`crate::beam::rotation`]), linear velocity v of the reference point and
//! spatial angular velocity ω (global axes). Generalised velocity ν = (v, ω), generalised
//! acceleration (a, α), generalised force (F, M) with the moment M taken about the reference
//! point; all six-vectors are in global axes.
//!
//! With c = Λ c_b the lever from the reference point to the centre of mass and J_c = Λ J_b Λᵀ
//! the inertia about the centre of mass, the Newton–Euler equations about the moving reference
//! point read M_rb (a, α) + b(ν) = (F, M) with
//!
//! ```text
//! M_rb = | m I      −m ĉ        |      b = | m ω×(ω×c)                  |
//!        | m ĉ    J_c − m ĉ ĉ   |          | ω×(J_c ω) + m c×(ω×(ω×c))  |
//! ```
//!
//! A body point p_b moves as x_p = x + Λ p_b, v_p = v + ω×r, a_p = a + α×r + ω×(ω×r) with
//! r = Λ p_b.

use nalgebra::{Matrix3, Matrix6, Vector3, Vector6};

use crate::beam::rotation::skew;

/// Position, orientation and velocities of the rigid body.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct BodyState {
    /// Position of the reference point, global axes (m).
    pub position_m: Vector3<f64>,
    /// Orientation Λ: body axes → global axes.
    pub rotation: Matrix3<f64>,
    /// Velocity of the reference point, global axes (m/s).
    pub velocity_m_per_s: Vector3<f64>,
    /// Spatial angular velocity, global axes (rad/s).
    pub angular_velocity_rad_per_s: Vector3<f64>,
}

impl Default for BodyState {
    fn default() -> Self {
        Self::at_rest()
    }
}

impl BodyState {
    /// Undisplaced body at rest (reference point at the origin, body axes = global axes).
    pub fn at_rest() -> Self {
        Self {
            position_m: Vector3::zeros(),
            rotation: Matrix3::identity(),
            velocity_m_per_s: Vector3::zeros(),
            angular_velocity_rad_per_s: Vector3::zeros(),
        }
    }

    /// Generalised velocity ν = (v, ω).
    pub(crate) fn velocity6(&self) -> Vector6<f64> {
        let mut nu = Vector6::zeros();
        nu.fixed_rows_mut::<3>(0).copy_from(&self.velocity_m_per_s);
        nu.fixed_rows_mut::<3>(3)
            .copy_from(&self.angular_velocity_rad_per_s);
        nu
    }

    /// Global position of a body point (m).
    pub(crate) fn point_position(&self, body_point: &Vector3<f64>) -> Vector3<f64> {
        self.position_m + self.rotation * body_point
    }

    /// Velocity of the material point currently at global position `x` (m/s).
    pub(crate) fn velocity_at(&self, x: &Vector3<f64>) -> Vector3<f64> {
        self.velocity_m_per_s
            + self
                .angular_velocity_rad_per_s
                .cross(&(x - self.position_m))
    }
}

/// Position, velocity and acceleration of one body point, global axes.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PointKinematics {
    /// Position (m).
    pub position_m: Vector3<f64>,
    /// Velocity (m/s).
    pub velocity_m_per_s: Vector3<f64>,
    /// Acceleration (m/s²).
    pub acceleration_m_per_s2: Vector3<f64>,
}

/// Kinematics of the body point `body_point` (body axes, m) for the state and the generalised
/// acceleration (a, α) (global axes).
pub(crate) fn point_kinematics(
    state: &BodyState,
    acceleration: &Vector6<f64>,
    body_point: &Vector3<f64>,
) -> PointKinematics {
    let r = state.rotation * body_point;
    let w = state.angular_velocity_rad_per_s;
    let a = acceleration.fixed_rows::<3>(0).into_owned();
    let alpha = acceleration.fixed_rows::<3>(3).into_owned();
    PointKinematics {
        position_m: state.position_m + r,
        velocity_m_per_s: state.velocity_m_per_s + w.cross(&r),
        acceleration_m_per_s2: a + alpha.cross(&r) + w.cross(&w.cross(&r)),
    }
}

/// Body points of fairleads on a circle of radius `radius_m` around the body z axis, `depth_m`
/// below the reference point, at the given azimuths (deg, from +x towards +y).
pub fn fairlead_body_points(
    radius_m: f64,
    depth_m: f64,
    azimuths_deg: &[f64],
) -> Vec<Vector3<f64>> {
    azimuths_deg
        .iter()
        .map(|az| {
            let (s, c) = az.to_radians().sin_cos();
            Vector3::new(radius_m * c, radius_m * s, -depth_m)
        })
        .collect()
}

/// Generalised load of a line attached at body point `body_point` and its derivative with
/// respect to the body position q (translation, spatial rotation).
///
/// `force_n` is the force the line exerts on the body at the fairlead (global, N) and
/// `stiffness_n_per_m` the condensed line stiffness K = −∂f/∂x_p at the fairlead (N/m). With
/// r = Λ p_b and δx_p = δx − r̂ δθ:
///
/// ```text
/// F = (f, r × f),   ∂F/∂q = −[[K, −K r̂], [r̂ K, −r̂ K r̂]] + [[0, 0], [0, f̂ r̂]]
/// ```
///
/// the last block being the change of lever arm under a rotation with the force held fixed.
pub fn fairlead_load(
    state: &BodyState,
    body_point: &Vector3<f64>,
    force_n: &Vector3<f64>,
    stiffness_n_per_m: &Matrix3<f64>,
) -> (Vector6<f64>, Matrix6<f64>) {
    let r = state.rotation * body_point;
    let mut w = Wrench::default();
    w.add_at(force_n, &r);
    let mut k = Matrix6::zeros();
    add_point_block(&mut k, stiffness_n_per_m, &r, -1.0);
    let geometric = skew(force_n) * skew(&r);
    let mut block = k.fixed_view_mut::<3, 3>(3, 3);
    block += geometric;
    (w.to_vector6(), k)
}

/// A force and its moment about the body reference point, global axes.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct Wrench {
    /// Force (N).
    pub force_n: Vector3<f64>,
    /// Moment about the reference point (N m).
    pub moment_nm: Vector3<f64>,
}

impl Wrench {
    /// Adds force `f` applied at lever `r` (point minus reference point).
    pub(crate) fn add_at(&mut self, f: &Vector3<f64>, r: &Vector3<f64>) {
        self.force_n += f;
        self.moment_nm += r.cross(f);
    }

    /// As a six-vector (F, M).
    pub fn to_vector6(&self) -> Vector6<f64> {
        let mut v = Vector6::zeros();
        v.fixed_rows_mut::<3>(0).copy_from(&self.force_n);
        v.fixed_rows_mut::<3>(3).copy_from(&self.moment_nm);
        v
    }
}

/// Adds to a 6×6 matrix the generalised form of a 3×3 point matrix `k` acting at lever `r`:
/// the map ν ↦ (k u, r × k u) with u = v + ω × r = v − r̂ ω, i.e.
/// `[[k, −k r̂], [r̂ k, −r̂ k r̂]]`, scaled by `sign`.
pub(crate) fn add_point_block(m: &mut Matrix6<f64>, k: &Matrix3<f64>, r: &Vector3<f64>, sign: f64) {
    let rh = skew(r);
    let kr = k * rh;
    let rk = rh * k;
    let rkr = rh * kr;
    for i in 0..3 {
        for j in 0..3 {
            m[(i, j)] += sign * k[(i, j)];
            m[(i, j + 3)] -= sign * kr[(i, j)];
            m[(i + 3, j)] += sign * rk[(i, j)];
            m[(i + 3, j + 3)] -= sign * rkr[(i, j)];
        }
    }
}

/// Mass, centre of mass and inertia of the rigid body, body axes.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct MassProperties {
    /// Total mass (kg).
    pub mass_kg: f64,
    /// Centre of mass relative to the reference point, body axes (m).
    pub centre_of_mass_m: Vector3<f64>,
    /// Inertia tensor about the centre of mass, body axes (kg m²).
    pub inertia_about_com_kg_m2: Matrix3<f64>,
}

impl MassProperties {
    /// Combines rigid parts given as (mass, centre, inertia about own centre) with the parallel
    /// axis theorem.
    pub(crate) fn combine(parts: &[(f64, Vector3<f64>, Matrix3<f64>)]) -> Self {
        let mass: f64 = parts.iter().map(|p| p.0).sum();
        let com = parts
            .iter()
            .fold(Vector3::zeros(), |acc, p| acc + p.1 * p.0)
            / mass;
        let mut inertia = Matrix3::zeros();
        for (m, c, j) in parts {
            let d = c - com;
            inertia += j + *m * (Matrix3::identity() * d.norm_squared() - d * d.transpose());
        }
        Self {
            mass_kg: mass,
            centre_of_mass_m: com,
            inertia_about_com_kg_m2: inertia,
        }
    }

    /// Rigid-body mass matrix about the reference point, global axes, for orientation Λ.
    pub fn mass_matrix(&self, rotation: &Matrix3<f64>) -> Matrix6<f64> {
        let m = self.mass_kg;
        let c = rotation * self.centre_of_mass_m;
        let ch = skew(&c);
        let jc = rotation * self.inertia_about_com_kg_m2 * rotation.transpose();
        let mut out = Matrix6::zeros();
        out.fixed_view_mut::<3, 3>(0, 0)
            .copy_from(&(Matrix3::identity() * m));
        out.fixed_view_mut::<3, 3>(0, 3).copy_from(&(-m * ch));
        out.fixed_view_mut::<3, 3>(3, 0).copy_from(&(m * ch));
        out.fixed_view_mut::<3, 3>(3, 3)
            .copy_from(&(jc - m * ch * ch));
        out
    }

    /// Velocity-dependent inertial terms b(ν) (centripetal and gyroscopic), global axes.
    pub(crate) fn inertial_bias(&self, state: &BodyState) -> Vector6<f64> {
        let m = self.mass_kg;
        let c = state.rotation * self.centre_of_mass_m;
        let jc = state.rotation * self.inertia_about_com_kg_m2 * state.rotation.transpose();
        let w = state.angular_velocity_rad_per_s;
        let centripetal = m * w.cross(&w.cross(&c));
        let mut b = Vector6::zeros();
        b.fixed_rows_mut::<3>(0).copy_from(&centripetal);
        b.fixed_rows_mut::<3>(3)
            .copy_from(&(w.cross(&(jc * w)) + c.cross(&centripetal)));
        b
    }

    /// ∂b/∂ν: the bias depends on ω only.
    pub(crate) fn inertial_bias_velocity_jacobian(&self, state: &BodyState) -> Matrix6<f64> {
        let m = self.mass_kg;
        let c = state.rotation * self.centre_of_mass_m;
        let jc = state.rotation * self.inertia_about_com_kg_m2 * state.rotation.transpose();
        let w = state.angular_velocity_rad_per_s;
        // d[ω×(ω×c)]/dω = (ω·c) I + ω cᵀ − 2 c ωᵀ ; d[ω×(Jω)]/dω = ω̂ J − (Jω)^
        let dcent =
            m * (Matrix3::identity() * w.dot(&c) + w * c.transpose() - 2.0 * c * w.transpose());
        let dgyro = skew(&w) * jc - skew(&(jc * w));
        let mut out = Matrix6::zeros();
        out.fixed_view_mut::<3, 3>(0, 3).copy_from(&dcent);
        out.fixed_view_mut::<3, 3>(3, 3)
            .copy_from(&(dgyro + skew(&c) * dcent));
        out
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::beam::rotation::exp_so3;

    fn sample() -> MassProperties {
        let j = Matrix3::new(
            3.0e9, 1.0e8, -2.0e7, 1.0e8, 4.0e9, 5.0e7, -2.0e7, 5.0e7, 6.0e9,
        );
        MassProperties {
            mass_kg: 1.4e7,
            centre_of_mass_m: Vector3::new(0.3, -0.2, -9.9),
            inertia_about_com_kg_m2: j,
        }
    }

    #[test]
    fn point_acceleration_matches_second_difference_of_rigid_motion() {
        // Motion x(t) = x0 + v t + a t²/2, Λ(t) = exp((ω0 t + α t²/2)^) Λ0 has, at t = 0, spatial
        // angular velocity ω0 and angular acceleration α (the increments commute at t = 0 only to
        // first order, so compare with a small step).
        let l0 = exp_so3(&Vector3::new(0.1, -0.2, 0.3));
        let (x0, v, a) = (
            Vector3::new(1.0, 2.0, -3.0),
            Vector3::new(0.5, -0.1, 0.2),
            Vector3::new(0.01, 0.02, -0.03),
        );
        let (w0, al) = (
            Vector3::new(0.02, -0.05, 0.03),
            Vector3::new(0.001, 0.002, -0.004),
        );
        let p = Vector3::new(40.0, -5.0, -14.0);
        let pos = |t: f64| {
            x0 + v * t + a * (0.5 * t * t) + exp_so3(&(w0 * t + al * (0.5 * t * t))) * l0 * p
        };
        let h = 1e-3;
        let fd_v = (pos(h) - pos(-h)) / (2.0 * h);
        let fd_a = (pos(h) - 2.0 * pos(0.0) + pos(-h)) / (h * h);
        let state = BodyState {
            position_m: x0,
            rotation: l0,
            velocity_m_per_s: v,
            angular_velocity_rad_per_s: w0,
        };
        let mut acc = Vector6::zeros();
        acc.fixed_rows_mut::<3>(0).copy_from(&a);
        acc.fixed_rows_mut::<3>(3).copy_from(&al);
        let k = point_kinematics(&state, &acc, &p);
        assert!((k.position_m - pos(0.0)).norm() < 1e-12);
        assert!((k.velocity_m_per_s - fd_v).norm() < 1e-6);
        assert!(
            (k.acceleration_m_per_s2 - fd_a).norm() < 1e-5,
            "{} vs {}",
            k.acceleration_m_per_s2,
            fd_a
        );
    }

    #[test]
    fn mass_matrix_gives_kinetic_energy_of_the_centre_of_mass_motion() {
        let mp = sample();
        let rot = exp_so3(&Vector3::new(0.2, 0.1, -0.4));
        let nu = Vector6::new(0.3, -0.2, 0.1, 0.01, -0.02, 0.015);
        let (v, w) = (
            nu.fixed_rows::<3>(0).into_owned(),
            nu.fixed_rows::<3>(3).into_owned(),
        );
        let c = rot * mp.centre_of_mass_m;
        let vc = v + w.cross(&c);
        let jc = rot * mp.inertia_about_com_kg_m2 * rot.transpose();
        let t_ref = 0.5 * mp.mass_kg * vc.norm_squared() + 0.5 * w.dot(&(jc * w));
        let t_mat = 0.5 * nu.dot(&(mp.mass_matrix(&rot) * nu));
        assert!((t_ref - t_mat).abs() < 1e-10 * t_ref);
    }

    #[test]
    fn inertial_bias_jacobian_matches_central_differences() {
        let mp = sample();
        let mut state = BodyState::at_rest();
        state.rotation = exp_so3(&Vector3::new(0.05, -0.1, 0.2));
        state.angular_velocity_rad_per_s = Vector3::new(0.03, -0.02, 0.05);
        let jac = mp.inertial_bias_velocity_jacobian(&state);
        let h = 1e-6;
        for j in 3..6 {
            let (mut p, mut m) = (state, state);
            p.angular_velocity_rad_per_s[j - 3] += h;
            m.angular_velocity_rad_per_s[j - 3] -= h;
            let fd = (mp.inertial_bias(&p) - mp.inertial_bias(&m)) / (2.0 * h);
            let scale = jac.column(j).norm().max(1.0);
            assert!(
                (fd - jac.column(j)).norm() < 1e-7 * scale,
                "column {j}: {fd} vs {}",
                jac.column(j)
            );
        }
    }

    #[test]
    fn fairlead_load_jacobian_matches_central_differences() {
        // A linear spring to a fixed anchor: f = −K (x_p − x_anchor) + f0, so −∂f/∂x_p = K.
        let k3 = Matrix3::new(
            5.0e4, 1.0e3, -2.0e3, 1.0e3, 2.0e4, 4.0e3, -2.0e3, 4.0e3, 3.0e4,
        );
        let anchor = Vector3::new(560.0, 40.0, -100.0);
        let f0 = Vector3::new(2.0e5, 1.0e4, -3.0e5);
        let p_b = fairlead_body_points(40.868, 14.0, &[-5.0])[0];
        let load = |s: &BodyState| {
            let xp = s.point_position(&p_b);
            let f = f0 - k3 * (xp - anchor);
            fairlead_load(s, &p_b, &f, &k3)
        };
        let mut state = BodyState::at_rest();
        state.position_m = Vector3::new(3.0, -1.0, 0.4);
        state.rotation = exp_so3(&Vector3::new(0.02, -0.05, 0.1));
        let (_, jac) = load(&state);
        for j in 0..6 {
            let h = if j < 3 { 1e-4 } else { 1e-7 };
            let shifted = |sign: f64| {
                let mut s = state;
                if j < 3 {
                    s.position_m[j] += sign * h;
                } else {
                    let mut th = Vector3::zeros();
                    th[j - 3] = sign * h;
                    s.rotation = exp_so3(&th) * state.rotation;
                }
                load(&s).0
            };
            let fd = (shifted(1.0) - shifted(-1.0)) / (2.0 * h);
            assert!(
                (fd - jac.column(j)).norm() < 1e-6 * jac.column(j).norm().max(1e4),
                "column {j}: {fd} vs {}",
                jac.column(j)
            );
        }
    }

    #[test]
    fn paper_case_fairleads_lie_on_their_circle_below_the_water() {
        let pts = fairlead_body_points(40.868, 14.0, &[-5.0, 5.0, 115.0, 125.0, 235.0, 245.0]);
        assert_eq!(pts.len(), 6);
        for p in &pts {
            assert!((p.xy().norm() - 40.868).abs() < 1e-12 && p.z == -14.0);
        }
        assert!((pts[1].y.atan2(pts[1].x).to_degrees() - 5.0).abs() < 1e-12);
    }

    #[test]
    fn combined_inertia_follows_the_parallel_axis_theorem() {
        let parts = [
            (2.0, Vector3::new(1.0, 0.0, 0.0), Matrix3::zeros()),
            (2.0, Vector3::new(-1.0, 0.0, 0.0), Matrix3::zeros()),
        ];
        let mp = MassProperties::combine(&parts);
        assert_eq!(mp.mass_kg, 4.0);
        assert!(mp.centre_of_mass_m.norm() < 1e-15);
        assert!(
            (mp.inertia_about_com_kg_m2 - Matrix3::from_diagonal(&Vector3::new(0.0, 4.0, 4.0)))
                .norm()
                < 1e-14
        );
    }
}
