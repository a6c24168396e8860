//! Analytical elastic catenaries of mooring lines resting on a flat seabed: the starting point
//! of the line statics and a verification reference for the finite-element line model.
//!
//! - `single`: one homogeneous line with seabed contact and friction, solved in closed form
//!   (Jonkman 2007, NREL/TP-500-41958) by Newton with an analytic Jacobian.
//! - `profile`: position, tension and curvature of a solved single line at any arc length.
//! - `segment`: one uniform segment of a multi-segment line, extra masses and clumps.
//! - [`segmented`]: fairlead-to-anchor lists of segments (chain, wire rope, extra masses),
//!   solved by shooting from the anchor.
//! - `newton`: the shared 2×2 damped Newton solve, its parameters and work counters.
//! - `error`: the typed errors.
//!
//! Frame of every catenary here: origin at the anchor, x horizontal towards the fairlead, z up.
//! Arc lengths are unstretched and, in public APIs, measured from the fairlead. Weights are
//! submerged weights per unit unstretched length (N/m).

pub(crate) mod error;
pub(crate) mod newton;
mod pieces;
pub(crate) mod profile;
pub(crate) mod segment;
pub mod segmented;
mod shooting;
pub(crate) mod single;

pub use error::CatenaryError;
pub use newton::{CatenaryParams, NewtonStats};
pub use profile::ProfilePoint;
pub use segment::{
    LineSegment, SEAWATER_DENSITY_KG_M3, STANDARD_GRAVITY_M_S2, STEEL_DENSITY_KG_M3,
};
pub use segmented::{solve_segmented, SegmentedCatenary, SegmentedSolution};
pub use single::{solve_catenary, Catenary, CatenarySolution, ElasticLine};
