//! The `strand` stage of a job: load the hot-spot series of its global job (found by that
//! job's cache key, so a global result shared from another campaign serves as well), convert
//! it to the strand load ε(t) = T(t) / EA and κ(t) (docs/strand-runs.md, "Strand jobs in
//! campaigns"), sampled every `load_stride` global output samples, and drive the detailed
//! strand model through it (`moorfret_solver::strand::history`). EA follows the campaign's rule
//! (`moorfret_campaign::stiffness`): measured on the strand model, once per model and artifact
//! directory (the first job to need it measures it, the others read it back), or the line
//! type's; the job result gives both.
//!
//! Results: the full per-contact records ([`ContactRecord`]: position, largest normal force,
//! rainflow slip cycles with their forces) as one content-addressed JSON artifact
//! (`contact_records`), and one small `contact_statistics` row per contact (class, cycle
//! count, largest slip range, largest normal force). From the records and the hot-spot tension
//! at the same samples, the per-sea-state damage inputs
//! (`moorfret_solver::damage::sea_state_damage_inputs`, configured by the campaign's
//! `fatigue` settings, [`moorfret_campaign::fatigue`]): one `damage_inputs` row per T-N curve and
//! one `class_damage_inputs` row per contact class, written with the job's completion.
//!
//! Checkpoints: the history run hands its full state over every few segments; at most every
//! `checkpoint_interval_s` of wall time it is written to the artifact store and a pointer file
//! `checkpoints/<job cache key>` (temp file + rename) names the newest one. A re-claimed job
//! resumes from it (and says so in its result, `resumed_from_checkpoint`); the solver
//! guarantees the result is bit-identical to an uninterrupted run. A checkpoint that cannot be
//! read, or that the solver refuses as another model's or history's, is logged and the job
//! starts over.
//! Slack samples (T < 0) are loaded as ε = 0 and counted in the job result.

use std::time::Duration;

use moorfret_solver::damage::{sea_state_damage_inputs, SeaStateInputs, TensionHistory};
use moorfret_solver::fretting::ContactRecord;
use moorfret_solver::global::HotSpotSeries;
use moorfret_solver::strand::history::stiffness::{samples_from_tension, SlackTension};
use moorfret_solver::strand::history::{HistoryResult, LoadSample};
use moorfret_solver::strand::model::{StrandModel, StrandModelParameters};
use moorfret_solver::strand::profile::Strand;
use serde_json::json;

use crate::context::StageContext;
use crate::failure::{permanent, transient};
use crate::gate::{auto_fe_selection, unselected_fe_result};
use crate::strand::checkpoint::{CheckpointTarget, Checkpoints};
use crate::strand::{
    measured_ea_n, run_fe, AxialStiffness, LazyModel, RefusedCheckpoint, StiffnessError,
    StiffnessRequest, StiffnessSource,
};
use moorfret_campaign::resolve::hot_spot_line_type;
use moorfret_campaign::spec::StrandContactLaws;
use moorfret_campaign::stiffness::{AxialStiffnessRule, STIFFNESS_STRAIN};
use moorfret_campaign::{CampaignInputs, StrandPayload};
use moorfret_store::{
    ArtifactRole, ArtifactStore, ClassDamageInput, ContactStatistics, DamageInput, FailureClass,
    JobFailure, JobResults, StoreError,
};

/// Loads the hot-spot series of the strand job's global job. The store reads are retried
/// under `retry` while the database is unreachable, as the worker loop's calls are.
pub fn upstream_series(
    ctx: &StageContext<'_>,
    payload: &StrandPayload,
) -> Result<HotSpotSeries, JobFailure> {
    series_of(ctx, &payload.global_cache_key, payload.hot_spot_index)
}

/// Loads the series of hot spot `hot_spot_index` of the done global job of `global_cache_key`.
pub fn series_of(
    ctx: &StageContext<'_>,
    global_cache_key: &str,
    hot_spot_index: usize,
) -> Result<HotSpotSeries, JobFailure> {
    let upstream = Upstream {
        what: "global",
        cache_key: global_cache_key,
        role: &ArtifactRole::HotSpotSeries(hot_spot_index),
    };
    let bytes = upstream.artifact(ctx)?;
    let text = String::from_utf8(bytes).map_err(|e| permanent(FailureClass::BadArtifact, e))?;
    HotSpotSeries::from_csv(&text).map_err(|e| permanent(FailureClass::BadArtifact, e))
}

