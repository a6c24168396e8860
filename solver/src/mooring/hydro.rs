//! Morison loads per unit length on a slender line element, with relative velocity to the water.
//!
//! With t = r'/|r'| the unit tangent, P = I − t tᵀ the normal projector, u = u_w − v the water
//! velocity relative to the line and a_w the water acceleration:
//!
//! f = ½ρD C_dn |u_n| u_n + ½ρD C_dt |u_t| u_t           (drag, u_n = P u, u_t = t tᵀ u)
//!   − ρA (C_an P + C_at t tᵀ) a                          (added mass on the line acceleration)
//!   + ρA (1 + C_an) P a_w                                (Froude–Krylov + diffraction)
//!
//! (DNV-RP-C205 §6.2 and DNV-OS-E301 Ch.2 Sec.2 for the split into normal and tangential
//! parts). The dependence on the direction uses d[t (t·x)]/dt = (t·x) I + t xᵀ =: W(x) and
//! dt/dr' = P / |r'| (written out in the projections in [`morison`]). The drag speed is regularised as √(|u|² + ε²) with ε = 1e-6 m/s so the
//! tangent stays finite at rest. The water kinematics are frozen during a step's iterations
//! (their gradient with respect to the line position is not linearised).

use nalgebra::Vector3;

use super::loads::{PointKinematics, PointLoad};
use super::section::Section;
use crate::waves::FluidKinematics;

const SPEED_REGULARISATION_M_S: f64 = 1e-6;

/// Quadratic drag force c |u| u with the regularised speed |u| = √(u·u + ε²), and that speed.
fn quadratic(c: f64, u: &Vector3<f64>) -> (Vector3<f64>, f64) {
    let s = (u.norm_squared() + SPEED_REGULARISATION_M_S * SPEED_REGULARISATION_M_S).sqrt();
    (u * (c * s), s)
}

/// Morison load at a point of a line with section `sec`, kinematics `k` and water `water`.
///
/// The derivatives are written out in the projections: with ℓ = |r'|, x_n = P x and
/// M(x) = W(x) P / ℓ = ((t·x) P + t x_nᵀ) / ℓ the derivative of t (t·x) with respect to r',
/// and D(u) = c (s I + u uᵀ / s) that of the drag c s u (s the regularised speed):
/// D(u_n) P = c_n (s_n P + u_n u_nᵀ / s_n), D(u_t) t tᵀ = c_t (s_t t tᵀ + u_t u_tᵀ / s_t) and
/// (D(u_t) − D(u_n)) M(u) = (c_t s_t − c_n s_n) M(u) + (t·u)/ℓ (c_t u_t / s_t − c_n u_n / s_n) u_nᵀ,
/// since u_tᵀ P = 0, u_nᵀ t = 0 and u_tᵀ t = t·u. M is linear in its argument, so the
/// M terms of drag, added mass and Froude–Krylov are summed as one, and the projections are
/// applied as rank-one updates of the identity (P = I − t tᵀ).
pub(crate) fn morison(sec: &Section, k: &PointKinematics, water: &FluidKinematics) -> PointLoad {
    let mut load = PointLoad::zero();
    let stretch = k.r_x.norm();
    if stretch <= 0.0 {
        return load;
    }
    let t = k.r_x / stretch;
    let ttt = t * t.transpose();
    // The three M(x) terms are linear in (t·x, x_n): their sum is M of the combined
    // (tx, xn), built once.
    let mut tx = 0.0;
    let mut xn = Vector3::zeros();

    // Drag.
    let (cn, ct) = (sec.drag_normal_kg_per_m2, sec.drag_tangential_kg_per_m2);
    if cn > 0.0 || ct > 0.0 {
        let u = water.velocity - k.v;
        let tu = t.dot(&u);
        let ut = t * tu;
        let un = u - ut;
        let (fn_, sn) = quadratic(cn, &un);
        let (ft, st) = quadratic(ct, &ut);
        load.f += fn_ + ft;
        // ∂u/∂v = −I; D(u_n) P + D(u_t) t tᵀ with u_t u_tᵀ = (t·u)² t tᵀ.
        let cns = cn * sn;
        load.d_v -= un * un.transpose() * (cn / sn) + ttt * (ct * st - cns + ct / st * tu * tu);
        for i in 0..3 {
            load.d_v[(i, i)] -= cns;
        }
        tx += tu * (ct * st - cns);
        xn += un * (ct * st - cns);
        load.d_rx += (ut * (ct / st) - un * (cn / sn)) * un.transpose() * (tu / stretch);
    }

    // Added mass on the structural acceleration.
    let (man, mat) = (
        sec.added_mass_normal_kg_per_m,
        sec.added_mass_tangential_kg_per_m,
    );
    if man > 0.0 || mat > 0.0 {
        let ta = t.dot(&k.a);
        let a_t = t * ta;
        let a_n = k.a - a_t;
        load.f -= a_n * man + a_t * mat;
        load.d_a -= ttt * (mat - man);
        for i in 0..3 {
            load.d_a[(i, i)] -= man;
        }
        tx -= ta * (mat - man);
        xn -= a_n * (mat - man);
    }

    // Froude–Krylov and diffraction on the normal water acceleration.
    let aw = water.acceleration;
    let fk = sec.froude_krylov_kg_per_m;
    if fk > 0.0 && aw.norm_squared() > 0.0 {
        let taw = t.dot(&aw);
        let aw_n = aw - t * taw;
        load.f += aw_n * fk;
        tx -= taw * fk;
        xn -= aw_n * fk;
    }
    // M(tx, xn) = (tx P + t xnᵀ) / ℓ with P = I − t tᵀ.
    let s = 1.0 / stretch;
    load.d_rx += (t * xn.transpose() - ttt * tx) * s;
    for i in 0..3 {
        load.d_rx[(i, i)] += tx * s;
    }
    load
}

