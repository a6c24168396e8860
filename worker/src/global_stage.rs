//! The `global` stage of a job: the campaign's base case with the job's sea state and seed,
//! coupled statics and dynamics (`moorfret_solver::global::run`), then per hot spot the
//! T(t), κ(t) series as a content-addressed artifact (role `hot_spot_<i>_series`) and a
//! `hot_spot_summaries` row (extremes, ranges, standard deviations, series hash).
//!
//! Invalid cases and diverging runs are deterministic: they fail the job at once with the
//! solver's diagnostic (time, line, node, residual). Artifact I/O errors are transient.

use moorfret_solver::floater::prescribed::PrescribedMotion;
use moorfret_solver::global::results::SeriesSummary;
use moorfret_solver::global::{run, FloaterInput, GlobalModel, HotSpotSeries, RunParams};
use serde_json::json;

use crate::failure::{permanent, transient};
use moorfret_campaign::payload::FloaterContent;
use moorfret_campaign::{CampaignInputs, GlobalPayload};
use moorfret_store::{
    ArtifactRole, ArtifactStore, FailureClass, HotSpotSummary, JobFailure, JobResults,
};

/// Runs one global job.
pub fn run_global(
    inputs: &CampaignInputs,
    payload: &GlobalPayload,
    artifacts: &ArtifactStore,
) -> Result<JobResults, JobFailure> {
    let case = inputs.case_of(payload);
    let floater = match &inputs.floater {
        FloaterContent::RigidBody(spec) => FloaterInput::RigidBody(spec.clone()),
        FloaterContent::PrescribedMotionCsv(text) => FloaterInput::Prescribed(
            PrescribedMotion::from_csv_str(text)
                .map_err(|e| permanent(FailureClass::InvalidCase, e))?,
        ),
    };
    let model = GlobalModel::new(&case, floater, None)
        .map_err(|e| permanent(FailureClass::InvalidCase, e))?;
    let params = RunParams {
        threads: inputs.spec.simulation.global_threads,
        ..RunParams::default()
    };
    let result =
        run(&model, &params, |_, _| {}).map_err(|e| permanent(FailureClass::GlobalDiverged, e))?;
    result
        .check_finite()
        .map_err(|e| permanent(FailureClass::GlobalNonFinite, e))?;
    tracing::info!(
        case = %case.name,
        statics_s = result.stats.statics_s,
        dynamics_s = result.stats.dynamics_s,
        "global stage done"
    );
    let mut out = JobResults::default();
    let mut series_hashes = Vec::new();
    for (index, h) in result.hot_spots.iter().enumerate() {
        let series = HotSpotSeries {
            time_s: result.time_s.clone(),
            tension_n: h.tension_n.clone(),
            curvature_per_m: h.curvature_per_m.clone(),
        };
        let artifact = artifacts
            .put(
                ArtifactRole::HotSpotSeries(index),
                series.to_csv().as_bytes(),
            )
            .map_err(|e| transient(FailureClass::ArtifactIo, e))?;
        out.hot_spots.push(HotSpotSummary {
            hot_spot_index: index as i64,
            summary: json!({
                "line": h.line,
                "arc_length_m": h.arc_length_m,
                "seed_index": payload.seed_index,
                "samples": series.time_s.len(),
                "duration_s": inputs.spec.simulation.duration_s,
                "tension_n": SeriesSummary::of(&h.tension_n),
                "curvature_per_m": SeriesSummary::of(&h.curvature_per_m),
                "series_sha256": artifact.sha256,
            }),
        });
        series_hashes.push(artifact.sha256.clone());
        out.artifacts.push(artifact);
    }
    let summary = result.summary();
    out.result = json!({
        "case": case.name,
        "wind_speed_m_s": result.wind_speed_m_s,
        "thrust_n": result.thrust_n,
        "lines": summary.lines,
        // The highest wave frequency the run kept, the limit that set it and what it kept.
        "wave_cut_off": summary.wave_cut_off,
        // Work counts only: wall times would make equal results differ.
        "work": {
            "steps": result.stats.steps,
            "coupling_iterations": result.stats.coupling_iterations,
            "line_iterations": result.stats.line_iterations,
            "cut_steps": result.stats.cut_steps,
            // Line steps written as the mirror image of a symmetric partner's.
            "mirrored_line_steps": result.stats.mirrored_line_steps,
        },
        "hot_spot_series_sha256": series_hashes,
    });
    Ok(out)
}
