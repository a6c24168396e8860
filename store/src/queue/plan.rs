//! Planning: campaigns, sea states, jobs with their dependencies, workers.

use super::{json_text, Queue, Result, Tx, PLAN_BATCH_ROWS};
use super::{Db, DIALECT};
use crate::error::StoreError;
use crate::model::{NewCampaign, NewSeaState, PlannedJob, WorkerInfo};
use crate::types::{CampaignId, JobId, JobState, SeaStateId, WorkerId};

impl Queue {
    pub(crate) async fn create_campaign(&self, campaign: &NewCampaign) -> Result<CampaignId> {
        const OP: &str = "create campaign";
        let mut tx = self.begin_write(OP).await?;
        let now = self.now_ms(&mut tx).await?;
        let id = insert_campaign_row(&mut tx, campaign, now).await?;
        tx.commit().await.map_err(StoreError::db(OP))?;
        Ok(id)
    }

    pub(crate) async fn campaign_by_name(&self, name: &str) -> Result<Option<CampaignId>> {
        let id: Option<i64> = sqlx::query_scalar("SELECT id FROM campaigns WHERE name = $1")
            .bind(name)
            .fetch_optional(&self.pool)
            .await
            .map_err(StoreError::db("find campaign"))?;
        Ok(id.map(CampaignId))
    }

    pub(crate) async fn insert_sea_states(
        &self,
        campaign: CampaignId,
        sea_states: &[NewSeaState],
    ) -> Result<Vec<SeaStateId>> {
        const OP: &str = "insert sea states";
        let mut tx = self.begin_write(OP).await?;
        let ids = insert_sea_state_rows(&mut tx, campaign, sea_states).await?;
        tx.commit().await.map_err(StoreError::db(OP))?;
        Ok(ids)
    }

    pub(crate) async fn insert_plan(
        &self,
        campaign: CampaignId,
        jobs: &[PlannedJob],
    ) -> Result<Vec<JobId>> {
        const OP: &str = "insert plan";
        let payloads = checked_payloads(jobs)?;
        let mut tx = self.begin_write(OP).await?;
        let now = self.now_ms(&mut tx).await?;
        let ids = insert_job_rows(&mut tx, campaign, jobs, &payloads, now).await?;
        tx.commit().await.map_err(StoreError::db(OP))?;
        Ok(ids)
    }

    pub(crate) async fn register_worker(&self, info: &WorkerInfo) -> Result<WorkerId> {
        const OP: &str = "register worker";
        let id = WorkerId(uuid::Uuid::new_v4().to_string());
        let mut tx = self.begin_write(OP).await?;
        let now = self.now_ms(&mut tx).await?;
        sqlx::query(
            "INSERT INTO workers (id, host, pid, version, started_at_ms, last_seen_at_ms) \
             VALUES ($1, $2, $3, $4, $5, $5)",
        )
        .bind(&id.0)
        .bind(&info.host)
        .bind(info.pid)
        .bind(&info.version)
        .bind(now)
        .execute(&mut *tx)
        .await
        .map_err(StoreError::db(OP))?;
        tx.commit().await.map_err(StoreError::db(OP))?;
        Ok(id)
    }
}

pub(super) async fn insert_campaign_row(
    tx: &mut Tx,
    campaign: &NewCampaign,
    now: i64,
) -> Result<CampaignId> {
    const OP: &str = "create campaign";
    let spec = json_text("campaigns.spec_json", &campaign.spec)?;
    let existing: Option<i64> = sqlx::query_scalar("SELECT id FROM campaigns WHERE name = $1")
        .bind(&campaign.name)
        .fetch_optional(&mut **tx)
        .await
        .map_err(StoreError::db(OP))?;
    if let Some(existing) = existing {
        return Err(StoreError::CampaignExists {
            name: campaign.name.clone(),
            existing: CampaignId(existing),
        });
    }
    let id: i64 = sqlx::query_scalar(
        "INSERT INTO campaigns (name, spec_json, spec_sha256, state, created_at_ms) \
         VALUES ($1, $2, $3, 'active', $4) RETURNING id",
    )
    .bind(&campaign.name)
    .bind(&spec)
    .bind(&campaign.spec_sha256)
    .bind(now)
    .fetch_one(&mut **tx)
    .await
    .map_err(StoreError::db(OP))?;
    Ok(CampaignId(id))
}

