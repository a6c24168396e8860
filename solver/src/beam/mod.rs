//! Geometrically exact wire beams: finite rotations and the two-node corotational element.

pub mod rotation;
