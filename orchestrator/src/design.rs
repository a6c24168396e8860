//! The design check of a campaign: the utilisation of every damage figure, the verdict per
//! mooring line, what governs it, and the damage by wave direction.
//!
//! The figures are the lifetime views' annual damages ([`moorfret_store`]): per hot spot and
//! contact class for the class measures, per hot spot for the T-N curves of the tension. Their
//! utilisation is u = γ_F · D_year · T_design ([`moorfret_campaign::design`]).
//!
//! Two kinds of measure enter the verdict of a line (the `design` checks):
//!
//! - `fretting_max`, the campaign's fretting law on the most damaged contact of a class (by
//!   default the contact-stress law: crack initiation at a wire crossing,
//!   docs/fretting-fatigue.md);
//! - every T-N curve of the hot-spot tension (`tn_*`): the rope's own design curves.
//!
//! The other class measures (`fretting_mean`, `rope_tn_max`, `rope_tn_mean`) are listed for
//! comparison. A line's verdict is the worst over its hot spots and design checks; its
//! governing figure is the design check of the largest utilisation, with the sector and the sea
//! state that contribute most to it (occurrence × annual rate).

use std::collections::BTreeMap;

use serde::Serialize;

use moorfret_campaign::design::{utilisation, Verdict, DEFAULT_DESIGN_FATIGUE_FACTOR};
use moorfret_campaign::CampaignInputs;
use moorfret_store::{CampaignId, Store};

/// Seconds per year (Julian), as the lifetime views count them.
const YEAR_S: f64 = 31_557_600.0;

/// Class measures listed for comparison only.
const COMPARISON_MEASURES: [&str; 3] = ["fretting_mean", "rope_tn_max", "rope_tn_mean"];

/// The whole design check of a campaign.
#[derive(Debug, Clone, Serialize)]
pub struct DesignCheck {
    /// Design life (years).
    pub design_life_years: f64,
    /// Design fatigue factor γ_F.
    pub design_fatigue_factor: f64,
    /// Share of the year in the campaign's climate.
    pub year_planned: f64,
    /// Every figure with its utilisation, largest first within each hot spot.
    pub figures: Vec<Figure>,
    /// Per line, its verdict and what governs it, in line order.
    pub lines: Vec<LineCheck>,
    /// Annual damage of each line's governing figure per directional sector.
    pub sectors: Vec<SectorDamage>,
    /// The hot spots found by screening (`"hot_spots": "auto"`), with their proxy.
    pub screening: Vec<moorfret_campaign::screening::ScreenedHotSpot>,
    /// Per hot spot, the mild sea states it skipped (none without `strand.skip_mild_share`).
    pub mild_seas: Vec<MildSkip>,
}

/// One damage figure and its utilisation.
#[derive(Debug, Clone, Serialize)]
pub struct Figure {
    /// Mooring line.
    pub line: u32,
    /// Hot spot index in the campaign.
    pub hot_spot_index: i64,
    /// Its arc length from the fairlead (m).
    pub arc_length_m: f64,
    /// Damage measure.
    pub measure: String,
    /// `design` (enters the verdict) or `comparison`.
    pub check: &'static str,
    /// Contact class (layer interface / angular position); empty for a T-N figure.
    pub class: String,
    /// Annual damage (1/year).
    pub annual_damage: f64,
    /// Life at that damage (years); `None` without damage.
    pub life_years: Option<f64>,
    /// γ_F · D_year · T_design.
    pub utilisation: f64,
    /// Share of the year its sea states cover.
    pub year_covered: f64,
    /// Pass, fail or incomplete.
    pub verdict: Verdict,
}

/// The mild sea states a hot spot skipped (`strand.skip_mild_share`).
#[derive(Debug, Clone, Serialize)]
pub struct MildSkip {
    /// Hot spot index in the campaign.
    pub hot_spot_index: i64,
    /// Skipped sea states.
    pub sea_states: usize,
    /// Their share of the year.
    pub year_share: f64,
    /// q: their share of the hot spot's tension-bending proxy.
    pub proxy_share: f64,
    /// The factor 1 / (1 − q) on the strand figures of the hot spot.
    pub damage_factor: f64,
}

/// The verdict of one mooring line.
#[derive(Debug, Clone, Serialize)]
pub struct LineCheck {
    /// Mooring line.
    pub line: u32,
    /// Worst verdict over its hot spots and design checks.
    pub verdict: Verdict,
    /// Largest utilisation of a design check.
    pub utilisation: f64,
    /// The governing figure (index in [`DesignCheck::figures`]).
    pub governing: usize,
    /// Sector contributing most to the governing figure (`None` for one table).
    pub governing_sector: Option<String>,
    /// Sea state contributing most to it: index, Hs (m), Tp (s), heading (deg).
    pub governing_sea_state: Option<(i64, f64, f64, f64)>,
    /// That sea state's share of the governing figure's annual damage.
    pub governing_sea_state_share: f64,
}

