//! The job queue's operations, written once for both backends.
//!
//! This module is mounted twice, as `sqlite::queue` and `postgres::queue`; each parent defines
//! `Db` (the sqlx database) and `DIALECT`. SQLite and PostgreSQL both accept `$n` placeholders,
//! `RETURNING`, `WITH RECURSIVE … UPDATE`, partial indexes and `||`, so the SQL text is shared;
//! what differs (how a write transaction begins, `FOR UPDATE SKIP LOCKED`, the server clock) is
//! in `DIALECT`. Writing this as generic code over `sqlx::Database` would need a higher-ranked
//! executor bound on every function; mounting the same files per backend keeps each backend's
//! code concrete and identical.
//!
//! - [`plan`]: campaigns, sea states, jobs with their dependencies, workers;
//! - [`campaign`]: a whole plan in one transaction, campaign rows;
//! - [`lease`]: claim, heartbeat, completion (fresh or from the cache), settling of gated
//!   jobs whose sea state is not selected;
//! - [`recovery`]: failures, expired leases and cancellation;
//! - [`read`]: jobs, attempts, results, progress and lifetime views;
//! - [`results`]: per-class damage rows and the result views.

mod campaign;
mod lease;
mod plan;
mod read;
mod recovery;
mod results;

use super::{Db, DIALECT};
use serde_json::Value;
use sha2::{Digest, Sha256};
use sqlx::{Pool, Row, Transaction};

use crate::clock::{system_now_ms, Clock};
use crate::error::StoreError;
use crate::model::{JobRecord, Lease};
use crate::policy::QueuePolicy;
use crate::types::{AttemptOutcome, CampaignId, JobId, SeaStateId, WorkerId};

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
            .try_get::<Option<String>, _>("error_class")
            .map_err(StoreError::db("decode job"))?
            .map(|t| t.parse())
            .transpose()?,
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
