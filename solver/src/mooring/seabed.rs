//! Seabed contact per unit length: a flat seabed at z = −depth resisting the penetration
//! g = −depth − z by a penalty spring and a damper, with optional regularised Coulomb friction
//! on the horizontal velocity (the penalty approach of the paper's line–seabed contact,
//! Sec. 3.1, with the stiffness of the campaign file).
//!
//! To let Newton's method converge when nodes touch down or lift off within a step, the spring
//! is smoothed over |g| < g₀ (g₀ = [`CONTACT_SMOOTHING_M`]):
//! f_s = 0 for g ≤ −g₀, k (g + g₀)² / (4 g₀) for |g| < g₀, k g for g ≥ g₀ (C¹, energy
//! k (g + g₀)³ / (12 g₀), resp. 2k g₀²/3 + k (g² − g₀²)/2), and the damper −c v_z is scaled by
//! the same smooth contact fraction s(g) = clamp((g + g₀) / (2 g₀), 0, 1). With the paper
//! stiffness (1e6 N/m²) a chain of 980 N/m settles 0.6 mm above the plane instead of 1 mm below
//! it. Friction: f_h = −μ f_z v_h / √(|v_h|² + v_ε²) while f_z > 0.

use nalgebra::{Matrix3, Vector3};

use super::loads::PointLoad;
use super::section::Section;
use super::spec::SeabedSpec;

/// Half-width of the smoothed contact transition (m).
pub(crate) const CONTACT_SMOOTHING_M: f64 = 0.005;

/// Spring force per unit length, its derivative with respect to g, and the contact fraction
/// with its derivative.
fn spring(k: f64, g: f64) -> (f64, f64, f64, f64) {
    let g0 = CONTACT_SMOOTHING_M;
    if g <= -g0 {
        (0.0, 0.0, 0.0, 0.0)
    } else if g < g0 {
        let x = g + g0;
        (
            k * x * x / (4.0 * g0),
            k * x / (2.0 * g0),
            x / (2.0 * g0),
            1.0 / (2.0 * g0),
        )
    } else {
        (k * g, k, 1.0, 0.0)
    }
}

/// Contact load at position `r` moving at `v`, above a seabed at `depth_m`.
pub(crate) fn seabed_load(
    sec: &Section,
    bed: &SeabedSpec,
    depth_m: f64,
    r: &Vector3<f64>,
    v: &Vector3<f64>,
) -> PointLoad {
    let mut load = PointLoad::zero();
    let g = -depth_m - r.z;
    let (fs, dfs, frac, dfrac) = spring(sec.seabed_stiffness_n_per_m2, g);
    if frac <= 0.0 {
        return load;
    }
    let c = sec.seabed_damping_n_s_per_m2;
    let fz = fs - c * frac * v.z;
    // ∂g/∂z = −1.
    let dfz_dz = -dfs + c * dfrac * v.z;
    let dfz_dvz = -c * frac;
    load.f.z = fz;
    load.d_r[(2, 2)] = dfz_dz;
    load.d_v[(2, 2)] = dfz_dvz;
    let mu = bed.friction_coefficient;
    if mu > 0.0 && fz > 0.0 {
        let vh = Vector3::new(v.x, v.y, 0.0);
        let s = (vh.norm_squared() + bed.friction_velocity_m_s * bed.friction_velocity_m_s).sqrt();
        let dir = vh / s;
        load.f -= dir * (mu * fz);
        let mut ddir = Matrix3::zeros();
        for i in 0..2 {
            for j in 0..2 {
                ddir[(i, j)] = if i == j { 1.0 / s } else { 0.0 } - vh[i] * vh[j] / (s * s * s);
            }
        }
        load.d_v -= ddir * (mu * fz);
        for i in 0..2 {
            load.d_r[(i, 2)] -= dir[i] * mu * dfz_dz;
            load.d_v[(i, 2)] -= dir[i] * mu * dfz_dvz;
        }
    }
    load
}

/// The force of [`seabed_load`] alone, without its derivatives (N/m).
pub(crate) fn seabed_force(
    sec: &Section,
    bed: &SeabedSpec,
    depth_m: f64,
    r: &Vector3<f64>,
    v: &Vector3<f64>,
) -> Vector3<f64> {
    let g = -depth_m - r.z;
    let (fs, _, frac, _) = spring(sec.seabed_stiffness_n_per_m2, g);
    if frac <= 0.0 {
        return Vector3::zeros();
    }
    let fz = fs - sec.seabed_damping_n_s_per_m2 * frac * v.z;
    let mut f = Vector3::new(0.0, 0.0, fz);
    let mu = bed.friction_coefficient;
    if mu > 0.0 && fz > 0.0 {
        let vh = Vector3::new(v.x, v.y, 0.0);
        let s = (vh.norm_squared() + bed.friction_velocity_m_s * bed.friction_velocity_m_s).sqrt();
        f -= (vh / s) * (mu * fz);
    }
    f
}

