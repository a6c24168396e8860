//! Spiral-strand geometry for the detailed strand model (the paper's Sec. 2).
//!
//! - [`profile`]: the serde profile (core wire, layers, material, model length), its validation
//!   (radial stacking, lateral clearance, lay angle, counts) into a resolved [`profile::Strand`];
//! - `helix`: exact helical centrelines, Frenet frames, arc length ↔ z;
//! - `clearance`: exact lateral clearance of neighbouring helical wires;
//! - `wires`: wire numbering (`wires::WireId`);
//! - [`contacts`]: trellis crossings between adjacent layers and the core line contact;
//! - [`mesh`]: nodes at contact points, wire elements, contact elements, counts;
//! - [`analytical`]: Costello's simple straight strand and the bent-helix stick/slip references;
//! - [`bending`]: section force and moment from the wire forces, EI_min / EI_max bounds;
//! - [`loading`]: imposed section motion from (ε, κ) and the two-stage load path;
//! - `ends`: penalty ties of the helical wire ends to the core end sections;
//! - `periodic`: periodic multi-point constraints of the wire ends (the paper's Eqs. 12-13);
//! - [`model`]: the FE model (beams, contacts, ties, DOFs, pattern);
//! - `error`: the errors of building the model ([`error::StrandModelError`], also at its
//!   historical path `model::StrandModelError`);
//! - [`problem`]: its equilibrium as a Newton problem;
//! - [`driver`]: one loading case solved and its monitors extracted;
//! - [`history`]: the model driven through a (t, ε, κ) load history, monitors and per-contact
//!   rainflow records;
//! - [`reduced`]: a reduced response calibrated on the FE model, per-contact Jenkins elements
//!   that turn a load history into the same records in seconds.
//!
//! Strand frame: axis along z, angular position θ in the x-y plane (θ = +π/2 outer arc for
//! bending about y with κ > 0 towards +x: ARCHITECTURE.md, Conventions). Units: m, rad, N, Pa.

pub mod analytical;
pub mod bending;
pub(crate) mod clearance;
pub mod contacts;
pub mod driver;
pub(crate) mod ends;
pub(crate) mod error;
pub(crate) mod helix;
pub mod history;
pub mod loading;
pub mod mesh;
pub mod model;
pub(crate) mod periodic;
pub mod problem;
pub mod profile;
pub mod reduced;
pub(crate) mod wires;
