// Backend-independent queue operations, compiled once per backend by `include!` from
// `sqlite.rs` and `postgres.rs`, which define `Db` (the sqlx database) and `DIALECT`.
//
// SQLite and PostgreSQL both accept `$n` placeholders, `RETURNING`, `WITH RECURSIVE … UPDATE`,
// partial indexes and `||`, so the SQL text is shared; what differs (how a write transaction
// begins, `FOR UPDATE SKIP LOCKED`, the server clock) is in `DIALECT`. Writing this once as
// generic code over `sqlx::Database` would need a higher-ranked executor bound on every
// function; textual inclusion keeps each backend's code concrete and identical.

use serde_json::Value;
use sha2::{Digest, Sha256};
use sqlx::{Pool, Row, Transaction};

use super::clock::{system_now_ms, Clock};
use super::error::StoreError;
use super::model::{
    AttemptRecord, CampaignProgress, CancelReport, ClaimFilter, ContactStatistics, DamageInput,
    FailureDisposition, FailureKind, HotSpotSummary, JobArtifact, JobFailure, JobRecord,
    JobResults, Lease, LifetimeDamage, NewCampaign, NewSeaState, PlannedJob, SweepReport,
    WorkerInfo,
};
use super::policy::QueuePolicy;
use super::types::{
    AttemptId, AttemptOutcome, CampaignId, JobId, JobKind, JobState, LeaseToken, SeaStateId,
    WorkerId,
};

type Result<T> = std::result::Result<T, StoreError>;

/// Rows per multi-row insert: 13 parameters each stays below SQLite's 32 766 and
/// PostgreSQL's 65 535 bound parameters per statement.
const PLAN_BATCH_ROWS: usize = 1_000;
type Tx = Transaction<'static, Db>;

/// Queue operations on one backend's pool.
#[derive(Debug, Clone)]
pub(crate) struct Queue {
    pool: Pool<Db>,
    clock: Clock,
    policy: QueuePolicy,
}

fn json_text(field: &'static str, value: &Value) -> Result<String> {
    serde_json::to_string(value).map_err(|source| StoreError::Json { field, source })
}

fn parse_json(field: &'static str, text: &str) -> Result<Value> {
    serde_json::from_str(text).map_err(|source| StoreError::Json { field, source })
}

fn sha256_hex(text: &str) -> String {
    hex::encode(Sha256::digest(text.as_bytes()))
}

const JOB_COLUMNS: &str = "id, campaign_id, sea_state_id, kind, state, payload_json, attempt, \
     max_attempts, lost_count, lease_token, lease_expires_at_ms, worker_id, priority, cache_key, \
     result_json, result_sha256, cached_from_job_id, error_class, error_message, not_before_ms";

fn job_from_row(row: &<Db as sqlx::Database>::Row) -> Result<JobRecord> {
    let kind: String = row.try_get("kind").map_err(StoreError::db("decode job"))?;
    let state: String = row.try_get("state").map_err(StoreError::db("decode job"))?;
    let payload: String = row
        .try_get("payload_json")
        .map_err(StoreError::db("decode job"))?;
    let result: Option<String> = row
        .try_get("result_json")
        .map_err(StoreError::db("decode job"))?;
    let record = JobRecord {
        id: JobId(row.try_get("id").map_err(StoreError::db("decode job"))?),
        campaign: CampaignId(
            row.try_get("campaign_id")
                .map_err(StoreError::db("decode job"))?,
        ),
        sea_state: row
            .try_get::<Option<i64>, _>("sea_state_id")
            .map_err(StoreError::db("decode job"))?
            .map(SeaStateId),
        kind: kind.parse()?,
        state: state.parse()?,
        payload: parse_json("jobs.payload_json", &payload)?,
        attempt: row
            .try_get("attempt")
            .map_err(StoreError::db("decode job"))?,
        max_attempts: row
            .try_get("max_attempts")
            .map_err(StoreError::db("decode job"))?,
        lost_count: row
            .try_get("lost_count")
            .map_err(StoreError::db("decode job"))?,
        lease_token: row
            .try_get("lease_token")
            .map_err(StoreError::db("decode job"))?,
        lease_expires_at_ms: row
            .try_get("lease_expires_at_ms")
            .map_err(StoreError::db("decode job"))?,
        worker: row
            .try_get::<Option<String>, _>("worker_id")
            .map_err(StoreError::db("decode job"))?
            .map(WorkerId),
        priority: row
            .try_get("priority")
            .map_err(StoreError::db("decode job"))?,
        cache_key: row
            .try_get("cache_key")
            .map_err(StoreError::db("decode job"))?,
        result: result
            .as_deref()
            .map(|t| parse_json("jobs.result_json", t))
            .transpose()?,
        result_sha256: row
            .try_get("result_sha256")
            .map_err(StoreError::db("decode job"))?,
        cached_from: row
            .try_get::<Option<i64>, _>("cached_from_job_id")
            .map_err(StoreError::db("decode job"))?
            .map(JobId),
        error_class: row
            .try_get("error_class")
            .map_err(StoreError::db("decode job"))?,
        error_message: row
            .try_get("error_message")
            .map_err(StoreError::db("decode job"))?,
        not_before_ms: row
            .try_get("not_before_ms")
            .map_err(StoreError::db("decode job"))?,
    };
    Ok(record)
}

