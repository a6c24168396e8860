//! Schema version check and migration, written once for both backends.
//!
//! Mounted twice, as `sqlite::schema` and `postgres::schema`; each parent defines `Db`,
//! `DIALECT` and `MIGRATOR`.

use sqlx::{Database, Pool};

use super::{Db, DIALECT, MIGRATOR};
use crate::error::StoreError;

type Result<T> = std::result::Result<T, StoreError>;

/// Newest schema version this binary embeds.
pub(crate) fn supported_version() -> i64 {
    MIGRATOR.iter().map(|m| m.version).max().unwrap_or(0)
}

/// Whether the database holds a moorfret store: its `schema_info` marker (written by the
/// first migration) and its `campaigns` table. Reads only, on the pool's connection.
#[allow(dead_code)] // SQLite asks on a connection of its own (`sqlite::holds_store`)
pub(crate) async fn is_moorfret_store(pool: &Pool<Db>) -> Result<bool> {
    let mut conn = pool
        .acquire()
        .await
        .map_err(StoreError::db("look for the store's tables"))?;
    is_moorfret_store_on(&mut conn).await
}

/// [`is_moorfret_store`] on one connection.
pub(crate) async fn is_moorfret_store_on(conn: &mut <Db as Database>::Connection) -> Result<bool> {
    const OP: &str = "look for the store's tables";
    for table in ["schema_info", "campaigns"] {
        let exists = sqlx::query_scalar::<_, i64>(DIALECT.table_exists_sql)
            .bind(table)
            .fetch_one(&mut *conn)
            .await
            .map_err(StoreError::db(OP))?
            > 0;
        if !exists {
            return Ok(false);
        }
    }
    Ok(true)
}

/// Schema version recorded in the database (0 for an empty database).
pub(crate) async fn found_version(pool: &Pool<Db>) -> Result<i64> {
    let mut conn = pool
        .acquire()
        .await
        .map_err(StoreError::db("read schema version"))?;
    found_version_on(&mut conn).await
}

/// [`found_version`] on one connection (inside its transaction, if any).
async fn found_version_on(conn: &mut <Db as Database>::Connection) -> Result<i64> {
    const OP: &str = "read schema version";
    let mut found = 0_i64;
    for table in ["_sqlx_migrations", "schema_info"] {
        let exists = sqlx::query_scalar::<_, i64>(DIALECT.table_exists_sql)
            .bind(table)
            .fetch_one(&mut *conn)
            .await
            .map_err(StoreError::db(OP))?
            > 0;
        if !exists {
            continue;
        }
        if table == "_sqlx_migrations" {
            let applied: Option<i64> =
                sqlx::query_scalar("SELECT MAX(version) FROM _sqlx_migrations")
                    .fetch_one(&mut *conn)
                    .await
                    .map_err(StoreError::db(OP))?;
            found = found.max(applied.unwrap_or(0));
        } else {
            let recorded: Option<String> =
                sqlx::query_scalar("SELECT value FROM schema_info WHERE key = 'schema_version'")
                    .fetch_optional(&mut *conn)
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
    }
    Ok(found)
}

/// Replaces the checksum a store recorded for a migration whose released text was later
/// edited in comments only ([`crate::dialect::Dialect::edited_migrations`]) by the embedded
/// one, so that sqlx migrates it; any other recorded checksum is left for sqlx to refuse.
async fn accept_edited_migrations(conn: &mut <Db as Database>::Connection) -> Result<()> {
    const OP: &str = "accept the checksum of an edited migration";
    let recorded = sqlx::query_scalar::<_, i64>(DIALECT.table_exists_sql)
        .bind("_sqlx_migrations")
        .fetch_one(&mut *conn)
        .await
        .map_err(StoreError::db(OP))?
        > 0;
    if !recorded {
        return Ok(());
    }
    for &(version, old_hex) in DIALECT.edited_migrations {
        let Some(embedded) = MIGRATOR.iter().find(|m| m.version == version) else {
            continue;
        };
        sqlx::query(
            "UPDATE _sqlx_migrations SET checksum = $1 WHERE version = $2 AND checksum = $3",
        )
        .bind(embedded.checksum.to_vec())
        .bind(version)
        .bind(hex_bytes(old_hex))
        .execute(&mut *conn)
        .await
        .map_err(StoreError::db(OP))?;
    }
    Ok(())
}

/// The bytes of a hexadecimal text (the constants of `edited_migrations`).
fn hex_bytes(hex: &str) -> Vec<u8> {
    hex.as_bytes()
        .chunks(2)
        .filter_map(|pair| u8::from_str_radix(std::str::from_utf8(pair).ok()?, 16).ok())
        .collect()
}

/// Refuses a database from a newer binary (before writing anything), then applies the
/// embedded migrations it lacks. On SQLite the check and the migrations run in one `BEGIN
/// IMMEDIATE` transaction, so that processes opening a new store at once migrate it once: the
/// others wait for the write lock, then find it current.
pub(crate) async fn prepare_schema(pool: &Pool<Db>) -> Result<()> {
    let supported = supported_version();
    if !DIALECT.migrate_in_write_transaction {
        let found = found_version(pool).await?;
        if found > supported {
            return Err(StoreError::SchemaTooNew { found, supported });
        }
        if found < supported {
            let mut conn = pool
                .acquire()
                .await
                .map_err(StoreError::db("migrate the store"))?;
            accept_edited_migrations(&mut conn).await?;
            drop(conn);
            MIGRATOR.run(pool).await?;
        }
        return Ok(());
    }
    // A current store needs no write lock (read commands stay read-only).
    let found = found_version(pool).await?;
    if found > supported {
        return Err(StoreError::SchemaTooNew { found, supported });
    }
    if found == supported {
        return Ok(());
    }
    let mut tx = pool
        .begin_with(DIALECT.begin_write)
        .await
        .map_err(StoreError::db("lock the store to migrate it"))?;
    let found = found_version_on(&mut tx).await?;
    if found > supported {
        return Err(StoreError::SchemaTooNew { found, supported });
    }
    if found < supported {
        accept_edited_migrations(&mut tx).await?;
        // `run_direct` on the transaction's connection: `run(&mut *tx)` makes the future of
        // `Store::open` not `Send` (sqlx's "`Acquire` is not general enough").
        MIGRATOR.run_direct(&mut *tx).await?;
    }
    tx.commit()
        .await
        .map_err(StoreError::db("commit the store's migration"))?;
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn edited_migrations_name_a_released_version_and_a_checksum_not_the_embedded_one() {
        for &(version, hex) in DIALECT.edited_migrations {
            let old = hex_bytes(hex);
            assert_eq!(old.len(), 48, "SHA-384 of migration {version}");
            let embedded = MIGRATOR.iter().find(|m| m.version == version).unwrap();
            assert_ne!(&embedded.checksum[..], &old[..]);
        }
    }
}
