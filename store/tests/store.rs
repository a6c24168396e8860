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
        "952f0050ed1fce88dcaa21a4d0992e37b5fdea1a23a16ee15f8e1439a38c10a9bb2778d9d91106f864f292dc6460d587",
    ),
    (
        Backend::Postgres,
        "1b040bec75f5723b891f75300ea5e41f6651820ab91b2f4e4e2094073592d47d69c41e9ba6cea5536443a2791642a0b3",
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
        let hex = RELEASED_0001_SHA384.iter().find(|(b, _)| *b == backend).unwrap().1;
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
                raw_execute(ts, backend, sql, None).await;
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
    assert!(refused.is_err(), "a foreign checksum of migration 1 must be refused");
    if backend == Backend::Postgres {
        let schema = ts.options.postgres_schema.clone().unwrap();
        raw_execute(&ts, backend, &format!("DROP SCHEMA {schema} CASCADE"), None).await;
    }
}

/// Runs `sql` (one statement, `$1` bound to `bind` if given) on the test store's database with
/// a connection of sqlx's own (in the store's schema on PostgreSQL).
async fn raw_execute(ts: &TestStore, backend: Backend, sql: &str, bind: Option<Vec<u8>>) {
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
