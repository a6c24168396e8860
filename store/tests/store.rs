//! Campaign store and job queue, run against SQLite and (when a server is reachable)
//! PostgreSQL with the same code.
//!
//! PostgreSQL tests use `MOORFRET_TEST_POSTGRES_URL` (default
//! `postgres://postgres@127.0.0.1:5432/test`), each in a schema of its own that is dropped
//! afterwards; without a server they print that they are skipped and pass.

use std::collections::HashMap;
use std::time::Duration;

use moorfret_store::{
    ArtifactRole, AttemptOutcome, CampaignId, ClassDamageInput, FailureClass, WorkerId,
};
use moorfret_store::{
    ArtifactStore, ClaimFilter, Clock, DamageInput, FailureDisposition, FailureKind,
    HotSpotSummary, JobFailure, JobKind, JobResults, JobState, ManualClock, NewCampaign,
    NewSeaState, PlannedJob, QueuePolicy, Store, StoreError, StoreOptions, TestPayload, WorkerInfo,
};
use moorfret_vocabulary::AngularPosition;
use serde_json::json;

const T0_MS: i64 = 1_700_000_000_000;

#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Backend {
    Sqlite,
    Postgres,
}

/// A throw-away store with a hand-driven clock.
struct TestStore {
    store: Store,
    clock: ManualClock,
    location: String,
    options: StoreOptions,
    _dir: tempfile::TempDir,
}

impl TestStore {
    /// Another handle with its own pool on the same database, as another process would have.
    async fn another_handle(&self, max_connections: u32) -> Store {
        let options = StoreOptions {
            max_connections,
            ..self.options.clone()
        };
        Store::open(&self.location, options).await.unwrap()
    }

    async fn finish(self) {
        self.store.drop_postgres_schema().await.unwrap();
    }
}

fn postgres_url() -> String {
    std::env::var("MOORFRET_TEST_POSTGRES_URL")
        .unwrap_or_else(|_| "postgres://postgres@127.0.0.1:5432/test".into())
}

async fn postgres_reachable(url: &str) -> bool {
    use sqlx::Connection;
    let attempt = tokio::time::timeout(Duration::from_secs(3), sqlx::PgConnection::connect(url));
    match attempt.await {
        Ok(Ok(conn)) => {
            let _ = conn.close().await;
            true
        }
        Ok(Err(err)) => {
            skip_postgres(&format!("no server at {url}: {err}"));
            false
        }
        Err(_) => {
            skip_postgres(&format!("connecting to {url} timed out"));
            false
        }
    }
}

async fn open_store(backend: Backend, policy: QueuePolicy) -> Option<TestStore> {
    let dir = tempfile::tempdir().unwrap();
    let clock = ManualClock::new(T0_MS);
    let mut options = StoreOptions {
        clock: Clock::Manual(clock.clone()),
        policy,
        max_connections: 4,
        postgres_schema: None,
    };
    let location = match backend {
        Backend::Sqlite => dir
            .path()
            .join("campaign.sqlite")
            .to_string_lossy()
            .into_owned(),
        Backend::Postgres => {
            let url = postgres_url();
            if !postgres_reachable(&url).await {
                return None;
            }
            options.postgres_schema = Some(format!("t_{}", uuid::Uuid::new_v4().simple()));
            url
        }
    };
    let store = Store::open(&location, options.clone()).await.unwrap();
    Some(TestStore {
        store,
        clock,
        location,
        options,
        _dir: dir,
    })
}

fn worker_info(n: i64) -> WorkerInfo {
    WorkerInfo {
        host: format!("node{n}"),
        pid: 1000 + n,
        version: "test".into(),
    }
}

async fn campaign(store: &Store, name: &str) -> CampaignId {
    store
        .create_campaign(&NewCampaign {
            name: name.into(),
            spec: json!({ "name": name }),
            spec_sha256: "0".repeat(64),
        })
        .await
        .unwrap()
}

fn test_job(payload: TestPayload) -> PlannedJob {
    PlannedJob::new(JobKind::Test, serde_json::to_value(payload).unwrap())
}

fn damage(hot_spot_index: i64, seed_index: i64, damage: f64) -> DamageInput {
    DamageInput {
        hot_spot_index,
        measure: "fretting_sn".into(),
        seed_index,
        effective_duration_s: 10_800.0,
        damage,
        details: json!({ "cycles": 12 }),
    }
}

fn strand_results(value: f64) -> JobResults {
    JobResults {
        result: json!({ "max_slip_m": value }),
        hot_spots: vec![HotSpotSummary {
            hot_spot_index: 0,
            summary: json!({ "t_max_n": 1.0e6 }),
        }],
        damage_inputs: vec![damage(0, 0, value)],
        // a class row too, so that cache copies are checked to carry it
        class_damage_inputs: vec![ClassDamageInput {
            hot_spot_index: 0,
            layer_interface: 1,
            angular_position: AngularPosition::OuterArc,
            seed_index: 0,
            effective_duration_s: 600.0,
            contacts: 4,
            fretting_damage_rate_max_per_s: value * 1e-9,
            fretting_damage_rate_mean_per_s: value * 0.5e-9,
            stick_cycles_per_hour: 0.0,
            partial_slip_cycles_per_hour: 120.0,
            gross_slip_cycles_per_hour: 6.0,
            ruiz_f1_max: 2.5,
            ruiz_f2_max: 1.0e9,
            peak_pressure_max_pa: 1.2e9,
            slip_amplitude_max_m: 3.0e-6,
            histogram: json!({ "cycles": [] }),
            rope_tn_damage_rate_max_per_s: value * 2e-9,
            rope_tn_damage_rate_mean_per_s: value * 1e-9,
            wear_power_max_w: value * 1e-6,
        }],
        ..JobResults::default()
    }
}

macro_rules! on_both_backends {
    ($($name:ident),+ $(,)?) => {
        mod sqlite {
            $(
                #[tokio::test(flavor = "multi_thread", worker_threads = 2)]
                async fn $name() {
                    super::$name(super::Backend::Sqlite).await;
                }
            )+
        }
        mod postgres {
            $(
                #[tokio::test(flavor = "multi_thread", worker_threads = 2)]
                async fn $name() {
                    super::$name(super::Backend::Postgres).await;
                }
            )+
        }
    };
}

on_both_backends!(
    eight_workers_complete_a_thousand_jobs_exactly_once,
    expired_lease_is_swept_back_to_ready_and_counted_lost,
    job_lost_too_often_fails_with_a_diagnostic,
    late_completion_with_a_stale_token_is_rejected_and_nothing_doubles,
    transient_failure_retries_after_capped_exponential_backoff,
    permanent_failure_fails_at_once_and_fails_everything_downstream,
    dependents_become_ready_only_when_every_dependency_is_done,
    cancelling_a_campaign_stops_its_jobs_and_revokes_running_leases,
    cached_results_of_another_campaign_are_reused,
    lifetime_view_reproduces_the_reference_annual_damage,
    claim_filter_respects_kind_and_expected_cost,
    newer_schema_is_refused_and_left_untouched,
    dependents_of_concurrently_completed_jobs_are_all_unblocked,
    database_clock_sets_lease_times,
    seed_spread_and_lifetime_band_of_known_seeds,
    settled_jobs_end_at_once_and_unblock_their_dependents,
    cancelling_a_finished_campaign_changes_nothing,
    the_wave_energy_kept_is_stored_with_every_sea_state,
    a_store_recorded_before_a_comment_of_migration_1_changed_migrates,
);

/// SHA-384 of migration 0001 as released, per backend, before a comment of it was edited.
const RELEASED_0001_SHA384: [(Backend, &str); 2] = [
    (
        Backend::Sqlite,
        "952f0050ed1fce88dcaa21a4d0992e37b5fdea1a23a16ee15f8e1439a38c10a9\
         bb2778d9d91106f864f292dc6460d587",
    ),
    (
        Backend::Postgres,
        "1b040bec75f5723b891f75300ea5e41f6651820ab91b2f4e4e2094073592d47d\
         69c41e9ba6cea5536443a2791642a0b3",
    ),
];