/// An artifact of an upstream job, found by the job's cache key (so a result shared from another
/// campaign serves as well) and the artifact's role.
pub(crate) struct Upstream<'a> {
    /// What the upstream job is, for messages ("global", "calibration").
    pub what: &'a str,
    /// Its cache key.
    pub cache_key: &'a str,
    /// The artifact's role.
    pub role: &'a ArtifactRole,
}

impl Upstream<'_> {
    /// The artifact's bytes. The store reads are retried under `retry` while the database is
    /// unreachable, as the worker loop's calls are.
    pub(crate) fn artifact(&self, ctx: &StageContext<'_>) -> Result<Vec<u8>, JobFailure> {
        let sha256 = self.artifact_sha256(ctx)?;
        ctx.artifacts
            .get(&sha256)
            .map_err(|e| transient(FailureClass::ArtifactIo, e))
    }

    /// The content address (sha256) of the artifact, without reading it.
    pub(crate) fn artifact_sha256(&self, ctx: &StageContext<'_>) -> Result<String, JobFailure> {
        let store = ctx.store;
        let what = self.what;
        let source = ctx
            .store_call("look up upstream job", || {
                store.lookup_cache(self.cache_key)
            })?
            .ok_or_else(|| {
                transient(
                    FailureClass::UpstreamMissing,
                    format!("no done {what} job carries this job's {what} cache key"),
                )
            })?;
        let results = ctx.store_call("read upstream results", || store.results_of(source))?;
        results
            .artifacts
            .into_iter()
            .find(|a| a.role == *self.role)
            .map(|a| a.sha256)
            .ok_or_else(|| {
                permanent(
                    FailureClass::UpstreamMissing,
                    format!("job {source} has no {}", self.role),
                )
            })
    }
}

/// The model parameters of the campaign's strand settings.
pub(crate) fn model_parameters(inputs: &CampaignInputs) -> StrandModelParameters {
    let st = &inputs.spec.strand;
    match st.contact_laws {
        StrandContactLaws::Regularised => StrandModelParameters::penalty_contact(
            st.normal_penalty_n_per_m
                .expect("a validated spec with regularised laws has a normal penalty"),
            st.elastic_slip_m
                .expect("a validated spec with regularised laws has an elastic slip"),
            st.ends.end_kind(),
        ),
        StrandContactLaws::ContactMechanics => {
            StrandModelParameters::contact_mechanics(st.ends.end_kind())
        }
    }
}

fn contact_row(hot_spot_index: usize, index: usize, c: &ContactRecord) -> ContactStatistics {
    ContactStatistics {
        hot_spot_index: hot_spot_index as i64,
        contact_index: index as i64,
        layer_interface: c.interface as i64,
        angular_position_rad: c.theta_rad,
        statistics: json!({
            "position_class": c.class().position.as_str(),
            "z_m": c.z_m,
            "max_normal_force_n": c.max_normal_force_n,
            "slip_cycles": c.slip_cycle_count(),
            "max_slip_range_m": c.max_slip_range_m(),
        }),
    }
}

