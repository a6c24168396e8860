//! The six-layer strand of the paper (profile `paper_six_layer`, 121 wires over the outer lay
//! length) with periodic ends: model size, one tension step (axial stiffness against the
//! straight-strand estimates) and bending steps at increasing curvature (section moment against
//! EI_min / EI_max), with the wall-time split of every step.
//!
//! Run (release): `cargo run --release -p moorfret-studies --bin strand_six_layer -- \
//!   [strain] [curvature 1/m ...]` (defaults: 2.5e-3, then 2e-3 5e-3 1e-2 2e-2 4e-2).
//! Contact regularisation: the paper campaign's set (ε_N = 2e8 N/m, γ_e = 1e-5 m) unless
//! `STRAND_CONTACT=ε_N,γ_e` gives another. `STRAND_LOAD_INCREMENT=Δλ` sets the first load increment of every step (default 1);
//! `STRAND_REUSE_MARGIN=none|N` overrides the preconditioner reuse of the split solver;
//! `RUST_LOG=moorfret_solver=trace` prints every Newton iteration (residual, tolerance), line
//! search and GMRES solve.

use std::time::Instant;

use moorfret_solver::contact::{ContactLaws, NormalLaw, TangentialLaw};
use moorfret_solver::linalg::{
    solve_load_path, GmresParams, NewtonParams, NewtonStats, NewtonWorkspace, SplitSolver,
};
use moorfret_solver::strand::bending::{bending_stiffness_bounds, section_resultants};
use moorfret_solver::strand::history::stiffness::{
    contact_compliant_stiffness_n, straight_strand_stiffness,
};
use moorfret_solver::strand::history::timing::{TimedProblem, TimedSolver, WorkTimes};
use moorfret_solver::strand::history::HistoryOptions;
use moorfret_solver::strand::loading::{LoadPath, SectionMotion};
use moorfret_solver::strand::model::{EndKind, StrandModel, StrandModelParameters};
use moorfret_solver::strand::problem::StrandProblem;
use moorfret_solver::strand::profile::profiles_from_json;

use moorfret_studies::directional::{directional_check, norm, statuses};
use moorfret_studies::irregular::irregular_history;
use moorfret_studies::logging;

const PROFILES: &str = include_str!(concat!(
    env!("CARGO_MANIFEST_DIR"),
    "/../campaigns/data/strand_profiles.json"
));