/// A store at schema 6 that recorded migration 0001's released checksum (as every store made
/// before its comment changed did) is migrated to the current schema, keeping its campaign; a
/// checksum recorded for no released text is still refused.
async fn a_store_recorded_before_a_comment_of_migration_1_changed_migrates(backend: Backend) {
    let Some(ts) = open_store(backend, QueuePolicy::default()).await else {
        return;
    };
    let id = campaign(&ts.store, "older").await;
    ts.store.close().await;
    let released: Vec<u8> = {
        let hex = RELEASED_0001_SHA384
            .iter()
            .find(|(b, _)| *b == backend)
            .unwrap()
            .1;
        (0..hex.len())
            .step_by(2)
            .map(|i| u8::from_str_radix(&hex[i..i + 2], 16).unwrap())
            .collect()
    };
    // back to schema 6, with the released checksum of 0001 (or a foreign one)
    let rewind = |checksum: Vec<u8>| {
        let ts = &ts;
        async move {
            for sql in [
                "DELETE FROM _sqlx_migrations WHERE version = 7",
                "ALTER TABLE sea_states DROP COLUMN wave_energy_kept",
                "UPDATE schema_info SET value = '6' WHERE key = 'schema_version'",
            ] {
                raw_execute(ts, backend, sql, None::<Vec<u8>>).await;
            }
            let sql = "UPDATE _sqlx_migrations SET checksum = $1 WHERE version = 1";
            raw_execute(ts, backend, sql, Some(checksum)).await;
        }
    };
    rewind(released).await;
    let store = Store::open(&ts.location, ts.options.clone()).await.unwrap();
    assert_eq!(
        store.schema_version().await.unwrap(),
        store.supported_schema_version()
    );
    assert_eq!(
        store.campaign_by_name("older").await.unwrap(),
        Some(id),
        "campaign kept"
    );
    store.close().await;
    rewind(vec![0; 48]).await;
    let refused = Store::open(&ts.location, ts.options.clone()).await;
    assert!(
        refused.is_err(),
        "a foreign checksum of migration 1 must be refused"
    );
    if backend == Backend::Postgres {
        let schema = ts.options.postgres_schema.clone().unwrap();
        let drop = format!("DROP SCHEMA {schema} CASCADE");
        raw_execute(&ts, backend, &drop, None::<Vec<u8>>).await;
    }
}

/// Runs `sql` (one statement, `$1` bound to `bind` if given) on the test store's database with
/// a connection of sqlx's own (in the store's schema on PostgreSQL), as another program would.
async fn raw_execute<T>(ts: &TestStore, backend: Backend, sql: &str, bind: Option<T>)
where
    T: for<'q> sqlx::Encode<'q, sqlx::Sqlite>
        + sqlx::Type<sqlx::Sqlite>
        + for<'q> sqlx::Encode<'q, sqlx::Postgres>
        + sqlx::Type<sqlx::Postgres>
        + Send,
{
    match backend {
        Backend::Sqlite => {
            let pool = sqlx::SqlitePool::connect(&format!("sqlite://{}", ts.location))
                .await
                .unwrap();
            let mut query = sqlx::query(sql);
            if let Some(b) = bind {
                query = query.bind(b);
            }
            query.execute(&pool).await.unwrap();
            pool.close().await;
        }
        Backend::Postgres => {
            use sqlx::postgres::{PgConnectOptions, PgPoolOptions};
            let schema = ts.options.postgres_schema.clone().unwrap();
            let options: PgConnectOptions = ts.location.parse().unwrap();
            let pool = PgPoolOptions::new()
                .connect_with(options.options([("search_path", schema.as_str())]))
                .await
                .unwrap();
            let mut query = sqlx::query(sql);
            if let Some(b) = bind {
                query = query.bind(b);
            }
            query.execute(&pool).await.unwrap();
            pool.close().await;
        }
    }
}

/// The energy each sea state's wave cut-off keeps is stored with it at planning (schema 7) and
/// read back as stored; a sea state planned without it reads none.
async fn the_wave_energy_kept_is_stored_with_every_sea_state(backend: Backend) {
    let Some(ts) = open_store(backend, QueuePolicy::default()).await else {
        return;
    };
    assert!(ts.store.supported_schema_version() >= 7);
    let id = campaign(&ts.store, "energy").await;
    let kept = [Some(0.8123456789012345), Some(1.0), None];
    let states: Vec<NewSeaState> = kept
        .iter()
        .enumerate()
        .map(|(i, &k)| NewSeaState {
            index: i as i64,
            hs_m: 1.0 + i as f64,
            tp_s: 5.0 + i as f64,
            occurrence_fraction: 0.1,
            seeds: vec![i as u64],
            heading_deg: 0.0,
            sector: None,
            wave_energy_kept: k,
        })
        .collect();
    ts.store.insert_sea_states(id, &states).await.unwrap();
    let read: Vec<Option<f64>> = ts
        .store
        .sea_state_status(id)
        .await
        .unwrap()
        .iter()
        .map(|s| s.wave_energy_kept)
        .collect();
    assert_eq!(read, kept);
    ts.finish().await;
}

/// A campaign whose jobs are all finished has nothing to cancel: 0 jobs cancelled and its
/// state as it was (it used to be marked cancelled).
async fn cancelling_a_finished_campaign_changes_nothing(backend: Backend) {
    let Some(ts) = open_store(backend, QueuePolicy::default()).await else {
        return;
    };
    let id = campaign(&ts.store, "finished").await;
    ts.store
        .insert_plan(id, &[test_job(TestPayload::Succeed)])
        .await
        .unwrap();
    let worker = ts.store.register_worker(&worker_info(1)).await.unwrap();
    let lease = ts
        .store
        .claim(&worker, &ClaimFilter::default())
        .await
        .unwrap()
        .unwrap();
    ts.store
        .complete(&lease, &JobResults::default())
        .await
        .unwrap();
    let state = |all: Vec<moorfret_store::CampaignRecord>| {
        all.into_iter().find(|c| c.id == id).unwrap().state
    };
    let before = state(ts.store.campaigns().await.unwrap());
    let report = ts.store.cancel_campaign(id).await.unwrap();
    assert_eq!(report.jobs_cancelled, 0);
    assert_eq!(state(ts.store.campaigns().await.unwrap()), before);
    assert_ne!(before, moorfret_store::CampaignState::Cancelled);
    ts.finish().await;
}

async fn eight_workers_complete_a_thousand_jobs_exactly_once(backend: Backend) {
    const JOBS: usize = 1_000;
    const WORKERS: i64 = 8;
    let Some(ts) = open_store(backend, QueuePolicy::default()).await else {
        return;
    };
    let id = campaign(&ts.store, "many").await;
    let plan: Vec<PlannedJob> = (0..JOBS).map(|_| test_job(TestPayload::Succeed)).collect();
    ts.store.insert_plan(id, &plan).await.unwrap();

    let mut handles = Vec::new();
    for n in 0..WORKERS {
        let store = ts.another_handle(2).await;
        handles.push(tokio::spawn(async move {
            let worker = store.register_worker(&worker_info(n)).await?;
            let mut completed = 0_usize;
            while let Some(lease) = store.claim(&worker, &ClaimFilter::default()).await? {
                let results = JobResults {
                    result: json!({ "by": n }),
                    ..JobResults::default()
                };
                store.complete(&lease, &results).await?;
                completed += 1;
            }
            store.close().await;
            Ok::<usize, StoreError>(completed)
        }));
    }
    let mut total = 0;
    for handle in handles {
        match handle.await.unwrap() {
            Ok(completed) => total += completed,
            Err(err) => panic!(
                "worker failed (locked: {}): {err}",
                err.is_database_locked()
            ),
        }
    }
    assert_eq!(total, JOBS);

    let jobs = ts.store.jobs_of_campaign(id).await.unwrap();
    assert_eq!(jobs.len(), JOBS);
    assert!(jobs
        .iter()
        .all(|j| j.state == JobState::Done && j.attempt == 1));
    let attempts = ts.store.attempts_of_campaign(id).await.unwrap();
    assert_eq!(attempts.len(), JOBS, "one attempt per job");
    let mut per_job: HashMap<i64, usize> = HashMap::new();
    for attempt in &attempts {
        assert_eq!(attempt.outcome, Some(AttemptOutcome::Done));
        *per_job.entry(attempt.job.0).or_default() += 1;
    }
    assert_eq!(per_job.len(), JOBS);
    assert!(per_job.values().all(|&n| n == 1));
    let progress = ts.store.progress(id).await.unwrap();
    assert_eq!(progress.jobs_by_state[3], (JobState::Done, JOBS as i64));
    ts.finish().await;
}

/// Two upstream jobs per dependent, drained by 8 concurrent workers: a dependent must become
/// ready even when its two upstream jobs complete at the same moment.
async fn dependents_of_concurrently_completed_jobs_are_all_unblocked(backend: Backend) {
    const GROUPS: usize = 60;
    let Some(ts) = open_store(backend, QueuePolicy::default()).await else {
        return;
    };
    let id = campaign(&ts.store, "fan-in").await;
    let mut plan = Vec::new();
    for g in 0..GROUPS {
        plan.push(test_job(TestPayload::Succeed));
        plan.push(test_job(TestPayload::Succeed));
        let mut joined = test_job(TestPayload::Succeed);
        joined.depends_on = vec![3 * g, 3 * g + 1];
        plan.push(joined);
    }
    ts.store.insert_plan(id, &plan).await.unwrap();
    let mut handles = Vec::new();
    for n in 0..8 {
        let store = ts.another_handle(2).await;
        handles.push(tokio::spawn(async move {
            let worker = store.register_worker(&worker_info(n)).await?;
            loop {
                match store.claim(&worker, &ClaimFilter::default()).await? {
                    Some(lease) => store.complete(&lease, &JobResults::default()).await?,
                    None => {
                        let progress = store.progress(id).await?;
                        let pending: i64 = progress.jobs_by_state[..3].iter().map(|(_, n)| n).sum();
                        if pending == 0 {
                            break;
                        }
                        // A blocked job with nothing running would never be unblocked.
                        let running = progress.jobs_by_state[2].1;
                        let ready = progress.jobs_by_state[1].1;
                        if running == 0 && ready == 0 {
                            panic!("stranded blocked jobs: {progress:?}");
                        }
                        tokio::time::sleep(Duration::from_millis(2)).await;
                    }
                }
            }
            store.close().await;
            Ok::<(), StoreError>(())
        }));
    }
    for handle in handles {
        handle.await.unwrap().unwrap();
    }
    let jobs = ts.store.jobs_of_campaign(id).await.unwrap();
    assert!(jobs.iter().all(|j| j.state == JobState::Done));
    ts.finish().await;
}

