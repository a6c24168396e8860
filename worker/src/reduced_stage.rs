//! The reduced strand stages of a `reduced` or `auto` campaign
//! (`moorfret_campaign::fidelity`, `moorfret_solver::strand::reduced`).
//!
//! - `calibrate` (per hot spot, once its global jobs are done; one for every hot spot with
//!   `strand.shared_calibration`): the load range of the hot spot (and of `shared_with`)
//!   over its payload's global jobs (ε = T / EA and κ, as the strand jobs load them; under the
//!   `strand_model` rule the first such job measures EA and caches it for the reduced and FE
//!   jobs), widened by `strand.calibration_margin` on each side, and the reduced response
//!   calibrated on the campaign's FE strand model over it. The calibration is stored as a
//!   content-addressed artifact (`reduced_strand`); its job result holds the range, the
//!   calibration's own report and its cost. With `strand.calibration_hs_fraction` > 0 a hot
//!   spot has two such jobs: the first over the largest seas' global jobs, which runs beside
//!   the other global jobs, and a check (`check_of`) after every global job, which keeps the
//!   first calibration (same artifact, no FE run) if its range covers every global job's load
//!   that a calibration can serve (up to the admissible fibre strain, beyond which a load fails
//!   under any calibration) and calibrates again over all of them otherwise. The reduced jobs
//!   read the check's.
//! - `strand_reduced` (one job per sea state, seed and hot spot): the strand load of its global
//!   job through the calibrated response; results as an FE strand job's (contact records,
//!   contact rows, damage inputs), marked `"fidelity": "reduced"`. Under
//!   `strand.skip_mild_share` a first-seed job whose sea state its hot spot skips as mild
//!   (`"skipped": "mild"`, [`crate::gate`]) does not run the strand model: it writes the T-N
//!   rows of the hot-spot tension only, and no contact or class rows.

use std::sync::{Arc, Mutex};
use std::time::Instant;

use moorfret_solver::strand::history::{
    HistoryObserver, HistoryOptions, HistoryProgress, LoadSample,
};
use moorfret_solver::strand::model::StrandModel;
use moorfret_solver::strand::profile::Strand;
use moorfret_solver::strand::reduced::{
    calibrate, model_key, run_reduced, CalibrationOptions, LoadRange, ReducedError, ReducedStrand,
};
use serde_json::json;

use crate::context::StageContext;
use crate::failure::{permanent, transient};
use crate::gate::{mild_seas_gate, skipped_mild_result};
use crate::strand::AxialStiffness;
use crate::strand_stage::{
    axial_stiffness, campaign_strand, damage_inputs, damage_rows, model_parameters, series_of,
    strand_load, strand_results, upstream_series, Upstream,
};
use moorfret_campaign::mild_seas::MildSeas;
use moorfret_campaign::{CalibratePayload, CampaignInputs, StrandPayload};
use moorfret_store::{
    ArtifactRole, ArtifactStore, FailureClass, JobArtifact, JobFailure, JobResults,
};

/// Logs the progress of the calibration's FE run about once a minute.
struct ProgressLog {
    job: String,
    last: Instant,
}

impl HistoryObserver for ProgressLog {
    fn progress(&mut self, p: &HistoryProgress) {
        if self.last.elapsed().as_secs_f64() >= 60.0 {
            self.last = Instant::now();
            tracing::info!(job = %self.job, segment = p.segment, segments = p.segments,
                "calibrating the reduced strand response");
        }
    }
}

/// The calibration settings of a campaign: the solver's, with the campaign's calibration
/// threads (`strand.calibration_threads`, by default the cores this process may use). The
/// design's chains are independent FE runs, so a second thread halves the calibration
/// (12.5 min for the six-layer paper strand on two cores); its results do not depend on the
/// threads. While global jobs remain, the threads share the cores with them.
fn calibration_options(inputs: &CampaignInputs) -> CalibrationOptions {
    CalibrationOptions {
        history: HistoryOptions {
            threads: inputs.spec.strand.calibration_threads(),
            ..HistoryOptions::default()
        },
        ..CalibrationOptions::default()
    }
}

