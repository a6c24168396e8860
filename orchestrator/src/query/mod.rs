//! Queries users run on a campaign's results (`moorfret query …`), read from the store's views
//! (README, "Results and queries"):
//!
//! - `damage-inputs`: `sea_state_class_damage_inputs`, one row per sea state × hot spot ×
//!   contact class for one fretting measure (`fretting_max` by default, or `fretting_mean`);
//! - `sea-states`: the sea states with their job counts, the fraction of their spectral energy
//!   the wave cut-off keeps (`wave_energy_kept`, stored at planning) and whether that flags it
//!   (`wave_energy_flagged`: below 90 %), and per-hot-spot
//!   damage rates of every other measure (T-N curves) from `sea_state_damage_inputs`;
//! - `lifetime`: `lifetime_damage` (per hot spot and measure) and `lifetime_class_damage` (per
//!   hot spot, contact class and fretting measure), annual damage with the covered occurrence
//!   and its seed band (`moorfret_store::SeedBand`: standard error, D ± 2 SE, effective degrees
//!   of freedom, sea states with and without a seed spread), and the life with its band;
//! - `seeds`: the seed-to-seed spread per sea state: seeds, mean and standard deviation of the
//!   damage rate, and the sea state's annual damage with its standard error, for the contact
//!   classes of one fretting measure and for every per-hot-spot measure;
//! - `contacts`: the per-contact statistics rows of the done jobs;
//! - `fidelity`: `fidelity_comparison`, the reduced against the FE strand result per sea state,
//!   seed, hot spot and contact class where both ran, with their relative differences.
//!
//! Results come as a [`Table`] (named columns, JSON values) printed as an aligned text table,
//! CSV or JSON (an array of objects).

mod table;

use anyhow::Context;
use serde_json::Value;

use moorfret_campaign::fatigue::FRETTING_MEASURES;
use moorfret_store::{CampaignId, Store};

pub use table::{significant, OutputFormat, Table};

/// SQLite file used when no `--db` is given, in the working directory.
pub const DEFAULT_DB: &str = "moorfret.sqlite";

/// Which query.
#[derive(Debug, Clone, Copy, PartialEq, Eq, clap::ValueEnum)]
pub enum QueryKind {
    /// Per sea state, hot spot and contact class.
    DamageInputs,
    /// Sea states, job counts and per hot spot damage rates.
    SeaStates,
    /// Annual damage per hot spot (and contact class), with its seed band.
    Lifetime,
    /// Seed-to-seed spread per sea state, hot spot (and contact class) and measure.
    Seeds,
    /// Per-contact statistics.
    Contacts,
    /// Reduced against FE strand results where both ran (`auto` fidelity).
    Fidelity,
    /// Utilisation γ_F · D · T_design of every damage figure, with its verdict.
    Utilisation,
    /// Pass or fail per mooring line, with the governing figure, sector and sea state.
    Lines,
    /// Annual damage of each line's governing figure per wave direction (sector).
    Directions,
}

/// The id of campaign `name`, or an error naming it.
pub async fn campaign_id(store: &Store, name: &str) -> anyhow::Result<CampaignId> {
    store
        .campaign_by_name(name)
        .await?
        .with_context(|| format!("campaign `{name}` is not in the store"))
}

