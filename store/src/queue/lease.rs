//! Leases: claim, heartbeat, completion (fresh or from the cache); settling of unselected gated
//! jobs, which are done without a lease.

use super::results::{insert_class_damage_inputs, COPY_CLASS_DAMAGE_INPUTS};
use super::DIALECT;
use super::{end_attempt, json_text, lease_lost, parse_json, sha256_hex, Queue, Result, Tx};
use crate::error::StoreError;
use crate::model::{ClaimFilter, JobResults, Lease};
use crate::types::{
    AttemptId, AttemptOutcome, CampaignId, JobId, JobKind, JobState, LeaseToken, SeaStateId,
    WorkerId,
};
use sqlx::Row;

/// Makes claimable the dependents of the done `job` whose every dependency is now done.
async fn unblock_dependents(tx: &mut Tx, job: JobId, now: i64) -> Result<()> {
    const OP: &str = "complete job";
    // On PostgreSQL two jobs feeding one dependent may complete concurrently; locking the
    // dependents makes the second completion wait and then see the first one's `done`.
    if !DIALECT.row_lock_suffix.is_empty() {
        let lock = format!(
            "SELECT id FROM jobs WHERE id IN \
             (SELECT job_id FROM job_dependencies WHERE depends_on = $1) \
             ORDER BY id{}",
            DIALECT.row_lock_suffix
        );
        sqlx::query(&lock)
            .bind(job.0)
            .fetch_all(&mut **tx)
            .await
            .map_err(StoreError::db(OP))?;
    }
    sqlx::query(
        "UPDATE jobs SET state = 'ready', updated_at_ms = $1 \
         WHERE state = 'blocked' \
           AND id IN (SELECT job_id FROM job_dependencies WHERE depends_on = $2) \
           AND NOT EXISTS (SELECT 1 FROM job_dependencies d JOIN jobs p ON p.id = d.depends_on \
                           WHERE d.job_id = jobs.id AND p.state <> 'done')",
    )
    .bind(now)
    .bind(job.0)
    .execute(&mut **tx)
    .await
    .map_err(StoreError::db(OP))?;
    Ok(())
}

impl Queue {
    pub(crate) async fn claim(
        &self,
        worker: &WorkerId,
        filter: &ClaimFilter,
    ) -> Result<Option<Lease>> {
        const OP: &str = "claim job";
        if filter.max_expected_cost_s.is_some_and(f64::is_nan) {
            return Err(StoreError::InvalidParameter {
                field: "max_expected_cost_s",
                value: "NaN".into(),
                reason: "must be a number of seconds",
            });
        }
        // Kinds come from a closed enum, so inlining their text is safe.
        let kind_filter = if filter.kinds.is_empty() {
            String::new()
        } else {
            let list: Vec<String> = filter
                .kinds
                .iter()
                .map(|k| format!("'{}'", k.as_str()))
                .collect();
            format!(" AND kind IN ({})", list.join(", "))
        };
        let sql = format!(
            "UPDATE jobs SET state = 'running', attempt = attempt + 1, lease_token = $1, \
             lease_expires_at_ms = $2 + $3, heartbeat_at_ms = $2, worker_id = $4, \
             updated_at_ms = $2 \
             WHERE id = (SELECT id FROM jobs WHERE state = 'ready' AND not_before_ms <= $2{kind_filter} \
                         AND ($5 IS NULL OR expected_cost_s <= $5) \
                         ORDER BY priority DESC, id LIMIT 1{skip_locked}) \
               AND state = 'ready' \
             RETURNING id, campaign_id, sea_state_id, kind, payload_json, attempt, max_attempts, \
                       lost_count, cache_key, lease_expires_at_ms",
            skip_locked = DIALECT.claim_lock_suffix,
        );
        let token = LeaseToken(uuid::Uuid::new_v4().to_string());
        let mut tx = self.begin_write(OP).await?;
        let now = self.now_ms(&mut tx).await?;
        let identity = sqlx::query("SELECT host, pid FROM workers WHERE id = $1")
            .bind(&worker.0)
            .fetch_optional(&mut *tx)
            .await
            .map_err(StoreError::db(OP))?;
        let Some(identity) = identity else {
            tx.rollback().await.map_err(StoreError::db(OP))?;
            return Err(StoreError::InvalidParameter {
                field: "worker",
                value: worker.0.clone(),
                reason: "is not registered in this store",
            });
        };
        let host: String = identity.try_get("host").map_err(StoreError::db(OP))?;
        let pid: i64 = identity.try_get("pid").map_err(StoreError::db(OP))?;
        let row = sqlx::query(&sql)
            .bind(&token.0)
            .bind(now)
            .bind(self.policy.lease_ms)
            .bind(&worker.0)
            .bind(filter.max_expected_cost_s)
            .fetch_optional(&mut *tx)
            .await
            .map_err(StoreError::db(OP))?;
        let Some(row) = row else {
            tx.rollback().await.map_err(StoreError::db(OP))?;
            return Ok(None);
        };
        let decode = || StoreError::db("decode claim");
        let job = JobId(row.try_get("id").map_err(decode())?);
        let attempt: i64 = row.try_get("attempt").map_err(decode())?;
        let lost_count: i64 = row.try_get("lost_count").map_err(decode())?;
        let kind: String = row.try_get("kind").map_err(decode())?;
        let payload: String = row.try_get("payload_json").map_err(decode())?;
        let attempt_id: i64 = sqlx::query_scalar(
            "INSERT INTO attempts (job_id, claim_number, lease_token, worker_id, host, pid, \
             started_at_ms) VALUES ($1, $2, $3, $4, $5, $6, $7) RETURNING id",
        )
        .bind(job.0)
        .bind(attempt + lost_count)
        .bind(&token.0)
        .bind(&worker.0)
        .bind(&host)
        .bind(pid)
        .bind(now)
        .fetch_one(&mut *tx)
        .await
        .map_err(StoreError::db(OP))?;
        sqlx::query("UPDATE workers SET last_seen_at_ms = $1 WHERE id = $2")
            .bind(now)
            .bind(&worker.0)
            .execute(&mut *tx)
            .await
            .map_err(StoreError::db(OP))?;
        let lease = Lease {
            job,
            campaign: CampaignId(row.try_get("campaign_id").map_err(decode())?),
            sea_state: row
                .try_get::<Option<i64>, _>("sea_state_id")
                .map_err(decode())?
                .map(SeaStateId),
            kind: kind.parse::<JobKind>()?,
            payload: parse_json("jobs.payload_json", &payload)?,
            attempt,
            max_attempts: row.try_get("max_attempts").map_err(decode())?,
            cache_key: row.try_get("cache_key").map_err(decode())?,
            token,
            expires_at_ms: row.try_get("lease_expires_at_ms").map_err(decode())?,
            attempt_id: AttemptId(attempt_id),
            worker: worker.clone(),
        };
        tx.commit().await.map_err(StoreError::db(OP))?;
        Ok(Some(lease))
    }

