//! Per-class damage rows and the result views.

use super::Db;
use super::{json_text, parse_json, Queue, Result, Tx};
use crate::error::StoreError;
use crate::results::{
    parse_position, standard_deviation, ClassDamageInput, ContactRow, FidelityComparison,
    LifetimeClassDamage, SeaStateClassDamage, SeaStateDamage, SeaStateStatus, SeedBand,
};
use crate::types::{CampaignId, JobId, JobKind};
use sqlx::Row;

pub(super) const CLASS_COLUMNS: &str =
    "hot_spot_index, layer_interface, angular_position, seed_index, \
     effective_duration_s, contacts, fretting_damage_rate_max_per_s, \
     fretting_damage_rate_mean_per_s, stick_cycles_per_hour, partial_slip_cycles_per_hour, \
     gross_slip_cycles_per_hour, ruiz_f1_max, ruiz_f2_max, peak_pressure_max_pa, \
     slip_amplitude_max_m, histogram_json, rope_tn_damage_rate_max_per_s, \
     rope_tn_damage_rate_mean_per_s, wear_power_max_w";

/// Inserts the class rows of a completing job inside its transaction.
pub(super) async fn insert_class_damage_inputs(
    tx: &mut Tx,
    job: JobId,
    rows: &[ClassDamageInput],
) -> Result<()> {
    const OP: &str = "complete job";
    let sql = format!(
        "INSERT INTO class_damage_inputs (job_id, {CLASS_COLUMNS}) VALUES \
         ($1, $2, $3, $4, $5, $6, $7, $8, $9, $10, $11, $12, $13, $14, $15, $16, $17, $18, $19, $20)"
    );
    for r in rows {
        sqlx::query(&sql)
            .bind(job.0)
            .bind(r.hot_spot_index)
            .bind(r.layer_interface)
            .bind(r.angular_position.as_str())
            .bind(r.seed_index)
            .bind(r.effective_duration_s)
            .bind(r.contacts)
            .bind(r.fretting_damage_rate_max_per_s)
            .bind(r.fretting_damage_rate_mean_per_s)
            .bind(r.stick_cycles_per_hour)
            .bind(r.partial_slip_cycles_per_hour)
            .bind(r.gross_slip_cycles_per_hour)
            .bind(r.ruiz_f1_max)
            .bind(r.ruiz_f2_max)
            .bind(r.peak_pressure_max_pa)
            .bind(r.slip_amplitude_max_m)
            .bind(json_text(
                "class_damage_inputs.histogram_json",
                &r.histogram,
            )?)
            .bind(r.rope_tn_damage_rate_max_per_s)
            .bind(r.rope_tn_damage_rate_mean_per_s)
            .bind(r.wear_power_max_w)
            .execute(&mut **tx)
            .await
            .map_err(StoreError::db(OP))?;
    }
    Ok(())
}

/// Copies the class rows of `source` to `job` (completion from the cache).
pub(super) const COPY_CLASS_DAMAGE_INPUTS: &str =
    "INSERT INTO class_damage_inputs (job_id, hot_spot_index, \
     layer_interface, angular_position, seed_index, effective_duration_s, contacts, \
     fretting_damage_rate_max_per_s, fretting_damage_rate_mean_per_s, stick_cycles_per_hour, \
     partial_slip_cycles_per_hour, gross_slip_cycles_per_hour, ruiz_f1_max, ruiz_f2_max, \
     peak_pressure_max_pa, slip_amplitude_max_m, histogram_json, \
     rope_tn_damage_rate_max_per_s, rope_tn_damage_rate_mean_per_s, wear_power_max_w) \
     SELECT $1, hot_spot_index, layer_interface, angular_position, seed_index, \
     effective_duration_s, contacts, fretting_damage_rate_max_per_s, \
     fretting_damage_rate_mean_per_s, stick_cycles_per_hour, partial_slip_cycles_per_hour, \
     gross_slip_cycles_per_hour, ruiz_f1_max, ruiz_f2_max, peak_pressure_max_pa, \
     slip_amplitude_max_m, histogram_json, rope_tn_damage_rate_max_per_s, \
     rope_tn_damage_rate_mean_per_s, wear_power_max_w FROM class_damage_inputs WHERE job_id = $2";

