//! Checkpoints of a strand history run: the solver hands its full state over every few
//! segments ([`HistoryObserver::checkpoint`]); [`Checkpoints`] writes it, at most every
//! `min_interval` of wall time, to where the run keeps it ([`CheckpointTarget`]), and reads the
//! newest back for a resume. A run resumed from a checkpoint gives results identical to the bit
//! to an uninterrupted run (the solver's guarantee). Every write replaces the previous one by
//! temporary file and rename, so a reader sees a whole checkpoint or the one before.

use std::path::{Path, PathBuf};
use std::time::{Duration, Instant};

use moorfret_campaign::stiffness::replace_file;
use moorfret_solver::strand::history::checkpoint::HistoryCheckpoint;
use moorfret_solver::strand::history::HistoryObserver;
use moorfret_store::{ArtifactRole, ArtifactStore};

/// Where a run keeps its checkpoint.
#[derive(Debug, Clone)]
pub enum CheckpointTarget<'a> {
    /// A file of its own (`moorfret run strand --checkpoint FILE`).
    File(PathBuf),
    /// The artifact store, with a pointer file naming the newest checkpoint artifact (a
    /// campaign's strand job: `checkpoints/<job cache key>` in the artifact directory).
    Artifacts {
        /// The artifact store.
        artifacts: &'a ArtifactStore,
        /// The pointer file.
        pointer: PathBuf,
    },
}

impl CheckpointTarget<'_> {
    /// The file a user would name in a message: the checkpoint file or the pointer.
    pub fn path(&self) -> &Path {
        match self {
            Self::File(path) => path,
            Self::Artifacts { pointer, .. } => pointer,
        }
    }

    fn write(&self, checkpoint: &HistoryCheckpoint) -> Result<(), String> {
        let bytes = checkpoint.to_bytes().map_err(|e| e.to_string())?;
        match self {
            Self::File(path) => {
                replace_file(path, &bytes).map_err(|e| format!("writing {}: {e}", path.display()))
            }
            Self::Artifacts { artifacts, pointer } => {
                let artifact = artifacts
                    .put(ArtifactRole::Checkpoint, &bytes)
                    .map_err(|e| e.to_string())?;
                // a worker whose lease was swept away may still be writing the same job's
                // pointer while its new claimant does: `replace_file` gives each its own
                // temporary file
                replace_file(pointer, artifact.sha256.as_bytes()).map_err(|e| e.to_string())
            }
        }
    }

    /// The newest checkpoint: `None` when there is none; an error when it cannot be read
    /// (missing or damaged artifact, format of another build).
    pub fn read(&self) -> Result<Option<HistoryCheckpoint>, String> {
        let bytes = match self {
            Self::File(path) => match std::fs::read(path) {
                Ok(bytes) => bytes,
                Err(e) if e.kind() == std::io::ErrorKind::NotFound => return Ok(None),
                Err(e) => return Err(format!("reading {}: {e}", path.display())),
            },
            Self::Artifacts { artifacts, pointer } => {
                let sha = match std::fs::read_to_string(pointer) {
                    Ok(sha) => sha,
                    Err(e) if e.kind() == std::io::ErrorKind::NotFound => return Ok(None),
                    Err(e) => return Err(format!("checkpoint pointer not readable: {e}")),
                };
                artifacts.get(sha.trim()).map_err(|e| e.to_string())?
            }
        };
        HistoryCheckpoint::from_bytes(&bytes)
            .map(Some)
            .map_err(|e| e.to_string())
    }
}

/// Writes the checkpoints of a run (module docs); a run without a target writes none.
#[derive(Debug)]
pub struct Checkpoints<'a> {
    target: Option<CheckpointTarget<'a>>,
    min_interval: Duration,
    last: Instant,
    written: usize,
}

impl<'a> Checkpoints<'a> {
    /// Checkpoints to `target`, at most every `min_interval` of wall time (zero: every one the
    /// solver hands over).
    pub fn new(target: Option<CheckpointTarget<'a>>, min_interval: Duration) -> Self {
        Self {
            target,
            min_interval,
            last: Instant::now(),
            written: 0,
        }
    }

    /// The target.
    pub fn target(&self) -> Option<&CheckpointTarget<'a>> {
        self.target.as_ref()
    }

    /// Checkpoints written so far.
    pub fn written(&self) -> usize {
        self.written
    }

    /// Writes `checkpoint` unless the last one is younger than the interval. A checkpoint that
    /// cannot be written is logged: it costs only recomputation after an interruption.
    pub fn offer(&mut self, checkpoint: &HistoryCheckpoint) {
        let Some(target) = &self.target else {
            return;
        };
        if self.last.elapsed() < self.min_interval {
            return;
        }
        self.last = Instant::now();
        match target.write(checkpoint) {
            Ok(()) => self.written += 1,
            Err(e) => tracing::warn!(error = %e, "strand checkpoint not written"),
        }
    }
}

impl HistoryObserver for Checkpoints<'_> {
    fn checkpoint(&mut self, checkpoint: &HistoryCheckpoint) {
        self.offer(checkpoint);
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn no_checkpoint_without_a_pointer_and_an_error_for_an_unreadable_one() {
        let dir = tempfile::tempdir().unwrap();
        let artifacts = ArtifactStore::open(dir.path()).unwrap();
        let pointer = dir.path().join("checkpoints").join("key");
        let target = CheckpointTarget::Artifacts {
            artifacts: &artifacts,
            pointer: pointer.clone(),
        };
        assert_eq!(target.read().map(|c| c.is_none()), Ok(true));
        std::fs::create_dir_all(pointer.parent().unwrap()).unwrap();
        // a pointer to an artifact that is not there
        std::fs::write(&pointer, "ab".repeat(32)).unwrap();
        assert!(target.read().is_err());
        // a pointer to an artifact that is no checkpoint
        let other = artifacts.put(ArtifactRole::ContactRecords, b"[]").unwrap();
        std::fs::write(&pointer, &other.sha256).unwrap();
        assert!(target.read().is_err());

        let file = CheckpointTarget::File(dir.path().join("run.checkpoint"));
        assert_eq!(file.read().map(|c| c.is_none()), Ok(true));
        std::fs::write(file.path(), b"not a checkpoint").unwrap();
        let e = file.read().unwrap_err();
        assert!(!e.is_empty());
    }
}