/// The EA of hot spot `hot_spot_index` under the campaign's rule (module docs). Under the
/// `strand_model` rule it is read from the artifact directory's cache or measured on `model`
/// (built here when `None`) and cached ([`measured_ea_n`]).
pub(crate) fn axial_stiffness(
    inputs: &CampaignInputs,
    hot_spot_index: usize,
    artifacts: &ArtifactStore,
    model: Option<&StrandModel>,
) -> Result<AxialStiffness, JobFailure> {
    let line_type_ea_n = inputs
        .hot_spot_axial_stiffness_n
        .get(hot_spot_index)
        .copied()
        .ok_or_else(|| permanent(FailureClass::BadPayload, "hot spot index out of range"))?;
    let rule = inputs.spec.strand.axial_stiffness_rule();
    if rule == AxialStiffnessRule::LineType {
        return Ok(AxialStiffness {
            ea_n: line_type_ea_n,
            source: StiffnessSource::LineType,
            measured_at_strain: None,
            campaign: Some((rule, line_type_ea_n)),
            estimates: None,
        });
    }
    let strand = campaign_strand(inputs)?;
    let params = model_parameters(inputs);
    let options = inputs.spec.strand.history_options();
    let request = StiffnessRequest {
        cache_dir: Some(artifacts.dir()),
        strain: STIFFNESS_STRAIN,
        options: &options,
        refresh: false,
    };
    let mut lazy = LazyModel::with_model(&strand, &params, model);
    let (ea_n, source) = measured_ea_n(&mut lazy, &request).map_err(|e| match e {
        StiffnessError::Model(e) => permanent(FailureClass::InvalidStrand, e),
        e @ StiffnessError::Measure(_) => permanent(FailureClass::StrandHistory, e),
    })?;
    // whether this job measured EA is logged, not stored: a job's result does not depend on
    // which job measured first, nor on a resume
    tracing::info!(
        ea_n,
        source = source.as_str(),
        "axial stiffness EA of the strand model"
    );
    Ok(AxialStiffness {
        ea_n,
        source,
        measured_at_strain: Some(STIFFNESS_STRAIN),
        campaign: Some((rule, line_type_ea_n)),
        estimates: None,
    })
}

/// The strand load of a strand job: its global job's hot-spot series and the strand samples.
pub(crate) struct StrandLoad {
    /// The hot-spot series of the global job.
    pub series: HotSpotSeries,
    /// The strand load samples (every `stride`-th series sample).
    pub samples: Vec<LoadSample>,
    /// Samples with T < 0, loaded as ε = 0.
    pub slack_samples: usize,
    /// Series samples per load sample.
    pub stride: usize,
    /// The EA of ε = T / EA.
    pub axial_stiffness: AxialStiffness,
}

/// The strand load of `series` under the campaign's settings, with EA from `axial_stiffness`
/// (module docs).
pub(crate) fn strand_load(
    inputs: &CampaignInputs,
    series: HotSpotSeries,
    axial_stiffness: AxialStiffness,
) -> Result<StrandLoad, JobFailure> {
    let stride = (inputs.spec.strand.load_interval_s / inputs.spec.simulation.output_interval_s)
        .round() as usize;
    let (samples, slack_samples) = samples_from_tension(
        &series.time_s,
        &series.tension_n,
        &series.curvature_per_m,
        axial_stiffness.ea_n,
        stride,
        SlackTension::AsZero,
    )
    .map_err(|e| permanent(FailureClass::StrandHistory, e))?;
    Ok(StrandLoad {
        series,
        samples,
        slack_samples,
        stride,
        axial_stiffness,
    })
}

/// The campaign's strand, validated.
pub(crate) fn campaign_strand(inputs: &CampaignInputs) -> Result<Strand, JobFailure> {
    inputs
        .profile
        .validate()
        .map_err(|e| permanent(FailureClass::InvalidStrand, e))
}

/// Runs one FE strand job. An FE job of an `auto` campaign (`if_selected`) first asks the
/// campaign's reduced results whether its sea state is selected (settling the unselected FE
/// jobs of its hot spot, [`crate::gate`]), and ends at once, with no result rows, if it is not.
pub fn run_strand(
    ctx: &StageContext<'_>,
    payload: &StrandPayload,
) -> Result<JobResults, JobFailure> {
    let (inputs, artifacts) = (ctx.inputs, ctx.artifacts);
    let selection = if payload.if_selected {
        let selection = auto_fe_selection(ctx, payload.hot_spot_index)?;
        if !selection.contains(payload.global.sea_state_index as i64) {
            return Ok(JobResults {
                result: unselected_fe_result(payload, &selection),
                ..JobResults::default()
            });
        }
        Some(selection)
    } else {
        None
    };
    let series = upstream_series(ctx, payload)?;
    let strand = campaign_strand(inputs)?;
    let model = StrandModel::new(&strand, &model_parameters(inputs))
        .map_err(|e| permanent(FailureClass::InvalidStrand, e))?;
    let stiffness = axial_stiffness(inputs, payload.hot_spot_index, artifacts, Some(&model))?;
    let load = strand_load(inputs, series, stiffness)?;
    let options = inputs.spec.strand.history_options();
    let target = ctx
        .lease
        .cache_key
        .as_ref()
        .map(|k| CheckpointTarget::Artifacts {
            artifacts,
            pointer: artifacts.dir().join("checkpoints").join(k),
        });
    // a checkpoint that cannot be read is logged and the job starts over
    let resume = target.as_ref().and_then(|t| {
        t.read().unwrap_or_else(|e| {
            tracing::warn!(pointer = %t.path().display(), error = %e,
                "checkpoint not readable; starting over");
            None
        })
    });
    let mut writer = Checkpoints::new(
        target,
        Duration::from_secs_f64(inputs.spec.strand.checkpoint_interval_s),
    );
    let run = run_fe(
        &model,
        &load.samples,
        &options,
        resume.as_ref(),
        RefusedCheckpoint::StartOver,
        &mut writer,
    )
    .map_err(|e| permanent(FailureClass::StrandHistory, e))?;
    let (result, resumed) = (run.result, run.resumed);
    let mut results = strand_results(inputs, payload, &strand, &load, &result, artifacts)?;
    results.result["fidelity"] = json!("fe");
    results.result["resumed_from_checkpoint"] = json!(resumed);
    if let Some(selection) = selection {
        results.result["selected"] = json!(true);
        results.result["selection"] = json!(selection);
    }
    Ok(results)
}

