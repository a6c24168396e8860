//! [`Store`]: the campaign store and job queue, over SQLite or PostgreSQL.
//!
//! The backend is chosen by the location: `postgres://…` / `postgresql://…` selects PostgreSQL,
//! anything else (`sqlite://path`, `sqlite:path` or a plain path) an SQLite file. Only
//! [`Store::open`] creates a store (with its parent directories), and only where nothing is;
//! [`Store::open_existing`] and [`Store::open_if_present`] create nothing, and every opening
//! refuses an existing file that is not a moorfret store (empty, another program's database)
//! before writing to it. Opening checks the schema version first: a database written by a
//! newer moorfret is refused untouched; an older one is migrated.
//!
//! Job protocol (ARCHITECTURE.md, "Data flow of a campaign"): [`Store::claim`] leases the
//! highest-priority ready job in one atomic statement; the worker renews the lease with
//! [`Store::heartbeat`] and ends it with [`Store::complete`], [`Store::complete_from_cache`] or
//! [`Store::fail`], each guarded by the lease token (a stale token gets [`StoreError::LeaseLost`]
//! and changes nothing). [`Store::sweep_expired`] returns jobs whose lease ran out to the queue.
//! Validity is decided by the token alone: a lease past its end that no sweep has taken back
//! yet may still be renewed or completed, since no other worker can hold the job.

use std::path::PathBuf;

use super::clock::Clock;
use super::error::StoreError;
use super::model::{
    AttemptRecord, CampaignProgress, CampaignRecord, CancelReport, ClaimFilter, FailureDisposition,
    JobFailure, JobRecord, JobResults, Lease, LifetimeDamage, NewCampaign, NewSeaState, PlannedJob,
    SweepReport, WorkerInfo,
};
use super::policy::QueuePolicy;
use super::results::{
    ClassDamageInput, ContactRow, FidelityComparison, LifetimeClassDamage, SeaStateClassDamage,
    SeaStateDamage, SeaStateStatus,
};
use super::types::{AttemptId, AttemptOutcome, CampaignId, JobId, JobKind, SeaStateId, WorkerId};
use super::{postgres, sqlite};

/// How to open a store.
#[derive(Debug, Clone)]
pub struct StoreOptions {
    /// Where "now" comes from.
    pub clock: Clock,
    /// Lease, lost-job and backoff settings.
    pub policy: QueuePolicy,
    /// Connections in this process's pool.
    pub max_connections: u32,
    /// PostgreSQL schema holding the store (created if missing); ignored for SQLite.
    pub postgres_schema: Option<String>,
}

impl Default for StoreOptions {
    fn default() -> Self {
        Self {
            clock: Clock::System,
            policy: QueuePolicy::default(),
            max_connections: 4,
            postgres_schema: None,
        }
    }
}

/// Which database a store uses.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum StoreLocation {
    /// An SQLite file.
    Sqlite(PathBuf),
    /// A PostgreSQL URL.
    Postgres(String),
}

impl StoreLocation {
    /// Reads a location: `postgres://…`, `postgresql://…`, `sqlite://path`, `sqlite:path` or a
    /// plain path.
    pub fn parse(location: &str) -> Result<Self, StoreError> {
        if let Some((scheme, _)) = location.split_once("://") {
            match scheme.to_ascii_lowercase().as_str() {
                "postgres" | "postgresql" => {
                    return Ok(StoreLocation::Postgres(location.to_owned()))
                }
                "sqlite" => {}
                _ => {
                    return Err(StoreError::InvalidLocation {
                        location: location.to_owned(),
                        reason: format!(
                            "unknown scheme `{scheme}`: give an SQLite file path, \
                             `sqlite://PATH` or `postgres://…`"
                        ),
                    })
                }
            }
        }
        let path = location
            .strip_prefix("sqlite://")
            .or_else(|| location.strip_prefix("sqlite:"))
            .unwrap_or(location);
        let path = path.split('?').next().unwrap_or(path);
        if path.is_empty() || path == ":memory:" {
            return Err(StoreError::InvalidLocation {
                location: location.to_owned(),
                reason: "a store needs a file path (workers share it)".into(),
            });
        }
        Ok(StoreLocation::Sqlite(PathBuf::from(path)))
    }

    /// Refuses an SQLite location whose file does not exist: commands that read or resume a
    /// campaign never create a store (a mistyped `--db` would otherwise leave an empty one).
    pub fn require_existing(&self) -> Result<(), StoreError> {
        match self {
            StoreLocation::Sqlite(path) if !path.exists() => Err(StoreError::InvalidLocation {
                location: path.display().to_string(),
                reason: "no such database file (`campaign launch` creates a store)".into(),
            }),
            _ => Ok(()),
        }
    }
}

