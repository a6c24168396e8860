//! Geometrically exact wire beams: finite rotations, sections and the two-node corotational
//! element.

pub mod corotational;
pub mod rotation;
pub mod section;
