//! Unit tests of the contact element: tangent against central finite differences, force against
//! the gradient of the gap functions, objectivity, history handling.

use nalgebra::{Matrix3, Vector3};

use super::element::{
    ContactHistory, ContactPair, ContactStatus, ElementMatrix, ElementVector, NodeKinematics,
};
use super::laws::{ContactParameters, NormalLaw, TangentialLaw};
use crate::beam::rotation::exp_so3;

const R1: f64 = 2.3e-3;
const R2: f64 = 2.0e-3;

struct Setup {
    pair: ContactPair,
    history: ContactHistory,
    ref1: NodeKinematics,
    ref2: NodeKinematics,
}

/// A generic crossed configuration (tangents at ≈ 70°, arbitrary node triads) with nodes at the
/// closest points of the two axes.
fn setup(params: &ContactParameters) -> Setup {
    let lam1 = exp_so3(&Vector3::new(0.3, -0.2, 0.5));
    let lam2 = exp_so3(&Vector3::new(-0.1, 0.4, 0.2));
    let tm1 = Vector3::new(1.0, 0.2, -0.3).normalize();
    let tm2 = Vector3::new(-0.2, 1.0, 0.4).normalize();
    let (t1, t2) = (lam1 * tm1, lam2 * tm2);
    let n = t1.cross(&t2).normalize();
    let x1 = Vector3::new(0.01, -0.02, 0.03);
    let ref1 = NodeKinematics {
        position: x1,
        rotation: lam1,
    };
    let ref2 = NodeKinematics {
        position: x1 + (R1 + R2) * n,
        rotation: lam2,
    };
    let (pair, history) = ContactPair::new(params, R1, R2, &ref1, &tm1, &ref2, &tm2).unwrap();
    Setup {
        pair,
        history,
        ref1,
        ref2,
    }
}

/// Moves the reference configuration: translations (m) and spatial rotation increments (rad).
fn moved(node: &NodeKinematics, du: Vector3<f64>, dtheta: Vector3<f64>) -> NodeKinematics {
    NodeKinematics {
        position: node.position + du,
        rotation: exp_so3(&dtheta) * node.rotation,
    }
}

/// Perturbs DOF `j` of the pair by `h` (rotations through exp_so3, spatial).
fn perturbed(
    a: &NodeKinematics,
    b: &NodeKinematics,
    j: usize,
    h: f64,
) -> (NodeKinematics, NodeKinematics) {
    let (mut a, mut b) = (*a, *b);
    let mut e = Vector3::zeros();
    e[j % 3] = h;
    match j / 3 {
        0 => a.position += e,
        1 => a.rotation = exp_so3(&e) * a.rotation,
        2 => b.position += e,
        _ => b.rotation = exp_so3(&e) * b.rotation,
    }
    (a, b)
}

fn step_size(j: usize) -> f64 {
    if (j / 3) % 2 == 0 {
        1e-10
    } else {
        1e-7
    }
}

fn check_tangent(
    s: &Setup,
    h: &ContactHistory,
    a: &NodeKinematics,
    b: &NodeKinematics,
    expect: ContactStatus,
) {
    check_tangent_within(s, h, a, b, expect, 1e-6);
}

/// As [`check_tangent`], with the relative tolerance `rel` per column.
fn check_tangent_within(
    s: &Setup,
    h: &ContactHistory,
    a: &NodeKinematics,
    b: &NodeKinematics,
    expect: ContactStatus,
    rel: f64,
) {
    let mut f = ElementVector::zeros();
    let mut k = ElementMatrix::zeros();
    let resp = s.pair.residual_and_tangent(h, a, b, &mut f, &mut k);
    assert_eq!(resp.status, expect);
    let scale = k.amax();
    for j in 0..12 {
        let hj = step_size(j);
        let (ap, bp) = perturbed(a, b, j, hj);
        let (am, bm) = perturbed(a, b, j, -hj);
        let (mut fp, mut fm) = (ElementVector::zeros(), ElementVector::zeros());
        assert_eq!(s.pair.residual(h, &ap, &bp, &mut fp).status, expect);
        assert_eq!(s.pair.residual(h, &am, &bm, &mut fm).status, expect);
        let fd = (fp - fm) / (2.0 * hj);
        let col = k.column(j);
        let err = (fd - col).amax();
        let tol = rel * col.amax().max(1e-4 * scale);
        assert!(
            err <= tol,
            "column {j}: error {err:.3e} > {tol:.3e}\nK: {col}\nFD: {fd}"
        );
    }
    // The value part of the tangent evaluation equals the plain residual.
    let mut f2 = ElementVector::zeros();
    s.pair.residual(h, a, b, &mut f2);
    assert!((f - f2).amax() <= 1e-12 * f.amax());
}

