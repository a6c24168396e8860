//! Errors of the strand model: building it (contact detection and meshing, wire sections, the
//! beam frame, contact elements, equation numbering, periodic end layout) and checking its
//! parameters.
//!
//! The type lives apart from the model so that the model and the periodic end constraints it
//! builds can both report it without depending on each other; it is re-exported from
//! `strand::model`, its historical path.

use super::contacts::GeometryError;
use crate::beam::frame::FrameError;
use crate::beam::section::SectionError;
use crate::contact::ContactError;
use crate::linalg::PatternError;

/// Errors while building or solving a strand model.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum StrandModelError {
    /// Contact detection or meshing failed.
    #[error(transparent)]
    Geometry(#[from] GeometryError),
    /// A wire section is invalid.
    #[error("wire {wire}: {source}")]
    Section {
        /// Wire index.
        wire: usize,
        /// Cause.
        source: SectionError,
    },
    /// Frame construction failed.
    #[error(transparent)]
    Frame(#[from] FrameError),
    /// A contact element cannot be built.
    #[error("contact {contact} (nodes {node1}, {node2}): {source}")]
    Contact {
        /// Contact index.
        contact: usize,
        /// Inner node.
        node1: usize,
        /// Outer node.
        node2: usize,
        /// Cause.
        source: ContactError,
    },
    /// Equation numbering failed.
    #[error(transparent)]
    Pattern(#[from] PatternError),
    /// A model parameter is out of range.
    #[error("strand model parameter {field} = {value}: {reason}")]
    InvalidParameter {
        /// Field.
        field: &'static str,
        /// Value.
        value: f64,
        /// Why.
        reason: &'static str,
    },
}
