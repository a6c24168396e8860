//! Cost of one contact evaluation (residual only, and residual + 12×12 tangent), in stick and in
//! slip, for a generic crossed configuration: under the paper's regularised laws (penalty,
//! elastic slip) and under the contact-mechanics laws (Hertz, the Cattaneo–Mindlin Iwan bank).

use criterion::{black_box, criterion_group, criterion_main, Criterion};
use moorfret_solver::beam::rotation::exp_so3;
use moorfret_solver::contact::{
    ContactPair, ContactParameters, ContactStatus, ElementMatrix, ElementVector, NodeKinematics,
    NormalLaw, TangentialLaw,
};
use nalgebra::Vector3;

fn bench(c: &mut Criterion) {
    let r = 2.3e-3;
    let tm1 = Vector3::new(0.2, 0.1, 1.0).normalize();
    let tm2 = Vector3::new(-0.3, 0.05, 1.0).normalize();
    let n = tm1.cross(&tm2).normalize();
    let a = NodeKinematics::at(Vector3::zeros());
    let b = NodeKinematics::at(2.0 * r * n);
    let regularised = ContactParameters {
        normal: NormalLaw::Penalty {
            stiffness_n_per_m: 2e8,
        },
        tangential: TangentialLaw::ElasticSlip {
            elastic_slip_m: 1e-7,
        },
        ..Default::default()
    };
    let contact_mechanics = ContactParameters {
        normal: NormalLaw::Hertz,
        tangential: TangentialLaw::CattaneoMindlin,
        ..Default::default()
    };
    let cases = [
        ("stick", 1e-8, regularised, ContactStatus::Stick),
        ("slip", 1e-5, regularised, ContactStatus::Slip),
        (
            "cattaneo_mindlin_stick",
            1e-10,
            contact_mechanics,
            ContactStatus::Stick,
        ),
        (
            "cattaneo_mindlin_slip",
            1e-5,
            contact_mechanics,
            ContactStatus::Slip,
        ),
    ];
    for (name, slide, params, status) in cases {
        let (pair, hist) = ContactPair::new(&params, r, r, &a, &tm1, &b, &tm2).unwrap();
        let bb = NodeKinematics {
            position: b.position - 1e-6 * n + slide * tm1,
            rotation: exp_so3(&Vector3::new(1e-6, 0.0, 2e-6)),
        };
        let mut f = ElementVector::zeros();
        let mut k = ElementMatrix::zeros();
        // the case times the regime it is named after
        assert_eq!(
            pair.residual(&hist, &a, &bb, &mut f).status,
            status,
            "{name}"
        );
        c.bench_function(&format!("contact_residual_{name}"), |bch| {
            bch.iter(|| pair.residual(black_box(&hist), black_box(&a), black_box(&bb), &mut f))
        });
        c.bench_function(&format!("contact_residual_and_tangent_{name}"), |bch| {
            bch.iter(|| {
                pair.residual_and_tangent(
                    black_box(&hist),
                    black_box(&a),
                    black_box(&bb),
                    &mut f,
                    &mut k,
                )
            })
        });
    }
}

criterion_group!(benches, bench);
criterion_main!(benches);
