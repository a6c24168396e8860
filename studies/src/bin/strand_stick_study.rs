//! Study of the outer-helix force of the 1+6+1 benchmark strand in stick (κ = 1e-2 1/m):
//! amplitude of the FE force variation against the stick solution, and where the outer wire's
//! contact points depart from plane-section motion during the bending stage.
//!
//! `cargo run -p moorfret-studies --bin strand_stick_study`

use moorfret_solver::contact::{ContactLaws, NormalLaw, TangentialLaw};
use moorfret_solver::linalg::{solve_load_path, NewtonParams, NewtonStats, NewtonWorkspace};
use moorfret_solver::strand::analytical::stick_force_variation;
use moorfret_solver::strand::contacts::ContactSearchParameters;
use moorfret_solver::strand::driver::{plane_section_departures, StrandRunParameters};
use moorfret_solver::strand::loading::LoadPath;
use moorfret_solver::strand::mesh::MeshParameters;
use moorfret_solver::strand::model::{StrandModel, StrandModelParameters};
use moorfret_solver::strand::problem::StrandProblem;
use moorfret_solver::strand::profile::profile_from_json;

const BENCHMARK: &str = include_str!(concat!(
    env!("CARGO_MANIFEST_DIR"),
    "/../campaigns/benchmarks/strand_1_6_1.json"
));

struct Variant {
    name: &'static str,
    penalty: f64,
    gamma: f64,
    hmax: Option<f64>,
    core_spacing: Option<f64>,
    end_factor: f64,
}

fn main() {
    let kappa: f64 = std::env::args()
        .nth(1)
        .and_then(|a| a.parse().ok())
        .unwrap_or(1e-2);
    let base = Variant {
        name: "vs_analytical",
        penalty: 2e8,
        gamma: 1e-7,
        hmax: None,
        core_spacing: None,
        end_factor: 1e3,
    };
    let variants = [
        base,
        Variant {
            name: "penalty x10",
            penalty: 2e9,
            ..base_v()
        },
        Variant {
            name: "penalty /10",
            penalty: 2e7,
            ..base_v()
        },
        Variant {
            name: "gamma /10",
            gamma: 1e-8,
            ..base_v()
        },
        Variant {
            name: "gamma x10",
            gamma: 1e-6,
            ..base_v()
        },
        Variant {
            name: "vs_surface",
            penalty: 2e6,
            gamma: 1e-5,
            ..base_v()
        },
        Variant {
            name: "mesh /2",
            hmax: Some(1e-3),
            ..base_v()
        },
        Variant {
            name: "core spacing /2",
            core_spacing: Some(2.5e-3),
            ..base_v()
        },
        Variant {
            name: "end factor /100",
            end_factor: 10.0,
            ..base_v()
        },
    ];
    for v in &variants {
        study(v, kappa);
    }
}

fn base_v() -> Variant {
    Variant {
        name: "",
        penalty: 2e8,
        gamma: 1e-7,
        hmax: None,
        core_spacing: None,
        end_factor: 1e3,
    }
}

