//! What the report shows, read from the store.

use std::collections::BTreeMap;

use anyhow::Context;
use moorfret_solver::fretting::{AngularPosition, CycleHistogram};
use moorfret_solver::global::HotSpotSeries;

use crate::query::{self, Table};
use moorfret_store::{
    ArtifactRole, ArtifactStore, JobKind, JobState, LifetimeClassDamage, SeaStateStatus, Store,
};

/// The contact class with the largest annual `fretting_max` damage.
#[derive(Debug, Clone, PartialEq)]
pub struct CriticalClass {
    /// Hot spot index.
    pub hot_spot_index: i64,
    /// Layer interface.
    pub layer_interface: i64,
    /// Angular position.
    pub angular_position: AngularPosition,
    /// Annual damage.
    pub annual_damage: f64,
}

/// Slip amplitude histogram of one layer interface, cycles per hour of the year.
#[derive(Debug, Clone, PartialEq)]
pub struct SlipHistogram {
    /// Hot spot index.
    pub hot_spot_index: i64,
    /// Layer interface.
    pub layer_interface: i64,
    /// Bin edges (m).
    pub edges_m: Vec<f64>,
    /// Cycles per hour of the year in each bin.
    pub cycles_per_hour: Vec<f64>,
}

/// Hot-spot series of one global job.
#[derive(Debug, Clone, PartialEq)]
pub struct GlobalJobSeries {
    /// Sea state index of the job.
    pub sea_state_index: i64,
    /// Per hot spot, in the order of their indices.
    pub hot_spots: Vec<HotSpotSeries>,
}

/// One contact class under both fretting laws, with its cycles per regime over the year.
#[derive(Debug, Clone, PartialEq)]
pub struct ClassLives {
    /// Hot spot index.
    pub hot_spot_index: i64,
    /// Layer interface.
    pub layer_interface: i64,
    /// Angular position.
    pub angular_position: AngularPosition,
    /// Annual damage of the most damaged contact, campaign law (`fretting_max`).
    pub annual_damage: f64,
    /// Annual damage of the most damaged contact, rope S-N per slip cycle (`rope_tn_max`).
    pub rope_tn_annual_damage: f64,
    /// Cycles per hour of the year, summed over the class: stick, partial slip, gross slip.
    pub regime_cycles_per_hour: [f64; 3],
}

impl ClassLives {
    /// The regime holding most cycles.
    pub fn dominant_regime(&self) -> &'static str {
        let [s, p, g] = self.regime_cycles_per_hour;
        if g >= p && g >= s && g > 0.0 {
            "gross slip"
        } else if p >= s && p > 0.0 {
            "partial slip"
        } else if s > 0.0 {
            "stick"
        } else {
            "none"
        }
    }
}

/// A sea state of the climate without its results: failed, skipped or not run yet.
#[derive(Debug, Clone, PartialEq)]
pub struct UnfinishedSeaState {
    /// Its directional sector (`None` for a climate of one table).
    pub sector: Option<String>,
    /// Its index in the campaign; `None` for a cell left out of the plan.
    pub sea_state_index: Option<i64>,
    /// Significant wave height (m).
    pub hs_m: f64,
    /// Peak period (s).
    pub tp_s: f64,
    /// Fraction of the year.
    pub occurrence_fraction: f64,
    /// `failed`, `skipped` or `not run yet`.
    pub status: &'static str,
    /// Why: the first failure's diagnostic, the wave model's objection, or the jobs done.
    pub reason: String,
}

/// Longest diagnostic shown for a failed sea state (characters).
const REASON_CHARS: usize = 240;

