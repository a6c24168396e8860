use std::f64::consts::PI;

use super::criterion::{cycle_life, ContactStressLaw, CycleLoad, STICK_RATIO_FOR_STICK};
use super::field::{
    hamilton_tangential_stress, hertz_normal_stress, partial_slip_tangential_stress,
    traction_stress, EllipseHotSpot, Kernel, Stress,
};
use super::material::{StrainLife, WireSurface};
use crate::contact::hertz::{CrossedCylinders, ElasticMaterial, HertzModel};
use crate::fretting::indicators::FrettingRegime;

const NU: f64 = 0.3;

fn rel(got: f64, want: f64, scale: f64) -> f64 {
    (got - want).abs() / scale
}

fn perpendicular_wires() -> HertzModel {
    let m = ElasticMaterial::default();
    HertzModel::crossed_cylinders(&CrossedCylinders {
        radius_1_m: 2.3e-3,
        radius_2_m: 2.3e-3,
        crossing_angle_rad: PI / 2.0,
        material_1: m,
        material_2: m,
    })
    .unwrap()
}

#[test]
fn hamilton_normal_stresses_match_boussinesq_integrated_over_the_hertz_pressure() {
    // Surface (z = 1e-4 a, the limit from inside the body) and subsurface points, inside,
    // at and outside the contact edge, on and off the x axis.
    let points = [
        [0.0, 0.0, 0.5],
        [0.3, 0.0, 0.48],
        [-1.0, 0.0, 0.05],
        [0.5, 0.4, 0.3],
        [1.3, 0.2, 0.2],
        [-0.6, 0.0, 1e-4],
        [1.5, 0.0, 1e-4],
        [0.2, -0.7, 0.9],
    ];
    for p in points {
        let closed = hertz_normal_stress(1.0, 1.0, NU, p[0], p[1], p[2]);
        let numeric = traction_stress(Kernel::Normal, NU, 1.0, 1.0, 1.0, p, 3);
        assert_close(&closed, &numeric, 0.01, &format!("{p:?}"));
    }
}

#[test]
fn hertz_normal_stresses_match_johnson_on_the_surface_and_the_axis() {
    // Johnson eq. 3.41 (surface, r < a) and 3.46 (axis).
    for r in [0.2_f64, 0.6, 0.95] {
        let s = hertz_normal_stress(1.0, 1.0, NU, r, 0.0, 0.0);
        let q = (1.0 - r * r).sqrt();
        let radial = (1.0 - 2.0 * NU) / 3.0 / (r * r) * (1.0 - q.powi(3)) - q;
        assert!(rel(s.xx, radial, 1.0) < 1e-12, "r = {r}");
        assert!(rel(s.zz, -q, 1.0) < 1e-12);
    }
    for z in [0.3_f64, 1.0, 2.5] {
        let s = hertz_normal_stress(1.0, 1.0, NU, 0.0, 0.0, z);
        let radial = -(1.0 + NU) * (1.0 - z * (1.0 / z).atan()) + 0.5 / (1.0 + z * z);
        assert!(rel(s.xx, radial, 1.0) < 1e-12);
        assert!(rel(s.zz, -1.0 / (1.0 + z * z), 1.0) < 1e-12);
    }
}

#[test]
fn tangential_traction_gives_the_closed_form_surface_stresses_inside_the_contact() {
    // q = q₀√(1 − r²/a²) in +x: on the surface inside the circle σ_x = −(π/8)(4 + ν) q₀ x/a
    // and τ_xz = −q (Hamilton & Goodman 1966; Johnson §7.1). Evaluated at z = 1e-4 a.
    for x in [-0.7_f64, -0.3, 0.4] {
        let s = traction_stress(Kernel::Tangential, NU, 1.0, 1.0, 1.0, [x, 0.0, 1e-4], 3);
        let sx = -PI / 8.0 * (4.0 + NU) * x;
        let q = (1.0 - x * x).sqrt();
        assert!(rel(s.xx, sx, sx.abs()) < 0.01, "x = {x}: {} vs {sx}", s.xx);
        assert!(rel(s.xz, -q, q) < 0.01, "x = {x}: {} vs {}", s.xz, -q);
    }
}

