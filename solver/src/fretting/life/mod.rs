//! Fretting-fatigue life of a wire crossing from its contact stress field.
//!
//! Per contact and per rainflow cycle of its slip: the Hertz patch of the crossed wires, the
//! Cattaneo-Mindlin slip regime, the stress field at the cycle's two extreme states (Hamilton's
//! normal part, the tangential part of the partial- or gross-slip traction), the wire's bulk
//! stress added, a critical-plane parameter (Smith-Watson-Topper; Fatemi-Socie beside it)
//! evaluated at the critical distance below the trailing edge (theory of critical distances),
//! and the strain-life constants of cold-drawn rope wire for its surface condition: the cycles
//! to crack initiation, Miner over the cycles. This answers the paper's closing request for "a
//! smaller-scale fretting fatigue analysis ... including material and corrosion influences"
//! (Bussolati et al. 2020, Sec. 4). Checks and sources: `docs/fretting-fatigue.md`.
//!
//! - [`field`]: stresses of the Hertz pressure (closed form) and of tangential tractions
//!   (Cerruti point-force solution integrated numerically; tabulated at the trailing edge);
//! - [`material`]: strain-life constants, critical distance, life from a parameter;
//! - [`criterion`]: one cycle's regime, parameters and life.

pub mod criterion;
pub mod field;
pub mod material;

#[cfg(test)]
mod tests;

pub use criterion::{cycle_life, ContactStressLaw, CriticalPlane, CycleLife, CycleLoad};
pub use material::{StrainLife, WireSurface};