#[derive(Debug, Clone)]
enum Backend {
    Sqlite(sqlite::Queue),
    Postgres(postgres::Queue, Option<String>),
}

/// Handle to a campaign store; cheap to clone (clones share the pool).
#[derive(Debug, Clone)]
pub struct Store {
    backend: Backend,
    location: StoreLocation,
}

macro_rules! dispatch {
    ($self:ident, $queue:ident => $call:expr) => {
        match &$self.backend {
            Backend::Sqlite($queue) => $call,
            Backend::Postgres($queue, _) => $call,
        }
    };
}

impl Store {
    /// Opens the moorfret store at `location` (migrating an older one), or creates one where
    /// nothing is: no file at an SQLite path (its missing directories are created), no
    /// moorfret tables in a PostgreSQL schema. An existing file that is not a moorfret store
    /// (an empty file, another program's database) is refused untouched.
    pub async fn open(location: &str, options: StoreOptions) -> Result<Store, StoreError> {
        if let Some(store) = Self::open_if_present(location, options.clone()).await? {
            return Ok(store);
        }
        let (policy, location) = Self::check(location, &options)?;
        let backend = match &location {
            StoreLocation::Sqlite(path) => {
                let pool = sqlite::create(path, options.max_connections).await?;
                Self::prepared_sqlite(pool, &options, policy).await?
            }
            StoreLocation::Postgres(url) => {
                let schema = options.postgres_schema.as_deref();
                let pool = postgres::connect(url, schema, options.max_connections).await?;
                Self::prepared_postgres(pool, &options, policy).await?
            }
        };
        Ok(Store { backend, location })
    }

    /// Opens the moorfret store at `location` (migrating an older one); refuses anything else
    /// (no file, an empty file, another program's database, a PostgreSQL schema without
    /// moorfret's tables) without creating or writing anything.
    pub async fn open_existing(location: &str, options: StoreOptions) -> Result<Store, StoreError> {
        let parsed = StoreLocation::parse(location)?;
        parsed.require_existing()?;
        Self::open_if_present(location, options)
            .await?
            .ok_or_else(|| StoreError::InvalidLocation {
                location: location.to_owned(),
                reason: "no moorfret store there (`campaign launch` creates a store)".into(),
            })
    }

    /// The moorfret store at `location`, opened (and migrated if older), or `None` where
    /// nothing is; anything else at an SQLite path is refused. Creates and writes nothing
    /// unless a moorfret store is there.
    pub async fn open_if_present(
        location: &str,
        options: StoreOptions,
    ) -> Result<Option<Store>, StoreError> {
        let (policy, location) = Self::check(location, &options)?;
        let backend = match &location {
            StoreLocation::Sqlite(path) => {
                match sqlite::open_if_present(path, options.max_connections).await? {
                    Some(pool) => Self::prepared_sqlite(pool, &options, policy).await?,
                    None => return Ok(None),
                }
            }
            StoreLocation::Postgres(url) => {
                let schema = options.postgres_schema.as_deref();
                match postgres::open_if_present(url, schema, options.max_connections).await? {
                    Some(pool) => Self::prepared_postgres(pool, &options, policy).await?,
                    None => return Ok(None),
                }
            }
        };
        Ok(Some(Store { backend, location }))
    }

    fn check(
        location: &str,
        options: &StoreOptions,
    ) -> Result<(QueuePolicy, StoreLocation), StoreError> {
        let policy = options.policy.clone().validated()?;
        if options.max_connections == 0 {
            return Err(StoreError::InvalidParameter {
                field: "max_connections",
                value: "0".into(),
                reason: "must be >= 1",
            });
        }
        Ok((policy, StoreLocation::parse(location)?))
    }

    async fn prepared_sqlite(
        pool: sqlx::Pool<sqlx::Sqlite>,
        options: &StoreOptions,
        policy: QueuePolicy,
    ) -> Result<Backend, StoreError> {
        if let Err(err) = sqlite::prepare_schema(&pool).await {
            pool.close().await;
            return Err(err);
        }
        Ok(Backend::Sqlite(sqlite::Queue::new(
            pool,
            options.clock.clone(),
            policy,
        )))
    }