#[test]
fn largest_surface_tension_of_a_sliding_contact_is_at_the_trailing_edge() {
    // σ_x,max = p₀[(1 − 2ν)/3 + π(4 + ν)μ/8] at x = −a (Hamilton 1983; Johnson §7.1).
    let mu = 0.3;
    let expected = (1.0 - 2.0 * NU) / 3.0 + PI * (4.0 + NU) * mu / 8.0;
    // Hamilton's closed forms on the surface (z = 1e-9 a: the 1/S terms are 0/0 on the edge).
    let along = |x: f64| {
        let n = hertz_normal_stress(1.0, 1.0, NU, x, 0.0, 1e-9);
        let t = hamilton_tangential_stress(1.0, NU, x, 0.0, 1e-9);
        n.xx + mu * t.xx
    };
    let edge = along(-1.0);
    // The residue (1e-4) is the offset of the evaluation point from the edge circle.
    assert!(rel(edge, expected, expected) < 1e-3, "{edge} vs {expected}");
    for x in [-1.6, -1.2, -0.9, -0.5, 0.0, 0.5, 0.9, 1.0, 1.3] {
        assert!(along(x) < edge, "x = {x}: {} ≥ {edge}", along(x));
    }
}

#[test]
fn cattaneo_stick_radius_is_half_the_contact_at_seven_eighths_of_the_limit() {
    let model = perpendicular_wires();
    let law = ContactStressLaw::default();
    let p = 400.0;
    let mu = 0.12;
    let life = |q: f64| {
        cycle_life(
            &model,
            &EllipseHotSpot::shared(model.axis_ratio, NU),
            mu,
            &law,
            &CycleLoad {
                normal_force_n: p,
                tangential_amplitude_n: q,
                slip_amplitude_m: 1e-6,
                bulk_max_pa: 500e6,
                bulk_min_pa: 450e6,
            },
        )
        .unwrap()
    };
    let half = life(7.0 / 8.0 * mu * p);
    assert!(
        (half.stick_ratio - 0.5).abs() < 1e-12,
        "{}",
        half.stick_ratio
    );
    assert_eq!(half.regime, FrettingRegime::PartialSlip);
    assert_eq!(life(mu * p).regime, FrettingRegime::GrossSlip);
    assert_eq!(life(2.0 * mu * p).stick_ratio, 0.0);
    let small = life(0.01 * mu * p);
    assert!(small.stick_ratio >= STICK_RATIO_FOR_STICK);
    assert_eq!(small.regime, FrettingRegime::Stick);
    // More tangential load, shorter life; gross slip records wear energy 4μPδ.
    assert!(life(0.3 * mu * p).cycles_to_initiation > half.cycles_to_initiation);
    assert!(half.cycles_to_initiation > life(mu * p).cycles_to_initiation);
    assert_eq!(half.wear_energy_j, 0.0);
    assert!((life(mu * p).wear_energy_j - 4.0 * mu * p * 1e-6).abs() < 1e-15);
}

fn largest_component(s: &Stress) -> f64 {
    [s.xx, s.yy, s.zz, s.xy, s.xz, s.yz]
        .iter()
        .fold(0.0_f64, |m, v| m.max(v.abs()))
}

fn assert_close(closed: &Stress, numeric: &Stress, tol: f64, what: &str) {
    let scale = largest_component(closed);
    for (name, c, n) in [
        ("xx", closed.xx, numeric.xx),
        ("yy", closed.yy, numeric.yy),
        ("zz", closed.zz, numeric.zz),
        ("xy", closed.xy, numeric.xy),
        ("xz", closed.xz, numeric.xz),
        ("yz", closed.yz, numeric.yz),
    ] {
        assert!(
            rel(c, n, scale) < tol,
            "{name} at {what}: closed form {c:.6} numeric {n:.6}"
        );
    }
}

#[test]
fn hamilton_tangential_stresses_match_cerruti_integrated_over_the_traction() {
    // Surface (z = 1e-4 a) and subsurface points, inside, at and outside the edge, on and off
    // the slip axis, on the trailing and the leading side.
    let points = [
        [-1.0, 0.0, 0.05],
        [-0.5, 0.0, 1e-4],
        [0.4, 0.0, 1e-4],
        [0.3, 0.4, 0.3],
        [-1.3, 0.2, 0.2],
        [0.2, -0.7, 0.9],
        [1.2, 0.5, 0.6],
        [-0.8, 0.0, 0.5],
    ];
    for p in points {
        let closed = hamilton_tangential_stress(1.0, NU, p[0], p[1], p[2]);
        let numeric = traction_stress(Kernel::Tangential, NU, 1.0, 1.0, 1.0, p, 3);
        assert_close(&closed, &numeric, 0.01, &format!("{p:?}"));
    }
}