async fn database_clock_sets_lease_times(backend: Backend) {
    let Some(ts) = open_store(backend, QueuePolicy::default()).await else {
        return;
    };
    let options = StoreOptions {
        clock: Clock::Database,
        ..ts.options.clone()
    };
    let store = Store::open(&ts.location, options).await.unwrap();
    let id = campaign(&store, "server-clock").await;
    store
        .insert_plan(id, &[test_job(TestPayload::Succeed)])
        .await
        .unwrap();
    let worker = store.register_worker(&worker_info(1)).await.unwrap();
    let before = moorfret_store::clock::system_now_ms();
    let lease = store
        .claim(&worker, &ClaimFilter::default())
        .await
        .unwrap()
        .unwrap();
    let after = moorfret_store::clock::system_now_ms();
    // The server runs on this machine, so its clock agrees with ours to well within a second.
    let lease_ms = store.policy().lease_ms;
    assert!(
        lease.expires_at_ms >= before + lease_ms - 1_000,
        "{} < {}",
        lease.expires_at_ms,
        before
    );
    assert!(
        lease.expires_at_ms <= after + lease_ms + 1_000,
        "{} > {}",
        lease.expires_at_ms,
        after
    );
    store.close().await;
    ts.finish().await;
}

async fn expired_lease_is_swept_back_to_ready_and_counted_lost(backend: Backend) {
    let policy = QueuePolicy::default();
    let Some(ts) = open_store(backend, policy.clone()).await else {
        return;
    };
    let id = campaign(&ts.store, "sweep").await;
    let job = ts
        .store
        .insert_plan(id, &[test_job(TestPayload::Succeed)])
        .await
        .unwrap()[0];
    let worker = ts.store.register_worker(&worker_info(1)).await.unwrap();
    let lease = ts
        .store
        .claim(&worker, &ClaimFilter::default())
        .await
        .unwrap()
        .unwrap();
    assert_eq!(lease.expires_at_ms, T0_MS + policy.lease_ms);

    // A heartbeat just before expiry pushes it out; a sweep between the two ends does nothing.
    ts.clock.advance_ms(policy.lease_ms - 1);
    let renewed = ts.store.heartbeat(&lease).await.unwrap();
    assert_eq!(renewed, T0_MS + 2 * policy.lease_ms - 1);
    ts.clock.advance_ms(2);
    assert_eq!(ts.store.sweep_expired().await.unwrap(), Default::default());

    // No heartbeat for a whole lease: swept, counted lost, the attempt given back.
    ts.clock.advance_ms(policy.lease_ms);
    let report = ts.store.sweep_expired().await.unwrap();
    assert_eq!(report.requeued, vec![job]);
    assert!(report.failed.is_empty());
    let record = ts.store.job(job).await.unwrap();
    assert_eq!(record.state, JobState::Ready);
    assert_eq!((record.lost_count, record.attempt), (1, 0));
    assert_eq!(record.lease_token, None);
    assert!(matches!(
        ts.store.heartbeat(&lease).await,
        Err(StoreError::LeaseLost { .. })
    ));
    let attempts = ts.store.attempts_of_campaign(id).await.unwrap();
    assert_eq!(attempts.len(), 1);
    assert_eq!(attempts[0].outcome, Some(AttemptOutcome::Lost));

    // The next claim is counted as the first attempt, and is the second claim.
    let again = ts
        .store
        .claim(&worker, &ClaimFilter::default())
        .await
        .unwrap()
        .unwrap();
    assert_eq!(again.attempt, 1);
    assert_ne!(again.token, lease.token);
    ts.store
        .complete(&again, &JobResults::default())
        .await
        .unwrap();
    let attempts = ts.store.attempts_of_campaign(id).await.unwrap();
    assert_eq!(attempts[1].claim_number, 2);
    assert_eq!(attempts[1].outcome, Some(AttemptOutcome::Done));
    ts.finish().await;
}

async fn job_lost_too_often_fails_with_a_diagnostic(backend: Backend) {
    let policy = QueuePolicy {
        max_lost: 3,
        ..QueuePolicy::default()
    };
    let Some(ts) = open_store(backend, policy.clone()).await else {
        return;
    };
    let id = campaign(&ts.store, "lost").await;
    let plan = vec![test_job(TestPayload::Succeed), {
        let mut downstream = test_job(TestPayload::Succeed);
        downstream.depends_on = vec![0];
        downstream
    }];
    let jobs = ts.store.insert_plan(id, &plan).await.unwrap();
    let worker = ts.store.register_worker(&worker_info(1)).await.unwrap();
    for round in 1..=3 {
        let lease = ts
            .store
            .claim(&worker, &ClaimFilter::default())
            .await
            .unwrap()
            .unwrap();
        assert_eq!(lease.job, jobs[0]);
        ts.clock.advance_ms(policy.lease_ms + 1);
        let report = ts.store.sweep_expired().await.unwrap();
        if round < 3 {
            assert_eq!(report.requeued, vec![jobs[0]]);
        } else {
            assert_eq!(report.failed, vec![jobs[0]]);
        }
    }
    let record = ts.store.job(jobs[0]).await.unwrap();
    assert_eq!(record.state, JobState::Failed);
    assert_eq!(record.lost_count, 3);
    assert_eq!(record.error_class.map(|c| c.as_str()), Some("lost"));
    let message = record.error_message.unwrap();
    assert!(
        message.contains("3 times") && message.contains(&worker.0),
        "{message}"
    );
    let downstream = ts.store.job(jobs[1]).await.unwrap();
    assert_eq!(downstream.state, JobState::Failed);
    assert_eq!(
        downstream.error_class.map(|c| c.as_str()),
        Some("upstream_failed")
    );
    assert!(ts
        .store
        .claim(&worker, &ClaimFilter::default())
        .await
        .unwrap()
        .is_none());
    ts.finish().await;
}

async fn late_completion_with_a_stale_token_is_rejected_and_nothing_doubles(backend: Backend) {
    let policy = QueuePolicy::default();
    let Some(ts) = open_store(backend, policy.clone()).await else {
        return;
    };
    let id = campaign(&ts.store, "stale").await;
    let plan = vec![PlannedJob::new(JobKind::Strand, json!({ "hot_spot": 0 }))];
    let job = ts.store.insert_plan(id, &plan).await.unwrap()[0];
    let slow = ts.store.register_worker(&worker_info(1)).await.unwrap();
    let fast = ts.store.register_worker(&worker_info(2)).await.unwrap();

    let stale = ts
        .store
        .claim(&slow, &ClaimFilter::default())
        .await
        .unwrap()
        .unwrap();
    ts.clock.advance_ms(policy.lease_ms + 1);
    ts.store.sweep_expired().await.unwrap();
    let current = ts
        .store
        .claim(&fast, &ClaimFilter::default())
        .await
        .unwrap()
        .unwrap();

    // The slow worker wakes up while the job is running elsewhere, and again once it is done.
    let late = ts.store.complete(&stale, &strand_results(1.0)).await;
    assert!(matches!(late, Err(StoreError::LeaseLost { job: j, .. }) if j == job));
    let failure = JobFailure {
        kind: FailureKind::Permanent,
        error_class: FailureClass::StrandHistory,
        message: "late".into(),
    };
    assert!(matches!(
        ts.store.fail(&stale, &failure).await,
        Err(StoreError::LeaseLost { .. })
    ));
    ts.store
        .complete(&current, &strand_results(2.0))
        .await
        .unwrap();
    let after_done = ts.store.complete(&stale, &strand_results(1.0)).await;
    assert!(matches!(after_done, Err(StoreError::LeaseLost { .. })));
    assert!(matches!(
        ts.store.complete(&current, &strand_results(2.0)).await,
        Err(StoreError::LeaseLost { .. })
    ));

    let stored = ts.store.results_of(job).await.unwrap();
    assert_eq!(stored, strand_results(2.0));
    let record = ts.store.job(job).await.unwrap();
    assert_eq!(
        (record.state, record.worker),
        (JobState::Done, Some(fast.clone()))
    );
    let outcomes: Vec<_> = ts
        .store
        .attempts_of_campaign(id)
        .await
        .unwrap()
        .into_iter()
        .map(|a| (a.worker, a.outcome))
        .collect();
    assert_eq!(
        outcomes,
        vec![
            (slow, Some(AttemptOutcome::Lost)),
            (fast, Some(AttemptOutcome::Done))
        ]
    );
    ts.finish().await;
}

