//! Verification of the Cattaneo–Mindlin tangential law of the contact element against its
//! closed form: one crossing of two wires at constant normal force driven tangentially through
//! loading, unloading and reloading (Johnson 1985, §7.2-7.3; Mindlin & Deresiewicz 1953).
//!
//! With P the normal force, c the (equivalent) Hertz contact radius, 1/G* = (2 − ν₁)/G₁ +
//! (2 − ν₂)/G₂ and δ_s = 3μP/(16 G* c):
//! - loading:   Q = μP [1 − (1 − δ/δ_s)^{3/2}],               0 ≤ δ ≤ δ*;
//! - unloading: Q = Q* − 2μP [1 − (1 − (δ* − δ)/(2δ_s))^{3/2}], δ* ≥ δ ≥ −δ*;
//! - reloading: Q = −Q* + 2μP [1 − (1 − (δ* + δ)/(2δ_s))^{3/2}], −δ* ≤ δ ≤ δ*;
//! - gross slip at δ = δ_s on the virgin curve (Q = μP).
//!
//! Energy dissipated per cycle of amplitude ±Q* (the area of the loop; integrating the two
//! branches above, cf. Johnson 1985 §7.3 and Mindlin & Deresiewicz 1953):
//!   W = (9 μ² P²/(10 c G*)) [1 − (1 − Q*/μP)^{5/3} − (5Q*/(6μP)) (1 + (1 − Q*/μP)^{2/3})],
//! checked here against the numerical integration of the closed-form loop and against the
//! element's loop.
//!
//! The element's law is a discrete Iwan model whose corners lie on the virgin curve
//! (`moorfret_solver::contact::memory`): its curves are the chord interpolant of the closed form,
//! exact at the corners and at the onset of gross slip. The tolerances are those of that
//! interpolation: 0.5 % of μP on the curves (Masing's branches double the virgin curve's
//! error), 1 % on the loop energy for 0.05 μP ≤ Q* < μP; the measured differences are printed.

use std::f64::consts::PI;

use moorfret_solver::contact::hertz::{
    tangential_modulus, CrossedCylinders, ElasticMaterial, HertzModel,
};
use moorfret_solver::contact::{
    ContactHistory, ContactPair, ContactParameters, ContactStatus, ElementVector, NodeKinematics,
    NormalLaw, TangentialLaw,
};
use nalgebra::Vector3;

const R: f64 = 2.3e-3;
const E: f64 = 210e9;
const NU: f64 = 0.3;
const MU: f64 = 0.12;

/// Closed form of one crossing: normal force, contact radius, δ_s.
struct Crossing {
    pair: ContactPair,
    hist: ContactHistory,
    a: NodeKinematics,
    b: NodeKinematics,
    dir: Vector3<f64>,
    p: f64,
    c: f64,
    g_star: f64,
    delta_s: f64,
}

/// Wire 1 along x, wire 2 at `angle` in the x-y plane above it, pressed by `indentation`,
/// moved along wire 1 (a direction of the tangent plane: the normal force stays constant).
fn crossing(angle: f64, indentation: f64) -> Crossing {
    let params = ContactParameters {
        normal: NormalLaw::Hertz,
        tangential: TangentialLaw::CattaneoMindlin,
        friction_coefficient: MU,
        young_modulus_pa: E,
        poisson_ratio: NU,
    };
    let t1 = Vector3::x();
    let t2 = Vector3::new(angle.cos(), angle.sin(), 0.0);
    let a = NodeKinematics::at(Vector3::zeros());
    let b = NodeKinematics::at(Vector3::new(0.0, 0.0, 2.0 * R));
    let (pair, hist) = ContactPair::new(&params, R, R, &a, &t1, &b, &t2).unwrap();
    let b = NodeKinematics::at(b.position - indentation * Vector3::z());
    let h = hertz(angle);
    let p = h.force_coefficient() * indentation.powf(1.5);
    let c = h.radius_coefficient() * p.cbrt();
    let g_star = tangential_modulus(E, NU, E, NU);
    Crossing {
        pair,
        hist,
        a,
        b,
        dir: t1,
        p,
        c,
        g_star,
        delta_s: 3.0 * MU * p / (16.0 * g_star * c),
    }
}

impl Crossing {
    /// Evaluates at tangential displacement `u` (m), accepts, returns (Q along dir, status).
    fn step(&mut self, u: f64) -> (f64, ContactStatus, f64) {
        let b = NodeKinematics {
            position: self.b.position + u * self.dir,
            rotation: self.b.rotation,
        };
        let mut f = ElementVector::zeros();
        let r = self.pair.residual(&self.hist, &self.a, &b, &mut f);
        self.hist.accept(&r);
        (
            r.tangential_force.dot(&self.dir),
            r.status,
            r.normal_force_n,
        )
    }
}