#[test]
fn partial_slip_field_is_the_superposition_of_two_sliding_fields() {
    // Against the integration of the partial-slip traction itself: the full circle less the
    // stick-zone correction, each integrated numerically.
    let (s, p) = (0.6, [-1.0, 0.0, 0.03]);
    let closed = partial_slip_tangential_stress(1.0, s, NU, p[0], p[1], p[2]);
    let full = traction_stress(Kernel::Tangential, NU, 1.0, 1.0, 1.0, p, 3);
    let stick = traction_stress(Kernel::Tangential, NU, s, s, s, p, 3);
    assert_close(
        &closed,
        &full.combine(1.0, stick, -1.0),
        0.01,
        "trailing edge",
    );
    // No tangential load: no field; almost sliding: the sliding field.
    let none = partial_slip_tangential_stress(1.0, 1.0, NU, p[0], p[1], p[2]);
    assert!(largest_component(&none) < 1e-12, "{none:?}");
    let almost = partial_slip_tangential_stress(1.0, 1e-3, NU, p[0], p[1], p[2]);
    let sliding = hamilton_tangential_stress(1.0, NU, p[0], p[1], p[2]);
    assert!(rel(almost.xx, sliding.xx, sliding.xx.abs()) < 1e-3);
}

#[test]
fn quadrature_converges_from_level_two_to_three() {
    for p in [[-1.0, 0.0, 0.003], [-2.5, 0.0, 0.05], [-1.0, 0.0, 0.5]] {
        let l2 = traction_stress(Kernel::Tangential, NU, 1.0, 1.0, 1.0, p, 2);
        let l3 = traction_stress(Kernel::Tangential, NU, 1.0, 1.0, 1.0, p, 3);
        let scale = l3.xx.abs().max(l3.xz.abs());
        assert!(
            rel(l2.xx, l3.xx, scale) < 2e-3,
            "{p:?}: {} vs {}",
            l2.xx,
            l3.xx
        );
        assert!(rel(l2.xz, l3.xz, scale) < 2e-3, "{p:?}");
    }
}

#[test]
fn equivalent_circle_error_at_the_hot_spot_is_bounded_for_strand_crossings() {
    // Crossing of the paper strand's layers: wires of 2.3 mm radius crossed at about 36°
    // (lay angles 18° and −18.5°). The sliding stress at L/2 below the trailing edge (the end
    // of the ellipse's axis along the slip), elliptical patch against the equivalent circle of
    // equal area and peak pressure.
    let m = ElasticMaterial::default();
    let model = HertzModel::crossed_cylinders(&CrossedCylinders {
        radius_1_m: 2.3e-3,
        radius_2_m: 2.3e-3,
        crossing_angle_rad: 36.5_f64.to_radians(),
        material_1: m,
        material_2: m,
    })
    .unwrap();
    let c = model.contact(300.0).unwrap();
    let (a, b, p0) = (c.semi_major_m, c.semi_minor_m, c.peak_pressure_pa);
    let req = (a * b).sqrt();
    let depth = 0.5 * WireSurface::Galvanised.constants().critical_distance_m;
    let mu = 0.12;
    let at = |ra: f64, rb: f64, x: f64| {
        let n = traction_stress(Kernel::Normal, NU, p0, ra, rb, [x, 0.0, depth], 2);
        let t = traction_stress(Kernel::Tangential, NU, mu * p0, ra, rb, [x, 0.0, depth], 2);
        n.combine(1.0, t, 1.0)
    };
    let circle = at(req, req, -req);
    // Slip along the major axis and along the minor axis.
    let along_major = at(a, b, -a);
    let along_minor = at(b, a, -b);
    let err_major = (along_major.xx - circle.xx) / circle.xx;
    let err_minor = (along_minor.xx - circle.xx) / circle.xx;
    // Measured (docs/fretting-fatigue.md): the circle understates σ_xx by 41 % (the ellipse's
    // is 1.70 times the circle's) for slip along the major axis, and misses its sign across it
    // (a slender patch's edge is in compression across its width). Pinned so that the
    // documented figures stay true.
    eprintln!(
        "axis ratio {:.3}: sigma_xx at the hot spot, ellipse/circle - 1: slip along major {:+.3}, along minor {:+.3}",
        b / a,
        err_major,
        err_minor
    );
    assert!((0.65..0.75).contains(&err_major), "{err_major}");
    assert!((-5.6..-5.0).contains(&err_minor), "{err_minor}");
}