/// The results of a strand run, FE or reduced: the contact records artifact, one statistics
/// row per contact, the damage inputs, and the job result (without its `fidelity`).
pub(crate) fn strand_results(
    inputs: &CampaignInputs,
    payload: &StrandPayload,
    strand: &Strand,
    load: &StrandLoad,
    result: &HistoryResult,
    artifacts: &ArtifactStore,
) -> Result<JobResults, JobFailure> {
    let artifact = if inputs.spec.strand.contact_records {
        let records = serde_json::to_vec(&result.contacts)
            .map_err(|e| permanent(FailureClass::SerialiseResults, e))?;
        Some(
            artifacts
                .put(ArtifactRole::ContactRecords, &records)
                .map_err(|e| transient(FailureClass::ArtifactIo, e))?,
        )
    } else {
        None
    };
    let contacts = result
        .contacts
        .iter()
        .enumerate()
        .map(|(i, c)| contact_row(payload.hot_spot_index, i, c))
        .collect();
    let (run_in_samples, run_in) = run_in(inputs, result);
    let damage = damage_inputs(
        inputs,
        payload,
        strand,
        load,
        run_in_samples,
        &result.contacts,
    )?;
    let (damage_inputs, class_damage_inputs) = damage_rows(
        payload.hot_spot_index as i64,
        payload.global.seed_index as i64,
        &damage,
    )
    .map_err(|e| permanent(FailureClass::SerialiseResults, e))?;
    let s = &result.stats;
    Ok(JobResults {
        result: json!({
            "hot_spot_index": payload.hot_spot_index,
            "seed_index": payload.global.seed_index,
            "samples": load.samples.len(),
            "slack_samples": load.slack_samples,
            "axial_stiffness": load.axial_stiffness.job_result(),
            "contacts": result.contacts.len(),
            "contact_records_sha256": artifact.as_ref().map(|a| a.sha256.clone()),
            "effective_duration_s": damage.effective_duration_s,
            "run_in_samples": damage.run_in_samples,
            "run_in": run_in,
            "work": {
                "kept_samples": s.kept_samples,
                "substeps": s.substeps,
                "newton_steps": s.newton_steps,
                "cutbacks": s.cutbacks,
                "iterations": s.iterations,
            },
        }),
        contacts,
        damage_inputs,
        class_damage_inputs,
        artifacts: artifact.into_iter().collect(),
        ..JobResults::default()
    })
}

/// The run-in of a strand run (module docs of `moorfret_campaign::fatigue`): the samples left
/// out of the statistics, and what the detection found on the slip monitors.
fn run_in(inputs: &CampaignInputs, result: &HistoryResult) -> (usize, serde_json::Value) {
    let fatigue = &inputs.spec.fatigue;
    let dt = inputs.spec.strand.load_interval_s;
    let fixed = fatigue.fixed_run_in_samples(dt);
    let (detected, detection) = fatigue.run_in_detection.detect(&result.monitors, dt);
    let too_short = detection.get("error").is_some();
    let (samples, source) = match (fixed, detected) {
        (Some(f), _) => (f, "fixed"),
        (None, Some(d)) => (d, "detected"),
        (None, None) if too_short => (0, "too_short_to_detect"),
        (None, None) => (0, "not_stabilised"),
    };
    (
        samples,
        json!({
            "source": source,
            "excluded_s": samples as f64 * dt,
            "detection": detection,
        }),
    )
}

