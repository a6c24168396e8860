//! Small-sliding node-to-node frictional contact between wire beams (the paper's Sec. 2.1,
//! Eqs. 1-11).
//!
//! - `element`: the two-node contact element (kinematics, return mapping, internal force,
//!   consistent tangent), its history and its outputs;
//! - `laws`: normal (penalty / Hertz) and tangential (elastic slip / Mindlin) laws, parameters
//!   and errors;
//! - [`hertz`]: the Hertz contact of crossed cylinders (ellipse, peak pressure, K_H) and of line
//!   contacts, the Mindlin tangential modulus; the fretting statistics read the same model;
//! - [`memory`]: the Cattaneo–Mindlin tangential law as an Iwan model of Jenkins elements;
//! - `scalar`: the generic scalar / dual-number arithmetic from which the tangent is derived.
//!
//! Contact pairing is fixed for the whole analysis; the history changes only when the caller
//! accepts a step.

pub(crate) mod element;
pub mod hertz;
pub(crate) mod laws;
pub mod memory;
pub(crate) mod scalar;

#[cfg(test)]
mod element_tests;

pub use element::{
    ContactHistory, ContactPair, ContactResponse, ContactStatus, ElementMatrix, ElementVector,
    NodeKinematics,
};
pub use laws::{ContactError, ContactLaws, ContactParameters, NormalLaw, TangentialLaw};
pub use memory::TangentialMemory;
