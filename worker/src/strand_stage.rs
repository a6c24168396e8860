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
//! (`moorfret_solver::fretting::sea_state_damage_inputs`, configured by the campaign's
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

use std::path::{Path, PathBuf};
use std::time::{Duration, Instant};

use moorfret_solver::fretting::{
    sea_state_damage_inputs, ContactRecord, SeaStateInputs, TensionHistory,
};
use moorfret_solver::strand::history::checkpoint::HistoryCheckpoint;
use moorfret_solver::strand::history::stiffness::{
    measure_axial_stiffness_n, samples_from_tension, SlackTension,
};
use moorfret_solver::strand::history::{
    run_history_from, HistoryObserver, HistoryResult, LoadSample,
};
use moorfret_solver::strand::model::{StrandModel, StrandModelParameters};
use moorfret_solver::strand::profile::Strand;
use serde::Serialize;
use serde_json::json;
use tokio::runtime::Handle;

use crate::failure::{permanent, transient};
use crate::gate::{auto_fe_selection, unselected_fe_result, GateContext};
use crate::global_stage::series_role;
use crate::series::HotSpotSeries;
use moorfret_campaign::resolve::hot_spot_line_type;
use moorfret_campaign::spec::StrandContactLaws;
use moorfret_campaign::stiffness::{
    replace_file, AxialStiffnessRule, StiffnessCache, STIFFNESS_STRAIN,
};
use moorfret_campaign::{CampaignInputs, StrandPayload};
use moorfret_store::{
    damage_rows, ArtifactStore, ContactStatistics, FailureClass, JobFailure, JobResults, Lease,
    RetryPolicy, Store,
};

/// Loads the hot-spot series of the strand job's global job. The store reads are retried
/// under `retry` while the database is unreachable, as the worker loop's calls are.
pub fn upstream_series(
    payload: &StrandPayload,
    store: &Store,
    retry: &RetryPolicy,
    artifacts: &ArtifactStore,
    rt: &Handle,
) -> Result<HotSpotSeries, JobFailure> {
    series_of(
        &payload.global_cache_key,
        payload.hot_spot_index,
        store,
        retry,
        artifacts,
        rt,
    )
}

/// Loads the series of hot spot `hot_spot_index` of the done global job of `global_cache_key`.
pub fn series_of(
    global_cache_key: &str,
    hot_spot_index: usize,
    store: &Store,
    retry: &RetryPolicy,
    artifacts: &ArtifactStore,
    rt: &Handle,
) -> Result<HotSpotSeries, JobFailure> {
    let role = series_role(hot_spot_index);
    let upstream = Upstream {
        what: "global",
        cache_key: global_cache_key,
        role: &role,
    };
    let bytes = upstream.artifact(store, retry, artifacts, rt)?;
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
    pub role: &'a str,
}

impl Upstream<'_> {
    /// The artifact's bytes. The store reads are retried under `retry` while the database is
    /// unreachable, as the worker loop's calls are.
    pub(crate) fn artifact(
        &self,
        store: &Store,
        retry: &RetryPolicy,
        artifacts: &ArtifactStore,
        rt: &Handle,
    ) -> Result<Vec<u8>, JobFailure> {
        let what = self.what;
        let source = rt
            .block_on(retry.run("look up upstream job", || {
                store.lookup_cache(self.cache_key)
            }))
            .map_err(|e| transient(FailureClass::Store, e))?
            .ok_or_else(|| {
                transient(
                    FailureClass::UpstreamMissing,
                    format!("no done {what} job carries this job's {what} cache key"),
                )
            })?;
        let results = rt
            .block_on(retry.run("read upstream results", || store.results_of(source)))
            .map_err(|e| transient(FailureClass::Store, e))?;
        let artifact = results
            .artifacts
            .iter()
            .find(|a| a.role == self.role)
            .ok_or_else(|| {
                permanent(
                    FailureClass::UpstreamMissing,
                    format!("job {source} has no {}", self.role),
                )
            })?;
        artifacts
            .get(&artifact.sha256)
            .map_err(|e| transient(FailureClass::ArtifactIo, e))
    }
}

/// Writes checkpoints to the artifact store, at most every `interval` of wall time.
struct CheckpointWriter<'a> {
    artifacts: &'a ArtifactStore,
    pointer: Option<PathBuf>,
    interval: Duration,
    last: Instant,
    written: usize,
}