/// The damage inputs of the run (`moorfret_solver::damage::sea_state_damage_inputs`): the
/// contact records with the hot-spot tension at the same samples as the strand load (every
/// `stride`-th global output sample), the first `run_in_samples` left out, configured by the
/// campaign's fatigue settings.
pub(crate) fn damage_inputs(
    inputs: &CampaignInputs,
    payload: &StrandPayload,
    strand: &Strand,
    load: &StrandLoad,
    run_in_samples: usize,
    records: &[ContactRecord],
) -> Result<SeaStateInputs, JobFailure> {
    let spec = &inputs.spec;
    let hot_spot = spec
        .hot_spots
        .get(payload.hot_spot_index)
        .ok_or_else(|| permanent(FailureClass::BadPayload, "hot spot index out of range"))?;
    let line_type =
        hot_spot_line_type(&inputs.base_case, hot_spot.arc_length_m).ok_or_else(|| {
            permanent(
                FailureClass::BadPayload,
                "the hot spot lies on no defined line type",
            )
        })?;
    let config = spec
        .fatigue
        .damage_config(strand, line_type, load.axial_stiffness.ea_n);
    let stride = load.stride.max(1);
    let tension: Vec<f64> = load
        .series
        .tension_n
        .iter()
        .step_by(stride)
        .copied()
        .collect();
    let history = TensionHistory {
        tension_n: &tension,
        dt_s: stride as f64 * spec.simulation.output_interval_s,
        run_in_samples,
    };
    sea_state_damage_inputs(records, &history, &config)
        .map_err(|e| permanent(FailureClass::DamageInputs, e))
}

/// Rows of one (sea state, seed, hot spot): T-N damage per curve, fretting inputs per class.
pub(crate) fn damage_rows(
    hot_spot_index: i64,
    seed_index: i64,
    inputs: &SeaStateInputs,
) -> Result<(Vec<DamageInput>, Vec<ClassDamageInput>), StoreError> {
    let json = |field: &'static str, value: Result<serde_json::Value, serde_json::Error>| {
        value.map_err(|source| StoreError::Json { field, source })
    };
    let tension = inputs
        .tension
        .iter()
        .map(|t| {
            Ok(DamageInput {
                hot_spot_index,
                measure: t.measure.clone(),
                seed_index,
                effective_duration_s: inputs.effective_duration_s,
                damage: t.damage,
                details: serde_json::json!({
                    "curve": json("damage_inputs.details_json", serde_json::to_value(t.curve))?,
                    "cycles": t.cycles,
                    "mean_tension_n": t.mean_tension_n,
                    "run_in_samples": inputs.run_in_samples,
                }),
            })
        })
        .collect::<Result<Vec<_>, StoreError>>()?;
    let classes = inputs
        .classes
        .iter()
        .map(|c| {
            Ok(ClassDamageInput {
                hot_spot_index,
                layer_interface: c.class.interface as i64,
                angular_position: c.class.position,
                seed_index,
                effective_duration_s: inputs.effective_duration_s,
                contacts: c.contacts as i64,
                fretting_damage_rate_max_per_s: c.fretting_damage_rate_max_per_s,
                fretting_damage_rate_mean_per_s: c.fretting_damage_rate_mean_per_s,
                stick_cycles_per_hour: c.regime_cycles_per_hour.stick,
                partial_slip_cycles_per_hour: c.regime_cycles_per_hour.partial_slip,
                gross_slip_cycles_per_hour: c.regime_cycles_per_hour.gross_slip,
                ruiz_f1_max: c.ruiz_f1_max,
                ruiz_f2_max: c.ruiz_f2_max,
                peak_pressure_max_pa: c.peak_pressure_max_pa,
                slip_amplitude_max_m: c.slip_amplitude_max_m,
                histogram: json(
                    "class_damage_inputs.histogram_json",
                    serde_json::to_value(&c.cycles_per_hour),
                )?,
                rope_tn_damage_rate_max_per_s: c.rope_tn_damage_rate_max_per_s,
                rope_tn_damage_rate_mean_per_s: c.rope_tn_damage_rate_mean_per_s,
                wear_power_max_w: c.wear_power_max_w,
            })
        })
        .collect::<Result<Vec<_>, StoreError>>()?;
    Ok((tension, classes))
}

