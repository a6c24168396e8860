//! Reads: jobs, attempts, results, progress and lifetime views.

use super::results::band_of;
use super::{job_from_row, parse_json, Queue, Result, JOB_COLUMNS};
use crate::error::StoreError;
use crate::model::{
    AttemptRecord, CampaignProgress, ContactStatistics, HotSpotSummary, JobArtifact, JobRecord,
    JobResults, LifetimeDamage,
};
use crate::results::DamageInput;
use crate::types::{
    ArtifactRole, AttemptId, AttemptOutcome, CampaignId, JobId, JobState, WorkerId,
};
use serde_json::Value;
use sqlx::Row;

impl Queue {
    pub(crate) async fn job(&self, job: JobId) -> Result<JobRecord> {
        let sql = format!("SELECT {JOB_COLUMNS} FROM jobs WHERE id = $1");
        let row = sqlx::query(&sql)
            .bind(job.0)
            .fetch_optional(&self.pool)
            .await
            .map_err(StoreError::db("read job"))?;
        match row {
            Some(row) => job_from_row(&row),
            None => Err(StoreError::UnknownJob(job)),
        }
    }

    pub(crate) async fn jobs_of_campaign(&self, campaign: CampaignId) -> Result<Vec<JobRecord>> {
        let sql = format!("SELECT {JOB_COLUMNS} FROM jobs WHERE campaign_id = $1 ORDER BY id");
        let rows = sqlx::query(&sql)
            .bind(campaign.0)
            .fetch_all(&self.pool)
            .await
            .map_err(StoreError::db("read jobs"))?;
        rows.iter().map(job_from_row).collect()
    }

    pub(crate) async fn attempt_outcome(
        &self,
        attempt: AttemptId,
    ) -> Result<Option<AttemptOutcome>> {
        let outcome: Option<Option<String>> =
            sqlx::query_scalar("SELECT outcome FROM attempts WHERE id = $1")
                .bind(attempt.0)
                .fetch_optional(&self.pool)
                .await
                .map_err(StoreError::db("read attempt"))?;
        match outcome {
            Some(text) => text
                .map(|t| t.parse().map_err(StoreError::from))
                .transpose(),
            None => Err(StoreError::InvalidParameter {
                field: "attempt",
                value: attempt.0.to_string(),
                reason: "is not recorded in this store",
            }),
        }
    }

    pub(crate) async fn attempts_of_campaign(
        &self,
        campaign: CampaignId,
    ) -> Result<Vec<AttemptRecord>> {
        const OP: &str = "read attempts";
        let rows = sqlx::query(
            "SELECT a.id, a.job_id, a.claim_number, a.worker_id, a.host, a.pid, \
             a.started_at_ms, a.ended_at_ms, a.outcome \
             FROM attempts a JOIN jobs j ON j.id = a.job_id \
             WHERE j.campaign_id = $1 ORDER BY a.id",
        )
        .bind(campaign.0)
        .fetch_all(&self.pool)
        .await
        .map_err(StoreError::db(OP))?;
        rows.iter()
            .map(|row| {
                let outcome: Option<String> = row.try_get("outcome").map_err(StoreError::db(OP))?;
                Ok(AttemptRecord {
                    id: AttemptId(row.try_get("id").map_err(StoreError::db(OP))?),
                    job: JobId(row.try_get("job_id").map_err(StoreError::db(OP))?),
                    claim_number: row.try_get("claim_number").map_err(StoreError::db(OP))?,
                    worker: WorkerId(row.try_get("worker_id").map_err(StoreError::db(OP))?),
                    host: row.try_get("host").map_err(StoreError::db(OP))?,
                    pid: row.try_get("pid").map_err(StoreError::db(OP))?,
                    started_at_ms: row.try_get("started_at_ms").map_err(StoreError::db(OP))?,
                    ended_at_ms: row.try_get("ended_at_ms").map_err(StoreError::db(OP))?,
                    outcome: outcome.map(|o| o.parse()).transpose()?,
                })
            })
            .collect()
    }