fn params(normal: NormalLaw, tangential: TangentialLaw) -> ContactParameters {
    ContactParameters {
        normal,
        tangential,
        friction_coefficient: 0.3,
        ..Default::default()
    }
}

/// History after one accepted stick step with a tangential offset, then a current configuration
/// with penetration, tangential motion `slide` and small rotations of both nodes.
fn loaded(s: &Setup, slide: f64, rot: f64) -> (ContactHistory, NodeKinematics, NodeKinematics) {
    let n = s.history.normal;
    let t1 = s.ref1.rotation * Vector3::new(1.0, 0.2, -0.3).normalize();
    let a0 = moved(
        &s.ref1,
        Vector3::new(5e-9, -1e-8, 3e-9),
        Vector3::new(2e-6, -1e-6, 3e-6),
    );
    let b0 = moved(
        &s.ref2,
        -8e-6 * n + 1e-8 * t1,
        Vector3::new(-1e-6, 2e-6, 1e-6),
    );
    let mut h = s.history;
    let mut f = ElementVector::zeros();
    let r = s.pair.residual(&h, &a0, &b0, &mut f);
    assert_eq!(r.status, ContactStatus::Stick);
    h.accept(&r);
    let dir = (t1 + 0.5 * n.cross(&t1)).normalize();
    let a = moved(
        &a0,
        Vector3::new(3e-8, 1e-8, -2e-8),
        rot * Vector3::new(1.0, 2.0, -1.0),
    );
    let b = moved(
        &b0,
        -4e-6 * n + slide * dir,
        rot * Vector3::new(-2.0, 1.0, 1.5),
    );
    (h, a, b)
}

#[test]
fn tangent_matches_finite_differences_in_stick_with_penalty_and_elastic_slip() {
    let s = setup(&params(
        NormalLaw::Penalty {
            stiffness_n_per_m: 2e6,
        },
        TangentialLaw::ElasticSlip {
            elastic_slip_m: 1e-4,
        },
    ));
    let (h, a, b) = loaded(&s, 3e-7, 1e-3);
    check_tangent(&s, &h, &a, &b, ContactStatus::Stick);
}

#[test]
fn tangent_matches_finite_differences_in_slip_with_penalty_and_elastic_slip() {
    let s = setup(&params(
        NormalLaw::Penalty {
            stiffness_n_per_m: 2e6,
        },
        TangentialLaw::ElasticSlip {
            elastic_slip_m: 1e-7,
        },
    ));
    let (h, a, b) = loaded(&s, 3e-6, 1e-3);
    check_tangent(&s, &h, &a, &b, ContactStatus::Slip);
}

#[test]
fn tangent_matches_finite_differences_with_hertz_and_mindlin_in_stick_and_slip() {
    let s = setup(&params(NormalLaw::Hertz, TangentialLaw::Mindlin));
    let (h, a, b) = loaded(&s, 2e-8, 1e-4);
    check_tangent(&s, &h, &a, &b, ContactStatus::Stick);
    let (h, a, b) = loaded(&s, 5e-6, 1e-3);
    check_tangent(&s, &h, &a, &b, ContactStatus::Slip);
}