    async fn prepared_postgres(
        pool: sqlx::Pool<sqlx::Postgres>,
        options: &StoreOptions,
        policy: QueuePolicy,
    ) -> Result<Backend, StoreError> {
        if let Err(err) = postgres::prepare_schema(&pool).await {
            pool.close().await;
            return Err(err);
        }
        Ok(Backend::Postgres(
            postgres::Queue::new(pool, options.clock.clone(), policy),
            options.postgres_schema.clone(),
        ))
    }

    /// Where this store lives.
    pub fn location(&self) -> &StoreLocation {
        &self.location
    }

    /// The queue policy in force.
    pub fn policy(&self) -> &QueuePolicy {
        dispatch!(self, q => q.policy())
    }

    /// Newest schema version this binary knows.
    pub fn supported_schema_version(&self) -> i64 {
        match &self.backend {
            Backend::Sqlite(_) => sqlite::supported_version(),
            Backend::Postgres(..) => postgres::supported_version(),
        }
    }

    /// Schema version recorded in the database.
    pub async fn schema_version(&self) -> Result<i64, StoreError> {
        match &self.backend {
            Backend::Sqlite(q) => sqlite::found_version(q.pool()).await,
            Backend::Postgres(q, _) => postgres::found_version(q.pool()).await,
        }
    }

    /// Closes every connection of this handle's pool.
    pub async fn close(&self) {
        dispatch!(self, q => q.close().await)
    }

    /// Drops the PostgreSQL schema this store lives in, then closes the pool (for throw-away
    /// test stores). Does nothing but close for SQLite or the default schema.
    pub async fn drop_postgres_schema(self) -> Result<(), StoreError> {
        if let Backend::Postgres(q, Some(schema)) = &self.backend {
            postgres::drop_schema(q.pool(), schema).await?;
        }
        self.close().await;
        Ok(())
    }

    /// Creates a campaign; its name must be new.
    pub async fn create_campaign(&self, campaign: &NewCampaign) -> Result<CampaignId, StoreError> {
        dispatch!(self, q => q.create_campaign(campaign).await)
    }

    /// Creates a campaign with its sea states and jobs in one transaction: an interrupted
    /// launch leaves nothing or the whole plan. `make_jobs` gets the sea-state ids in order.
    pub async fn create_planned_campaign(
        &self,
        campaign: &NewCampaign,
        sea_states: &[NewSeaState],
        make_jobs: impl FnOnce(&[SeaStateId]) -> Vec<PlannedJob>,
    ) -> Result<(CampaignId, Vec<JobId>), StoreError> {
        dispatch!(self, q => q.create_planned_campaign(campaign, sea_states, make_jobs).await)
    }

    /// Every campaign, by id.
    pub async fn campaigns(&self) -> Result<Vec<CampaignRecord>, StoreError> {
        dispatch!(self, q => q.campaigns().await)
    }

    /// Finds a campaign by name.
    pub async fn campaign_by_name(&self, name: &str) -> Result<Option<CampaignId>, StoreError> {
        dispatch!(self, q => q.campaign_by_name(name).await)
    }

    /// Adds the planned sea states of a campaign, in one transaction.
    pub async fn insert_sea_states(
        &self,
        campaign: CampaignId,
        sea_states: &[NewSeaState],
    ) -> Result<Vec<SeaStateId>, StoreError> {
        dispatch!(self, q => q.insert_sea_states(campaign, sea_states).await)
    }

    /// Adds a plan of jobs in one transaction; jobs without dependencies start ready, the
    /// others blocked. Returns the ids in plan order.
    pub async fn insert_plan(
        &self,
        campaign: CampaignId,
        jobs: &[PlannedJob],
    ) -> Result<Vec<JobId>, StoreError> {
        dispatch!(self, q => q.insert_plan(campaign, jobs).await)
    }

    /// Registers a worker process; its id goes with every claim.
    pub async fn register_worker(&self, info: &WorkerInfo) -> Result<WorkerId, StoreError> {
        dispatch!(self, q => q.register_worker(info).await)
    }

    /// Leases the ready job of highest priority (then lowest id) whose backoff has passed and
    /// that passes `filter`, or returns `None` when there is none.
    pub async fn claim(
        &self,
        worker: &WorkerId,
        filter: &ClaimFilter,
    ) -> Result<Option<Lease>, StoreError> {
        dispatch!(self, q => q.claim(worker, filter).await)
    }

    /// Renews the lease; returns its new end (ms since the epoch) or
    /// [`StoreError::LeaseLost`].
    pub async fn heartbeat(&self, lease: &Lease) -> Result<i64, StoreError> {
        dispatch!(self, q => q.heartbeat(lease).await)
    }

