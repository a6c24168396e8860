//! Verification of the node-to-node frictional contact element against closed-form results:
//! normal force of two crossed wires pressed together (penalty and Hertz), the Coulomb energy
//! dissipated by a tangential cycle, and the circumferential slip of rolling/spinning wires.

use std::f64::consts::PI;

use moorfret_solver::beam::rotation::exp_so3;
use moorfret_solver::contact::hertz::{
    tangential_modulus, CrossedCylinders, ElasticMaterial, HertzModel,
};
use moorfret_solver::contact::{
    ContactHistory, ContactPair, ContactParameters, ContactStatus, ElementVector, NodeKinematics,
    NormalLaw, TangentialLaw,
};
use nalgebra::Vector3;

const R: f64 = 2.15e-3;
const E: f64 = 210e9;
const NU: f64 = 0.3;

/// Wire 1 along x at the origin, wire 2 at `angle` from it in the x-y plane, above it along z.
fn crossed(
    params: &ContactParameters,
    angle: f64,
) -> (
    ContactPair,
    ContactHistory,
    NodeKinematics,
    NodeKinematics,
    Vector3<f64>,
    Vector3<f64>,
) {
    let t1 = Vector3::x();
    let t2 = Vector3::new(angle.cos(), angle.sin(), 0.0);
    let a = NodeKinematics::at(Vector3::zeros());
    let b = NodeKinematics::at(Vector3::new(0.0, 0.0, 2.0 * R));
    let (pair, hist) = ContactPair::new(params, R, R, &a, &t1, &b, &t2).unwrap();
    (pair, hist, a, b, t1, t2)
}

fn params(normal: NormalLaw, tangential: TangentialLaw, mu: f64) -> ContactParameters {
    ContactParameters {
        normal,
        tangential,
        friction_coefficient: mu,
        young_modulus_pa: E,
        poisson_ratio: NU,
    }
}

#[test]
fn crossed_wires_pressed_together_give_the_penalty_force() {
    let eps = 2e8;
    let p = params(
        NormalLaw::Penalty {
            stiffness_n_per_m: eps,
        },
        TangentialLaw::ElasticSlip {
            elastic_slip_m: 1e-7,
        },
        0.5,
    );
    let (pair, hist, a, b, _, _) = crossed(&p, 0.4);
    let delta = 3e-6;
    let b = NodeKinematics::at(b.position - delta * Vector3::z());
    let mut f = ElementVector::zeros();
    let r = pair.residual(&hist, &a, &b, &mut f);
    assert_eq!(r.status, ContactStatus::Stick);
    assert!((r.normal_force_n - eps * delta).abs() <= 1e-9 * eps * delta);
    // Internal force on node 2 is −f_N n (the contact pushes wire 2 away along +z), on node 1 +f_N n.
    assert!((f[8] + eps * delta).abs() <= 1e-9 * eps * delta);
    assert!((f[2] - eps * delta).abs() <= 1e-9 * eps * delta);
    assert!(r.tangential_force_n <= 1e-9 * r.normal_force_n);
}

#[test]
fn crossed_wires_at_right_angle_follow_hertz_sphere_on_flat() {
    // Equal cylinders crossed at 90° behave as a sphere of radius r on a flat:
    // P = (4/3) E* r^{1/2} δ^{3/2} (Johnson 1985, §4.2).
    let p = params(NormalLaw::Hertz, TangentialLaw::Mindlin, 0.5);
    let (pair, hist, a, b, _, _) = crossed(&p, 0.5 * PI);
    let es = E / (2.0 * (1.0 - NU * NU));
    for delta in [1e-7_f64, 1e-6, 5e-6] {
        let bb = NodeKinematics::at(b.position - delta * Vector3::z());
        let mut f = ElementVector::zeros();
        let r = pair.residual(&hist, &a, &bb, &mut f);
        let expect = 4.0 / 3.0 * es * R.sqrt() * delta.powf(1.5);
        assert!(
            (r.normal_force_n / expect - 1.0).abs() < 1e-9,
            "δ = {delta}: {} vs {expect}",
            r.normal_force_n
        );
    }
}

