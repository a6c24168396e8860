//! Probe of the assembled strand tangent along the Newton corrections of one bending step of
//! the 1+6+1 benchmark: per iteration ‖r‖, status changes, and the directional finite
//! difference (r(u + h δu) − r(u))/h against K δu.
//!
//! `cargo run --release -p moorfret-studies --bin strand_tangent_probe [kappa [dlambda [set
//! [from]]]]` with `set` 0 ('vs_analytical', default) or 1 ('vs_surface_model') and `from` the
//! load factor reached by the driver first (1 = end of the tension stage). Also splits each
//! correction into translation, twist about the wire tangent and other rotation. `PROBE_TOP=1`
//! lists the equations with the largest finite-difference mismatch; `PROBE_LS=1` applies the
//! corrections with a weighted Armijo backtracking, as the Newton driver does.

use moorfret_solver::contact::ContactStatus;
use moorfret_solver::linalg::{
    solve_load_path, LinearSolver, NewtonStats, NewtonWorkspace, NonlinearProblem, SparseLu,
};
use moorfret_solver::strand::driver::StrandRunParameters;
use moorfret_solver::strand::loading::LoadPath;
use moorfret_solver::strand::model::{EndKind, StrandModel, StrandModelParameters};
use moorfret_solver::strand::problem::StrandProblem;
use moorfret_solver::strand::profile::profile_from_json;

use moorfret_studies::directional::{directional_check, norm, statuses, DirectionalCheck};

const BENCHMARK: &str = include_str!(concat!(
    env!("CARGO_MANIFEST_DIR"),
    "/../campaigns/benchmarks/strand_1_6_1.json"
));