    pub(crate) async fn results_of(&self, job: JobId) -> Result<JobResults> {
        const OP: &str = "read results";
        let db = StoreError::db;
        let result: Option<Option<String>> =
            sqlx::query_scalar("SELECT result_json FROM jobs WHERE id = $1")
                .bind(job.0)
                .fetch_optional(&self.pool)
                .await
                .map_err(db(OP))?;
        let result = match result {
            None => return Err(StoreError::UnknownJob(job)),
            Some(text) => match text {
                Some(text) => parse_json("jobs.result_json", &text)?,
                None => Value::Null,
            },
        };
        let mut results = JobResults {
            result,
            ..JobResults::default()
        };
        let rows = sqlx::query(
            "SELECT hot_spot_index, summary_json FROM hot_spot_summaries \
             WHERE job_id = $1 ORDER BY hot_spot_index",
        )
        .bind(job.0)
        .fetch_all(&self.pool)
        .await
        .map_err(db(OP))?;
        for row in rows {
            let summary: String = row.try_get("summary_json").map_err(db(OP))?;
            results.hot_spots.push(HotSpotSummary {
                hot_spot_index: row.try_get("hot_spot_index").map_err(db(OP))?,
                summary: parse_json("hot_spot_summaries.summary_json", &summary)?,
            });
        }
        let rows = sqlx::query(
            "SELECT hot_spot_index, contact_index, layer_interface, angular_position_rad, \
             statistics_json FROM contact_statistics WHERE job_id = $1 \
             ORDER BY hot_spot_index, contact_index",
        )
        .bind(job.0)
        .fetch_all(&self.pool)
        .await
        .map_err(db(OP))?;
        for row in rows {
            let statistics: String = row.try_get("statistics_json").map_err(db(OP))?;
            results.contacts.push(ContactStatistics {
                hot_spot_index: row.try_get("hot_spot_index").map_err(db(OP))?,
                contact_index: row.try_get("contact_index").map_err(db(OP))?,
                layer_interface: row.try_get("layer_interface").map_err(db(OP))?,
                angular_position_rad: row.try_get("angular_position_rad").map_err(db(OP))?,
                statistics: parse_json("contact_statistics.statistics_json", &statistics)?,
            });
        }
        let rows = sqlx::query(
            "SELECT hot_spot_index, measure, seed_index, effective_duration_s, damage, \
             details_json FROM damage_inputs WHERE job_id = $1 ORDER BY hot_spot_index, measure",
        )
        .bind(job.0)
        .fetch_all(&self.pool)
        .await
        .map_err(db(OP))?;
        for row in rows {
            let details: String = row.try_get("details_json").map_err(db(OP))?;
            results.damage_inputs.push(DamageInput {
                hot_spot_index: row.try_get("hot_spot_index").map_err(db(OP))?,
                measure: row.try_get("measure").map_err(db(OP))?,
                seed_index: row.try_get("seed_index").map_err(db(OP))?,
                effective_duration_s: row.try_get("effective_duration_s").map_err(db(OP))?,
                damage: row.try_get("damage").map_err(db(OP))?,
                details: parse_json("damage_inputs.details_json", &details)?,
            });
        }
        results.class_damage_inputs = self.class_damage_inputs_of(job).await?;
        let rows = sqlx::query(
            "SELECT ja.role, a.sha256, a.size_bytes, a.path FROM job_artifacts ja \
             JOIN artifacts a ON a.sha256 = ja.sha256 WHERE ja.job_id = $1 ORDER BY ja.role",
        )
        .bind(job.0)
        .fetch_all(&self.pool)
        .await
        .map_err(db(OP))?;
        for row in rows {
            results.artifacts.push(JobArtifact {
                role: ArtifactRole::parse(&row.try_get::<String, _>("role").map_err(db(OP))?),
                sha256: row.try_get("sha256").map_err(db(OP))?,
                size_bytes: row.try_get("size_bytes").map_err(db(OP))?,
                path: row.try_get("path").map_err(db(OP))?,
            });
        }
        Ok(results)
    }

    pub(crate) async fn progress(&self, campaign: CampaignId) -> Result<CampaignProgress> {
        const OP: &str = "read progress";
        let row = sqlx::query("SELECT * FROM campaign_progress WHERE campaign_id = $1")
            .bind(campaign.0)
            .fetch_optional(&self.pool)
            .await
            .map_err(StoreError::db(OP))?
            .ok_or_else(|| StoreError::UnknownCampaign(campaign.to_string()))?;
        let mut jobs_by_state = Vec::with_capacity(JobState::ALL.len());
        for state in JobState::ALL {
            let column = format!("jobs_{}", state.as_str());
            let count: i64 = row.try_get(column.as_str()).map_err(StoreError::db(OP))?;
            jobs_by_state.push((*state, count));
        }
        Ok(CampaignProgress {
            campaign,
            name: row.try_get("campaign_name").map_err(StoreError::db(OP))?,
            jobs_total: row.try_get("jobs_total").map_err(StoreError::db(OP))?,
            jobs_by_state,
            occurrence_planned: row
                .try_get("occurrence_planned")
                .map_err(StoreError::db(OP))?,
            occurrence_covered: row
                .try_get("occurrence_covered")
                .map_err(StoreError::db(OP))?,
        })
    }

    pub(crate) async fn lifetime_damage(
        &self,
        campaign: CampaignId,
    ) -> Result<Vec<LifetimeDamage>> {
        const OP: &str = "read lifetime damage";
        let rows = sqlx::query(
            "SELECT hot_spot_index, measure, annual_damage, occurrence_covered, sea_states, \
             annual_damage_variance, annual_damage_variance_dof_sum, sea_states_with_spread, \
             sea_states_without_spread \
             FROM lifetime_damage WHERE campaign_id = $1 ORDER BY hot_spot_index, measure",
        )
        .bind(campaign.0)
        .fetch_all(&self.pool)
        .await
        .map_err(StoreError::db(OP))?;
        rows.iter()
            .map(|row| {
                let annual_damage: f64 =
                    row.try_get("annual_damage").map_err(StoreError::db(OP))?;
                Ok(LifetimeDamage {
                    hot_spot_index: row.try_get("hot_spot_index").map_err(StoreError::db(OP))?,
                    measure: row.try_get("measure").map_err(StoreError::db(OP))?,
                    annual_damage,
                    band: band_of(row, annual_damage, OP)?,
                    occurrence_covered: row
                        .try_get("occurrence_covered")
                        .map_err(StoreError::db(OP))?,
                    sea_states: row.try_get("sea_states").map_err(StoreError::db(OP))?,
                })
            })
            .collect()
    }
}