pub(super) fn get<'r, T>(
    row: &'r <Db as sqlx::Database>::Row,
    column: &str,
    op: &'static str,
) -> Result<T>
where
    T: sqlx::Decode<'r, Db> + sqlx::Type<Db>,
{
    row.try_get(column).map_err(StoreError::db(op))
}

pub(super) fn class_from_row(
    row: &<Db as sqlx::Database>::Row,
    op: &'static str,
) -> Result<ClassDamageInput> {
    let position: String = get(row, "angular_position", op)?;
    let histogram: String = get(row, "histogram_json", op)?;
    Ok(ClassDamageInput {
        hot_spot_index: get(row, "hot_spot_index", op)?,
        layer_interface: get(row, "layer_interface", op)?,
        angular_position: parse_position(&position)?,
        seed_index: get(row, "seed_index", op)?,
        effective_duration_s: get(row, "effective_duration_s", op)?,
        contacts: get(row, "contacts", op)?,
        fretting_damage_rate_max_per_s: get(row, "fretting_damage_rate_max_per_s", op)?,
        fretting_damage_rate_mean_per_s: get(row, "fretting_damage_rate_mean_per_s", op)?,
        stick_cycles_per_hour: get(row, "stick_cycles_per_hour", op)?,
        partial_slip_cycles_per_hour: get(row, "partial_slip_cycles_per_hour", op)?,
        gross_slip_cycles_per_hour: get(row, "gross_slip_cycles_per_hour", op)?,
        ruiz_f1_max: get(row, "ruiz_f1_max", op)?,
        ruiz_f2_max: get(row, "ruiz_f2_max", op)?,
        peak_pressure_max_pa: get(row, "peak_pressure_max_pa", op)?,
        slip_amplitude_max_m: get(row, "slip_amplitude_max_m", op)?,
        histogram: parse_json("class_damage_inputs.histogram_json", &histogram)?,
        rope_tn_damage_rate_max_per_s: get(row, "rope_tn_damage_rate_max_per_s", op)?,
        rope_tn_damage_rate_mean_per_s: get(row, "rope_tn_damage_rate_mean_per_s", op)?,
        wear_power_max_w: get(row, "wear_power_max_w", op)?,
    })
}

/// The seed band of a lifetime view row (migration 0004).
pub(super) fn band_of(
    row: &<Db as sqlx::Database>::Row,
    annual_damage: f64,
    op: &'static str,
) -> Result<SeedBand> {
    Ok(SeedBand::new(
        annual_damage,
        get(row, "annual_damage_variance", op)?,
        get(row, "annual_damage_variance_dof_sum", op)?,
        get(row, "sea_states_with_spread", op)?,
        get(row, "sea_states_without_spread", op)?,
    ))
}

impl Queue {
    pub(crate) async fn class_damage_inputs_of(&self, job: JobId) -> Result<Vec<ClassDamageInput>> {
        const OP: &str = "read class damage inputs";
        let sql = format!(
            "SELECT {CLASS_COLUMNS} FROM class_damage_inputs WHERE job_id = $1 \
             ORDER BY hot_spot_index, layer_interface, angular_position"
        );
        let rows = sqlx::query(&sql)
            .bind(job.0)
            .fetch_all(&self.pool)
            .await
            .map_err(StoreError::db(OP))?;
        rows.iter().map(|row| class_from_row(row, OP)).collect()
    }