fn virgin(mp: f64, ds: f64, d: f64) -> f64 {
    mp * (1.0 - (1.0 - d / ds).powf(1.5))
}

fn unloading(mp: f64, ds: f64, d_star: f64, q_star: f64, d: f64) -> f64 {
    q_star - 2.0 * mp * (1.0 - (1.0 - (d_star - d) / (2.0 * ds)).powf(1.5))
}

fn reloading(mp: f64, ds: f64, d_star: f64, q_star: f64, d: f64) -> f64 {
    -q_star + 2.0 * mp * (1.0 - (1.0 - (d_star + d) / (2.0 * ds)).powf(1.5))
}

/// Energy per cycle of amplitude ±Q* (module docs).
fn loop_energy(mu_p: f64, c: f64, g_star: f64, q_star: f64) -> f64 {
    let r = q_star / mu_p;
    9.0 * mu_p * mu_p / (10.0 * c * g_star)
        * (1.0 - (1.0 - r).powf(5.0 / 3.0) - 5.0 * r / 6.0 * (1.0 + (1.0 - r).powf(2.0 / 3.0)))
}

#[test]
fn loading_unloading_and_reloading_follow_the_cattaneo_mindlin_closed_form() {
    for angle in [0.5 * PI, 37f64.to_radians()] {
        let mut x = crossing(angle, 2e-6);
        let (mp, ds) = (MU * x.p, x.delta_s);
        let d_star = 0.6 * ds;
        let q_star = virgin(mp, ds, d_star);
        let n = 400;
        let mut worst: f64 = 0.0;
        let mut check = |q: f64, expect: f64, status: ContactStatus, fnorm: f64| {
            assert_eq!(status, ContactStatus::Stick);
            assert!((fnorm / x_p(angle) - 1.0).abs() < 1e-12);
            worst = worst.max((q - expect).abs() / mp);
        };
        for k in 0..=n {
            let d = d_star * k as f64 / n as f64;
            let (q, st, fnorm) = x.step(d);
            check(q, virgin(mp, ds, d), st, fnorm);
        }
        for k in 1..=2 * n {
            let d = d_star - d_star * k as f64 / n as f64;
            let (q, st, fnorm) = x.step(d);
            check(q, unloading(mp, ds, d_star, q_star, d), st, fnorm);
        }
        for k in 1..=2 * n {
            let d = -d_star + d_star * k as f64 / n as f64;
            let (q, st, fnorm) = x.step(d);
            check(q, reloading(mp, ds, d_star, q_star, d), st, fnorm);
        }
        // Past the turning point the reloading branch rejoins the virgin curve (Masing's
        // memory rule), up to gross slip at δ_s.
        for k in 1..=n {
            let d = d_star + (0.999 * ds - d_star) * k as f64 / n as f64;
            let (q, st, fnorm) = x.step(d);
            check(q, virgin(mp, ds, d), st, fnorm);
        }
        eprintln!(
            "angle {:.1} deg: P = {:.2} N, c = {:.3e} m, δ_s = {:.4e} m, largest difference \
             {worst:.2e} μP over loading, unloading, reloading",
            angle.to_degrees(),
            x.p,
            x.c,
            ds
        );
        assert!(worst < 5e-3, "largest difference {worst:e} μP");
        let (q, st, _) = x.step(1.001 * ds);
        assert_eq!(st, ContactStatus::Slip);
        assert!((q / mp - 1.0).abs() < 1e-12);
    }
}

/// The normal force of the indentation used in these tests (P = K_H δ^{3/2}).
fn x_p(angle: f64) -> f64 {
    let h = hertz(angle);
    h.force_coefficient() * 2e-6f64.powf(1.5)
}

#[test]
fn gross_slip_starts_at_delta_s_on_the_virgin_curve() {
    let x0 = crossing(0.5 * PI, 2e-6);
    for (frac, status) in [(0.99, ContactStatus::Stick), (1.01, ContactStatus::Slip)] {
        let mut x = crossing(0.5 * PI, 2e-6);
        let n = 200;
        let mut last = (0.0, ContactStatus::Open, 0.0);
        for k in 1..=n {
            last = x.step(frac * x0.delta_s * k as f64 / n as f64);
        }
        assert_eq!(last.1, status, "δ = {frac} δ_s");
        let mp = MU * x.p;
        let expect = if frac < 1.0 {
            virgin(mp, x.delta_s, frac * x.delta_s)
        } else {
            mp
        };
        // 0.99 δ_s lies between the last two corners of the Iwan elements
        let tolerance = if frac < 1.0 { 5e-3 } else { 1e-12 };
        assert!(
            (last.0 / expect - 1.0).abs() < tolerance,
            "δ = {frac} δ_s: {} vs {expect}",
            last.0
        );
    }
}