/// Runs one calibration job (module docs).
pub fn run_calibrate(
    ctx: &StageContext<'_>,
    payload: &CalibratePayload,
) -> Result<JobResults, JobFailure> {
    let (inputs, lease, artifacts) = (ctx.inputs, ctx.lease, ctx.artifacts);
    let strand = campaign_strand(inputs)?;
    let params = model_parameters(inputs);
    let model = StrandModel::new(&strand, &params)
        .map_err(|e| permanent(FailureClass::InvalidStrand, e))?;
    let stiffness = axial_stiffness(inputs, payload.hot_spot_index, artifacts, Some(&model))?;
    let mut loads: Option<LoadRange> = None;
    for &hot_spot in std::iter::once(&payload.hot_spot_index).chain(&payload.shared_with) {
        let stiffness = if hot_spot == payload.hot_spot_index {
            stiffness
        } else {
            axial_stiffness(inputs, hot_spot, artifacts, Some(&model))?
        };
        for key in &payload.global_cache_keys {
            let series = series_of(ctx, key, hot_spot)?;
            let load = strand_load(inputs, series, stiffness)?;
            if let Some(r) = LoadRange::of(&load.samples) {
                loads = Some(loads.map_or(r, |l| l.union(r)));
            }
        }
    }
    let loads = loads.ok_or_else(|| {
        permanent(
            FailureClass::StrandHistory,
            "the campaign's global jobs gave no strand load samples",
        )
    })?;
    let options = calibration_options(inputs);
    let widened = loads.widened(inputs.spec.strand.calibration_margin);
    let max_fibre_strain = options.history.max_fibre_strain;
    let range = widened
        .within_fibre_strain(max_fibre_strain, strand.outer_diameter_m())
        .ok_or_else(|| {
            permanent(
                FailureClass::StrandHistory,
                format!(
                    "the hot spots' curvature alone ({:?} 1/m) takes the strand's surface beyond \
                     the admissible fibre strain {max_fibre_strain:e}: no load range to calibrate",
                    widened.curvature_per_m
                ),
            )
        })?;
    if let Some(first) = &payload.check_of {
        let (bytes, kept) = calibration_of(ctx, first)?;
        // loads beyond the range a new calibration would take (beyond the strand's elastic
        // range) fail at their hot spots under any calibration: no reason to calibrate again
        if kept.range.serves(&loads, &range) {
            tracing::info!(job = %lease.job, global_jobs = payload.global_cache_keys.len(),
                "every global job's load that a calibration can serve lies within the first \
                 calibration's range: kept");
            // the same artifact, no FE run of its own
            let artifact = put_calibration(artifacts, &bytes)?;
            let mut result = calibration_result(payload, stiffness, loads, &kept, &artifact);
            result["check_of"] = json!(first);
            result["kept"] = json!(true);
            return Ok(JobResults {
                result,
                artifacts: vec![artifact],
                ..JobResults::default()
            });
        }
        tracing::warn!(job = %lease.job, load_strain = ?loads.strain,
            load_curvature_per_m = ?loads.curvature_per_m, calibrated_strain = ?kept.range.strain,
            calibrated_curvature_per_m = ?kept.range.curvature_per_m,
            "a global job's load leaves the first calibration's range: calibrating again over \
             every global job");
    }
    if range.strain[1] < widened.strain[1] {
        tracing::warn!(job = %lease.job, load_strain = ?loads.strain,
            calibrated_strain = ?range.strain, max_fibre_strain,
            "the largest loads take the wires beyond their elastic range: the calibration stops \
             at the admissible fibre strain and the sea states beyond it fail at their hot spots");
    }
    tracing::info!(job = %lease.job, strain = ?range.strain, curvature_per_m = ?range.curvature_per_m,
        threads = options.history.threads, "calibrating the reduced strand response");
    let mut log = ProgressLog {
        job: lease.job.to_string(),
        last: Instant::now(),
    };
    let mut reduced = calibrate(&model, range, &options, &mut log)
        .map_err(|e| permanent(FailureClass::StrandHistory, e))?;
    reduced.model_key = model_key(&strand, &params, &options);
    let bytes =
        serde_json::to_vec(&reduced).map_err(|e| permanent(FailureClass::SerialiseResults, e))?;
    let artifact = put_calibration(artifacts, &bytes)?;
    let c = &reduced.calibration;
    let mut result = calibration_result(payload, stiffness, loads, &reduced, &artifact);
    for (field, value) in [
        ("design_samples", json!(c.design_samples)),
        ("fe_substeps", json!(c.fe_substeps)),
        ("fe_iterations", json!(c.fe_iterations)),
        ("fe_wall_time_s", json!(c.fe_wall_time_s)),
        ("chains", json!(c.chains)),
        ("threads", json!(options.history.threads)),
        ("fits", json!(c.fits)),
        ("replay", json!(c.replay)),
        ("check_of", json!(payload.check_of)),
        // the loads beyond the strand model's elastic range (none when the range holds them)
        (
            "strain_beyond_elastic_range",
            json!((range.strain[1] < widened.strain[1]).then_some(loads.strain[1])),
        ),
    ] {
        result[field] = value;
    }
    Ok(JobResults {
        result,
        artifacts: vec![artifact],
        ..JobResults::default()
    })
}