#[test]
fn internal_force_is_the_gradient_of_the_gap_functions() {
    let s = setup(&params(
        NormalLaw::Penalty {
            stiffness_n_per_m: 2e6,
        },
        TangentialLaw::ElasticSlip {
            elastic_slip_m: 1e-7,
        },
    ));
    let (h, a, b) = loaded(&s, 3e-6, 1e-3);
    let mut f = ElementVector::zeros();
    let r = s.pair.residual(&h, &a, &b, &mut f);
    for j in 0..12 {
        let hj = step_size(j);
        let (ap, bp) = perturbed(&a, &b, j, hj);
        let (am, bm) = perturbed(&a, &b, j, -hj);
        let (gnp, gtp) = s.pair.gaps(&h, &ap, &bp);
        let (gnm, gtm) = s.pair.gaps(&h, &am, &bm);
        let dgn = (gnp - gnm) / (2.0 * hj);
        let dgt = (gtp - gtm) / (2.0 * hj);
        let expect = -r.normal_force_n * dgn + r.tangential_force.dot(&dgt);
        assert!(
            (f[j] - expect).abs() <= 1e-6 * f.amax(),
            "dof {j}: {} vs {expect}",
            f[j]
        );
    }
}

#[test]
fn rigid_motion_of_a_stuck_pair_rotates_the_forces_with_it() {
    let s = setup(&params(
        NormalLaw::Penalty {
            stiffness_n_per_m: 2e6,
        },
        TangentialLaw::ElasticSlip {
            elastic_slip_m: 1e-4,
        },
    ));
    let (mut h, a, b) = loaded(&s, 3e-7, 1e-3);
    let mut f = ElementVector::zeros();
    let r = s.pair.residual(&h, &a, &b, &mut f);
    assert_eq!(r.status, ContactStatus::Stick);
    h.accept(&r);
    // Same configuration, accepted history: same forces, no new slip.
    let r0 = s.pair.residual(&h, &a, &b, &mut f);
    assert!((r0.tangential_force - r.tangential_force).norm() <= 1e-12 * r.tangential_force_n);
    // Large rigid rotation (about 1.2 rad) about a point, plus a translation.
    let q: Matrix3<f64> = exp_so3(&Vector3::new(0.7, -0.5, 0.8));
    let c = Vector3::new(0.1, 0.2, -0.3);
    let rig = |n: &NodeKinematics| NodeKinematics {
        position: q * n.position + c,
        rotation: q * n.rotation,
    };
    let mut g = ElementVector::zeros();
    let r1 = s.pair.residual(&h, &rig(&a), &rig(&b), &mut g);
    assert_eq!(r1.status, ContactStatus::Stick);
    assert!((r1.normal_force_n - r0.normal_force_n).abs() <= 1e-10 * r0.normal_force_n);
    assert!((r1.tangential_force - q * r0.tangential_force).norm() <= 1e-9 * r0.tangential_force_n);
    assert!(
        r1.slip_increment.norm() <= 1e-15,
        "{}",
        r1.slip_increment.norm()
    );
    for i in 0..4 {
        let fi = q * Vector3::new(f[3 * i], f[3 * i + 1], f[3 * i + 2]);
        let gi = Vector3::new(g[3 * i], g[3 * i + 1], g[3 * i + 2]);
        assert!(
            (fi - gi).norm() <= 1e-9 * f.amax(),
            "node part {i}: {fi} vs {gi}"
        );
    }
}

#[test]
fn accepted_slip_step_leaves_the_elastic_gap_at_the_regularisation_and_counts_the_sliding() {
    let ge = 1e-7;
    let s = setup(&params(
        NormalLaw::Penalty {
            stiffness_n_per_m: 2e6,
        },
        TangentialLaw::ElasticSlip { elastic_slip_m: ge },
    ));
    let (mut h, a, b) = loaded(&s, 3e-6, 1e-3);
    let mut f = ElementVector::zeros();
    let r = s.pair.residual(&h, &a, &b, &mut f);
    assert_eq!(r.status, ContactStatus::Slip);
    assert!((r.tangential_force_n - 0.3 * r.normal_force_n).abs() <= 1e-12 * r.normal_force_n);
    let before = h;
    // Trial evaluations never touch the history.
    s.pair.residual(&h, &a, &b, &mut f);
    assert_eq!(h, before);
    h.accept(&r);
    let t1 = a.rotation * Vector3::new(1.0, 0.2, -0.3).normalize();
    let t2 = b.rotation * Vector3::new(-0.2, 1.0, 0.4).normalize();
    let e = t1 * h.elastic_gap_m[0] + t2 * h.elastic_gap_m[1];
    assert!((e.norm() - ge).abs() <= 1e-12 * ge);
    assert!((h.slip_path_m - (r.tangential_gap.norm() - ge)).abs() <= 1e-12 * h.slip_path_m);
    assert_eq!(h.status, ContactStatus::Slip);
}

