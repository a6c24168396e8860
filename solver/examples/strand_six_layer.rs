//! The six-layer strand of the seed (profile `paper_six_layer`, 121 wires over the outer lay
//! length) with periodic ends: model size, one tension step (axial stiffness against the
//! straight-strand estimates) and bending steps at increasing curvature (section moment against
//! EI_min / EI_max), with the wall-time split of every step.
//!
//! Run (release): `cargo run --release -p moorfret-solver --example strand_six_layer -- \
//!   [strain] [curvature 1/m ...]` (defaults: 2.5e-3, then 2e-3 5e-3 1e-2 2e-2 4e-2).
//! `STRAND_REUSE_MARGIN=none|N` overrides the preconditioner reuse of the split solver.

use std::time::Instant;

use moorfret_solver::linalg::{
    solve_load_path, GmresParams, NewtonParams, NewtonStats, NewtonWorkspace, SplitSolver,
};
use moorfret_solver::strand::bending::{bending_stiffness_bounds, section_resultants};
use moorfret_solver::strand::history::stiffness::straight_strand_stiffness;
use moorfret_solver::strand::history::timing::{TimedProblem, TimedSolver, WorkTimes};
use moorfret_solver::strand::history::HistoryOptions;
use moorfret_solver::strand::loading::{LoadPath, SectionMotion};
use moorfret_solver::strand::model::{EndKind, StrandModel, StrandModelParameters};
use moorfret_solver::strand::problem::StrandProblem;
use moorfret_solver::strand::profile::profiles_from_json;

const PROFILES: &str = include_str!(concat!(
    env!("CARGO_MANIFEST_DIR"),
    "/../campaigns/data/strand_profiles.json"
));

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let args: Vec<f64> = std::env::args()
        .skip(1)
        .map(|a| a.parse::<f64>())
        .collect::<Result<_, _>>()?;
    let strain = args.first().copied().unwrap_or(2.5e-3);
    let curvatures: Vec<f64> = if args.len() > 1 {
        args[1..].to_vec()
    } else {
        vec![2e-3, 5e-3, 1e-2, 2e-2, 4e-2]
    };
    let profiles = profiles_from_json(PROFILES)?;
    let strand = profiles
        .get("paper_six_layer")
        .ok_or("profile paper_six_layer missing")?
        .validate()?;
    let t = Instant::now();
    let params = StrandModelParameters {
        ends: EndKind::Periodic,
        ..StrandModelParameters::default()
    };
    let model = StrandModel::new(&strand, &params)?;
    let periodic = model.periodic.as_ref().ok_or("no periodic ends")?;
    println!(
        "model: {} wires, {} nodes, {} elements, {} contacts, {} anchored ends, {} eliminated \
         ends; {} equations ({} before elimination), {} nonzeros; built in {:.2} s",
        strand.wire_count(),
        model.mesh.nodes.len(),
        model.mesh.elements.len(),
        model.contacts.len(),
        periodic.layout.anchored.len(),
        periodic.layout.constraints.len(),
        model.pattern.size(),
        periodic.extended.size(),
        model.pattern.nnz(),
        t.elapsed().as_secs_f64()
    );
    let newton = NewtonParams {
        initial_load_increment: 1.0,
        ..HistoryOptions::default().newton
    };
    let mut problem = StrandProblem::new(
        &model,
        LoadPath {
            strain,
            curvature_per_m: 0.0,
        },
    );
    let t = Instant::now();
    let mut solver = TimedSolver {
        inner: match std::env::var("STRAND_REUSE_MARGIN").as_deref() {
            Ok("none") => model.linear_solver_with(GmresParams::default())?,
            Ok(m) => model.linear_solver_with(GmresParams {
                reuse_margin: Some(m.parse()?),
                ..GmresParams::default()
            })?,
            Err(_) => model.linear_solver()?,
        },
        times: WorkTimes::default(),
    };
    println!("symbolic analysis: {:.2} s", t.elapsed().as_secs_f64());
    let mut ws = NewtonWorkspace::new(&model.pattern);
    let mid = 0.5 * strand.model_length_m;
    let mut step = |problem: &mut StrandProblem<'_>,
                    solver: &mut TimedSolver<SplitSolver>,
                    end: f64,
                    label: String|
     -> Result<(), Box<dyn std::error::Error>> {
        let before = solver.times;
        let split_before = solver.inner.stats();
        let mut timed = TimedProblem {
            inner: problem,
            times: WorkTimes::default(),
        };
        let mut stats = NewtonStats::default();
        let t = Instant::now();
        let start = timed.inner.load_factor();
        solve_load_path(
            &mut timed,
            start,
            end,
            &model.pattern,
            solver,
            &newton,
            &mut ws,
            &mut stats,
        )?;
        let wall = t.elapsed().as_secs_f64();
        println!(
            "{label}: {wall:.2} s (assembly {:.2} s, factorisation {:.2} s, solves {:.3} s); \
             {} steps, {} cut-backs, {} iterations {:?}, {} factorisations",
            timed.times.assembly_s,
            solver.times.factorisation_s - before.factorisation_s,
            solver.times.solve_s - before.solve_s,
            stats.steps,
            stats.cutbacks,
            stats.iterations,
            stats.step_iterations,
            stats.factorisations
        );
        let split = solver.inner.stats();
        let solves = split.solves - split_before.solves;
        println!(
            "  linear solves: {solves}, GMRES iterations {} ({:.1} per solve), LDLᵀ \
             factorisations {}, reuses {}, LU fallbacks {}",
            split.iterations - split_before.iterations,
            (split.iterations - split_before.iterations) as f64 / solves.max(1) as f64,
            split.factorisations - split_before.factorisations,
            split.reuses - split_before.reuses,
            split.lu_fallbacks - split_before.lu_fallbacks
        );
        Ok(())
    };
    step(
        &mut problem,
        &mut solver,
        1.0,
        format!("tension ε = {strain:e}"),
    )?;
    let motion = problem.motion();
    let r = section_resultants(&model, problem.state(), &motion, mid)?;
    let ea = r.force_n.z / strain;
    let est = straight_strand_stiffness(&strand);
    println!(
        "axial stiffness: EA = {ea:.4e} N; straight strand {:.4e} N ({:+.2} %), \
         Costello-corrected {:.4e} N ({:+.2} %)",
        est.simple_n,
        100.0 * (ea / est.simple_n - 1.0),
        est.corrected_n,
        100.0 * (ea / est.corrected_n - 1.0)
    );
    let bounds = bending_stiffness_bounds(&strand, mid);
    println!(
        "EI_min = {:.1} N m², EI_max = {:.1} N m²",
        bounds.min_n_m2, bounds.max_n_m2
    );
    let m0 = r.moment_n_m.y;
    for &k in &curvatures {
        problem.start_segment(SectionMotion {
            strain,
            curvature_per_m: k,
        });
        step(
            &mut problem,
            &mut solver,
            1.0,
            format!("bending to κ = {k:e} 1/m"),
        )?;
        let motion = problem.motion();
        let r = section_resultants(&model, problem.state(), &motion, mid)?;
        let secant = (r.moment_n_m.y - m0) / k;
        println!(
            "  κ = {k:e} 1/m: M_y = {:.2} N m, secant M/κ = {secant:.1} N m² \
             ({:.3} of EI_max), F_z = {:.1} N",
            r.moment_n_m.y,
            secant / bounds.max_n_m2,
            r.force_n.z
        );
    }
    Ok(())
}