/// Stores a calibration as a content-addressed artifact.
fn put_calibration(artifacts: &ArtifactStore, bytes: &[u8]) -> Result<JobArtifact, JobFailure> {
    artifacts
        .put(ArtifactRole::ReducedStrand, bytes)
        .map_err(|e| transient(FailureClass::ArtifactIo, e))
}

/// What every calibration job's result holds: the load range of its global jobs, the
/// calibration's range, model key and artifact.
fn calibration_result(
    payload: &CalibratePayload,
    stiffness: AxialStiffness,
    loads: LoadRange,
    calibration: &ReducedStrand,
    artifact: &JobArtifact,
) -> serde_json::Value {
    json!({
        "hot_spot_index": payload.hot_spot_index,
        "shared_with": payload.shared_with,
        "global_jobs": payload.global_cache_keys.len(),
        "axial_stiffness": stiffness.job_result(),
        "load_range": loads,
        "calibrated_range": calibration.range,
        "design_strain_floor": calibration.lowest_designed_strain(),
        "model_key": calibration.model_key,
        "calibration_sha256": artifact.sha256,
    })
}

/// The calibration artifact of the calibration job with cache key `key`.
fn calibration_upstream(key: &str) -> Upstream<'_> {
    static ROLE: ArtifactRole = ArtifactRole::ReducedStrand;
    Upstream {
        what: "calibration",
        cache_key: key,
        role: &ROLE,
    }
}

/// The calibration of a reduced job's hot spot, from its calibration job's artifact: the
/// artifact's bytes and the validated calibration.
fn calibration_of(
    ctx: &StageContext<'_>,
    key: &str,
) -> Result<(Vec<u8>, ReducedStrand), JobFailure> {
    let upstream = calibration_upstream(key);
    let bytes = upstream.artifact(ctx)?;
    let reduced =
        ReducedStrand::from_json(&bytes).map_err(|e| permanent(FailureClass::BadArtifact, e))?;
    Ok((bytes, reduced))
}

/// Calibrations this process has read, by content address, the most recent last: a worker
/// runs many reduced jobs of the same few calibrations (one per hot spot, or one shared), each
/// megabytes of JSON. Content-addressed, so an entry cannot go stale.
static CALIBRATIONS: Mutex<Vec<(String, Arc<ReducedStrand>)>> = Mutex::new(Vec::new());