#[test]
fn separated_nodes_give_no_force_and_reset_the_elastic_gap() {
    let s = setup(&ContactParameters::default());
    let b = moved(&s.ref2, 1e-6 * s.history.normal, Vector3::zeros());
    let mut f = ElementVector::from_element(1.0);
    let mut k = ElementMatrix::from_element(1.0);
    let r = s
        .pair
        .residual_and_tangent(&s.history, &s.ref1, &b, &mut f, &mut k);
    assert_eq!(r.status, ContactStatus::Open);
    assert!((r.normal_gap_m - 1e-6).abs() < 1e-15);
    assert_eq!(f.amax(), 0.0);
    assert_eq!(k.amax(), 0.0);
    assert_eq!(r.next_history.elastic_gap_m, [0.0, 0.0]);
}

#[test]
fn tangent_matches_finite_differences_in_seeded_random_configurations() {
    let laws = [
        (
            NormalLaw::Penalty {
                stiffness_n_per_m: 2e6,
            },
            TangentialLaw::ElasticSlip {
                elastic_slip_m: 1e-6,
            },
        ),
        (
            NormalLaw::Hertz,
            TangentialLaw::ElasticSlip {
                elastic_slip_m: 1e-6,
            },
        ),
        (
            NormalLaw::Penalty {
                stiffness_n_per_m: 2e8,
            },
            TangentialLaw::Mindlin,
        ),
        (NormalLaw::Hertz, TangentialLaw::Mindlin),
    ];
    let (checked, slips) = random_configurations(&laws, 20_260_101, 40);
    assert!(
        checked >= 25 && slips >= 5 && checked - slips >= 5,
        "checked {checked}, slips {slips}"
    );
}

#[test]
fn tangent_matches_finite_differences_in_seeded_random_configurations_with_contact_mechanics() {
    let laws = [
        (NormalLaw::Hertz, TangentialLaw::CattaneoMindlin),
        (
            NormalLaw::Line { length_m: 5e-3 },
            TangentialLaw::CattaneoMindlin,
        ),
        (
            NormalLaw::Line { length_m: 5e-3 },
            TangentialLaw::ElasticSlip {
                elastic_slip_m: 1e-6,
            },
        ),
        (NormalLaw::ContactMechanics, TangentialLaw::CattaneoMindlin),
    ];
    let (checked, slips) = random_configurations(&laws, 20_261_202, 60);
    eprintln!("contact-mechanics laws: {checked} configurations checked, {slips} in slip");
    assert!(
        checked >= 25 && slips >= 5 && checked - slips >= 5,
        "checked {checked}, slips {slips}"
    );
}