#[cfg(test)]
mod tests {
    use super::*;
    use moorfret_campaign::stiffness::StiffnessCache;
    use moorfret_solver::strand::history::stiffness::{
        measure_axial_stiffness_n, straight_strand_stiffness,
    };
    use std::path::Path;

    /// The `strand_model` rule measures EA on the campaign's strand model once per artifact
    /// directory (the solver's measurement, to the bit) and the next job reads it back;
    /// `line_type` takes the line type's EA. On the demo's 1+6+1 strand, whose contacts carry
    /// little, the measured EA lies just below the straight-strand estimate
    /// E (A_core + Σ n A cos³β) (docs/strand-runs.md: −0.8 %).
    #[test]
    fn the_strand_model_rule_measures_ea_once_and_line_type_takes_the_line_types() {
        let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("../campaigns/demo.json");
        let mut inputs = moorfret_campaign::resolve(&path).unwrap().inputs;
        let dir = tempfile::tempdir().unwrap();
        let artifacts = ArtifactStore::open(dir.path()).unwrap();

        let line = axial_stiffness(&inputs, 0, &artifacts, None).unwrap();
        assert_eq!(line.campaign, Some((AxialStiffnessRule::LineType, 3.6e8)));
        assert_eq!(line.ea_n, 3.6e8);
        assert_eq!(line.strand_model_ea_n(), None);
        assert_eq!(
            line.job_result(),
            json!({ "rule": "line_type", "ea_n": 3.6e8, "line_type_ea_n": 3.6e8,
                    "strand_model_ea_n": null })
        );

        inputs.spec.strand.axial_stiffness = Some(AxialStiffnessRule::StrandModel);
        let strand = campaign_strand(&inputs).unwrap();
        let options = inputs.spec.strand.history_options();
        let cache = StiffnessCache::new(
            artifacts.dir(),
            &strand,
            &model_parameters(&inputs),
            STIFFNESS_STRAIN,
            &options.initialisation_newton(),
        );
        assert_eq!(cache.get(), None);
        let first = axial_stiffness(&inputs, 0, &artifacts, None).unwrap();
        assert_eq!(cache.get(), Some(first.ea_n));
        assert_eq!(first.source, StiffnessSource::Measured);
        assert_eq!(
            first.campaign,
            Some((AxialStiffnessRule::StrandModel, 3.6e8))
        );
        assert_eq!(first.strand_model_ea_n(), Some(first.ea_n));
        let estimate = straight_strand_stiffness(&strand).simple_n;
        let relative = (first.ea_n - estimate) / estimate;
        assert!(
            (-0.02..0.0).contains(&relative),
            "EA {} N against the estimate {estimate} N",
            first.ea_n
        );
        let model = StrandModel::new(&strand, &model_parameters(&inputs)).unwrap();
        let direct = measure_axial_stiffness_n(&model, STIFFNESS_STRAIN, &options).unwrap();
        assert_eq!(first.ea_n, direct);

        // read back, not measured again: a changed entry is what the next job gets
        cache.put(2.0 * first.ea_n, STIFFNESS_STRAIN).unwrap();
        let second = axial_stiffness(&inputs, 0, &artifacts, Some(&model)).unwrap();
        assert_eq!(second.ea_n, 2.0 * first.ea_n);
        assert_eq!(second.source, StiffnessSource::Cached);
        assert_eq!(
            second.job_result(),
            json!({ "rule": "strand_model", "ea_n": second.ea_n, "line_type_ea_n": 3.6e8,
                    "strand_model_ea_n": second.ea_n })
        );

        let e = axial_stiffness(&inputs, 3, &artifacts, None).unwrap_err();
        assert_eq!(e.error_class, FailureClass::BadPayload);
        assert!(e.message.contains("hot spot index"), "{}", e.message);
    }
}
