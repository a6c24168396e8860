//! The `strand` stage of a job: load the hot-spot series of its global job (found by that
//! job's cache key, so a global result shared from another campaign serves as well), convert
//! it to the strand load ε(t) = T(t) / EA, κ(t) (DESIGN §4.4), sampled every `load_stride`
//! global output samples, and run the strand history on it.

use tokio::runtime::Handle;

use super::global_stage::series_role;
use super::series::HotSpotSeries;
use super::{permanent, transient};
use crate::campaign::{CampaignInputs, StrandPayload};
use crate::store::{ArtifactStore, JobFailure, JobResults, Lease, Store};

/// The strand load: axial strain and curvature at the sample times.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct StrandLoad {
    /// Times (s).
    pub time_s: Vec<f64>,
    /// Axial strain ε = T / EA.
    pub axial_strain: Vec<f64>,
    /// Curvature (1/m).
    pub curvature_per_m: Vec<f64>,
}

/// ε(t) = T(t) / EA and κ(t), every `stride`-th sample of `series`.
pub fn strand_load(series: &HotSpotSeries, axial_stiffness_n: f64, stride: usize) -> StrandLoad {
    let stride = stride.max(1);
    let pick = |x: &[f64]| x.iter().step_by(stride).copied().collect::<Vec<_>>();
    StrandLoad {
        time_s: pick(&series.time_s),
        axial_strain: series
            .tension_n
            .iter()
            .step_by(stride)
            .map(|t| t / axial_stiffness_n)
            .collect(),
        curvature_per_m: pick(&series.curvature_per_m),
    }
}

/// Loads the hot-spot series of the strand job's global job.
pub fn upstream_series(
    payload: &StrandPayload,
    store: &Store,
    artifacts: &ArtifactStore,
    rt: &Handle,
) -> Result<HotSpotSeries, JobFailure> {
    let source = rt
        .block_on(store.lookup_cache(&payload.global_cache_key))
        .map_err(|e| transient("store", e))?
        .ok_or_else(|| {
            transient(
                "upstream_missing",
                "no done global job carries this strand job's upstream cache key",
            )
        })?;
    let results = rt
        .block_on(store.results_of(source))
        .map_err(|e| transient("store", e))?;
    let role = series_role(payload.hot_spot_index);
    let artifact = results
        .artifacts
        .iter()
        .find(|a| a.role == role)
        .ok_or_else(|| permanent("upstream_missing", format!("job {source} has no {role}")))?;
    let bytes = artifacts
        .get(&artifact.sha256)
        .map_err(|e| transient("artifact_io", e))?;
    let text = String::from_utf8(bytes).map_err(|e| permanent("bad_artifact", e))?;
    HotSpotSeries::from_csv(&text).map_err(|e| permanent("bad_artifact", e))
}

/// Runs one strand job.
pub fn run_strand(
    inputs: &CampaignInputs,
    payload: &StrandPayload,
    _lease: &Lease,
    store: &Store,
    artifacts: &ArtifactStore,
    rt: &Handle,
) -> Result<JobResults, JobFailure> {
    let series = upstream_series(payload, store, artifacts, rt)?;
    let ea = inputs
        .hot_spot_axial_stiffness_n
        .get(payload.hot_spot_index)
        .copied()
        .ok_or_else(|| permanent("bad_payload", "hot spot index out of range"))?;
    let stride = (inputs.spec.strand.load_interval_s / inputs.spec.simulation.output_interval_s)
        .round() as usize;
    let load = strand_load(&series, ea, stride);
    Err(permanent(
        "strand_history_unavailable",
        format!(
            "the strand history solver is not part of this build; load of {} samples prepared",
            load.time_s.len()
        ),
    ))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn strain_is_tension_over_axial_stiffness_at_every_stride_sample() {
        let series = HotSpotSeries {
            time_s: vec![0.0, 0.1, 0.2, 0.3, 0.4],
            tension_n: vec![3.6e5, 7.2e5, 1.08e6, 0.0, 3.6e6],
            curvature_per_m: vec![0.01, 0.02, 0.03, 0.04, 0.05],
        };
        let load = strand_load(&series, 3.6e8, 2);
        assert_eq!(load.time_s, vec![0.0, 0.2, 0.4]);
        for (e, expected) in load.axial_strain.iter().zip([1e-3, 3e-3, 1e-2]) {
            // one division: within an ulp of the quotient
            assert!((e - expected).abs() <= f64::EPSILON * expected, "{e}");
        }
        assert_eq!(load.curvature_per_m, vec![0.01, 0.03, 0.05]);
    }
}