fn main() {
    let args: Vec<f64> = std::env::args()
        .skip(1)
        .filter_map(|a| a.parse().ok())
        .collect();
    let kappa = args.first().copied().unwrap_or(1.0);
    let dlambda = args.get(1).copied().unwrap_or(0.125);
    // optional: regularisation (0 = vs_analytical, 1 = vs_surface_model), then the load factor
    // reached by the driver before the probed step
    let surface = args.get(2).copied().unwrap_or(0.0) > 0.5;
    let pre = args.get(3).copied().unwrap_or(1.0);
    let (penalty, gamma) = if surface { (2e6, 1e-5) } else { (2e8, 1e-7) };
    let strand = profile_from_json(BENCHMARK)
        .and_then(|p| p.validate())
        .expect("benchmark profile is valid");
    let params = StrandModelParameters::penalty_contact(penalty, gamma, EndKind::PenaltyTies);
    let model = StrandModel::new(&strand, &params).expect("model builds");
    let run = StrandRunParameters::default();
    let mut problem = StrandProblem::new(
        &model,
        LoadPath {
            strain: 1e-3,
            curvature_per_m: kappa,
        },
    );
    let p = &model.pattern;
    let mut solver = SparseLu::new(p).expect("symbolic");
    let mut ws = NewtonWorkspace::new(p);
    let mut stats = NewtonStats::default();
    let np = moorfret_solver::linalg::NewtonParams {
        initial_load_increment: run.tension_increment,
        ..run.newton
    };
    solve_load_path(
        &mut problem,
        0.0,
        1.0,
        p,
        &mut solver,
        &np,
        &mut ws,
        &mut stats,
    )
    .expect("tension stage");
    if pre > 1.0 {
        let np = moorfret_solver::linalg::NewtonParams {
            initial_load_increment: run.bending_increment,
            ..run.newton
        };
        solve_load_path(
            &mut problem,
            1.0,
            pre,
            p,
            &mut solver,
            &np,
            &mut ws,
            &mut stats,
        )
        .expect("bending to the probed step");
    }
    let n = p.size();
    let target = pre + dlambda;
    let mut r = vec![0.0; n];
    let mut k = vec![0.0; p.nnz()];
    let mut prev: Vec<Option<ContactStatus>> = Vec::new();
    let mut rot = vec![false; n];
    for node in 0..model.frame.node_count() {
        for l in 3..6 {
            if let Some(i) = model
                .dofs
                .equation(moorfret_solver::beam::frame::NodeId(node), l)
                .index()
            {
                rot[i] = true;
            }
        }
    }
    for it in 0..40 {
        r.fill(0.0);
        k.fill(0.0);
        problem
            .evaluate(target, &mut r, Some(&mut k))
            .expect("evaluate");
        let status = statuses(&problem);
        let flips = if prev.is_empty() {
            0
        } else {
            status.iter().zip(&prev).filter(|(a, b)| a != b).count()
        };
        let slips = status
            .iter()
            .filter(|s| **s == Some(ContactStatus::Slip))
            .count();
        prev = status;
        solver.factorize(p, &k).expect("factorize");
        let mut du: Vec<f64> = r.iter().map(|v| -v).collect();
        solver.solve_in_place(&mut du).expect("solve");
        let mut kdu = vec![0.0; n];
        p.mul_vec(&k, &du, &mut kdu);
        let mut fd = String::new();
        for h in [1e-2, 1e-4, 1e-6] {
            let DirectionalCheck {
                mismatch: diff,
                flips: flips_h,
                ..
            } = directional_check(&problem, target, &r, &kdu, &du, h, &prev).expect("evaluate");
            if h < 1e-5 && std::env::var("PROBE_TOP").is_ok() {
                let mut idx: Vec<usize> = (0..n).collect();
                idx.sort_by(|a, b| diff[*b].abs().total_cmp(&diff[*a].abs()));
                for &i in idx.iter().take(4) {
                    let node = (0..model.frame.node_count())
                        .find(|&nd| {
                            (0..6).any(|l| {
                                model
                                    .dofs
                                    .equation(moorfret_solver::beam::frame::NodeId(nd), l)
                                    .index()
                                    == Some(i)
                            })
                        })
                        .unwrap();
                    let local = (0..6)
                        .find(|&l| {
                            model
                                .dofs
                                .equation(moorfret_solver::beam::frame::NodeId(node), l)
                                .index()
                                == Some(i)
                        })
                        .unwrap();
                    let cs: Vec<String> = model
                        .mesh
                        .contacts
                        .iter()
                        .enumerate()
                        .filter(|(_, c)| c.nodes[0].0 == node || c.nodes[1].0 == node)
                        .map(|(ci, _)| {
                            let rsp = problem.responses()[ci].unwrap();
                            format!(
                                "c{ci} {:?} fN {:.1} |gT| {:.3e} gN {:.2e}",
                                rsp.status,
                                rsp.normal_force_n,
                                rsp.tangential_gap.norm(),
                                rsp.normal_gap_m
                            )
                        })
                        .collect();
                    println!("    dof {i} node {node} wire {} local {local}: mismatch {:.3e}, Kdu {:.3e}, contacts [{}]", model.mesh.nodes[node].wire.0, diff[i], kdu[i], cs.join("; "));
                }
            }
            fd += &format!(
                " h {h:.0e}: |fd-Kdu|/|Kdu| {:.2e} (flips {flips_h})",
                norm(&diff) / norm(&kdu)
            );
        }
        // split the correction per node into translation, twist (about the current wire
        // tangent) and the rest of the rotation
        let (mut mt, mut mtw, mut mb, mut worst) = (0.0f64, 0.0f64, 0.0f64, (0, 0usize));
        for node in 0..model.frame.node_count() {
            let eq = |l: usize| {
                model
                    .dofs
                    .equation(moorfret_solver::beam::frame::NodeId(node), l)
                    .index()
            };
            let g = |l: usize| eq(l).map_or(0.0, |i| du[i]);
            let t = nalgebra::Vector3::new(g(0), g(1), g(2));
            let th = nalgebra::Vector3::new(g(3), g(4), g(5));
            let tan = problem.state().rotations[node] * model.mesh.nodes[node].tangent;
            let tw = th.dot(&tan);
            let b = (th - tan * tw).norm();
            mt = mt.max(t.norm());
            mb = mb.max(b);
            if tw.abs() > mtw {
                mtw = tw.abs();
                worst = (model.mesh.nodes[node].wire.0, node);
            }
        }
        println!(
            "it {it:2} |r| {:.3e} flips {flips:3} slip {slips:3} max|du| {mt:.2e} m, twist {mtw:.2e} rad (wire {} node {}), other rot {mb:.2e}{fd}",
            norm(&r),
            worst.0, worst.1
        );
        if std::env::var("PROBE_LS").is_err() {
            problem.apply_increment(&du);
            continue;
        }
        // weighted Armijo backtracking on φ = ½ rᵀ W r
        let weight: Vec<f64> = (0..n)
            .map(|i| {
                if rot[i] {
                    1.0 / (2.15e-3f64).powi(2)
                } else {
                    1.0
                }
            })
            .collect();
        let phi = |r: &[f64]| 0.5 * r.iter().zip(&weight).map(|(a, w)| w * a * a).sum::<f64>();
        let phi0 = phi(&r);
        let mut alpha = 1.0;
        let mut applied = 0.0;
        let mut best = (f64::INFINITY, 1.0);
        let mut rr = vec![0.0; n];
        let mut tries = 0;
        loop {
            let step: Vec<f64> = du.iter().map(|v| v * (alpha - applied)).collect();
            problem.apply_increment(&step);
            applied = alpha;
            rr.fill(0.0);
            let ok = problem.evaluate(target, &mut rr, None).is_ok();
            let ph = if ok { phi(&rr) } else { f64::INFINITY };
            if ph < best.0 {
                best = (ph, alpha);
            }
            tries += 1;
            if ph <= phi0 * (1.0 - 2e-4 * alpha) || tries > 10 {
                break;
            }
            let q = if ph.is_finite() {
                phi0 * alpha * alpha / (ph - phi0 + 2.0 * phi0 * alpha)
            } else {
                0.1 * alpha
            };
            alpha = q.clamp(0.1 * alpha, 0.5 * alpha);
        }
        if best.1 != applied && tries > 10 {
            let step: Vec<f64> = du.iter().map(|v| v * (best.1 - applied)).collect();
            problem.apply_increment(&step);
            applied = best.1;
        }
        println!(
            "    line search: alpha {applied:.3e} after {tries} trials, phi {:.3e} -> {:.3e}",
            phi0, best.0
        );
        if (phi0.sqrt() as f64) < 1e-3 {
            break;
        }
    }
}
