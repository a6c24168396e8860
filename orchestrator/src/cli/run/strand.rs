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
//!   [`slip_force_variation`]), as the seed's Fig. 4.
//!
//! With `--load LOAD.csv` the same profile is driven through a load history instead
//! ([`super::strand_history`]).

use std::collections::BTreeMap;
use std::path::PathBuf;

use anyhow::{anyhow, Context};
use clap::Args;
use moorfret_solver::strand::analytical::{slip_force_variation, stick_force_variation};
use moorfret_solver::strand::driver::{run_case, CaseResult, StrandRunParameters};
use moorfret_solver::strand::model::{StrandModel, StrandModelParameters};
use moorfret_solver::strand::profile::{
    profile_from_json, profiles_from_json, Regularisation, Strand, StrandProfile,
};
use plotters::prelude::*;
use serde::Serialize;

use moorfret_solver::strand::model::EndKind;

/// Arguments of `moorfret run strand`.
#[derive(Debug, Args)]
pub(crate) struct StrandArgs {
    /// Strand profile JSON (as `campaigns/benchmarks/strand_1_6_1.json`): geometry, material,
    /// `regularisation` sets and, without `--load`, the `loading` block; or a file of named
    /// profiles (as `campaigns/data/strand_profiles.json`) with `--profile-name`.
    pub(crate) profile: PathBuf,
    /// Name of the profile in a file of named profiles.
    #[arg(long)]
    pub(crate) profile_name: Option<String>,
    /// Output directory (created if missing).
    #[arg(long)]
    pub(crate) out: PathBuf,
    /// Name of the regularisation set of the profile.
    #[arg(long, default_value = "vs_analytical")]
    pub(crate) regularisation: String,
    /// Normal penalty ε_N (N/m) and elastic slip γ_e (m), instead of a named regularisation set.
    #[arg(long, num_args = 2, value_names = ["NORMAL_PENALTY_N_PER_M", "ELASTIC_SLIP_M"])]
    pub(crate) contact_regularisation: Option<Vec<f64>>,
    /// End conditions of the helical wires.
    #[arg(long, value_enum, default_value_t = Ends::PenaltyTies)]
    pub(crate) ends: Ends,
    /// Load history CSV: `time_s,tension_n,curvature_per_m` or
    /// `time_s,axial_strain,curvature_per_m`. Without it, the profile's `loading` block.
    #[arg(long)]
    pub(crate) load: Option<PathBuf>,
    #[command(flatten)]
    pub(crate) history: super::strand_history::HistoryArgs,
}

/// End conditions of the helical wires (`--ends`).
#[derive(Debug, Clone, Copy, PartialEq, Eq, clap::ValueEnum)]
pub(crate) enum Ends {
    /// Periodic constraints between the two ends (seed Sec. 2.3).
    Periodic,
    /// Penalty ties of the helical wire ends to the core end sections (seed Sec. 2.2).
    PenaltyTies,
}

impl Ends {
    /// The solver's end condition.
    pub(crate) fn end_kind(self) -> EndKind {
        match self {
            Self::Periodic => EndKind::Periodic,
            Self::PenaltyTies => EndKind::PenaltyTies,
        }
    }
}

/// Sizes of a strand model.
#[derive(Debug, Serialize)]
pub(crate) struct ModelSizes {
    nodes: usize,
    elements: usize,
    contacts: usize,
    free_dofs: usize,
}

impl ModelSizes {
    pub(crate) fn of(model: &StrandModel) -> Self {
        Self {
            nodes: model.mesh.stats.nodes,
            elements: model.mesh.stats.elements,
            contacts: model.mesh.stats.contacts,
            free_dofs: model.dofs.free_count(),
        }
    }
}

/// The profile of `args`, its validated strand, the model with the chosen regularisation and
/// ends, and those model parameters.
pub(crate) fn load_model(
    args: &StrandArgs,
) -> anyhow::Result<(StrandProfile, Strand, StrandModel, StrandModelParameters)> {
    let text = std::fs::read_to_string(&args.profile)
        .with_context(|| format!("reading strand profile {}", args.profile.display()))?;
    let profile = match &args.profile_name {
        None => profile_from_json(&text)
            .with_context(|| format!("in strand profile {}", args.profile.display()))?,
        Some(name) => profiles_from_json(&text)
            .with_context(|| format!("in strand profiles {}", args.profile.display()))?
            .remove(name)
            .with_context(|| {
                format!(
                    "--profile-name {name}: no such profile in {}",
                    args.profile.display()
                )
            })?,
    };
    let strand = profile
        .validate()
        .with_context(|| format!("in strand profile {}", args.profile.display()))?;
    let reg = match args.contact_regularisation.as_deref() {
        Some(&[normal_penalty_n_per_m, elastic_slip_m]) => Regularisation {
            normal_penalty_n_per_m,
            elastic_slip_m,
        },
        _ => *profile
            .regularisation
            .as_ref()
            .and_then(|m| m.get(&args.regularisation))
            .ok_or_else(|| {
                anyhow!(
                    "profile has no regularisation named {:?} (give one with \
                     --contact-regularisation NORMAL_PENALTY_N_PER_M ELASTIC_SLIP_M)",
                    args.regularisation
                )
            })?,
    };
    let params = StrandModelParameters::penalty_contact(
        reg.normal_penalty_n_per_m,
        reg.elastic_slip_m,
        args.ends.end_kind(),
    );
    let model = StrandModel::new(&strand, &params)?;
    Ok((profile, strand, model, params))
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
        return super::strand_history::execute(&args, load);
    }
    let (profile, strand, model, _) = load_model(&args)?;
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
        regularisation: args.regularisation.clone(),
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