async fn transient_failure_retries_after_capped_exponential_backoff(backend: Backend) {
    let policy = QueuePolicy {
        backoff_base_ms: 1_000,
        backoff_cap_ms: 1_500,
        ..QueuePolicy::default()
    };
    let Some(ts) = open_store(backend, policy).await else {
        return;
    };
    let id = campaign(&ts.store, "retry").await;
    let payload = TestPayload::FailTransient {
        failing_attempts: 10,
    };
    let mut planned = test_job(payload.clone());
    planned.max_attempts = 3;
    let job = ts.store.insert_plan(id, &[planned]).await.unwrap()[0];
    let worker = ts.store.register_worker(&worker_info(1)).await.unwrap();
    let any = ClaimFilter::default();

    // Expected delays: 1000 ms, then min(2000, 1500) ms, then no attempts left.
    for (attempt, delay_ms) in [(1, 1_000), (2, 1_500)] {
        let lease = ts.store.claim(&worker, &any).await.unwrap().unwrap();
        assert_eq!(lease.attempt, attempt);
        let failure = payload.failure_on_attempt(lease.attempt).unwrap();
        let now = ts.clock.now_ms();
        let disposition = ts.store.fail(&lease, &failure).await.unwrap();
        assert_eq!(
            disposition,
            FailureDisposition::Retry {
                not_before_ms: now + delay_ms
            }
        );
        let record = ts.store.job(job).await.unwrap();
        assert_eq!(record.state, JobState::Ready);
        assert_eq!(
            record.error_class.map(|c| c.as_str()),
            Some("test_transient")
        );
        ts.clock.advance_ms(delay_ms - 1);
        assert!(
            ts.store.claim(&worker, &any).await.unwrap().is_none(),
            "claimed during backoff"
        );
        ts.clock.advance_ms(1);
    }
    let lease = ts.store.claim(&worker, &any).await.unwrap().unwrap();
    assert_eq!(lease.attempt, 3);
    let failure = payload.failure_on_attempt(3).unwrap();
    let disposition = ts.store.fail(&lease, &failure).await.unwrap();
    assert_eq!(
        disposition,
        FailureDisposition::Failed {
            dependents_failed: 0
        }
    );
    let record = ts.store.job(job).await.unwrap();
    assert_eq!(record.state, JobState::Failed);
    let message = record.error_message.unwrap();
    assert!(message.contains("attempt 3 of 3"), "{message}");
    let outcomes: Vec<_> = ts
        .store
        .attempts_of_campaign(id)
        .await
        .unwrap()
        .into_iter()
        .map(|a| a.outcome)
        .collect();
    assert_eq!(outcomes, vec![Some(AttemptOutcome::TransientFailure); 3]);

    // A job whose fault clears on the second attempt ends done.
    let recovering = TestPayload::FailTransient {
        failing_attempts: 1,
    };
    let job = ts
        .store
        .insert_plan(id, &[test_job(recovering.clone())])
        .await
        .unwrap()[0];
    let lease = ts.store.claim(&worker, &any).await.unwrap().unwrap();
    assert_eq!(lease.job, job);
    let failure = recovering.failure_on_attempt(lease.attempt).unwrap();
    ts.store.fail(&lease, &failure).await.unwrap();
    ts.clock.advance_ms(1_000);
    let lease = ts.store.claim(&worker, &any).await.unwrap().unwrap();
    assert!(recovering.failure_on_attempt(lease.attempt).is_none());
    ts.store
        .complete(&lease, &JobResults::default())
        .await
        .unwrap();
    let record = ts.store.job(job).await.unwrap();
    assert_eq!((record.state, record.attempt), (JobState::Done, 2));
    assert_eq!(record.error_class, None);
    ts.finish().await;
}

async fn permanent_failure_fails_at_once_and_fails_everything_downstream(backend: Backend) {
    let Some(ts) = open_store(backend, QueuePolicy::default()).await else {
        return;
    };
    let id = campaign(&ts.store, "permanent").await;
    let mut first = test_job(TestPayload::FailPermanent);
    first.max_attempts = 5;
    let mut second = test_job(TestPayload::Succeed);
    second.depends_on = vec![0];
    let mut third = test_job(TestPayload::Succeed);
    third.depends_on = vec![1];
    let independent = test_job(TestPayload::Succeed);
    let jobs = ts
        .store
        .insert_plan(id, &[first, second, third, independent])
        .await
        .unwrap();
    let worker = ts.store.register_worker(&worker_info(1)).await.unwrap();

    let lease = ts
        .store
        .claim(&worker, &ClaimFilter::default())
        .await
        .unwrap()
        .unwrap();
    assert_eq!(lease.job, jobs[0]);
    let failure = TestPayload::FailPermanent.failure_on_attempt(1).unwrap();
    let disposition = ts.store.fail(&lease, &failure).await.unwrap();
    assert_eq!(
        disposition,
        FailureDisposition::Failed {
            dependents_failed: 2
        }
    );
    let record = ts.store.job(jobs[0]).await.unwrap();
    assert_eq!((record.state, record.attempt), (JobState::Failed, 1));
    assert_eq!(
        record.error_class.map(|c| c.as_str()),
        Some("test_permanent")
    );
    assert_eq!(
        record.error_message.as_deref(),
        Some("test job fails permanently")
    );
    for downstream in &jobs[1..3] {
        let record = ts.store.job(*downstream).await.unwrap();
        assert_eq!(record.state, JobState::Failed);
        assert_eq!(
            record.error_class.map(|c| c.as_str()),
            Some("upstream_failed")
        );
    }
    assert_eq!(ts.store.job(jobs[3]).await.unwrap().state, JobState::Ready);
    ts.finish().await;
}

async fn dependents_become_ready_only_when_every_dependency_is_done(backend: Backend) {
    let Some(ts) = open_store(backend, QueuePolicy::default()).await else {
        return;
    };
    let id = campaign(&ts.store, "deps").await;
    let mut low = PlannedJob::new(JobKind::Global, json!({ "seed": 1 }));
    low.priority = 1;
    let mut high = PlannedJob::new(JobKind::Global, json!({ "seed": 2 }));
    high.priority = 5;
    let mut joined = PlannedJob::new(JobKind::Strand, json!({ "hot_spot": 0 }));
    joined.depends_on = vec![0, 1];
    let jobs = ts
        .store
        .insert_plan(id, &[low, high, joined])
        .await
        .unwrap();
    assert_eq!(
        ts.store.job(jobs[2]).await.unwrap().state,
        JobState::Blocked
    );
    let worker = ts.store.register_worker(&worker_info(1)).await.unwrap();
    let any = ClaimFilter::default();

    let first = ts.store.claim(&worker, &any).await.unwrap().unwrap();
    assert_eq!(first.job, jobs[1], "higher priority first");
    ts.store
        .complete(&first, &JobResults::default())
        .await
        .unwrap();
    assert_eq!(
        ts.store.job(jobs[2]).await.unwrap().state,
        JobState::Blocked
    );
    let second = ts.store.claim(&worker, &any).await.unwrap().unwrap();
    assert_eq!(second.job, jobs[0]);
    assert!(
        ts.store.claim(&worker, &any).await.unwrap().is_none(),
        "blocked job claimed"
    );
    ts.store
        .complete(&second, &JobResults::default())
        .await
        .unwrap();
    assert_eq!(ts.store.job(jobs[2]).await.unwrap().state, JobState::Ready);
    let third = ts.store.claim(&worker, &any).await.unwrap().unwrap();
    assert_eq!((third.job, third.kind), (jobs[2], JobKind::Strand));

    let bad = PlannedJob {
        depends_on: vec![0],
        ..PlannedJob::new(JobKind::Test, json!({}))
    };
    let refused = ts.store.insert_plan(id, &[bad]).await;
    assert!(matches!(
        refused,
        Err(StoreError::BadDependency {
            job_index: 0,
            depends_on: 0
        })
    ));
    ts.finish().await;
}

