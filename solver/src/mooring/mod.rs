//! Mooring lines: the analytical elastic catenary (statics start), the finite-element line
//! model (Hermite cable elements for wire rope, tension-only bars for chain), seabed contact,
//! hydrodynamic loads, static equilibrium, implicit dynamics and hot-spot outputs.
//!
//! Data flow: a [`spec::LineSpec`] (line types and segments, fairlead to anchor) with the site
//! [`spec::Environment`] and the end points builds an immutable [`line::LineModel`];
//! [`statics::solve_statics`] finds the equilibrium; [`dynamics::LineIntegrator`] advances it in
//! time with the generalised-α method under a prescribed fairlead motion
//! ([`trajectory::FairleadMotion`]) and a sea ([`crate::waves::SeaKinematics`]), exposing after
//! each step the fairlead force and the condensed fairlead stiffness; [`hotspot`] turns states
//! into tension and curvature histories and envelopes.

pub mod assembly;
pub(crate) mod banded;
pub mod bar_element;
pub(crate) mod cable_element;
pub mod catenary;
pub mod dynamics;
pub(crate) mod error;
pub(crate) mod hermite;
pub mod hotspot;
pub(crate) mod hydro;
pub(crate) mod ids;
pub mod line;
pub(crate) mod loads;
pub(crate) mod seabed;
pub(crate) mod section;
pub mod spec;
pub mod statics;
pub mod trajectory;
pub mod workspace;

pub use error::LineError;
pub use ids::{ElementId, NodeId};
pub use line::LineModel;