#[test]
fn the_loop_dissipates_the_mindlin_deresiewicz_energy() {
    let mut x = crossing(0.5 * PI, 2e-6);
    let (mp, ds) = (MU * x.p, x.delta_s);
    for ratio in [0.05, 0.2, 0.5, 0.9, 0.99] {
        // amplitude Q* = ratio μP on the virgin curve: δ* = δ_s [1 − (1 − Q*/μP)^{2/3}]
        let q_star = ratio * mp;
        let d_star = ds * (1.0 - (1.0 - ratio).powf(2.0 / 3.0));
        let formula = loop_energy(mp, x.c, x.g_star, q_star);
        // 1. the formula against a numerical integration (Simpson) of the closed-form loop
        let m = 2000;
        let h = 2.0 * d_star / m as f64;
        let mut area = 0.0;
        for k in 0..=m {
            let d = -d_star + k as f64 * h;
            let w = if k == 0 || k == m {
                1.0
            } else if k % 2 == 1 {
                4.0
            } else {
                2.0
            };
            area +=
                w * (unloading(mp, ds, d_star, q_star, d) - reloading(mp, ds, d_star, q_star, d));
        }
        // ∮ Q dδ over unloading (δ decreasing) and reloading (increasing): the area between
        let numeric = -area * h / 3.0;
        assert!(
            (numeric / formula - 1.0).abs() < 1e-6,
            "Q*/μP = {ratio}: closed-form loop {numeric:e} J vs formula {formula:e} J"
        );
        // 2. the element's loop: first loading, then ±δ* cycles; work of one cycle
        x = crossing(0.5 * PI, 2e-6);
        let n = 1000;
        for k in 0..=n {
            x.step(d_star * k as f64 / n as f64);
        }
        let mut work = 0.0;
        let mut prev = (d_star, x.step(d_star).0);
        let q_reached = prev.1;
        let path = (1..=2 * n)
            .map(|k| d_star - d_star * k as f64 / n as f64)
            .chain((1..=2 * n).map(|k| -d_star + d_star * k as f64 / n as f64));
        for d in path {
            let (q, st, _) = x.step(d);
            assert_eq!(st, ContactStatus::Stick);
            work += 0.5 * (q + prev.1) * (d - prev.0);
            prev = (d, q);
        }
        // the work done on the contact over a closed cycle is the dissipated energy
        assert!(work > 0.0);
        assert!(
            (work / formula - 1.0).abs() < 1e-2,
            "Q*/μP = {ratio}: element loop {work:e} J vs formula {formula:e} J"
        );
        // Masing's memory: the reloading ends where the first loading turned
        assert!((prev.1 / q_reached - 1.0).abs() < 1e-9, "the loop closes");
        assert!(
            (q_reached / q_star - 1.0).abs() < 5e-3,
            "Q* reached {q_reached} vs {q_star}"
        );
        eprintln!(
            "Q*/μP = {ratio}: W formula {formula:.6e} J, closed-form loop (Simpson) \
             {numeric:.6e} J ({:+.1e}), element loop {work:.6e} J ({:+.1e})",
            numeric / formula - 1.0,
            work / formula - 1.0
        );
    }
}

#[test]
fn a_falling_normal_force_makes_a_loaded_contact_slide() {
    let mut x = crossing(0.5 * PI, 2e-6);
    let d = 0.5 * x.delta_s;
    for k in 1..=10 {
        x.step(d * k as f64 / 10.0);
    }
    let (q, _, _) = x.step(d);
    // lift the wire: P falls to a fifth, below Q/μ
    let lift = 2e-6 * (1.0 - 0.2f64.powf(2.0 / 3.0));
    let b = NodeKinematics::at(x.b.position + lift * Vector3::z() + d * x.dir);
    let mut f = ElementVector::zeros();
    let r = x.pair.residual(&x.hist, &x.a, &b, &mut f);
    assert!(q > 0.2 * MU * x.p);
    assert_eq!(r.status, ContactStatus::Slip);
    assert!((r.tangential_force_n / (MU * r.normal_force_n) - 1.0).abs() < 1e-12);
}

/// The Hertz contact of the two wires of these tests crossing at `angle`.
fn hertz(angle: f64) -> HertzModel {
    let steel = ElasticMaterial {
        youngs_modulus_pa: E,
        poisson_ratio: NU,
    };
    HertzModel::crossed_cylinders(&CrossedCylinders::of_one_material(R, R, angle, steel)).unwrap()
}
