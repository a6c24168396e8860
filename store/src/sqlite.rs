//! SQLite backend: one database file in WAL mode, written in `BEGIN IMMEDIATE` transactions.
//!
//! Connection settings (ARCHITECTURE.md, the store): `journal_mode=WAL` so readers never block the
//! writer, `synchronous=NORMAL` (durable at checkpoints, safe against corruption in WAL mode),
//! `foreign_keys=ON`, and a 30 s busy timeout set on every connection through the connect
//! options, so that concurrent workers wait for the write lock instead of failing with
//! "database is locked". Write transactions begin `IMMEDIATE`: the lock is taken before the
//! first read, so a transaction never has to upgrade (the upgrade is what fails without waiting
//! in WAL mode). A file on a network file system is refused ([`super::filesystem`]).

use std::path::{Path, PathBuf};
use std::time::Duration;

use sqlx::migrate::Migrator;
use sqlx::sqlite::{SqliteConnectOptions, SqlitePoolOptions, SqliteSynchronous};
use sqlx::Pool;
use sqlx::Sqlite as Db;

use super::dialect::{Dialect, SQLITE};
use super::error::StoreError;

const DIALECT: Dialect = SQLITE;

/// Migrations of the SQLite schema, embedded at compile time.
pub(crate) static MIGRATOR: Migrator = sqlx::migrate!("../migrations/sqlite");

/// How long a connection waits for another writer before giving up.
pub(crate) const BUSY_TIMEOUT: Duration = Duration::from_secs(30);

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

const SQLITE_HEADER: &[u8; 16] = b"SQLite format 3\0";

/// Connect options on the existing file `path`, which open it without writing to it: no file
/// is created and the journal mode is left as it is (switching to WAL writes the file's
/// header).
fn existing_options(path: &Path) -> SqliteConnectOptions {
    SqliteConnectOptions::new()
        .filename(path)
        .create_if_missing(false)
        .synchronous(SqliteSynchronous::Normal)
        .foreign_keys(true)
        .busy_timeout(BUSY_TIMEOUT)
}

/// A pool on the existing file `path`, opened without writing to it.
async fn connect_existing(path: &Path, max_connections: u32) -> Result<Pool<Db>> {
    SqlitePoolOptions::new()
        .max_connections(max_connections)
        .acquire_timeout(BUSY_TIMEOUT)
        .connect_with(existing_options(path))
        .await
        .map_err(|source| open_error(path, source))
}

/// Whether the SQLite file at `path` holds a moorfret store: its `schema_info` marker (written
/// by the first migration) and its `campaigns` table. Read on one connection that is closed
/// before the answer is returned, so that SQLite has removed the `-wal` and `-shm` files it
/// made beside a WAL-mode database of another program by then (a pool closes its last
/// connection on a thread of its own, which may outlive a process that exits at once).
async fn holds_store(path: &Path) -> Result<bool> {
    use sqlx::{ConnectOptions, Connection};
    const OP: &str = "look for the store's tables";
    let mut conn = existing_options(path)
        .connect()
        .await
        .map_err(|source| open_error(path, source))?;
    let ours = schema::is_moorfret_store_on(&mut conn).await;
    conn.close().await.map_err(StoreError::db(OP))?;
    ours
}

fn open_error(path: &Path, source: sqlx::Error) -> StoreError {
    match &source {
        // SQLITE_CANTOPEN: say why when it is the directory
        sqlx::Error::Database(db) if db.code().as_deref() == Some("14") => {
            match unwritable_directory(path) {
                Some((dir, io)) => StoreError::Unwritable {
                    path: path.to_path_buf(),
                    dir,
                    source: io,
                },
                None => StoreError::Database {
                    operation: "open store",
                    source,
                },
            }
        }
        sqlx::Error::Database(db) if db.code().as_deref() == Some("26") => {
            StoreError::NotADatabase {
                path: path.to_path_buf(),
                reason: db.message().into(),
            }
        }
        _ => StoreError::Database {
            operation: "open store",
            source,
        },
    }
}

fn refuse_network_filesystem(path: &Path) -> Result<()> {
    match super::filesystem::network_filesystem_of(path) {
        Some(fs_type) => Err(StoreError::NetworkFilesystem {
            path: path.to_path_buf(),
            fs_type,
        }),
        None => Ok(()),
    }
}