    /// Stores the results and marks the job done, unblocking dependents whose dependencies are
    /// all done, in one transaction guarded by the lease token.
    pub async fn complete(&self, lease: &Lease, results: &JobResults) -> Result<(), StoreError> {
        dispatch!(self, q => q.complete(lease, results).await)
    }

    /// Settles gated jobs whose gate is known to be closed, each with its result, in one
    /// transaction: those still ready or blocked become done with no rows, and their
    /// dependents are unblocked. Returns the jobs settled (running or finished ones are left
    /// alone).
    pub async fn settle(
        &self,
        jobs: &[(JobId, serde_json::Value)],
    ) -> Result<Vec<JobId>, StoreError> {
        dispatch!(self, q => q.settle(jobs).await)
    }

    /// Running jobs held by worker processes registered on `host`, with each worker's pid.
    pub async fn running_on_host(&self, host: &str) -> Result<Vec<(JobId, i64)>, StoreError> {
        dispatch!(self, q => q.running_on_host(host).await)
    }

    /// Ends now the leases held by the worker processes `pids` of `host`, which are known to be
    /// dead (their parent saw them exit, or the host has no such process): their jobs are
    /// swept as expired leases at once instead of when the leases run out.
    pub async fn expire_leases_of(
        &self,
        host: &str,
        pids: &[i64],
    ) -> Result<SweepReport, StoreError> {
        dispatch!(self, q => q.expire_leases_of(host, pids).await)
    }

    /// A done job (of any campaign) with this cache key, whose results may be reused.
    pub async fn lookup_cache(&self, cache_key: &str) -> Result<Option<JobId>, StoreError> {
        dispatch!(self, q => q.lookup_cache(cache_key).await)
    }

    /// Completes the leased job with copies of the results of `source`, which must be done and
    /// carry the same cache key.
    pub async fn complete_from_cache(
        &self,
        lease: &Lease,
        source: JobId,
    ) -> Result<(), StoreError> {
        dispatch!(self, q => q.complete_from_cache(lease, source).await)
    }

    /// Reports a failure: transient ones are retried after backoff while attempts remain,
    /// the others fail the job (and every blocked job downstream of it).
    pub async fn fail(
        &self,
        lease: &Lease,
        failure: &JobFailure,
    ) -> Result<FailureDisposition, StoreError> {
        dispatch!(self, q => q.fail(lease, failure).await)
    }

    /// Gives a running job back to the queue without counting the attempt (a worker stopping
    /// on a signal); the attempt is recorded as `cancelled` with `reason`.
    pub async fn release(&self, lease: &Lease, reason: &str) -> Result<(), StoreError> {
        dispatch!(self, q => q.release(lease, reason).await)
    }

    /// Returns running jobs whose lease expired to ready (counting them lost, not failed);
    /// a job lost `policy.max_lost` times is failed with a diagnostic.
    pub async fn sweep_expired(&self) -> Result<SweepReport, StoreError> {
        dispatch!(self, q => q.sweep_expired().await)
    }

    /// Cancels a campaign and every unfinished job of it; running jobs lose their leases. A
    /// campaign without unfinished jobs is left as it is (0 jobs cancelled).
    pub async fn cancel_campaign(&self, campaign: CampaignId) -> Result<CancelReport, StoreError> {
        dispatch!(self, q => q.cancel_campaign(campaign).await)
    }

    /// One job row.
    pub async fn job(&self, job: JobId) -> Result<JobRecord, StoreError> {
        dispatch!(self, q => q.job(job).await)
    }

    /// Every job of a campaign, by id.
    pub async fn jobs_of_campaign(
        &self,
        campaign: CampaignId,
    ) -> Result<Vec<JobRecord>, StoreError> {
        dispatch!(self, q => q.jobs_of_campaign(campaign).await)
    }

    /// Every attempt on a campaign's jobs, in order.
    pub async fn attempts_of_campaign(
        &self,
        campaign: CampaignId,
    ) -> Result<Vec<AttemptRecord>, StoreError> {
        dispatch!(self, q => q.attempts_of_campaign(campaign).await)
    }

    /// How an attempt ended (`None` while it runs).
    pub async fn attempt_outcome(
        &self,
        attempt: AttemptId,
    ) -> Result<Option<AttemptOutcome>, StoreError> {
        dispatch!(self, q => q.attempt_outcome(attempt).await)
    }