fn main() -> Result<(), Box<dyn std::error::Error>> {
    logging::init();
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
    // contact regularisation: the paper campaign's set (ε_N of the paper's Sec. 2.2
    // 'vs_analytical', γ_e of its 'vs_surface_model') unless
    // STRAND_CONTACT=penalty_n_per_m,elastic_slip_m says otherwise
    let (normal, tangential) = match std::env::var("STRAND_CONTACT") {
        Ok(v) => {
            let (a, b) = v
                .split_once(',')
                .ok_or("STRAND_CONTACT: (penalty|hertz),(elastic_slip|mindlin)")?;
            let normal = match a {
                "hertz" => NormalLaw::Hertz,
                _ => NormalLaw::Penalty {
                    stiffness_n_per_m: a.parse()?,
                },
            };
            let tangential = match b {
                "mindlin" => TangentialLaw::Mindlin,
                _ => TangentialLaw::ElasticSlip {
                    elastic_slip_m: b.parse()?,
                },
            };
            (normal, tangential)
        }
        Err(_) => (
            NormalLaw::Penalty {
                stiffness_n_per_m: 2e8,
            },
            TangentialLaw::ElasticSlip {
                elastic_slip_m: 1e-5,
            },
        ),
    };
    println!("contact: {normal:?}, {tangential:?}");
    let params = StrandModelParameters {
        ends: match std::env::var("STRAND_ENDS").as_deref() {
            Ok("ties") => EndKind::PenaltyTies,
            _ => EndKind::Periodic,
        },
        contact: ContactLaws { normal, tangential },
        ..StrandModelParameters::default()
    };
    let model = StrandModel::new(&strand, &params)?;
    let ends = match &model.periodic {
        Some(p) => format!(
            "{} anchored ends, {} eliminated ends; {} equations ({} before elimination)",
            p.layout.anchored.len(),
            p.layout.constraints.len(),
            model.pattern.size(),
            p.extended.size()
        ),
        None => format!("penalty-tied ends; {} equations", model.pattern.size()),
    };
    println!(
        "model: {} wires, {} nodes, {} elements, {} contacts, {ends}, {} nonzeros; built in \
         {:.2} s",
        strand.wire_count(),
        model.mesh.nodes.len(),
        model.mesh.elements.len(),
        model.contacts.len(),
        model.pattern.nnz(),
        t.elapsed().as_secs_f64()
    );
    let newton = NewtonParams {
        initial_load_increment: match std::env::var("STRAND_LOAD_INCREMENT") {
            Ok(v) => v.parse()?,
            Err(_) => 1.0,
        },
        pseudo_transient_shift: match std::env::var("STRAND_PTC") {
            Ok(v) => v.parse()?,
            Err(_) => HistoryOptions::default().newton.pseudo_transient_shift,
        },
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
    let gmres = match std::env::var("STRAND_REUSE_MARGIN").as_deref() {
        Ok("none") => GmresParams::default(),
        Ok(m) => GmresParams {
            reuse_margin: Some(m.parse()?),
            ..GmresParams::default()
        },
        Err(_) => GmresParams {
            reuse_margin: Some(moorfret_solver::strand::model::PRECONDITIONER_REUSE_MARGIN),
            ..GmresParams::default()
        },
    };
    let threads: usize = match std::env::var("STRAND_THREADS") {
        Ok(v) => v.parse()?,
        Err(_) => 1,
    };
    let mut solver = TimedSolver {
        inner: model.linear_solver_with(gmres, threads)?,
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
             factorisations {}, reuses {} ({} refreshed), LU fallbacks {}",
            split.iterations - split_before.iterations,
            (split.iterations - split_before.iterations) as f64 / solves.max(1) as f64,
            split.factorisations - split_before.factorisations,
            split.reuses - split_before.reuses,
            split.refreshes - split_before.refreshes,
            split.lu_fallbacks - split_before.lu_fallbacks
        );
        Ok(())
    };
    if let Ok(v) = std::env::var("STRAND_HISTORY") {
        return history(&model, v.parse()?, strain, &curvatures, threads);
    }
    if let Ok(v) = std::env::var("STRAND_PROBE") {
        probe(&model, &mut problem, &mut solver.inner, v.parse()?)?;
        return Ok(());
    }
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
    if let NormalLaw::Penalty { stiffness_n_per_m } = params.contact.normal {
        let compliant = contact_compliant_stiffness_n(&model, stiffness_n_per_m);
        println!(
            "  with the contacts' compliance (helix radii shortened by the penetrations): \
             {compliant:.4e} N ({:+.2} %)",
            100.0 * (ea / compliant - 1.0)
        );
    }
    layer_report(&model, &problem, strain, mid)?;
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

/// `STRAND_PROBE=λ`: plain Newton corrections of the tension step at load factor λ from the
/// reference state, each with its residual, contact status changes and the directional finite
/// difference (r(u + h δu) − r(u))/h against K δu.
fn probe(
    model: &StrandModel,
    problem: &mut StrandProblem<'_>,
    solver: &mut SplitSolver,
    load_factor: f64,
) -> Result<(), Box<dyn std::error::Error>> {
    use moorfret_solver::contact::ContactStatus;
    use moorfret_solver::linalg::{LinearSolver, NonlinearProblem};
    let p = &model.pattern;
    let n = p.size();
    let mut r = vec![0.0; n];
    let mut k = vec![0.0; p.nnz()];
    for it in 0..8 {
        r.fill(0.0);
        k.fill(0.0);
        problem.evaluate(load_factor, &mut r, Some(&mut k))?;
        let status = statuses(problem);
        let count = |s: ContactStatus| status.iter().filter(|x| **x == Some(s)).count();
        solver.factorize_preconditioned(p, &k, problem.preconditioner())?;
        let mut du: Vec<f64> = r.iter().map(|v| -v).collect();
        solver.solve_in_place(&mut du)?;
        let mut kdu = vec![0.0; n];
        p.mul_vec(&k, &du, &mut kdu);
        let mut line = format!(
            "it {it}: |r| {:.3e}, open/stick/slip {}/{}/{}, max|du| {:.2e}",
            norm(&r),
            count(ContactStatus::Open),
            count(ContactStatus::Stick),
            count(ContactStatus::Slip),
            du.iter().fold(0.0f64, |m, v| m.max(v.abs()))
        );
        for h in [1.0, 1e-1, 1e-2, 1e-4, 1e-6] {
            let c = directional_check(problem, load_factor, &r, &kdu, &du, h, &status)?;
            line += &format!(
                "; h {h:.0e}: |r_h| {:.2e}, fd {:.1e}, flips {}",
                norm(&c.residual),
                norm(&c.mismatch) / norm(&kdu),
                c.flips
            );
        }
        println!("{line}");
        problem.apply_increment(&du);
    }
    Ok(())
}

/// Per layer: axial force across the mid-length section against the straight-strand share
/// n E A cos³β ε, and the contact normal forces and penetrations of its interface underneath.
fn layer_report(
    model: &StrandModel,
    problem: &StrandProblem<'_>,
    strain: f64,
    mid: f64,
) -> Result<(), Box<dyn std::error::Error>> {
    use moorfret_solver::strand::history::monitors::contact_sites;
    let strand = &model.strand;
    let wires = strand.wires();
    let state = problem.state();
    let reference = model.frame.reference_positions();
    let layers = strand.layers.len();
    let mut force = vec![0.0; layers + 1];
    let mut fe = nalgebra::SVector::<f64, 12>::zeros();
    for (e, el) in model.frame.elements().iter().enumerate() {
        let [a, b] = el.nodes;
        if !(reference[a.0].z <= mid && reference[b.0].z > mid) {
            continue;
        }
        el.beam.internal_force(
            &state.positions[a.0],
            &state.positions[b.0],
            &state.rotations[a.0],
            &state.rotations[b.0],
            &mut fe,
        )?;
        let layer = wires[model.mesh.elements[e].wire.0]
            .layer
            .map_or(0, |k| k + 1);
        force[layer] += fe[8];
    }
    let e = strand.young_modulus_pa;
    let area = |r: f64| std::f64::consts::PI * r * r;
    println!(
        "  core: F_z {:.1} kN ({:.3} of E A ε)",
        1e-3 * force[0],
        force[0] / (e * area(strand.core_wire_radius_m) * strain)
    );
    let sites = contact_sites(model);
    for (k, layer) in strand.layers.iter().enumerate() {
        let share = layer.wires as f64
            * e
            * area(layer.wire_radius_m)
            * layer.lay_angle_rad.cos().powi(3)
            * strain;
        let (mut n, mut sum, mut max, mut pen) = (0usize, 0.0f64, 0.0f64, 0.0f64);
        for (c, r) in problem.responses().iter().enumerate() {
            if let (Some(r), true) = (r, sites[c].interface == k) {
                n += 1;
                sum += r.normal_force_n;
                max = max.max(r.normal_force_n);
                pen = pen.max(-r.normal_gap_m);
            }
        }
        println!(
            "  layer {}: F_z {:.1} kN ({:.3} of n E A cos³β ε); interface underneath: {n} \
             contacts, mean / max normal force {:.1} / {:.1} N, max penetration {:.2e} m",
            k + 1,
            1e-3 * force[k + 1],
            force[k + 1] / share,
            sum / n.max(1) as f64,
            max,
            pen
        );
        wire_force_spread(model, problem, k)?;
    }
    Ok(())
}

/// Periodicity in tension: the axial force of every element of layer `k`'s wires, the
/// reference wire (wire 0 of the layer) apart, as mean / min / max over the interior and over
/// the end elements.
fn wire_force_spread(
    model: &StrandModel,
    problem: &StrandProblem<'_>,
    k: usize,
) -> Result<(), Box<dyn std::error::Error>> {
    use moorfret_solver::strand::history::monitors::element_axial_force;
    let reference = model.strand.first_wire_of_layer(k);
    let wires = model.strand.wires();
    let mut groups = [(0.0f64, f64::INFINITY, f64::NEG_INFINITY, 0usize); 4];
    for w in wires.iter().filter(|w| w.layer == Some(k)) {
        let own: Vec<usize> = (0..model.mesh.elements.len())
            .filter(|&e| model.mesh.elements[e].wire == w.id)
            .collect();
        for (i, &e) in own.iter().enumerate() {
            let f = element_axial_force(model, problem.state(), e)?;
            let end = i == 0 || i + 1 == own.len();
            let g = &mut groups[2 * usize::from(w.id == reference) + usize::from(end)];
            *g = (g.0 + f, g.1.min(f), g.2.max(f), g.3 + 1);
        }
    }
    let show = |g: (f64, f64, f64, usize)| {
        format!("{:.0} [{:.0}, {:.0}]", g.0 / g.3.max(1) as f64, g.1, g.2)
    };
    println!(
        "    wire force (N), mean [min, max]: other wires interior {}, ends {}; reference \
         wire interior {}, ends {}",
        show(groups[0]),
        show(groups[1]),
        show(groups[2]),
        show(groups[3])
    );
    Ok(())
}

/// `STRAND_HISTORY=seconds`: an irregular history through [`run_history`] (module docs).
fn history(
    model: &StrandModel,
    duration_s: f64,
    strain: f64,
    curvatures: &[f64],
    threads: usize,
) -> Result<(), Box<dyn std::error::Error>> {
    use moorfret_solver::strand::history::{run_history, NoObserver};
    let amplitude = curvatures.iter().fold(0.0f64, |m, k| m.max(k.abs()));
    // ε ± 10 % of e(t), κ up to about ±amplitude
    let samples = irregular_history(duration_s, 0.1, strain, 0.1 * strain, amplitude / 3.0);
    let mut options = HistoryOptions {
        threads,
        ..HistoryOptions::default()
    };
    if let Ok(v) = std::env::var("STRAND_PTC") {
        options.newton.pseudo_transient_shift = v.parse()?;
    }
    if let Ok(v) = std::env::var("STRAND_PTC_INIT") {
        options.initialisation_shift = v.parse()?;
    }
    if let Ok(v) = std::env::var("STRAND_FORCING") {
        options.newton.linear_forcing = v.parse()?;
    }
    let t = Instant::now();
    let r = run_history(model, &samples, &options, &mut NoObserver)?;
    let s = r.stats;
    let history_substeps = s.substeps - s.initialisation_substeps;
    println!(
        "history {duration_s} s: {} of {} samples kept, {} sub-steps, {} Newton steps, {} \
         cut-backs, {} iterations; {:.1} s in all (initialisation {:.1} s, history solves {:.1} \
         s = {:.2} s per sub-step, {:.1} iterations per sub-step; outputs {:.1} s); assembly \
         {:.1} s, factorisation {:.1} s, solves {:.1} s; {} sub-steps in the initialisation",
        s.kept_samples,
        s.samples,
        s.substeps,
        s.newton_steps,
        s.cutbacks,
        s.iterations,
        t.elapsed().as_secs_f64(),
        s.initialisation_time_s,
        s.solve_time_s,
        s.solve_time_s / history_substeps.max(1) as f64,
        s.iterations as f64 / s.substeps.max(1) as f64,
        s.output_time_s,
        s.work.assembly_s,
        s.work.factorisation_s,
        s.work.solve_s,
        s.initialisation_substeps
    );
    Ok(())
}
