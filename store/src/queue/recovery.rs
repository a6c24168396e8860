//! Failures, expired leases and cancellation.

use super::DIALECT;
use super::{end_attempt, fail_dependents, lease_lost, Queue, Result};
use crate::error::StoreError;
use crate::model::{CancelReport, FailureDisposition, FailureKind, JobFailure, Lease, SweepReport};
use crate::types::{AttemptOutcome, CampaignId, JobId, JobState};
use sqlx::Row;

impl Queue {
    pub(crate) async fn fail(
        &self,
        lease: &Lease,
        failure: &JobFailure,
    ) -> Result<FailureDisposition> {
        const OP: &str = "fail job";
        let mut tx = self.begin_write(OP).await?;
        let now = self.now_ms(&mut tx).await?;
        let row = sqlx::query(&format!(
            "SELECT attempt, max_attempts FROM jobs \
                 WHERE id = $1 AND lease_token = $2 AND state = 'running'{}",
            DIALECT.row_lock_suffix
        ))
        .bind(lease.job.0)
        .bind(&lease.token.0)
        .fetch_optional(&mut *tx)
        .await
        .map_err(StoreError::db(OP))?;
        let Some(row) = row else {
            tx.rollback().await.map_err(StoreError::db(OP))?;
            return Err(lease_lost(lease));
        };
        let attempt: i64 = row.try_get("attempt").map_err(StoreError::db(OP))?;
        let max_attempts: i64 = row.try_get("max_attempts").map_err(StoreError::db(OP))?;
        let retry = failure.kind == FailureKind::Transient && attempt < max_attempts;
        let (state, outcome, disposition) = if retry {
            let not_before_ms = now + self.policy.backoff_ms(attempt);
            (
                JobState::Ready,
                AttemptOutcome::TransientFailure,
                FailureDisposition::Retry { not_before_ms },
            )
        } else {
            let outcome = match failure.kind {
                FailureKind::Transient => AttemptOutcome::TransientFailure,
                FailureKind::Permanent => AttemptOutcome::PermanentFailure,
            };
            (
                JobState::Failed,
                outcome,
                FailureDisposition::Failed {
                    dependents_failed: 0,
                },
            )
        };
        let message = if failure.kind == FailureKind::Transient && !retry {
            format!(
                "{} (attempt {attempt} of {max_attempts}, no attempts left)",
                failure.message
            )
        } else {
            failure.message.clone()
        };
        let not_before = match disposition {
            FailureDisposition::Retry { not_before_ms } => not_before_ms,
            FailureDisposition::Failed { .. } => now,
        };
        sqlx::query(
            "UPDATE jobs SET state = $1, lease_token = NULL, lease_expires_at_ms = NULL, \
             error_class = $2, error_message = $3, not_before_ms = $4, updated_at_ms = $5 \
             WHERE id = $6 AND lease_token = $7",
        )
        .bind(state.as_str())
        .bind(failure.error_class.as_str())
        .bind(&message)
        .bind(not_before)
        .bind(now)
        .bind(lease.job.0)
        .bind(&lease.token.0)
        .execute(&mut *tx)
        .await
        .map_err(StoreError::db(OP))?;
        end_attempt(&mut tx, lease, now, outcome, Some(&message)).await?;
        let disposition = match disposition {
            FailureDisposition::Failed { .. } => FailureDisposition::Failed {
                dependents_failed: fail_dependents(&mut tx, lease.job, now).await?,
            },
            retry => retry,
        };
        tx.commit().await.map_err(StoreError::db(OP))?;
        Ok(disposition)
    }

    pub(crate) async fn sweep_expired(&self) -> Result<SweepReport> {
        const OP: &str = "sweep expired leases";
        let mut tx = self.begin_write(OP).await?;
        let now = self.now_ms(&mut tx).await?;
        // Rows are locked (PostgreSQL) job first, attempt second, the order every other write
        // uses, so a sweep and a completion cannot deadlock; rows another transaction holds
        // are left for the next sweep.
        let select = format!(
            "SELECT id, lease_token FROM jobs \
             WHERE state = 'running' AND lease_expires_at_ms < $1 ORDER BY id{}",
            DIALECT.claim_lock_suffix
        );
        let expired = sqlx::query(&select)
            .bind(now)
            .fetch_all(&mut *tx)
            .await
            .map_err(StoreError::db(OP))?;
        let mut report = SweepReport::default();
        for row in expired {
            let job = JobId(row.try_get("id").map_err(StoreError::db(OP))?);
            let token: Option<String> = row.try_get("lease_token").map_err(StoreError::db(OP))?;
            // A lost lease is not a failed attempt: the attempt counter is given back.
            let state: Option<String> = sqlx::query_scalar(
                "UPDATE jobs SET \
                   state = CASE WHEN lost_count + 1 >= $2 THEN 'failed' ELSE 'ready' END, \
                   error_class = CASE WHEN lost_count + 1 >= $2 THEN 'lost' ELSE error_class END, \
                   error_message = CASE WHEN lost_count + 1 >= $2 \
                     THEN 'lease expired ' || (lost_count + 1) || ' times (limit ' || $2 || \
                          '); last held by worker ' || COALESCE(worker_id, '?') \
                     ELSE error_message END, \
                   lost_count = lost_count + 1, attempt = attempt - 1, lease_token = NULL, \
                   lease_expires_at_ms = NULL, updated_at_ms = $1 \
                 WHERE id = $3 AND state = 'running' AND lease_expires_at_ms < $1 \
                 RETURNING state",
            )
            .bind(now)
            .bind(self.policy.max_lost)
            .bind(job.0)
            .fetch_optional(&mut *tx)
            .await
            .map_err(StoreError::db(OP))?;
            let Some(state) = state else { continue };
            sqlx::query(
                "UPDATE attempts SET outcome = 'lost', ended_at_ms = $1 \
                 WHERE lease_token = $2 AND outcome IS NULL",
            )
            .bind(now)
            .bind(&token)
            .execute(&mut *tx)
            .await
            .map_err(StoreError::db(OP))?;
            if state.parse::<JobState>()? == JobState::Failed {
                fail_dependents(&mut tx, job, now).await?;
                report.failed.push(job);
            } else {
                report.requeued.push(job);
            }
        }
        tx.commit().await.map_err(StoreError::db(OP))?;
        Ok(report)
    }