/// Work of the tangential force over one closed displacement cycle +a → −a → +a along the
/// tangent of wire 1, after a first loading 0 → +a, at constant indentation.
fn cycle_work(
    pair: &ContactPair,
    mut hist: ContactHistory,
    a: &NodeKinematics,
    b: &NodeKinematics,
    dir: Vector3<f64>,
    amp: f64,
    step: f64,
) -> (f64, f64, f64) {
    let n = (amp / step).round() as usize;
    let mut path: Vec<f64> = (0..=n).map(|k| k as f64 * step).collect();
    path.extend((1..=2 * n).map(|k| amp - k as f64 * step));
    path.extend((1..=2 * n).map(|k| -amp + k as f64 * step));
    let mut f = ElementVector::zeros();
    let (mut work, mut fmax, mut fnormal) = (0.0, 0.0_f64, 0.0);
    let mut prev: Option<(f64, f64)> = None;
    for (k, &u) in path.iter().enumerate() {
        let bb = NodeKinematics {
            position: b.position + u * dir,
            rotation: b.rotation,
        };
        let r = pair.residual(&hist, a, &bb, &mut f);
        hist.accept(&r);
        let force = Vector3::new(f[6], f[7], f[8]).dot(&dir);
        fmax = fmax.max(r.tangential_force_n);
        fnormal = r.normal_force_n;
        if k > n {
            if let Some((u0, f0)) = prev {
                work += 0.5 * (force + f0) * (u - u0);
            }
        }
        prev = Some((u, force));
    }
    (work, fmax, fnormal)
}

#[test]
fn tangential_cycle_dissipates_the_coulomb_energy_with_elastic_slip() {
    // Elastic-perfectly-plastic loop: elastic branches of slope μ f_N/γ_e, plateaus at ±μ f_N.
    // Over +a → −a → +a the area is 2 μ f_N × 2 (a − γ_e) = 4 μ f_N (a − γ_e).
    let (mu, ge, eps, delta) = (0.5, 1e-6, 2e8, 2e-6);
    let p = params(
        NormalLaw::Penalty {
            stiffness_n_per_m: eps,
        },
        TangentialLaw::ElasticSlip { elastic_slip_m: ge },
        mu,
    );
    let (pair, hist, a, b, t1, _) = crossed(&p, 0.5);
    let b = NodeKinematics::at(b.position - delta * Vector3::z());
    let amp = 5.0 * ge;
    // Steps of γ_e/4 land on every corner of the loop: the trapezoidal rule is then exact.
    let (work, fmax, fnormal) = cycle_work(&pair, hist, &a, &b, t1, amp, 0.25 * ge);
    let fn_expect = eps * delta;
    assert!((fnormal - fn_expect).abs() <= 1e-9 * fn_expect);
    assert!((fmax - mu * fn_expect).abs() <= 1e-9 * mu * fn_expect);
    let expect = 4.0 * mu * fn_expect * (amp - ge);
    assert!(
        (work / expect - 1.0).abs() < 1e-9,
        "work {work} vs {expect}"
    );
}

#[test]
fn tangential_cycle_dissipates_the_coulomb_energy_with_hertz_and_mindlin() {
    // Mindlin initial stiffness k_T = 8 G* c, c = (ab)^{1/2} of the Hertz ellipse; the loop
    // area is 4 μ f_N (a − μ f_N / k_T).
    let mu = 0.5;
    let angle = 0.6;
    let p = params(NormalLaw::Hertz, TangentialLaw::Mindlin, mu);
    let (pair, hist, a, b, t1, _) = crossed(&p, angle);
    let delta: f64 = 2e-6;
    let b = NodeKinematics::at(b.position - delta * Vector3::z());
    let h = hertz(angle);
    let fnorm = h.force_coefficient() * delta.powf(1.5);
    let kt = 8.0 * tangential_modulus(E, NU, E, NU) * h.radius_coefficient() * fnorm.cbrt();
    let gamma = mu * fnorm / kt;
    let amp = 4.0 * gamma;
    let (work, fmax, fnormal) = cycle_work(&pair, hist, &a, &b, t1, amp, 0.25 * gamma);
    assert!((fnormal / fnorm - 1.0).abs() < 1e-9);
    assert!((fmax / (mu * fnorm) - 1.0).abs() < 1e-9);
    let expect = 4.0 * mu * fnorm * (amp - gamma);
    assert!(
        (work / expect - 1.0).abs() < 1e-9,
        "work {work} vs {expect}"
    );
}