async fn cancelling_a_campaign_stops_its_jobs_and_revokes_running_leases(backend: Backend) {
    let Some(ts) = open_store(backend, QueuePolicy::default()).await else {
        return;
    };
    let doomed = campaign(&ts.store, "doomed").await;
    let other = campaign(&ts.store, "other").await;
    let mut plan: Vec<PlannedJob> = (0..3).map(|_| test_job(TestPayload::Succeed)).collect();
    plan[0].priority = 10;
    plan[1].priority = 10;
    plan[2].depends_on = vec![1];
    let jobs = ts.store.insert_plan(doomed, &plan).await.unwrap();
    let survivor = ts
        .store
        .insert_plan(other, &[test_job(TestPayload::Succeed)])
        .await
        .unwrap()[0];
    let worker = ts.store.register_worker(&worker_info(1)).await.unwrap();
    let any = ClaimFilter::default();

    let done = ts.store.claim(&worker, &any).await.unwrap().unwrap();
    ts.store
        .complete(&done, &JobResults::default())
        .await
        .unwrap();
    let running = ts.store.claim(&worker, &any).await.unwrap().unwrap();
    assert_eq!((done.job, running.job), (jobs[0], jobs[1]));

    let report = ts.store.cancel_campaign(doomed).await.unwrap();
    assert_eq!(report.jobs_cancelled, 2, "the running and the blocked job");
    let states: Vec<JobState> = ts
        .store
        .jobs_of_campaign(doomed)
        .await
        .unwrap()
        .iter()
        .map(|j| j.state)
        .collect();
    assert_eq!(
        states,
        vec![JobState::Done, JobState::Cancelled, JobState::Cancelled]
    );
    assert!(matches!(
        ts.store.heartbeat(&running).await,
        Err(StoreError::LeaseLost { .. })
    ));
    let late = ts.store.complete(&running, &JobResults::default()).await;
    assert!(matches!(late, Err(StoreError::LeaseLost { .. })));
    let attempts = ts.store.attempts_of_campaign(doomed).await.unwrap();
    assert_eq!(attempts[1].outcome, Some(AttemptOutcome::Cancelled));

    let next = ts.store.claim(&worker, &any).await.unwrap().unwrap();
    assert_eq!(next.job, survivor, "other campaigns are untouched");
    let unknown = ts.store.cancel_campaign(CampaignId(999_999)).await;
    assert!(matches!(unknown, Err(StoreError::UnknownCampaign(_))));
    ts.finish().await;
}

async fn cached_results_of_another_campaign_are_reused(backend: Backend) {
    let Some(ts) = open_store(backend, QueuePolicy::default()).await else {
        return;
    };
    let first = campaign(&ts.store, "first").await;
    let second = campaign(&ts.store, "second").await;
    let mut planned = PlannedJob::new(JobKind::Strand, json!({ "hot_spot": 0 }));
    planned.cache_key = Some("a".repeat(64));
    let source = ts
        .store
        .insert_plan(first, &[planned.clone()])
        .await
        .unwrap()[0];
    let worker = ts.store.register_worker(&worker_info(1)).await.unwrap();
    let any = ClaimFilter::default();
    let key = planned.cache_key.clone().unwrap();

    let lease = ts.store.claim(&worker, &any).await.unwrap().unwrap();
    assert_eq!(
        ts.store.lookup_cache(&key).await.unwrap(),
        None,
        "running jobs are no cache"
    );
    ts.store
        .complete(&lease, &strand_results(3.0))
        .await
        .unwrap();

    let reuser = ts.store.insert_plan(second, &[planned]).await.unwrap()[0];
    let lease = ts.store.claim(&worker, &any).await.unwrap().unwrap();
    assert_eq!(lease.job, reuser);
    let hit = ts
        .store
        .lookup_cache(lease.cache_key.as_deref().unwrap())
        .await
        .unwrap();
    assert_eq!(hit, Some(source));
    ts.store.complete_from_cache(&lease, source).await.unwrap();

    assert_eq!(
        ts.store.results_of(reuser).await.unwrap(),
        strand_results(3.0)
    );
    let record = ts.store.job(reuser).await.unwrap();
    assert_eq!(
        (record.state, record.cached_from),
        (JobState::Done, Some(source))
    );
    assert_eq!(
        record.result_sha256,
        ts.store.job(source).await.unwrap().result_sha256
    );
    let attempts = ts.store.attempts_of_campaign(second).await.unwrap();
    assert_eq!(attempts[0].outcome, Some(AttemptOutcome::Cached));
    ts.finish().await;
}

/// docs/damage.md, lifetime damage: occurrences 0.30 and 0.13758, T_eff = 10 800 s, per-sea-state
/// damage 1e-6 and 4e-6 give an annual damage of 2.48463504e-3 (Julian year, 31 557 600 s).
async fn lifetime_view_reproduces_the_reference_annual_damage(backend: Backend) {
    let Some(ts) = open_store(backend, QueuePolicy::default()).await else {
        return;
    };
    let id = campaign(&ts.store, "lifetime").await;
    let sea_states = ts
        .store
        .insert_sea_states(
            id,
            &[
                NewSeaState {
                    index: 0,
                    hs_m: 2.75,
                    tp_s: 8.5,
                    occurrence_fraction: 0.30,
                    seeds: vec![11, 12],
                    heading_deg: 0.0,
                    sector: None,
                    wave_energy_kept: None,
                },
                NewSeaState {
                    index: 1,
                    hs_m: 8.75,
                    tp_s: 16.5,
                    occurrence_fraction: 0.13758,
                    seeds: vec![13, 14],
                    heading_deg: 0.0,
                    sector: None,
                    wave_energy_kept: None,
                },
            ],
        )
        .await
        .unwrap();
    // Two seeds per sea state whose mean is the reference damage.
    let per_seed = [(0, 0.5e-6), (0, 1.5e-6), (1, 3.0e-6), (1, 5.0e-6)];
    let plan: Vec<PlannedJob> = per_seed
        .iter()
        .map(|&(s, _)| PlannedJob {
            sea_state: Some(sea_states[s]),
            ..PlannedJob::new(JobKind::Strand, json!({}))
        })
        .collect();
    let mut test_plan = test_job(TestPayload::Succeed);
    test_plan.sea_state = Some(sea_states[0]);
    let mut all = plan.clone();
    all.push(test_plan);
    let jobs = ts.store.insert_plan(id, &all).await.unwrap();
    let worker = ts.store.register_worker(&worker_info(1)).await.unwrap();
    let any = ClaimFilter::default();
    let progress = ts.store.progress(id).await.unwrap();
    assert!((progress.occurrence_planned - 0.43758).abs() < 1e-12);
    assert_eq!(progress.occurrence_covered, 0.0);

    for (seed, &(_, d)) in per_seed.iter().enumerate() {
        let lease = ts.store.claim(&worker, &any).await.unwrap().unwrap();
        assert_eq!(lease.job, jobs[seed]);
        let results = JobResults {
            damage_inputs: vec![damage(0, (seed % 2) as i64, d)],
            ..JobResults::default()
        };
        ts.store.complete(&lease, &results).await.unwrap();
    }
    // The test-kind job may not write users' result rows.
    let lease = ts.store.claim(&worker, &any).await.unwrap().unwrap();
    let refused = ts
        .store
        .complete(
            &lease,
            &JobResults {
                damage_inputs: vec![damage(0, 0, 1.0)],
                ..JobResults::default()
            },
        )
        .await;
    assert!(matches!(refused, Err(StoreError::TestKindResults(j)) if j == lease.job));
    ts.store
        .complete(&lease, &JobResults::default())
        .await
        .unwrap();

    let lifetime = ts.store.lifetime_damage(id).await.unwrap();
    assert_eq!(lifetime.len(), 1);
    let reference = 2.48463504e-3;
    let relative = (lifetime[0].annual_damage - reference).abs() / reference;
    assert!(
        relative < 1e-8,
        "annual damage {} vs {reference}",
        lifetime[0].annual_damage
    );
    assert!((lifetime[0].occurrence_covered - 0.43758).abs() < 1e-12);
    assert_eq!(lifetime[0].sea_states, 2);
    let progress = ts.store.progress(id).await.unwrap();
    assert!((progress.occurrence_covered - 0.43758).abs() < 1e-12);
    ts.finish().await;
}

/// A class row of fretting damage rate `rate` (most damaged contact; half of it for the mean
/// over the class).
fn class_row(seed_index: i64, rate: f64) -> ClassDamageInput {
    ClassDamageInput {
        hot_spot_index: 0,
        layer_interface: 2,
        angular_position: AngularPosition::NeutralAxis,
        seed_index,
        effective_duration_s: 100.0,
        contacts: 3,
        fretting_damage_rate_max_per_s: rate,
        fretting_damage_rate_mean_per_s: 0.5 * rate,
        stick_cycles_per_hour: 0.0,
        partial_slip_cycles_per_hour: 10.0,
        gross_slip_cycles_per_hour: 0.0,
        ruiz_f1_max: 1.0,
        ruiz_f2_max: 1.0,
        peak_pressure_max_pa: 1.0e9,
        slip_amplitude_max_m: 1.0e-6,
        histogram: json!({}),
        rope_tn_damage_rate_max_per_s: 2.0 * rate,
        rope_tn_damage_rate_mean_per_s: rate,
        wear_power_max_w: 0.0,
    }
}

