//! Gated jobs: jobs that run only if a selection over stored results picks their sea state.
//!
//! Three gates, all pure functions of stored rows (no driver, no planning job):
//!
//! - the FE jobs of an `auto` campaign (`StrandPayload::if_selected`): selected by the reduced
//!   first-seed results of their hot spot (`moorfret_campaign::fidelity::select_fe_sea_states`);
//! - the jobs of an extra seed (`GlobalPayload::extra_seed`, `simulation.extra_seeds`): selected
//!   by the first-seed strand results of the campaign, FE with `fe` and reduced with `reduced`
//!   and `auto` (`moorfret_campaign::seeds`); a global job for any hot spot, a strand job for
//!   its own;
//! - the first-seed reduced jobs under `strand.skip_mild_share`: skipped when their hot spot's
//!   mild sea states (`moorfret_campaign::mild_seas`, from the first-seed global results, all
//!   done before the calibration every reduced job depends on) include their sea state.
//!
//! Every gated job depends on every job whose rows its selection reads, so all of them find
//! the same selection. In the first two gates, the first gated job to compute it also settles, in one store
//! transaction ([`Store::settle`]), every job of its group that is not selected and still
//! waits (ready or blocked): done, no rows, a result that says `selected: false` and which job
//! settled it. The unselected jobs thus never wait in the queue behind the selected ones; one
//! that another worker is already running reaches the same answer itself.

use std::collections::BTreeMap;
use std::sync::{Arc, Mutex};

use serde_json::{json, Value};

use crate::context::StageContext;
use moorfret_campaign::fidelity::{select_fe_sea_states, ClassDamageRate, Selection};
use moorfret_campaign::mild_seas::{mild_sea_states, MildSeas, SeaStateLoad};
use moorfret_campaign::seeds::select_extra_seed_sea_states;
use moorfret_campaign::{GlobalPayload, StrandPayload};
use moorfret_store::{
    CampaignId, FailureClass, JobFailure, JobId, JobKind, JobRecord, JobResults, JobState,
};

impl StageContext<'_> {
    /// The class rows of the campaign's done jobs of `kind` with seed index below the first
    /// seeds, per hot spot.
    fn first_seed_rows(
        &self,
        kind: JobKind,
    ) -> Result<BTreeMap<i64, Vec<ClassDamageRate>>, JobFailure> {
        let first = i64::from(self.inputs.spec.simulation.seeds_per_sea_state);
        let rows = self.store_call("read first-seed strand results", || {
            self.store.class_rows_of_kind(self.lease.campaign, kind)
        })?;
        let mut per_hot_spot: BTreeMap<i64, Vec<ClassDamageRate>> = BTreeMap::new();
        for (sea_state_index, occurrence_fraction, c) in &rows {
            if c.seed_index >= first {
                continue;
            }
            per_hot_spot
                .entry(c.hot_spot_index)
                .or_default()
                .push(ClassDamageRate {
                    sea_state_index: *sea_state_index,
                    occurrence_fraction: *occurrence_fraction,
                    seed_index: c.seed_index,
                    class: (c.layer_interface, c.angular_position.as_str()),
                    damage_rate_per_s: c.fretting_damage_rate_max_per_s,
                });
        }
        Ok(per_hot_spot)
    }

    /// Settles the listed jobs (module docs); logs how many.
    fn settle(&self, jobs: Vec<(JobId, Value)>) -> Result<(), JobFailure> {
        if jobs.is_empty() {
            return Ok(());
        }
        let settled = self.store_call("settle unselected jobs", || self.store.settle(&jobs))?;
        tracing::info!(job = %self.lease.job, settled = settled.len(),
            "unselected gated jobs settled");
        Ok(())
    }

    /// The campaign's jobs that still wait (ready or blocked).
    fn waiting_jobs(&self) -> Result<Vec<JobRecord>, JobFailure> {
        let jobs = self.store_call("list jobs", || {
            self.store.jobs_of_campaign(self.lease.campaign)
        })?;
        Ok(jobs
            .into_iter()
            .filter(|j| {
                j.id != self.lease.job && matches!(j.state, JobState::Ready | JobState::Blocked)
            })
            .collect())
    }
}

/// The FE selection of an `auto` campaign for hot spot `hot_spot_index`, from the reduced
/// first-seed results; the unselected FE jobs of that hot spot that still wait are settled.
pub(crate) fn auto_fe_selection(
    ctx: &StageContext<'_>,
    hot_spot_index: usize,
) -> Result<Selection, JobFailure> {
    let rows = ctx.first_seed_rows(JobKind::StrandReduced)?;
    let rows = rows
        .get(&(hot_spot_index as i64))
        .map_or(&[][..], Vec::as_slice);
    let selection = select_fe_sea_states(rows, &ctx.inputs.spec.strand.auto_fe);
    let mut unselected = Vec::new();
    for job in ctx.waiting_jobs()? {
        if job.kind != JobKind::Strand {
            continue;
        }
        let Ok(p) = serde_json::from_value::<StrandPayload>(job.payload.clone()) else {
            continue;
        };
        if p.if_selected
            && p.hot_spot_index == hot_spot_index
            && !selection.contains(p.global.sea_state_index as i64)
        {
            let mut result = unselected_fe_result(&p, &selection);
            result["settled_by"] = json!(ctx.lease.job.0);
            unselected.push((job.id, result));
        }
    }
    ctx.settle(unselected)?;
    Ok(selection)
}