/// Calibrations kept by [`CALIBRATIONS`] (a campaign's hot spots, a few MB each).
const CALIBRATIONS_KEPT: usize = 8;

/// The calibration of a reduced job, from this process's [`CALIBRATIONS`] or read and
/// validated from its calibration job's artifact.
fn cached_calibration(ctx: &StageContext<'_>, key: &str) -> Result<Arc<ReducedStrand>, JobFailure> {
    let upstream = calibration_upstream(key);
    let sha256 = upstream.artifact_sha256(ctx)?;
    let kept = |cache: &mut Vec<(String, Arc<ReducedStrand>)>| {
        let at = cache.iter().position(|(s, _)| *s == sha256)?;
        let entry = cache.remove(at);
        let reduced = entry.1.clone();
        cache.push(entry);
        Some(reduced)
    };
    // a poisoned lock only means another job panicked while holding it: the entries are whole
    let mut cache = CALIBRATIONS.lock().unwrap_or_else(|e| e.into_inner());
    if let Some(reduced) = kept(&mut cache) {
        return Ok(reduced);
    }
    drop(cache);
    let bytes = ctx
        .artifacts
        .get(&sha256)
        .map_err(|e| transient(FailureClass::ArtifactIo, e))?;
    let reduced = Arc::new(
        ReducedStrand::from_json(&bytes).map_err(|e| permanent(FailureClass::BadArtifact, e))?,
    );
    let mut cache = CALIBRATIONS.lock().unwrap_or_else(|e| e.into_inner());
    if kept(&mut cache).is_none() {
        if cache.len() == CALIBRATIONS_KEPT {
            cache.remove(0);
        }
        cache.push((sha256, reduced.clone()));
    }
    Ok(reduced)
}

/// Wall time of a job's phases, logged at debug level (where a job's time goes).
struct PhaseClock {
    last: Instant,
    laps: Vec<(&'static str, f64)>,
}

impl PhaseClock {
    fn start() -> Self {
        Self {
            last: Instant::now(),
            laps: Vec::new(),
        }
    }