/// Sea states that failed, were skipped (left out of the plan, cancelled) or wait, in that
/// order, each in plan order; the cells left out come from the stored spec's `left_out`.
fn unfinished(
    states: &[SeaStateStatus],
    jobs: &[moorfret_store::JobRecord],
    stored_spec: Option<&serde_json::Value>,
) -> Vec<UnfinishedSeaState> {
    let mut failed = Vec::new();
    let mut skipped = Vec::new();
    let mut waiting = Vec::new();
    for s in states {
        let of_state: Vec<&moorfret_store::JobRecord> = jobs
            .iter()
            .filter(|j| j.sea_state.map(|id| id.0) == Some(s.sea_state_id))
            .collect();
        let entry = |status, reason| UnfinishedSeaState {
            sector: s.sector.clone(),
            sea_state_index: Some(s.sea_state_index),
            hs_m: s.hs_m,
            tp_s: s.tp_s,
            occurrence_fraction: s.occurrence_fraction,
            status,
            reason,
        };
        let first_failed = of_state
            .iter()
            .filter(|j| j.state == JobState::Failed)
            .min_by_key(|j| j.id.0);
        let cancelled = of_state
            .iter()
            .filter(|j| j.state == JobState::Cancelled)
            .count();
        if let Some(job) = first_failed {
            let message = job
                .error_message
                .as_deref()
                .unwrap_or("no diagnostic stored")
                .lines()
                .next()
                .unwrap_or_default();
            let mut message: String = message.chars().take(REASON_CHARS).collect();
            if message.chars().count() == REASON_CHARS {
                message.push('…');
            }
            let class = job
                .error_class
                .map(|c| format!(" ({})", c.as_str()))
                .unwrap_or_default();
            failed.push(entry(
                "failed",
                format!(
                    "{} of {} jobs failed; {} job {}{class}: {message}",
                    s.jobs_failed,
                    s.jobs_total,
                    job.kind.as_str(),
                    job.id.0
                ),
            ));
        } else if cancelled > 0 {
            skipped.push(entry(
                "skipped",
                format!(
                    "campaign cancelled: {cancelled} of {} jobs cancelled",
                    s.jobs_total
                ),
            ));
        } else if s.jobs_done < s.jobs_total {
            waiting.push(entry(
                "not run yet",
                format!("{} of {} jobs done", s.jobs_done, s.jobs_total),
            ));
        }
    }
    let left_out = stored_spec
        .and_then(|spec| spec.get("left_out"))
        .and_then(serde_json::Value::as_array)
        .map(Vec::as_slice)
        .unwrap_or_default();
    let mut cells: Vec<UnfinishedSeaState> = left_out
        .iter()
        .map(|c| UnfinishedSeaState {
            sector: c["sector"].as_str().map(str::to_owned),
            sea_state_index: None,
            hs_m: c["hs_m"].as_f64().unwrap_or(f64::NAN),
            tp_s: c["tp_s"].as_f64().unwrap_or(f64::NAN),
            occurrence_fraction: c["occurrence_fraction"].as_f64().unwrap_or(f64::NAN),
            status: "skipped",
            reason: format!(
                "left out of the plan (outside the wave model): {}",
                c["reason"].as_str().unwrap_or_default()
            ),
        })
        .collect();
    cells.append(&mut skipped);
    failed.append(&mut cells);
    failed.append(&mut waiting);
    failed
}