#[test]
fn strain_life_inverts_its_own_curves() {
    let m = StrainLife::cold_drawn_wire(WireSurface::Bright);
    m.validate().unwrap();
    for n in [1e3_f64, 1e5, 1e7, 1e9] {
        let two_n = 2.0 * n;
        let (sf, b, ef, c, e) = (
            m.strength_coefficient_pa,
            m.strength_exponent,
            m.ductility_coefficient,
            m.ductility_exponent,
            m.youngs_modulus_pa,
        );
        let swt = sf * sf / e * two_n.powf(2.0 * b) + sf * ef * two_n.powf(b + c);
        assert!(rel(m.swt_life(swt), n, n) < 1e-8, "{n}");
        let g = m.shear_modulus_pa();
        let fs = sf / 3f64.sqrt() / g * two_n.powf(b) + 3f64.sqrt() * ef * two_n.powf(c);
        assert!(rel(m.fatemi_socie_life(fs), n, n) < 1e-8, "{n}");
    }
    assert_eq!(m.swt_life(0.0), f64::INFINITY);
    let sea = StrainLife::cold_drawn_wire(WireSurface::SeaWater);
    assert!(sea.swt_life(1e6) < m.swt_life(1e6));
}

#[test]
fn uniaxial_stress_reduces_swt_to_its_definition() {
    // No contact load: the bulk stress alone; SWT = σ_max Δσ/(2E).
    let model = perpendicular_wires();
    let law = ContactStressLaw::default();
    let m = law.material();
    let life = cycle_life(
        &model,
        &EllipseHotSpot::shared(model.axis_ratio, NU),
        0.12,
        &law,
        &CycleLoad {
            normal_force_n: 1e-9,
            tangential_amplitude_n: 0.0,
            slip_amplitude_m: 0.0,
            bulk_max_pa: 600e6,
            bulk_min_pa: 400e6,
        },
    )
    .unwrap();
    let swt = 600e6 * 100e6 / m.youngs_modulus_pa;
    assert!(
        rel(life.swt_pa, swt, swt) < 1e-3,
        "{} vs {swt}",
        life.swt_pa
    );
}

#[test]
fn ellipse_table_of_a_circle_reproduces_hamilton_at_the_trailing_edge() {
    let table = EllipseHotSpot::new(1.0, NU);
    for eta in [0.004, 0.03, 0.11, 0.6] {
        let n = hertz_normal_stress(1.0, 1.0, NU, -1.0, 0.0, eta);
        assert_close(&n, &table.normal(eta), 0.01, &format!("normal, eta {eta}"));
        for s in [0.0, 0.35, 0.8] {
            let t = partial_slip_tangential_stress(1.0, s, NU, -1.0, 0.0, eta);
            let got = table.tangential(eta, s);
            // Scale: the sliding field's largest component (the partial-slip field vanishes
            // as s → 1).
            let scale = largest_component(&hamilton_tangential_stress(1.0, NU, -1.0, 0.0, eta));
            for (c, g) in [
                (t.xx, got.xx),
                (t.yy, got.yy),
                (t.zz, got.zz),
                (t.xz, got.xz),
            ] {
                assert!(rel(g, c, scale) < 0.015, "eta {eta}, s {s}: {g} vs {c}");
            }
        }
    }
}

#[test]
fn ellipse_table_interpolates_the_integrated_field() {
    let k = 0.234;
    let table = EllipseHotSpot::new(k, NU);
    for (eta, s) in [
        (0.0123, 0.37),
        (0.051, 0.812),
        (0.0031, 0.155),
        (0.27, 0.64),
    ] {
        let direct_n = traction_stress(Kernel::Normal, NU, 1.0, 1.0, k, [-1.0, 0.0, eta], 2);
        assert_close(
            &direct_n,
            &table.normal(eta),
            0.01,
            &format!("normal {eta}"),
        );
        let full = traction_stress(Kernel::Tangential, NU, 1.0, 1.0, k, [-1.0, 0.0, eta], 2);
        let stick = traction_stress(Kernel::Tangential, NU, s, s, s * k, [-1.0, 0.0, eta], 2);
        let direct = full.combine(1.0, stick, -1.0);
        let got = table.tangential(eta, s);
        let scale = largest_component(&full);
        for (c, g) in [
            (direct.xx, got.xx),
            (direct.zz, got.zz),
            (direct.xz, got.xz),
        ] {
            assert!(rel(g, c, scale) < 0.015, "eta {eta}, s {s}: {g} vs {c}");
        }
    }
}
