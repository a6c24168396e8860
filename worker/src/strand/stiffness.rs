//! The EA of ε = T / EA (`moorfret_campaign::stiffness`): one description of the EA a strand
//! run used ([`AxialStiffness`]), and one way to get a measured EA, from the cache or measured
//! on the model and cached ([`measured_ea_n`]): a campaign's strand jobs keep the cache in the
//! artifact directory, `moorfret run strand` in the user's cache directory.

use std::path::Path;

use moorfret_campaign::stiffness::{AxialStiffnessRule, StiffnessCache};
use moorfret_solver::strand::history::{HistoryError, HistoryOptions};
use moorfret_solver::strand::model::StrandModelError;
use serde::Serialize;
use serde_json::json;

use super::LazyModel;

/// Where the EA of a run came from.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum StiffnessSource {
    /// Given by the user (`--axial-stiffness-n`).
    Given,
    /// Measured on the same model by an earlier run, read from the cache.
    Cached,
    /// Measured on the model by this run.
    Measured,
    /// The global line type's (a campaign's `line_type` rule).
    LineType,
}

impl StiffnessSource {
    /// The name in summaries and logs.
    pub fn as_str(self) -> &'static str {
        match self {
            Self::Given => "given",
            Self::Cached => "cached",
            Self::Measured => "measured",
            Self::LineType => "line_type",
        }
    }
}

/// Straight-strand estimates of EA, for comparison (N).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct StraightStrandEstimates {
    /// Wire tensions only.
    pub simple_n: f64,
    /// With Costello's bending and twisting terms.
    pub costello_n: f64,
    /// The latter with the helix radii shortened by the contact penetrations (penalty normal
    /// law with the model built only).
    pub contact_compliant_n: Option<f64>,
}

/// The EA of a strand run's tension → strain conversion, where it came from and what it is
/// compared with.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct AxialStiffness {
    /// EA of ε = T / EA, and of the fretting stress's metallic area EA / E (N).
    pub ea_n: f64,
    /// Where it came from.
    pub source: StiffnessSource,
    /// Strain of the tension step that measured it on the model (cached or measured).
    pub measured_at_strain: Option<f64>,
    /// The campaign's rule and the line type's EA at the hot spot (a campaign's strand jobs).
    pub campaign: Option<(AxialStiffnessRule, f64)>,
    /// Straight-strand estimates (`moorfret run strand`).
    pub estimates: Option<StraightStrandEstimates>,
}

impl AxialStiffness {
    /// EA measured on the strand model (N), if it was (now or by an earlier run).
    pub fn strand_model_ea_n(&self) -> Option<f64> {
        matches!(
            self.source,
            StiffnessSource::Cached | StiffnessSource::Measured
        )
        .then_some(self.ea_n)
    }

    /// The `axial_stiffness` of a strand or calibration job's result: the rule applied, the EA
    /// used, the line type's and the strand model's.
    pub fn job_result(&self) -> serde_json::Value {
        let (rule, line_type_ea_n) = match self.campaign {
            Some((rule, ea)) => (Some(rule), Some(ea)),
            None => (None, None),
        };
        json!({
            "rule": rule,
            "ea_n": self.ea_n,
            "line_type_ea_n": line_type_ea_n,
            "strand_model_ea_n": self.strand_model_ea_n(),
        })
    }

    /// The `axial_stiffness` of a `run strand` summary.
    pub fn summary(&self) -> impl Serialize {
        let estimates = self.estimates;
        StiffnessSummary {
            ea_n: self.ea_n,
            source: self.source.as_str(),
            measured_at_strain: self.measured_at_strain,
            straight_strand_simple_n: estimates.map(|e| e.simple_n),
            straight_strand_costello_n: estimates.map(|e| e.costello_n),
            straight_strand_contact_compliant_n: estimates.and_then(|e| e.contact_compliant_n),
        }
    }
}