/// Annual damage of a line's governing figure from one directional sector.
#[derive(Debug, Clone, Serialize)]
pub struct SectorDamage {
    /// Mooring line.
    pub line: u32,
    /// Sector label (`all` for a climate of one table).
    pub sector: String,
    /// Heading of its sea states (deg).
    pub heading_deg: f64,
    /// Its share of the year covered by the figure.
    pub year_share: f64,
    /// Its annual damage.
    pub annual_damage: f64,
}

/// One sea state's contribution to a figure: (sea state index, occurrence × year × rate).
type Contribution = (i64, f64);

/// Reads the campaign's lifetime and per-sea-state figures and makes its design check; `None`
/// for a campaign stored without its inputs (no hot spots, design life or factor to judge by).
pub async fn check(store: &Store, campaign: CampaignId) -> anyhow::Result<Option<DesignCheck>> {
    let record = store
        .campaigns()
        .await?
        .into_iter()
        .find(|c| c.id == campaign)
        .ok_or_else(|| anyhow::anyhow!("campaign id {campaign} is not in the store"))?;
    if record
        .spec
        .get("inputs")
        .is_none_or(serde_json::Value::is_null)
    {
        return Ok(None);
    }
    let inputs: CampaignInputs = moorfret_campaign::stored_inputs(&record.spec)?;
    let spec = &inputs.spec;
    let life = spec.design_life_years;
    let factor = spec
        .design_fatigue_factor
        .unwrap_or(DEFAULT_DESIGN_FATIGUE_FACTOR);
    let states = store.sea_state_status(campaign).await?;
    let year_planned: f64 = states.iter().map(|s| s.occurrence_fraction).sum();

    // contributions of each sea state to each figure, keyed (hot spot, measure, class)
    let mut per_state: BTreeMap<(i64, String, String), Vec<Contribution>> = BTreeMap::new();
    for r in store.sea_state_class_damage(campaign).await? {
        let class = class_name(r.layer_interface, &r.angular_position);
        per_state
            .entry((r.hot_spot_index, r.measure.clone(), class))
            .or_default()
            .push((
                r.sea_state_index,
                r.occurrence_fraction * YEAR_S * r.damage_rate_per_s,
            ));
    }
    for r in store.sea_state_damage(campaign).await? {
        per_state
            .entry((r.hot_spot_index, r.measure.clone(), String::new()))
            .or_default()
            .push((
                r.sea_state_index,
                r.occurrence_fraction * YEAR_S * r.damage_rate_per_s,
            ));
    }

    let mild_seas = mild_skips(store, campaign).await?;
    let mild_of = |h: i64| mild_seas.iter().find(|m| m.hot_spot_index == h);
    let hot_spot = |i: i64| spec.hot_spots.get(i as usize);
    let mut figures = Vec::new();
    let mut push = |hot_spot_index: i64,
                    measure: &str,
                    class: String,
                    annual_damage: f64,
                    year_covered: f64| {
        let Some(h) = hot_spot(hot_spot_index) else {
            return;
        };
        let class_measure = !class.is_empty();
        let check = if class_measure && COMPARISON_MEASURES.contains(&measure) {
            "comparison"
        } else if class_measure && measure != "fretting_max" {
            // a class measure this version does not know: shown, never judged on
            "comparison"
        } else {
            "design"
        };
        // the strand figures of a hot spot that skipped mild sea states carry their bound
        // (`annual_damage` times 1/(1 − q), `moorfret_campaign::mild_seas`) and cover their year
        let (annual_damage, year_skipped) = match mild_of(hot_spot_index) {
            Some(m) if class_measure => (annual_damage * m.damage_factor, m.year_share),
            _ => (annual_damage, 0.0),
        };
        let year_covered = year_covered + year_skipped;
        let u = utilisation(annual_damage, life, factor);
        figures.push(Figure {
            line: h.line,
            hot_spot_index,
            arc_length_m: h.arc_length_m,
            measure: measure.to_owned(),
            check,
            class,
            annual_damage,
            life_years: (annual_damage > 0.0).then(|| 1.0 / annual_damage),
            utilisation: u,
            year_covered,
            verdict: Verdict::of(u, year_covered),
        });
    };
    for r in store.lifetime_class_damage(campaign).await? {
        let class = class_name(r.layer_interface, &r.angular_position);
        push(
            r.hot_spot_index,
            &r.measure,
            class,
            r.annual_damage,
            r.occurrence_covered,
        );
    }
    for r in store.lifetime_damage(campaign).await? {
        push(
            r.hot_spot_index,
            &r.measure,
            String::new(),
            r.annual_damage,
            r.occurrence_covered,
        );
    }
    figures.sort_by(|a, b| {
        (a.line, a.hot_spot_index)
            .cmp(&(b.line, b.hot_spot_index))
            .then(b.utilisation.total_cmp(&a.utilisation))
    });

    let state_of = |index: i64| states.iter().find(|s| s.sea_state_index == index);
    let mut lines = Vec::new();
    let mut sectors = Vec::new();
    let mut line_ids: Vec<u32> = spec.hot_spots.iter().map(|h| h.line).collect();
    line_ids.sort_unstable();
    line_ids.dedup();
    for line in line_ids {
        let design: Vec<(usize, &Figure)> = figures
            .iter()
            .enumerate()
            .filter(|(_, f)| f.line == line && f.check == "design")
            .collect();
        let Some(&(governing, top)) = design
            .iter()
            .max_by(|a, b| a.1.utilisation.total_cmp(&b.1.utilisation))
        else {
            continue;
        };
        let verdict = design
            .iter()
            .fold(Verdict::Pass, |v, (_, f)| v.worse(f.verdict));
        let key = (top.hot_spot_index, top.measure.clone(), top.class.clone());
        let contributions = per_state.get(&key).map(Vec::as_slice).unwrap_or(&[]);
        let total: f64 = contributions.iter().map(|c| c.1).sum();
        let largest = contributions.iter().max_by(|a, b| a.1.total_cmp(&b.1));
        let governing_sea_state = largest.and_then(|&(index, _)| {
            state_of(index).map(|s| (index, s.hs_m, s.tp_s, s.heading_deg.unwrap_or(0.0)))
        });
        // damage per sector of the governing figure
        let mut by_sector: BTreeMap<String, (f64, f64, f64)> = BTreeMap::new();
        for &(index, d) in contributions {
            if let Some(s) = state_of(index) {
                let name = s.sector.clone().unwrap_or_else(|| "all".to_owned());
                let e = by_sector
                    .entry(name)
                    .or_insert((s.heading_deg.unwrap_or(0.0), 0.0, 0.0));
                e.1 += s.occurrence_fraction;
                e.2 += d;
            }
        }
        let governing_sector = by_sector
            .iter()
            .filter(|(name, _)| name.as_str() != "all")
            .max_by(|a, b| a.1 .2.total_cmp(&b.1 .2))
            .map(|(name, _)| name.clone());
        for (sector, (heading_deg, year_share, annual_damage)) in by_sector {
            sectors.push(SectorDamage {
                line,
                sector,
                heading_deg,
                year_share,
                annual_damage,
            });
        }
        lines.push(LineCheck {
            line,
            verdict,
            utilisation: top.utilisation,
            governing,
            governing_sector,
            governing_sea_state,
            governing_sea_state_share: match largest {
                Some(&(_, d)) if total > 0.0 => d / total,
                _ => 0.0,
            },
        });
    }
    Ok(Some(DesignCheck {
        design_life_years: life,
        design_fatigue_factor: factor,
        year_planned,
        figures,
        lines,
        sectors,
        screening: inputs.hot_spot_screening.clone(),
        mild_seas,
    }))
}