/// Runs query `kind` on campaign `name`; `measure` selects the fretting measure of
/// `damage-inputs`.
pub async fn run(
    store: &Store,
    name: &str,
    kind: QueryKind,
    measure: &str,
) -> anyhow::Result<Table> {
    // Refused for every kind, also those that list every measure: a mistyped measure is
    // never ignored ("" stands for the default, `fretting_max`).
    let measure = if measure.is_empty() {
        FRETTING_MEASURES[0]
    } else {
        measure
    };
    if !FRETTING_MEASURES.contains(&measure) {
        anyhow::bail!(
            "--measure `{measure}` is not a fretting measure (one of {})",
            FRETTING_MEASURES.join(", ")
        );
    }
    let campaign = campaign_id(store, name).await?;
    match kind {
        QueryKind::DamageInputs => {
            let rows: Vec<_> = store
                .sea_state_class_damage(campaign)
                .await?
                .into_iter()
                .filter(|r| r.measure == measure)
                .collect();
            Table::from_rows(
                &[
                    "sea_state_index",
                    "hs_m",
                    "tp_s",
                    "occurrence_fraction",
                    "hot_spot_index",
                    "layer_interface",
                    "angular_position",
                    "measure",
                    "seeds",
                    "contacts",
                    "effective_duration_s",
                    "damage_rate_per_s",
                    "damage_seed_mean",
                    "stick_cycles_per_hour",
                    "partial_slip_cycles_per_hour",
                    "gross_slip_cycles_per_hour",
                    "ruiz_f1_max",
                    "ruiz_f2_max",
                    "peak_pressure_max_pa",
                    "slip_amplitude_max_m",
                    "fidelity",
                ],
                &rows,
            )
        }
        QueryKind::SeaStates => sea_states(store, campaign).await,
        QueryKind::Lifetime => lifetime(store, campaign).await,
        QueryKind::Seeds => seeds(store, campaign, measure).await,
        QueryKind::Fidelity => fidelity(store, campaign).await,
        QueryKind::Utilisation | QueryKind::Lines | QueryKind::Directions => {
            design_table(store, campaign, kind).await
        }
        QueryKind::Contacts => Table::from_rows(
            &[
                "sea_state_index",
                "job_id",
                "hot_spot_index",
                "contact_index",
                "layer_interface",
                "angular_position_rad",
                "statistics",
            ],
            &store.contact_rows(campaign).await?,
        ),
    }
}

/// Whether a sea state whose wave cut-off keeps `kept` of its energy is flagged: below
/// [`moorfret_campaign::sea_limits::FLAG_ENERGY_KEPT`], as the planning judged it.
pub fn energy_flagged(kept: f64) -> bool {
    kept < moorfret_campaign::sea_limits::FLAG_ENERGY_KEPT
}

/// Sea states with job counts, and one column `<measure>_rate_per_s_hs<k>` per hot spot and
/// per-hot-spot measure.
async fn sea_states(store: &Store, campaign: CampaignId) -> anyhow::Result<Table> {
    let states = store.sea_state_status(campaign).await?;
    let damage = store.sea_state_damage(campaign).await?;
    let mut extra: Vec<(i64, String)> = damage
        .iter()
        .map(|d| (d.hot_spot_index, d.measure.clone()))
        .collect();
    extra.sort();
    extra.dedup();
    let mut table = Table::from_rows(
        &[
            "sea_state_index",
            "hs_m",
            "tp_s",
            "occurrence_fraction",
            "jobs_total",
            "jobs_done",
            "jobs_failed",
        ],
        &states,
    )?;
    // The fraction of each sea state's spectral energy the global stage's wave cut-off keeps:
    // stored with the sea state at planning, or (stores written before it was stored)
    // computed from the campaign's stored inputs; empty for a campaign stored without them.
    let inputs = if states.iter().any(|s| s.wave_energy_kept.is_none()) {
        store
            .campaigns()
            .await?
            .into_iter()
            .find(|c| c.id == campaign)
            .and_then(|c| {
                serde_json::from_value::<moorfret_campaign::CampaignInputs>(
                    c.spec["inputs"].clone(),
                )
                .ok()
            })
    } else {
        None
    };
    let kept: Vec<Option<f64>> = states
        .iter()
        .map(|s| {
            s.wave_energy_kept.or_else(|| {
                inputs
                    .as_ref()
                    .and_then(|i| moorfret_campaign::sea_limits::check(i, s.hs_m, s.tp_s).ok())
                    .map(|l| l.energy_kept)
            })
        })
        .collect();
    let flagged = kept
        .iter()
        .map(|k| k.map_or(Value::Null, |k| Value::from(energy_flagged(k))))
        .collect();
    table.push_column(
        "wave_energy_kept".into(),
        kept.iter()
            .map(|k| k.map_or(Value::Null, Value::from))
            .collect(),
    );
    table.push_column("wave_energy_flagged".into(), flagged);
    for (hot_spot, measure) in &extra {
        let column = format!("{measure}_rate_per_s_hs{hot_spot}");
        let values = states
            .iter()
            .map(|s| {
                damage
                    .iter()
                    .find(|d| {
                        d.sea_state_index == s.sea_state_index
                            && d.hot_spot_index == *hot_spot
                            && &d.measure == measure
                    })
                    .map_or(Value::Null, |d| Value::from(d.damage_rate_per_s))
            })
            .collect();
        table.push_column(column, values);
    }
    Ok(table)
}