/// One step of a motion of wire 2: rotation ψ about its own axis and axis advance `advance_m`
/// along t₂ × n.
fn step_slip(psi: f64, advance_m: f64) -> (Vector3<f64>, Vector3<f64>) {
    let p = params(
        NormalLaw::Penalty {
            stiffness_n_per_m: 2e8,
        },
        TangentialLaw::ElasticSlip {
            elastic_slip_m: 1.0,
        },
        0.5,
    );
    let (pair, hist, a, b, _, t2) = crossed(&p, 1.0);
    let n = Vector3::z();
    let b = NodeKinematics {
        position: b.position - 1e-6 * n + advance_m * t2.cross(&n),
        rotation: exp_so3(&(psi * t2)),
    };
    let mut f = ElementVector::zeros();
    let r = pair.residual(&hist, &a, &b, &mut f);
    (r.slip_increment, t2.cross(&n))
}

#[test]
fn rolling_spinning_and_sliding_give_the_circumferential_slip_of_the_r_n_terms() {
    let psi = 0.02;
    // Rolling without slip: the axis advances by r ψ along t₂ × n while the wire turns by ψ.
    // The material point that was in contact moves on a circle; the straight-line (chord)
    // approximation of Eq. 9 leaves g_T^Δ = r (ψ − sin ψ) along t₂ × n.
    let (g, e) = step_slip(psi, R * psi);
    assert!((g - R * (psi - psi.sin()) * e).norm() <= 1e-18, "{g}");
    // Spinning in place: only the circumferential term, g_T^Δ = −r sin ψ (t₂ × n).
    let (g, e) = step_slip(psi, 0.0);
    assert!((g + R * psi.sin() * e).norm() <= 1e-15 * R, "{g}");
    // Sliding of the axis without rotation: g_T^Δ = r ψ (t₂ × n).
    let (g, e) = step_slip(0.0, R * psi);
    assert!((g - R * psi * e).norm() <= 1e-15 * R, "{g}");
}

#[test]
fn contacts_detected_on_the_benchmark_strand_start_closed_with_an_outward_radial_normal() {
    use moorfret_solver::strand::contacts::{find_contacts, ContactSearchParameters};
    use moorfret_solver::strand::profile::profile_from_json;
    let text = include_str!(concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/../campaigns/benchmarks/strand_1_6_1.json"
    ));
    let strand = profile_from_json(text).unwrap().validate().unwrap();
    let wires = strand.wires();
    let set = find_contacts(&strand, &ContactSearchParameters::default()).unwrap();
    let p = ContactParameters::default();
    for c in &set.contacts {
        let (wi, wo) = (&wires[c.inner.0], &wires[c.outer.0]);
        let a = NodeKinematics::at(c.inner_position);
        let b = NodeKinematics::at(c.outer_position);
        let (pair, hist) = ContactPair::new(
            &p,
            wi.radius_m,
            wo.radius_m,
            &a,
            &wi.helix.tangent(c.z_m),
            &b,
            &wo.helix.tangent(c.z_m),
        )
        .unwrap();
        let mut f = ElementVector::zeros();
        let r = pair.residual(&hist, &a, &b, &mut f);
        assert!(
            r.normal_gap_m.abs() < 1e-15,
            "{c:?}: g_N = {:e}",
            r.normal_gap_m
        );
        let radial = Vector3::new(c.outer_position.x, c.outer_position.y, 0.0).normalize();
        assert!((r.normal - radial).norm() < 1e-12, "{c:?}");
        assert_eq!(hist.sliding_m.map(|x| (x.abs() < 1e-15) as u8), [1, 1]);
    }
}

/// The Hertz contact of the two wires of these tests crossing at `angle`.
fn hertz(angle: f64) -> HertzModel {
    let steel = ElasticMaterial {
        youngs_modulus_pa: E,
        poisson_ratio: NU,
    };
    HertzModel::crossed_cylinders(&CrossedCylinders::of_one_material(R, R, angle, steel)).unwrap()
}
