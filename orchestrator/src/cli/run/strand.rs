//! `moorfret run strand PROFILE --out DIR`: the detailed strand FE model
//! (`moorfret_solver::strand`) on one strand profile with its `loading` block: axial strain ε,
//! then each curvature κ as a separate case, with a named regularisation of the profile
//! (default `vs_analytical`).
//!
//! Writes into DIR:
//! - `outer_helix_axial_force.csv`: `curvature_per_m,arc_length_m,theta_rad,axial_force_n`, one
//!   row per element of the first wire of the outermost layer, per curvature case;
//! - `summary.json`: per case the Newton statistics, stage timings, largest contact normal
//!   force, largest slip and contact status counts, plus the model sizes;
//! - `outer_helix_axial_force.svg`: FE force against θ per case with the stick solution
//!   T₀ + EA cos²β R κ sin θ and the friction-limited (full slip) solution, the triangle wave
//!   T₀ + (π/2) μ T₀ sin β · tri(θ) (|dF/ds| = μ q with q = T₀ sin²β/R and dθ/ds = sin β/R,
//!   [`slip_force_variation`]), as the paper's Fig. 4.
//!
//! With `--load LOAD.csv` the same profile is driven through a load history instead
//! ([`super::strand_history`]).

use std::collections::BTreeMap;
use std::path::PathBuf;

use anyhow::{anyhow, Context};
use clap::Args;
use moorfret_solver::strand::analytical::{slip_force_variation, stick_force_variation};
use moorfret_solver::strand::driver::{run_case, CaseResult, StrandRunParameters};
use plotters::prelude::*;
use serde::Serialize;

use super::strand_model::{load_model, ContactLawsArg, ModelArgs, ModelSizes};

/// Arguments of `moorfret run strand`. Negative numbers parse as values, so that a value out of
/// range is refused by its option's name rather than taken for an unknown flag.
#[derive(Debug, Args)]
#[command(allow_negative_numbers = true)]
pub(crate) struct StrandArgs {
    /// The strand model.
    #[command(flatten)]
    pub(crate) model: ModelArgs,
    /// Output directory (created if missing).
    #[arg(long)]
    pub(crate) out: PathBuf,
    /// Load history CSV: `time_s,tension_n,curvature_per_m` or
    /// `time_s,axial_strain,curvature_per_m`. Without it, the profile's `loading` block.
    #[arg(long)]
    pub(crate) load: Option<PathBuf>,
    #[command(flatten)]
    pub(crate) history: super::strand_history::HistoryArgs,
}

#[derive(Debug, Serialize)]
struct CaseSummary {
    curvature_per_m: f64,
    axial_strain: f64,
    newton_steps: usize,
    newton_cutbacks: usize,
    newton_iterations: usize,
    factorisations: usize,
    evaluations: usize,
    step_iterations: Vec<usize>,
    tension_time_s: f64,
    bending_time_s: f64,
    max_contact_normal_force_n: f64,
    max_slip_m: f64,
    status_counts: BTreeMap<String, usize>,
    outer_tension_share_n: f64,
    strand_force_at_mid_length_n: f64,
}

#[derive(Debug, Serialize)]
struct Summary {
    regularisation: String,
    #[serde(flatten)]
    sizes: ModelSizes,
    straight_case: CaseSummary,
    cases: Vec<CaseSummary>,
}

fn summarise(r: &CaseResult, t0: f64) -> CaseSummary {
    let mut status_counts = BTreeMap::new();
    for c in &r.contacts {
        *status_counts.entry(format!("{:?}", c.status)).or_insert(0) += 1;
    }
    CaseSummary {
        curvature_per_m: r.curvature_per_m,
        axial_strain: r.strain,
        newton_steps: r.stats.steps,
        newton_cutbacks: r.stats.cutbacks,
        newton_iterations: r.stats.iterations,
        factorisations: r.stats.factorisations,
        evaluations: r.stats.evaluations,
        step_iterations: r.stats.step_iterations.clone(),
        tension_time_s: r.tension_time_s,
        bending_time_s: r.bending_time_s,
        max_contact_normal_force_n: r
            .contacts
            .iter()
            .map(|c| c.normal_force_n)
            .fold(0.0, f64::max),
        max_slip_m: r.contacts.iter().map(|c| c.slip_m).fold(0.0, f64::max),
        status_counts,
        outer_tension_share_n: t0,
        strand_force_at_mid_length_n: r.strand_force_n,
    }
}

/// One plotted curve point: (θ, FE, stick, slip).
type Row = (f64, f64, f64, f64);

