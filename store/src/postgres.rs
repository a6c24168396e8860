//! PostgreSQL backend for clusters: the same schema and behaviour as SQLite.
//!
//! Claims lock the chosen row with `FOR UPDATE SKIP LOCKED`, so concurrent claimers pass over
//! each other's rows instead of queueing on them. With [`super::Clock::Database`] lease times
//! come from the server clock (`moorfret_now_ms()`), so hosts with skewed clocks agree on
//! expiry. A store may live in its own schema (`search_path`), which is created if missing.

use sqlx::migrate::Migrator;
use sqlx::postgres::{PgConnectOptions, PgPoolOptions};
use sqlx::Pool;
use sqlx::{ConnectOptions, Connection, Postgres as Db};

use super::dialect::{Dialect, POSTGRES};
use super::error::StoreError;

const DIALECT: Dialect = POSTGRES;

/// Migrations of the PostgreSQL schema, embedded at compile time.
pub(crate) static MIGRATOR: Migrator = sqlx::migrate!("../migrations/postgres");

type Result<T> = std::result::Result<T, StoreError>;

// The queue and schema code is shared text, mounted once per backend (see `queue/mod.rs`).
#[allow(clippy::duplicate_mod)]
#[path = "queue/mod.rs"]
pub(crate) mod queue;
#[allow(clippy::duplicate_mod)]
#[path = "schema.rs"]
mod schema;

pub(crate) use queue::Queue;
pub(crate) use schema::{found_version, prepare_schema, supported_version};

/// Connects a pool of `max_connections` to `url`, in `schema` if given (created if missing).
pub(crate) async fn connect(
    url: &str,
    schema: Option<&str>,
    max_connections: u32,
) -> Result<Pool<Db>> {
    connect_in(url, schema, max_connections, true)
        .await?
        .ok_or_else(|| StoreError::InvalidLocation {
            location: url.to_owned(),
            reason: "the schema could not be created".into(),
        })
}

/// The moorfret store at `url` (in `schema` if given), or `None` when the schema is missing or
/// holds no moorfret tables; nothing is created.
pub(crate) async fn open_if_present(
    url: &str,
    schema: Option<&str>,
    max_connections: u32,
) -> Result<Option<Pool<Db>>> {
    let Some(pool) = connect_in(url, schema, max_connections, false).await? else {
        return Ok(None);
    };
    match schema::is_moorfret_store(&pool).await {
        Ok(true) => Ok(Some(pool)),
        Ok(false) => {
            pool.close().await;
            Ok(None)
        }
        Err(err) => {
            pool.close().await;
            Err(err)
        }
    }
}

/// A pool on `url` in `schema` (created when missing if `create`, else `None`).
async fn connect_in(
    url: &str,
    schema: Option<&str>,
    max_connections: u32,
    create: bool,
) -> Result<Option<Pool<Db>>> {
    let invalid = |reason: String| StoreError::InvalidLocation {
        location: url.to_owned(),
        reason,
    };
    let mut options: PgConnectOptions = url.parse().map_err(|e| invalid(format!("{e}")))?;
    if let Some(schema) = schema {
        let valid = !schema.is_empty()
            && schema
                .chars()
                .all(|c| c.is_ascii_lowercase() || c.is_ascii_digit() || c == '_')
            && !schema.starts_with(|c: char| c.is_ascii_digit());
        if !valid {
            return Err(StoreError::InvalidParameter {
                field: "postgres_schema",
                value: schema.to_owned(),
                reason: "must be a lower-case identifier ([a-z_][a-z0-9_]*)",
            });
        }
        let mut conn = options
            .connect()
            .await
            .map_err(StoreError::db("open store"))?;
        let present = if create {
            sqlx::query(&format!("CREATE SCHEMA IF NOT EXISTS {schema}"))
                .execute(&mut conn)
                .await
                .map_err(StoreError::db("create schema"))?;
            true
        } else {
            sqlx::query_scalar::<_, i64>(
                "SELECT COUNT(*) FROM information_schema.schemata WHERE schema_name = $1",
            )
            .bind(schema)
            .fetch_one(&mut conn)
            .await
            .map_err(StoreError::db("look for the schema"))?
                > 0
        };
        conn.close().await.map_err(StoreError::db("open store"))?;
        if !present {
            return Ok(None);
        }
        options = options.options([("search_path", schema)]);
    }
    match PgPoolOptions::new()
        .max_connections(max_connections)
        .connect_with(options.clone())
        .await
    {
        // The pool retries until its acquire timeout, then says only that it timed out; one
        // direct attempt says why (connection refused, authentication, unknown database).
        Err(sqlx::Error::PoolTimedOut) => match options.connect().await {
            Err(cause) => Err(StoreError::db("open store")(cause)),
            Ok(conn) => {
                let _ = conn.close().await;
                Err(StoreError::db("open store")(sqlx::Error::PoolTimedOut))
            }
        },
        connected => connected.map(Some).map_err(StoreError::db("open store")),
    }
}

/// Drops a schema and everything in it (test clean-up).
pub(crate) async fn drop_schema(pool: &Pool<Db>, schema: &str) -> Result<()> {
    sqlx::query(&format!("DROP SCHEMA IF EXISTS {schema} CASCADE"))
        .execute(pool)
        .await
        .map_err(StoreError::db("drop schema"))?;
    Ok(())
}