impl Queue {
    pub(crate) fn new(pool: Pool<Db>, clock: Clock, policy: QueuePolicy) -> Self {
        Self {
            pool,
            clock,
            policy,
        }
    }

    pub(crate) fn pool(&self) -> &Pool<Db> {
        &self.pool
    }

    pub(crate) fn policy(&self) -> &QueuePolicy {
        &self.policy
    }

    pub(crate) async fn close(&self) {
        self.pool.close().await;
    }

    async fn now_ms(&self, conn: &mut <Db as sqlx::Database>::Connection) -> Result<i64> {
        match &self.clock {
            Clock::System => Ok(system_now_ms()),
            Clock::Manual(clock) => Ok(clock.now_ms()),
            Clock::Database => sqlx::query_scalar::<_, i64>(DIALECT.now_ms_sql)
                .fetch_one(conn)
                .await
                .map_err(StoreError::db("read database clock")),
        }
    }

    async fn begin_write(&self, operation: &'static str) -> Result<Tx> {
        self.pool
            .begin_with(DIALECT.begin_write)
            .await
            .map_err(StoreError::db(operation))
    }

    pub(crate) async fn create_campaign(&self, campaign: &NewCampaign) -> Result<CampaignId> {
        const OP: &str = "create campaign";
        let spec = json_text("campaigns.spec_json", &campaign.spec)?;
        let mut tx = self.begin_write(OP).await?;
        let now = self.now_ms(&mut tx).await?;
        let existing: Option<i64> = sqlx::query_scalar("SELECT id FROM campaigns WHERE name = $1")
            .bind(&campaign.name)
            .fetch_optional(&mut *tx)
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
        .fetch_one(&mut *tx)
        .await
        .map_err(StoreError::db(OP))?;
        tx.commit().await.map_err(StoreError::db(OP))?;
        Ok(CampaignId(id))
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
        let mut ids = Vec::with_capacity(sea_states.len());
        for sea_state in sea_states {
            let seeds =
                serde_json::to_string(&sea_state.seeds).map_err(|source| StoreError::Json {
                    field: "sea_states.seeds_json",
                    source,
                })?;
            let id: i64 = sqlx::query_scalar(
                "INSERT INTO sea_states \
                 (campaign_id, sea_state_index, hs_m, tp_s, occurrence_fraction, seeds_json) \
                 VALUES ($1, $2, $3, $4, $5, $6) RETURNING id",
            )
            .bind(campaign.0)
            .bind(sea_state.index)
            .bind(sea_state.hs_m)
            .bind(sea_state.tp_s)
            .bind(sea_state.occurrence_fraction)
            .bind(seeds)
            .fetch_one(&mut *tx)
            .await
            .map_err(StoreError::db(OP))?;
            ids.push(SeaStateId(id));
        }
        tx.commit().await.map_err(StoreError::db(OP))?;
        Ok(ids)
    }

    pub(crate) async fn insert_plan(
        &self,
        campaign: CampaignId,
        jobs: &[PlannedJob],
    ) -> Result<Vec<JobId>> {
        const OP: &str = "insert plan";
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
        let mut tx = self.begin_write(OP).await?;
        let now = self.now_ms(&mut tx).await?;
        // Ids are reserved first so that the rows and their dependencies can be written in
        // multi-row statements (one round trip per batch instead of per row).
        let count = i64::try_from(jobs.len()).unwrap_or(i64::MAX);
        let ids: Vec<JobId> = sqlx::query_scalar::<_, i64>(DIALECT.reserve_job_ids_sql)
            .bind(count)
            .fetch_all(&mut *tx)
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
            .zip(&payloads)
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
                .execute(&mut *tx)
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
                .execute(&mut *tx)
                .await
                .map_err(StoreError::db(OP))?;
        }
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