    pub(crate) async fn sea_state_class_damage(
        &self,
        campaign: CampaignId,
    ) -> Result<Vec<SeaStateClassDamage>> {
        const OP: &str = "read sea_state_class_damage_inputs";
        let rows = sqlx::query(
            "SELECT * FROM sea_state_class_damage_inputs WHERE campaign_id = $1 \
             ORDER BY sea_state_index, hot_spot_index, layer_interface, angular_position, measure",
        )
        .bind(campaign.0)
        .fetch_all(&self.pool)
        .await
        .map_err(StoreError::db(OP))?;
        rows.iter()
            .map(|row| {
                let position: String = get(row, "angular_position", OP)?;
                Ok(SeaStateClassDamage {
                    sea_state_index: get(row, "sea_state_index", OP)?,
                    hs_m: get(row, "hs_m", OP)?,
                    tp_s: get(row, "tp_s", OP)?,
                    occurrence_fraction: get(row, "occurrence_fraction", OP)?,
                    hot_spot_index: get(row, "hot_spot_index", OP)?,
                    layer_interface: get(row, "layer_interface", OP)?,
                    angular_position: parse_position(&position)?,
                    measure: get(row, "measure", OP)?,
                    seeds: get(row, "seeds", OP)?,
                    contacts: get(row, "contacts", OP)?,
                    effective_duration_s: get(row, "effective_duration_s", OP)?,
                    damage_rate_per_s: get(row, "damage_rate_per_s", OP)?,
                    damage_seed_mean: get(row, "damage_seed_mean", OP)?,
                    damage_rate_sd: standard_deviation(get(row, "damage_rate_variance", OP)?),
                    stick_cycles_per_hour: get(row, "stick_cycles_per_hour", OP)?,
                    partial_slip_cycles_per_hour: get(row, "partial_slip_cycles_per_hour", OP)?,
                    gross_slip_cycles_per_hour: get(row, "gross_slip_cycles_per_hour", OP)?,
                    ruiz_f1_max: get(row, "ruiz_f1_max", OP)?,
                    ruiz_f2_max: get(row, "ruiz_f2_max", OP)?,
                    peak_pressure_max_pa: get(row, "peak_pressure_max_pa", OP)?,
                    slip_amplitude_max_m: get(row, "slip_amplitude_max_m", OP)?,
                    fidelity: get(row, "fidelity", OP)?,
                })
            })
            .collect()
    }

    pub(crate) async fn lifetime_class_damage(
        &self,
        campaign: CampaignId,
    ) -> Result<Vec<LifetimeClassDamage>> {
        const OP: &str = "read lifetime_class_damage";
        let rows = sqlx::query(
            "SELECT * FROM lifetime_class_damage WHERE campaign_id = $1 \
             ORDER BY hot_spot_index, layer_interface, angular_position, measure",
        )
        .bind(campaign.0)
        .fetch_all(&self.pool)
        .await
        .map_err(StoreError::db(OP))?;
        rows.iter()
            .map(|row| {
                let position: String = get(row, "angular_position", OP)?;
                let annual_damage: f64 = get(row, "annual_damage", OP)?;
                Ok(LifetimeClassDamage {
                    hot_spot_index: get(row, "hot_spot_index", OP)?,
                    layer_interface: get(row, "layer_interface", OP)?,
                    angular_position: parse_position(&position)?,
                    measure: get(row, "measure", OP)?,
                    annual_damage,
                    band: band_of(row, annual_damage, OP)?,
                    occurrence_covered: get(row, "occurrence_covered", OP)?,
                    sea_states: get(row, "sea_states", OP)?,
                })
            })
            .collect()
    }

    pub(crate) async fn sea_state_damage(
        &self,
        campaign: CampaignId,
    ) -> Result<Vec<SeaStateDamage>> {
        const OP: &str = "read sea_state_damage_inputs";
        let rows = sqlx::query(
            "SELECT * FROM sea_state_damage_inputs WHERE campaign_id = $1 \
             ORDER BY sea_state_index, hot_spot_index, measure",
        )
        .bind(campaign.0)
        .fetch_all(&self.pool)
        .await
        .map_err(StoreError::db(OP))?;
        rows.iter()
            .map(|row| {
                Ok(SeaStateDamage {
                    sea_state_index: get(row, "sea_state_index", OP)?,
                    hs_m: get(row, "hs_m", OP)?,
                    tp_s: get(row, "tp_s", OP)?,
                    occurrence_fraction: get(row, "occurrence_fraction", OP)?,
                    hot_spot_index: get(row, "hot_spot_index", OP)?,
                    measure: get(row, "measure", OP)?,
                    seeds: get(row, "seeds", OP)?,
                    damage_seed_mean: get(row, "damage_seed_mean", OP)?,
                    effective_duration_s: get(row, "effective_duration_s", OP)?,
                    damage_rate_per_s: get(row, "damage_rate_per_s", OP)?,
                    damage_rate_sd: standard_deviation(get(row, "damage_rate_variance", OP)?),
                    fidelity: get(row, "fidelity", OP)?,
                })
            })
            .collect()
    }