/// Per hot spot, the mild sea states its reduced jobs skipped, from their results
/// (`"skipped": "mild"`, written by the worker's gate).
async fn mild_skips(store: &Store, campaign: CampaignId) -> anyhow::Result<Vec<MildSkip>> {
    let mut per_hot_spot: BTreeMap<i64, MildSkip> = BTreeMap::new();
    for job in store.jobs_of_campaign(campaign).await? {
        let Some(result) = &job.result else {
            continue;
        };
        if result["skipped"] != "mild" {
            continue;
        }
        let (Some(h), Some(q), Some(year), Some(n)) = (
            result["hot_spot_index"].as_i64(),
            result["mild_seas"]["proxy_share"].as_f64(),
            result["mild_seas"]["occurrence_fraction"].as_f64(),
            result["mild_seas"]["skipped"].as_u64(),
        ) else {
            continue;
        };
        per_hot_spot.entry(h).or_insert(MildSkip {
            hot_spot_index: h,
            sea_states: n as usize,
            year_share: year,
            proxy_share: q,
            damage_factor: moorfret_campaign::mild_seas::damage_factor(q),
        });
    }
    Ok(per_hot_spot.into_values().collect())
}

/// `interface <i> / <position>` of a contact class.
fn class_name(layer_interface: i64, position: &impl Serialize) -> String {
    let position = serde_json::to_value(position)
        .ok()
        .and_then(|v| v.as_str().map(str::to_owned))
        .unwrap_or_default();
    format!("interface {layer_interface} / {position}")
}