    pub(crate) async fn heartbeat(&self, lease: &Lease) -> Result<i64> {
        const OP: &str = "heartbeat";
        let mut tx = self.begin_write(OP).await?;
        let now = self.now_ms(&mut tx).await?;
        let expires: Option<i64> = sqlx::query_scalar(
            "UPDATE jobs SET heartbeat_at_ms = $1, lease_expires_at_ms = $1 + $2, \
             updated_at_ms = $1 \
             WHERE id = $3 AND lease_token = $4 AND state = 'running' \
             RETURNING lease_expires_at_ms",
        )
        .bind(now)
        .bind(self.policy.lease_ms)
        .bind(lease.job.0)
        .bind(&lease.token.0)
        .fetch_optional(&mut *tx)
        .await
        .map_err(StoreError::db(OP))?;
        let Some(expires) = expires else {
            tx.rollback().await.map_err(StoreError::db(OP))?;
            return Err(lease_lost(lease));
        };
        sqlx::query("UPDATE workers SET last_seen_at_ms = $1 WHERE id = $2")
            .bind(now)
            .bind(&lease.worker.0)
            .execute(&mut *tx)
            .await
            .map_err(StoreError::db(OP))?;
        tx.commit().await.map_err(StoreError::db(OP))?;
        Ok(expires)
    }

    /// Marks the leased job done if the token still matches; the caller's transaction then
    /// stores results and commits.
    pub(super) async fn finish_lease(
        &self,
        tx: &mut Tx,
        lease: &Lease,
        now: i64,
        result_text: &str,
        cached_from: Option<JobId>,
        outcome: AttemptOutcome,
    ) -> Result<()> {
        const OP: &str = "complete job";
        let updated = sqlx::query(
            "UPDATE jobs SET state = 'done', result_json = $1, result_sha256 = $2, \
             cached_from_job_id = $3, lease_token = NULL, lease_expires_at_ms = NULL, \
             error_class = NULL, error_message = NULL, updated_at_ms = $4 \
             WHERE id = $5 AND lease_token = $6 AND state = 'running'",
        )
        .bind(result_text)
        .bind(sha256_hex(result_text))
        .bind(cached_from.map(|j| j.0))
        .bind(now)
        .bind(lease.job.0)
        .bind(&lease.token.0)
        .execute(&mut **tx)
        .await
        .map_err(StoreError::db(OP))?
        .rows_affected();
        if updated == 0 {
            return Err(lease_lost(lease));
        }
        end_attempt(tx, lease, now, outcome, None).await?;
        unblock_dependents(tx, lease.job, now).await
    }

