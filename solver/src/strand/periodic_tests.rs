//! Periodic ends on the 1+6+1 benchmark strand (model length = one outer lay length, two inner
//! ones): the reference configuration satisfies the constraints, the eliminated tangent is the
//! derivative of the eliminated residual, and wire forces are periodic at the ends.

use std::f64::consts::PI;

use super::*;
use crate::contact::{ContactParameters, NormalLaw, TangentialLaw};
use crate::linalg::{
    solve_load_path, NewtonParams, NewtonStats, NewtonWorkspace, NonlinearProblem, SparseLu,
};
use crate::strand::bending::{bending_stiffness_bounds, section_resultants};
use crate::strand::history::monitors::element_axial_force;
use crate::strand::loading::LoadPath;
use crate::strand::model::{EndKind, StrandModel, StrandModelParameters};
use crate::strand::problem::StrandProblem;
use crate::strand::profile::profile_from_json;

const BENCHMARK: &str = include_str!(concat!(
    env!("CARGO_MANIFEST_DIR"),
    "/../campaigns/benchmarks/strand_1_6_1.json"
));

fn periodic_model() -> StrandModel {
    let strand = profile_from_json(BENCHMARK)
        .expect("benchmark profile parses")
        .validate()
        .expect("benchmark profile is valid");
    let params = StrandModelParameters {
        contact: ContactParameters {
            normal: NormalLaw::Penalty {
                stiffness_n_per_m: 2e8,
            },
            tangential: TangentialLaw::ElasticSlip {
                elastic_slip_m: 1e-7,
            },
            ..ContactParameters::default()
        },
        ends: EndKind::Periodic,
        ..StrandModelParameters::default()
    };
    StrandModel::new(&strand, &params).expect("periodic benchmark model builds")
}

fn newton() -> NewtonParams {
    NewtonParams {
        max_iterations: 30,
        easy_iterations: 8,
        relative_tolerance: 1e-8,
        energy_tolerance: 1e-20,
        ..NewtonParams::default()
    }
}

fn solved(model: &StrandModel, strain: f64, curvature: f64) -> StrandProblem<'_> {
    let mut problem = StrandProblem::new(
        model,
        LoadPath {
            strain,
            curvature_per_m: curvature,
        },
    );
    let mut solver = SparseLu::new(&model.pattern).unwrap();
    let mut ws = NewtonWorkspace::new(&model.pattern);
    let mut stats = NewtonStats::default();
    let end = if curvature == 0.0 { 1.0 } else { 2.0 };
    solve_load_path(
        &mut problem,
        0.0,
        end,
        &model.pattern,
        &mut solver,
        &newton(),
        &mut ws,
        &mut stats,
    )
    .unwrap();
    problem
}

#[test]
fn layout_anchors_the_outer_arc_ends_and_the_reference_configuration_satisfies_it() {
    let model = periodic_model();
    let p = model.periodic.as_ref().unwrap();
    // both ends of both reference wires lie at the outer arc (phase 90°, whole lay lengths)
    assert_eq!(p.layout.anchored.len(), 4);
    // the other 5 wires of layer 0 have two eliminated ends each; the outer layer has one wire
    assert_eq!(p.layout.constraints.len(), 10);
    let mut state = crate::beam::frame::FrameState::reference(&model.frame);
    let reference = state.clone();
    p.enforce(&SectionMotion::default(), &mut state);
    for c in &p.layout.constraints {
        let d = (state.positions[c.node] - reference.positions[c.node]).norm();
        assert!(d < 1e-15, "end {} moved by {d}", c.node);
        assert!(c.z_r_m > 0.0 && c.z_r_m < model.strand.model_length_m);
    }
}

/// Columns of the eliminated tangent against central differences of the eliminated residual
/// at a bent state (step h = 1e-9 m / rad: the truncation error h² |r'''| and the round-off
/// ε_mach |r| / h both stay below 1e-5 of the column norm).
#[test]
fn eliminated_tangent_is_the_derivative_of_the_eliminated_residual() {
    let model = periodic_model();
    let mut problem = solved(&model, 1e-3, 5e-3);
    let n = model.pattern.size();
    let mut values = vec![0.0; model.pattern.nnz()];
    let mut r0 = vec![0.0; n];
    problem.evaluate(2.0, &mut r0, Some(&mut values)).unwrap();
    // columns: translations of the masters of every constraint, plus a spread of others
    let dofs = &model.dofs;
    let p = model.periodic.as_ref().unwrap();
    let mut reduced_index = vec![usize::MAX; p.extended.size()];
    let mut k = 0;
    let dependent: Vec<usize> = p
        .layout
        .constraints
        .iter()
        .flat_map(|c| {
            (0..3).filter_map(move |m| dofs.equation(crate::beam::frame::NodeId(c.node), m).index())
        })
        .collect();
    for (e, slot) in reduced_index.iter_mut().enumerate() {
        if !dependent.contains(&e) {
            *slot = k;
            k += 1;
        }
    }
    assert_eq!(k, n);
    let mut columns: Vec<usize> = p
        .layout
        .constraints
        .iter()
        .flat_map(|c| c.masters)
        .filter_map(|m| dofs.equation(crate::beam::frame::NodeId(m), 0).index())
        .map(|e| reduced_index[e])
        .collect();
    columns.extend((0..n).step_by(n / 7 + 1));
    let h = 1e-9;
    let (mut rp, mut rm, mut dx) = (vec![0.0; n], vec![0.0; n], vec![0.0; n]);
    let (cp, ri) = (model.pattern.col_ptr(), model.pattern.row_idx());
    for &j in &columns {
        for (sign, out) in [(1.0, &mut rp), (-1.0, &mut rm)] {
            dx.fill(0.0);
            dx[j] = sign * h;
            problem.apply_increment(&dx);
            out.fill(0.0);
            problem.evaluate(2.0, out, None).unwrap();
            problem.restore();
        }
        let mut column = vec![0.0; n];
        for idx in cp[j]..cp[j + 1] {
            column[ri[idx]] = values[idx];
        }
        let norm = column.iter().map(|x| x * x).sum::<f64>().sqrt();
        let err = (0..n)
            .map(|i| ((rp[i] - rm[i]) / (2.0 * h) - column[i]).powi(2))
            .sum::<f64>()
            .sqrt();
        assert!(
            err <= 1e-5 * norm,
            "column {j}: error {err:e}, norm {norm:e}"
        );
    }
}