/// Checks the tangent in `cases` seeded random configurations, the laws taken in turn; returns
/// how many were checked (away from a stick/slip boundary) and how many of those slipped.
fn random_configurations(
    laws: &[(NormalLaw, TangentialLaw)],
    seed: u64,
    cases: usize,
) -> (usize, usize) {
    use rand::{Rng, SeedableRng};
    let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(seed);
    let unit = |rng: &mut rand_chacha::ChaCha8Rng| {
        Vector3::new(
            rng.gen_range(-1.0..1.0),
            rng.gen_range(-1.0..1.0),
            rng.gen_range(-1.0..1.0),
        )
        .normalize()
    };
    let (mut checked, mut slips) = (0, 0);
    for case in 0..cases {
        let (tm1, tm2) = (unit(&mut rng), unit(&mut rng));
        if tm1.cross(&tm2).norm() < 0.3 {
            continue;
        }
        let lam1 = exp_so3(&(unit(&mut rng) * rng.gen_range(0.0..3.0)));
        let lam2 = exp_so3(&(unit(&mut rng) * rng.gen_range(0.0..3.0)));
        let (t1, t2) = (lam1 * tm1, lam2 * tm2);
        let n = t1.cross(&t2).normalize();
        let x1 = Vector3::new(
            rng.gen_range(-0.1..0.1),
            rng.gen_range(-0.1..0.1),
            rng.gen_range(-0.1..0.1),
        );
        let a = NodeKinematics {
            position: x1,
            rotation: lam1,
        };
        let b = NodeKinematics {
            position: x1 + (R1 + R2) * n,
            rotation: lam2,
        };
        let (normal, tangential) = laws[case % laws.len()];
        let p = params(normal, tangential);
        let (pair, hist) = ContactPair::new(&p, R1, R2, &a, &tm1, &b, &tm2).unwrap();
        let s = Setup {
            pair,
            history: hist,
            ref1: a,
            ref2: b,
        };
        let a = moved(
            &s.ref1,
            unit(&mut rng) * rng.gen_range(0.0..2e-6),
            unit(&mut rng) * rng.gen_range(0.0..2e-3),
        );
        let b = moved(
            &s.ref2,
            -rng.gen_range(2e-6..1e-5) * n + unit(&mut rng) * rng.gen_range(0.0..4e-6),
            unit(&mut rng) * rng.gen_range(0.0..2e-3),
        );
        let mut f = ElementVector::zeros();
        let status = s.pair.residual(&s.history, &a, &b, &mut f).status;
        // Skip configurations within the finite-difference step of the stick/slip boundary.
        let stable = (0..12).all(|j| {
            let (ap, bp) = perturbed(&a, &b, j, step_size(j));
            let (am, bm) = perturbed(&a, &b, j, -step_size(j));
            s.pair.residual(&s.history, &ap, &bp, &mut f).status == status
                && s.pair.residual(&s.history, &am, &bm, &mut f).status == status
        });
        if !stable || status == ContactStatus::Open {
            continue;
        }
        check_tangent(&s, &s.history, &a, &b, status);
        checked += 1;
        slips += (status == ContactStatus::Slip) as usize;
    }
    (checked, slips)
}

/// The preconditioning surrogate P = k_N b_N b_Nᵀ + B_Tᵀ C B_T, checked through the gap
/// functions: for a perturbation δq, P δq = k_N b_N (δg_N) + B_Tᵀ C δg_T with δg_N, δg_T and the
/// rows of b_N, B_T from central differences of [`ContactPair::gaps`]; symmetric and positive
/// semi-definite in stick and in slip.
#[test]
fn preconditioning_surrogate_is_the_stiffness_of_the_gaps_without_coupling_or_curvature() {
    for (gamma, slide, status) in [
        (1e-4, 3e-7, ContactStatus::Stick),
        (1e-7, 3e-6, ContactStatus::Slip),
    ] {
        let s = setup(&params(
            NormalLaw::Penalty {
                stiffness_n_per_m: 2e6,
            },
            TangentialLaw::ElasticSlip {
                elastic_slip_m: gamma,
            },
        ));
        let (h, a, b) = loaded(&s, slide, 1e-3);
        let (r, _, _, p) = with_surrogate(&s, &h, &a, &b, 0.0);
        assert_eq!(r.status, status);
        assert!((p - p.transpose()).norm() <= 1e-12 * p.norm());
        let eig = p.symmetric_eigenvalues();
        assert!(eig.min() >= -1e-9 * eig.max(), "{eig}");
        // gap Jacobians by central differences
        let mut bn = ElementVector::zeros();
        let mut bt = nalgebra::SMatrix::<f64, 3, 12>::zeros();
        for j in 0..12 {
            let hs = step_size(j);
            let (ap, bp) = perturbed(&a, &b, j, hs);
            let (am, bm) = perturbed(&a, &b, j, -hs);
            let (gp, tp) = s.pair.gaps(&h, &ap, &bp);
            let (gm, tm) = s.pair.gaps(&h, &am, &bm);
            bn[j] = (gp - gm) / (2.0 * hs);
            bt.set_column(j, &((tp - tm) / (2.0 * hs)));
        }
        let kn = 2e6;
        let c = match status {
            ContactStatus::Slip => {
                let g = r.tangential_gap;
                let u = g / g.norm();
                (Matrix3::identity() - u * u.transpose()) * (0.3 * r.normal_force_n / g.norm())
            }
            _ => Matrix3::identity() * (0.3 * r.normal_force_n / gamma),
        };
        let expected = bn * bn.transpose() * kn + bt.transpose() * c * bt;
        let err = (p - expected).norm() / expected.norm();
        assert!(err < 1e-5, "{status:?}: relative difference {err:e}");
    }
}

