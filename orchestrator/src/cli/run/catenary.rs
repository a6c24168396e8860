//! `moorfret run catenary`: equilibrium of one homogeneous elastic mooring line between an
//! anchor on the seabed and a fairlead, from the closed-form catenary with seabed friction
//! (`moorfret_solver::mooring::catenary`).
//!
//! Output: with `--json`, one JSON object on stdout with exactly the keys
//! `horizontal_tension_n`, `fairlead_vertical_tension_n`, `fairlead_tension_n`,
//! `anchor_tension_n`, `laid_length_m`; otherwise a short table. Without `--axial-stiffness-n`
//! the line is treated as inextensible: EA = [`INEXTENSIBLE_AXIAL_STIFFNESS_N`] and no stretch
//! is allowed to reach the fairlead (a chord at least as long as the line is "too short"). With
//! an EA the line may stretch up to the solver's default strain limit. Bad input and lines that
//! cannot reach their fairlead are errors naming the quantity; `main` turns them into exit
//! code 1.

use crate::cli::output::outln;
use anyhow::{anyhow, Context};
use clap::Args;
use moorfret_solver::mooring::catenary::{
    solve_catenary, Catenary, CatenaryError, CatenaryParams, CatenarySolution, ElasticLine,
};
use moorfret_solver::text::Num;
use serde::Serialize;

/// Axial stiffness standing for an inextensible line (N): at 1 MN of tension it stretches by
/// one part in 1e9, far below the solver tolerance on any realistic line.
pub(crate) const INEXTENSIBLE_AXIAL_STIFFNESS_N: f64 = 1.0e15;

/// Arguments of `moorfret run catenary`.
#[derive(Debug, Args)]
#[command(allow_negative_numbers = true)]
pub(crate) struct CatenaryArgs {
    /// Horizontal distance from the anchor to the fairlead X_F (m).
    #[arg(long, allow_negative_numbers = true)]
    pub(crate) horizontal_span_m: f64,
    /// Height of the fairlead above the anchor Z_F (m).
    #[arg(long, allow_negative_numbers = true)]
    pub(crate) vertical_span_m: f64,
    /// Unstretched line length L (m).
    #[arg(long, allow_negative_numbers = true)]
    pub(crate) length_m: f64,
    /// Submerged weight per unit length w (N/m).
    #[arg(long, allow_negative_numbers = true)]
    pub(crate) weight_n_per_m: f64,
    /// Axial stiffness EA (N); omitted: inextensible line (EA = 1e15 N, no stretch to reach).
    #[arg(long, allow_negative_numbers = true)]
    pub(crate) axial_stiffness_n: Option<f64>,
    /// Seabed friction coefficient C_B (-).
    #[arg(long, allow_negative_numbers = true, default_value_t = 0.0)]
    pub(crate) seabed_friction: f64,
    /// Print one JSON object instead of a table.
    #[arg(long)]
    pub(crate) json: bool,
}

/// The machine-readable result.
#[derive(Debug, Serialize)]
struct CatenaryReport {
    horizontal_tension_n: f64,
    fairlead_vertical_tension_n: f64,
    fairlead_tension_n: f64,
    anchor_tension_n: f64,
    laid_length_m: f64,
}

impl From<&CatenarySolution> for CatenaryReport {
    fn from(sol: &CatenarySolution) -> Self {
        Self {
            horizontal_tension_n: sol.horizontal_tension_n,
            fairlead_vertical_tension_n: sol.fairlead_vertical_tension_n,
            fairlead_tension_n: sol.fairlead_tension_n(),
            anchor_tension_n: sol.anchor_tension_n(),
            laid_length_m: sol.laid_length_m,
        }
    }
}

/// Solves the catenary and prints the result.
pub(crate) fn execute(args: CatenaryArgs) -> anyhow::Result<()> {
    let catenary = Catenary {
        line: ElasticLine {
            length_m: args.length_m,
            weight_n_per_m: args.weight_n_per_m,
            axial_stiffness_n: args
                .axial_stiffness_n
                .unwrap_or(INEXTENSIBLE_AXIAL_STIFFNESS_N),
        },
        horizontal_span_m: args.horizontal_span_m,
        vertical_span_m: args.vertical_span_m,
        seabed_friction: args.seabed_friction,
    };
    let params = CatenaryParams {
        max_axial_strain: if args.axial_stiffness_n.is_some() {
            CatenaryParams::default().max_axial_strain
        } else {
            0.0
        },
        ..CatenaryParams::default()
    };
    let solution = solve_catenary(&catenary, &params).map_err(|err| match &err {
        CatenaryError::InvalidInput { field, .. } => {
            let option = format!("--{}", field.replace('_', "-"));
            anyhow!(err).context(format!("invalid {option}"))
        }
        _ => anyhow!(err).context(format!(
            "no catenary for --length-m {} between spans --horizontal-span-m {} and \
             --vertical-span-m {}",
            Num(args.length_m),
            Num(args.horizontal_span_m),
            Num(args.vertical_span_m)
        )),
    })?;
    tracing::debug!(
        iterations = solution.stats.iterations,
        residual_m = solution.stats.residual_m,
        "catenary solved"
    );
    let report = CatenaryReport::from(&solution);
    if args.json {
        let text = serde_json::to_string(&report).context("serialising the catenary result")?;
        outln!("{text}")?;
    } else {
        outln!(
            "horizontal tension H        {:>14.2} N",
            report.horizontal_tension_n
        )?;
        outln!(
            "fairlead vertical tension   {:>14.2} N",
            report.fairlead_vertical_tension_n
        )?;
        outln!(
            "fairlead tension            {:>14.2} N",
            report.fairlead_tension_n
        )?;
        outln!(
            "anchor tension              {:>14.2} N",
            report.anchor_tension_n
        )?;
        outln!(
            "laid length                 {:>14.4} m",
            report.laid_length_m
        )?;
    }
    Ok(())
}