    pub(crate) async fn claim(
        &self,
        worker: &WorkerId,
        filter: &ClaimFilter,
    ) -> Result<Option<Lease>> {
        const OP: &str = "claim job";
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
    async fn finish_lease(
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
                .bind(lease.job.0)
                .fetch_all(&mut **tx)
                .await
                .map_err(StoreError::db(OP))?;
        }
        // Dependents whose every dependency is now done become claimable.
        sqlx::query(
            "UPDATE jobs SET state = 'ready', updated_at_ms = $1 \
             WHERE state = 'blocked' \
               AND id IN (SELECT job_id FROM job_dependencies WHERE depends_on = $2) \
               AND NOT EXISTS (SELECT 1 FROM job_dependencies d JOIN jobs p ON p.id = d.depends_on \
                               WHERE d.job_id = jobs.id AND p.state <> 'done')",
        )
        .bind(now)
        .bind(lease.job.0)
        .execute(&mut **tx)
        .await
        .map_err(StoreError::db(OP))?;
        Ok(())
    }

    pub(crate) async fn complete(&self, lease: &Lease, results: &JobResults) -> Result<()> {
        const OP: &str = "complete job";
        let has_rows = !(results.hot_spots.is_empty()
            && results.contacts.is_empty()
            && results.damage_inputs.is_empty()
            && results.artifacts.is_empty());
        if lease.kind == JobKind::Test && has_rows {
            return Err(StoreError::TestKindResults(lease.job));
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
                .bind(&artifact.role)
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
        .bind(&failure.error_class)
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

    pub(crate) async fn cancel_campaign(&self, campaign: CampaignId) -> Result<CancelReport> {
        const OP: &str = "cancel campaign";
        let mut tx = self.begin_write(OP).await?;
        let now = self.now_ms(&mut tx).await?;
        let found = sqlx::query("UPDATE campaigns SET state = 'cancelled' WHERE id = $1")
            .bind(campaign.0)
            .execute(&mut *tx)
            .await
            .map_err(StoreError::db(OP))?
            .rows_affected();
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
                role: row.try_get("role").map_err(db(OP))?,
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
            "SELECT hot_spot_index, measure, annual_damage, occurrence_covered, sea_states \
             FROM lifetime_damage WHERE campaign_id = $1 ORDER BY hot_spot_index, measure",
        )
        .bind(campaign.0)
        .fetch_all(&self.pool)
        .await
        .map_err(StoreError::db(OP))?;
        rows.iter()
            .map(|row| {
                Ok(LifetimeDamage {
                    hot_spot_index: row.try_get("hot_spot_index").map_err(StoreError::db(OP))?,
                    measure: row.try_get("measure").map_err(StoreError::db(OP))?,
                    annual_damage: row.try_get("annual_damage").map_err(StoreError::db(OP))?,
                    occurrence_covered: row
                        .try_get("occurrence_covered")
                        .map_err(StoreError::db(OP))?,
                    sea_states: row.try_get("sea_states").map_err(StoreError::db(OP))?,
                })
            })
            .collect()
    }
}

fn lease_lost(lease: &Lease) -> StoreError {
    StoreError::LeaseLost {
        job: lease.job,
        token: lease.token.0.clone(),
    }
}

async fn end_attempt(
    tx: &mut Tx,
    lease: &Lease,
    now: i64,
    outcome: AttemptOutcome,
    message: Option<&str>,
) -> Result<()> {
    sqlx::query(
        "UPDATE attempts SET ended_at_ms = $1, outcome = $2, error_message = $3 WHERE id = $4",
    )
    .bind(now)
    .bind(outcome.as_str())
    .bind(message)
    .bind(lease.attempt_id.0)
    .execute(&mut **tx)
    .await
    .map_err(StoreError::db("record attempt"))?;
    Ok(())
}

/// Fails every blocked job downstream of `job`; returns how many.
async fn fail_dependents(tx: &mut Tx, job: JobId, now: i64) -> Result<u64> {
    let failed = sqlx::query(
        "WITH RECURSIVE downstream (id) AS ( \
             SELECT job_id FROM job_dependencies WHERE depends_on = $1 \
             UNION \
             SELECT d.job_id FROM job_dependencies d JOIN downstream s ON d.depends_on = s.id) \
         UPDATE jobs SET state = 'failed', error_class = 'upstream_failed', \
             error_message = 'upstream job ' || $1 || ' failed', updated_at_ms = $2 \
         WHERE state = 'blocked' AND id IN (SELECT id FROM downstream)",
    )
    .bind(job.0)
    .bind(now)
    .execute(&mut **tx)
    .await
    .map_err(StoreError::db("fail dependent jobs"))?
    .rows_affected();
    Ok(failed)
}