/// The force of [`morison`] alone, without its derivatives (N/m).
pub(crate) fn morison_force(
    sec: &Section,
    k: &PointKinematics,
    water: &FluidKinematics,
) -> Vector3<f64> {
    let stretch = k.r_x.norm();
    if stretch <= 0.0 {
        return Vector3::zeros();
    }
    let t = k.r_x / stretch;
    let mut f = Vector3::zeros();
    if sec.drag_normal_kg_per_m2 > 0.0 || sec.drag_tangential_kg_per_m2 > 0.0 {
        let u = water.velocity - k.v;
        let ut = t * t.dot(&u);
        let un = u - ut;
        let eps2 = SPEED_REGULARISATION_M_S * SPEED_REGULARISATION_M_S;
        f += un * (sec.drag_normal_kg_per_m2 * (un.norm_squared() + eps2).sqrt());
        f += ut * (sec.drag_tangential_kg_per_m2 * (ut.norm_squared() + eps2).sqrt());
    }
    let (man, mat) = (
        sec.added_mass_normal_kg_per_m,
        sec.added_mass_tangential_kg_per_m,
    );
    if man > 0.0 || mat > 0.0 {
        let a_t = t * t.dot(&k.a);
        f -= (k.a - a_t) * man + a_t * mat;
    }
    let aw = water.acceleration;
    if sec.froude_krylov_kg_per_m > 0.0 && aw.norm_squared() > 0.0 {
        f += (aw - t * t.dot(&aw)) * sec.froude_krylov_kg_per_m;
    }
    f
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::mooring::spec::{Environment, LineTypeSpec, SegmentSpec};
    use nalgebra::Matrix3;

    fn section() -> Section {
        let lt = LineTypeSpec {
            mass_kg_per_m: 16.5,
            submerged_weight_n_per_m: 140.6,
            axial_stiffness_n: 3.6e8,
            bending_stiffness_nm2: 8.0e4,
            bending_stiffness_min_nm2: None,
            torsional_stiffness_nm2: None,
            hydrodynamic_diameter_m: 0.1,
            drag_normal: 1.2,
            drag_tangential: 0.3,
            added_mass_normal: 1.0,
            added_mass_tangential: 0.4,
            minimum_breaking_load_n: None,
        };
        let seg = SegmentSpec {
            name: "s".into(),
            line_type: "t".into(),
            length_m: 1.0,
            elements: 1,
            extra_mass_kg: None,
            extra_volume_m3: None,
        };
        let env = Environment {
            water_depth_m: 100.0,
            water_density_kg_m3: 1025.0,
            gravity_m_s2: 9.81,
            seabed: Default::default(),
        };
        Section::new(&lt, &seg, &env)
    }

    #[test]
    fn force_only_path_equals_the_full_load() {
        let full = morison(&section(), &kin(), &water()).f;
        let only = morison_force(&section(), &kin(), &water());
        assert!((full - only).norm() <= 1e-12 * full.norm());
    }

    fn kin() -> PointKinematics {
        PointKinematics {
            r: Vector3::new(1.0, 2.0, -30.0),
            r_x: Vector3::new(0.6, 0.1, -0.79),
            v: Vector3::new(0.3, -0.2, 0.5),
            a: Vector3::new(-0.4, 0.9, 0.2),
        }
    }

    fn water() -> FluidKinematics {
        FluidKinematics {
            velocity: Vector3::new(1.1, 0.2, -0.3),
            acceleration: Vector3::new(0.5, 0.0, 0.7),
            dynamic_pressure_pa: 0.0,
        }
    }

    /// Central differences of the load with respect to one kinematic vector.
    fn fd(which: usize) -> Matrix3<f64> {
        let sec = section();
        let h = 1e-6;
        let mut m = Matrix3::zeros();
        for j in 0..3 {
            let mut kp = kin();
            let mut km = kin();
            let (p, q) = match which {
                0 => (&mut kp.v, &mut km.v),
                1 => (&mut kp.a, &mut km.a),
                _ => (&mut kp.r_x, &mut km.r_x),
            };
            p[j] += h;
            q[j] -= h;
            let col = (morison(&sec, &kp, &water()).f - morison(&sec, &km, &water()).f) / (2.0 * h);
            m.set_column(j, &col);
        }
        m
    }

    #[test]
    fn morison_tangents_match_central_differences() {
        let l = morison(&section(), &kin(), &water());
        for (which, exact) in [(0, l.d_v), (1, l.d_a), (2, l.d_rx)] {
            let err = (fd(which) - exact).norm();
            assert!(
                err < 1e-6 * exact.norm().max(1.0),
                "derivative {which}: error {err}"
            );
        }
    }

    #[test]
    fn drag_opposes_motion_in_still_water() {
        let mut k = kin();
        k.r_x = Vector3::x();
        k.v = Vector3::new(0.0, 0.0, 2.0);
        k.a = Vector3::zeros();
        let l = morison(&section(), &k, &FluidKinematics::default());
        let sec = section();
        // Normal motion only: f = −½ρD C_dn |v| v.
        let expected = -sec.drag_normal_kg_per_m2 * 2.0 * 2.0;
        assert!((l.f.z - expected).abs() < 1e-9 * expected.abs());
        assert!(l.f.x.abs() < 1e-12 && l.f.y.abs() < 1e-12);
    }
}
