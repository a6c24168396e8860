//! Checkpoint of a history run: everything needed to continue it so that the results are
//! identical to the bit to those of an uninterrupted run — the committed configuration
//! (positions, rotations), the contact histories, the imposed section motion, the last solved
//! snapshot the next segment interpolates from, the rainflow counters with their stacks and the
//! cycles already closed, the monitor series so far, the position in the history and the work
//! counts. Serialised with serde (bincode for the compact binary form, [`to_bytes`]).
//!
//! A checkpoint is tied to its model and history: resuming checks the sample count, the kept
//! samples of the turning-point reduction, the node and contact counts, and refuses a mismatch.
//!
//! [`to_bytes`]: HistoryCheckpoint::to_bytes

use nalgebra::{Matrix3, Vector3};
use serde::{Deserialize, Serialize};

use super::recording::{Recorder, Snapshot};
use super::{HistoryError, HistoryStats};
use crate::contact::ContactHistory;

/// Complete state of a history run between two segments.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct HistoryCheckpoint {
    /// Number of original samples of the history.
    pub samples: usize,
    /// Indices of the samples the solver visits.
    pub kept_samples: Vec<usize>,
    /// Next segment to solve (index into the windows of `kept_samples`).
    pub next_segment: usize,
    /// Imposed axial strain of the committed state.
    pub strain: f64,
    /// Imposed curvature of the committed state (1/m).
    pub curvature_per_m: f64,
    /// Committed node positions (m).
    pub positions: Vec<Vector3<f64>>,
    /// Committed node rotations.
    pub rotations: Vec<Matrix3<f64>>,
    /// Committed contact histories.
    pub histories: Vec<ContactHistory>,
    /// Outputs of the last solved state.
    pub(super) previous: Snapshot,
    /// Rainflow counters, closed cycles, peak forces and monitor series so far.
    pub(super) recorder: Recorder,
    /// Work counts and times so far.
    pub stats: HistoryStats,
}

/// The first bytes of a checkpoint's binary form: its format. bincode is not self-describing,
/// so a checkpoint of another layout (the contact histories' tangential memory changed with
/// format 2, the work counts with format 3) would be misread rather than refused without it.
const FORMAT: &[u8; 8] = b"mfchk003";

impl HistoryCheckpoint {
    /// Compact binary form: [`FORMAT`], then bincode.
    pub fn to_bytes(&self) -> Result<Vec<u8>, HistoryError> {
        let mut bytes = FORMAT.to_vec();
        bincode::serialize_into(&mut bytes, self).map_err(|e| HistoryError::Checkpoint {
            reason: e.to_string(),
        })?;
        Ok(bytes)
    }

    /// Reads the binary form written by [`Self::to_bytes`]; the form of another format is
    /// refused.
    pub fn from_bytes(bytes: &[u8]) -> Result<Self, HistoryError> {
        let body =
            bytes
                .strip_prefix(FORMAT.as_slice())
                .ok_or_else(|| HistoryError::Checkpoint {
                    reason: "not a checkpoint of this format (written by another build?)".into(),
                })?;
        bincode::deserialize(body).map_err(|e| HistoryError::Checkpoint {
            reason: e.to_string(),
        })
    }

    /// Refuses a checkpoint of another model or history.
    pub(super) fn check(
        &self,
        samples: usize,
        kept: &[usize],
        nodes: usize,
        contacts: usize,
    ) -> Result<(), HistoryError> {
        let mismatch = |what: &str, here: usize, there: usize| {
            Err(HistoryError::Checkpoint {
                reason: format!("{what}: the run has {here}, the checkpoint {there}"),
            })
        };
        if self.samples != samples {
            return mismatch("history samples", samples, self.samples);
        }
        if self.kept_samples != kept {
            return mismatch("kept samples", kept.len(), self.kept_samples.len());
        }
        if self.positions.len() != nodes || self.rotations.len() != nodes {
            return mismatch("model nodes", nodes, self.positions.len());
        }
        if self.histories.len() != contacts {
            return mismatch("contacts", contacts, self.histories.len());
        }
        if self.next_segment >= kept.len().max(1) {
            return mismatch(
                "next segment",
                kept.len().saturating_sub(1),
                self.next_segment,
            );
        }
        Ok(())
    }
}