/// Seeds of known values give the mean, standard deviation and lifetime band by hand:
/// sea state 0 (p = 0.2) has three seeds, sea state 1 (p = 0.1) one.
async fn seed_spread_and_lifetime_band_of_known_seeds(backend: Backend) {
    let Some(ts) = open_store(backend, QueuePolicy::default()).await else {
        return;
    };
    let id = campaign(&ts.store, "seeds").await;
    let sea_states = ts
        .store
        .insert_sea_states(
            id,
            &[
                NewSeaState {
                    index: 0,
                    hs_m: 6.25,
                    tp_s: 14.0,
                    occurrence_fraction: 0.2,
                    seeds: vec![1, 2, 3],
                    heading_deg: 0.0,
                    sector: None,
                    wave_energy_kept: None,
                },
                NewSeaState {
                    index: 1,
                    hs_m: 2.25,
                    tp_s: 8.0,
                    occurrence_fraction: 0.1,
                    seeds: vec![4],
                    heading_deg: 0.0,
                    sector: None,
                    wave_energy_kept: None,
                },
            ],
        )
        .await
        .unwrap();
    // (sea state, seed, fretting rate 1/s, T-N damage over 100 s)
    let seeds = [
        (0, 0, 1e-9, 1e-6),
        (0, 1, 2e-9, 3e-6),
        (0, 2, 6e-9, 5e-6),
        (1, 0, 4e-9, 2e-6),
    ];
    let plan: Vec<PlannedJob> = seeds
        .iter()
        .map(|&(s, ..)| PlannedJob {
            sea_state: Some(sea_states[s]),
            ..PlannedJob::new(JobKind::Strand, json!({}))
        })
        .collect();
    ts.store.insert_plan(id, &plan).await.unwrap();
    let worker = ts.store.register_worker(&worker_info(1)).await.unwrap();
    for &(_, seed, rate, tn) in &seeds {
        let lease = ts
            .store
            .claim(&worker, &ClaimFilter::default())
            .await
            .unwrap()
            .unwrap();
        let results = JobResults {
            damage_inputs: vec![DamageInput {
                hot_spot_index: 0,
                measure: "tn_test".into(),
                seed_index: seed,
                effective_duration_s: 100.0,
                damage: tn,
                details: json!({}),
            }],
            class_damage_inputs: vec![class_row(seed, rate)],
            ..JobResults::default()
        };
        ts.store.complete(&lease, &results).await.unwrap();
    }
    let year = 31_557_600.0;
    let close = |got: f64, want: f64| (got - want).abs() <= 1e-12 * want.abs();
    // per sea state: fretting_max mean 3e-9, SD √7e-9 (deviations -2, -1, 3; 14 / 2);
    // fretting_mean half of it, rope_tn_max twice, rope_tn_mean equal (the rows of
    // `class_row`); one seed: no SD
    let cells = ts.store.sea_state_class_damage(id).await.unwrap();
    assert_eq!(cells.len(), 2 * 4, "2 sea states × 4 fretting measures");
    for c in &cells {
        let scale = match c.measure.as_str() {
            "fretting_max" => 1.0,
            "fretting_mean" => 0.5,
            "rope_tn_max" => 2.0,
            "rope_tn_mean" => 1.0,
            other => panic!("unexpected measure {other}"),
        };
        if c.sea_state_index == 0 {
            assert_eq!(c.seeds, 3);
            assert!(close(c.damage_rate_per_s, scale * 3e-9), "{c:?}");
            let sd = c.damage_rate_sd.unwrap();
            assert!(close(sd, scale * 7f64.sqrt() * 1e-9), "{c:?}");
        } else {
            assert_eq!(c.seeds, 1);
            assert!(close(c.damage_rate_per_s, scale * 4e-9), "{c:?}");
            assert_eq!(c.damage_rate_sd, None);
        }
    }
    // T-N rates 1e-8, 3e-8, 5e-8: mean 3e-8, SD 2e-8
    let tn = ts.store.sea_state_damage(id).await.unwrap();
    assert_eq!(tn.len(), 2);
    assert!(close(tn[0].damage_rate_per_s, 3e-8));
    assert!(close(tn[0].damage_rate_sd.unwrap(), 2e-8));
    assert_eq!(tn[1].damage_rate_sd, None);
    // D = year (0.2 · 3e-9 + 0.1 · 4e-9) = year · 1e-9; SE = 0.2 · year · √(7 / 3) e-9, from
    // sea state 0 alone (two degrees of freedom); sea state 1 has no spread
    let lifetime = ts.store.lifetime_class_damage(id).await.unwrap();
    let max = lifetime
        .iter()
        .find(|l| l.measure == "fretting_max")
        .unwrap();
    assert!(close(max.annual_damage, year * 1e-9));
    let se = 0.2 * year * (7.0f64 / 3.0).sqrt() * 1e-9;
    assert!(close(max.band.annual_damage_se, se), "{max:?}");
    assert!(close(max.band.annual_damage_high, year * 1e-9 + 2.0 * se));
    assert!(close(max.band.annual_damage_low, year * 1e-9 - 2.0 * se));
    assert!(close(max.band.effective_dof.unwrap(), 2.0));
    assert_eq!(
        (
            max.band.sea_states_with_spread,
            max.band.sea_states_without_spread
        ),
        (1, 1)
    );
    let mean = lifetime
        .iter()
        .find(|l| l.measure == "fretting_mean")
        .unwrap();
    assert!(close(mean.band.annual_damage_se, 0.5 * se));
    // T-N: D = year (0.2 · 3e-8 + 0.1 · 2e-8) = 8e-9 year, SE = 0.2 · year · 2e-8 / √3
    let tn_life = ts.store.lifetime_damage(id).await.unwrap();
    assert_eq!(tn_life.len(), 1);
    let (d, se) = (8e-9 * year, 0.2 * year * 2e-8 / 3f64.sqrt());
    assert!(close(tn_life[0].annual_damage, d));
    assert!(close(tn_life[0].band.annual_damage_se, se));
    assert!(close(tn_life[0].band.annual_damage_low, d - 2.0 * se));
    assert!(close(tn_life[0].band.annual_damage_high, d + 2.0 * se));
    ts.finish().await;
}

/// Settling: listed jobs still ready or blocked become done with their result, no rows and no
/// attempt, in one transaction, and their dependents are unblocked; a running job is left to
/// its worker, and settling again changes nothing.
async fn settled_jobs_end_at_once_and_unblock_their_dependents(backend: Backend) {
    let Some(ts) = open_store(backend, QueuePolicy::default()).await else {
        return;
    };
    let id = campaign(&ts.store, "settle").await;
    // 0 ← 1 ← 2, 1 ← 4, 0 ← 3 ← 5
    let mut plan: Vec<PlannedJob> = (0..6).map(|_| test_job(TestPayload::Succeed)).collect();
    plan[1].depends_on = vec![0];
    plan[2].depends_on = vec![1];
    plan[3].depends_on = vec![0];
    plan[4].depends_on = vec![1];
    plan[5].depends_on = vec![3];
    let jobs = ts.store.insert_plan(id, &plan).await.unwrap();
    let worker = ts.store.register_worker(&worker_info(1)).await.unwrap();
    let any = ClaimFilter::default();
    let first = ts.store.claim(&worker, &any).await.unwrap().unwrap();
    assert_eq!(first.job, jobs[0]);
    ts.store
        .complete(&first, &JobResults::default())
        .await
        .unwrap();
    // 1 and 3 are ready; 1 is claimed
    let running = ts.store.claim(&worker, &any).await.unwrap().unwrap();
    assert_eq!(running.job, jobs[1]);
    let result = |k: usize| json!({ "selected": false, "settled_by": k });
    let settled = ts
        .store
        .settle(&[
            (jobs[3], result(3)),
            (jobs[1], result(1)),
            (jobs[2], result(2)),
        ])
        .await
        .unwrap();
    // 2 waits on the running 1 but its answer is known: settled too
    assert_eq!(settled, vec![jobs[2], jobs[3]]);
    let states = |records: Vec<moorfret_store::JobRecord>| -> Vec<JobState> {
        jobs.iter()
            .map(|id| records.iter().find(|j| j.id == *id).unwrap().state)
            .collect()
    };
    assert_eq!(
        states(ts.store.jobs_of_campaign(id).await.unwrap()),
        [
            JobState::Done,
            JobState::Running,
            JobState::Done,
            JobState::Done,
            JobState::Blocked,
            JobState::Ready
        ]
    );
    for k in [2, 3] {
        let results = ts.store.results_of(jobs[k]).await.unwrap();
        assert_eq!(results.result, result(k));
        assert!(results.class_damage_inputs.is_empty() && results.damage_inputs.is_empty());
    }
    let attempts = ts.store.attempts_of_campaign(id).await.unwrap();
    assert!(attempts
        .iter()
        .all(|a| a.job != jobs[2] && a.job != jobs[3]));
    // the running job completes by itself and unblocks 4; settling again changes nothing
    ts.store
        .complete(&running, &JobResults::default())
        .await
        .unwrap();
    let again = ts
        .store
        .settle(&[(jobs[1], result(9)), (jobs[3], result(9))])
        .await
        .unwrap();
    assert!(again.is_empty());
    assert_eq!(
        ts.store.results_of(jobs[3]).await.unwrap().result,
        result(3)
    );
    assert_eq!(
        states(ts.store.jobs_of_campaign(id).await.unwrap())[4],
        JobState::Ready
    );
    ts.finish().await;
}