fn study(v: &Variant, kappa: f64) {
    let strand = profile_from_json(BENCHMARK)
        .and_then(|p| p.validate())
        .expect("benchmark profile");
    let mut mesh = MeshParameters::default();
    if let Some(h) = v.hmax {
        mesh.max_element_length_m = h;
    }
    let mut search = ContactSearchParameters::default();
    if let Some(s) = v.core_spacing {
        search.core_line_spacing_m = s;
    }
    let params = StrandModelParameters {
        contact: ContactLaws {
            normal: NormalLaw::Penalty {
                stiffness_n_per_m: v.penalty,
            },
            tangential: TangentialLaw::ElasticSlip {
                elastic_slip_m: v.gamma,
            },
        },
        mesh,
        search,
        end_penalty_factor: v.end_factor,
        ..StrandModelParameters::default()
    };
    let model = StrandModel::new(&strand, &params).expect("model");
    let run = StrandRunParameters::default();
    let path = LoadPath {
        strain: 1e-3,
        curvature_per_m: kappa,
    };
    let mut problem = StrandProblem::new(&model, path);
    let mut solver = model.linear_solver().expect("symbolic analysis");
    let mut ws = NewtonWorkspace::new(&model.pattern);
    let mut stats = NewtonStats::default();
    let np = |inc: f64| NewtonParams {
        initial_load_increment: inc,
        ..run.newton
    };
    if let Err(e) = solve_load_path(
        &mut problem,
        0.0,
        1.0,
        &model.pattern,
        &mut solver,
        &np(1.0),
        &mut ws,
        &mut stats,
    ) {
        println!("{:>16}: tension failed: {e}", v.name);
        return;
    }
    let dev0 = deviations(&model, &problem);
    let f0 = outer_forces(&model, &problem);
    solve_load_path(
        &mut problem,
        1.0,
        2.0,
        &model.pattern,
        &mut solver,
        &np(0.25),
        &mut ws,
        &mut stats,
    )
    .map_err(|e| println!("{:>16}: bending failed: {e}", v.name))
    .ok();
    let dev1 = deviations(&model, &problem);
    let f1 = outer_forces(&model, &problem);

    let wires = strand.wires();
    let outer = strand.first_wire_of_layer(1);
    let layer = &strand.layers[1];
    let sec = &model.sections[outer.0];
    let ea = sec.young_pa * sec.area_m2;
    let (mut sxy, mut sxx) = (0.0, 0.0);
    for ((theta, a), (_, b)) in f1.iter().zip(&f0) {
        let stick =
            stick_force_variation(ea, layer.lay_angle_rad, layer.helix_radius_m, kappa, *theta);
        sxy += stick * (a - b);
        sxx += stick * stick;
    }
    // scale: amplitude of the stick displacement of the outer wire along itself
    let beta = layer.lay_angle_rad;
    let r = layer.helix_radius_m;
    let u_stick = kappa * r * beta.cos().powi(2) * r / beta.sin();
    let sigma = wires[outer.0].helix.rate_rad_per_m.signum();
    // in-phase part: least-squares c of d ≈ c (−u_stick cos θ) + d₀, the displacement whose
    // derivative along the wire is the stick force; the force ratio it implies is 1 + c
    let rms = |k: usize| {
        let d: Vec<f64> = dev1.iter().zip(&dev0).map(|(a, b)| a[k] - b[k]).collect();
        let n = d.len() as f64;
        let mean = d.iter().sum::<f64>() / n;
        let g: Vec<f64> = dev1.iter().map(|a| -sigma * u_stick * a[5].cos()).collect();
        let gm = g.iter().sum::<f64>() / n;
        let (mut sgd, mut sgg) = (0.0, 0.0);
        for (x, y) in g.iter().zip(&d) {
            sgd += (x - gm) * (y - mean);
            sgg += (x - gm) * (x - gm);
        }
        sgd / sgg * u_stick
    };
    println!(
        "{:>16}: ratio FE/stick {:.3}; in-phase departure from plane sections along the outer wire (c, u_stick {:.2e} m): outer axis {:.3}, gap {:.3}, inner top {:.3}, inner axis {:.3}, inner bottom {:.3}; iterations {} steps {}",
        v.name,
        sxy / sxx,
        u_stick,
        rms(0) / u_stick,
        rms(1) / u_stick,
        rms(2) / u_stick,
        rms(3) / u_stick,
        rms(4) / u_stick,
        stats.iterations,
        stats.steps,
    );
}

/// (θ, axial force) of each outer-wire element.
fn outer_forces(model: &StrandModel, problem: &StrandProblem) -> Vec<(f64, f64)> {
    let outer = model.strand.first_wire_of_layer(1);
    let wires = model.strand.wires();
    let state = problem.state();
    model
        .frame
        .elements()
        .iter()
        .zip(&model.mesh.elements)
        .filter(|(_, me)| me.wire == outer)
        .map(|(el, me)| {
            let [a, b] = el.nodes;
            let lf = el
                .beam
                .local_forces(
                    &state.positions[a.0],
                    &state.positions[b.0],
                    &state.rotations[a.0],
                    &state.rotations[b.0],
                )
                .expect("element");
            let z = 0.5 * (model.mesh.nodes[a.0].z_m + model.mesh.nodes[b.0].z_m);
            (wires[me.wire.0].helix.angle(z), lf.axial_n)
        })
        .collect()
}

/// Per trellis contact: [outer axis, gap (outer point − inner top), inner top, inner axis,
/// inner bottom, θ] departures from plane sections along the outer wire.
fn deviations(model: &StrandModel, problem: &StrandProblem) -> Vec<[f64; 6]> {
    plane_section_departures(model, problem.state(), &problem.motion())
        .iter()
        .map(|d| {
            [
                d.outer_axis_m,
                d.outer_point_m - d.inner_top_m,
                d.inner_top_m,
                d.inner_axis_m,
                d.inner_bottom_m,
                d.theta_rad,
            ]
        })
        .collect()
}