/// A crossing (the generic setup) pressed by a fixed penetration and moved tangentially along
/// `dir` by `x` (m), with small fixed rotations of both nodes.
fn cm_config(s: &Setup, x: f64) -> (NodeKinematics, NodeKinematics) {
    let n = s.history.normal;
    let t1 = s.ref1.rotation * Vector3::new(1.0, 0.2, -0.3).normalize();
    let dir = (t1 + 0.5 * n.cross(&t1)).normalize();
    let a = moved(
        &s.ref1,
        Vector3::new(3e-9, 1e-9, -2e-9),
        Vector3::new(2e-6, -1e-6, 3e-6),
    );
    let b = moved(
        &s.ref2,
        -6e-6 * n + x * dir,
        Vector3::new(-1e-6, 2e-6, 1e-6),
    );
    (a, b)
}

/// Every Iwan stretch of a Cattaneo–Mindlin history (components on the tangents `t`) within
/// its element's yield displacement dᵢ = xᵢ δ_s.
fn assert_stretches_within_their_limits(
    h: &ContactHistory,
    t: (Vector3<f64>, Vector3<f64>),
    delta_s: f64,
) {
    let elements = super::memory::iwan_elements();
    for (e, el) in h.tangential_memory.stretches.iter().zip(elements.iter()) {
        let v = t.0 * e[0] + t.1 * e[1];
        assert!(
            v.norm() <= el.yield_fraction * delta_s * (1.0 + 1e-6),
            "{} > {}",
            v.norm(),
            el.yield_fraction * delta_s
        );
    }
}

#[test]
fn tangent_matches_finite_differences_with_cattaneo_mindlin_through_reversals_and_slip() {
    for normal in [NormalLaw::Hertz, NormalLaw::Line { length_m: 5e-3 }] {
        let s = setup(&params(normal, TangentialLaw::CattaneoMindlin));
        let mut f = ElementVector::zeros();
        // δ_s of this crossing, from the initial slope (the Iwan chord's, 0.2 % below k₀)
        let (a, b) = cm_config(&s, 0.0);
        let r0 = s.pair.residual(&s.history, &a, &b, &mut f);
        let (a1, b1) = cm_config(&s, 1e-9);
        let r1 = s.pair.residual(&s.history, &a1, &b1, &mut f);
        let k0 = (r1.tangential_force - r0.tangential_force).norm() / 1e-9;
        let delta_s = 1.5 * 0.3 * r0.normal_force_n / k0;
        let mut h = s.history;
        // virgin loading, an unloading (reversal), a reloading inside it (a second reversal),
        // the trial of a reloading beyond the first reversal, and a gross slip
        for (x, accept) in [
            (0.3, true),
            (0.5, true),
            (0.2, true),
            (0.35, true),
            (0.6, false),
            (-2.0, false),
        ] {
            let (a, b) = cm_config(&s, x * delta_s);
            let r = s.pair.residual(&h, &a, &b, &mut f);
            let expect = if x.abs() > 1.0 {
                ContactStatus::Slip
            } else {
                ContactStatus::Stick
            };
            assert_eq!(r.status, expect, "x = {x}");
            check_tangent(&s, &h, &a, &b, expect);
            let t = (
                a.rotation * Vector3::new(1.0, 0.2, -0.3).normalize(),
                b.rotation * Vector3::new(-0.2, 1.0, 0.4).normalize(),
            );
            assert_stretches_within_their_limits(&r.next_history, t, delta_s * 1.002);
            if expect == ContactStatus::Slip {
                // every element at its limit, each along its own trial stretch: those directions
                // differ by the stretches' offsets (≤ δ_s) over a trial gap of 3 δ_s here
                let ratio = r.tangential_force_n / (0.3 * r.normal_force_n);
                assert!(ratio <= 1.0 + 1e-12 && ratio > 1.0 - 1e-6, "Q/μP = {ratio}");
            }
            if accept {
                h.accept(&r);
            }
        }
    }
}

