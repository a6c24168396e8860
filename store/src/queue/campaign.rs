//! Campaign-level writes and reads: a whole plan in one transaction, campaign rows.

use super::plan::{checked_payloads, insert_campaign_row, insert_job_rows, insert_sea_state_rows};
use super::{end_attempt, lease_lost, parse_json, Queue, Result};
use crate::error::StoreError;
use crate::model::{CampaignRecord, Lease, NewCampaign, NewSeaState, PlannedJob};
use crate::types::{AttemptOutcome, CampaignId, JobId, SeaStateId};
use sqlx::Row;

impl Queue {
    /// Creates the campaign, its sea states and its jobs in one transaction, so that an
    /// interrupted launch leaves either nothing or a complete plan. `make_jobs` receives the
    /// sea-state ids in the order of `sea_states`.
    pub(crate) async fn create_planned_campaign(
        &self,
        campaign: &NewCampaign,
        sea_states: &[NewSeaState],
        make_jobs: impl FnOnce(&[SeaStateId]) -> Vec<PlannedJob>,
    ) -> Result<(CampaignId, Vec<JobId>)> {
        const OP: &str = "create planned campaign";
        let mut tx = self.begin_write(OP).await?;
        let now = self.now_ms(&mut tx).await?;
        let id = insert_campaign_row(&mut tx, campaign, now).await?;
        let sea_state_ids = insert_sea_state_rows(&mut tx, id, sea_states).await?;
        let jobs = make_jobs(&sea_state_ids);
        let payloads = checked_payloads(&jobs)?;
        let job_ids = insert_job_rows(&mut tx, id, &jobs, &payloads, now).await?;
        tx.commit().await.map_err(StoreError::db(OP))?;
        Ok((id, job_ids))
    }

    pub(crate) async fn campaigns(&self) -> Result<Vec<CampaignRecord>> {
        const OP: &str = "read campaigns";
        let rows = sqlx::query(
            "SELECT id, name, spec_json, spec_sha256, state, created_at_ms FROM campaigns \
             ORDER BY id",
        )
        .fetch_all(&self.pool)
        .await
        .map_err(StoreError::db(OP))?;
        rows.iter()
            .map(|row| {
                let spec: String = row.try_get("spec_json").map_err(StoreError::db(OP))?;
                let state: String = row.try_get("state").map_err(StoreError::db(OP))?;
                Ok(CampaignRecord {
                    id: CampaignId(row.try_get("id").map_err(StoreError::db(OP))?),
                    name: row.try_get("name").map_err(StoreError::db(OP))?,
                    spec: parse_json("campaigns.spec_json", &spec)?,
                    spec_sha256: row.try_get("spec_sha256").map_err(StoreError::db(OP))?,
                    state: state.parse()?,
                    created_at_ms: row.try_get("created_at_ms").map_err(StoreError::db(OP))?,
                })
            })
            .collect()
    }
}

impl Queue {
    /// Gives a running job back to the queue without counting the attempt (a worker stopping
    /// on a signal). The attempt is ended as `cancelled` with `reason`.
    pub(crate) async fn release(&self, lease: &Lease, reason: &str) -> Result<()> {
        const OP: &str = "release job";
        let mut tx = self.begin_write(OP).await?;
        let now = self.now_ms(&mut tx).await?;
        let updated = sqlx::query(
            "UPDATE jobs SET state = 'ready', attempt = attempt - 1, lease_token = NULL, \
             lease_expires_at_ms = NULL, not_before_ms = $1, updated_at_ms = $1 \
             WHERE id = $2 AND lease_token = $3 AND state = 'running'",
        )
        .bind(now)
        .bind(lease.job.0)
        .bind(&lease.token.0)
        .execute(&mut *tx)
        .await
        .map_err(StoreError::db(OP))?
        .rows_affected();
        if updated == 0 {
            tx.rollback().await.map_err(StoreError::db(OP))?;
            return Err(lease_lost(lease));
        }
        end_attempt(&mut tx, lease, now, AttemptOutcome::Cancelled, Some(reason)).await?;
        tx.commit().await.map_err(StoreError::db(OP))?;
        Ok(())
    }
}
