//! Schema version check and migration, written once for both backends.
//!
//! Mounted twice, as `sqlite::schema` and `postgres::schema`; each parent defines `Db`,
//! `DIALECT` and `MIGRATOR`.

use sqlx::Pool;

use super::{Db, DIALECT, MIGRATOR};
use crate::error::StoreError;

type Result<T> = std::result::Result<T, StoreError>;

/// Newest schema version this binary embeds.
pub(crate) fn supported_version() -> i64 {
    MIGRATOR.iter().map(|m| m.version).max().unwrap_or(0)
}

/// Schema version recorded in the database (0 for an empty database).
pub(crate) async fn found_version(pool: &Pool<Db>) -> Result<i64> {
    const OP: &str = "read schema version";
    let mut found = 0_i64;
    let has_table = |name: &'static str| async move {
        sqlx::query_scalar::<_, i64>(DIALECT.table_exists_sql)
            .bind(name)
            .fetch_one(pool)
            .await
            .map(|n| n > 0)
            .map_err(StoreError::db(OP))
    };
    if has_table("_sqlx_migrations").await? {
        let applied: Option<i64> = sqlx::query_scalar("SELECT MAX(version) FROM _sqlx_migrations")
            .fetch_one(pool)
            .await
            .map_err(StoreError::db(OP))?;
        found = found.max(applied.unwrap_or(0));
    }
    if has_table("schema_info").await? {
        let recorded: Option<String> =
            sqlx::query_scalar("SELECT value FROM schema_info WHERE key = 'schema_version'")
                .fetch_optional(pool)
                .await
                .map_err(StoreError::db(OP))?;
        if let Some(text) = recorded {
            let version = text.parse::<i64>().map_err(|_| StoreError::UnknownValue {
                field: "schema_info.schema_version",
                value: text.clone(),
            })?;
            found = found.max(version);
        }
    }
    Ok(found)
}

/// Refuses a database from a newer binary (before writing anything), then applies the
/// embedded migrations it lacks.
pub(crate) async fn prepare_schema(pool: &Pool<Db>) -> Result<()> {
    let supported = supported_version();
    let found = found_version(pool).await?;
    if found > supported {
        return Err(StoreError::SchemaTooNew { found, supported });
    }
    if found < supported {
        MIGRATOR.run(pool).await?;
    }
    Ok(())
}