/// The result of an FE job of an `auto` campaign whose sea state is not selected.
pub(crate) fn unselected_fe_result(payload: &StrandPayload, selection: &Selection) -> Value {
    json!({
        "fidelity": "fe",
        "selected": false,
        "hot_spot_index": payload.hot_spot_index,
        "seed_index": payload.global.seed_index,
        "selection": selection,
    })
}

/// The extra-seed selections of every hot spot (`moorfret_campaign::seeds`).
fn extra_seed_selections(ctx: &StageContext<'_>) -> Result<Vec<Selection>, JobFailure> {
    let Some(rule) = &ctx.inputs.spec.simulation.extra_seeds else {
        return Err(crate::failure::permanent(
            FailureClass::BadPayload,
            "an extra-seed job in a campaign without simulation.extra_seeds",
        ));
    };
    let kind = if ctx.inputs.spec.strand.fidelity.uses_reduced() {
        JobKind::StrandReduced
    } else {
        JobKind::Strand
    };
    let rows = ctx.first_seed_rows(kind)?;
    let first = ctx.inputs.spec.simulation.seeds_per_sea_state;
    Ok((0..ctx.inputs.spec.hot_spots.len())
        .map(|h| {
            let rows = rows.get(&(h as i64)).map_or(&[][..], Vec::as_slice);
            select_extra_seed_sea_states(rows, first, rule)
        })
        .collect())
}

/// Whether the realisation `global` is selected: for hot spot `hot_spot` (a strand job), or for
/// any hot spot (`None`, a global job).
fn is_selected(selections: &[Selection], global: &GlobalPayload, hot_spot: Option<usize>) -> bool {
    let s = global.sea_state_index as i64;
    match hot_spot {
        Some(h) => selections.get(h).is_some_and(|sel| sel.contains(s)),
        None => selections.iter().any(|sel| sel.contains(s)),
    }
}

/// The result of an extra-seed job that does not run.
fn unselected_extra_result(
    global: &GlobalPayload,
    hot_spot: Option<usize>,
    selections: &[Selection],
) -> Value {
    json!({
        "selected": false,
        "extra_seed": true,
        "sea_state_index": global.sea_state_index,
        "seed_index": global.seed_index,
        "hot_spot_index": hot_spot,
        "selection": selections,
    })
}

/// The gate of a job of an extra seed (`global` its realisation, `hot_spot` its hot spot for a
/// strand job): `Some(results)` to end with when its sea state is not selected, `None` to run.
/// Either way the campaign's unselected extra-seed jobs that still wait are settled.
pub(crate) fn extra_seed_gate(
    ctx: &StageContext<'_>,
    global: &GlobalPayload,
    hot_spot: Option<usize>,
) -> Result<Option<JobResults>, JobFailure> {
    let selections = extra_seed_selections(ctx)?;
    let mut unselected = Vec::new();
    for job in ctx.waiting_jobs()? {
        let (g, h) = match job.kind {
            JobKind::Global => match serde_json::from_value::<GlobalPayload>(job.payload.clone()) {
                Ok(g) => (g, None),
                Err(_) => continue,
            },
            JobKind::Strand | JobKind::StrandReduced => {
                match serde_json::from_value::<StrandPayload>(job.payload.clone()) {
                    Ok(p) => (p.global, Some(p.hot_spot_index)),
                    Err(_) => continue,
                }
            }
            _ => continue,
        };
        if g.extra_seed && !is_selected(&selections, &g, h) {
            let mut result = unselected_extra_result(&g, h, &selections);
            result["settled_by"] = json!(ctx.lease.job.0);
            unselected.push((job.id, result));
        }
    }
    ctx.settle(unselected)?;
    if is_selected(&selections, global, hot_spot) {
        return Ok(None);
    }
    Ok(Some(JobResults {
        result: unselected_extra_result(global, hot_spot, &selections),
        ..JobResults::default()
    }))
}

/// The mild-sea selections of the campaigns this process has served: the first-seed global
/// results are all done before any reduced job runs, so one selection serves every job.
static MILD_SEAS: Mutex<Vec<(CampaignId, Arc<Vec<MildSeas>>)>> = Mutex::new(Vec::new());

