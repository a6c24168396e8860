//! Geometrically exact wire beams: finite rotations, sections, the two-node corotational
//! element, frames of such elements and their static equilibrium.

pub mod corotational;
pub mod frame;
pub mod rotation;
pub mod section;
pub mod statics;