/// In a periodic strand the wire force depends on the angular position only (seed Fig. 8):
/// the force of the end element of every helical wire equals that of the reference wire at the
/// same angle near mid-length. Tension: every end within 1 % of the mean wire force at
/// mid-length. Tension + bending in stick (κ = 5e-3 1/m, below the onset ≈ 1.2e-2 1/m): every
/// end within 10 % of the stick amplitude EA cos²β R κ of the reference-wire force at its angle
/// (the reference wire's element forces are interpolated linearly in angle to the end element's
/// midpoint angle; with elements spanning up to ~15° of the helix the interpolation error is
/// below 1 % of the amplitude). In stick the secant bending stiffness at mid-length lies
/// between EI_min and EI_max ([`crate::strand::bending`]).
#[test]
fn wire_forces_are_periodic_at_the_ends_and_the_bending_moment_is_bounded() {
    let model = periodic_model();
    let wires = model.strand.wires();
    let elements = &model.mesh.elements;
    let mid = 0.5 * model.strand.model_length_m;
    let bounds = bending_stiffness_bounds(&model.strand, mid);
    let mut moment0 = 0.0;
    for (curvature, relative) in [(0.0, 0.01), (5e-3, 0.10)] {
        let problem = solved(&model, 1e-3, curvature);
        let state = problem.state();
        let moment = section_resultants(&model, state, &problem.motion(), mid)
            .unwrap()
            .moment_n_m
            .y;
        if curvature == 0.0 {
            moment0 = moment;
        } else {
            let secant = (moment - moment0).abs() / curvature;
            eprintln!(
                "secant bending stiffness {secant:.2} N m² in [{:.2}, {:.2}]",
                bounds.min_n_m2, bounds.max_n_m2
            );
            assert!(secant >= bounds.min_n_m2 && secant <= bounds.max_n_m2);
        }
        let force = |e: usize| element_axial_force(&model, state, e).unwrap();
        for (k, layer) in model.strand.layers.iter().enumerate() {
            let reference = model.strand.first_wire_of_layer(k);
            let ea = model.sections[reference.0].young_pa * model.sections[reference.0].area_m2;
            let amplitude = ea * layer.lay_angle_rad.cos().powi(2) * layer.helix_radius_m;
            let site = |e: usize| {
                let el = &elements[e];
                let z = 0.5
                    * (model.mesh.nodes[el.nodes[0].0].z_m + model.mesh.nodes[el.nodes[1].0].z_m);
                (wires[el.wire.0].helix.angle(z), z)
            };
            let of_wire = |w: usize| (0..elements.len()).filter(move |&e| elements[e].wire.0 == w);
            let all: Vec<usize> = of_wire(reference.0).collect();
            let ref_elements: Vec<usize> = all[1..all.len() - 1].to_vec();
            let mean_mid = {
                let f: Vec<f64> = ref_elements.iter().map(|&e| force(e)).collect();
                f.iter().sum::<f64>() / f.len() as f64
            };
            // the reference wire's own ends are anchored at the outer arc here
            for w in wires
                .iter()
                .filter(|w| w.layer == Some(k) && w.id != reference)
            {
                let own: Vec<usize> = of_wire(w.id.0).collect();
                for &e in [own[0], own[own.len() - 1]].iter() {
                    let (theta, _) = site(e);
                    let angle_gap = |r: usize| {
                        let d = (site(r).0 - theta).rem_euclid(2.0 * PI);
                        d.min(2.0 * PI - d) + 1e-3 * (site(r).1 - mid).abs()
                    };
                    let idx = (0..ref_elements.len())
                        .min_by(|&a, &b| {
                            angle_gap(ref_elements[a]).total_cmp(&angle_gap(ref_elements[b]))
                        })
                        .unwrap();
                    // linear interpolation in angle with the neighbour on θ's side
                    let wrap = |x: f64| (x + PI).rem_euclid(2.0 * PI) - PI;
                    let r = ref_elements[idx];
                    let d = wrap(theta - site(r).0);
                    let step = wrap(site(ref_elements[idx + 1]).0 - site(r).0);
                    let n = if (d >= 0.0) == (step >= 0.0) {
                        idx + 1
                    } else {
                        idx - 1
                    };
                    let dn = wrap(site(ref_elements[n]).0 - site(r).0);
                    let (fe, fr) = (
                        force(e),
                        force(r) + (force(ref_elements[n]) - force(r)) * d / dn,
                    );
                    let scale = if curvature == 0.0 {
                        mean_mid
                    } else {
                        amplitude * curvature
                    };
                    let err = (fe - fr).abs() / scale;
                    assert!(
                        err < relative,
                        "κ = {curvature}: wire {} end element {e} force {fe:.2} N vs reference \
                         {fr:.2} N at the same angle ({:.1} % of {scale:.1} N)",
                        w.id.0,
                        100.0 * err
                    );
                }
            }
        }
    }
}