    /// Settles gated jobs whose gate is known to be closed (`jobs`, each with its result): in
    /// one transaction, every listed job still `ready` or `blocked` becomes `done` with its
    /// result and no rows, and its dependents whose dependencies are all done become ready.
    /// Jobs that are running, done, failed or cancelled are left alone (a running one reaches
    /// the same answer itself). Returns the jobs settled.
    pub(crate) async fn settle(&self, jobs: &[(JobId, serde_json::Value)]) -> Result<Vec<JobId>> {
        const OP: &str = "settle gated jobs";
        if jobs.is_empty() {
            return Ok(Vec::new());
        }
        // in id order, as completions lock rows, so concurrent writers never deadlock
        let mut jobs: Vec<&(JobId, serde_json::Value)> = jobs.iter().collect();
        jobs.sort_by_key(|j| j.0);
        let mut texts = Vec::with_capacity(jobs.len());
        for (_, result) in &jobs {
            texts.push(json_text("jobs.result_json", result)?);
        }
        let mut tx = self.begin_write(OP).await?;
        let now = self.now_ms(&mut tx).await?;
        let mut settled = Vec::new();
        for ((job, _), text) in jobs.iter().copied().zip(&texts) {
            let updated = sqlx::query(
                "UPDATE jobs SET state = 'done', result_json = $1, result_sha256 = $2, \
                 lease_token = NULL, lease_expires_at_ms = NULL, error_class = NULL, \
                 error_message = NULL, updated_at_ms = $3 \
                 WHERE id = $4 AND state IN ('ready', 'blocked')",
            )
            .bind(text)
            .bind(sha256_hex(text))
            .bind(now)
            .bind(job.0)
            .execute(&mut *tx)
            .await
            .map_err(StoreError::db(OP))?
            .rows_affected();
            if updated > 0 {
                settled.push(*job);
            }
        }
        for job in &settled {
            unblock_dependents(&mut tx, *job, now).await?;
        }
        tx.commit().await.map_err(StoreError::db(OP))?;
        Ok(settled)
    }

    pub(crate) async fn complete(&self, lease: &Lease, results: &JobResults) -> Result<()> {
        const OP: &str = "complete job";
        #[cfg(feature = "test-support")]
        if lease.kind == JobKind::Test {
            let has_rows = !(results.hot_spots.is_empty()
                && results.contacts.is_empty()
                && results.damage_inputs.is_empty()
                && results.class_damage_inputs.is_empty()
                && results.artifacts.is_empty());
            if has_rows {
                return Err(StoreError::TestKindResults(lease.job));
            }
        }
        let result_text = json_text("jobs.result_json", &results.result)?;
        let mut tx = self.begin_write(OP).await?;
        let now = self.now_ms(&mut tx).await?;
        if let Err(err) = self
            .finish_lease(
                &mut tx,
                lease,
                now,
                &result_text,
                None,
                AttemptOutcome::Done,
            )
            .await
        {
            tx.rollback().await.map_err(StoreError::db(OP))?;
            return Err(err);
        }
        for hot_spot in &results.hot_spots {
            sqlx::query(
                "INSERT INTO hot_spot_summaries (job_id, hot_spot_index, summary_json) \
                 VALUES ($1, $2, $3)",
            )
            .bind(lease.job.0)
            .bind(hot_spot.hot_spot_index)
            .bind(json_text(
                "hot_spot_summaries.summary_json",
                &hot_spot.summary,
            )?)
            .execute(&mut *tx)
            .await
            .map_err(StoreError::db(OP))?;
        }
        for contact in &results.contacts {
            sqlx::query(
                "INSERT INTO contact_statistics (job_id, hot_spot_index, contact_index, \
                 layer_interface, angular_position_rad, statistics_json) \
                 VALUES ($1, $2, $3, $4, $5, $6)",
            )
            .bind(lease.job.0)
            .bind(contact.hot_spot_index)
            .bind(contact.contact_index)
            .bind(contact.layer_interface)
            .bind(contact.angular_position_rad)
            .bind(json_text(
                "contact_statistics.statistics_json",
                &contact.statistics,
            )?)
            .execute(&mut *tx)
            .await
            .map_err(StoreError::db(OP))?;
        }
        for damage in &results.damage_inputs {
            sqlx::query(
                "INSERT INTO damage_inputs (job_id, hot_spot_index, measure, seed_index, \
                 effective_duration_s, damage, details_json) \
                 VALUES ($1, $2, $3, $4, $5, $6, $7)",
            )
            .bind(lease.job.0)
            .bind(damage.hot_spot_index)
            .bind(&damage.measure)
            .bind(damage.seed_index)
            .bind(damage.effective_duration_s)
            .bind(damage.damage)
            .bind(json_text("damage_inputs.details_json", &damage.details)?)
            .execute(&mut *tx)
            .await
            .map_err(StoreError::db(OP))?;
        }
        insert_class_damage_inputs(&mut tx, lease.job, &results.class_damage_inputs).await?;
        for artifact in &results.artifacts {
            sqlx::query(
                "INSERT INTO artifacts (sha256, size_bytes, path, created_at_ms) \
                 VALUES ($1, $2, $3, $4) ON CONFLICT (sha256) DO NOTHING",
            )
            .bind(&artifact.sha256)
            .bind(artifact.size_bytes)
            .bind(&artifact.path)
            .bind(now)
            .execute(&mut *tx)
            .await
            .map_err(StoreError::db(OP))?;
            sqlx::query("INSERT INTO job_artifacts (job_id, role, sha256) VALUES ($1, $2, $3)")
                .bind(lease.job.0)
                .bind(artifact.role.as_str().into_owned())
                .bind(&artifact.sha256)
                .execute(&mut *tx)
                .await
                .map_err(StoreError::db(OP))?;
        }
        tx.commit().await.map_err(StoreError::db(OP))?;
        Ok(())
    }