    pub(crate) async fn sea_state_status(
        &self,
        campaign: CampaignId,
    ) -> Result<Vec<SeaStateStatus>> {
        const OP: &str = "read sea states";
        let rows = sqlx::query(
            "SELECT s.id AS sea_state_id, s.sea_state_index, s.hs_m, s.tp_s, s.occurrence_fraction, \
             s.heading_deg, s.sector, s.wave_energy_kept, \
             (SELECT COUNT(*) FROM jobs j WHERE j.sea_state_id = s.id) AS jobs_total, \
             (SELECT COUNT(*) FROM jobs j WHERE j.sea_state_id = s.id AND j.state = 'done') \
                 AS jobs_done, \
             (SELECT COUNT(*) FROM jobs j WHERE j.sea_state_id = s.id AND j.state = 'failed') \
                 AS jobs_failed \
             FROM sea_states s WHERE s.campaign_id = $1 ORDER BY s.sea_state_index",
        )
        .bind(campaign.0)
        .fetch_all(&self.pool)
        .await
        .map_err(StoreError::db(OP))?;
        rows.iter()
            .map(|row| {
                Ok(SeaStateStatus {
                    sea_state_id: get(row, "sea_state_id", OP)?,
                    sea_state_index: get(row, "sea_state_index", OP)?,
                    hs_m: get(row, "hs_m", OP)?,
                    tp_s: get(row, "tp_s", OP)?,
                    occurrence_fraction: get(row, "occurrence_fraction", OP)?,
                    jobs_total: get(row, "jobs_total", OP)?,
                    jobs_done: get(row, "jobs_done", OP)?,
                    jobs_failed: get(row, "jobs_failed", OP)?,
                    heading_deg: get(row, "heading_deg", OP)?,
                    sector: get(row, "sector", OP)?,
                    wave_energy_kept: get(row, "wave_energy_kept", OP)?,
                })
            })
            .collect()
    }

    pub(crate) async fn contact_rows(&self, campaign: CampaignId) -> Result<Vec<ContactRow>> {
        const OP: &str = "read contact statistics";
        let rows = sqlx::query(
            "SELECT s.sea_state_index, c.job_id, c.hot_spot_index, c.contact_index, \
             c.layer_interface, c.angular_position_rad, c.statistics_json \
             FROM contact_statistics c \
             JOIN jobs j ON j.id = c.job_id AND j.state = 'done' AND j.kind <> 'test' \
             JOIN sea_states s ON s.id = j.sea_state_id \
             WHERE j.campaign_id = $1 \
             ORDER BY s.sea_state_index, c.job_id, c.hot_spot_index, c.contact_index",
        )
        .bind(campaign.0)
        .fetch_all(&self.pool)
        .await
        .map_err(StoreError::db(OP))?;
        rows.iter()
            .map(|row| {
                let statistics: String = get(row, "statistics_json", OP)?;
                Ok(ContactRow {
                    sea_state_index: get(row, "sea_state_index", OP)?,
                    job_id: get(row, "job_id", OP)?,
                    hot_spot_index: get(row, "hot_spot_index", OP)?,
                    contact_index: get(row, "contact_index", OP)?,
                    layer_interface: get(row, "layer_interface", OP)?,
                    angular_position_rad: get(row, "angular_position_rad", OP)?,
                    statistics: parse_json("contact_statistics.statistics_json", &statistics)?,
                })
            })
            .collect()
    }

    pub(crate) async fn class_rows_of_campaign(
        &self,
        campaign: CampaignId,
    ) -> Result<Vec<(i64, f64, ClassDamageInput)>> {
        self.class_rows(
            "counted_class_damage_inputs c JOIN jobs j ON j.id = c.job_id",
            campaign,
            None,
        )
        .await
    }