/// Lifetime rows of both views in one table; class columns are empty for per-hot-spot
/// measures.
async fn lifetime(store: &Store, campaign: CampaignId) -> anyhow::Result<Table> {
    let columns = [
        "hot_spot_index",
        "layer_interface",
        "angular_position",
        "measure",
        "annual_damage",
        "annual_damage_se",
        "annual_damage_low",
        "annual_damage_high",
        "occurrence_covered",
        "sea_states",
        "sea_states_with_spread",
        "sea_states_without_spread",
        "effective_dof",
    ];
    let mut table = Table::from_rows(&columns, &store.lifetime_damage(campaign).await?)?;
    let classes = Table::from_rows(&columns, &store.lifetime_class_damage(campaign).await?)?;
    table.rows.extend(classes.rows);
    // life in years at the annual damage (Miner, failure at D = 1), and at the band's ends;
    // empty without damage
    let life = |column: usize| -> Vec<Value> {
        table
            .rows
            .iter()
            .map(|r| match r[column].as_f64() {
                Some(d) if d > 0.0 => Value::from(1.0 / d),
                _ => Value::Null,
            })
            .collect()
    };
    let (years, shortest, longest) = (life(4), life(7), life(6));
    table.push_column("life_years".into(), years);
    table.push_column("life_years_low".into(), shortest);
    table.push_column("life_years_high".into(), longest);
    Ok(table)
}

/// The seed-to-seed spread per sea state: the class rows of `measure`, then the per-hot-spot
/// measures; with the sea state's annual damage p · year · mean and its standard error
/// p · year · s / √n (empty for one seed).
async fn seeds(store: &Store, campaign: CampaignId, measure: &str) -> anyhow::Result<Table> {
    const YEAR_S: f64 = 31_557_600.0;
    let columns = [
        "sea_state_index",
        "hs_m",
        "tp_s",
        "occurrence_fraction",
        "hot_spot_index",
        "layer_interface",
        "angular_position",
        "measure",
        "seeds",
        "damage_rate_per_s",
        "damage_rate_sd",
        "fidelity",
    ];
    let classes: Vec<_> = store
        .sea_state_class_damage(campaign)
        .await?
        .into_iter()
        .filter(|r| r.measure == measure)
        .collect();
    let mut table = Table::from_rows(&columns, &classes)?;
    let per_hot_spot = Table::from_rows(&columns, &store.sea_state_damage(campaign).await?)?;
    table.rows.extend(per_hot_spot.rows);
    let column = |name: &str| columns.iter().position(|c| *c == name).unwrap_or(0);
    let (p, n, mean, sd) = (
        column("occurrence_fraction"),
        column("seeds"),
        column("damage_rate_per_s"),
        column("damage_rate_sd"),
    );
    let mut annual = Vec::with_capacity(table.rows.len());
    let mut se = Vec::with_capacity(table.rows.len());
    let mut cv = Vec::with_capacity(table.rows.len());
    for r in &table.rows {
        let weight = r[p].as_f64().unwrap_or(f64::NAN) * YEAR_S;
        let mean = r[mean].as_f64().unwrap_or(f64::NAN);
        annual.push(Value::from(weight * mean));
        match (r[sd].as_f64(), r[n].as_f64()) {
            (Some(sd), Some(n)) if n > 1.0 => {
                se.push(Value::from(weight * sd / n.sqrt()));
                cv.push(if mean > 0.0 {
                    Value::from(sd / mean)
                } else {
                    Value::Null
                });
            }
            _ => {
                se.push(Value::Null);
                cv.push(Value::Null);
            }
        }
    }
    table.push_column("damage_rate_cv".into(), cv);
    table.push_column("annual_damage".into(), annual);
    table.push_column("annual_damage_se".into(), se);
    Ok(table)
}

/// The `fidelity_comparison` rows of a campaign as [`fidelity_table`] lays them out.
async fn fidelity(store: &Store, campaign: CampaignId) -> anyhow::Result<Table> {
    fidelity_table(&store.fidelity_comparison(campaign).await?)
}

