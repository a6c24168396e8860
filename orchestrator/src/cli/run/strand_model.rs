//! The strand model of `moorfret run strand`: which profile, which contact regularisation,
//! which end conditions ([`ModelArgs`]), and the model built from them ([`load_model`]).

use std::path::PathBuf;

use anyhow::{anyhow, bail, Context};
use clap::{Args, ValueEnum};
use moorfret_solver::contact::TangentialLaw;
use moorfret_solver::strand::model::{EndKind, StrandModel, StrandModelParameters};
use moorfret_solver::strand::profile::{
    select_profile, ProfileError, Regularisation, Strand, StrandProfile,
};
use serde::Serialize;

/// The strand model of a run: profile, regularisation and end conditions.
#[derive(Debug, Args)]
pub(crate) struct ModelArgs {
    /// Strand profile JSON (as `campaigns/benchmarks/strand_1_6_1.json`): geometry, material,
    /// `regularisation` sets and, without `--load`, the `loading` block; or a file of named
    /// profiles (as `campaigns/data/strand_profiles.json`) with `--profile-name`.
    pub(crate) profile: PathBuf,
    /// Name of the profile in a file of named profiles.
    #[arg(long)]
    pub(crate) profile_name: Option<String>,
    /// Name of the regularisation set of the profile.
    #[arg(long, default_value = "vs_analytical")]
    pub(crate) regularisation: String,
    /// Normal penalty ε_N (N/m) and elastic slip γ_e (m), instead of a named regularisation set.
    #[arg(long, num_args = 2, value_names = ["NORMAL_PENALTY_N_PER_M", "ELASTIC_SLIP_M"])]
    pub(crate) contact_regularisation: Option<Vec<f64>>,
    /// End conditions of the helical wires.
    #[arg(long, value_enum, default_value_t = Ends::PenaltyTies)]
    pub(crate) ends: Ends,
    /// Contact laws of the wire crossings: `regularised` (penalty normal law and elastic-slip
    /// Coulomb law, from `--regularisation` or `--contact-regularisation`) or
    /// `contact-mechanics` (Hertz at the crossings, line law on the core, Cattaneo–Mindlin
    /// tangential law with memory; no regularisation), or `hertz-mindlin` (the same normal laws,
    /// Mindlin's initial tangential stiffness up to the Coulomb limit).
    #[arg(long, value_enum, default_value_t = ContactLawsArg::Regularised)]
    pub(crate) contact_laws: ContactLawsArg,
}

/// Contact laws of a run (`--contact-laws`).
#[derive(Debug, Clone, Copy, PartialEq, Eq, clap::ValueEnum)]
pub(crate) enum ContactLawsArg {
    /// Penalty normal law and elastic-slip regularised Coulomb law (the paper's Sec. 2.1).
    Regularised,
    /// Hertz / line-contact normal laws and the Cattaneo–Mindlin tangential law with memory.
    ContactMechanics,
    /// Hertz / line-contact normal laws and Mindlin's initial tangential stiffness 8 G* c up to
    /// the Coulomb limit (elastic–perfectly-plastic: no micro-slip curve below μP).
    HertzMindlin,
}

impl ContactLawsArg {
    /// The value of `--contact-laws` that selects these laws.
    pub(crate) fn name(self) -> String {
        self.to_possible_value()
            .map_or_else(String::new, |v| v.get_name().to_owned())
    }
}

impl ModelArgs {
    /// The contact laws as a run's summary names them.
    pub(crate) fn regularisation_name(&self) -> String {
        match (self.contact_laws, &self.contact_regularisation) {
            (ContactLawsArg::ContactMechanics, _) => {
                "contact mechanics (Hertz, line contacts on the core, Cattaneo-Mindlin)".into()
            }
            (ContactLawsArg::HertzMindlin, _) => {
                "Hertz, line contacts on the core, Mindlin stiffness up to Coulomb".into()
            }
            (_, Some(v)) => format!("normal penalty {} N/m, elastic slip {} m", v[0], v[1]),
            (_, None) => self.regularisation.clone(),
        }
    }
}

/// End conditions of the helical wires (`--ends`).
#[derive(Debug, Clone, Copy, PartialEq, Eq, clap::ValueEnum)]
pub(crate) enum Ends {
    /// Periodic constraints between the two ends (the paper's Sec. 2.3).
    Periodic,
    /// Periodic constraints with the far ends following the start ends in rotation too.
    PeriodicRotations,
    /// Penalty ties of the helical wire ends to the core end sections (the paper's Sec. 2.2).
    PenaltyTies,
}

impl Ends {
    /// The solver's end condition.
    pub(crate) fn end_kind(self) -> EndKind {
        match self {
            Self::Periodic => EndKind::Periodic,
            Self::PeriodicRotations => EndKind::PeriodicRotations,
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
    args: &ModelArgs,
) -> anyhow::Result<(StrandProfile, Strand, StrandModel, StrandModelParameters)> {
    let (profile, strand, params) = load_strand(args)?;
    let model = StrandModel::new(&strand, &params)?;
    Ok((profile, strand, model, params))
}

/// The profile of `args`, its validated strand and the model parameters, without building the
/// model.
pub(crate) fn load_strand(
    args: &ModelArgs,
) -> anyhow::Result<(StrandProfile, Strand, StrandModelParameters)> {
    let text = std::fs::read_to_string(&args.profile)
        .with_context(|| format!("reading strand profile {}", args.profile.display()))?;
    let profile = select_profile(&text, args.profile_name.as_deref()).map_err(|e| match e {
        ProfileError::UnknownProfile { name, .. } => anyhow!(
            "--profile-name {name}: no such profile in {}",
            args.profile.display()
        ),
        e => anyhow!(e).context(match &args.profile_name {
            None => format!("in strand profile {}", args.profile.display()),
            Some(_) => format!("in strand profiles {}", args.profile.display()),
        }),
    })?;
    let strand = profile
        .validate()
        .with_context(|| format!("in strand profile {}", args.profile.display()))?;
    if args.contact_laws != ContactLawsArg::Regularised {
        if args.contact_regularisation.is_some() {
            bail!(
                "--contact-regularisation is not used by --contact-laws {} (its laws have no \
                 regularisation)",
                args.contact_laws.name()
            );
        }
        let mut params = StrandModelParameters::contact_mechanics(args.ends.end_kind());
        if args.contact_laws == ContactLawsArg::HertzMindlin {
            params.contact.tangential = TangentialLaw::Mindlin;
        }
        return Ok((profile, strand, params));
    }
    let reg = match args.contact_regularisation.as_deref() {
        Some(&[normal_penalty_n_per_m, elastic_slip_m]) => {
            for (name, v) in [
                ("NORMAL_PENALTY_N_PER_M", normal_penalty_n_per_m),
                ("ELASTIC_SLIP_M", elastic_slip_m),
            ] {
                if !(v.is_finite() && v > 0.0) {
                    bail!(
                        "--contact-regularisation: {name} must be > 0 (got {})",
                        moorfret_solver::text::Num(v)
                    );
                }
            }
            Regularisation {
                normal_penalty_n_per_m,
                elastic_slip_m,
            }
        }
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
    Ok((profile, strand, params))
}