pub(super) async fn insert_sea_state_rows(
    tx: &mut Tx,
    campaign: CampaignId,
    sea_states: &[NewSeaState],
) -> Result<Vec<SeaStateId>> {
    const OP: &str = "insert sea states";
    let mut ids = Vec::with_capacity(sea_states.len());
    for sea_state in sea_states {
        let seeds = serde_json::to_string(&sea_state.seeds).map_err(|source| StoreError::Json {
            field: "sea_states.seeds_json",
            source,
        })?;
        let id: i64 = sqlx::query_scalar(
            "INSERT INTO sea_states \
             (campaign_id, sea_state_index, hs_m, tp_s, occurrence_fraction, seeds_json, \
              heading_deg, sector, wave_energy_kept) \
             VALUES ($1, $2, $3, $4, $5, $6, $7, $8, $9) RETURNING id",
        )
        .bind(campaign.0)
        .bind(sea_state.index)
        .bind(sea_state.hs_m)
        .bind(sea_state.tp_s)
        .bind(sea_state.occurrence_fraction)
        .bind(seeds)
        .bind(sea_state.heading_deg)
        .bind(sea_state.sector.as_deref())
        .bind(sea_state.wave_energy_kept)
        .fetch_one(&mut **tx)
        .await
        .map_err(StoreError::db(OP))?;
        ids.push(SeaStateId(id));
    }
    Ok(ids)
}

/// Checks a plan's dependencies, attempts and costs; returns the payloads as text.
pub(super) fn checked_payloads(jobs: &[PlannedJob]) -> Result<Vec<String>> {
    let mut payloads = Vec::with_capacity(jobs.len());
    for (index, job) in jobs.iter().enumerate() {
        if let Some(&dep) = job.depends_on.iter().find(|&&dep| dep >= index) {
            return Err(StoreError::BadDependency {
                job_index: index,
                depends_on: dep,
            });
        }
        if job.max_attempts < 1 {
            return Err(StoreError::InvalidParameter {
                field: "max_attempts",
                value: job.max_attempts.to_string(),
                reason: "must be >= 1",
            });
        }
        if !(job.expected_cost_s.is_finite() && job.expected_cost_s >= 0.0) {
            return Err(StoreError::InvalidParameter {
                field: "expected_cost_s",
                value: job.expected_cost_s.to_string(),
                reason: "must be finite and >= 0",
            });
        }
        payloads.push(json_text("jobs.payload_json", &job.payload)?);
    }
    Ok(payloads)
}

pub(super) async fn insert_job_rows(
    tx: &mut Tx,
    campaign: CampaignId,
    jobs: &[PlannedJob],
    payloads: &[String],
    now: i64,
) -> Result<Vec<JobId>> {
    const OP: &str = "insert plan";
    // Ids are reserved first so that the rows and their dependencies can be written in
    // multi-row statements (one round trip per batch instead of per row).
    let count = i64::try_from(jobs.len()).unwrap_or(i64::MAX);
    let ids: Vec<JobId> = sqlx::query_scalar::<_, i64>(DIALECT.reserve_job_ids_sql)
        .bind(count)
        .fetch_all(&mut **tx)
        .await
        .map_err(StoreError::db(OP))?
        .into_iter()
        .map(JobId)
        .collect();
    if ids.len() != jobs.len() {
        return Err(StoreError::InvalidParameter {
            field: "jobs",
            value: jobs.len().to_string(),
            reason: "could not reserve as many job ids",
        });
    }
    let rows: Vec<(JobId, &PlannedJob, &String)> = ids
        .iter()
        .copied()
        .zip(jobs.iter())
        .zip(payloads)
        .map(|((i, j), p)| (i, j, p))
        .collect();
    for batch in rows.chunks(PLAN_BATCH_ROWS) {
        let mut insert = sqlx::QueryBuilder::<Db>::new(
            "INSERT INTO jobs (id, campaign_id, sea_state_id, kind, state, payload_json, \
             max_attempts, priority, expected_cost_s, cache_key, not_before_ms, \
             created_at_ms, updated_at_ms) ",
        );
        insert.push_values(batch, |mut row, &(id, job, payload)| {
            let state = if job.depends_on.is_empty() {
                JobState::Ready
            } else {
                JobState::Blocked
            };
            row.push_bind(id.0)
                .push_bind(campaign.0)
                .push_bind(job.sea_state.map(|s| s.0))
                .push_bind(job.kind.as_str())
                .push_bind(state.as_str())
                .push_bind(payload.as_str())
                .push_bind(job.max_attempts)
                .push_bind(job.priority)
                .push_bind(job.expected_cost_s)
                .push_bind(job.cache_key.as_deref())
                .push_bind(0_i64)
                .push_bind(now)
                .push_bind(now);
        });
        insert
            .build()
            .execute(&mut **tx)
            .await
            .map_err(StoreError::db(OP))?;
    }
    let edges: Vec<(i64, i64)> = jobs
        .iter()
        .enumerate()
        .flat_map(|(index, job)| job.depends_on.iter().map(move |&dep| (index, dep)))
        .map(|(index, dep)| (ids[index].0, ids[dep].0))
        .collect();
    for batch in edges.chunks(PLAN_BATCH_ROWS) {
        let mut insert =
            sqlx::QueryBuilder::<Db>::new("INSERT INTO job_dependencies (job_id, depends_on) ");
        insert.push_values(batch, |mut row, &(job, dep)| {
            row.push_bind(job).push_bind(dep);
        });
        insert
            .build()
            .execute(&mut **tx)
            .await
            .map_err(StoreError::db(OP))?;
    }
    Ok(ids)
}