    pub(crate) async fn class_rows_of_kind(
        &self,
        campaign: CampaignId,
        kind: JobKind,
    ) -> Result<Vec<(i64, f64, ClassDamageInput)>> {
        self.class_rows(
            "class_damage_inputs c JOIN jobs j ON j.id = c.job_id AND j.state = 'done'",
            campaign,
            Some(kind),
        )
        .await
    }

    /// Class rows with their sea state's index and occurrence, from `from` (which names the
    /// rows `c` and their job `j`), of one job kind or of all.
    async fn class_rows(
        &self,
        from: &str,
        campaign: CampaignId,
        kind: Option<JobKind>,
    ) -> Result<Vec<(i64, f64, ClassDamageInput)>> {
        const OP: &str = "read class damage inputs";
        let columns = CLASS_COLUMNS
            .split(", ")
            .map(|c| format!("c.{}", c.trim()))
            .collect::<Vec<_>>()
            .join(", ");
        let sql = format!(
            "SELECT s.sea_state_index, s.occurrence_fraction, {columns} \
             FROM {from} \
             JOIN sea_states s ON s.id = j.sea_state_id \
             WHERE j.campaign_id = $1{} \
             ORDER BY s.sea_state_index, c.job_id, c.layer_interface, c.angular_position",
            if kind.is_some() {
                " AND j.kind = $2"
            } else {
                ""
            }
        );
        let mut query = sqlx::query(&sql).bind(campaign.0);
        if let Some(kind) = kind {
            query = query.bind(kind.as_str());
        }
        let rows = query
            .fetch_all(&self.pool)
            .await
            .map_err(StoreError::db(OP))?;
        rows.iter()
            .map(|row| {
                Ok((
                    get(row, "sea_state_index", OP)?,
                    get(row, "occurrence_fraction", OP)?,
                    class_from_row(row, OP)?,
                ))
            })
            .collect()
    }

    pub(crate) async fn fidelity_comparison(
        &self,
        campaign: CampaignId,
    ) -> Result<Vec<FidelityComparison>> {
        const OP: &str = "read fidelity_comparison";
        let rows = sqlx::query(
            "SELECT * FROM fidelity_comparison WHERE campaign_id = $1 \
             ORDER BY sea_state_index, seed_index, hot_spot_index, layer_interface, \
             angular_position",
        )
        .bind(campaign.0)
        .fetch_all(&self.pool)
        .await
        .map_err(StoreError::db(OP))?;
        rows.iter()
            .map(|row| {
                let position: String = get(row, "angular_position", OP)?;
                Ok(FidelityComparison {
                    sea_state_index: get(row, "sea_state_index", OP)?,
                    hs_m: get(row, "hs_m", OP)?,
                    tp_s: get(row, "tp_s", OP)?,
                    occurrence_fraction: get(row, "occurrence_fraction", OP)?,
                    seed_index: get(row, "seed_index", OP)?,
                    hot_spot_index: get(row, "hot_spot_index", OP)?,
                    layer_interface: get(row, "layer_interface", OP)?,
                    angular_position: parse_position(&position)?,
                    reduced_damage_rate_max_per_s: get(row, "reduced_damage_rate_max_per_s", OP)?,
                    fe_damage_rate_max_per_s: get(row, "fe_damage_rate_max_per_s", OP)?,
                    reduced_damage_rate_mean_per_s: get(row, "reduced_damage_rate_mean_per_s", OP)?,
                    fe_damage_rate_mean_per_s: get(row, "fe_damage_rate_mean_per_s", OP)?,
                    reduced_slip_amplitude_max_m: get(row, "reduced_slip_amplitude_max_m", OP)?,
                    fe_slip_amplitude_max_m: get(row, "fe_slip_amplitude_max_m", OP)?,
                    reduced_slip_cycles_per_hour: get(row, "reduced_slip_cycles_per_hour", OP)?,
                    fe_slip_cycles_per_hour: get(row, "fe_slip_cycles_per_hour", OP)?,
                })
            })
            .collect()
    }
}