impl CheckpointWriter<'_> {
    fn write(&mut self, checkpoint: &HistoryCheckpoint) -> Result<(), String> {
        let Some(pointer) = &self.pointer else {
            return Ok(());
        };
        let bytes = checkpoint.to_bytes().map_err(|e| e.to_string())?;
        let artifact = self
            .artifacts
            .put("checkpoint", &bytes)
            .map_err(|e| e.to_string())?;
        // a worker whose lease was swept away may still be writing the same job's pointer
        // while its new claimant does: `replace_file` gives each its own temporary file
        replace_file(pointer, artifact.sha256.as_bytes()).map_err(|e| e.to_string())?;
        self.written += 1;
        Ok(())
    }
}

impl HistoryObserver for CheckpointWriter<'_> {
    fn checkpoint(&mut self, checkpoint: &HistoryCheckpoint) {
        if self.last.elapsed() < self.interval {
            return;
        }
        self.last = Instant::now();
        if let Err(e) = self.write(checkpoint) {
            // A missed checkpoint costs only recomputation after a crash.
            tracing::warn!(error = %e, "strand checkpoint not written");
        }
    }
}

/// The newest checkpoint named by `pointer`: `None` when there is none, or when it cannot be
/// read (missing or damaged artifact, format of another build), which is logged: the job then
/// starts over.
fn read_checkpoint(artifacts: &ArtifactStore, pointer: &Path) -> Option<HistoryCheckpoint> {
    let sha = match std::fs::read_to_string(pointer) {
        Ok(sha) => sha,
        Err(e) if e.kind() == std::io::ErrorKind::NotFound => return None,
        Err(e) => {
            tracing::warn!(pointer = %pointer.display(), error = %e, "checkpoint pointer not readable; starting over");
            return None;
        }
    };
    let read = artifacts
        .get(sha.trim())
        .map_err(|e| e.to_string())
        .and_then(|bytes| HistoryCheckpoint::from_bytes(&bytes).map_err(|e| e.to_string()));
    match read {
        Ok(checkpoint) => Some(checkpoint),
        Err(e) => {
            tracing::warn!(pointer = %pointer.display(), error = %e, "checkpoint not readable; starting over");
            None
        }
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

/// The EA of a strand job's tension → strain conversion under the campaign's rule
/// (`moorfret_campaign::stiffness`), with the line type's beside it.
#[derive(Debug, Clone, Copy, Serialize)]
pub(crate) struct AxialStiffness {
    /// The rule applied.
    pub rule: AxialStiffnessRule,
    /// EA of ε = T / EA and of the fretting stress's metallic area EA / E (N).
    pub ea_n: f64,
    /// EA of the global line type at the hot spot (N).
    pub line_type_ea_n: f64,
    /// EA measured on the strand model (N), under the `strand_model` rule.
    pub strand_model_ea_n: Option<f64>,
}

/// The EA of hot spot `hot_spot_index` (module docs). Under the `strand_model` rule it is read
/// from the artifact directory's cache or measured on `model` (built here when `None`) and
/// cached.
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
            rule,
            ea_n: line_type_ea_n,
            line_type_ea_n,
            strand_model_ea_n: None,
        });
    }
    let strand = campaign_strand(inputs)?;
    let params = model_parameters(inputs);
    let options = inputs.spec.strand.history_options();
    let cache = StiffnessCache::new(
        artifacts.dir(),
        &strand,
        &params,
        STIFFNESS_STRAIN,
        &options.initialisation_newton(),
    );
    let (ea_n, source) = match cache.get() {
        Some(ea) => (ea, "cached"),
        None => {
            let built;
            let model = match model {
                Some(m) => m,
                None => {
                    built = StrandModel::new(&strand, &params)
                        .map_err(|e| permanent(FailureClass::InvalidStrand, e))?;
                    &built
                }
            };
            let ea = measure_axial_stiffness_n(model, STIFFNESS_STRAIN, &options).map_err(|e| {
                permanent(
                    FailureClass::StrandHistory,
                    format!("measuring the axial stiffness EA of the strand model: {e}"),
                )
            })?;
            if let Err(e) = cache.put(ea, STIFFNESS_STRAIN) {
                tracing::warn!(error = %e, file = %cache.file().display(), "EA not cached");
            }
            (ea, "measured")
        }
    };
    // whether this job measured EA is logged, not stored: a job's result does not depend on
    // which job measured first, nor on a resume
    tracing::info!(ea_n, source, "axial stiffness EA of the strand model");
    Ok(AxialStiffness {
        rule,
        ea_n,
        line_type_ea_n,
        strand_model_ea_n: Some(ea_n),
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
    inputs: &CampaignInputs,
    payload: &StrandPayload,
    lease: &Lease,
    store: &Store,
    retry: &RetryPolicy,
    artifacts: &ArtifactStore,
    rt: &Handle,
) -> Result<JobResults, JobFailure> {
    let selection = if payload.if_selected {
        let ctx = GateContext {
            inputs,
            lease,
            store,
            retry,
            rt,
        };
        let selection = auto_fe_selection(&ctx, payload.hot_spot_index)?;
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
    let series = upstream_series(payload, store, retry, artifacts, rt)?;
    let strand = campaign_strand(inputs)?;
    let model = StrandModel::new(&strand, &model_parameters(inputs))
        .map_err(|e| permanent(FailureClass::InvalidStrand, e))?;
    let stiffness = axial_stiffness(inputs, payload.hot_spot_index, artifacts, Some(&model))?;
    let load = strand_load(inputs, series, stiffness)?;
    let options = inputs.spec.strand.history_options();
    let pointer = lease
        .cache_key
        .as_ref()
        .map(|k| artifacts.dir().join("checkpoints").join(k));
    let resume = pointer.as_ref().and_then(|p| read_checkpoint(artifacts, p));
    let mut writer = CheckpointWriter {
        artifacts,
        pointer,
        interval: Duration::from_secs_f64(inputs.spec.strand.checkpoint_interval_s),
        last: Instant::now(),
        written: 0,
    };
    if let Some(cp) = &resume {
        tracing::info!(job = %lease.job, segment = cp.next_segment,
            segments = cp.kept_samples.len().saturating_sub(1),
            "strand job resumes from its checkpoint");
    }
    let samples = &load.samples;
    let mut resumed = resume.is_some();
    let result = match run_history_from(&model, samples, &options, resume.as_ref(), &mut writer) {
        Ok(r) => r,
        // A checkpoint from another build or input is not used: start over.
        Err(moorfret_solver::strand::history::HistoryError::Checkpoint { reason })
            if resume.is_some() =>
        {
            tracing::warn!(job = %lease.job, %reason, "checkpoint refused; starting over");
            resumed = false;
            run_history_from(&model, samples, &options, None, &mut writer)
                .map_err(|e| permanent(FailureClass::StrandHistory, e))?
        }
        Err(e) => return Err(permanent(FailureClass::StrandHistory, e)),
    };
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
                .put("contact_records", &records)
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
            "axial_stiffness": load.axial_stiffness,
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

/// The damage inputs of the run (`moorfret_solver::fretting::sea_state_damage_inputs`): the
/// contact records with the hot-spot tension at the same samples as the strand load (every
/// `stride`-th global output sample), the first `run_in_samples` left out, configured by the
/// campaign's fatigue settings.
fn damage_inputs(
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

#[cfg(test)]
mod tests {
    use super::*;
    use moorfret_solver::strand::history::stiffness::straight_strand_stiffness;

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
        assert_eq!(line.rule, AxialStiffnessRule::LineType);
        assert_eq!(line.ea_n, 3.6e8);
        assert_eq!(line.strand_model_ea_n, None);

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
        assert_eq!(first.line_type_ea_n, 3.6e8);
        assert_eq!(first.strand_model_ea_n, Some(first.ea_n));
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

        let e = axial_stiffness(&inputs, 3, &artifacts, None).unwrap_err();
        assert_eq!(e.error_class, FailureClass::BadPayload);
        assert!(e.message.contains("hot spot index"), "{}", e.message);
    }

    #[test]
    fn no_checkpoint_without_a_pointer_or_with_a_pointer_to_an_unreadable_one() {
        let dir = tempfile::tempdir().unwrap();
        let artifacts = ArtifactStore::open(dir.path()).unwrap();
        let pointer = dir.path().join("checkpoints").join("key");
        assert!(read_checkpoint(&artifacts, &pointer).is_none());
        std::fs::create_dir_all(pointer.parent().unwrap()).unwrap();
        // a pointer to an artifact that is not there
        std::fs::write(&pointer, "ab".repeat(32)).unwrap();
        assert!(read_checkpoint(&artifacts, &pointer).is_none());
        // a pointer to an artifact that is no checkpoint
        let other = artifacts.put("contact_records", b"[]").unwrap();
        std::fs::write(&pointer, &other.sha256).unwrap();
        assert!(read_checkpoint(&artifacts, &pointer).is_none());
    }
}
