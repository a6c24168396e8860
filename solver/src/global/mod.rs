//! The coupled global stage (the paper's Sec. 3; `docs/global-stage.md`): the floating wind turbine
//! (rigid body with strip-theory hydrodynamics, or a prescribed motion) and its catenary lines in
//! an irregular JONSWAP sea, integrated together in one implicit generalised-α scheme, producing
//! rope tension T(t) and curvature κ(t) at the hot spots, envelopes along every line and floater
//! motions.
//!
//! Data flow: [`case::CaseSpec`] (JSON) → [`system::GlobalModel`] (validated, sea realised,
//! thrust from the wind law, waves cut off at the highest frequency the run resolves:
//! `resolution`) → [`system::solve_coupled_statics`] (floater equilibrium with all
//! lines and the mean thrust) → [`dynamics::run_dynamics`] (coupled time integration) →
//! [`results::GlobalResult`] and its [`results::GlobalSummary`]. [`run`] chains the three.
//!
//! Units SI; global frame z up, still water level z = 0, waves along +x unless a heading is
//! given, rotor thrust along +x; arc lengths from the fairlead.

pub mod case;
mod coupling;
pub mod dynamics;
pub(crate) mod error;
mod mirror;
pub(crate) mod motion;
pub(crate) mod params;
pub(crate) mod resolution;
pub mod results;
pub mod run;
pub mod sea;
pub mod series;
pub mod system;

pub use case::CaseSpec;
pub use error::GlobalError;
pub use params::DynamicsParams;
pub use resolution::{CutOffLimit, WaveCutOff, WaveResolution};
pub use results::{GlobalResult, GlobalSummary};
pub use run::{run, RunParams};
pub use series::HotSpotSeries;
pub use system::{FloaterInput, GlobalModel};