/// Everything on the page.
#[derive(Debug, Clone)]
pub struct ReportData {
    /// Campaign name.
    pub name: String,
    /// Sea states.
    pub sea_states: Vec<SeaStateStatus>,
    /// Critical class, if any fretting result is stored.
    pub critical: Option<CriticalClass>,
    /// Per sea state index: share of the critical class's annual fretting damage.
    pub fretting_share: BTreeMap<i64, f64>,
    /// T-N measure shown, and per sea state index its share of the annual T-N damage.
    pub tn_share: Option<(String, BTreeMap<i64, f64>)>,
    /// Slip histograms per hot spot and layer interface.
    pub histograms: Vec<SlipHistogram>,
    /// Hot-spot series, if an artifact holds them.
    pub series: Option<GlobalJobSeries>,
    /// Lifetime table (`query lifetime`).
    pub lifetime: Table,
    /// Per contact class: both fretting laws and the regimes, most damaged class first.
    pub class_lives: Vec<ClassLives>,
    /// Damage inputs of the critical class (`query damage-inputs`), largest share first.
    pub damage_inputs: Table,
    /// Seed-to-seed spread of the critical class (`query seeds`, `fretting_max`), largest
    /// share first.
    pub seeds: Table,
    /// Per sea state index: the strand fidelity of its counted results (`fe`, `reduced`,
    /// `mixed`).
    pub fidelity: BTreeMap<i64, String>,
    /// Reduced against FE where both ran (`query fidelity`).
    pub comparison: Table,
    /// Results of the calibration jobs (load range, cost, in-sample fit).
    pub calibrations: Vec<serde_json::Value>,
    /// Per sea state index: the run-in detected on its counted strand result (s), `None` when
    /// the history never stabilised or was too short; the run-in left out of its statistics (s).
    pub run_in: BTreeMap<i64, (Option<f64>, f64)>,
    /// The design check (`query utilisation`, `lines`, `directions`); `None` for a campaign
    /// stored without its inputs.
    pub design: Option<crate::design::DesignCheck>,
    /// Sea states without their results: failed, skipped or not run yet.
    pub unfinished: Vec<UnfinishedSeaState>,
}

/// Rows of the damage-inputs table in the report: the most damaging sea states of the
/// critical class.
const DAMAGE_INPUT_ROWS: usize = 25;

/// The columns of `table` named in `names` (missing names are skipped), rows kept.
pub(crate) fn select_columns(table: &Table, names: &[&str]) -> Table {
    let picks: Vec<usize> = names
        .iter()
        .filter_map(|n| table.columns.iter().position(|c| c == n))
        .collect();
    Table {
        columns: picks.iter().map(|&i| table.columns[i].clone()).collect(),
        rows: table
            .rows
            .iter()
            .map(|r| picks.iter().map(|&i| r[i].clone()).collect())
            .collect(),
    }
}

/// The rows of the damage-inputs table of `critical`, largest occurrence × damage rate first.
fn critical_rows(table: Table, critical: Option<&CriticalClass>) -> Table {
    let Some(c) = critical else {
        return Table {
            columns: table.columns,
            rows: Vec::new(),
        };
    };
    let col = |n: &str| table.columns.iter().position(|c| c == n);
    let (Some(hs), Some(li), Some(ap), Some(occ), Some(rate)) = (
        col("hot_spot_index"),
        col("layer_interface"),
        col("angular_position"),
        col("occurrence_fraction"),
        col("damage_rate_per_s"),
    ) else {
        return table;
    };
    let weight = |r: &Vec<serde_json::Value>| {
        r[occ].as_f64().unwrap_or(0.0) * r[rate].as_f64().unwrap_or(0.0)
    };
    let mut rows: Vec<Vec<serde_json::Value>> = table
        .rows
        .into_iter()
        .filter(|r| {
            r[hs].as_i64() == Some(c.hot_spot_index)
                && r[li].as_i64() == Some(c.layer_interface)
                && r[ap].as_str() == Some(c.angular_position.as_str())
        })
        .collect();
    rows.sort_by(|a, b| weight(b).total_cmp(&weight(a)));
    rows.truncate(DAMAGE_INPUT_ROWS);
    Table {
        columns: table.columns,
        rows,
    }
}

fn shares(terms: impl Iterator<Item = (i64, f64)>) -> BTreeMap<i64, f64> {
    let terms: BTreeMap<i64, f64> = terms.collect();
    let total: f64 = terms.values().sum();
    terms
        .into_iter()
        .map(|(k, v)| (k, if total > 0.0 { v / total } else { 0.0 }))
        .collect()
}

fn critical_class(rows: &[LifetimeClassDamage]) -> Option<CriticalClass> {
    rows.iter()
        .filter(|r| r.measure == "fretting_max")
        .max_by(|a, b| a.annual_damage.total_cmp(&b.annual_damage))
        .map(|r| CriticalClass {
            hot_spot_index: r.hot_spot_index,
            layer_interface: r.layer_interface,
            angular_position: r.angular_position,
            annual_damage: r.annual_damage,
        })
}

