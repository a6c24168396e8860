//! The strand load of a run from a load file (`moorfret run strand --load`): the file read and
//! checked by the hot-spot series' parser ([`LoadTable::parse`]: `time_s`, `curvature_per_m`
//! and `tension_n` or `axial_strain`, or the hot spot of a global run's `hotspots.csv`), a
//! tension turned into ε = T / EA with EA given or measured on the model ([`samples_of`]), and
//! refusals in the words of the file: the sample, its line and the column.

use std::path::Path;

use anyhow::{anyhow, bail, Context};
use moorfret_solver::contact::NormalLaw;
use moorfret_solver::global::series::{LoadKind, LoadTable, SeriesError};
use moorfret_solver::strand::history::stiffness::{
    contact_compliant_stiffness_n, samples_from_tension, straight_strand_stiffness, SlackTension,
};
use moorfret_solver::strand::history::{HistoryError, HistoryOptions, LoadSample};

use super::stiffness::{
    measured_ea_n, AxialStiffness, StiffnessRequest, StiffnessSource, StraightStrandEstimates,
};
use super::LazyModel;

/// How a tension history becomes a strain history.
#[derive(Debug, Clone, Copy)]
pub struct StiffnessOptions<'a> {
    /// EA (N) given instead of measured.
    pub given_ea_n: Option<f64>,
    /// Axial strain of the tension step that measures EA.
    pub strain: f64,
    /// Directory of the EA cache; `None`: no cache.
    pub cache_dir: Option<&'a Path>,
    /// Measure even if the cache holds it.
    pub refresh: bool,
}

/// The axial strain of every sample of `table`: as given, or T / `ea_n` for a tension
/// history (slack samples, admitted by `--slack-as-zero`, as zero strain).
pub fn table_strain(table: &LoadTable, ea_n: Option<f64>) -> anyhow::Result<Vec<f64>> {
    match (table.kind, ea_n) {
        (LoadKind::Strain, _) => Ok(table.value.clone()),
        (LoadKind::Tension, Some(ea)) => {
            let (samples, _) = tension_samples(table, ea)?;
            Ok(samples.iter().map(|s| s.strain).collect())
        }
        (LoadKind::Tension, None) => bail!("a tension history needs the EA of its run"),
    }
}

/// The samples of a tension table, ε = T / `ea_n` (slack samples, admitted by
/// `--slack-as-zero`, as zero strain), with the count of slack samples.
fn tension_samples(table: &LoadTable, ea_n: f64) -> anyhow::Result<(Vec<LoadSample>, usize)> {
    Ok(samples_from_tension(
        &table.time_s,
        &table.value,
        &table.curvature_per_m,
        ea_n,
        1,
        SlackTension::AsZero,
    )?)
}

/// "LOAD.csv sample i (line l), column c".
fn at(path: &Path, index: usize, column: &str) -> String {
    format!(
        "{}: sample {index} (line {}), column {column}",
        path.display(),
        index + 2
    )
}

/// Reads and checks the load file (module docs, [`LoadTable::parse`]); the error names the
/// sample and the column.
pub fn read_load(path: &Path, slack_as_zero: bool, hot_spot: usize) -> anyhow::Result<LoadTable> {
    let text = std::fs::read_to_string(path)
        .with_context(|| format!("reading load history {}", path.display()))?;
    let table = LoadTable::parse(&text, hot_spot).map_err(|e| match e {
        SeriesError::Header(m) if m.starts_with("no hot spot") => {
            anyhow!("{}: {m} (--hot-spot)", path.display())
        }
        e => anyhow!("{}: {e}", path.display()),
    })?;
    if table.kind == LoadKind::Tension && !slack_as_zero {
        if let Some(index) = table.value.iter().position(|&t| t < 0.0) {
            bail!(
                "{}: negative tension {} N (slack); pass --slack-as-zero to load slack samples \
                 as zero strain",
                at(path, index, "tension_n"),
                table.value[index]
            );
        }
    }
    Ok(table)
}

/// EA for a tension history: given (`--axial-stiffness-n`), or measured on the model, from the
/// cache or by a tension step ([`measured_ea_n`]); with its source and the measuring strain
/// (none when given).
fn axial_stiffness_n(
    lazy: &mut LazyModel<'_>,
    args: &StiffnessOptions<'_>,
    options: &HistoryOptions,
) -> anyhow::Result<(f64, StiffnessSource, Option<f64>)> {
    if let Some(ea) = args.given_ea_n {
        if !(ea.is_finite() && ea > 0.0) {
            bail!("--axial-stiffness-n {ea}: the axial stiffness must be finite and > 0 N");
        }
        return Ok((ea, StiffnessSource::Given, None));
    }
    let request = StiffnessRequest {
        cache_dir: args.cache_dir,
        strain: args.strain,
        options,
        refresh: args.refresh,
    };
    let (ea, source) = measured_ea_n(lazy, &request)?;
    Ok((ea, source, Some(args.strain)))
}

/// The load samples of `table` on the model of `lazy`, with the EA used (and the straight-strand
/// estimates beside it) and the slack sample count.
pub fn samples_of(
    table: &LoadTable,
    lazy: &mut LazyModel<'_>,
    args: &StiffnessOptions<'_>,
    options: &HistoryOptions,
) -> anyhow::Result<(Vec<LoadSample>, Option<AxialStiffness>, usize)> {
    match table.kind {
        LoadKind::Strain => {
            let samples = (0..table.time_s.len())
                .map(|i| LoadSample {
                    time_s: table.time_s[i],
                    strain: table.value[i],
                    curvature_per_m: table.curvature_per_m[i],
                })
                .collect();
            Ok((samples, None, 0))
        }
        LoadKind::Tension => {
            let estimate = straight_strand_stiffness(lazy.strand);
            let (ea, source, measured_at_strain) = axial_stiffness_n(lazy, args, options)?;
            // the estimate needs the model's contacts: left out when the model is not built
            let compliant = match (lazy.params.contact.normal, lazy.built()) {
                (NormalLaw::Penalty { stiffness_n_per_m }, Some(model)) => {
                    Some(contact_compliant_stiffness_n(model, stiffness_n_per_m))
                }
                _ => None,
            };
            // Negative tensions were refused by `read_load` unless `--slack-as-zero`.
            let (samples, slack) = tension_samples(table, ea)?;
            let stiffness = AxialStiffness {
                ea_n: ea,
                source,
                measured_at_strain,
                campaign: None,
                estimates: Some(StraightStrandEstimates {
                    simple_n: estimate.simple_n,
                    costello_n: estimate.corrected_n,
                    contact_compliant_n: compliant,
                }),
            };
            Ok((samples, Some(stiffness), slack))
        }
    }
}

/// A refused sample in the words of the load file: its line and column.
pub fn refused(path: &Path, kind: LoadKind, e: HistoryError) -> anyhow::Error {
    match e {
        HistoryError::InvalidSample {
            index,
            field,
            value,
            reason,
            ..
        } => {
            let column = match field {
                "strain" => kind.column(),
                other => other,
            };
            let shown = if field == "strain" && kind == LoadKind::Tension {
                format!("strain T/EA = {value:e}")
            } else {
                format!("{value}")
            };
            anyhow!("{}: {shown}: {reason}", at(path, index, column))
        }
        other => anyhow!(other),
    }
}