    /// Ends the phase `name`.
    fn lap(&mut self, name: &'static str) {
        self.laps.push((name, self.last.elapsed().as_secs_f64()));
        self.last = Instant::now();
    }
}

/// The diagnostic of a load beyond the strand model's elastic range, when that is why the
/// reduced response refused it: a sample whose fibre strain ε + |κ| D/2 exceeds the admissible
/// one lies beyond every calibration (which stops there); so does, within the elastic range, a
/// strain above a calibration whose highest strain that limit set at the range's largest
/// curvature (a calibration range is a box in (ε, κ)).
fn beyond_elastic_range(
    error: &ReducedError,
    strand: &Strand,
    range: &LoadRange,
    samples: &[LoadSample],
    options: &HistoryOptions,
) -> Option<String> {
    let ReducedError::OutOfRange {
        index,
        time_s,
        field,
        ..
    } = error
    else {
        return None;
    };
    let s = samples.get(*index)?;
    let diameter = strand.outer_diameter_m();
    let max = options.max_fibre_strain;
    let fibre = s.strain + s.bending_strain(diameter);
    if fibre > max {
        return Some(format!(
            "load sample {index} (t = {time_s} s): strain {:.3e} and curvature {:.3e} 1/m give \
             the fibre strain {fibre:.3e} at the strand surface, beyond the admissible {max:.3e} \
             of the strand model's elastic range (the wires would yield): this hot spot's \
             fretting is not computed in this sea state, whose tension calls for an extreme-load \
             check",
            s.strain, s.curvature_per_m
        ));
    }
    let bent = range.largest_bending_strain(diameter);
    // the calibration stopped at the admissible fibre strain at its largest curvature
    let capped = range.strain[1] + bent >= max * (1.0 - 1e-6);
    (*field == "strain" && s.strain > range.strain[1] && capped).then(|| {
        format!(
            "load sample {index} (t = {time_s} s): strain {:.3e} lies above the calibrated \
             range's highest {:.3e}, where the calibration stops so that its largest curvature \
             ({:.3e} 1/m) keeps the fibre strain within the admissible {max:.3e}; at this \
             instant's curvature ({:.3e} 1/m) the fibre strain {fibre:.3e} is within {:.0} % of \
             that elastic limit: this hot spot's fretting is not computed in this sea state, \
             whose tension calls for an extreme-load check (or an FE strand run, fidelity fe)",
            s.strain,
            range.strain[1],
            bent / (0.5 * diameter),
            s.curvature_per_m,
            100.0 * (1.0 - fibre / max)
        )
    })
}

/// A reduced job whose sea state its hot spot skips as mild: no strand model, but the T-N
/// damage of the hot-spot tension (the rope's design curves), which needs only the global
/// series, so that those figures still cover the whole year. The run-in is the campaign's
/// fixed one (`fatigue.run_in_s`), none where the campaign detects it on a strand run.
fn skipped_mild(
    ctx: &StageContext<'_>,
    payload: &StrandPayload,
    mild: &MildSeas,
) -> Result<JobResults, JobFailure> {
    let inputs = ctx.inputs;
    let series = upstream_series(ctx, payload)?;
    let stiffness = axial_stiffness(inputs, payload.hot_spot_index, ctx.artifacts, None)?;
    let load = strand_load(inputs, series, stiffness)?;
    let strand = campaign_strand(inputs)?;
    let run_in_samples = inputs
        .spec
        .fatigue
        .fixed_run_in_samples(inputs.spec.strand.load_interval_s)
        .unwrap_or(0);
    let damage = damage_inputs(inputs, payload, &strand, &load, run_in_samples, &[])?;
    let (damage_inputs, _) = damage_rows(
        payload.hot_spot_index as i64,
        payload.global.seed_index as i64,
        &damage,
    )
    .map_err(|e| permanent(FailureClass::SerialiseResults, e))?;
    let mut result = skipped_mild_result(payload, mild);
    result["effective_duration_s"] = json!(damage.effective_duration_s);
    result["run_in_samples"] = json!(run_in_samples);
    result["axial_stiffness"] = load.axial_stiffness.job_result();
    Ok(JobResults {
        result,
        damage_inputs,
        ..JobResults::default()
    })
}

/// Runs one reduced strand job (module docs).
pub fn run_strand_reduced(
    ctx: &StageContext<'_>,
    payload: &StrandPayload,
) -> Result<JobResults, JobFailure> {
    let (inputs, artifacts) = (ctx.inputs, ctx.artifacts);
    let key = payload.calibration_cache_key.as_deref().ok_or_else(|| {
        permanent(
            FailureClass::BadPayload,
            "a strand_reduced job needs calibration_cache_key",
        )
    })?;
    if let Some(mild) = mild_seas_gate(ctx, payload)? {
        return skipped_mild(ctx, payload, &mild);
    }
    let mut clock = PhaseClock::start();
    let reduced = cached_calibration(ctx, key)?;
    clock.lap("calibration");
    let series = upstream_series(ctx, payload)?;
    let stiffness = axial_stiffness(inputs, payload.hot_spot_index, artifacts, None)?;
    let load = strand_load(inputs, series, stiffness)?;
    let strand = campaign_strand(inputs)?;
    let options = inputs.spec.strand.history_options();
    clock.lap("load");
    let result = run_reduced(&reduced, &load.samples, &options).map_err(|e| {
        if let Some(beyond) =
            beyond_elastic_range(&e, &strand, &reduced.range, &load.samples, &options)
        {
            return permanent(FailureClass::StrandHistory, beyond);
        }
        // an extra seed is loaded through the calibration of the first seeds' load range
        if payload.global.extra_seed {
            permanent(
                FailureClass::StrandHistory,
                format!(
                    "{e} (an extra seed of simulation.extra_seeds, outside the first seeds' \
                     load range: raise strand.calibration_margin)"
                ),
            )
        } else {
            permanent(FailureClass::StrandHistory, e)
        }
    })?;
    let floor = reduced.lowest_designed_strain();
    let below = load.samples.iter().filter(|s| s.strain < floor).count();
    clock.lap("response");
    let mut results = strand_results(inputs, payload, &strand, &load, &result, artifacts)?;
    clock.lap("damage");
    tracing::debug!(job = %ctx.lease.job, phases_s = ?clock.laps, "reduced strand job");
    results.result["fidelity"] = json!("reduced");
    results.result["calibration"] = json!({
        "model_key": reduced.model_key,
        "range": reduced.range,
    });
    results.result["samples_below_design_strain"] = json!(below);
    Ok(results)
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::path::Path;

    /// The diagnostics of a load the calibrated range refuses, on the six-layer paper strand
    /// (D from its profile) with the admissible fibre strain 7e-3: beyond the elastic range at
    /// the sample; above a range capped by that limit at its largest curvature (the whole-year
    /// campaign's 6.32e-3 against 6.24e-3, at a small curvature); and no such diagnostic for a
    /// curvature outside the range or for a strain above a range the limit did not cap.
    #[test]
    fn a_refused_load_is_blamed_on_the_elastic_range_only_when_it_set_the_range() {
        let paper = Path::new(env!("CARGO_MANIFEST_DIR")).join("../campaigns/paper.json");
        let inputs = moorfret_campaign::resolve(&paper).unwrap().inputs;
        let strand = campaign_strand(&inputs).unwrap();
        let d = strand.outer_diameter_m();
        let options = HistoryOptions::default();
        let max = options.max_fibre_strain;
        let kappa = [-0.0031, 0.025];
        let capped = LoadRange {
            strain: [0.0, (max - kappa[1] * 0.5 * d) * (1.0 - 1e-9)],
            curvature_per_m: kappa,
        };
        let sample = |strain: f64, curvature_per_m: f64| LoadSample {
            time_s: 268.7,
            strain,
            curvature_per_m,
        };
        let refused = |field: &'static str, value: f64, range: &LoadRange| {
            let [low, high] = if field == "strain" {
                range.strain
            } else {
                range.curvature_per_m
            };
            ReducedError::OutOfRange {
                index: 0,
                time_s: 268.7,
                field,
                value,
                low,
                high,
            }
        };
        let message = |s: LoadSample, e: ReducedError, range: &LoadRange| {
            beyond_elastic_range(&e, &strand, range, &[s], &options)
        };
        // beyond the elastic range at the sample itself
        let s = sample(max, 0.01);
        let m = message(s, refused("strain", s.strain, &capped), &capped).unwrap();
        assert!(m.contains("beyond the admissible"), "{m}");
        // within it, above the capped range
        let s = sample(
            capped.strain[1] + 0.5 * (max - capped.strain[1]) * 0.5,
            0.002,
        );
        assert!(s.strain + s.bending_strain(d) < max);
        let m = message(s, refused("strain", s.strain, &capped), &capped).unwrap();
        assert!(
            m.contains("lies above the calibrated range's highest"),
            "{m}"
        );
        assert!(m.contains("extreme-load check"), "{m}");
        // a curvature outside the range is no question of the elastic range
        let s = sample(1e-3, 0.03);
        assert!(message(s, refused("curvature_per_m", 0.03, &capped), &capped).is_none());
        // nor a strain above a range the limit did not cap
        let mild = LoadRange {
            strain: [0.0, 2e-3],
            curvature_per_m: kappa,
        };
        let s = sample(2.5e-3, 0.002);
        assert!(message(s, refused("strain", s.strain, &mild), &mild).is_none());
    }
}