fn class_lives(
    lifetime: &[LifetimeClassDamage],
    per_sea_state: &[moorfret_store::SeaStateClassDamage],
) -> Vec<ClassLives> {
    type Key = (i64, i64, AngularPosition);
    let mut classes: BTreeMap<Key, ClassLives> = BTreeMap::new();
    for r in lifetime {
        let key = (r.hot_spot_index, r.layer_interface, r.angular_position);
        let entry = classes.entry(key).or_insert(ClassLives {
            hot_spot_index: key.0,
            layer_interface: key.1,
            angular_position: key.2,
            annual_damage: 0.0,
            rope_tn_annual_damage: 0.0,
            regime_cycles_per_hour: [0.0; 3],
        });
        match r.measure.as_str() {
            "fretting_max" => entry.annual_damage = r.annual_damage,
            "rope_tn_max" => entry.rope_tn_annual_damage = r.annual_damage,
            _ => {}
        }
    }
    for r in per_sea_state.iter().filter(|r| r.measure == "fretting_max") {
        let key = (r.hot_spot_index, r.layer_interface, r.angular_position);
        if let Some(entry) = classes.get_mut(&key) {
            let w = r.occurrence_fraction;
            entry.regime_cycles_per_hour[0] += w * r.stick_cycles_per_hour;
            entry.regime_cycles_per_hour[1] += w * r.partial_slip_cycles_per_hour;
            entry.regime_cycles_per_hour[2] += w * r.gross_slip_cycles_per_hour;
        }
    }
    let mut out: Vec<ClassLives> = classes.into_values().collect();
    out.sort_by(|a, b| b.annual_damage.total_cmp(&a.annual_damage));
    out
}

