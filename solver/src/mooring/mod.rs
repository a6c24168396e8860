//! Mooring lines: the analytical elastic catenary (statics start), the finite-element line
//! model (Hermite cable elements for wire rope, tension-only bars for chain), seabed contact,
//! hydrodynamic loads, static equilibrium, implicit dynamics and hot-spot outputs.

pub mod catenary;