/// The moorfret store at `path`, opened (switched to WAL, migrated if older), or `None` when
/// no file is there. Anything else at `path` (an empty file, another program's database, a
/// file that is not a database) is refused before a byte of it is written.
pub(crate) async fn open_if_present(path: &Path, max_connections: u32) -> Result<Option<Pool<Db>>> {
    refuse_network_filesystem(path)?;
    let not_a_store = |reason: &str| StoreError::NotADatabase {
        path: path.to_path_buf(),
        reason: reason.to_owned(),
    };
    match std::fs::metadata(path) {
        Err(err) if err.kind() == std::io::ErrorKind::NotFound => return Ok(None),
        Err(source) => {
            return Err(StoreError::Io {
                path: path.to_path_buf(),
                source,
            })
        }
        Ok(m) if m.is_dir() => return Err(not_a_store("it is a directory")),
        Ok(m) if m.len() == 0 => {
            return Err(not_a_store(
                "the file is empty (it was left as it is; `campaign launch` creates a store \
                 where no file is)",
            ))
        }
        Ok(_) => {}
    }
    check_header(path)?;
    if !holds_store(path).await? {
        return Err(not_a_store(
            "an SQLite database without moorfret's tables, another program's (it was left as \
             it is; `campaign launch` creates a store where no file is)",
        ));
    }
    let pool = connect_existing(path, max_connections).await?;
    // A newer schema is refused before the journal mode is touched.
    let checked = match schema::found_version(&pool).await {
        Ok(found) if found > supported_version() => Err(StoreError::SchemaTooNew {
            found,
            supported: supported_version(),
        }),
        Ok(_) => switch_to_wal(&pool).await,
        Err(err) => Err(err),
    };
    if let Err(err) = checked {
        pool.close().await;
        return Err(err);
    }
    Ok(Some(pool))
}

/// Puts the store in WAL mode (a no-op once it is). Processes switching a new store at the
/// same moment can get SQLITE_BUSY at once, without the busy handler: retried here for up to
/// the busy timeout.
async fn switch_to_wal(pool: &Pool<Db>) -> Result<()> {
    let started = std::time::Instant::now();
    let mut attempt = 0_u32;
    loop {
        let result = sqlx::query("PRAGMA journal_mode = WAL").execute(pool).await;
        match &result {
            Err(sqlx::Error::Database(db))
                if db.code().as_deref() == Some("5") && started.elapsed() < BUSY_TIMEOUT =>
            {
                attempt += 1;
                tokio::time::sleep(Duration::from_millis(10 * u64::from(attempt.min(20)))).await;
            }
            _ => {
                result.map_err(StoreError::db("switch the store to WAL"))?;
                return Ok(());
            }
        }
    }
}

/// Creates a moorfret store at `path` where no file is (its missing parent directories too),
/// or opens the one another process created at the same moment. The store is built and
/// migrated under a temporary name and linked into place, so that `path` never holds a
/// partial store that another opener would take for a foreign file.
pub(crate) async fn create(path: &Path, max_connections: u32) -> Result<Pool<Db>> {
    refuse_network_filesystem(path)?;
    let dir = match path.parent().filter(|p| !p.as_os_str().is_empty()) {
        Some(parent) => {
            std::fs::create_dir_all(parent).map_err(|source| StoreError::Io {
                path: parent.to_path_buf(),
                source,
            })?;
            parent.to_path_buf()
        }
        None => PathBuf::from("."),
    };
    let name = path.file_name().unwrap_or_default().to_string_lossy();
    let nanos = std::time::SystemTime::now()
        .duration_since(std::time::UNIX_EPOCH)
        .map_or(0, |d| d.subsec_nanos());
    let temporary = dir.join(format!(".{name}.new-{}-{nanos}", std::process::id()));
    let built = build_new(&temporary, path).await;
    let linked = built.and_then(|()| match std::fs::hard_link(&temporary, path) {
        Ok(()) => Ok(()),
        // another process created it first: use theirs
        Err(e) if e.kind() == std::io::ErrorKind::AlreadyExists => Ok(()),
        // a file system without hard links
        Err(_) if !path.exists() => {
            std::fs::rename(&temporary, path).map_err(|source| StoreError::Io {
                path: path.to_path_buf(),
                source,
            })
        }
        Err(source) => Err(StoreError::Io {
            path: path.to_path_buf(),
            source,
        }),
    });
    for suffix in ["", "-journal", "-wal", "-shm"] {
        let mut p = temporary.clone().into_os_string();
        p.push(suffix);
        let _ = std::fs::remove_file(p);
    }
    linked?;
    open_if_present(path, max_connections)
        .await?
        .ok_or_else(|| StoreError::InvalidLocation {
            location: path.display().to_string(),
            reason: "the new store disappeared as it was created".into(),
        })
}

