//! Errors of the campaign store and the artifact store.
//!
//! Every variant carries what the caller needs to act: the operation, job, path or value.
//! [`StoreError::is_retryable`] tells a worker whether trying the same call again may succeed.

use std::path::PathBuf;

use super::types::{CampaignId, JobId, JobState, UnknownValue};

/// Errors of [`super::Store`] and [`super::ArtifactStore`].
#[derive(Debug, thiserror::Error)]
pub enum StoreError {
    /// The database URL or path cannot be used.
    #[error("invalid store location {location:?}: {reason}")]
    InvalidLocation {
        /// What was given.
        location: String,
        /// Why it was refused.
        reason: String,
    },
    /// The file exists but is not an SQLite database (or is damaged).
    #[error("{path:?} is not a moorfret store: {reason}")]
    NotADatabase {
        /// The file.
        path: PathBuf,
        /// What the database engine said.
        reason: String,
    },
    /// An SQLite store whose directory cannot be written: SQLite writes the store's `-wal`
    /// and `-shm` files beside it, even to read.
    #[error(
        "cannot open store {path:?}: its directory {dir:?} is not writable ({source}); an \
         SQLite store writes its -wal and -shm files beside it, even to read"
    )]
    Unwritable {
        /// The database file.
        path: PathBuf,
        /// Its directory.
        dir: PathBuf,
        /// Why a file could not be created there.
        source: std::io::Error,
    },
    /// An SQLite store on a network file system, where its locking is unreliable.
    #[error(
        "{path:?} is on a {fs_type} network file system, where SQLite locking is unreliable: \
         use a PostgreSQL store (postgres://…) for workers on several hosts"
    )]
    NetworkFilesystem {
        /// The database file.
        path: PathBuf,
        /// File system type from the mount table.
        fs_type: String,
    },
    /// The database was written by a newer moorfret; it is left untouched.
    #[error(
        "the store has schema version {found}, this moorfret knows up to {supported}: \
         upgrade moorfret (the store was not modified)"
    )]
    SchemaTooNew {
        /// Version found in the database.
        found: i64,
        /// Newest version this binary knows.
        supported: i64,
    },
    /// Applying the embedded migrations failed.
    #[error("migrating the store failed: {0}")]
    Migrate(#[from] sqlx::migrate::MigrateError),
    /// A database call failed.
    #[error("store operation `{operation}` failed: {source}")]
    Database {
        /// The store operation.
        operation: &'static str,
        /// The driver's error.
        #[source]
        source: sqlx::Error,
    },
    /// The lease is no longer held: the job was swept, re-claimed or cancelled. The caller must
    /// discard its results.
    #[error("lease on job {job} lost (token {token} no longer matches); results discarded")]
    LeaseLost {
        /// The job.
        job: JobId,
        /// The token that is no longer valid.
        token: String,
    },
    /// A campaign of this name exists already.
    #[error("a campaign named {name:?} already exists (id {existing})")]
    CampaignExists {
        /// The name.
        name: String,
        /// The existing campaign.
        existing: CampaignId,
    },
    /// No campaign has this id or name.
    #[error("no campaign {0}")]
    UnknownCampaign(String),
    /// No job has this id.
    #[error("no job {0}")]
    UnknownJob(JobId),
    /// A job is not in the state an operation needs.
    #[error("job {job} is {state}, expected {expected}")]
    WrongState {
        /// The job.
        job: JobId,
        /// Its state.
        state: JobState,
        /// What the operation needed.
        expected: &'static str,
    },
    /// A planned job depends on one that is not planned before it.
    #[error(
        "planned job {job_index} depends on planned job {depends_on}, which does not precede it"
    )]
    BadDependency {
        /// Index of the job in the plan.
        job_index: usize,
        /// Index it refers to.
        depends_on: usize,
    },
    /// A parameter is out of range.
    #[error("invalid parameter {field} = {value}: {reason}")]
    InvalidParameter {
        /// Parameter name.
        field: &'static str,
        /// Its value.
        value: String,
        /// The rule it breaks.
        reason: &'static str,
    },
    /// A text column holds a value this binary does not know.
    #[error("unknown value {value:?} in {field}")]
    UnknownValue {
        /// Table and column.
        field: &'static str,
        /// The text found.
        value: String,
    },
    /// JSON could not be encoded or decoded.
    #[error("JSON of {field} is invalid: {source}")]
    Json {
        /// What was being encoded or decoded.
        field: &'static str,
        /// The serde error.
        #[source]
        source: serde_json::Error,
    },
    /// Results of the test-only job kind were offered for the users' result tables.
    #[cfg(feature = "test-support")]
    #[error("job {0} is of the test kind; only its job-level result may be stored")]
    TestKindResults(JobId),
    /// A file or directory of the store (not an artifact) could not be read or created.
    #[error("I/O on {path:?} failed: {source}")]
    Io {
        /// The file or directory.
        path: PathBuf,
        /// The OS error.
        #[source]
        source: std::io::Error,
    },
    /// A file of the artifact store could not be read or written.
    #[error("artifact I/O on {path:?} failed: {source}")]
    ArtifactIo {
        /// The file or directory.
        path: PathBuf,
        /// The OS error.
        #[source]
        source: std::io::Error,
    },
    /// An artifact's content does not match its name.
    #[error("artifact {expected} is corrupt: its content hashes to {actual}")]
    ArtifactCorrupt {
        /// The hash it is stored under.
        expected: String,
        /// The hash of what was read.
        actual: String,
    },
    /// No artifact has this hash.
    #[error("no artifact {0}")]
    ArtifactMissing(String),
}