#[test]
fn cattaneo_mindlin_memory_turns_with_a_rigid_motion() {
    let s = setup(&params(NormalLaw::Hertz, TangentialLaw::CattaneoMindlin));
    let mut f = ElementVector::zeros();
    let mut h = s.history;
    for x in [1e-7, 4e-7, 2e-7] {
        let (a, b) = cm_config(&s, x);
        let r = s.pair.residual(&h, &a, &b, &mut f);
        h.accept(&r);
    }
    assert!(!h.tangential_memory.is_empty());
    let (a, b) = cm_config(&s, 3e-7);
    let r0 = s.pair.residual(&h, &a, &b, &mut f);
    let q: Matrix3<f64> = exp_so3(&Vector3::new(0.7, -0.5, 0.8));
    let c = Vector3::new(0.1, 0.2, -0.3);
    let rig = |n: &NodeKinematics| NodeKinematics {
        position: q * n.position + c,
        rotation: q * n.rotation,
    };
    let r1 = s.pair.residual(&h, &rig(&a), &rig(&b), &mut f);
    assert_eq!(r1.status, ContactStatus::Stick);
    assert!((r1.tangential_force - q * r0.tangential_force).norm() <= 1e-9 * r0.tangential_force_n);
    // the stretches, by their components on the wires' tangents, are those of the unmoved pair
    let (m0, m1) = (
        &r0.next_history.tangential_memory,
        &r1.next_history.tangential_memory,
    );
    let scale = m0
        .stretches
        .iter()
        .flatten()
        .fold(0.0_f64, |m, v| m.max(v.abs()));
    for (e0, e1) in m0.stretches.iter().zip(&m1.stretches) {
        assert!((e0[0] - e1[0]).abs() <= 1e-9 * scale && (e0[1] - e1[1]).abs() <= 1e-9 * scale);
    }
}

#[test]
fn existing_laws_keep_an_empty_memory() {
    let s = setup(&params(
        NormalLaw::Penalty {
            stiffness_n_per_m: 2e6,
        },
        TangentialLaw::ElasticSlip {
            elastic_slip_m: 1e-4,
        },
    ));
    let (h, a, b) = loaded(&s, 3e-7, 1e-3);
    let mut f = ElementVector::zeros();
    let r = s.pair.residual(&h, &a, &b, &mut f);
    assert_eq!(
        r.next_history.tangential_memory,
        super::memory::TangentialMemory::default()
    );
}

#[test]
fn tangent_matches_finite_differences_for_steps_across_the_branch() {
    let s = setup(&params(NormalLaw::Hertz, TangentialLaw::CattaneoMindlin));
    let n = s.history.normal;
    let t1 = s.ref1.rotation * Vector3::new(1.0, 0.2, -0.3).normalize();
    let dir = (t1 + 0.5 * n.cross(&t1)).normalize();
    let side = n.cross(&dir).normalize();
    let mut f = ElementVector::zeros();
    let (a, b) = cm_config(&s, 0.0);
    let r0 = s.pair.residual(&s.history, &a, &b, &mut f);
    let (a1, b1) = cm_config(&s, 1e-9);
    let r1 = s.pair.residual(&s.history, &a1, &b1, &mut f);
    let delta_s =
        1.5 * 0.3 * r0.normal_force_n / ((r1.tangential_force - r0.tangential_force).norm() / 1e-9);
    let mut h = s.history;
    let (a, b) = cm_config(&s, 0.5 * delta_s);
    let r = s.pair.residual(&h, &a, &b, &mut f);
    h.accept(&r);
    // steps nearly perpendicular to the loading: each element turns on its own
    for lean in [0.1, 0.0, -0.1] {
        let step = 0.25 * delta_s * (side + lean * dir).normalize();
        let b2 = moved(&b, step, Vector3::zeros());
        let r = s.pair.residual(&h, &a, &b2, &mut f);
        assert_eq!(r.status, ContactStatus::Stick);
        check_tangent(&s, &h, &a, &b2, ContactStatus::Stick);
    }
}

