//! The few SQL differences between the SQLite and PostgreSQL backends.
//!
//! Everything else (placeholders `$n`, `RETURNING`, recursive CTEs, partial indexes) is shared
//! text in `queue/`.

/// SQL fragments that differ per backend.
#[derive(Debug, Clone, Copy)]
pub(crate) struct Dialect {
    /// Statement opening a write transaction. SQLite takes the write lock at once
    /// (`BEGIN IMMEDIATE`), so a transaction never fails halfway to upgrade a read lock.
    pub(crate) begin_write: &'static str,
    /// Appended to the claim's inner `SELECT`: PostgreSQL skips rows other claimers hold.
    pub(crate) claim_lock_suffix: &'static str,
    /// Appended to a `SELECT` whose rows the transaction goes on to change: PostgreSQL locks
    /// them; SQLite's `BEGIN IMMEDIATE` already serialises writers.
    pub(crate) row_lock_suffix: &'static str,
    /// Query returning the server clock in ms since the epoch.
    pub(crate) now_ms_sql: &'static str,
    /// Query reserving `$1` new job ids, in increasing order, inside a write transaction.
    pub(crate) reserve_job_ids_sql: &'static str,
    /// Query counting tables named `$1` in the current schema.
    pub(crate) table_exists_sql: &'static str,
    /// Whether the schema is checked and migrated inside one write transaction. sqlx's SQLite
    /// migrator takes no lock, so processes opening a new store at once would each apply the
    /// migrations; PostgreSQL's takes an advisory lock.
    pub(crate) migrate_in_write_transaction: bool,
    /// Released migrations whose text was later edited in comments only: (version, SHA-384 of
    /// the text stores recorded, hex). sqlx refuses to migrate a store whose recorded
    /// checksum differs from the embedded one; these recorded checksums are accepted instead.
    pub(crate) edited_migrations: &'static [(i64, &'static str)],
}

/// SQLite.
pub(crate) const SQLITE: Dialect = Dialect {
    begin_write: "BEGIN IMMEDIATE",
    claim_lock_suffix: "",
    row_lock_suffix: "",
    now_ms_sql: "SELECT CAST(unixepoch('subsec') * 1000 AS INTEGER)",
    // The write lock is held from `BEGIN IMMEDIATE`, so ids above the current maximum stay free.
    reserve_job_ids_sql: "WITH RECURSIVE seq (n) AS \
                          (SELECT 1 WHERE $1 > 0 UNION ALL SELECT n + 1 FROM seq WHERE n < $1) \
                          SELECT (SELECT COALESCE(MAX(id), 0) FROM jobs) + n FROM seq ORDER BY n",
    table_exists_sql: "SELECT COUNT(*) FROM sqlite_master WHERE type = 'table' AND name = $1",
    migrate_in_write_transaction: true,
    // 0001: a comment's reference to the damage documentation
    edited_migrations: &[(
        1,
        "952f0050ed1fce88dcaa21a4d0992e37b5fdea1a23a16ee15f8e1439a38c10a9\
         bb2778d9d91106f864f292dc6460d587",
    )],
};

/// PostgreSQL.
pub(crate) const POSTGRES: Dialect = Dialect {
    begin_write: "BEGIN",
    claim_lock_suffix: " FOR UPDATE SKIP LOCKED",
    row_lock_suffix: " FOR UPDATE",
    now_ms_sql: "SELECT moorfret_now_ms()",
    reserve_job_ids_sql: "SELECT nextval(pg_get_serial_sequence('jobs', 'id')) AS id \
                          FROM generate_series(1, $1) ORDER BY id",
    table_exists_sql: "SELECT COUNT(*) FROM information_schema.tables \
                       WHERE table_schema = current_schema() AND table_name = $1",
    migrate_in_write_transaction: false,
    // 0001: a comment's reference to the damage documentation
    edited_migrations: &[(
        1,
        "1b040bec75f5723b891f75300ea5e41f6651820ab91b2f4e4e2094073592d47d\
         69c41e9ba6cea5536443a2791642a0b3",
    )],
};