async fn claim_filter_respects_kind_and_expected_cost(backend: Backend) {
    let Some(ts) = open_store(backend, QueuePolicy::default()).await else {
        return;
    };
    let id = campaign(&ts.store, "filter").await;
    let mut long = PlannedJob::new(JobKind::Strand, json!({}));
    long.expected_cost_s = 600.0;
    long.priority = 9;
    let mut short = PlannedJob::new(JobKind::Strand, json!({}));
    short.expected_cost_s = 60.0;
    let global = PlannedJob::new(JobKind::Global, json!({}));
    let jobs = ts
        .store
        .insert_plan(id, &[long, short, global])
        .await
        .unwrap();
    let worker = ts.store.register_worker(&worker_info(1)).await.unwrap();
    let only_global = ClaimFilter {
        kinds: vec![JobKind::Global],
        max_expected_cost_s: None,
    };
    let lease = ts
        .store
        .claim(&worker, &only_global)
        .await
        .unwrap()
        .unwrap();
    assert_eq!(lease.job, jobs[2]);
    assert!(ts
        .store
        .claim(&worker, &only_global)
        .await
        .unwrap()
        .is_none());
    let little_time = ClaimFilter {
        kinds: vec![],
        max_expected_cost_s: Some(100.0),
    };
    let lease = ts
        .store
        .claim(&worker, &little_time)
        .await
        .unwrap()
        .unwrap();
    assert_eq!(
        lease.job, jobs[1],
        "the long job does not fit the remaining time"
    );
    let unregistered = WorkerId("nobody".into());
    let refused = ts.store.claim(&unregistered, &ClaimFilter::default()).await;
    assert!(matches!(
        refused,
        Err(StoreError::InvalidParameter {
            field: "worker",
            ..
        })
    ));
    assert_eq!(
        ts.store.job(jobs[0]).await.unwrap().state,
        JobState::Ready,
        "rolled back"
    );
    ts.finish().await;
}

/// The bytes of the SQLite file at `location` once its write-ahead log is gone and the file
/// has not changed over four successive polls 50 ms apart (at most 30 s in all).
async fn settled_bytes(location: &str) -> Vec<u8> {
    let wal = format!("{location}-wal");
    let mut last = std::fs::read(location).unwrap();
    let mut unchanged = 0;
    for _ in 0..600 {
        tokio::time::sleep(std::time::Duration::from_millis(50)).await;
        let now = std::fs::read(location).unwrap();
        let log_gone = !std::path::Path::new(&wal).exists();
        unchanged = if now == last && log_gone {
            unchanged + 1
        } else {
            0
        };
        if unchanged == 4 {
            return now;
        }
        last = now;
    }
    last
}

async fn newer_schema_is_refused_and_left_untouched(backend: Backend) {
    let Some(ts) = open_store(backend, QueuePolicy::default()).await else {
        return;
    };
    let supported = ts.store.supported_schema_version();
    assert_eq!(ts.store.schema_version().await.unwrap(), supported);
    let id = campaign(&ts.store, "kept").await;
    ts.store
        .insert_plan(id, &[test_job(TestPayload::Succeed)])
        .await
        .unwrap();
    let newer = (supported + 1).to_string();
    let sql = "UPDATE schema_info SET value = $1 WHERE key = 'schema_version'";
    raw_execute(&ts, backend, sql, Some(newer)).await;
    ts.store.close().await;
    let file_before = match backend {
        Backend::Sqlite => {
            // the last connection folds its log into the file on a thread of its own after the
            // pool is closed: wait until the log is gone and the file has kept its bytes for
            // a while (up to 30 s on a loaded machine), so that the bytes compared are settled
            Some(settled_bytes(&ts.location).await)
        }
        Backend::Postgres => None,
    };
    match Store::open(&ts.location, ts.options.clone()).await {
        Err(StoreError::SchemaTooNew {
            found,
            supported: s,
        }) => {
            assert_eq!((found, s), (supported + 1, supported));
        }
        other => panic!("expected SchemaTooNew, got {other:?}"),
    }
    if let Some(before) = file_before {
        assert_eq!(
            std::fs::read(&ts.location).unwrap(),
            before,
            "database file modified"
        );
    }
    // Drop the schema, which the store cannot open to clean up.
    if backend == Backend::Postgres {
        let schema = ts.options.postgres_schema.clone().unwrap();
        let drop = format!("DROP SCHEMA {schema} CASCADE");
        raw_execute(&ts, backend, &drop, None::<String>).await;
    }
}

/// Names of the tables in PostgreSQL schema `schema`, sorted, and whether the schema exists.
async fn postgres_tables(url: &str, schema: &str) -> (bool, Vec<String>) {
    use sqlx::Connection;
    let mut conn = sqlx::PgConnection::connect(url).await.unwrap();
    let exists: i64 = sqlx::query_scalar(
        "SELECT COUNT(*) FROM information_schema.schemata WHERE schema_name = $1",
    )
    .bind(schema)
    .fetch_one(&mut conn)
    .await
    .unwrap();
    let tables: Vec<String> = sqlx::query_scalar(
        "SELECT table_name::text FROM information_schema.tables WHERE table_schema = $1 \
         ORDER BY table_name",
    )
    .bind(schema)
    .fetch_all(&mut conn)
    .await
    .unwrap();
    conn.close().await.unwrap();
    (exists > 0, tables)
}

/// Opening an existing store (every command but `campaign launch`) on a PostgreSQL schema
/// that holds another program's table, or on a schema that does not exist, is refused and
/// creates nothing: no moorfret table, no schema.
#[tokio::test]
async fn a_postgres_database_without_a_store_is_refused_untouched() {
    use sqlx::Connection;
    let url = postgres_url();
    if !postgres_reachable(&url).await {
        return;
    }
    let foreign = format!("t_{}", uuid::Uuid::new_v4().simple());
    let missing = format!("t_{}", uuid::Uuid::new_v4().simple());
    let mut conn = sqlx::PgConnection::connect(&url).await.unwrap();
    for sql in [
        format!("CREATE SCHEMA {foreign}"),
        format!("CREATE TABLE {foreign}.notes (id BIGINT PRIMARY KEY, body TEXT)"),
    ] {
        sqlx::query(&sql).execute(&mut conn).await.unwrap();
    }
    for schema in [&foreign, &missing] {
        let options = StoreOptions {
            postgres_schema: Some(schema.clone()),
            ..StoreOptions::default()
        };
        let before = postgres_tables(&url, schema).await;
        match Store::open_existing(&url, options.clone()).await {
            Err(StoreError::InvalidLocation { reason, .. }) => {
                assert!(reason.contains("no moorfret store"), "{reason}");
            }
            other => panic!("{schema}: expected InvalidLocation, got {other:?}"),
        }
        assert!(
            matches!(Store::open_if_present(&url, options).await, Ok(None)),
            "{schema}"
        );
        assert_eq!(postgres_tables(&url, schema).await, before, "{schema}");
    }
    assert_eq!(
        postgres_tables(&url, &foreign).await,
        (true, vec!["notes".to_owned()])
    );
    assert!(!postgres_tables(&url, &missing).await.0);
    sqlx::query(&format!("DROP SCHEMA {foreign} CASCADE"))
        .execute(&mut conn)
        .await
        .unwrap();
    conn.close().await.unwrap();
}

#[tokio::test]
async fn opening_a_missing_path_creates_the_store_with_its_directories() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("new/sub/dir/campaign.sqlite");
    let location = format!("sqlite://{}", path.display());
    let store = Store::open(&location, StoreOptions::default())
        .await
        .unwrap();
    assert!(path.exists());
    assert_eq!(
        store.schema_version().await.unwrap(),
        store.supported_schema_version()
    );
    store.close().await;
    // Reopening an up-to-date store applies nothing.
    let again = Store::open(&location, StoreOptions::default())
        .await
        .unwrap();
    assert_eq!(
        again.schema_version().await.unwrap(),
        again.supported_schema_version()
    );
    again.close().await;
}

/// Several processes opening one new SQLite store at once (three `campaign launch` on a new
/// file) migrate it once: every open succeeds and finds the schema current.
#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn concurrent_first_opens_of_a_new_store_all_succeed() {
    for round in 0..5 {
        let dir = tempfile::tempdir().unwrap();
        let location = format!("sqlite://{}", dir.path().join("new.sqlite").display());
        let opens: Vec<_> = (0..6)
            .map(|_| {
                let location = location.clone();
                tokio::spawn(async move { Store::open(&location, StoreOptions::default()).await })
            })
            .collect();
        for open in opens {
            let store = open
                .await
                .unwrap()
                .unwrap_or_else(|e| panic!("round {round}: {e}"));
            assert_eq!(
                store.schema_version().await.unwrap(),
                store.supported_schema_version()
            );
            store.close().await;
        }
    }
}