/// Reads the report data of campaign `name`.
pub async fn gather(
    store: &Store,
    name: &str,
    artifacts: Option<&ArtifactStore>,
) -> anyhow::Result<ReportData> {
    let campaign = query::campaign_id(store, name).await?;
    let sea_states = store.sea_state_status(campaign).await?;
    let lifetime_classes = store.lifetime_class_damage(campaign).await?;
    let critical = critical_class(&lifetime_classes);
    let class_lives = class_lives(
        &lifetime_classes,
        &store.sea_state_class_damage(campaign).await?,
    );
    let mut fretting_share = BTreeMap::new();
    let mut tn_share = None;
    if let Some(c) = &critical {
        let rows = store.sea_state_class_damage(campaign).await?;
        fretting_share = shares(
            rows.iter()
                .filter(|r| {
                    r.measure == "fretting_max"
                        && r.hot_spot_index == c.hot_spot_index
                        && r.layer_interface == c.layer_interface
                        && r.angular_position == c.angular_position
                })
                .map(|r| {
                    (
                        r.sea_state_index,
                        r.occurrence_fraction * r.damage_rate_per_s,
                    )
                }),
        );
    }
    let tn_rows = store.sea_state_damage(campaign).await?;
    let hot_spot = critical.as_ref().map_or(0, |c| c.hot_spot_index);
    let measure = tn_rows
        .iter()
        .filter(|r| r.hot_spot_index == hot_spot && r.measure.starts_with("tn"))
        .map(|r| r.measure.clone())
        .min();
    if let Some(measure) = measure {
        let share = shares(
            tn_rows
                .iter()
                .filter(|r| r.hot_spot_index == hot_spot && r.measure == measure)
                .map(|r| {
                    (
                        r.sea_state_index,
                        r.occurrence_fraction * r.damage_rate_per_s,
                    )
                }),
        );
        tn_share = Some((measure, share));
    }
    let histograms = slip_histograms(store.class_rows_of_campaign(campaign).await?)?;
    let damage_inputs = critical_rows(
        query::run(store, name, query::QueryKind::DamageInputs, "fretting_max").await?,
        critical.as_ref(),
    );
    let seeds = critical_rows(
        query::run(store, name, query::QueryKind::Seeds, "fretting_max").await?,
        critical.as_ref(),
    );
    let fidelity: BTreeMap<i64, String> = store
        .sea_state_class_damage(campaign)
        .await?
        .into_iter()
        .filter(|r| r.measure == "fretting_max")
        .map(|r| (r.sea_state_index, r.fidelity))
        .collect();
    let mut calibrations = Vec::new();
    let mut seeds_run_in: BTreeMap<i64, Vec<(bool, Option<f64>, f64)>> = BTreeMap::new();
    let index_of: BTreeMap<i64, i64> = sea_states
        .iter()
        .map(|s| (s.sea_state_id, s.sea_state_index))
        .collect();
    for job in store.jobs_of_campaign(campaign).await? {
        if job.state != JobState::Done {
            continue;
        }
        if job.kind == JobKind::Calibrate {
            calibrations.push(store.results_of(job.id).await?.result);
            continue;
        }
        let Some(result) = job.result.as_ref() else {
            continue;
        };
        let Some(r) = result.get("run_in") else {
            continue;
        };
        let index = job
            .sea_state
            .and_then(|id| index_of.get(&id.0).copied())
            .unwrap_or(-1);
        // per sea state, the run-in of every seed and fidelity
        let detected = r["detection"]["end_s"].as_f64();
        let excluded = r["excluded_s"].as_f64().unwrap_or(0.0);
        let fe = job.kind == JobKind::Strand;
        seeds_run_in
            .entry(index)
            .or_default()
            .push((fe, detected, excluded));
    }
    // the counted fidelity's seeds (FE where it ran); the latest run-in over them, none
    // detected if one seed never stabilised
    let run_in: BTreeMap<i64, (Option<f64>, f64)> = seeds_run_in
        .into_iter()
        .map(|(index, seeds)| {
            let any_fe = seeds.iter().any(|s| s.0);
            let counted: Vec<_> = seeds.into_iter().filter(|s| s.0 == any_fe).collect();
            let detected = counted
                .iter()
                .map(|s| s.1)
                .try_fold(0.0_f64, |m, d| d.map(|d| m.max(d)));
            let excluded = counted.iter().map(|s| s.2).fold(0.0, f64::max);
            (index, (detected, excluded))
        })
        .collect();
    let stored_spec = store
        .campaigns()
        .await?
        .into_iter()
        .find(|c| c.id == campaign)
        .map(|c| c.spec);
    let unfinished = unfinished(
        &sea_states,
        &store.jobs_of_campaign(campaign).await?,
        stored_spec.as_ref(),
    );
    let series = match artifacts {
        Some(a) => hot_spot_series(store, campaign, a, &fretting_share).await?,
        None => None,
    };
    Ok(ReportData {
        name: name.to_owned(),
        sea_states,
        critical,
        fretting_share,
        tn_share,
        histograms,
        series,
        lifetime: query::run(store, name, query::QueryKind::Lifetime, "").await?,
        class_lives,
        damage_inputs,
        seeds,
        fidelity,
        comparison: query::run(store, name, query::QueryKind::Fidelity, "").await?,
        calibrations,
        run_in,
        design: crate::design::check(store, campaign).await?,
        unfinished,
    })
}