/// `fidelity_comparison` rows with the relative difference (reduced − FE) / FE of each
/// compared quantity (empty where the FE value is 0): the `query fidelity` table, which the
/// report reads too.
pub(crate) fn fidelity_table(rows: &[moorfret_store::FidelityComparison]) -> anyhow::Result<Table> {
    let mut table = Table::from_rows(
        &[
            "sea_state_index",
            "hs_m",
            "tp_s",
            "occurrence_fraction",
            "seed_index",
            "hot_spot_index",
            "layer_interface",
            "angular_position",
            "fe_damage_rate_max_per_s",
            "reduced_damage_rate_max_per_s",
            "fe_damage_rate_mean_per_s",
            "reduced_damage_rate_mean_per_s",
            "fe_slip_amplitude_max_m",
            "reduced_slip_amplitude_max_m",
            "fe_slip_cycles_per_hour",
            "reduced_slip_cycles_per_hour",
        ],
        rows,
    )?;
    let relative = |f: fn(&moorfret_store::FidelityComparison) -> (f64, f64)| -> Vec<Value> {
        rows.iter()
            .map(|r| {
                let (fe, reduced) = f(r);
                if fe != 0.0 && fe.is_finite() && reduced.is_finite() {
                    Value::from((reduced - fe) / fe)
                } else {
                    Value::Null
                }
            })
            .collect()
    };
    table.push_column(
        "damage_max_rel_diff".into(),
        relative(|r| (r.fe_damage_rate_max_per_s, r.reduced_damage_rate_max_per_s)),
    );
    table.push_column(
        "damage_mean_rel_diff".into(),
        relative(|r| {
            (
                r.fe_damage_rate_mean_per_s,
                r.reduced_damage_rate_mean_per_s,
            )
        }),
    );
    table.push_column(
        "slip_amplitude_rel_diff".into(),
        relative(|r| (r.fe_slip_amplitude_max_m, r.reduced_slip_amplitude_max_m)),
    );
    table.push_column(
        "slip_cycles_rel_diff".into(),
        relative(|r| (r.fe_slip_cycles_per_hour, r.reduced_slip_cycles_per_hour)),
    );
    Ok(table)
}

/// The design check's tables: every figure, the verdict per line, the damage per direction.
async fn design_table(
    store: &Store,
    campaign: CampaignId,
    kind: QueryKind,
) -> anyhow::Result<Table> {
    let check = crate::design::check(store, campaign)
        .await?
        .context("the campaign is stored without its inputs: no design check")?;
    match kind {
        QueryKind::Utilisation => Table::from_rows(
            &[
                "line",
                "hot_spot_index",
                "arc_length_m",
                "measure",
                "check",
                "class",
                "annual_damage",
                "life_years",
                "utilisation",
                "year_covered",
                "verdict",
            ],
            &check.figures,
        ),
        QueryKind::Lines => lines_table(&check),
        _ => Table::from_rows(
            &[
                "line",
                "sector",
                "heading_deg",
                "year_share",
                "annual_damage",
            ],
            &check.sectors,
        ),
    }
}

/// The verdict per line with the governing figure, sector and sea state.
pub fn lines_table(check: &crate::design::DesignCheck) -> anyhow::Result<Table> {
    let rows: Vec<Value> = check
        .lines
        .iter()
        .map(|l| {
            let f = &check.figures[l.governing];
            let state = l.governing_sea_state;
            serde_json::json!({
                "line": l.line,
                "verdict": l.verdict.as_str(),
                "utilisation": l.utilisation,
                "hot_spot_index": f.hot_spot_index,
                "measure": f.measure,
                "class": f.class,
                "life_years": f.life_years,
                "sector": l.governing_sector,
                "sea_state_index": state.map(|s| s.0),
                "hs_m": state.map(|s| s.1),
                "tp_s": state.map(|s| s.2),
                "heading_deg": state.map(|s| s.3),
                "sea_state_share": l.governing_sea_state_share,
            })
        })
        .collect();
    Table::from_rows(
        &[
            "line",
            "verdict",
            "utilisation",
            "hot_spot_index",
            "measure",
            "class",
            "life_years",
            "sector",
            "sea_state_index",
            "hs_m",
            "tp_s",
            "heading_deg",
            "sea_state_share",
        ],
        &rows,
    )
}
