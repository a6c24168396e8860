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

/// A sea state whose realisation keeps far less of its spectrum's energy than the campaign
/// allows (`simulation.min_wave_energy_kept`, the planning's check; a tenth of it as margin for
/// the discrete band) fails at once, before its dynamics: its loads would not be computed, and
/// a sea state with a failed job never counts as covered. Planning refuses such sea states;
/// this keeps a campaign stored before it did from running one in calm water.
fn check_energy_kept(inputs: &CampaignInputs, kept: f64) -> Result<(), JobFailure> {
    let min_kept = inputs
        .spec
        .simulation
        .min_wave_energy_kept
        .unwrap_or(moorfret_campaign::sea_limits::DEFAULT_MIN_ENERGY_KEPT);
    if kept < 0.9 * min_kept {
        return Err(permanent(
            FailureClass::InvalidCase,
            format!(
                "the wave cut-off keeps {:.1} % of the sea state's spectral energy, less than \
                 simulation.min_wave_energy_kept {:.1} %: its loads would not be computed",
                100.0 * kept,
                100.0 * min_kept
            ),
        ));
    }
    Ok(())
}

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
    check_energy_kept(inputs, model.wave_cut_off.kept_m0_fraction)?;
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

#[cfg(test)]
mod tests {
    use super::*;
    use std::path::Path;

    /// A sea state wholly above the wave cut-off (Tp 0.5 s), as a store planned before the
    /// planning's checks may hold, fails at once instead of running in calm water with damage
    /// 0; the demo's own sea state runs past the check.
    #[test]
    fn a_sea_state_above_the_cut_off_fails_before_its_dynamics() {
        let demo = Path::new(env!("CARGO_MANIFEST_DIR")).join("../campaigns/demo.json");
        let inputs = moorfret_campaign::resolve(&demo).unwrap().inputs;
        let dir = tempfile::tempdir().unwrap();
        let artifacts = ArtifactStore::open(dir.path()).unwrap();
        let payload = GlobalPayload {
            sea_state_index: 0,
            hs_m: 0.25,
            tp_s: 0.5,
            seed_index: 0,
            seed: 7,
            extra_seed: false,
            heading_deg: None,
        };
        let failure = run_global(&inputs, &payload, &artifacts).unwrap_err();
        assert_eq!(failure.kind, moorfret_store::FailureKind::Permanent);
        assert_eq!(failure.error_class, FailureClass::InvalidCase);
        assert!(
            failure.message.contains("keeps 0.0 %")
                && failure.message.contains("simulation.min_wave_energy_kept"),
            "{}",
            failure.message
        );
        // the check passes the demo's own sea states
        assert!(check_energy_kept(&inputs, 0.99).is_ok());
        assert!(check_energy_kept(&inputs, 0.46).is_ok());
        assert!(check_energy_kept(&inputs, 0.44).is_err());
    }
}