/// Σ over sea states of occurrence × seed-mean cycles per hour, per hot spot and interface,
/// marginal over normal force and angular position.
fn slip_histograms(
    rows: Vec<(i64, f64, moorfret_store::ClassDamageInput)>,
) -> anyhow::Result<Vec<SlipHistogram>> {
    // Seeds per (sea state, hot spot, class), to take seed means.
    let mut seeds: BTreeMap<(i64, i64, i64, AngularPosition), f64> = BTreeMap::new();
    for (s, _, r) in &rows {
        *seeds
            .entry((*s, r.hot_spot_index, r.layer_interface, r.angular_position))
            .or_default() += 1.0;
    }
    let mut out: BTreeMap<(i64, i64), SlipHistogram> = BTreeMap::new();
    for (s, occurrence, r) in &rows {
        let h: CycleHistogram = serde_json::from_value(r.histogram.clone())
            .context("decoding a stored cycle histogram")?;
        let n = seeds[&(*s, r.hot_spot_index, r.layer_interface, r.angular_position)];
        let edges = h.slip_edges().edges().to_vec();
        let entry = out
            .entry((r.hot_spot_index, r.layer_interface))
            .or_insert_with(|| SlipHistogram {
                hot_spot_index: r.hot_spot_index,
                layer_interface: r.layer_interface,
                cycles_per_hour: vec![0.0; edges.len() - 1],
                edges_m: edges.clone(),
            });
        if entry.edges_m != edges {
            anyhow::bail!(
                "hot spot {}, interface {}: stored histograms have different slip bins",
                r.hot_spot_index,
                r.layer_interface
            );
        }
        for (i, bin) in entry.cycles_per_hour.iter_mut().enumerate() {
            let row: f64 = (0..h.force_edges().bins()).map(|j| h.count(i, j)).sum();
            *bin += occurrence * row / n;
        }
    }
    Ok(out.into_values().collect())
}

/// Reads the hot-spot series artifacts of the done global job of the sea state with the largest
/// fretting share (or of the first one holding it).
async fn hot_spot_series(
    store: &Store,
    campaign: moorfret_store::CampaignId,
    artifacts: &ArtifactStore,
    fretting_share: &BTreeMap<i64, f64>,
) -> anyhow::Result<Option<GlobalJobSeries>> {
    let states = store.sea_state_status(campaign).await?;
    let mut jobs: Vec<_> = store
        .jobs_of_campaign(campaign)
        .await?
        .into_iter()
        .filter(|j| j.kind == JobKind::Global && j.state == JobState::Done)
        .collect();
    let mut best: Option<(f64, GlobalJobSeries)> = None;
    jobs.sort_by_key(|j| j.id.0);
    for job in jobs {
        let index = states
            .iter()
            .find(|s| Some(s.sea_state_id) == job.sea_state.map(|id| id.0))
            .map_or(-1, |s| s.sea_state_index);
        let share = fretting_share.get(&index).copied().unwrap_or(0.0);
        if best.as_ref().is_some_and(|(s, _)| share <= *s) {
            continue;
        }
        let results = store.results_of(job.id).await?;
        // One artifact per hot spot (`hot_spot_<i>_series`) or one for all (`hotspots.csv`).
        let mut parts: Vec<(usize, &str, &ArtifactRole)> = results
            .artifacts
            .iter()
            .filter_map(|a| Some((a.role.hot_spot_series()?, a.sha256.as_str(), &a.role)))
            .collect();
        parts.sort();
        if parts.is_empty() {
            if let Some(a) = results
                .artifacts
                .iter()
                .find(|a| matches!(&a.role, ArtifactRole::Other(text) if text.contains("hotspots")))
            {
                parts.push((0, a.sha256.as_str(), &a.role));
            }
        }
        let mut series: Option<GlobalJobSeries> = None;
        for (_, sha, role) in parts {
            // A missing or damaged artifact is an error, not an absent plot.
            let bytes = artifacts.get(sha).with_context(|| {
                format!(
                    "artifact {role} ({sha}) of job {} in {}",
                    job.id,
                    artifacts.dir().display()
                )
            })?;
            let text = std::str::from_utf8(&bytes)
                .with_context(|| format!("artifact {role} ({sha}) of job {}", job.id))?;
            let part = HotSpotSeries::all_from_csv(text)
                .with_context(|| format!("artifact {role} ({sha}) of job {}", job.id))?;
            match &mut series {
                None => {
                    series = Some(GlobalJobSeries {
                        sea_state_index: index,
                        hot_spots: part,
                    })
                }
                Some(s) => s.hot_spots.extend(part),
            }
        }
        let Some(series) = series else {
            continue;
        };
        best = Some((share, series));
    }
    Ok(best.map(|(_, s)| s))
}