    pub(crate) async fn lookup_cache(&self, cache_key: &str) -> Result<Option<JobId>> {
        let id: Option<i64> = sqlx::query_scalar(
            "SELECT id FROM jobs WHERE cache_key = $1 AND state = 'done' ORDER BY id LIMIT 1",
        )
        .bind(cache_key)
        .fetch_optional(&self.pool)
        .await
        .map_err(StoreError::db("look up cache"))?;
        Ok(id.map(JobId))
    }

    pub(crate) async fn complete_from_cache(&self, lease: &Lease, source: JobId) -> Result<()> {
        const OP: &str = "complete job from cache";
        let mut tx = self.begin_write(OP).await?;
        let now = self.now_ms(&mut tx).await?;
        let row = sqlx::query("SELECT state, cache_key, result_json FROM jobs WHERE id = $1")
            .bind(source.0)
            .fetch_optional(&mut *tx)
            .await
            .map_err(StoreError::db(OP))?;
        let Some(row) = row else {
            tx.rollback().await.map_err(StoreError::db(OP))?;
            return Err(StoreError::UnknownJob(source));
        };
        let state: JobState = row
            .try_get::<String, _>("state")
            .map_err(StoreError::db(OP))?
            .parse()?;
        let key: Option<String> = row.try_get("cache_key").map_err(StoreError::db(OP))?;
        let result: Option<String> = row.try_get("result_json").map_err(StoreError::db(OP))?;
        let (JobState::Done, Some(key), Some(result)) = (state, key, result) else {
            tx.rollback().await.map_err(StoreError::db(OP))?;
            return Err(StoreError::WrongState {
                job: source,
                state,
                expected: "done",
            });
        };
        if lease.cache_key.as_deref() != Some(key.as_str()) {
            tx.rollback().await.map_err(StoreError::db(OP))?;
            return Err(StoreError::InvalidParameter {
                field: "cache source",
                value: source.to_string(),
                reason: "has a different cache key than the leased job",
            });
        }
        if let Err(err) = self
            .finish_lease(
                &mut tx,
                lease,
                now,
                &result,
                Some(source),
                AttemptOutcome::Cached,
            )
            .await
        {
            tx.rollback().await.map_err(StoreError::db(OP))?;
            return Err(err);
        }
        for copy in [
            "INSERT INTO hot_spot_summaries (job_id, hot_spot_index, summary_json) \
             SELECT $1, hot_spot_index, summary_json FROM hot_spot_summaries WHERE job_id = $2",
            "INSERT INTO contact_statistics (job_id, hot_spot_index, contact_index, \
             layer_interface, angular_position_rad, statistics_json) \
             SELECT $1, hot_spot_index, contact_index, layer_interface, angular_position_rad, \
             statistics_json FROM contact_statistics WHERE job_id = $2",
            "INSERT INTO damage_inputs (job_id, hot_spot_index, measure, seed_index, \
             effective_duration_s, damage, details_json) \
             SELECT $1, hot_spot_index, measure, seed_index, effective_duration_s, damage, \
             details_json FROM damage_inputs WHERE job_id = $2",
            COPY_CLASS_DAMAGE_INPUTS,
            "INSERT INTO job_artifacts (job_id, role, sha256) \
             SELECT $1, role, sha256 FROM job_artifacts WHERE job_id = $2",
        ] {
            sqlx::query(copy)
                .bind(lease.job.0)
                .bind(source.0)
                .execute(&mut *tx)
                .await
                .map_err(StoreError::db(OP))?;
        }
        tx.commit().await.map_err(StoreError::db(OP))?;
        Ok(())
    }
}