    pub(crate) async fn running_on_host(&self, host: &str) -> Result<Vec<(JobId, i64)>> {
        const OP: &str = "read running jobs of a host";
        let rows = sqlx::query(
            "SELECT j.id, w.pid FROM jobs j JOIN workers w ON w.id = j.worker_id \
             WHERE j.state = 'running' AND w.host = $1 ORDER BY j.id",
        )
        .bind(host)
        .fetch_all(&self.pool)
        .await
        .map_err(StoreError::db(OP))?;
        rows.iter()
            .map(|r| {
                Ok((
                    JobId(r.try_get("id").map_err(StoreError::db(OP))?),
                    r.try_get("pid").map_err(StoreError::db(OP))?,
                ))
            })
            .collect()
    }

    pub(crate) async fn expire_leases_of(&self, host: &str, pids: &[i64]) -> Result<SweepReport> {
        const OP: &str = "expire the leases of dead workers";
        if pids.is_empty() {
            return Ok(SweepReport::default());
        }
        let mut tx = self.begin_write(OP).await?;
        for &pid in pids {
            sqlx::query(
                "UPDATE jobs SET lease_expires_at_ms = -1 WHERE state = 'running' AND worker_id IN \
                 (SELECT id FROM workers WHERE host = $1 AND pid = $2)",
            )
            .bind(host)
            .bind(pid)
            .execute(&mut *tx)
            .await
            .map_err(StoreError::db(OP))?;
        }
        tx.commit().await.map_err(StoreError::db(OP))?;
        self.sweep_expired().await
    }

    pub(crate) async fn cancel_campaign(&self, campaign: CampaignId) -> Result<CancelReport> {
        const OP: &str = "cancel campaign";
        let mut tx = self.begin_write(OP).await?;
        let now = self.now_ms(&mut tx).await?;
        let found: i64 = sqlx::query_scalar("SELECT COUNT(*) FROM campaigns WHERE id = $1")
            .bind(campaign.0)
            .fetch_one(&mut *tx)
            .await
            .map_err(StoreError::db(OP))?;
        if found == 0 {
            tx.rollback().await.map_err(StoreError::db(OP))?;
            return Err(StoreError::UnknownCampaign(campaign.to_string()));
        }
        // The running jobs' tokens, read (and locked on PostgreSQL) before the jobs change.
        let running = format!(
            "SELECT lease_token FROM jobs WHERE campaign_id = $1 AND state = 'running' \
             ORDER BY id{}",
            DIALECT.row_lock_suffix
        );
        let tokens: Vec<Option<String>> = sqlx::query_scalar(&running)
            .bind(campaign.0)
            .fetch_all(&mut *tx)
            .await
            .map_err(StoreError::db(OP))?;
        let cancelled = sqlx::query(
            "UPDATE jobs SET state = 'cancelled', lease_token = NULL, lease_expires_at_ms = NULL, \
             updated_at_ms = $1 \
             WHERE campaign_id = $2 AND state IN ('blocked', 'ready', 'running') \
             RETURNING lease_token",
        )
        .bind(now)
        .bind(campaign.0)
        .fetch_all(&mut *tx)
        .await
        .map_err(StoreError::db(OP))?;
        if cancelled.is_empty() {
            // every job is finished: nothing to cancel, and the campaign keeps its state
            tx.rollback().await.map_err(StoreError::db(OP))?;
            return Ok(CancelReport { jobs_cancelled: 0 });
        }
        sqlx::query("UPDATE campaigns SET state = 'cancelled' WHERE id = $1")
            .bind(campaign.0)
            .execute(&mut *tx)
            .await
            .map_err(StoreError::db(OP))?;
        for token in &tokens {
            sqlx::query(
                "UPDATE attempts SET outcome = 'cancelled', ended_at_ms = $1 \
                 WHERE lease_token = $2 AND outcome IS NULL",
            )
            .bind(now)
            .bind(token)
            .execute(&mut *tx)
            .await
            .map_err(StoreError::db(OP))?;
        }
        tx.commit().await.map_err(StoreError::db(OP))?;
        Ok(CancelReport {
            jobs_cancelled: cancelled.len() as u64,
        })
    }
}
