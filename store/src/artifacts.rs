//! Content-addressed artifact files: large series and checkpoints, named by their sha256.
//!
//! Layout: `<dir>/<first two hex digits>/<64 hex digits>`. A write goes to a uniquely named
//! temporary file in the destination directory, is flushed to disk (`fsync`), then renamed over
//! the final name, and the directory is synced; a reader therefore sees either nothing or the
//! whole file, never a partial one, and two writers of the same content both succeed. Reading
//! re-hashes the content and refuses a file that does not match its name.
//!
//! The calls block on file I/O; async callers run them on a blocking thread.

use std::fs::{self, File};
use std::io::{self, Read, Write};
use std::path::{Path, PathBuf};

use sha2::{Digest, Sha256};

use super::error::StoreError;
use super::model::JobArtifact;
use super::types::ArtifactRole;

const TEMP_PREFIX: &str = ".tmp-";

/// A directory of content-addressed files.
#[derive(Debug, Clone)]
pub struct ArtifactStore {
    dir: PathBuf,
}

fn io_error(path: &Path) -> impl FnOnce(io::Error) -> StoreError + '_ {
    move |source| StoreError::ArtifactIo {
        path: path.to_path_buf(),
        source,
    }
}

fn is_sha256_hex(text: &str) -> bool {
    text.len() == 64
        && text
            .bytes()
            .all(|b| b.is_ascii_digit() || (b'a'..=b'f').contains(&b))
}

impl ArtifactStore {
    /// Uses (creating if needed) `dir`.
    pub fn open(dir: impl Into<PathBuf>) -> Result<Self, StoreError> {
        let dir = dir.into();
        fs::create_dir_all(&dir).map_err(io_error(&dir))?;
        Ok(Self { dir })
    }

    /// The directory `<database file name>.artifacts` next to an SQLite store file.
    pub fn beside_database(database: &Path) -> Result<Self, StoreError> {
        Self::open(Self::path_beside_database(database))
    }

    /// Where [`ArtifactStore::beside_database`] puts the directory, without creating it.
    pub fn path_beside_database(database: &Path) -> PathBuf {
        let mut name = database.file_name().unwrap_or_default().to_os_string();
        name.push(".artifacts");
        database.with_file_name(name)
    }

    /// Checks what is already at `dir` without creating anything: nothing there passes (the
    /// directory is made later), a directory must take files, anything else is refused. A
    /// caller runs this before it opens a store, so that a refusal leaves the store unopened.
    pub fn check_existing(dir: &Path) -> Result<(), StoreError> {
        match fs::metadata(dir) {
            Err(err) if err.kind() == io::ErrorKind::NotFound => Ok(()),
            Err(err) => Err(io_error(dir)(err)),
            Ok(meta) if meta.is_dir() => Self {
                dir: dir.to_path_buf(),
            }
            .check_writable(),
            Ok(_) => Err(io_error(dir)(io::Error::new(
                io::ErrorKind::AlreadyExists,
                "a file is in the way of the directory",
            ))),
        }
    }

    /// Writes, syncs and removes a probe file: an error here (a file in the way, a read-only
    /// or full disk) is found before a campaign is stored, not by its workers.
    pub fn check_writable(&self) -> Result<(), StoreError> {
        let probe = self
            .dir
            .join(format!("{TEMP_PREFIX}probe-{}", std::process::id()));
        let written = File::create(&probe)
            .and_then(|mut f| f.write_all(&[0_u8; 4096]).and_then(|()| f.sync_all()));
        let removed = fs::remove_file(&probe);
        written.map_err(io_error(&probe))?;
        removed.map_err(io_error(&probe))
    }

    /// The directory.
    pub fn dir(&self) -> &Path {
        &self.dir
    }

    /// Path of the artifact `sha256`, relative to the directory.
    pub fn relative_path(sha256: &str) -> PathBuf {
        Path::new(&sha256[..2.min(sha256.len())]).join(sha256)
    }

    /// Stores `bytes`; returns its reference (with `role` for the job's result).
    pub fn put(&self, role: ArtifactRole, bytes: &[u8]) -> Result<JobArtifact, StoreError> {
        let sha256 = hex::encode(Sha256::digest(bytes));
        let relative = Self::relative_path(&sha256);
        let path = self.dir.join(&relative);
        let reference = JobArtifact {
            role,
            sha256: sha256.clone(),
            size_bytes: i64::try_from(bytes.len()).unwrap_or(i64::MAX),
            path: relative.to_string_lossy().into_owned(),
        };
        if path.exists() {
            // Same name, same content: verify rather than trust a possibly damaged copy.
            match self.get(&sha256) {
                Ok(_) => return Ok(reference),
                Err(StoreError::ArtifactCorrupt { .. }) => {}
                Err(other) => return Err(other),
            }
        }
        let parent = path.parent().unwrap_or(&self.dir).to_path_buf();
        fs::create_dir_all(&parent).map_err(io_error(&parent))?;
        let temp = parent.join(format!("{TEMP_PREFIX}{}", uuid::Uuid::new_v4()));
        let written = (|| {
            let mut file = File::create_new(&temp)?;
            file.write_all(bytes)?;
            file.sync_all()?;
            fs::rename(&temp, &path)?;
            File::open(&parent)?.sync_all()
        })();
        if let Err(source) = written {
            let _ = fs::remove_file(&temp);
            return Err(StoreError::ArtifactIo { path, source });
        }
        Ok(reference)
    }

    /// Reads the artifact `sha256`, checking that its content hashes to its name.
    pub fn get(&self, sha256: &str) -> Result<Vec<u8>, StoreError> {
        if !is_sha256_hex(sha256) {
            return Err(StoreError::InvalidParameter {
                field: "sha256",
                value: sha256.to_owned(),
                reason: "must be 64 lower-case hex digits",
            });
        }
        let path = self.dir.join(Self::relative_path(sha256));
        let mut bytes = Vec::new();
        match File::open(&path) {
            Ok(mut file) => file.read_to_end(&mut bytes).map_err(io_error(&path))?,
            Err(err) if err.kind() == io::ErrorKind::NotFound => {
                return Err(StoreError::ArtifactMissing(sha256.to_owned()))
            }
            Err(source) => return Err(StoreError::ArtifactIo { path, source }),
        };
        let actual = hex::encode(Sha256::digest(&bytes));
        if actual != sha256 {
            return Err(StoreError::ArtifactCorrupt {
                expected: sha256.to_owned(),
                actual,
            });
        }
        Ok(bytes)
    }

    /// Removes temporary files left by interrupted writes; returns how many.
    pub fn remove_stale_temporaries(&self) -> Result<usize, StoreError> {
        let mut removed = 0;
        for shard in fs::read_dir(&self.dir).map_err(io_error(&self.dir))? {
            let shard = shard.map_err(io_error(&self.dir))?.path();
            if !shard.is_dir() {
                continue;
            }
            for entry in fs::read_dir(&shard).map_err(io_error(&shard))? {
                let entry = entry.map_err(io_error(&shard))?.path();
                let is_temp = entry
                    .file_name()
                    .and_then(|n| n.to_str())
                    .is_some_and(|n| n.starts_with(TEMP_PREFIX));
                if is_temp {
                    fs::remove_file(&entry).map_err(io_error(&entry))?;
                    removed += 1;
                }
            }
        }
        Ok(removed)
    }
}