impl StoreError {
    /// Wraps a driver error with the operation that failed.
    pub(crate) fn db(operation: &'static str) -> impl FnOnce(sqlx::Error) -> StoreError {
        move |source| StoreError::Database { operation, source }
    }

    /// Whether the same call may succeed later (busy database, lost connection, I/O).
    pub fn is_retryable(&self) -> bool {
        match self {
            StoreError::Database { source, .. } => {
                matches!(
                    source,
                    sqlx::Error::Io(_)
                        | sqlx::Error::PoolTimedOut
                        | sqlx::Error::PoolClosed
                        | sqlx::Error::WorkerCrashed
                ) || is_busy(source)
                    || is_server_unavailable(source)
            }
            StoreError::ArtifactIo { .. } | StoreError::Io { .. } => true,
            _ => false,
        }
    }

    /// Whether this is SQLite's "database is locked" / "database is busy".
    pub fn is_database_locked(&self) -> bool {
        matches!(self, StoreError::Database { source, .. } if is_busy(source))
    }
}

/// Whether PostgreSQL reports that the connection or the server went away, or that the
/// transaction lost a race it may win on a second try (SQLSTATE class 08 connection
/// exceptions; 57P01-57P03 shutdown, crash and start-up; 40001 serialization failure; 40P01
/// deadlock). SQLite's codes are numeric, so they never match.
fn is_server_unavailable(source: &sqlx::Error) -> bool {
    match source {
        sqlx::Error::Database(db) => db.code().is_some_and(|code| {
            code.starts_with("08")
                || matches!(
                    code.as_ref(),
                    "57P01" | "57P02" | "57P03" | "40001" | "40P01"
                )
        }),
        _ => false,
    }
}

fn is_busy(source: &sqlx::Error) -> bool {
    match source {
        sqlx::Error::Database(db) => {
            // SQLITE_BUSY = 5, SQLITE_LOCKED = 6 (primary result codes).
            let code = db.code();
            let primary = code
                .as_deref()
                .and_then(|c| c.parse::<i64>().ok())
                .map(|c| c & 0xff);
            matches!(primary, Some(5) | Some(6)) || db.message().contains("database is locked")
        }
        _ => false,
    }
}

impl From<UnknownValue> for StoreError {
    fn from(e: UnknownValue) -> Self {
        Self::UnknownValue {
            field: e.field,
            value: e.value,
        }
    }
}