/// A new store at `temporary` (rollback journal: one file, ready to be linked), migrated.
async fn build_new(temporary: &Path, path: &Path) -> Result<()> {
    let options = SqliteConnectOptions::new()
        .filename(temporary)
        .create_if_missing(true)
        .foreign_keys(true)
        .busy_timeout(BUSY_TIMEOUT);
    let pool = SqlitePoolOptions::new()
        .max_connections(1)
        .connect_with(options)
        .await
        .map_err(|source| match open_error(temporary, source) {
            StoreError::Unwritable { dir, source, .. } => StoreError::Unwritable {
                path: path.to_path_buf(),
                dir,
                source,
            },
            other => other,
        })?;
    let prepared = prepare_schema(&pool).await;
    pool.close().await;
    prepared
}

/// The directory of `path` and why no file can be created in it, if none can (probed with a
/// file of this process's own name, removed at once).
fn unwritable_directory(path: &Path) -> Option<(PathBuf, std::io::Error)> {
    let dir = match path.parent() {
        Some(p) if !p.as_os_str().is_empty() => p.to_path_buf(),
        _ => PathBuf::from("."),
    };
    let probe = dir.join(format!(".moorfret-write-probe-{}", std::process::id()));
    match std::fs::OpenOptions::new()
        .write(true)
        .create_new(true)
        .open(&probe)
    {
        Ok(_) => {
            let _ = std::fs::remove_file(&probe);
            None
        }
        Err(e) => Some((dir, e)),
    }
}

/// Files whose header this process has read, kept open for the life of the process.
///
/// SQLite locks database files with POSIX advisory locks, which belong to the process and the
/// file, not to a descriptor: closing *any* descriptor of the file releases every lock the
/// process's connections hold on it ("How To Corrupt An SQLite Database File", sqlite.org,
/// §2.2). A header check that opened and closed the file while a pool of this process was
/// connected to it silently dropped that pool's WAL locks, so other processes could checkpoint
/// under its readers (stale reads) and corrupt the file. The descriptor used for the check is
/// therefore never closed.
static HEADER_FILES: std::sync::Mutex<Vec<(std::path::PathBuf, std::fs::File)>> =
    std::sync::Mutex::new(Vec::new());

/// Refuses a non-empty file that does not start with the SQLite header, before the engine
/// touches it. The descriptor opened for the check stays open (see [`HEADER_FILES`]).
fn check_header(path: &Path) -> Result<()> {
    use std::os::unix::fs::FileExt;
    let io = |source| StoreError::Io {
        path: path.to_path_buf(),
        source,
    };
    use std::os::unix::fs::MetadataExt;
    let current = match std::fs::metadata(path) {
        Ok(m) => (m.dev(), m.ino()),
        Err(err) if err.kind() == std::io::ErrorKind::NotFound => return Ok(()),
        Err(source) => return Err(io(source)),
    };
    let mut files = HEADER_FILES.lock().unwrap_or_else(|e| e.into_inner());
    // The same file (a path replaced by a new file is checked again).
    let known = files
        .iter()
        .position(|(p, f)| p == path && f.metadata().is_ok_and(|m| (m.dev(), m.ino()) == current));
    let index = match known {
        Some(i) => i,
        None => match std::fs::File::open(path) {
            Ok(file) => {
                files.push((path.to_path_buf(), file));
                files.len() - 1
            }
            Err(err) if err.kind() == std::io::ErrorKind::NotFound => return Ok(()),
            Err(source) => return Err(io(source)),
        },
    };
    let file = &files[index].1;
    let mut header = [0_u8; 16];
    let mut read = 0;
    while read < header.len() {
        match file.read_at(&mut header[read..], read as u64).map_err(io)? {
            0 => break,
            n => read += n,
        }
    }
    if read == 0 || (read == header.len() && &header == SQLITE_HEADER) {
        Ok(())
    } else {
        Err(StoreError::NotADatabase {
            path: path.to_path_buf(),
            reason: "the file does not start with the SQLite header".into(),
        })
    }
}