/// The sliding stiffness of the Newton iteration matrix: on a Cattaneo–Mindlin contact in gross
/// slip it leaves the force (and the preconditioner's surrogate) as they are, to the bit, and
/// adds k_s (∂f_int/∂f_T) d dᵀ ∂g_T/∂q to the tangent, k_s = fraction · k₀ with
/// k₀ = c f_N^{1/3}; its translational rows are −k_s d wᵀ (f_int = −f_T there) with
/// w = ∂(d · g_T)/∂q, here from central differences of the gap. A sticking contact's tangent does
/// not change.
#[test]
fn sliding_stiffness_stiffens_only_a_gross_slipping_contact_along_its_slip() {
    use super::laws::ResolvedTangential;
    let s = setup(&params(NormalLaw::Hertz, TangentialLaw::CattaneoMindlin));
    let ResolvedTangential::CattaneoMindlinPoint(coefficient) = s.pair.laws().tangential else {
        panic!("a Hertz crossing gets the point law");
    };
    let fraction = 0.1;
    let evaluate = |a: &NodeKinematics, b: &NodeKinematics, sliding: f64| {
        with_surrogate(&s, &s.history, a, b, sliding)
    };
    let (a, b) = cm_config(&s, 0.0);
    let delta_s = {
        let mut f = ElementVector::zeros();
        let r = s.pair.residual(&s.history, &a, &b, &mut f);
        1.5 * 0.3 * r.normal_force_n / (coefficient * r.normal_force_n.cbrt())
    };
    for (x, slipping) in [(0.4, false), (-2.0, true)] {
        let (a, b) = cm_config(&s, x * delta_s);
        let (r0, f0, k0_tangent, p0) = evaluate(&a, &b, 0.0);
        let (r1, f1, k1_tangent, p1) = evaluate(&a, &b, fraction);
        assert_eq!(r0.status == ContactStatus::Slip, slipping, "x = {x}");
        assert_eq!(f0, f1);
        assert_eq!(p0, p1);
        assert_eq!(r0.tangential_force, r1.tangential_force);
        let added = k1_tangent - k0_tangent;
        if !slipping {
            assert_eq!(added, ElementMatrix::zeros());
            continue;
        }
        let d = r0.tangential_force / r0.tangential_force_n;
        let ks = fraction * coefficient * r0.normal_force_n.cbrt();
        for j in 0..12 {
            let hj = step_size(j);
            let (ap, bp) = perturbed(&a, &b, j, hj);
            let (am, bm) = perturbed(&a, &b, j, -hj);
            let w = (d.dot(&s.pair.gaps(&s.history, &ap, &bp).1)
                - d.dot(&s.pair.gaps(&s.history, &am, &bm).1))
                / (2.0 * hj);
            let expected = -ks * w * d;
            let column = Vector3::new(added[(0, j)], added[(1, j)], added[(2, j)]);
            assert!(
                (column - expected).norm() <= 1e-6 * expected.norm().max(1e-6 * ks),
                "column {j}: {column} against {expected}"
            );
        }
        // rank one: every column is a multiple of the one with the largest entry
        let (jmax, _) = (0..12)
            .map(|j| (j, added.column(j).amax()))
            .fold((0, 0.0), |m, c| if c.1 > m.1 { c } else { m });
        let u = added.column(jmax) / added.column(jmax).norm();
        for j in 0..12 {
            let c = added.column(j);
            assert!(
                (c - u * u.dot(&c)).norm() <= 1e-9 * added.amax(),
                "column {j}"
            );
        }
    }
}

/// Response, force, tangent and preconditioning surrogate of the pair of `s` at (`a`, `b`)
/// from history `h`, with the Newton matrix's sliding stiffness `sliding`.
fn with_surrogate(
    s: &Setup,
    h: &ContactHistory,
    a: &NodeKinematics,
    b: &NodeKinematics,
    sliding: f64,
) -> (
    super::element::ContactResponse,
    ElementVector,
    ElementMatrix,
    ElementMatrix,
) {
    let (mut f, mut k, mut p) = (
        ElementVector::zeros(),
        ElementMatrix::zeros(),
        ElementMatrix::zeros(),
    );
    let r = s
        .pair
        .residual_tangent_and_surrogate(h, a, b, &mut f, &mut k, &mut p, sliding);
    (r, f, k, p)
}