/// Execute `moorfret run strand`.
pub(crate) fn execute(args: StrandArgs) -> anyhow::Result<()> {
    if let Some(load) = &args.load {
        return super::strand_history::execute(&args.model, &args.history, load, &args.out);
    }
    let (profile, strand, model, _) = load_model(&args.model)?;
    let loading = profile
        .loading
        .clone()
        .ok_or_else(|| anyhow!("profile has no `loading` block"))?;
    let run = StrandRunParameters::default();
    let outer_layer = strand
        .layers
        .len()
        .checked_sub(1)
        .ok_or_else(|| anyhow!("profile has no helical layer"))?;
    let outer = strand.first_wire_of_layer(outer_layer);
    let layer = &strand.layers[outer_layer];
    let section = &model.sections[outer.0];
    let ea = section.young_pa * section.area_m2;
    std::fs::create_dir_all(&args.out)
        .with_context(|| format!("creating {}", args.out.display()))?;

    let straight = run_case(&model, loading.axial_strain, 0.0, &run)?;
    let outer_forces = |r: &CaseResult| -> Vec<_> {
        r.element_forces
            .iter()
            .filter(|f| f.wire == outer)
            .copied()
            .collect()
    };
    let f0 = outer_forces(&straight);
    let t0 = f0.iter().map(|f| f.axial_force_n).sum::<f64>() / f0.len().max(1) as f64;
    let beta = layer.lay_angle_rad;
    let mu = strand.friction_coefficient;

    let mut csv = csv::Writer::from_path(args.out.join("outer_helix_axial_force.csv"))?;
    csv.write_record([
        "curvature_per_m",
        "arc_length_m",
        "theta_rad",
        "axial_force_n",
    ])?;
    let mut cases = Vec::new();
    let mut curves: Vec<(f64, Vec<Row>)> = Vec::new();
    for &kappa in &loading.curvatures_per_m {
        let r = run_case(&model, loading.axial_strain, kappa, &run)?;
        let forces = outer_forces(&r);
        let stick =
            |theta: f64| t0 + stick_force_variation(ea, beta, layer.helix_radius_m, kappa, theta);
        let slip = |theta: f64| t0 + slip_force_variation(mu, beta, t0, theta);
        let mut rows = Vec::with_capacity(forces.len());
        for f in &forces {
            csv.write_record([
                kappa.to_string(),
                f.arc_length_m.to_string(),
                f.theta_rad.to_string(),
                f.axial_force_n.to_string(),
            ])?;
            rows.push((
                f.theta_rad,
                f.axial_force_n,
                stick(f.theta_rad),
                slip(f.theta_rad),
            ));
        }
        tracing::info!(kappa, steps = r.stats.steps, "strand case solved");
        cases.push(summarise(&r, t0));
        curves.push((kappa, rows));
    }
    csv.flush()?;
    let summary = Summary {
        regularisation: match args.model.contact_laws {
            ContactLawsArg::ContactMechanics | ContactLawsArg::HertzMindlin => {
                args.model.regularisation_name()
            }
            ContactLawsArg::Regularised => args.model.regularisation.clone(),
        },
        sizes: ModelSizes::of(&model),
        straight_case: summarise(&straight, t0),
        cases,
    };
    std::fs::write(
        args.out.join("summary.json"),
        serde_json::to_string_pretty(&summary)?,
    )?;
    plot(&args.out.join("outer_helix_axial_force.svg"), &curves)?;
    Ok(())
}

fn plot(path: &std::path::Path, curves: &[(f64, Vec<Row>)]) -> anyhow::Result<()> {
    let height = 360 * curves.len().max(1) as u32;
    let root = SVGBackend::new(path, (900, height)).into_drawing_area();
    root.fill(&WHITE).map_err(|e| anyhow!("{e}"))?;
    let panels = root.split_evenly((curves.len().max(1), 1));
    for (panel, (kappa, rows)) in panels.iter().zip(curves) {
        let mut sorted = rows.clone();
        sorted.sort_by(|a, b| a.0.total_cmp(&b.0));
        let (lo, hi) = sorted
            .iter()
            .fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), r| {
                (lo.min(r.1).min(r.2).min(r.3), hi.max(r.1).max(r.2).max(r.3))
            });
        let pad = 0.05 * (hi - lo).max(1.0);
        let mut chart = ChartBuilder::on(panel)
            .caption(
                format!("outer helix axial force, kappa = {kappa} 1/m"),
                ("sans-serif", 18),
            )
            .margin(10)
            .x_label_area_size(35)
            .y_label_area_size(70)
            .build_cartesian_2d(-3.2..3.2, (lo - pad)..(hi + pad))
            .map_err(|e| anyhow!("{e}"))?;
        chart
            .configure_mesh()
            .x_desc("theta (rad)")
            .y_desc("axial force (N)")
            .draw()
            .map_err(|e| anyhow!("{e}"))?;
        chart
            .draw_series(LineSeries::new(sorted.iter().map(|r| (r.0, r.2)), &BLUE))
            .map_err(|e| anyhow!("{e}"))?
            .label("stick")
            .legend(|(x, y)| PathElement::new(vec![(x, y), (x + 20, y)], BLUE));
        chart
            .draw_series(LineSeries::new(sorted.iter().map(|r| (r.0, r.3)), &GREEN))
            .map_err(|e| anyhow!("{e}"))?
            .label("friction-limited slip")
            .legend(|(x, y)| PathElement::new(vec![(x, y), (x + 20, y)], GREEN));
        chart
            .draw_series(
                rows.iter()
                    .map(|r| Circle::new((r.0, r.1), 3, RED.filled())),
            )
            .map_err(|e| anyhow!("{e}"))?
            .label("FE")
            .legend(|(x, y)| Circle::new((x + 10, y), 3, RED.filled()));
        chart
            .configure_series_labels()
            .background_style(WHITE)
            .border_style(BLACK)
            .draw()
            .map_err(|e| anyhow!("{e}"))?;
    }
    root.present().map_err(|e| anyhow!("{e}"))?;
    Ok(())
}