    /// The results stored for a job (empty lists before it is done).
    pub async fn results_of(&self, job: JobId) -> Result<JobResults, StoreError> {
        dispatch!(self, q => q.results_of(job).await)
    }

    /// Jobs by state and occurrence covered.
    pub async fn progress(&self, campaign: CampaignId) -> Result<CampaignProgress, StoreError> {
        dispatch!(self, q => q.progress(campaign).await)
    }

    /// Annual damage per hot spot and measure from the stored damage inputs.
    pub async fn lifetime_damage(
        &self,
        campaign: CampaignId,
    ) -> Result<Vec<LifetimeDamage>, StoreError> {
        dispatch!(self, q => q.lifetime_damage(campaign).await)
    }

    /// Rows of the `sea_state_class_damage_inputs` view of a campaign.
    pub async fn sea_state_class_damage(
        &self,
        campaign: CampaignId,
    ) -> Result<Vec<SeaStateClassDamage>, StoreError> {
        dispatch!(self, q => q.sea_state_class_damage(campaign).await)
    }

    /// Rows of the `lifetime_class_damage` view of a campaign.
    pub async fn lifetime_class_damage(
        &self,
        campaign: CampaignId,
    ) -> Result<Vec<LifetimeClassDamage>, StoreError> {
        dispatch!(self, q => q.lifetime_class_damage(campaign).await)
    }

    /// Rows of the `sea_state_damage_inputs` view of a campaign (per hot spot measures).
    pub async fn sea_state_damage(
        &self,
        campaign: CampaignId,
    ) -> Result<Vec<SeaStateDamage>, StoreError> {
        dispatch!(self, q => q.sea_state_damage(campaign).await)
    }

    /// Sea states of a campaign with their job counts.
    pub async fn sea_state_status(
        &self,
        campaign: CampaignId,
    ) -> Result<Vec<SeaStateStatus>, StoreError> {
        dispatch!(self, q => q.sea_state_status(campaign).await)
    }

    /// Per-contact statistics of the done jobs of a campaign.
    pub async fn contact_rows(&self, campaign: CampaignId) -> Result<Vec<ContactRow>, StoreError> {
        dispatch!(self, q => q.contact_rows(campaign).await)
    }

    /// Class rows of the done jobs of a campaign with their sea state index and occurrence.
    pub async fn class_rows_of_campaign(
        &self,
        campaign: CampaignId,
    ) -> Result<Vec<(i64, f64, ClassDamageInput)>, StoreError> {
        dispatch!(self, q => q.class_rows_of_campaign(campaign).await)
    }

    /// Class rows of the done jobs of one kind of a campaign (every row, counted or not),
    /// with their sea state index and occurrence.
    pub async fn class_rows_of_kind(
        &self,
        campaign: CampaignId,
        kind: JobKind,
    ) -> Result<Vec<(i64, f64, ClassDamageInput)>, StoreError> {
        dispatch!(self, q => q.class_rows_of_kind(campaign, kind).await)
    }

    /// Rows of the `fidelity_comparison` view of a campaign.
    pub async fn fidelity_comparison(
        &self,
        campaign: CampaignId,
    ) -> Result<Vec<FidelityComparison>, StoreError> {
        dispatch!(self, q => q.fidelity_comparison(campaign).await)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn locations_select_the_backend_by_scheme() {
        assert_eq!(
            StoreLocation::parse("postgres://u@h/db").unwrap(),
            StoreLocation::Postgres("postgres://u@h/db".into())
        );
        assert_eq!(
            StoreLocation::parse("sqlite://runs/a.sqlite?mode=rwc").unwrap(),
            StoreLocation::Sqlite("runs/a.sqlite".into())
        );
        assert_eq!(
            StoreLocation::parse("b.sqlite").unwrap(),
            StoreLocation::Sqlite("b.sqlite".into())
        );
        assert_eq!(
            StoreLocation::parse("POSTGRES://u@h/db").unwrap(),
            StoreLocation::Postgres("POSTGRES://u@h/db".into())
        );
        assert!(matches!(
            StoreLocation::parse("mysql://x"),
            Err(StoreError::InvalidLocation { .. })
        ));
        let missing = StoreLocation::parse("no/such/dir/typo.db").unwrap();
        assert!(matches!(
            missing.require_existing(),
            Err(StoreError::InvalidLocation { .. })
        ));
        assert!(matches!(
            StoreLocation::parse("sqlite::memory:"),
            Err(StoreError::InvalidLocation { .. })
        ));
    }
}