/// The `axial_stiffness` of a `run strand` summary, in its order.
#[derive(Serialize)]
struct StiffnessSummary {
    ea_n: f64,
    /// "measured" (by this run), "cached" (measured by an earlier run on the same model) or
    /// "given" (`--axial-stiffness-n`).
    source: &'static str,
    /// Strain of the tension step that measured it on the model, or null when it was given.
    measured_at_strain: Option<f64>,
    /// Straight-strand estimates for comparison (N): wire tensions only, with Costello's
    /// bending and twisting terms, and the latter with the helix radii shortened by the
    /// contact penetrations (penalty normal law only).
    straight_strand_simple_n: Option<f64>,
    straight_strand_costello_n: Option<f64>,
    straight_strand_contact_compliant_n: Option<f64>,
}

/// How to get a measured EA.
#[derive(Debug, Clone, Copy)]
pub struct StiffnessRequest<'a> {
    /// Directory of the cache; `None`: no cache.
    pub cache_dir: Option<&'a Path>,
    /// Axial strain of the tension step.
    pub strain: f64,
    /// The history settings of the tension step (its Newton settings key the cache).
    pub options: &'a HistoryOptions,
    /// Measure even if the cache holds it; the new value replaces the cached one.
    pub refresh: bool,
}

/// Why no EA was measured.
#[derive(Debug, thiserror::Error)]
pub enum StiffnessError {
    /// The strand model could not be built.
    #[error(transparent)]
    Model(#[from] StrandModelError),
    /// The tension step failed.
    #[error("measuring the axial stiffness EA of the strand model: {0}")]
    Measure(HistoryError),
}

/// EA measured on the model of `model`: read from the cache of `request`, or measured (the
/// model built if it is not yet) and cached; with [`StiffnessSource::Cached`] or
/// [`StiffnessSource::Measured`]. A cache that cannot be written is logged: it costs only a
/// measurement next time.
pub fn measured_ea_n(
    model: &mut LazyModel<'_>,
    request: &StiffnessRequest<'_>,
) -> Result<(f64, StiffnessSource), StiffnessError> {
    let cache = request.cache_dir.map(|dir| {
        StiffnessCache::new(
            dir,
            model.strand,
            model.params,
            request.strain,
            &request.options.initialisation_newton(),
        )
    });
    if let Some(ea) = cache
        .as_ref()
        .filter(|_| !request.refresh)
        .and_then(StiffnessCache::get)
    {
        return Ok((ea, StiffnessSource::Cached));
    }
    let ea = moorfret_solver::strand::history::stiffness::measure_axial_stiffness_n(
        model.get()?,
        request.strain,
        request.options,
    )
    .map_err(StiffnessError::Measure)?;
    if let Some(c) = &cache {
        if let Err(e) = c.put(ea, request.strain) {
            tracing::warn!(error = %e, file = %c.file().display(), "EA not cached");
        }
    }
    Ok((ea, StiffnessSource::Measured))
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The two forms of the one description: a `run strand` summary's and a strand job's
    /// result, in the fields and the order their files have always had.
    #[test]
    fn a_summary_and_a_job_result_keep_their_fields() {
        let given = AxialStiffness {
            ea_n: 2.5e7,
            source: StiffnessSource::Given,
            measured_at_strain: None,
            campaign: None,
            estimates: Some(StraightStrandEstimates {
                simple_n: 2.6e7,
                costello_n: 2.55e7,
                contact_compliant_n: None,
            }),
        };
        assert_eq!(
            serde_json::to_string(&given.summary()).unwrap(),
            "{\"ea_n\":25000000.0,\"source\":\"given\",\"measured_at_strain\":null,\
             \"straight_strand_simple_n\":26000000.0,\"straight_strand_costello_n\":25500000.0,\
             \"straight_strand_contact_compliant_n\":null}"
        );
        assert_eq!(given.strand_model_ea_n(), None);
        let measured = AxialStiffness {
            source: StiffnessSource::Measured,
            measured_at_strain: Some(1e-3),
            campaign: Some((AxialStiffnessRule::StrandModel, 3.6e8)),
            estimates: None,
            ..given
        };
        assert_eq!(
            measured.job_result(),
            json!({ "rule": "strand_model", "ea_n": 2.5e7, "line_type_ea_n": 3.6e8,
                    "strand_model_ea_n": 2.5e7 })
        );
        let cached = AxialStiffness {
            source: StiffnessSource::Cached,
            ..measured
        };
        assert_eq!(cached.strand_model_ea_n(), Some(2.5e7));
    }
}