/// The mild sea states of every hot spot (`moorfret_campaign::mild_seas`), from the
/// campaign's done first-seed global jobs: each one's hot-spot tension and curvature
/// standard deviations, the strand's EA per hot spot and its outer diameter.
fn mild_seas_of_campaign(ctx: &StageContext<'_>) -> Result<Vec<MildSeas>, JobFailure> {
    let inputs = ctx.inputs;
    let first = i64::from(inputs.spec.simulation.seeds_per_sea_state);
    let campaign = ctx.lease.campaign;
    let jobs = ctx.store_call("list jobs", || ctx.store.jobs_of_campaign(campaign))?;
    let states = ctx.store_call("read sea states", || ctx.store.sea_state_status(campaign))?;
    let occurrence: BTreeMap<i64, f64> = states
        .iter()
        .map(|s| (s.sea_state_index, s.occurrence_fraction))
        .collect();
    let diameter = crate::strand_stage::campaign_strand(inputs)?.outer_diameter_m();
    let hot_spots = inputs.spec.hot_spots.len();
    let ea: Vec<f64> = (0..hot_spots)
        .map(|h| {
            crate::strand_stage::axial_stiffness(inputs, h, ctx.artifacts, None).map(|s| s.ea_n)
        })
        .collect::<Result<_, _>>()?;
    let mut loads = vec![Vec::new(); hot_spots];
    for job in &jobs {
        if job.kind != JobKind::Global || job.state != JobState::Done {
            continue;
        }
        let Ok(g) = serde_json::from_value::<GlobalPayload>(job.payload.clone()) else {
            continue;
        };
        if g.extra_seed || g.seed_index as i64 >= first {
            continue;
        }
        let results = ctx.store_call("read global results", || ctx.store.results_of(job.id))?;
        for s in &results.hot_spots {
            let h = s.hot_spot_index as usize;
            let std = |what: &str| s.summary[what]["std"].as_f64().unwrap_or(f64::NAN);
            if let (Some(list), Some(&ea)) = (loads.get_mut(h), ea.get(h)) {
                let sea_state = g.sea_state_index as i64;
                list.push(SeaStateLoad {
                    sea_state_index: sea_state,
                    occurrence_fraction: occurrence.get(&sea_state).copied().unwrap_or(f64::NAN),
                    tp_s: g.tp_s,
                    measure: SeaStateLoad::fibre_strain_measure(
                        std("tension_n"),
                        std("curvature_per_m"),
                        ea,
                        diameter,
                    ),
                });
            }
        }
    }
    let share = inputs.spec.strand.skip_mild_share;
    Ok(loads.iter().map(|l| mild_sea_states(l, share)).collect())
}

/// The result of a reduced job whose sea state its hot spot skips as mild.
pub(crate) fn skipped_mild_result(payload: &StrandPayload, mild: &MildSeas) -> Value {
    json!({
        "fidelity": "reduced",
        "skipped": "mild",
        "hot_spot_index": payload.hot_spot_index,
        "sea_state_index": payload.global.sea_state_index,
        "seed_index": payload.global.seed_index,
        "mild_seas": {
            "share": mild.share,
            "proxy_share": mild.proxy_share,
            "occurrence_fraction": mild.occurrence_fraction,
            "largest_skipped_measure": mild.largest_skipped_measure,
            "skipped": mild.skipped.len(),
            "sea_states": mild.sea_states,
        },
    })
}

/// The gate of a first-seed reduced job under `strand.skip_mild_share`: its hot spot's mild
/// sea states when they include the job's (the job then skips the strand model), `None` to
/// run. The first job of a campaign in this process computes the selections of every hot spot
/// from the stored global results and keeps them: every reduced job depends on the calibration,
/// which waits for every first-seed global job, so all find the same selection.
pub(crate) fn mild_seas_gate(
    ctx: &StageContext<'_>,
    payload: &StrandPayload,
) -> Result<Option<MildSeas>, JobFailure> {
    if ctx.inputs.spec.strand.skip_mild_share <= 0.0 || payload.global.extra_seed {
        return Ok(None);
    }
    let campaign = ctx.lease.campaign;
    let known = |cache: &Vec<(CampaignId, Arc<Vec<MildSeas>>)>| {
        cache
            .iter()
            .find(|(c, _)| *c == campaign)
            .map(|(_, m)| m.clone())
    };
    // a poisoned lock only means another job panicked while holding it: the entries are whole
    let cached = known(&MILD_SEAS.lock().unwrap_or_else(|e| e.into_inner()));
    let selections = match cached {
        Some(s) => s,
        None => {
            let selections = Arc::new(mild_seas_of_campaign(ctx)?);
            for (h, m) in selections.iter().enumerate() {
                tracing::info!(job = %ctx.lease.job, hot_spot = h, skipped = m.skipped.len(),
                    sea_states = m.sea_states, proxy_share = m.proxy_share,
                    year_share = m.occurrence_fraction, "mild sea states skipped");
            }
            let mut cache = MILD_SEAS.lock().unwrap_or_else(|e| e.into_inner());
            if known(&cache).is_none() {
                cache.push((campaign, selections.clone()));
            }
            selections
        }
    };
    Ok(selections
        .get(payload.hot_spot_index)
        .filter(|m| m.skips(payload.global.sea_state_index as i64))
        .cloned())
}