/// Energy stored in the seabed spring per unit length at `r` (J/m).
pub(crate) fn seabed_energy(sec: &Section, depth_m: f64, r: &Vector3<f64>) -> f64 {
    let g = -depth_m - r.z;
    let g0 = CONTACT_SMOOTHING_M;
    let k = sec.seabed_stiffness_n_per_m2;
    if g <= -g0 {
        0.0
    } else if g < g0 {
        k * (g + g0).powi(3) / (12.0 * g0)
    } else {
        2.0 * k * g0 * g0 / 3.0 + 0.5 * k * (g * g - g0 * g0)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::mooring::spec::{Environment, LineTypeSpec, SegmentSpec};

    fn section() -> Section {
        let lt = LineTypeSpec {
            mass_kg_per_m: 114.9,
            submerged_weight_n_per_m: 980.4,
            axial_stiffness_n: 4.93e8,
            bending_stiffness_nm2: 0.0,
            bending_stiffness_min_nm2: None,
            torsional_stiffness_nm2: None,
            hydrodynamic_diameter_m: 0.1368,
            drag_normal: 2.4,
            drag_tangential: 1.15,
            added_mass_normal: 1.0,
            added_mass_tangential: 0.5,
            minimum_breaking_load_n: None,
        };
        let seg = SegmentSpec {
            name: "c".into(),
            line_type: "c".into(),
            length_m: 10.0,
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
        let sec = section();
        let v = Vector3::new(0.3, -0.2, 0.05);
        for mu in [0.0, 0.4] {
            let bed = SeabedSpec {
                friction_coefficient: mu,
                ..SeabedSpec::default()
            };
            for z in [-100.0 - 0.004, -100.0 + 0.002, -100.0 - 0.02, -99.0] {
                let r = Vector3::new(1.0, 2.0, z);
                let full = seabed_load(&sec, &bed, 100.0, &r, &v).f;
                assert_eq!(
                    seabed_force(&sec, &bed, 100.0, &r, &v),
                    full,
                    "z {z}, μ {mu}"
                );
            }
        }
    }

    #[test]
    fn smoothed_spring_force_is_the_derivative_of_its_energy() {
        let sec = section();
        let bed = SeabedSpec::default();
        let h = 1e-7;
        for &z in &[-100.0 - 0.004, -100.0 + 0.002, -100.0 - 0.02] {
            let e = |z: f64| seabed_energy(&sec, 100.0, &Vector3::new(0.0, 0.0, z));
            let f = seabed_load(
                &sec,
                &bed,
                100.0,
                &Vector3::new(0.0, 0.0, z),
                &Vector3::zeros(),
            )
            .f
            .z;
            let de = -(e(z + h) - e(z - h)) / (2.0 * h);
            assert!(
                (de - f).abs() < 1e-6 * f.abs().max(1.0),
                "z {z}: {de} vs {f}"
            );
        }
    }

    #[test]
    fn seabed_tangent_with_friction_matches_central_differences() {
        let sec = section();
        let bed = SeabedSpec {
            friction_coefficient: 0.6,
            ..Default::default()
        };
        let r = Vector3::new(3.0, 1.0, -100.002);
        // Inside the smoothing band, where every term varies.
        let v = Vector3::new(0.004, -0.007, 0.01);
        let l = seabed_load(&sec, &bed, 100.0, &r, &v);
        let h = 1e-8;
        for j in 0..3 {
            let mut rp = r;
            let mut rm = r;
            rp[j] += h;
            rm[j] -= h;
            let dr = (seabed_load(&sec, &bed, 100.0, &rp, &v).f
                - seabed_load(&sec, &bed, 100.0, &rm, &v).f)
                / (2.0 * h);
            let mut vp = v;
            let mut vm = v;
            vp[j] += h;
            vm[j] -= h;
            let dv = (seabed_load(&sec, &bed, 100.0, &r, &vp).f
                - seabed_load(&sec, &bed, 100.0, &r, &vm).f)
                / (2.0 * h);
            assert!(
                (dr - l.d_r.column(j)).norm() < 1e-6 * l.d_r.norm(),
                "d_r col {j}"
            );
            assert!(
                (dv - l.d_v.column(j)).norm() < 1e-5 * l.d_v.norm(),
                "d_v col {j}"
            );
        }
    }

    #[test]
    fn lying_line_is_carried_by_the_spring_without_force_above_the_seabed() {
        let sec = section();
        let bed = SeabedSpec::default();
        // Beyond the smoothing band the spring is linear: k g.
        let r = Vector3::new(0.0, 0.0, -100.0 - 0.01);
        let l = seabed_load(&sec, &bed, 100.0, &r, &Vector3::zeros());
        assert!((l.f.z - 1.0e4).abs() < 1e-6);
        let above = seabed_load(
            &sec,
            &bed,
            100.0,
            &Vector3::new(0.0, 0.0, -99.0),
            &Vector3::zeros(),
        );
        assert_eq!(above.f, Vector3::zeros());
    }
}