/// A closed PostgreSQL port: after the pool's retries, the error says why it could not connect.
#[tokio::test]
async fn unreachable_postgres_says_why() {
    let err = match Store::open(
        "postgres://postgres@127.0.0.1:1/test",
        StoreOptions::default(),
    )
    .await
    {
        Ok(_) => panic!("nothing listens on port 1"),
        Err(e) => e.to_string(),
    };
    assert!(err.to_lowercase().contains("refused"), "{err}");
}

/// A store whose directory cannot be written is refused naming the directory and the reason
/// (SQLite itself says only "unable to open database file").
#[tokio::test]
async fn a_store_in_an_unwritable_directory_names_the_directory() {
    use std::os::unix::fs::PermissionsExt;
    let dir = tempfile::tempdir().unwrap();
    let locked = dir.path().join("locked");
    std::fs::create_dir(&locked).unwrap();
    std::fs::set_permissions(&locked, std::fs::Permissions::from_mode(0o555)).unwrap();
    // the superuser writes there anyway: then a directory where nobody creates files (sysfs)
    let target = if std::fs::write(locked.join("probe"), b"").is_ok() {
        std::path::PathBuf::from("/sys")
    } else {
        locked.clone()
    };
    let path = target.join("campaign.sqlite");
    match Store::open(path.to_str().unwrap(), StoreOptions::default()).await {
        Err(e @ StoreError::Unwritable { .. }) => {
            let text = e.to_string();
            assert!(text.contains("not writable"), "{text}");
            assert!(text.contains(&format!("{target:?}")), "{text}");
        }
        other => panic!("expected Unwritable, got {other:?}"),
    }
    assert!(!path.exists());
    std::fs::set_permissions(&locked, std::fs::Permissions::from_mode(0o755)).unwrap();
}

#[tokio::test]
async fn opening_garbage_is_refused_with_a_clear_error() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("notes.sqlite");
    let garbage = b"these are field notes, not a database\n".repeat(200);
    std::fs::write(&path, &garbage).unwrap();
    match Store::open(path.to_str().unwrap(), StoreOptions::default()).await {
        Err(StoreError::NotADatabase { path: p, reason }) => {
            assert_eq!(p, path);
            assert!(reason.contains("SQLite header"), "{reason}");
        }
        other => panic!("expected NotADatabase, got {other:?}"),
    }
    assert_eq!(
        std::fs::read(&path).unwrap(),
        garbage,
        "garbage file modified"
    );
}

#[test]
fn artifacts_round_trip_and_identical_content_is_stored_once() {
    let dir = tempfile::tempdir().unwrap();
    let store = ArtifactStore::open(dir.path().join("artifacts")).unwrap();
    let bytes: Vec<u8> = (0..100_000_u32).flat_map(|i| i.to_le_bytes()).collect();
    let first = store.put(ArtifactRole::HotSpotSeries(0), &bytes).unwrap();
    let second = store.put(ArtifactRole::HotSpotSeries(1), &bytes).unwrap();
    assert_eq!(first.sha256, second.sha256);
    assert_eq!(first.size_bytes, 400_000);
    // sha256 of the empty input (FIPS 180-4 test vector).
    let empty = store.put(ArtifactRole::ContactRecords, b"").unwrap();
    assert_eq!(
        empty.sha256,
        "e3b0c44298fc1c149afbf4c8996fb92427ae41e4649b934ca495991b7852b855"
    );
    assert_eq!(store.get(&first.sha256).unwrap(), bytes);
    let shard = store.dir().join(&first.sha256[..2]);
    let names: Vec<_> = std::fs::read_dir(&shard)
        .unwrap()
        .map(|e| e.unwrap().file_name())
        .collect();
    assert_eq!(
        names,
        vec![std::ffi::OsString::from(&first.sha256)],
        "one file, no temporaries"
    );
    assert!(matches!(
        store.get(&"0".repeat(64)),
        Err(StoreError::ArtifactMissing(_))
    ));
    assert!(matches!(
        store.get("../../etc"),
        Err(StoreError::InvalidParameter { .. })
    ));
}

/// The check made before a store is opened creates nothing: an absent directory passes and
/// stays absent, a writable one passes, a file in the way is refused.
#[test]
fn existing_artifact_path_is_checked_without_creating_anything() {
    let dir = tempfile::tempdir().unwrap();
    let absent = ArtifactStore::path_beside_database(&dir.path().join("c.sqlite"));
    assert!(absent.ends_with("c.sqlite.artifacts"));
    ArtifactStore::check_existing(&absent).unwrap();
    assert!(!absent.exists());
    std::fs::create_dir(&absent).unwrap();
    ArtifactStore::check_existing(&absent).unwrap();
    assert_eq!(std::fs::read_dir(&absent).unwrap().count(), 0);
    std::fs::remove_dir(&absent).unwrap();
    std::fs::write(&absent, b"in the way").unwrap();
    match ArtifactStore::check_existing(&absent) {
        Err(StoreError::ArtifactIo { path, source }) => {
            assert_eq!(path, absent);
            assert_eq!(source.kind(), std::io::ErrorKind::AlreadyExists);
        }
        other => panic!("expected ArtifactIo, got {other:?}"),
    }
    assert_eq!(std::fs::read(&absent).unwrap(), b"in the way");
}

#[test]
fn corrupted_artifact_is_refused_on_read_and_repaired_by_a_new_write() {
    let dir = tempfile::tempdir().unwrap();
    let store = ArtifactStore::beside_database(&dir.path().join("c.sqlite")).unwrap();
    assert!(store.dir().ends_with("c.sqlite.artifacts"));
    let reference = store
        .put(ArtifactRole::Checkpoint, b"solver state")
        .unwrap();
    let path = store.dir().join(&reference.path);
    std::fs::write(&path, b"solver stat\0").unwrap();
    match store.get(&reference.sha256) {
        Err(StoreError::ArtifactCorrupt { expected, actual }) => {
            assert_eq!(expected, reference.sha256);
            assert_ne!(actual, expected);
        }
        other => panic!("expected ArtifactCorrupt, got {other:?}"),
    }
    store
        .put(ArtifactRole::Checkpoint, b"solver state")
        .unwrap();
    assert_eq!(store.get(&reference.sha256).unwrap(), b"solver state");
}

#[test]
fn interrupted_writes_leave_only_temporaries_which_are_never_read() {
    let dir = tempfile::tempdir().unwrap();
    let store = ArtifactStore::open(dir.path()).unwrap();
    let bytes = vec![7_u8; 4096];
    let reference = store.put(ArtifactRole::HotSpotSeries(0), &bytes).unwrap();
    // A writer killed before its rename leaves a partial temporary beside the real files.
    let shard = store.dir().join(&reference.sha256[..2]);
    std::fs::write(shard.join(".tmp-killed"), &bytes[..100]).unwrap();
    assert_eq!(store.get(&reference.sha256).unwrap(), bytes);
    assert_eq!(store.remove_stale_temporaries().unwrap(), 1);
    assert_eq!(std::fs::read_dir(&shard).unwrap().count(), 1);
}

#[test]
fn concurrent_writers_and_readers_never_see_a_partial_artifact() {
    let dir = tempfile::tempdir().unwrap();
    let store = ArtifactStore::open(dir.path()).unwrap();
    let bytes: Vec<u8> = (0..2_000_000_u32).map(|i| (i % 251) as u8).collect();
    let sha256 = hex::encode(<sha2::Sha256 as sha2::Digest>::digest(&bytes));
    std::thread::scope(|scope| {
        for _ in 0..4 {
            scope.spawn(|| {
                let reference = store.put(ArtifactRole::ReducedStrand, &bytes).unwrap();
                assert_eq!(reference.sha256, sha256);
            });
        }
        for _ in 0..4 {
            scope.spawn(|| {
                for _ in 0..50 {
                    // Every read either finds nothing yet or the whole, verified content.
                    match store.get(&sha256) {
                        Ok(read) => assert_eq!(read.len(), bytes.len()),
                        Err(StoreError::ArtifactMissing(_)) => {}
                        Err(other) => panic!("reader saw {other}"),
                    }
                }
            });
        }
    });
    assert_eq!(store.get(&sha256).unwrap(), bytes);
    assert_eq!(store.remove_stale_temporaries().unwrap(), 0);
}

/// Says why the PostgreSQL half of a test is skipped; fails instead where the environment
/// requires the services (`MOORFRET_REQUIRE_SERVICES`, set by `.ci/run`).
fn skip_postgres(reason: &str) {
    if std::env::var_os("MOORFRET_REQUIRE_SERVICES").is_some() {
        panic!("PostgreSQL is required here (MOORFRET_REQUIRE_SERVICES is set): {reason}");
    }
    eprintln!("SKIPPED (PostgreSQL): {reason}");
}
